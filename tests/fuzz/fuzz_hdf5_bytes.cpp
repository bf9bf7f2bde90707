// libFuzzer target: the HDF5 height readers of surface/SurfaceIO (generic, with the box
// size from the dataset's attributes, and the challenge's own format), on any bytes
// taken as an HDF5 file.
//
// Bad input must end in a SurfaceFileError (the documented error); anything else thrown
// is a finding. A map that was read must match its grid and hold finite heights, and
// the readers must leave no HDF5 object open (they hold every id in an H5Handle).
#include "FuzzInput.hpp"

#include "cmc/surface/SurfaceIO.hpp"

#include <hdf5.h>

#include <cmath>
#include <exception>
#include <string>

namespace {

using cmc::fuzz::require;

void check_map(const cmc::HeightMap& m, bool square) {
  require(m.grid.nx >= 1 && m.grid.ny >= 1, "height map without points");
  require(m.heights.size() == std::size_t(m.grid.nx) * std::size_t(m.grid.ny), "height map does not match its grid");
  require(!square || m.grid.nx == m.grid.ny, "challenge map is not square");
  require(std::isfinite(m.grid.lx) && m.grid.lx > 0 && std::isfinite(m.grid.ly) && m.grid.ly > 0,
          "box size not positive and finite");
  for (double h : m.heights) require(std::isfinite(h), "non-finite height accepted");
}

template <class F>
void expect_surface_error_or_ok(const char* what, F&& f) {
  try {
    f();
  } catch (const cmc::SurfaceFileError&) {
    // bad input, reported as such
  } catch (const std::exception& e) {
    cmc::fuzz::fail(std::string(what) + " threw something other than SurfaceFileError: " + e.what());
  }
  const ssize_t open = H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL);
  require(open == 0, std::string(what) + " left " + std::to_string(open) + " HDF5 object(s) open");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static cmc::fuzz::TempFile file("heights.h5");
  file.write(cmc::fuzz::as_text(data, size));
  expect_surface_error_or_ok("read_hdf5_heights", [&] {
    check_map(cmc::read_hdf5_heights(file.path(), "surface", 0.0, 0.0, 1e-6), false);
  });
  expect_surface_error_or_ok("read_challenge_hdf5", [&] { check_map(cmc::read_challenge_hdf5(file.path()), true); });
  return 0;
}
