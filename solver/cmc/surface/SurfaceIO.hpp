// Reading and writing height maps: the Contact Mechanics Challenge's published formats
// (Müser & Dapp, "The contact mechanics challenge: problem definition"; see
// shared/notes/reference-solutions.md) and generic height maps of explicit size.
//
// Layout everywhere: row-major, x fastest. A file row / the slowest HDF5 dimension is y:
// an HDF5 dataset of dims {d0, d1} becomes nx = d1, ny = d0, value (ix, iy) = data[iy][ix];
// row iy of an ASCII matrix holds h(ix = 0..nx-1, iy). Whether the challenge's own files
// used x or y as their fastest index is not documented; the orientation matters only
// for cross-sections (e.g. the cut at x = 50 µm), not for any statistic.
//
// Every error is a SurfaceFileError whose message starts with the file name and says
// what was expected (dataset, line, first offending index).
#pragma once

#include "cmc/grid/Grid.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace cmc {

struct HeightMap {
  Grid grid;
  Field heights;  // grid.size() values, row-major, x fastest
};

// One Fourier coefficient of a periodic height map on a box lx * ly:
//   h(x, y) = sum_k c_k exp(+2 pi i (kx x / lx + ky y / ly))     (FFTW's backward sign)
// i.e. c_k = (1/N) * (FFTW forward r2c/dft of h): c_k has the units of h, and for a real
// h c_{-k} = conj(c_k). Lists hold one half-plane (kx > 0, or kx == 0 and ky > 0) unless
// said otherwise; (0,0) is the mean height.
struct FourierMode {
  int kx = 0, ky = 0;
  Complex c;
};

class SurfaceFileError : public std::runtime_error {
 public:
  SurfaceFileError(const std::filesystem::path& file, const std::string& what)
      : std::runtime_error(file.string() + ": " + what) {}
};

// The largest map a reader accepts. It is checked against the shape a file declares (an
// HDF5 dataset's extent) or reaches (an ASCII file's rows and columns, as they are read)
// before the heights are allocated, so a lying header or an oversized file is an error
// naming the shape, never an allocation of what it claims. A case passes its own grid
// (a file may match it or be coarser). Text files are also refused beyond
// kMaxBytesPerValue bytes per allowed value (plus 1 MiB for comments).
struct MapLimit {
  static constexpr long long kMaxSide = 1LL << 20;
  static constexpr double kMaxBytesPerValue = 100.0;
  long long nx = kMaxSide, ny = kMaxSide;  // points along x (columns) and y (rows)
  double max_text_bytes() const { return kMaxBytesPerValue * double(nx) * double(ny) + double(1 << 20); }
};

// A file whose shape exceeds the MapLimit it was read with (a SurfaceFileError too).
class SurfaceShapeError : public SurfaceFileError {
 public:
  using SurfaceFileError::SurfaceFileError;
};

// ---- The challenge's formats (heights and box in units of the system size L).
// HDF5 file with one 2-D, square dataset "surface"; grid lx = ly = 1.
HeightMap read_challenge_hdf5(const std::filesystem::path& file, MapLimit limit = {});
// Plain ASCII matrix (whitespace separated, one row per line, '#' comments allowed);
// must be square; heights multiplied by height_scale (units: caller's); lx = ly = 1.
HeightMap read_challenge_ascii(const std::filesystem::path& file, double height_scale = 1.0, MapLimit limit = {});

// ---- Generic height maps with explicit physical size (the caller passes lx, ly).
// dataset: name of a 2-D floating-point (or integer) dataset. lx <= 0 or ly <= 0: take
// the size from the dataset's attributes "lx" and "ly" (written by write_hdf5_heights)
// and fail if they are absent.
HeightMap read_hdf5_heights(const std::filesystem::path& file, const std::string& dataset = "surface",
                            double lx = 0.0, double ly = 0.0, double height_scale = 1.0,
                            bool require_square = false, MapLimit limit = {});
HeightMap read_ascii_heights(const std::filesystem::path& file, double lx, double ly,
                             double height_scale = 1.0, bool require_square = false, MapLimit limit = {});

// ---- Fourier-coefficient lists. One mode per line: "kx ky re im" (integers, then two
// reals; whitespace or commas; '#' comments and blank lines ignored). Either one member
// of each pair (k, -k) may be listed (the other is implied by c_{-k} = conj(c_k)) or both;
// if both, they must agree to 1e-6 relative. Duplicates, malformed lines and non-finite
// values are errors. Coefficients are multiplied by scale.
std::vector<FourierMode> read_fourier_list(const std::filesystem::path& file, double scale = 1.0);
// Synthesise the list on an n x n grid of box lx = ly = box. n == 0: the smallest power
// of two that holds every mode. A mode with |kx| or |ky| >= n/2 is an error ("out of
// range"), never silently dropped. With n > 0 the file may hold at most MapLimit's bytes
// per mode of the n x n grid.
HeightMap read_fourier_heights(const std::filesystem::path& file, int n = 0, double scale = 1.0,
                               double box = 1.0);

// ---- Writers. Each writes to a temporary name beside the target, then renames (atomic).
// HDF5: a 2-D double dataset {ny, nx} with double attributes "lx", "ly".
void write_hdf5_heights(const std::filesystem::path& file, const HeightMap& map,
                        const std::string& dataset = "surface");
// ASCII: ny lines of nx values (%.17g, exact round trip), heights divided by height_scale.
void write_ascii_heights(const std::filesystem::path& file, const HeightMap& map, double height_scale = 1.0);
// Fourier list: "kx ky re im" per mode, %.17g.
void write_fourier_list(const std::filesystem::path& file, const std::vector<FourierMode>& modes);

}  // namespace cmc
