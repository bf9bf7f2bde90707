// libFuzzer target: the text height readers of surface/SurfaceIO (the ASCII height matrix,
// generic and challenge flavour, and the Fourier-coefficient list), on any bytes.
//
// Bad input must end in a SurfaceFileError (the documented error); anything else thrown
// is a finding. A map that was read must match its grid and hold finite heights; a
// Fourier list must hold finite coefficients in the canonical half-plane.
#include "FuzzInput.hpp"

#include "cmc/surface/SurfaceIO.hpp"

#include <cmath>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

using cmc::fuzz::require;

void check_map(const cmc::HeightMap& m, bool square) {
  require(m.grid.nx >= 1 && m.grid.ny >= 1, "height map without points");
  require(m.heights.size() == std::size_t(m.grid.nx) * std::size_t(m.grid.ny), "height map does not match its grid");
  require(!square || m.grid.nx == m.grid.ny, "challenge map is not square");
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
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static cmc::fuzz::TempFile file("heights.txt");
  file.write(cmc::fuzz::as_text(data, size));
  expect_surface_error_or_ok("read_ascii_heights", [&] {
    check_map(cmc::read_ascii_heights(file.path(), 1e-4, 2e-4, 1e-6), false);
  });
  expect_surface_error_or_ok("read_challenge_ascii", [&] {
    check_map(cmc::read_challenge_ascii(file.path(), 0.5), true);
  });
  expect_surface_error_or_ok("read_fourier_list", [&] {
    const auto modes = cmc::read_fourier_list(file.path(), 1e-4);
    require(!modes.empty(), "empty Fourier list accepted");
    for (const auto& m : modes) {
      require(m.kx > 0 || (m.kx == 0 && m.ky >= 0), "mode outside the canonical half-plane");
      require(std::abs(m.kx) <= (1 << 24) && std::abs(m.ky) <= (1 << 24), "wave index out of range accepted");
      require(std::isfinite(m.c.real()) && std::isfinite(m.c.imag()), "non-finite coefficient accepted");
      require(m.kx != 0 || m.ky != 0 || m.c.imag() == 0, "complex mean height");
    }
  });
  return 0;
}
