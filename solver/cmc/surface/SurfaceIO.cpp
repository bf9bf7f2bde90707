#include "cmc/surface/SurfaceIO.hpp"

#include "cmc/surface/SelfAffine.hpp"

#include "cmc/grid/FilePaths.hpp"
#include "cmc/surface/H5Handle.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include <unistd.h>

namespace fs = std::filesystem;

namespace cmc {

namespace {

// ---------------------------------------------------------------- text helpers
std::string memory_text(double bytes) {
  char buf[48];
  if (bytes >= 1e9) std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
  else if (bytes >= 1e6) std::snprintf(buf, sizeof buf, "%.3g MB", bytes / 1e6);
  else std::snprintf(buf, sizeof buf, "%.0f bytes", bytes);
  return buf;
}

// The whole text of a file of at most max_bytes (checked before it is read).
std::string read_text(const fs::path& file, double max_bytes = 0.0) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw SurfaceFileError(file, "no such file");
  if (!fs::is_regular_file(file, ec)) throw SurfaceFileError(file, "not a regular file");
  if (const auto size = fs::file_size(file, ec); !ec && max_bytes > 0.0 && double(size) > max_bytes)
    throw SurfaceFileError(file, "is " + memory_text(double(size)) + ", more than a height file of the expected size "
                                 "takes (at most " + memory_text(max_bytes) + ")");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw SurfaceFileError(file, "cannot open for reading");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw SurfaceFileError(file, "read error");
  return std::move(ss).str();
}

// Splits a line into tokens at whitespace and commas, after dropping a '#' comment.
void tokenize(std::string_view line, std::vector<std::string_view>& tok) {
  tok.clear();
  if (auto c = line.find('#'); c != std::string_view::npos) line = line.substr(0, c);
  std::size_t i = 0;
  auto sep = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == ',' || ch == '\v' || ch == '\f'; };
  while (i < line.size()) {
    while (i < line.size() && sep(line[i])) ++i;
    std::size_t j = i;
    while (j < line.size() && !sep(line[j])) ++j;
    if (j > i) tok.push_back(line.substr(i, j - i));
    i = j;
  }
}

bool parse_double(std::string_view t, double& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}
bool parse_int(std::string_view t, long& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  if (r.ec == std::errc() && r.ptr == t.data() + t.size()) return true;
  double d;  // accept integral reals such as "3.0"
  if (parse_double(t, d) && std::isfinite(d) && d == std::floor(d) && std::abs(d) < 1e15) {
    v = long(d);
    return true;
  }
  return false;
}

// Calls f(line_number, tokens) for each non-empty line.
template <class F>
void for_each_line(const std::string& text, F&& f) {
  std::vector<std::string_view> tok;
  std::string_view all(text);
  long line = 0;
  std::size_t pos = 0;
  while (pos < all.size()) {
    std::size_t end = all.find('\n', pos);
    if (end == std::string_view::npos) end = all.size();
    ++line;
    tokenize(all.substr(pos, end - pos), tok);
    if (!tok.empty()) f(line, tok);
    pos = end + 1;
  }
}

std::string quoted(std::string_view t) { return "'" + std::string(t.substr(0, 40)) + "'"; }

void check_size(const fs::path& file, double lx, double ly) {
  if (!(lx > 0) || !(ly > 0) || !std::isfinite(lx) || !std::isfinite(ly))
    throw SurfaceFileError(file, "physical size lx, ly must be positive and finite");
}

// ---------------------------------------------------------------- atomic writes
// Through the one output-file helper (grid/FilePaths.hpp): a new path or a regular file,
// replaced atomically; a folder, device, FIFO or link is refused before anything is written.
template <class F>
void write_atomic(const fs::path& file, F&& body) {
  write_output_file(file, body);
}

void check_map(const fs::path& file, const HeightMap& map) {
  if (map.grid.size() == 0 || map.heights.size() != map.grid.size())
    throw SurfaceFileError(file, "height map does not match its grid (" + std::to_string(map.heights.size()) +
                                     " values for " + std::to_string(map.grid.nx) + " x " +
                                     std::to_string(map.grid.ny) + ")");
}

// ---------------------------------------------------------------- HDF5 helpers
// H5Handle, H5Quiet: cmc/surface/H5Handle.hpp.

std::string root_names(hid_t f) {
  H5G_info_t info;
  if (H5Gget_info(f, &info) < 0) return "";
  std::string s;
  for (hsize_t i = 0; i < info.nlinks && i < 10; ++i) {
    char buf[256] = {0};
    if (H5Lget_name_by_idx(f, ".", H5_INDEX_NAME, H5_ITER_INC, i, buf, sizeof buf, H5P_DEFAULT) < 0) break;
    s += (s.empty() ? "" : ", ") + std::string("'") + buf + "'";
  }
  if (info.nlinks > 10) s += ", ...";
  return s.empty() ? "none" : s;
}

double read_double_attribute(const fs::path& file, hid_t obj, const char* name, const std::string& dataset) {
  if (H5Aexists(obj, name) <= 0)
    throw SurfaceFileError(file, "dataset '" + dataset + "' has no attribute '" + name +
                                     "': pass the physical size lx, ly explicitly");
  H5Handle a(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  if (!a.ok()) throw SurfaceFileError(file, "attribute '" + std::string(name) + "' of dataset '" + dataset + "' cannot be read");
  // One value: H5Aread writes every element of the attribute, and v holds one.
  H5Handle space(H5Aget_space(a), H5Sclose);
  if (!space.ok() || H5Sget_simple_extent_npoints(space) != 1)
    throw SurfaceFileError(file, "attribute '" + std::string(name) + "' of dataset '" + dataset +
                                     "' is not a single number");
  double v = 0;
  if (H5Aread(a, H5T_NATIVE_DOUBLE, &v) < 0 || !(v > 0) || !std::isfinite(v))
    throw SurfaceFileError(file, "attribute '" + std::string(name) + "' of dataset '" + dataset +
                                     "' is not a positive number");
  return v;
}

// "" when every value of the 2-D dataset d was written, else which part was not. Chunked
// datasets store only the chunks written (and H5Dget_space_status calls a compressed one
// partly allocated), so their chunks are counted; other layouts have all or nothing.
std::string unwritten_part(hid_t d, const hsize_t dims[2]) {
  H5Handle dcpl(H5Dget_create_plist(d), H5Pclose);
  if (dcpl.ok() && H5Pget_layout(dcpl) == H5D_CHUNKED) {
    hsize_t chunk[2] = {0, 0}, stored = 0;
    H5Handle space(H5Dget_space(d), H5Sclose);  // (HDF5 1.10 refuses H5S_ALL here)
    if (H5Pget_chunk(dcpl, 2, chunk) != 2 || chunk[0] == 0 || chunk[1] == 0 || !space.ok() ||
        H5Dget_num_chunks(d, space, &stored) < 0)
      return "(its chunks cannot be counted)";
    const hsize_t all = ((dims[0] + chunk[0] - 1) / chunk[0]) * ((dims[1] + chunk[1] - 1) / chunk[1]);
    if (stored < all)
      return "in " + std::to_string(all - stored) + " of its " + std::to_string(all) + " chunks (never written)";
    return "";
  }
  H5D_space_status_t status = H5D_SPACE_STATUS_ERROR;
  if (H5Dget_space_status(d, &status) < 0 || status != H5D_SPACE_STATUS_ALLOCATED) return "(never written)";
  return "";
}

void check_finite(const fs::path& file, const HeightMap& m, const std::string& where) {
  for (std::size_t i = 0; i < m.heights.size(); ++i)
    if (!std::isfinite(m.heights[i])) {
      const std::size_t ix = i % std::size_t(m.grid.nx), iy = i / std::size_t(m.grid.nx);
      throw SurfaceFileError(file, where + ": non-finite height " + std::to_string(m.heights[i]) + " at (ix=" +
                                       std::to_string(ix) + ", iy=" + std::to_string(iy) + ") = [" +
                                       std::to_string(iy) + "][" + std::to_string(ix) + "] (first offending value)");
    }
}

// ---------------------------------------------------------------- Fourier lists
struct ListedMode {
  FourierMode m;  // canonical half-plane
  long line;      // first line it came from
  int forms;      // bit 1: listed as k, bit 2: listed as -k
};

std::vector<ListedMode> parse_fourier_list(const fs::path& file, double scale, double max_bytes = 0.0) {
  const std::string text = read_text(file, max_bytes);
  constexpr long max_index = 1L << 24;
  std::vector<ListedMode> out;
  std::unordered_map<long long, std::size_t> where;
  for_each_line(text, [&](long line, const std::vector<std::string_view>& t) {
    const std::string at = "line " + std::to_string(line) + ": ";
    if (t.size() != 4)
      throw SurfaceFileError(file, at + "expected 4 values 'kx ky re im', found " + std::to_string(t.size()) +
                                       (t.size() < 4 ? " (truncated file?)" : ""));
    long kx, ky;
    double re, im;
    if (!parse_int(t[0], kx) || !parse_int(t[1], ky))
      throw SurfaceFileError(file, at + "wave indices kx ky must be integers, got " + quoted(t[0]) + " " + quoted(t[1]));
    if (!parse_double(t[2], re) || !parse_double(t[3], im))
      throw SurfaceFileError(file, at + "cannot parse the coefficient " + quoted(t[2]) + " " + quoted(t[3]));
    if (!std::isfinite(re) || !std::isfinite(im)) throw SurfaceFileError(file, at + "non-finite coefficient");
    if (std::abs(kx) > max_index || std::abs(ky) > max_index)
      throw SurfaceFileError(file, at + "wave index (" + std::to_string(kx) + ", " + std::to_string(ky) + ") out of range");
    Complex c(re * scale, im * scale);
    int form = 1;
    if (kx < 0 || (kx == 0 && ky < 0)) kx = -kx, ky = -ky, c = std::conj(c), form = 2;
    if (kx == 0 && ky == 0) c = Complex(c.real(), 0.0);  // the mean is real
    const long long key = ((long long)(kx) << 32) ^ (long long)(ky + max_index);
    auto [it, fresh] = where.try_emplace(key, out.size());
    if (fresh) {
      out.push_back({{int(kx), int(ky), c}, line, form});
      return;
    }
    ListedMode& prev = out[it->second];
    if ((prev.forms & form) || (kx == 0 && ky == 0))
      throw SurfaceFileError(file, at + "mode (" + std::string(t[0]) + ", " + std::string(t[1]) +
                                       ") listed twice (first on line " + std::to_string(prev.line) + ")");
    // Both k and -k listed: a real surface needs c_{-k} = conj(c_k).
    const double tol = 1e-6 * std::max(std::abs(c), std::abs(prev.m.c));
    if (std::abs(c - prev.m.c) > tol)
      throw SurfaceFileError(file, at + "coefficient is not the complex conjugate of mode (" + std::to_string(-kx) +
                                       ", " + std::to_string(-ky) + ") on line " + std::to_string(prev.line) +
                                       " (heights must be real)");
    prev.m.c = 0.5 * (prev.m.c + c);
    prev.forms |= form;
  });
  if (out.empty()) throw SurfaceFileError(file, "no Fourier modes (expected lines 'kx ky re im')");
  return out;
}

std::string grid_text(int nx, int ny) { return std::to_string(nx) + " x " + std::to_string(ny); }

HeightMap parse_ascii(const fs::path& file, double lx, double ly, double scale, bool require_square,
                      const MapLimit& limit) {
  check_size(file, lx, ly);
  const std::string text = read_text(file, limit.max_text_bytes());
  std::vector<double> v;
  v.reserve(std::min<std::size_t>(text.size() / 8, std::size_t(limit.nx * limit.ny)));
  long nx = -1, ny = 0, first_line = 0;
  for_each_line(text, [&](long line, const std::vector<std::string_view>& t) {
    const std::string at = "line " + std::to_string(line);
    if (nx < 0) nx = long(t.size()), first_line = line;
    if (nx > limit.nx)
      throw SurfaceShapeError(file, at + " has " + std::to_string(t.size()) + " values, more than the " +
                                       std::to_string(limit.nx) + " columns (points along x) expected");
    if (ny >= limit.ny)
      throw SurfaceShapeError(file, at + ": more than the " + std::to_string(limit.ny) +
                                       " rows (points along y) expected");
    if (long(t.size()) != nx)
      throw SurfaceFileError(file, at + " has " + std::to_string(t.size()) + " values, expected " + std::to_string(nx) +
                                       " like line " + std::to_string(first_line) + " (ragged rows or truncated file)");
    for (std::size_t j = 0; j < t.size(); ++j) {
      double x;
      if (!parse_double(t[j], x))
        throw SurfaceFileError(file, at + ", column " + std::to_string(j + 1) + ": cannot parse " + quoted(t[j]) + " as a number");
      if (!std::isfinite(x))
        throw SurfaceFileError(file, at + ", column " + std::to_string(j + 1) + ": non-finite height " + quoted(t[j]));
      v.push_back(x * scale);
    }
    ++ny;
  });
  if (ny == 0) throw SurfaceFileError(file, "no data (expected a matrix of heights, one row per line)");
  if (require_square && nx != ny)
    throw SurfaceFileError(file, "height matrix is " + grid_text(int(nx), int(ny)) + " (columns x rows), expected a square");
  HeightMap m{Grid{int(nx), int(ny), lx, ly}, Field(v.begin(), v.end())};
  return m;
}

HeightMap read_hdf5(const fs::path& file, const std::string& dataset, double lx, double ly, double scale,
                    bool require_square, const MapLimit& limit) {
  std::error_code ec;
  if (!fs::exists(file, ec)) throw SurfaceFileError(file, "no such file");
  H5Quiet quiet;
  H5Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!f.ok()) throw SurfaceFileError(file, "cannot open as HDF5 (not an HDF5 file, or truncated/corrupt)");
  if (H5Lexists(f, dataset.c_str(), H5P_DEFAULT) <= 0)
    throw SurfaceFileError(file, "no dataset '" + dataset + "' (expected a 2-D height dataset; the file has " +
                                     root_names(f) + ")");
  H5Handle d(H5Dopen2(f, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) throw SurfaceFileError(file, "'" + dataset + "' is not a readable dataset");
  H5Handle space(H5Dget_space(d), H5Sclose);
  const int rank = space.ok() ? H5Sget_simple_extent_ndims(space) : -1;
  if (rank != 2)
    throw SurfaceFileError(file, "dataset '" + dataset + "' has " + std::to_string(rank) + " dimensions, expected 2");
  hsize_t dims[2];
  H5Sget_simple_extent_dims(space, dims, nullptr);
  H5Handle type(H5Dget_type(d), H5Tclose);
  const H5T_class_t cls = type.ok() ? H5Tget_class(type) : H5T_NO_CLASS;
  if (cls != H5T_FLOAT && cls != H5T_INTEGER)
    throw SurfaceFileError(file, "dataset '" + dataset + "' is not numeric (expected floating-point heights)");
  // The declared shape, checked before anything of that size is allocated or read.
  if (dims[0] == 0 || dims[1] == 0)
    throw SurfaceFileError(file, "dataset '" + dataset + "' has unusable extent " + std::to_string(dims[1]) + " x " +
                                     std::to_string(dims[0]));
  if (dims[1] > hsize_t(limit.nx) || dims[0] > hsize_t(limit.ny))
    throw SurfaceShapeError(file, "dataset '" + dataset + "' declares " + std::to_string(dims[1]) + " x " +
                                     std::to_string(dims[0]) + " points (x by y), more than the " +
                                     std::to_string(limit.nx) + " x " + std::to_string(limit.ny) + " expected");
  // A dataset created but never (fully) written reads as its fill value (a flat surface):
  // refuse it, before allocating what its extent claims.
  if (const std::string missing = unwritten_part(d, dims); !missing.empty())
    throw SurfaceFileError(file, "dataset '" + dataset + "' holds no data " + missing);
  const int nx = int(dims[1]), ny = int(dims[0]);
  if (require_square && nx != ny)
    throw SurfaceFileError(file, "dataset '" + dataset + "' is " + grid_text(nx, ny) + ", expected a square");
  if (lx <= 0 || ly <= 0) {
    lx = read_double_attribute(file, d, "lx", dataset);
    ly = read_double_attribute(file, d, "ly", dataset);
  }
  check_size(file, lx, ly);
  HeightMap m{Grid{nx, ny, lx, ly}, Field(std::size_t(nx) * ny)};
  if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.heights.data()) < 0)
    throw SurfaceFileError(file, "reading dataset '" + dataset + "' failed (truncated or corrupt file?)");
  check_finite(file, m, "dataset '" + dataset + "'");
  if (scale != 1.0)
    for (double& h : m.heights) h *= scale;
  return m;
}

}  // namespace

// ---------------------------------------------------------------- public readers
HeightMap read_challenge_hdf5(const fs::path& file, MapLimit limit) {
  return read_hdf5(file, "surface", 1.0, 1.0, 1.0, true, limit);
}

HeightMap read_challenge_ascii(const fs::path& file, double height_scale, MapLimit limit) {
  return parse_ascii(file, 1.0, 1.0, height_scale, true, limit);
}

HeightMap read_hdf5_heights(const fs::path& file, const std::string& dataset, double lx, double ly, double height_scale,
                            bool require_square, MapLimit limit) {
  return read_hdf5(file, dataset, lx, ly, height_scale, require_square, limit);
}

HeightMap read_ascii_heights(const fs::path& file, double lx, double ly, double height_scale, bool require_square,
                             MapLimit limit) {
  return parse_ascii(file, lx, ly, height_scale, require_square, limit);
}

std::vector<FourierMode> read_fourier_list(const fs::path& file, double scale) {
  std::vector<FourierMode> out;
  for (const ListedMode& l : parse_fourier_list(file, scale)) out.push_back(l.m);
  return out;
}

HeightMap read_fourier_heights(const fs::path& file, int n, double scale, double box) {
  check_size(file, box, box);
  const std::vector<ListedMode> listed =
      parse_fourier_list(file, scale, n > 0 ? MapLimit{n, n}.max_text_bytes() : 0.0);
  long kmax = 0;
  for (const ListedMode& l : listed) kmax = std::max({kmax, long(std::abs(l.m.kx)), long(std::abs(l.m.ky))});
  if (n == 0) {
    n = 2;
    while (n / 2 <= kmax) n *= 2;
  } else if (n < 1) {
    throw SurfaceFileError(file, "grid size must be positive");
  }
  std::vector<FourierMode> modes;
  modes.reserve(listed.size());
  for (const ListedMode& l : listed) {
    if (2L * std::abs(l.m.kx) >= n || 2L * std::abs(l.m.ky) >= n)
      throw SurfaceFileError(file, "line " + std::to_string(l.line) + ": mode (" + std::to_string(l.m.kx) + ", " +
                                       std::to_string(l.m.ky) + ") is out of range for a " + grid_text(n, n) +
                                       " grid (need |kx|, |ky| < " + std::to_string(n / 2) + ")");
    modes.push_back(l.m);
  }
  return synthesize(modes, Grid{n, n, box, box}).map;
}

// ---------------------------------------------------------------- writers
void write_hdf5_heights(const fs::path& file, const HeightMap& map, const std::string& dataset) {
  check_map(file, map);
  write_atomic(file, [&](const fs::path& tmp) {
    H5Quiet quiet;
    H5Handle f(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!f.ok()) throw SurfaceFileError(file, "cannot create HDF5 file " + tmp.string());
    const hsize_t dims[2] = {hsize_t(map.grid.ny), hsize_t(map.grid.nx)};
    H5Handle space(H5Screate_simple(2, dims, nullptr), H5Sclose);
    H5Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
    H5Pset_create_intermediate_group(lcpl, 1);
    H5Handle d(H5Dcreate2(f, dataset.c_str(), H5T_IEEE_F64LE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
    if (!d.ok() || H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, map.heights.data()) < 0)
      throw SurfaceFileError(file, "cannot write dataset '" + dataset + "'");
    H5Handle scalar(H5Screate(H5S_SCALAR), H5Sclose);
    for (auto [name, value] : {std::pair{"lx", map.grid.lx}, std::pair{"ly", map.grid.ly}}) {
      H5Handle a(H5Acreate2(d, name, H5T_IEEE_F64LE, scalar, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
      if (!a.ok() || H5Awrite(a, H5T_NATIVE_DOUBLE, &value) < 0)
        throw SurfaceFileError(file, std::string("cannot write attribute '") + name + "'");
    }
    d.reset();
    if (f.reset() < 0) throw SurfaceFileError(file, "closing HDF5 file failed (disk full?)");
  });
}

namespace {
template <class Lines>
void write_text(const fs::path& file, Lines&& lines) {
  write_atomic(file, [&](const fs::path& tmp) {
    std::FILE* fp = std::fopen(tmp.c_str(), "w");
    if (!fp) throw SurfaceFileError(file, "cannot create " + tmp.string());
    lines(fp);
    const bool bad = std::ferror(fp) != 0;
    if (std::fclose(fp) != 0 || bad) throw SurfaceFileError(file, "write error (disk full?)");
  });
}
}  // namespace

void write_ascii_heights(const fs::path& file, const HeightMap& map, double height_scale) {
  check_map(file, map);
  write_text(file, [&](std::FILE* fp) {
    const std::size_t nx = std::size_t(map.grid.nx);
    for (std::size_t iy = 0; iy < std::size_t(map.grid.ny); ++iy)
      for (std::size_t ix = 0; ix < nx; ++ix)
        std::fprintf(fp, "%.17g%c", map.heights[iy * nx + ix] / height_scale, ix + 1 < nx ? ' ' : '\n');
  });
}

void write_fourier_list(const fs::path& file, const std::vector<FourierMode>& modes) {
  write_text(file, [&](std::FILE* fp) {
    std::fprintf(fp, "# kx ky re(c_k) im(c_k);  h(x) = sum_k c_k exp(+2 pi i k.x / L), c_k = FFT(h)/N;"
                     " c_{-k} = conj(c_k) implied\n");
    for (const FourierMode& m : modes) std::fprintf(fp, "%d %d %.17g %.17g\n", m.kx, m.ky, m.c.real(), m.c.imag());
  });
}

}  // namespace cmc
