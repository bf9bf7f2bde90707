// Green's functions of the elastic half-space.
#include "cmc/elastic/HalfSpace.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace cmc;
using std::numbers::pi;

namespace {
Field cosine(const Grid& g, int kx, int ky, double amp) {
  Field f = g.field();
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix)
      f[std::size_t(iy) * g.nx + ix] = amp * std::cos(2 * pi * (kx * ix * g.dx() / g.lx + ky * iy * g.dy() / g.ly));
  return f;
}
}  // namespace

// A single Fourier mode p = p̂ cos(q·x) gives u = 2 p̂ / (E* |q|) cos(q·x)
// (Johnson 1985 §13.2): exact to round-off on the grid.
TEST(PeriodicHalfSpace, SingleModeDisplacement) {
  for (auto [nx, ny, kx, ky] : {std::tuple{64, 64, 3, 0}, {64, 32, 2, 5}, {128, 1, 7, 0}}) {
    Grid g{nx, ny, 1.0, ny == 1 ? 1.0 : 0.5};
    const double estar = 2.5;
    PeriodicHalfSpace hs(g, estar);
    const Field p = cosine(g, kx, ky, 0.3);
    Field u;
    hs.displacement(p, u);
    const double q = std::hypot(2 * pi * kx / g.lx, 2 * pi * ky / g.ly);
    const Field expected = cosine(g, kx, ky, 2 * 0.3 / (estar * q));
    for (std::size_t i = 0; i < u.size(); ++i) ASSERT_NEAR(u[i], expected[i], 1e-14) << "nx=" << nx << " i=" << i;
    EXPECT_EQ(hs.fft_pairs(), 1);
  }
}

TEST(PeriodicHalfSpace, MeanPressureGivesNoDisplacement) {
  Grid g{32, 32, 1.0, 1.0};
  PeriodicHalfSpace hs(g, 1.0);
  Field p(g.size(), 0.7), u;
  hs.displacement(p, u);
  for (double x : u) ASSERT_NEAR(x, 0.0, 1e-15);
}

// pressure() inverts displacement() on zero-mean fields.
TEST(PeriodicHalfSpace, PressureInvertsDisplacement) {
  Grid g{48, 40, 1.0, 1.2};
  PeriodicHalfSpace hs(g, 1.3);
  Field p = cosine(g, 2, 3, 1.0), u, back;
  for (std::size_t i = 0; i < p.size(); ++i) p[i] += 0.2 * std::sin(0.37 * double(i));  // add broadband content
  const double mean = Grid::mean(p);
  for (auto& x : p) x -= mean;
  hs.displacement(p, u);
  hs.pressure(u, back);
  for (std::size_t i = 0; i < p.size(); ++i) ASSERT_NEAR(back[i], p[i], 1e-12);
}

// The elastic energy computed in Fourier space from u alone equals the work of the
// pressure, (1/2) ∫ p u dA.
TEST(PeriodicHalfSpace, EnergyEqualsWorkOfPressure) {
  Grid g{64, 48, 1.0, 0.75};
  PeriodicHalfSpace hs(g, 0.8);
  Field p(g.size()), u;
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = std::exp(-0.001 * double((i * 7919) % 1013));
  hs.displacement(p, u);
  const double work = hs.energy(p, u);
  const double fourier = hs.energy_from_displacement(u);
  EXPECT_GT(work, 0.0);
  EXPECT_NEAR(fourier, work, 1e-12 * work);
  // And for a single mode, the closed form U/A = E* q û² / 8.
  Grid g1{64, 64, 1.0, 1.0};
  PeriodicHalfSpace hs1(g1, 1.0);
  const Field u1 = cosine(g1, 4, 0, 0.01);
  EXPECT_NEAR(hs1.energy_from_displacement(u1), 2 * pi * 4 * 1e-4 / 8, 1e-16);
}

// Love's rectangle (Johnson 1985 eq. 3.25) at the centre of a uniformly loaded square
// of side s: ∫∫ 1/r over the square is 4 s asinh(1), so u = 4 s asinh(1) / (π E*).
TEST(FreeHalfSpace, InfluenceCoefficientAtCentre) {
  const double s = 0.1, estar = 2.0;
  EXPECT_NEAR(FreeHalfSpace::influence(0, 0, s, s, estar), 4 * s * std::asinh(1.0) / (pi * estar), 1e-15);
  // Far away, a cell acts as a point force: u → p s² / (π E* r).
  const double r = 50 * s;
  EXPECT_NEAR(FreeHalfSpace::influence(r, 0, s, s, estar) / (s * s / (pi * estar * r)), 1.0, 1e-4);
  // Symmetric in x and y, and in sign.
  EXPECT_DOUBLE_EQ(FreeHalfSpace::influence(0.3, -0.2, s, s, estar), FreeHalfSpace::influence(-0.3, 0.2, s, s, estar));
  EXPECT_NEAR(FreeHalfSpace::influence(0.3, 0.2, s, s, estar), FreeHalfSpace::influence(0.2, 0.3, s, s, estar), 1e-16);
}

// The FFT convolution on the padded grid equals the direct sum over all cells:
// nothing wraps around (the free-boundary operator is not silently periodic).
TEST(FreeHalfSpace, MatchesDirectSummation) {
  Grid g{12, 10, 1.2, 1.0};
  FreeHalfSpace hs(g, 1.0);
  Field p(g.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = 1.0 + std::sin(0.9 * double(i));
  Field u;
  hs.displacement(p, u);
  for (int jy = 0; jy < g.ny; ++jy)
    for (int jx = 0; jx < g.nx; ++jx) {
      double direct = 0.0;
      for (int iy = 0; iy < g.ny; ++iy)
        for (int ix = 0; ix < g.nx; ++ix)
          direct += p[std::size_t(iy) * g.nx + ix] *
                    FreeHalfSpace::influence((jx - ix) * g.dx(), (jy - iy) * g.dy(), g.dx(), g.dy(), 1.0);
      ASSERT_NEAR(u[std::size_t(jy) * g.nx + jx], direct, 1e-13) << jx << "," << jy;
    }
}

TEST(FreeHalfSpace, PressureInvertsDisplacementAndEnergy) {
  Grid g{24, 24, 1.0, 1.0};
  FreeHalfSpace hs(g, 1.0);
  Field p(g.size()), u, back;
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = std::cos(0.21 * double(i)) + 0.5;
  hs.displacement(p, u);
  hs.pressure(u, back, 1e-13);
  for (std::size_t i = 0; i < p.size(); ++i) ASSERT_NEAR(back[i], p[i], 1e-9);
  EXPECT_NEAR(hs.energy_from_displacement(u), hs.energy(p, u), 1e-9 * hs.energy(p, u));
}

TEST(HalfSpace, RejectsBadInput) {
  EXPECT_THROW(PeriodicHalfSpace(Grid{8, 8, 1, 1}, -1.0), std::invalid_argument);
  EXPECT_THROW(PeriodicHalfSpace(Grid{8, 8, 1, 1}, std::nan("")), std::invalid_argument);
  EXPECT_THROW(FreeHalfSpace(Grid{8, 1, 1, 1}, 1.0), std::invalid_argument);
}

// The operator times one of its own FFT pairs (the unit of a run's cost) and counts them.
TEST(HalfSpace, TimesItsFftPair) {
  for (bool periodic : {true, false}) {
    const auto hs = make_half_space(Grid{32, 32, 1.0, 1.0}, 1.0, periodic);
    const double before = hs->fft_pairs();  // the free kernel's transform counts half a pair
    const double t = hs->time_fft_pair(0.0, 5);
    EXPECT_GT(t, 0.0);
    EXPECT_LT(t, 1.0);  // a 64² transform pair, even on a loaded machine
    EXPECT_EQ(hs->fft_pairs() - before, 6.0);  // one untimed pair, then five timed
  }
}
