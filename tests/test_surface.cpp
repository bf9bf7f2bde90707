// Tests of the challenge surface generator, surface readers/writers and statistics.
#include "cmc/surface/SelfAffine.hpp"
#include "cmc/surface/SurfaceIO.hpp"
#include "cmc/contact/Interaction.hpp"
#include "cmc/surface/SurfaceStats.hpp"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;
using namespace cmc;

namespace {
constexpr double pi = std::numbers::pi;

// Large grids: plan with FFTW_ESTIMATE unless the caller chose a planner (FFTW_MEASURE
// at 4096^2 costs tens of seconds the first time). Scoped, so other tests are unaffected.
struct EstimatePlanner {
  bool set = std::getenv("CMC_FFTW_PLANNER") == nullptr;
  EstimatePlanner() { if (set) setenv("CMC_FFTW_PLANNER", "estimate", 1); }
  ~EstimatePlanner() { if (set) unsetenv("CMC_FFTW_PLANNER"); }
};

// A small band (K = 60) that fits a 128^2 grid: fast, same code path as the challenge.
SelfAffineSpec small_spec(unsigned long seed = 7) {
  SelfAffineSpec s;
  s.cutoff_wavelength = 1.0 / 60;
  s.seed = seed;
  return s;
}

double max_abs(const std::vector<FourierMode>& m) {
  double a = 0;
  for (auto& x : m) a = std::max(a, std::abs(x.c));
  return a;
}

// Every mode of `list` that fits an n x n grid (|kx|, |ky| < n/2) must appear in the grid's
// spectrum `got` (fourier_modes of the surface) with the same coefficient; k = 0 is the
// min-shift and is skipped. Returns the number compared.
long compare_modes(const std::vector<FourierMode>& list, const HeightMap& map, double tol) {
  const int n = map.grid.nx;
  const Grid& g = map.grid;
  Fourier fft(g.nx, g.ny);
  fft.forward(map.heights);
  const auto s = fft.spectrum();
  long compared = 0;
  double worst = 0;
  for (const auto& m : list) {
    if (2 * m.kx >= n || 2 * std::abs(m.ky) >= n) continue;
    const Complex c = s[std::size_t(m.ky >= 0 ? m.ky : m.ky + n) * g.nqx() + m.kx] * fft.normalisation();
    worst = std::max(worst, std::abs(c - m.c));
    ++compared;
  }
  EXPECT_LE(worst, tol) << "on the " << n << "^2 grid";
  return compared;
}
}  // namespace

// ------------------------------------------------------------------ generator

// The challenge surface itself: defaults (H = 0.8, lambda_r = L/5, lambda_s = L/1000,
// rms gradient 1, seed 28) on 2048^2, the smallest grid that holds every mode (~0.5 s).
TEST(SelfAffine, ChallengeSurface2048) {
  EstimatePlanner planner;
  const SelfAffineSpec spec;
  const SelfAffineSurface s = generate_self_affine(spec, 2048);
  EXPECT_EQ(s.modes_dropped, 0);
  EXPECT_FALSE(s.low_passed());
  EXPECT_NEAR(s.modes_total, pi * 1000 * 1000 / 2, 2 * pi * 1000);  // half of the disc |k| <= 1000
  const SurfaceStatistics st = surface_statistics(s.map.grid, s.map.heights);
  // Normalised from the full band; on a grid holding every mode Parseval makes the grid's
  // rms gradient equal to it up to rounding (~1e-15): 1e-12 leaves a wide margin.
  EXPECT_NEAR(st.rms_gradient, 1.0, 1e-12);
  EXPECT_EQ(st.min, 0.0);  // shifted by exactly -min
  // Problem definition: rms height 0.762 µm = 0.762e-2 L. A realisation scatters by ~4 %
  // (std over seeds 1..100 of the full-band rms: 0.780 ± 0.031 µm), so 5 % holds for this
  // seed (0.750 µm) but not for every seed; the ensemble value is checked separately below.
  EXPECT_NEAR(st.rms_height / 0.762e-2, 1.0, 0.05);
  // R_c = 60 nm = 6e-4 L from the rms line-scan curvature. Curvature is set by ~1e6 short-
  // wavelength modes: realisation scatter < 0.5 %, expected 60.1 nm; 5 % as asked.
  EXPECT_NEAR(st.curvature_radius / 6e-4, 1.0, 0.05);
  // mu_T = 3 for w = 2e-5, E* = 1, rho = 2.071e-5 (reduced units of the problem definition).
  EXPECT_NEAR(tabor_parameter(1.0, st.curvature_radius, 2e-5, 2.071e-5) / 3.0, 1.0, 0.05);
  // The other curvature definition (|Lap h|/2) would give ~73.6 nm: clearly distinguishable.
  EXPECT_GT(1.0 / st.rms_mean_curvature, 1.15 * 6e-4);
  EXPECT_NEAR(st.mean, s.shift, 1e-12);  // synthesis has zero mean
}

// The ensemble (expected) rms height of the normalised band is grid- and seed-independent
// up to the 1 % scatter of the normalisation constant: 0.78 µm vs the published 0.762 µm.
TEST(SelfAffine, ExpectedRmsHeightOfBand) {
  const SelfAffineSpec spec;
  const SelfAffineModes band = self_affine_modes(spec);
  double var = 0, grad = 0;
  for (const auto& m : band.modes) {
    const double k = std::hypot(m.kx, m.ky);
    var += 2 * band.amplitude * band.amplitude * self_affine_shape(spec, k);
    grad += 2 * std::norm(m.c) * 4 * pi * pi * k * k;
  }
  EXPECT_NEAR(std::sqrt(var) / 0.762e-2, 1.0, 0.05);
  EXPECT_NEAR(grad, 1.0, 1e-13);  // the band itself is normalised exactly
  EXPECT_EQ(band.max_index, 1000);
  EXPECT_EQ(band.full_grid(), 2048);
}

// Same seed, same modes at every grid size: a small band on 64^2 (low-passed) and 256^2.
TEST(SelfAffine, SameModesAtEveryGridSizeSmallBand) {
  const SelfAffineSpec spec = small_spec();
  const SelfAffineModes band = self_affine_modes(spec);
  const double tol = 1e-12 * max_abs(band.modes);  // FFT rounding ~1e-16 relative
  const auto coarse = generate_self_affine(spec, 64), fine = generate_self_affine(spec, 256);
  EXPECT_GT(coarse.modes_dropped, 0);
  EXPECT_EQ(fine.modes_dropped, 0);
  const long nc = compare_modes(band.modes, coarse.map, tol), nf = compare_modes(band.modes, fine.map, tol);
  EXPECT_EQ(nf, long(band.modes.size()));
  EXPECT_EQ(nc, long(band.modes.size()) - coarse.modes_dropped);
  // The coarse grid's rms gradient is below 1 (modes cut), the fine one's is 1.
  EXPECT_LT(surface_statistics(coarse.map.grid, coarse.map.heights).rms_gradient, 0.99);
  EXPECT_NEAR(surface_statistics(fine.map.grid, fine.map.heights).rms_gradient, 1.0, 1e-12);
}

// The real thing: the challenge band on 1024^2 (low-passed) and 4096^2 (~3 s in all).
TEST(SelfAffine, SameModesChallenge1024And4096) {
  EstimatePlanner planner;
  const SelfAffineSpec spec;
  const SelfAffineModes band = self_affine_modes(spec);
  const double tol = 1e-12 * max_abs(band.modes);
  {
    const auto s = generate_self_affine(spec, 1024);
    EXPECT_TRUE(s.low_passed());
    EXPECT_EQ(compare_modes(band.modes, s.map, tol), long(band.modes.size()) - s.modes_dropped);
  }
  {
    const auto s = generate_self_affine(spec, 4096);
    EXPECT_FALSE(s.low_passed());
    EXPECT_EQ(compare_modes(band.modes, s.map, tol), long(band.modes.size()));
  }
}

TEST(SelfAffine, SeedsAreDeterministicAndDistinct) {
  const auto a = self_affine_modes(small_spec(1)), b = self_affine_modes(small_spec(1)),
             c = self_affine_modes(small_spec(2));
  ASSERT_EQ(a.modes.size(), c.modes.size());
  double same = 0, diff = 0, norm = 0;
  for (std::size_t i = 0; i < a.modes.size(); ++i) {
    same = std::max(same, std::abs(a.modes[i].c - b.modes[i].c));
    diff += std::norm(a.modes[i].c - c.modes[i].c);
    norm += std::norm(a.modes[i].c);
  }
  EXPECT_EQ(same, 0.0);  // bitwise reproducible
  // Independent realisations: E|a-c|^2 = 2 E|a|^2; anything above 1 is "different".
  EXPECT_GT(diff / norm, 1.0);
  const auto sa = generate_self_affine(small_spec(1), 128), sc = generate_self_affine(small_spec(2), 128);
  EXPECT_NE(sa.map.heights, sc.map.heights);
}

// The realised spectrum follows C ~ q^{-2(1+H)} between q_r and q_s. Fixed seed, so the
// check is deterministic; tolerances reflect the statistics: ~3e5 modes in the fit range
// make the count-weighted mean ratio accurate to < 1 %, the slope to < 0.02.
TEST(SelfAffine, SpectrumFollowsPowerLaw) {
  EstimatePlanner planner;
  const SelfAffineSpec spec;
  const SelfAffineModes band = self_affine_modes(spec);
  const auto s = generate_self_affine(spec, 2048);
  const RadialPsd psd = radial_psd(s.map.grid, s.map.heights, 200, true);
  double sw = 0, sr = 0, n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < psd.q.size(); ++i) {
    const double q = psd.q[i];
    if (q < 2 * 2 * pi * 5 || q > 2 * pi * 500) continue;
    sr += psd.count[i] * psd.C[i] / band.expected_psd(spec, q);
    sw += psd.count[i];
    const double x = std::log(q), y = std::log(psd.C[i]);
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  EXPECT_NEAR(sr / sw, 1.0, 0.02);
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  EXPECT_NEAR(slope, -2 * (1 + spec.hurst), 0.05);
  // Nothing beyond the cutoff: linear bins centred on |k| = 1001, 1002, ... hold only modes
  // with |k| > 1000.5, whose power is FFT rounding noise (~1e-6 of C(q_s) would already be
  // 1e20 times the noise of ~eps * h per point): 1e-12 C(q_s) is a safe bound.
  const RadialPsd lin = radial_psd(s.map.grid, s.map.heights);
  int beyond = 0;
  for (std::size_t i = 0; i < lin.q.size(); ++i)
    if (lin.q[i] > 2 * pi * 1000.6) {
      ++beyond;
      EXPECT_LT(lin.C[i], 1e-12 * band.expected_psd(spec, 2 * pi * 1000)) << "q/2pi = " << lin.q[i] / (2 * pi);
    }
  EXPECT_GT(beyond, 10);
}

TEST(SelfAffine, ShapeAndBadSpecs) {
  const SelfAffineSpec spec;
  EXPECT_EQ(self_affine_shape(spec, 0.0), 0.0);
  EXPECT_EQ(self_affine_shape(spec, 1.0), 1.0);
  EXPECT_EQ(self_affine_shape(spec, 4.99), 1.0);
  EXPECT_NEAR(self_affine_shape(spec, 10.0), std::pow(2.0, -3.6), 1e-15);
  EXPECT_GT(self_affine_shape(spec, 1000.0), 0.0);
  EXPECT_EQ(self_affine_shape(spec, 1000.5), 0.0);
  SelfAffineSpec bad = spec;
  bad.cutoff_wavelength = 0;
  EXPECT_THROW(self_affine_modes(bad), std::invalid_argument);
  bad = spec;
  bad.rms_gradient = -1;
  EXPECT_THROW(self_affine_modes(bad), std::invalid_argument);
  EXPECT_THROW(generate_self_affine(small_spec(), Grid{64, 64, 1.0, 2.0}), std::invalid_argument);
}

// A box of side L != 1: heights scale with L, gradient unchanged.
TEST(SelfAffine, BoxSideScalesHeights) {
  const auto a = generate_self_affine(small_spec(), Grid{128, 128, 1.0, 1.0});
  const auto b = generate_self_affine(small_spec(), Grid{128, 128, 3.0, 3.0});
  for (std::size_t i = 0; i < a.map.heights.size(); i += 97) EXPECT_NEAR(b.map.heights[i], 3 * a.map.heights[i], 1e-14);
  EXPECT_NEAR(surface_statistics(b.map.grid, b.map.heights).rms_gradient, 1.0, 1e-12);
}

// ------------------------------------------------------------------ interpolation

TEST(FourierInterpolation, BandLimitedCosineIsExact) {
  const Grid g{16, 12, 2.0, 1.5};
  auto f = [&](double x, double y) {
    return 0.25 + std::cos(2 * pi * (3 * x / g.lx + 2 * y / g.ly)) + 0.5 * std::sin(2 * pi * (5 * x / g.lx - 4 * y / g.ly));
  };
  HeightMap m{g, g.field()};
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) m.heights[iy * g.nx + ix] = f(ix * g.dx(), iy * g.dy());
  const HeightMap fine = fourier_interpolate(m, 64, 48);
  EXPECT_EQ(fine.grid.lx, g.lx);
  double err = 0;
  for (int iy = 0; iy < 48; ++iy)
    for (int ix = 0; ix < 64; ++ix)
      err = std::max(err, std::abs(fine.heights[iy * 64 + ix] - f(ix * fine.grid.dx(), iy * fine.grid.dy())));
  EXPECT_LT(err, 1e-13);  // rounding of two FFTs of O(1) data
}

// A pure Nyquist mode (+1, -1, ...) is split symmetrically: cos(pi x / dx), zero between.
TEST(FourierInterpolation, NyquistSplitKeepsCoarsePoints) {
  const Grid g{8, 8, 1.0, 1.0};
  HeightMap m{g, g.field()};
  for (int iy = 0; iy < 8; ++iy)
    for (int ix = 0; ix < 8; ++ix) m.heights[iy * 8 + ix] = ((ix + iy) % 2 ? -1.0 : 1.0);
  const HeightMap fine = fourier_interpolate(m, 16, 16);
  for (int iy = 0; iy < 16; ++iy)
    for (int ix = 0; ix < 16; ++ix) {
      const double expect = std::cos(pi * ix / 2.0) * std::cos(pi * iy / 2.0);
      EXPECT_NEAR(fine.heights[iy * 16 + ix], expect, 1e-14) << ix << "," << iy;
    }
}

// Interpolating a generated surface reproduces the surface generated on the finer grid
// (same modes; the min-shifts differ and are removed).
TEST(FourierInterpolation, GeneratedSurfaceMatchesFinerGeneration) {
  const auto c = generate_self_affine(small_spec(), 128), f = generate_self_affine(small_spec(), 512);
  const HeightMap up = fourier_interpolate(c.map, 512, 512);
  double err = 0;
  for (std::size_t i = 0; i < up.heights.size(); ++i)
    err = std::max(err, std::abs((up.heights[i] - c.shift) - (f.map.heights[i] - f.shift)));
  EXPECT_LT(err, 1e-12 * surface_statistics(f.map.grid, f.map.heights).rms_height);
}

// ------------------------------------------------------------------ statistics

TEST(SurfaceStats, CosineExactMoments) {
  const Grid g{64, 32, 2.0, 1.0};
  const double a = 0.3, q = 2 * pi * 3 / g.lx;
  Field h = g.field();
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) h[iy * g.nx + ix] = 1.0 + a * std::cos(q * ix * g.dx());
  const auto s = surface_statistics(g, h);
  EXPECT_NEAR(s.mean, 1.0, 1e-14);
  EXPECT_NEAR(s.max, 1.0 + a, 1e-14);
  EXPECT_NEAR(s.rms_height, a / std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(s.rms_gradient, a * q / std::sqrt(2.0), 1e-13);
  EXPECT_NEAR(s.rms_slope_y, 0.0, 1e-13);
  // Line scans along x have <h_xx^2> = a^2 q^4 / 2, along y zero: mean of the two.
  EXPECT_NEAR(s.rms_curvature, a * q * q / 2, 1e-12);
  EXPECT_NEAR(s.rms_mean_curvature, a * q * q / (2 * std::sqrt(2.0)), 1e-12);
  EXPECT_NEAR(s.curvature_radius, 2 / (a * q * q), 1e-12);
  // PSD: one bin at q, integral d^2q C = <dh^2>.
  // Every bin holding modes is returned; all but one hold rounding noise only. The bin of
  // q (width 2 pi / lx) also holds other modes with |q| within half a bin, so its mean |q|
  // is only near q, but count * C * dq_x dq_y must be the whole variance (Parseval).
  const RadialPsd p = radial_psd(g, h);
  std::size_t hit = 0, nonzero = 0;
  for (std::size_t i = 0; i < p.q.size(); ++i)
    if (p.C[i] > 1e-20) hit = i, ++nonzero;
  ASSERT_EQ(nonzero, 1u);
  EXPECT_NEAR(p.q[hit], q, 0.5 * 2 * pi / g.lx);
  const double dq2 = (2 * pi / g.lx) * (2 * pi / g.ly);
  EXPECT_NEAR(p.count[hit] * p.C[hit] * dq2, a * a / 2, 1e-14);
}

TEST(SurfaceStats, TaborParameterAndPsdNormalisation) {
  // mu_T = R^{1/3} (w/E*)^{2/3} / rho: R = 6e-4, w = 2e-5, rho = 2.071e-5 -> 3.0014...
  EXPECT_NEAR(tabor_parameter(1.0, 6e-4, 2e-5, 2.071e-5), std::cbrt(6e-4) * std::pow(2e-5, 2.0 / 3.0) / 2.071e-5, 1e-12);
  EXPECT_NEAR(tabor_parameter(1.0, 6e-4, 2e-5, 2.071e-5), 3.0, 0.01);
  EXPECT_THROW(tabor_parameter(1, -1, 1, 1), std::invalid_argument);
  // Parseval for the binned PSD: every mode of a K = 60 band on 256^2 lies inside the bins.
  const auto s = generate_self_affine(small_spec(), 256);
  const RadialPsd p = radial_psd(s.map.grid, s.map.heights);
  double integral = 0;
  for (std::size_t i = 0; i < p.q.size(); ++i) integral += p.count[i] * p.C[i] * 4 * pi * pi;
  const double rms = surface_statistics(s.map.grid, s.map.heights).rms_height;
  EXPECT_NEAR(integral, rms * rms, 1e-12 * rms * rms);
}

// ------------------------------------------------------------------ readers and writers

class SurfaceFiles : public ::testing::Test {
 protected:
  fs::path dir;
  void SetUp() override {
    dir = fs::temp_directory_path() / ("cmc_test_surface_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  fs::path text(const std::string& name, const std::string& content) {
    const fs::path p = dir / name;
    std::ofstream(p) << content;
    return p;
  }
  static HeightMap ramp(int nx, int ny, double lx, double ly) {
    HeightMap m{Grid{nx, ny, lx, ly}, Field(std::size_t(nx) * ny)};
    for (std::size_t i = 0; i < m.heights.size(); ++i) m.heights[i] = std::sin(0.37 * double(i)) * 1e-3 + 1.0 / 3.0;
    return m;
  }
  // Runs f, which must throw SurfaceFileError naming `file` and containing `needle`.
  template <class F>
  static void expect_error(F&& f, const fs::path& file, const std::string& needle) {
    try {
      f();
      ADD_FAILURE() << "no error for " << file;
    } catch (const SurfaceFileError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(file.string()), std::string::npos) << m;
      EXPECT_NE(m.find(needle), std::string::npos) << "expected '" << needle << "' in: " << m;
    }
  }
  bool no_temporaries() const {
    for (auto& e : fs::directory_iterator(dir))
      if (e.path().string().find(".tmp") != std::string::npos) return false;
    return true;
  }
};

TEST_F(SurfaceFiles, Hdf5RoundTrip) {
  const HeightMap m = ramp(12, 8, 2.0, 3.0);
  const fs::path p = dir / "map.h5";
  write_hdf5_heights(p, m);
  EXPECT_TRUE(no_temporaries());
  const HeightMap a = read_hdf5_heights(p);  // size from the attributes
  EXPECT_EQ(a.grid.nx, 12);
  EXPECT_EQ(a.grid.ny, 8);
  EXPECT_EQ(a.grid.lx, 2.0);
  EXPECT_EQ(a.grid.ly, 3.0);
  EXPECT_EQ(a.heights, m.heights);  // bitwise
  const HeightMap b = read_hdf5_heights(p, "surface", 5.0, 6.0, 2.0);
  EXPECT_EQ(b.grid.lx, 5.0);
  EXPECT_EQ(b.heights[5], 2.0 * m.heights[5]);
  // Nested dataset names and the challenge reader (square, box 1).
  const HeightMap sq = ramp(16, 16, 1.0, 1.0);
  write_hdf5_heights(dir / "challenge.h5", sq);
  write_hdf5_heights(dir / "nested.h5", sq, "/data/heights");
  EXPECT_EQ(read_challenge_hdf5(dir / "challenge.h5").heights, sq.heights);
  EXPECT_EQ(read_hdf5_heights(dir / "nested.h5", "/data/heights", 1, 1).heights, sq.heights);
  write_hdf5_heights(p, sq);  // overwriting is atomic too
  EXPECT_EQ(read_hdf5_heights(p).grid.nx, 16);
}

TEST_F(SurfaceFiles, AsciiRoundTrip) {
  const HeightMap m = ramp(7, 5, 1.0, 2.0);
  const fs::path p = dir / "map.txt";
  write_ascii_heights(p, m);
  EXPECT_TRUE(no_temporaries());
  const HeightMap a = read_ascii_heights(p, 1.0, 2.0);
  EXPECT_EQ(a.grid.nx, 7);
  EXPECT_EQ(a.grid.ny, 5);
  EXPECT_EQ(a.heights, m.heights);  // %.17g round-trips doubles exactly
  // Challenge ASCII: square, units given by the caller (here micrometres -> L = 100 µm).
  const fs::path c = text("challenge.txt", "# heights in um\n1 2.5\n\n+3e0 4 # trailing comment\n");
  const HeightMap b = read_challenge_ascii(c, 1e-2);
  EXPECT_EQ(b.grid.nx, 2);
  EXPECT_NEAR(b.heights[1], 2.5e-2, 1e-17);
  EXPECT_NEAR(b.heights[2], 3e-2, 1e-17);  // row 2 is iy = 1
  EXPECT_EQ(b.grid.lx, 1.0);
}

TEST_F(SurfaceFiles, FourierListRoundTripAndConvention) {
  // Convention: h = sum_k c_k exp(+2 pi i k.x/L): c_(1,0) = 0.5 alone (partner implied) or
  // with its conjugate listed gives h = cos(2 pi x / L).
  for (const char* content : {"1 0 0.5 0\n", "1 0 0.5 0\n-1 0 0.5 -0\n", "1, 0, 0.5, 0.0\n"}) {
    const fs::path p = text("cos.txt", content);
    const HeightMap h = read_fourier_heights(p, 8);
    for (int ix = 0; ix < 8; ++ix) EXPECT_NEAR(h.heights[ix], std::cos(2 * pi * ix / 8.0), 1e-15) << content;
  }
  // c_(0,1) = -0.5i: h = sin(2 pi y / L); n = 0 picks the smallest power of two (4).
  const HeightMap s = read_fourier_heights(text("sin.txt", "0 1 0 -0.5\n"), 0);
  EXPECT_EQ(s.grid.nx, 4);
  EXPECT_NEAR(s.heights[1 * 4 + 0], 1.0, 1e-15);
  // A generated band-limited surface: modes -> list -> heights reproduces it.
  const auto g = generate_self_affine(small_spec(), 128);
  // With a threshold far above rounding (~1e-19) and far below the smallest band mode
  // (~1e-9 here), exactly the band plus the mean (the min-shift) is listed.
  const auto modes = fourier_modes(g.map, 1e-14);
  EXPECT_EQ(modes.size(), self_affine_modes(small_spec()).modes.size() + 1);
  const fs::path p = dir / "modes.txt";
  write_fourier_list(p, modes);
  EXPECT_TRUE(no_temporaries());
  EXPECT_EQ(read_fourier_list(p).size(), modes.size());
  const HeightMap back = read_fourier_heights(p, 128);
  double err = 0;
  for (std::size_t i = 0; i < back.heights.size(); ++i) err = std::max(err, std::abs(back.heights[i] - g.map.heights[i]));
  EXPECT_LT(err, 1e-15);  // heights ~1e-2, two FFTs of rounding
}

TEST_F(SurfaceFiles, MissingFiles) {
  const fs::path p = dir / "does_not_exist.h5";
  expect_error([&] { read_challenge_hdf5(p); }, p, "no such file");
  expect_error([&] { read_ascii_heights(p, 1, 1); }, p, "no such file");
  expect_error([&] { read_fourier_list(p); }, p, "no such file");
}

TEST_F(SurfaceFiles, BadHdf5Files) {
  const HeightMap sq = ramp(8, 8, 1, 1);
  // wrong dataset name
  const fs::path wrong = dir / "wrong_name.h5";
  write_hdf5_heights(wrong, sq, "heights");
  expect_error([&] { read_challenge_hdf5(wrong); }, wrong, "no dataset 'surface'");
  // not square
  const fs::path rect = dir / "rect.h5";
  write_hdf5_heights(rect, ramp(8, 4, 1, 1));
  expect_error([&] { read_challenge_hdf5(rect); }, rect, "expected a square");
  // no size attributes and none given
  const fs::path plain = dir / "three_d.h5";
  {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    const hid_t f = H5Fcreate(plain.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[3] = {2, 3, 4};
    const hid_t sp = H5Screate_simple(3, dims, nullptr);
    const hid_t d = H5Dcreate2(f, "surface", H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    std::vector<double> v(24, 1.0);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    const hsize_t d2[2] = {4, 4};
    const hid_t sp2 = H5Screate_simple(2, d2, nullptr);
    const hid_t e = H5Dcreate2(f, "flat", H5T_NATIVE_DOUBLE, sp2, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(e, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Dclose(e), H5Sclose(sp2), H5Dclose(d), H5Sclose(sp), H5Fclose(f);
  }
  expect_error([&] { read_challenge_hdf5(plain); }, plain, "3 dimensions, expected 2");
  expect_error([&] { read_hdf5_heights(plain, "flat"); }, plain, "attribute 'lx'");
  EXPECT_EQ(read_hdf5_heights(plain, "flat", 1, 1).grid.nx, 4);
  // NaN: the first offending index is reported
  HeightMap nan = sq;
  nan.heights[2 * 8 + 3] = std::nan("");
  nan.heights[5 * 8 + 1] = INFINITY;
  const fs::path pn = dir / "nan.h5";
  write_hdf5_heights(pn, nan);
  expect_error([&] { read_challenge_hdf5(pn); }, pn, "(ix=3, iy=2)");
  // not HDF5 at all, and a truncated file
  const fs::path txt = text("not_hdf5.h5", "1 2\n3 4\n");
  expect_error([&] { read_challenge_hdf5(txt); }, txt, "cannot open as HDF5");
  const fs::path cut = dir / "truncated.h5";
  write_hdf5_heights(cut, ramp(64, 64, 1, 1));
  fs::resize_file(cut, fs::file_size(cut) / 2);
  expect_error([&] { read_challenge_hdf5(cut); }, cut, "");
}

// Found by tests/fuzz/fuzz_hdf5_heights: a size attribute of several elements overflowed
// the one double it was read into (a stack buffer overflow; AddressSanitizer reported it),
// and a dataset that was never written was read as its fill value, a flat surface (and
// a few-kB file declaring 2^20 x 2^20 unwritten points made the reader allocate 8 TB).
TEST_F(SurfaceFiles, Hdf5FilesFoundByFuzzing) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  // Writes dataset "surface" ({ny, nx} doubles) with lx = {lx values}, ly = 1; chunk: 0 for
  // contiguous; rows_written: how many rows get data (the first ones; -1: all).
  auto write = [&](const std::string& name, hsize_t ny, hsize_t nx, std::vector<double> lx, hsize_t chunk,
                   bool deflate, long rows_written) {
    const fs::path p = dir / name;
    const hid_t f = H5Fcreate(p.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[2] = {ny, nx}, chunks[2] = {chunk, chunk};
    const hid_t sp = H5Screate_simple(2, dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (chunk) H5Pset_chunk(dcpl, 2, chunks);
    if (deflate) H5Pset_deflate(dcpl, 6);
    const hid_t d = H5Dcreate2(f, "surface", H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    if (rows_written != 0) {
      const hsize_t rows = rows_written < 0 ? ny : hsize_t(rows_written), start[2] = {0, 0}, count[2] = {rows, nx};
      std::vector<double> v(rows * nx);
      for (std::size_t i = 0; i < v.size(); ++i) v[i] = 0.25 * double(i);
      const hid_t mem = H5Screate_simple(2, count, nullptr);
      H5Sselect_hyperslab(sp, H5S_SELECT_SET, start, nullptr, count, nullptr);
      EXPECT_GE(H5Dwrite(d, H5T_NATIVE_DOUBLE, mem, sp, H5P_DEFAULT, v.data()), 0);
      H5Sclose(mem);
    }
    const hsize_t n = lx.size();
    const hid_t asp = H5Screate_simple(1, &n, nullptr), scalar = H5Screate(H5S_SCALAR);
    const hid_t a = H5Acreate2(d, "lx", H5T_NATIVE_DOUBLE, asp, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, H5T_NATIVE_DOUBLE, lx.data());
    const double one = 1.0;
    const hid_t b = H5Acreate2(d, "ly", H5T_NATIVE_DOUBLE, scalar, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(b, H5T_NATIVE_DOUBLE, &one);
    H5Aclose(b), H5Aclose(a), H5Sclose(scalar), H5Sclose(asp), H5Dclose(d), H5Pclose(dcpl), H5Sclose(sp), H5Fclose(f);
    return p;
  };
  // lx of eight elements: refused, nothing written past the one double.
  const fs::path many = write("lx_array.h5", 4, 4, {2, 3, 4, 5, 6, 7, 8, 9}, 0, false, -1);
  expect_error([&] { read_hdf5_heights(many); }, many, "attribute 'lx' of dataset 'surface' is not a single number");
  // lx of one element (a 1-element array) is a number.
  EXPECT_EQ(read_hdf5_heights(write("lx_one.h5", 4, 4, {2.0}, 0, false, -1)).grid.lx, 2.0);
  // Never written, contiguous and chunked: no data, not a flat surface.
  const fs::path never = write("never.h5", 4, 4, {1}, 0, false, 0);
  expect_error([&] { read_hdf5_heights(never); }, never, "holds no data (never written)");
  const fs::path half = write("half.h5", 8, 8, {1}, 4, true, 4);  // 2 of 4 chunks written
  expect_error([&] { read_hdf5_heights(half); }, half, "holds no data in 2 of its 4 chunks");
  // A compressed dataset written in full is read (HDF5 calls its space "partly allocated").
  const HeightMap full = read_hdf5_heights(write("full.h5", 8, 8, {1}, 4, true, -1));
  EXPECT_EQ(full.heights[63], 0.25 * 63);
  // 2^20 x 2^20 declared, nothing written: refused before anything is allocated.
  const fs::path huge = write("huge.h5", hsize_t(1) << 20, hsize_t(1) << 20, {1}, 1024, false, 0);
  EXPECT_LT(fs::file_size(huge), 10000u);
  expect_error([&] { read_hdf5_heights(huge); }, huge, "holds no data in 1048576 of its 1048576 chunks");
}

TEST_F(SurfaceFiles, BadAsciiFiles) {
  const fs::path ragged = text("ragged.txt", "1 2 3\n4 5\n6 7 8\n");
  expect_error([&] { read_ascii_heights(ragged, 1, 1); }, ragged, "line 2 has 2 values, expected 3");
  const fs::path nan = text("nan.txt", "1 2\n3 4\n5 nan\n");
  expect_error([&] { read_ascii_heights(nan, 1, 1); }, nan, "line 3, column 2: non-finite");
  const fs::path inf = text("inf.txt", "1 -inf\n3 4\n");
  expect_error([&] { read_ascii_heights(inf, 1, 1); }, inf, "line 1, column 2: non-finite");
  const fs::path word = text("word.txt", "1 2\n3 x4\n");
  expect_error([&] { read_ascii_heights(word, 1, 1); }, word, "cannot parse 'x4'");
  const fs::path empty = text("empty.txt", "# nothing\n\n");
  expect_error([&] { read_ascii_heights(empty, 1, 1); }, empty, "no data");
  const fs::path rect = text("rect.txt", "1 2 3\n4 5 6\n");
  expect_error([&] { read_challenge_ascii(rect); }, rect, "expected a square");
  const fs::path truncated = text("truncated.txt", "1 2 3\n4 5 6\n7 8");
  expect_error([&] { read_challenge_ascii(truncated); }, truncated, "line 3 has 2 values");
  expect_error([&] { read_ascii_heights(rect, -1, 1); }, rect, "lx, ly must be positive");
}

TEST_F(SurfaceFiles, BadFourierLists) {
  const fs::path range = text("range.txt", "1 0 0.5 0\n4 1 0.1 0\n");
  expect_error([&] { read_fourier_heights(range, 8); }, range, "line 2: mode (4, 1) is out of range");
  EXPECT_EQ(read_fourier_heights(range, 0).grid.nx, 16);  // auto size holds it
  const fs::path shortline = text("short.txt", "1 0 0.5 0\n2 0 0.5\n");
  expect_error([&] { read_fourier_list(shortline); }, shortline, "line 2: expected 4 values");
  const fs::path real_index = text("real_index.txt", "1.5 0 0.5 0\n");
  expect_error([&] { read_fourier_list(real_index); }, real_index, "must be integers");
  const fs::path dup = text("dup.txt", "1 2 0.5 0\n3 0 1 1\n1 2 0.5 0\n");
  expect_error([&] { read_fourier_list(dup); }, dup, "listed twice (first on line 1)");
  const fs::path conj = text("conj.txt", "1 2 0.5 0.25\n-1 -2 0.5 0.25\n");
  expect_error([&] { read_fourier_list(conj); }, conj, "not the complex conjugate");
  const fs::path nan = text("nan_coeff.txt", "1 2 nan 0\n");
  expect_error([&] { read_fourier_list(nan); }, nan, "line 1: non-finite");
  const fs::path empty = text("empty_modes.txt", "# only a comment\n");
  expect_error([&] { read_fourier_list(empty); }, empty, "no Fourier modes");
}
