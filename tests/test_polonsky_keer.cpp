// Polonsky–Keer on problems with known answers.
#include "cmc/analytic/Analytic.hpp"
#include "cmc/contact/ContactRule.hpp"
#include "cmc/contact/PolonskyKeer.hpp"
#include "cmc/surface/Topography.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace cmc;

// Hertz on a free boundary, a/dx = 16: δ(F) within 1e-3 of Hertz (the bound of
// cases/validation/hertz-free.toml, set there by its convergence run: 6.8e-4 at a/dx <= 16
// on 64², 9.7e-5 at a/dx <= 32; the error measured here is ~1e-4), every gap non-negative, pressure
// non-negative, total force exact.
TEST(PolonskyKeer, HertzFreeBoundary) {
  Grid g{64, 64, 1.0, 1.0};
  const double R = 1.0, a = 0.25, F = 4 * a * a * a / (3 * R);
  auto topo = sphere(g, R, 0.5, 0.5, false);
  FreeHalfSpace hs(g, 1.0);
  PolonskyKeer::Options o;
  o.tolerance = 1e-12;
  PolonskyKeer pk(hs, topo.heights, o);
  ContactState st;
  const auto r = pk.solve({Control::MeanPressure, F / g.area()}, st);
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_LE(r.residual, 1e-12);
  EXPECT_NEAR(st.penetration / analytic::hertz_from_force(1.0, R, F).penetration, 1.0, 1e-3);
  EXPECT_NEAR(Grid::sum(st.pressure) * g.cell_area(), F, 1e-12 * F);
  for (std::size_t i = 0; i < g.size(); ++i) {
    ASSERT_GE(st.pressure[i], 0.0);
    ASSERT_GE(st.gap[i], -1e-10 * a * a / R);
  }
  EXPECT_GT(r.fft_pairs, r.iterations);  // the count is honest: at least one pair per iteration
}

// Displacement control lands on the same state as force control.
TEST(PolonskyKeer, DisplacementControlMatchesForceControl) {
  Grid g{64, 64, 1.0, 1.0};
  auto topo = wavy2d(g, 0.01, 1.0);
  PeriodicHalfSpace hs(g, 1.0);
  PolonskyKeer::Options o;
  o.tolerance = 1e-12;
  PolonskyKeer pk(hs, topo.heights, o);
  ContactState a, b;
  ASSERT_TRUE(pk.solve({Control::MeanPressure, 0.01}, a).converged);
  const auto r = pk.solve({Control::Penetration, a.penetration}, b);
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_NEAR(b.mean_pressure, 0.01, 1e-8);
  for (std::size_t i = 0; i < g.size(); ++i) ASSERT_NEAR(a.pressure[i], b.pressure[i], 1e-7);
}

// An indenter that does not reach the surface: zero pressure, converged, no NaN.
TEST(PolonskyKeer, NoContact) {
  Grid g{32, 32, 1.0, 1.0};
  auto topo = sphere(g, 1.0, 0.5, 0.5, true);
  PeriodicHalfSpace hs(g, 1.0);
  PolonskyKeer pk(hs, topo.heights, {});
  ContactState st;
  const auto r = pk.solve({Control::Penetration, -0.01}, st);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(Grid::sum(st.pressure), 0.0);
  for (double x : st.gap) ASSERT_TRUE(std::isfinite(x));
}

// A solve stopped by its iteration cap says so.
TEST(PolonskyKeer, ReportsNotConverged) {
  Grid g{64, 64, 1.0, 1.0};
  auto topo = sphere(g, 1.0, 0.5, 0.5, false);
  FreeHalfSpace hs(g, 1.0);
  PolonskyKeer::Options o;
  o.tolerance = 1e-14;
  o.max_iterations = 3;
  PolonskyKeer pk(hs, topo.heights, o);
  ContactState st;
  const auto r = pk.solve({Control::MeanPressure, 0.01}, st);
  EXPECT_FALSE(r.converged);
  EXPECT_GT(r.residual, 1e-14);
  EXPECT_NE(r.message.find("stopped after 3 iterations"), std::string::npos) << r.message;
}

// Near full contact of a 1-D wave: the pressure approaches p* and the gap closes.
TEST(PolonskyKeer, NearFullContactWestergaard) {
  Grid g{512, 1, 1.0, 1.0};
  const double h = 1e-3, pstar = analytic::westergaard_full_contact_pressure(1.0, h, 1.0);
  auto topo = wavy1d(g, h, 1.0);
  PeriodicHalfSpace hs(g, 1.0);
  PolonskyKeer::Options o;
  o.tolerance = 1e-12;
  PolonskyKeer pk(hs, topo.heights, o);
  ContactState st;
  const auto r = pk.solve({Control::MeanPressure, 0.995 * pstar}, st);
  ASSERT_TRUE(r.converged) << r.message;
  const double a = analytic::westergaard_half_width(1.0, h, 1.0, 0.995 * pstar);
  const double in_contact = double(contact_points(st.gap));  // contact/ContactRule.hpp
  // Pixel-counted contact width agrees with 2a to within two grid cells.
  EXPECT_NEAR(in_contact / g.nx, 2 * a, 2.0 / g.nx);
}
