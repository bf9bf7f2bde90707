// The tolerance the quasi-static solver's inner (Polonsky-Keer) solves run at,
// qs::inner_tolerance (contact/quasi_static/Parts.hpp): the user's, except for a monostable
// law whose move floor (capped at kMonostableMoveFloor ρ) is under kInnerErrorTrigger times
// the inner solves' gap error (tolerance × rms height); there the error is put at the floor
// over kFloorOverInnerError, and the floor itself does not move.
#include "cmc/contact/quasi_static/QuasiStaticAdhesion.hpp"
#include "cmc/contact/quasi_static/Parts.hpp"
#include "cmc/contact/polonsky_keer/PolonskyKeer.hpp"
#include "cmc/contact/Interaction.hpp"
#include "cmc/elastic/HalfSpace.hpp"
#include "rough_patch.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace cmc;

// `shape` at 4096² with inner tolerance 1e-6: rms height 750.4 nm, the floor (1e-4 ρ) 0.85
// of the gap error, so ρ = 0.85 × 7.504e-13 m / 1e-4. There the inner solves run at the
// tolerance whose error is the floor over kFloorOverInnerError. Kept bit for bit: a
// bistable law; `shape` at 2048² (ρ √2 larger: the floor 1.2 of the error); a tight
// tolerance (1e-8: the floor 85 times the error); a floor exactly at the trigger.
TEST(QuasiStatic, InnerToleranceFollowsTheMoveFloor) {
  const double h = 750.4e-9, rho = 0.85 * 1e-6 * h / qs::kMonostableMoveFloor;
  const double floor = qs::move_floor(rho, 1e-6, h, true);
  ASSERT_EQ(floor, qs::kMonostableMoveFloor * rho);
  const double tight = qs::inner_tolerance(rho, 1e-6, h, true);
  EXPECT_LT(tight, 1e-6);
  EXPECT_NEAR(tight * h, floor / qs::kFloorOverInnerError, 1e-12 * floor);
  EXPECT_EQ(qs::move_floor(rho, tight, h, true), floor);  // the floor stays where it was
  EXPECT_EQ(qs::inner_tolerance(rho, 1e-6, h, false), 1e-6);
  EXPECT_EQ(qs::inner_tolerance(rho * std::sqrt(2.0), 1e-6, h, true), 1e-6);
  EXPECT_EQ(qs::inner_tolerance(rho, 1e-8, h, true), 1e-8);
  const double at_trigger = qs::kMonostableMoveFloor * rho / (qs::kInnerErrorTrigger * h);
  EXPECT_EQ(qs::inner_tolerance(rho, at_trigger, h, true), at_trigger);
  EXPECT_LT(qs::inner_tolerance(rho, at_trigger * 1.01, h, true), at_trigger * 1.01);
  // The solver: the shape law on the rough patch gets the rule's tolerance where the rule
  // tightens it (1e-4: the floor there is capped below the error), the plain law never;
  // options() keeps the user's.
  RoughPatch s;
  PeriodicHalfSpace hs(s.map.grid, 1.0);
  const ExponentialAdhesion plain(s.w, s.rho);
  const ExponentialAdhesion shape = shape_coarse_grained(s.w, s.rho, hs.self_stiffness());
  const double hr = PolonskyKeer::residual_scale(s.map.heights);
  int tightened = 0;
  for (double tol : {1e-4, 1e-6, 1e-10}) {
    QuasiStaticAdhesion::Options o;
    o.tolerance = tol;
    const QuasiStaticAdhesion p(hs, s.map.heights, plain, o), c(hs, s.map.heights, shape, o);
    EXPECT_EQ(p.inner_tolerance(), tol) << tol;
    EXPECT_EQ(c.inner_tolerance(), qs::inner_tolerance(shape.range(), tol, hr, true)) << tol;
    EXPECT_EQ(c.options().tolerance, tol) << tol;
    EXPECT_EQ(c.move_floor(), qs::move_floor(shape.range(), tol, hr, true)) << tol;
    tightened += c.inner_tolerance() < tol;
  }
  EXPECT_GE(tightened, 1);
}
