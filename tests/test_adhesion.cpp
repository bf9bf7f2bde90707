// Adhesive contact: interactions, the adhesive CG solver, load paths, validated against
// Johnson (1995), JKR and Maugis–Dugdale. Every tolerance below is next to the number it
// was set from (a measured discretisation / finite-range error or a convergence study);
// the measured values are printed (and recorded as test properties) on every run.
#include "cmc/contact/adhesive_cg/AdhesiveSolver.hpp"
#include "cmc/analytic/Analytic.hpp"
#include "cmc/contact/Interaction.hpp"
#include "cmc/contact/LoadPath.hpp"
#include "cmc/contact/polonsky_keer/PolonskyKeer.hpp"
#include "cmc/surface/SelfAffine.hpp"
#include "cmc/surface/SurfaceStats.hpp"
#include "cmc/surface/Topography.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>
#include <vector>

using namespace cmc;
namespace an = cmc::analytic;

namespace {

constexpr double pi = std::numbers::pi;

void report(const char* key, double value) {
  std::printf("    [adhesion] %-40s %.6g\n", key, value);
  ::testing::Test::RecordProperty(key, std::to_string(value));
}

// One line per recorded step (branch, target, p̄, contact fraction, jump, halvings, solves,
// iterations): the path's history is part of the test output.
void print_path(const LoadPathResult& res) {
  for (const auto& s : res.steps)
    std::printf("    [path] %-9s target %+.5e  p %+.5e  contact %.4f  jump %d  halvings %d  solves %d  iterations %d\n",
                s.branch == Branch::Loading ? "loading" : "unloading", s.target.value, s.mean_pressure, s.contact_fraction, int(s.jump), s.halvings,
                s.solves, s.iterations);
}

StepSolver as_step_solver(AdhesiveSolver& s) {
  return [&s](const Target& t, ContactState& st) { return s.solve(t, st); };
}

// Distance from the point (x, y) to the polyline through `curve`, in units (xs, ys).
double polyline_distance(const std::vector<std::pair<double, double>>& curve, double x, double y, double xs,
                         double ys) {
  double best = INFINITY;
  for (std::size_t i = 0; i + 1 < curve.size(); ++i) {
    const double ax = curve[i].first / xs, ay = curve[i].second / ys;
    const double bx = curve[i + 1].first / xs, by = curve[i + 1].second / ys;
    const double px = x / xs, py = y / ys;
    const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / l2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    best = std::min(best, std::hypot(px - ax - t * dx, py - ay - t * dy));
  }
  return best;
}

// The JKR curve (δ(a), F(a)) for a from a_lo to a_hi.
std::vector<std::pair<double, double>> jkr_curve(double Es, double R, double w, double a_lo, double a_hi, int n) {
  std::vector<std::pair<double, double>> c;
  for (int i = 0; i <= n; ++i) {
    const double a = a_lo + (a_hi - a_lo) * i / n;
    c.emplace_back(an::jkr_penetration(Es, R, w, a), an::jkr_force(Es, R, w, a));
  }
  return c;
}

// The Maugis–Dugdale curve (Δ, P̄) in Maugis' units, from the A -> 0 end to A_max.
std::vector<std::pair<double, double>> md_curve_points(double lambda, double A_max, int n) {
  std::vector<std::pair<double, double>> c;
  const auto z = an::md_zero_radius_limit(lambda);
  c.emplace_back(z.Delta, z.Pbar);
  const double A_lo = 1e-3;
  for (int i = 0; i <= n; ++i) {
    // denser at small A, where the curve turns
    const double t = double(i) / n;
    const auto p = an::md_point(lambda, A_lo + (A_max - A_lo) * t * t);
    c.emplace_back(p.Delta, p.Pbar);
  }
  return c;
}

}  // namespace

// ============================================================================ interactions

// force = −dφ/dg and curvature = d²φ/dg² = −d(force)/dg by central differences (h = 1e-5 ρ:
// truncation ~1e-10 relative, round-off ~1e-11); peak tension w/ρ at g = 0; exact zero
// beyond the cutoff (e^{-g/ρ} < 2^-52).
TEST(Interaction, ExponentialDerivativesAndPeak) {
  const double w = 0.3, rho = 0.02;
  const ExponentialAdhesion e(w, rho);
  EXPECT_DOUBLE_EQ(e.peak_tension(), w / rho);
  EXPECT_DOUBLE_EQ(e.evaluate(0.0).force, -w / rho);
  EXPECT_DOUBLE_EQ(e.evaluate(0.0).energy, -w);
  const double hstep = 1e-5 * rho;
  for (double g : {0.001 * rho, 0.3 * rho, rho, 4.0 * rho, 20.0 * rho}) {
    const auto v = e.evaluate(g), vp = e.evaluate(g + hstep), vm = e.evaluate(g - hstep);
    EXPECT_NEAR(v.force, -(vp.energy - vm.energy) / (2 * hstep), 1e-8 * w / rho) << g;
    EXPECT_NEAR(v.curvature, -(vp.force - vm.force) / (2 * hstep), 1e-7 * w / (rho * rho)) << g;
    EXPECT_LT(v.curvature, 0.0);  // concave everywhere
  }
  EXPECT_EQ(e.evaluate(e.cutoff()).energy, 0.0);
  EXPECT_LT(std::abs(e.evaluate(0.999 * e.cutoff()).force), 2.5e-16 * w / rho);  // 2^(-52 x 0.999)
  EXPECT_THROW(ExponentialAdhesion(-1.0, rho), std::invalid_argument);
  EXPECT_THROW(ExponentialAdhesion(w, 0.0), std::invalid_argument);
}

// The shape coarse-graining's laws (Interaction.hpp, shape_coarse_grained), for the three
// regimes of the self-stiffness k: a monostable exponential is returned unchanged, bit for
// bit; a bistable one gets a linear head of slope θ k with the peak tension w/ρ kept; where
// even the triangle would be bistable, the triangle with its peak lowered to √(2 w θ k).
// Each keeps w = ∫ tension dg (midpoint rule over 4e5 cells: the kink at g1 and the tail's
// curvature leave < 1e-6 w), its largest |φ''| is at most θ k, force and curvature are the
// derivatives of the energy (central differences, h = 1e-5 ρ), the tension is continuous
// at g1, and the law is concave.
TEST(Interaction, ShapeCoarseGrainedLaws) {
  const double w = 0.3, rho = 0.02, theta = kCoarseGrainingMargin;
  const double k_exp = w / (rho * rho) / theta;  // the exponential exactly monostable at the margin
  const double k_tri = (w / rho) * (w / rho) / (2 * w) / theta;  // the triangle exactly at it
  for (double k : {2.0 * k_exp, 0.5 * (k_exp + k_tri), 0.7 * k_tri, 0.05 * k_tri}) {
    const ExponentialAdhesion a = shape_coarse_grained(w, rho, k);
    const double peak = k >= k_tri ? w / rho : std::sqrt(2 * w * theta * k);
    EXPECT_NEAR(a.peak_tension(), peak, 1e-12 * peak) << k;
    EXPECT_NEAR(a.evaluate(0.0).force, -peak, 1e-12 * peak) << k;
    EXPECT_NEAR(a.evaluate(0.0).energy, -w, 1e-12 * w) << k;
    double integral = 0.0;
    const int m = 400000;
    const double top = a.cutoff(), dg = top / m;
    for (int j = 0; j < m; ++j) integral += a.evaluate((j + 0.5) * dg).force * dg;
    EXPECT_NEAR(integral, -w, 1e-6 * w) << k;
    if (k >= k_exp) {  // unchanged
      EXPECT_EQ(a.head(), 0.0);
      for (double g : {0.0, 0.3 * rho, 5 * rho}) {
        const ExponentialAdhesion e(w, rho);
        EXPECT_EQ(a.evaluate(g).energy, e.evaluate(g).energy);
        EXPECT_EQ(a.evaluate(g).force, e.evaluate(g).force);
        EXPECT_EQ(a.evaluate(g).curvature, e.evaluate(g).curvature);
      }
      continue;
    }
    EXPECT_GT(a.head(), 0.0) << k;
    EXPECT_NEAR(a.largest_curvature(), theta * k, 1e-12 * theta * k) << k;
    EXPECT_EQ(a.tail_tension() == 0.0, k < k_tri) << k;  // the triangle where the peak had to fall
    const double g1 = a.head(), hstep = 1e-5 * rho;
    EXPECT_NEAR(a.evaluate(g1 * (1 - 1e-12)).force, a.evaluate(g1).force, 1e-9 * peak) << k;
    double last_force = -peak;
    for (double f : {0.1, 0.5, 0.9, 1.1, 2.0, 5.0, 20.0}) {
      const double g = f * g1;
      if (g + hstep >= a.cutoff() || std::abs(g - g1) < 2 * hstep) continue;
      const auto v = a.evaluate(g), vp = a.evaluate(g + hstep), vm = a.evaluate(g - hstep);
      EXPECT_NEAR(v.force, -(vp.energy - vm.energy) / (2 * hstep), 1e-8 * peak) << k << " " << f;
      EXPECT_NEAR(v.curvature, -(vp.force - vm.force) / (2 * hstep), 1e-6 * theta * k) << k << " " << f;
      EXPECT_LE(v.curvature, 0.0);
      EXPECT_GE(-v.curvature, -theta * k * (1 + 1e-12));
      EXPECT_GE(v.force, last_force);  // the tension falls: concave
      last_force = v.force;
    }
  }
  EXPECT_THROW(ExponentialAdhesion::with_head(w, w / rho, 0.1 * w / (rho * rho)), std::invalid_argument);
}

// The smoothed Dugdale law keeps w = ∫ f dg and σ0 exactly for every smoothing width, and
// its force/curvature are the derivatives of its energy.
TEST(Interaction, DugdaleDerivativesWorkAndStress) {
  const double w = 0.05, h0 = 0.01;
  for (double eps : {0.0, 0.002, 0.01}) {
    const DugdaleAdhesion d(w, h0, eps);
    EXPECT_DOUBLE_EQ(d.peak_tension(), w / h0);
    EXPECT_DOUBLE_EQ(d.evaluate(0.0).energy, -w);
    EXPECT_DOUBLE_EQ(d.evaluate(0.0).force, -w / h0);
    EXPECT_EQ(d.evaluate(h0 + 0.5 * eps + 1e-12).force, 0.0);
    // ∫_0^∞ f dg = −w by the midpoint rule (exact for piecewise-linear f away from kinks).
    double integral = 0.0;
    const int m = 200000;
    const double top = 2 * h0, dg = top / m;
    for (int i = 0; i < m; ++i) integral += d.evaluate((i + 0.5) * dg).force * dg;
    EXPECT_NEAR(integral, -w, 1e-6 * w) << eps;
    if (eps > 0) {
      const double hs = 1e-4 * eps;
      for (double g : {0.3 * (h0 - 0.5 * eps), h0 - 0.25 * eps, h0, h0 + 0.25 * eps}) {  // away from the kinks
        const auto v = d.evaluate(g), vp = d.evaluate(g + hs), vm = d.evaluate(g - hs);
        EXPECT_NEAR(v.force, -(vp.energy - vm.energy) / (2 * hs), 1e-8 * w / h0) << g;
        EXPECT_NEAR(v.curvature, -(vp.force - vm.force) / (2 * hs), 1e-6 * w / (h0 * eps)) << g;
      }
      EXPECT_DOUBLE_EQ(d.evaluate(h0).curvature, -(w / h0) / eps);
    }
  }
  EXPECT_THROW(DugdaleAdhesion(w, h0, 2 * h0), std::invalid_argument);
}

TEST(Interaction, HardWallAndParameterHelpers) {
  const HardWall hw;
  EXPECT_EQ(hw.evaluate(0.0).force, 0.0);
  EXPECT_EQ(peak_tension(Interaction{hw}), 0.0);
  // μ_T = R^{1/3} (w/E*)^{2/3} / ρ and its inverse.
  const double Es = 2.0, R = 3.0, w = 0.01;
  const double rho = exponential_range_from_tabor(Es, R, w, 3.0);
  EXPECT_NEAR(tabor_parameter(Es, R, w, rho), 3.0, 1e-14);
  EXPECT_NEAR(rho, std::cbrt(R) * std::pow(w / Es, 2.0 / 3.0) / 3.0, 1e-16);
  // σ0 from λ inverts Analytic's md_lambda.
  for (double lambda : {0.3, 1.0, 3.0}) {
    const double s0 = dugdale_stress_from_lambda(Es, R, w, lambda);
    EXPECT_NEAR(an::md_lambda(Es, R, w, s0), lambda, 1e-13 * lambda);
    const auto d = dugdale_from_lambda(Es, R, w, lambda, 0.0);
    EXPECT_NEAR(d.stress(), s0, 1e-14 * s0);
  }
}

// ============================================================================ solver basics

// With a hard wall only, the adhesive CG solves the same problem as Polonsky–Keer: same
// pressure field (to 1e-9 of the mean pressure; both solved to 1e-10/1e-12), periodic
// and free boundary; and load control lands on Polonsky–Keer's penetration.
TEST(AdhesiveSolver, HardWallMatchesPolonskyKeerPeriodic) {
  Grid g{64, 64, 1.0, 1.0};
  auto topo = wavy2d(g, 0.01, 1.0);
  PeriodicHalfSpace hs(g, 1.0);
  PolonskyKeer::Options po;
  po.tolerance = 1e-12;
  PolonskyKeer pk(hs, topo.heights, po);
  ContactState a;
  ASSERT_TRUE(pk.solve({Control::MeanPressure, 0.01}, a).converged);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-10;
  AdhesiveSolver s(hs, topo.heights, HardWall{}, o);
  ContactState b;
  const auto r = s.solve({Control::Penetration, a.penetration}, b);
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_NEAR(b.mean_pressure, 0.01, 1e-9);
  double dp = 0;
  for (std::size_t i = 0; i < g.size(); ++i) dp = std::max(dp, std::abs(a.pressure[i] - b.pressure[i]));
  EXPECT_LT(dp, 1e-9);
  EXPECT_GE(r.fft_pairs, r.iterations);  // honest: at least one pair per iteration
  EXPECT_LT(r.fft_pairs, 1.5 * r.iterations + 5);
  // Load control (outer search on δ) reproduces Polonsky–Keer's δ.
  ContactState c;
  const auto rl = s.solve({Control::MeanPressure, 0.01}, c);
  ASSERT_TRUE(rl.converged) << rl.message;
  EXPECT_NEAR(c.penetration, a.penetration, 1e-8 * a.penetration);
  EXPECT_NEAR(c.mean_pressure, 0.01, 1e-8);
}

TEST(AdhesiveSolver, HardWallMatchesPolonskyKeerFreeBoundary) {
  Grid g{64, 64, 1.0, 1.0};
  const double R = 1, a = 0.25, F = 4 * a * a * a / (3 * R);
  auto topo = sphere(g, R, 0.5, 0.5, false);
  FreeHalfSpace hs(g, 1.0);
  PolonskyKeer::Options po;
  po.tolerance = 1e-12;
  PolonskyKeer pk(hs, topo.heights, po);
  ContactState A;
  ASSERT_TRUE(pk.solve({Control::MeanPressure, F}, A).converged);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-10;
  AdhesiveSolver s(hs, topo.heights, HardWall{}, o);
  ContactState B;
  const auto r = s.solve({Control::Penetration, A.penetration}, B);
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_NEAR(B.mean_pressure * g.area(), F, 1e-8 * F);
  double dp = 0;
  for (std::size_t i = 0; i < g.size(); ++i) dp = std::max(dp, std::abs(A.pressure[i] - B.pressure[i]));
  EXPECT_LT(dp, 1e-7 * F / (a * a));
}

// A solve stopped by its iteration cap says so; an impossible target says so; no NaN.
TEST(AdhesiveSolver, ReportsNotConvergedAndInfeasible) {
  Grid g{64, 64, 1.0, 1.0};
  auto topo = wavy2d(g, 0.01, 1.0);
  PeriodicHalfSpace hs(g, 1.0);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-14;
  o.max_iterations = 3;
  AdhesiveSolver s(hs, topo.heights, ExponentialAdhesion(1e-4, 1e-3), o);
  ContactState st;
  const auto r = s.solve({Control::Penetration, 0.005}, st);
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.message.find("stopped after 3 iterations"), std::string::npos) << r.message;
  for (double p : st.pressure) ASSERT_TRUE(std::isfinite(p));
  ContactState bad;
  const auto rb = s.solve({Control::Penetration, 1.0}, bad);  // mean gap < 0 on a periodic grid
  EXPECT_FALSE(rb.converged);
  EXPECT_NE(rb.message.find("no admissible state"), std::string::npos) << rb.message;
  const auto rn = s.solve({Control::Penetration, std::nan("")}, bad);
  EXPECT_FALSE(rn.converged);
}

// Load control on an adhesive branch (Johnson sinusoid, α = 0.3, nx = 1024): from a state in
// contact, a tensile mean pressure between pull-off and zero is found on the same branch
// (the displacement-controlled solve at the returned δ reproduces it to the load-control
// tolerance 10 × tol × P ≈ 5e-5 p*), and a target beyond the pull-off is reported as not
// converged, without NaN.
TEST(AdhesiveSolver, LoadControlOnAdhesiveBranch) {
  const double h0 = 0.01, Es = 1.0, alpha = 0.3, ell = 2e-3;
  const double w = std::pow(alpha * pi * h0, 2) * Es / 2, rho = std::sqrt(8 * w * ell / (pi * Es));
  const double pstar = an::westergaard_full_contact_pressure(Es, h0, 1.0);
  Grid g{1024, 1, 1.0, 1.0};
  auto topo = wavy1d(g, h0, 1.0);
  PeriodicHalfSpace hs(g, Es);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-6;
  o.max_iterations = 3000;  // solves converge in ~100-200; near the snap-off fold they slow down
  AdhesiveSolver solver(hs, topo.heights, ExponentialAdhesion(w, rho), o);
  ContactState st;
  ASSERT_TRUE(solver.solve({Control::Penetration, 0.2 * h0}, st).converged);
  ASSERT_GT(contact_fraction(st.gap), 0.1);
  const double target = -0.05 * pstar;  // Johnson pull-off is −0.096 p*
  const auto r = solver.solve({Control::MeanPressure, target}, st);
  ASSERT_TRUE(r.converged) << r.message;
  const double ftol = 10 * o.tolerance * solver.pressure_scale();
  EXPECT_NEAR(st.mean_pressure, target, ftol);
  report("load_control.inner_solves", r.diagnostics.outer_iterations);
  ContactState check = st;
  ASSERT_TRUE(solver.solve({Control::Penetration, st.penetration}, check).converged);
  EXPECT_NEAR(check.mean_pressure, target, 2 * ftol);
  ContactState beyond = st;
  const auto rb = solver.solve({Control::MeanPressure, -0.2 * pstar}, beyond);
  EXPECT_FALSE(rb.converged);
  EXPECT_FALSE(rb.message.empty());
  std::printf("    [adhesion] beyond pull-off: %s\n", rb.message.c_str());
  for (double p : beyond.pressure) ASSERT_TRUE(std::isfinite(p));
}

// ============================================================================ load path logic

// A synthetic solver with a discontinuity at v = 1 (a "snap") and a window where it fails:
// the path halves steps there, records the jump after the finest level, and reports the
// failure honestly.
TEST(LoadPath, HalvingJumpsAndFailures) {
  int calls = 0;
  auto fake = [&](bool fail_window) {
    return [&calls, fail_window](const Target& t, ContactState& s) {
      ++calls;
      SolveResult r;
      r.converged = !(fail_window && t.value > 2.2 && t.value < 2.3);
      r.iterations = 1;
      s.penetration = t.value;
      s.mean_pressure = t.value < 1.0 ? -0.1 * t.value : 5.0 + t.value;
      s.gap.assign(100, 1.0);
      const int nc = t.value < 1.0 ? 0 : 20;
      for (int i = 0; i < nc; ++i) s.gap[i] = 0.0;
      s.pressure.assign(100, s.mean_pressure);
      return r;
    };
  };
  LoadPathOptions lo;
  lo.max_halvings = 4;
  lo.pressure_floor = 1.0;
  ContactState st;
  auto res = run_load_path(fake(false), ramp(Control::Penetration, 0.0, 2.0, 4), st, lo);
  ASSERT_EQ(res.steps.size(), 5u);
  EXPECT_TRUE(res.completed);
  EXPECT_TRUE(res.steps[2].jump);  // 0.5 -> 1.0 reaches the snap: halved 4 times, then accepted
  EXPECT_EQ(res.steps[2].halvings, 4);
  EXPECT_EQ(res.steps[1].halvings, 0);
  int jumped = 0;
  for (const auto& s : res.steps) jumped += s.jump;
  EXPECT_EQ(jumped, 1);
  EXPECT_EQ(res.max_halvings, 4);
  EXPECT_EQ(res.steps[0].branch, Branch::Loading);
  EXPECT_DOUBLE_EQ(res.steps.back().penetration, 2.0);
  EXPECT_DOUBLE_EQ(res.pulloff_mean_pressure, -0.1 * (1.0 - 1.0 / 32.0));
  // Unloading back: branch flips; a failure window stops the path with a message.
  ContactState st2;
  auto res2 = run_load_path(fake(true), load_unload(Control::Penetration, 2.0, 3.0, 2.25, 2, 1), st2, lo);
  EXPECT_FALSE(res2.completed);
  EXPECT_EQ(res2.failed_steps, 1);
  EXPECT_NE(res2.message.find("stopped"), std::string::npos);
  EXPECT_EQ(res2.steps.back().branch, Branch::Unloading);
  EXPECT_FALSE(res2.steps.back().result.converged);
}

// ============================================================================ Johnson (1995)

// 1-D wavy surface h = h0 (1 − cos 2πx/λ) with exponential adhesion, displacement-
// controlled loading from out of contact to a ≈ 0.3 λ and unloading to detachment, for
// amplitudes across the documented range 0.05 ≤ α ≤ 0.56 (Johnson's partial contact at
// zero load ends at α = 3^{3/4}/4 ≈ 0.570).
// Grid and range: nx = 8192, h0 = 0.01 λ; ρ is set from the cohesive-zone length
// ℓ = (π/8) E* ρ²/w = 5e-4 λ ≈ 4 Δx (so w Δx/(E* ρ²) = 0.1 < 1: no bistable point). The
// shipped validation cases (cases/validation/johnson-*) run at ℓ ≈ 2 Δx.
// Short range (ℓ ≪ a) is Johnson's JKR-like limit. The finite-range reference (a study over
// α = 0.05 … 0.56, ℓ = 1.25e-4 … 1e-3 λ, nx 2048 … 32768, ℓ/Δx 2 … 16):
//  - p̄ against Johnson at the solved mean gap (no contact edge needed): the finite-range
//    part is below 1e-4 p* at ℓ = 5e-4 (1.1e-5 / 4.4e-5 for α = 0.05 / 0.3 at ℓ/Δx = 8).
//    What remains is discretisation: at ℓ/Δx = 2 up to 7.8e-4 (α ≤ 0.5) and 1.0e-3
//    (α = 0.56) p*, falling 3.2–3.6× when nx doubles; at ℓ/Δx = 4 (this test) at most
//    2.35e-4 (α = 0.56). Tolerance 5e-4: twice that.
//  - p̄ against Johnson at the counted half-width: the counted contact edge lies κ ℓ inside
//    Johnson's crack tip, κ = (a_J(ḡ) − a)/ℓ with medians 1.6–2.3 over the study, the same
//    on every grid at fixed ℓ (reported below). The deviation |p̄ − p̄_J(a)| ≈
//    |dp̄_J/da| κ ℓ is first order in ℓ (5.0, 2.9, 1.6, 0.87e-3 p* at ℓ = 1e-3 … 1.25e-4,
//    α = 0.05) and at ℓ = 5e-4 lies in 1.8e-3 … 3.05e-3 p* for every α of the range, on
//    every grid; the counted a carries ±Δx/2 → ≤ 1e-4 p*. Tolerance 5e-3.
class Johnson : public ::testing::TestWithParam<double> {};

TEST_P(Johnson, SinusoidLoadingUnloading) {
  const double alpha = GetParam();
  const double h0 = 0.01, lam = 1.0, Es = 1.0, ell = 5e-4;
  const int nx = 8192;
  const double w = std::pow(alpha * pi * h0, 2) * Es / (2 * lam);  // α = √(2wλ/E*)/(π h0)
  const double rho = std::sqrt(8 * w * ell / (pi * Es));
  const double pstar = an::westergaard_full_contact_pressure(Es, h0, lam);
  ASSERT_NEAR(an::johnson_alpha(Es, w, h0, lam), alpha, 1e-12);
  Grid g{nx, 1, lam, 1.0};
  auto topo = wavy1d(g, h0, lam);
  PeriodicHalfSpace hs(g, Es);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-6;
  o.max_iterations = 20000;
  AdhesiveSolver solver(hs, topo.heights, ExponentialAdhesion(w, rho), o);

  const auto po = an::johnson_pulloff(Es, w, h0, lam);
  // Displacement-controlled detachment: the largest mean gap on the small-a side.
  double gmax = 0, a_det = 0;
  for (double a = 1e-4; a < po.half_width; a += 1e-4) {
    const double gb = an::johnson_mean_gap(Es, w, h0, lam, a);
    if (gb > gmax) gmax = gb, a_det = a;
  }
  const double d_detach = h0 - gmax;  // δ = mean(h) − ḡ
  const double d_peak = h0 - an::johnson_mean_gap(Es, w, h0, lam, 0.3 * lam);
  const auto targets = load_unload(Control::Penetration, -20 * rho, d_peak, d_detach - 0.05 * h0, 12, 18);
  LoadPathOptions lo;
  lo.pressure_floor = pstar;  // the pressure scale of the path
  lo.max_halvings = 4;
  lo.refine_pulloff = 8;
  ContactState st;
  const auto res = run_load_path(as_step_solver(solver), targets, st, lo);

  print_path(res);
  ASSERT_TRUE(res.completed) << res.message;
  double e_a = 0, e_g = 0;
  std::vector<double> kappas;  // the finite-range edge offset (header)
  bool jump_in = false, jump_off = false;
  for (const auto& s : res.steps) {
    ASSERT_TRUE(s.result.converged) << s.result.message;
    if (s.jump && s.branch == Branch::Loading) jump_in = true;
    if (s.jump && s.branch == Branch::Unloading) jump_off = true;
    if (s.contact_fraction <= 0) continue;
    const double a = 0.5 * s.contact_fraction * lam;
    const double pj = an::johnson_mean_pressure(Es, w, h0, lam, a);
    e_a = std::max(e_a, std::abs(s.mean_pressure - pj) / pstar);
    // Johnson's a at the simulated mean gap (stable branch a > a_det), then p̄_J(a).
    const double gb = h0 - s.penetration;
    double lo_a = a_det, hi_a = 0.4999 * lam;
    if (an::johnson_mean_gap(Es, w, h0, lam, lo_a) >= gb && an::johnson_mean_gap(Es, w, h0, lam, hi_a) < gb) {
      for (int k = 0; k < 80; ++k) {
        const double m = 0.5 * (lo_a + hi_a);
        (an::johnson_mean_gap(Es, w, h0, lam, m) > gb ? lo_a : hi_a) = m;
      }
      e_g = std::max(e_g, std::abs(s.mean_pressure - an::johnson_mean_pressure(Es, w, h0, lam, lo_a)) / pstar);
      // The edge offset, where p̄_J(a) is steep enough for a to be read from p̄ (|dp̄_J/da|
      // > 0.5 p*/λ; near the pull-off's flat minimum a is not defined by p̄).
      const double slope = (an::johnson_mean_pressure(Es, w, h0, lam, a + 1e-6) - an::johnson_mean_pressure(Es, w, h0, lam, a - 1e-6)) / 2e-6;
      if (std::abs(slope) > 0.5 * pstar / lam) {
        kappas.push_back((lo_a - a) / ell);
      }
    }
  }
  const double po_err = res.pulloff_mean_pressure / po.mean_pressure - 1;
  report("johnson.alpha", alpha);
  report("johnson.max_err_pbar_vs_a/pstar", e_a);
  report("johnson.max_err_pbar_vs_gbar/pstar", e_g);
  report("johnson.pulloff_rel_err", po_err);
  std::sort(kappas.begin(), kappas.end());
  if (!kappas.empty()) {
    report("johnson.edge_offset_min/ell", kappas.front());
    report("johnson.edge_offset_median/ell", kappas[kappas.size() / 2]);
    report("johnson.edge_offset_max/ell", kappas.back());
  }
  report("johnson.halved_steps", res.halved_steps);
  EXPECT_LT(e_a, 5e-3);   // measured 1.8e-3 .. 3.05e-3 (header)
  EXPECT_LT(e_g, 5e-4);   // measured ≤ 2.35e-4 at ℓ/Δx = 4 (header)
  // required 2 %; measured 0.08 / 0.09 / 0.22 % for α = 0.1 / 0.3 / 0.5 with the golden-
  // section refinement (1.2 % for α = 0.1 from the path samples alone)
  EXPECT_LT(std::abs(po_err), 0.02);
  EXPECT_TRUE(jump_in);   // jump into contact detected on loading
  EXPECT_TRUE(jump_off);  // snap-off detected on unloading
  EXPECT_LE(res.halved_steps, 4);  // the two real jumps, plus at most two cautious halvings
}

INSTANTIATE_TEST_SUITE_P(JohnsonSinusoid, Johnson, ::testing::Values(0.05, 0.1, 0.3, 0.5, 0.56));

// ============================================================================ JKR (exponential)

namespace {
// A sphere R = 1 on a free-boundary patch of side 1 (E* = 1) whose Maugis length unit
// s = (π w R²/K)^{1/3} is a given fraction of the patch: w = s³ K/(π R²), K = 4E*/3.
double work_for_scale(double s) { return s * s * s * (4.0 / 3.0) / pi; }
}  // namespace

// Loading from out of contact through jump-in to F ≈ +0.7 (3/2)πwR (a ≈ 2s), unloading
// through pull-off to snap-off, μ_T = 3, n = 128 (a_c ≈ 23 Δx, w Δx/(E* ρ²) = 0.56).
// Measured against JKR: pull-off −1.028 (3/2)πwR at n = 128 and −1.028 at n = 256 (grid-
// converged; −1.030 with the golden-section refinement), i.e. 2.8-3.0 % stronger than JKR:
// that is the finite range at μ_T = 3 (the Maugis–Dugdale curve with the same first moment
// of the force law, λ ≈ 1.7, gives 3.3 %). The F–δ points lie within 2.5 % (distance in
// units of (3/2)πwR and |δ_c|) of JKR on the load-stable branch (δ >= δ_c) and up to 8 %
// close to the displacement-controlled snap-off, where a is smallest: the 2 % F(δ)
// requirement needs μ_T = 5 (next test).
TEST(JKR, ExponentialPathTabor3) {
  const int n = 128;
  const double Es = 1, R = 1, s = 1.0 / 6, w = work_for_scale(s), muT = 3.0;
  const double rho = exponential_range_from_tabor(Es, R, w, muT);
  Grid g{n, n, 1.0, 1.0};
  auto topo = sphere(g, R, 0.5, 0.5, false);
  FreeHalfSpace hs(g, Es);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-6;
  AdhesiveSolver solver(hs, topo.heights, ExponentialAdhesion(w, rho), o);
  const double Fc = 1.5 * pi * w * R;
  const auto dc = an::jkr_pulloff_displacement_controlled(Es, R, w);
  const auto lc = an::jkr_pulloff_load_controlled(Es, R, w);
  const double d_peak = an::jkr_penetration(Es, R, w, 2.0 * s);
  LoadPathOptions lo;
  lo.pressure_floor = 2 * Fc / g.area();  // the spread of F along the path (≈ −Fc … +0.7 Fc)
  lo.max_halvings = 3;
  lo.refine_pulloff = 8;
  ContactState st;
  const auto res = run_load_path(as_step_solver(solver),
                                 load_unload(Control::Penetration, -8 * rho, d_peak, 1.3 * dc.penetration, 8, 12),
                                 st, lo);
  print_path(res);
  ASSERT_TRUE(res.completed) << res.message;
  const auto curve = jkr_curve(Es, R, w, dc.radius, 3.0 * s, 4000);
  double dist_all = 0, dist_stable = 0;
  bool jump_in = false, jump_off = false;
  for (const auto& r : res.steps) {
    ASSERT_TRUE(r.result.converged) << r.result.message;
    jump_in |= r.jump && r.branch == Branch::Loading;
    jump_off |= r.jump && r.branch == Branch::Unloading;
    if (r.contact_fraction <= 0) continue;
    const double d = polyline_distance(curve, r.penetration, r.mean_pressure * g.area(), std::abs(lc.penetration), Fc);
    dist_all = std::max(dist_all, d);
    if (r.penetration >= lc.penetration) dist_stable = std::max(dist_stable, d);
  }
  const double po = res.pulloff_mean_pressure * g.area() / (-Fc);
  report("jkr3.pulloff/(1.5 pi w R)", po);
  report("jkr3.max_dist_load_stable_branch", dist_stable);
  report("jkr3.max_dist_all_contact_states", dist_all);
  report("jkr3.halved_steps", res.halved_steps);
  EXPECT_NEAR(po, 1.0, 0.03);      // required 3 %; measured 2.8-3.0 % (finite range, see above)
  // F(δ) is not held to 2 % here: at μ_T = 3 the finite-range deviation itself is larger
  // (reported above; 2.5 % on the load-stable branch, up to ~8 % next to the snap-off).
  EXPECT_TRUE(jump_in);
  EXPECT_TRUE(jump_off);
  EXPECT_LE(res.halved_steps, 4);  // jump-in, snap-off and at most two cautious halvings
}

// The 2 % F(δ) check at μ_T = 5 (n = 256, w Δx/(E* ρ²) = 0.78), on a short path that starts
// in contact: loading to a ≈ 2s, unloading to the load-controlled pull-off δ_c. Measured
// (full path): distance ≤ 0.8 % for δ ≥ δ_c; μ_T = 4 at n = 192 gave 2.1 %, which is why
// this test needs μ_T = 5 and the finer grid (the notes' rule: Δx below ρ²E*/w).
TEST(JKR, ForceVersusPenetrationTabor5) {
  const int n = 256;
  const double Es = 1, R = 1, s = 1.0 / 6, w = work_for_scale(s), muT = 5.0;
  const double rho = exponential_range_from_tabor(Es, R, w, muT);
  Grid g{n, n, 1.0, 1.0};
  auto topo = sphere(g, R, 0.5, 0.5, false);
  FreeHalfSpace hs(g, Es);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-6;
  AdhesiveSolver solver(hs, topo.heights, ExponentialAdhesion(w, rho), o);
  const double Fc = 1.5 * pi * w * R;
  const auto dc = an::jkr_pulloff_displacement_controlled(Es, R, w);
  const auto lc = an::jkr_pulloff_load_controlled(Es, R, w);
  const double d_peak = an::jkr_penetration(Es, R, w, 2.0 * s);
  LoadPathOptions lo;
  lo.pressure_floor = 2 * Fc / g.area();  // the spread of F along the path (≈ −Fc … +0.7 Fc)
  lo.max_halvings = 3;
  ContactState st;
  const auto res = run_load_path(as_step_solver(solver),
                                 load_unload(Control::Penetration, 0.4 * d_peak, d_peak, lc.penetration, 2, 5), st, lo);
  print_path(res);
  ASSERT_TRUE(res.completed) << res.message;
  const auto curve = jkr_curve(Es, R, w, dc.radius, 3.0 * s, 4000);
  double dist = 0;
  for (const auto& r : res.steps) {
    ASSERT_TRUE(r.result.converged) << r.result.message;
    ASSERT_GT(r.contact_fraction, 0.0);
    dist = std::max(dist, polyline_distance(curve, r.penetration, r.mean_pressure * g.area(), std::abs(lc.penetration), Fc));
  }
  report("jkr5.max_dist", dist);
  report("jkr5.halved_steps", res.halved_steps);
  EXPECT_LT(dist, 0.02);  // required
  EXPECT_LE(res.halved_steps, 2);
}

// The coarse-grainings of Interaction.hpp on the exponential-law sphere,
// μ_T = 3, s = 1/6. Pull-off (golden-section refined, on a path that unloads from a ≈ 2s
// through snap-off) on the resolved grid, n = 256 (Δx = 0.75 ρ, the plain law), against
// n = 48 (Δx = 3.98 ρ) with each strategy and without one.
//  * range (coarse_grained_range: ρ_c = √(2w/K_ii) = 1.60 ρ, so μ_T falls to 1.87):
//    measured 3.5 % stronger than the resolved pull-off 1.0280 (3/2)πwR (as
//    JKR.ExponentialPathTabor3 finds at n = 128 and 256); with θ = 1, ρ_c = 1.13 ρ: 3.3 %.
//  * shape (shape_coarse_grained: w and the peak tension kept, so μ_T stays 3 as long as
//    the triangle is monostable; at 4 ρ it is not quite, and the peak falls to 0.88 w/ρ):
//    measured 0.78 % stronger. The bar a coarse-graining is held to, 2 % at 4 ρ, is met
//    and asserted. On other grids (same path, measured once, not asserted): +0.19 % at 1.5 ρ
//    (the plain law: monostable there), +0.66 % at 2 ρ, +1.2 % at 2.4 ρ, +0.79 % at 3 ρ,
//    +3.0 % at 4.8 ρ, +1.1 % at 6 ρ, +5.0 % at 8 ρ, against range +6.2 % at 6 ρ: not
//    monotone in Δx (the sphere's pixels and the contact edge's position among them).
//  * plain: 6.2 % stronger.
// Asserted besides: each strategy is closer to the resolved pull-off than the plain law
// on the same grid, and all err on the strong side (the sign measured; a change of sign
// would be a new finding to explain).
TEST(JKR, PullOffCoarseGrainingAtFourRho) {
  const double Es = 1, R = 1, s = 1.0 / 6, w = work_for_scale(s), muT = 3.0;
  const double rho = exponential_range_from_tabor(Es, R, w, muT);
  const double Fc = 1.5 * pi * w * R;
  const auto dc = an::jkr_pulloff_displacement_controlled(Es, R, w);
  const double d_peak = an::jkr_penetration(Es, R, w, 2.0 * s);
  enum Law { Plain, Range, Shape };
  auto pulloff = [&](int n, Law kind, double* peak) {
    Grid g{n, n, 1.0, 1.0};
    auto topo = sphere(g, R, 0.5, 0.5, false);
    FreeHalfSpace hs(g, Es);
    const ExponentialAdhesion law = kind == Shape   ? shape_coarse_grained(w, rho, hs.self_stiffness())
                                    : kind == Range ? ExponentialAdhesion(w, coarse_grained_range(w, rho, hs.self_stiffness()))
                                                    : ExponentialAdhesion(w, rho);
    *peak = law.peak_tension() / (w / rho);
    AdhesiveSolver::Options o;
    o.tolerance = 1e-6;
    AdhesiveSolver solver(hs, topo.heights, law, o);
    LoadPathOptions lo;
    lo.pressure_floor = 2 * Fc / g.area();
    lo.max_halvings = 3;
    lo.refine_pulloff = 8;
    ContactState st;
    const auto res = run_load_path(as_step_solver(solver),
                                   load_unload(Control::Penetration, 0.4 * d_peak, d_peak, 1.3 * dc.penetration, 1, 10),
                                   st, lo);
    EXPECT_TRUE(res.completed) << res.message;
    for (const auto& r : res.steps) EXPECT_TRUE(r.result.converged) << r.result.message;
    return res.pulloff_mean_pressure * g.area() / (-Fc);
  };
  const int n_fine = 256, n4 = int(std::lround(1.0 / (4.0 * rho)));
  double p_fine = 0, p_range = 0, p_shape = 0, p_plain = 0;
  const double fine = pulloff(n_fine, Plain, &p_fine);
  const double range = pulloff(n4, Range, &p_range);
  const double shape = pulloff(n4, Shape, &p_shape);
  const double plain = pulloff(n4, Plain, &p_plain);
  report("sphere_cg.dx_over_rho.fine", 1.0 / n_fine / rho);
  report("sphere_cg.dx_over_rho.coarse", 1.0 / n4 / rho);
  report("sphere_cg.range_peak_over_w_rho", p_range);
  report("sphere_cg.shape_peak_over_w_rho", p_shape);
  report("sphere_cg.pulloff_fine/(1.5 pi w R)", fine);
  report("sphere_cg.pulloff_range_rel_err", range / fine - 1);
  report("sphere_cg.pulloff_shape_rel_err", shape / fine - 1);
  report("sphere_cg.pulloff_plain_rel_err", plain / fine - 1);
  EXPECT_LE(1.0 / n_fine, 0.8 * rho);
  EXPECT_NEAR(1.0 / n4 / rho, 4.0, 0.1);
  EXPECT_LT(std::abs(shape / fine - 1), 0.02);  // the bar: within 2 % at Δx = 4 ρ
  EXPECT_LT(std::abs(range / fine - 1), std::abs(plain / fine - 1));
  EXPECT_LT(std::abs(shape / fine - 1), std::abs(plain / fine - 1));
  EXPECT_GT(range, fine);
  EXPECT_GT(shape, fine);
  EXPECT_GT(plain, fine);
  EXPECT_GT(p_shape, p_range);  // the shape rule lowers the peak tension (μ_T) less
}

// Refinement: grid spacing and range shrink together (ρ ∝ √Δx, i.e. w Δx/(E* ρ²) fixed at
// 0.56 and μ_T ∝ Δx^{-1/2}: 1.5, 2.1, 3.0 for n = 32, 64, 128), and the force at
// δ = |δ_c| (one solve from a cold start, in contact) approaches JKR's. Measured signed
// errors −4.2 %, −2.9 %, −1.5 % of (3/2)πwR (and −1.1 % at n = 192, μ_T = 3.7): observed
// order ≈ 0.75 in Δx. The error must fall by at least 20 % at every refinement.
TEST(JKR, ErrorShrinksWithGridAndRange) {
  const double Es = 1, R = 1, s = 1.0 / 6, w = work_for_scale(s);
  const double Fc = 1.5 * pi * w * R;
  const double delta = std::abs(an::jkr_pulloff_load_controlled(Es, R, w).penetration);
  const double F_jkr = [&] {  // JKR at δ on the stable branch
    double lo = an::jkr_pulloff_displacement_controlled(Es, R, w).radius, hi = 1.0;
    for (int k = 0; k < 200; ++k) {
      const double m = 0.5 * (lo + hi);
      (an::jkr_penetration(Es, R, w, m) < delta ? lo : hi) = m;
    }
    return an::jkr_force(Es, R, w, lo);
  }();
  std::vector<double> err;
  for (int n : {32, 64, 128}) {
    const double muT = 3.0 * std::sqrt(n / 128.0);
    const double rho = exponential_range_from_tabor(Es, R, w, muT);
    Grid g{n, n, 1.0, 1.0};
    auto topo = sphere(g, R, 0.5, 0.5, false);
    FreeHalfSpace hs(g, Es);
    AdhesiveSolver::Options o;
    o.tolerance = 1e-7;
    AdhesiveSolver solver(hs, topo.heights, ExponentialAdhesion(w, rho), o);
    ContactState st;
    const auto r = solver.solve({Control::Penetration, delta}, st);
    ASSERT_TRUE(r.converged) << r.message;
    err.push_back(std::abs(st.mean_pressure * g.area() - F_jkr) / Fc);
    char key[64];
    std::snprintf(key, sizeof key, "jkr_refine.n%d.err_F/Fc", n);
    report(key, err.back());
  }
  report("jkr_refine.observed_order_in_dx", std::log2(err.front() / err.back()) / 2.0);
  for (std::size_t i = 1; i < err.size(); ++i) EXPECT_LT(err[i], 0.8 * err[i - 1]) << i;
}

// ============================================================================ Maugis–Dugdale

// Sphere with the (smoothed) Dugdale law against Maugis (1992), free boundary, loading from
// in contact to A = A_max, unloading through pull-off to separation. Smoothing ε is the
// grid's non-bistability bound ε_min = 2σ0Δx/(1.2E*) or 0.2 h0, whichever is larger.
// Errors: the pull-off (golden-section refined), and the largest distance of the (Δ, P̄)
// points from Maugis' curve in units of the pull-off force and penetration.
// Measured (grid study, λ = 3, s = 1/6, refined pull-off): n = 128/192/256 → pull-off
// error 1.6/1.3/0.26 %, distance 2.0/1.3/1.3 %: λ = 3 (cohesive zone c − a ≈ 0.07 a) needs
// ~3 Δx across the zone (Δx/s ≈ 0.023). The test runs it on a larger patch scale s = 0.22,
// A_max = 1.8, n = 192 (same Δx/s, 2x cheaper): 0.74 %, 1.6 %. λ = 1 (s = 1/6, n = 128):
// 0.16 %, 0.22 %; λ = 0.3 (s = 1/8, n = 128; the cohesive zone reaches c ≈ 2.7 s): 0.05 %,
// 0.04 %.
struct MDCase {
  double lambda, s, A_max;
  int n;
};
void PrintTo(const MDCase& c, std::ostream* os) {
  *os << "lambda " << c.lambda << ", s " << c.s << ", A_max " << c.A_max << ", n " << c.n;
}
class Maugis : public ::testing::TestWithParam<MDCase> {};

TEST_P(Maugis, DugdaleSpherePath) {
  const MDCase c = GetParam();
  const double Es = 1, R = 1, w = work_for_scale(c.s);
  Grid g{c.n, c.n, 1.0, 1.0};
  const auto law0 = dugdale_from_lambda(Es, R, w, c.lambda, 0.0);
  const double eps = std::max(0.2 * law0.h0, dugdale_min_smoothing(Es, law0.stress(), g.dx()));
  const DugdaleAdhesion law(w, law0.h0, eps);
  auto topo = sphere(g, R, 0.5, 0.5, false);
  FreeHalfSpace hs(g, Es);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-6;
  AdhesiveSolver solver(hs, topo.heights, law, o);
  const auto sc = an::md_scales(Es, R, w);
  const auto po = an::md_pulloff(c.lambda);
  const auto curve = md_curve_points(c.lambda, 1.3 * c.A_max, 3000);
  double Dmin = 0;
  for (const auto& p : curve) Dmin = std::min(Dmin, p.first);
  const double d_start = an::md_point(c.lambda, 0.6 * c.A_max).Delta * sc.penetration;
  const double d_peak = an::md_point(c.lambda, c.A_max).Delta * sc.penetration;
  LoadPathOptions lo;
  lo.pressure_floor = 2 * std::abs(po.Pbar) * sc.force / g.area();  // the spread of F along the path
  lo.max_halvings = 3;
  lo.refine_pulloff = 8;
  ContactState st;
  const auto res = run_load_path(as_step_solver(solver),
                                 load_unload(Control::Penetration, d_start, d_peak, 1.3 * Dmin * sc.penetration, 1, 8),
                                 st, lo);
  print_path(res);
  ASSERT_TRUE(res.completed) << res.message;
  double dist = 0;
  for (const auto& r : res.steps) {
    ASSERT_TRUE(r.result.converged) << r.result.message;
    if (r.contact_fraction <= 0) continue;
    dist = std::max(dist, polyline_distance(curve, r.penetration / sc.penetration, r.mean_pressure * g.area() / sc.force,
                                            std::abs(po.Delta), std::abs(po.Pbar)));
  }
  const double po_err = res.pulloff_mean_pressure * g.area() / sc.force / po.Pbar - 1;
  char key[80];
  std::snprintf(key, sizeof key, "md.lambda%.1f.pulloff_rel_err", c.lambda);
  report(key, po_err);
  std::snprintf(key, sizeof key, "md.lambda%.1f.max_dist", c.lambda);
  report(key, dist);
  std::snprintf(key, sizeof key, "md.lambda%.1f.halved_steps", c.lambda);
  report(key, res.halved_steps);
  EXPECT_LT(std::abs(po_err), 0.01);  // required
  EXPECT_LT(dist, 0.02);              // required
  EXPECT_LE(res.halved_steps, 4);
}

INSTANTIATE_TEST_SUITE_P(MaugisDugdale, Maugis,
                         ::testing::Values(MDCase{0.3, 1.0 / 8, 1.5, 128}, MDCase{1.0, 1.0 / 6, 2.0, 128},
                                           MDCase{3.0, 0.22, 1.8, 192}),
                         [](const auto& info) {  // lambda0_3, lambda1_0, lambda3_0
                           const int tenths = int(std::lround(10 * info.param.lambda));
                           return "lambda" + std::to_string(tenths / 10) + "_" + std::to_string(tenths % 10);
                         });

// ============================================================================ hard cases

// Cold start at Tabor 3 on a small rough patch: self-affine, 128², cutoff 16 Δx, with the
// challenge's ratios (w/ρ = E*, μ_T = 3 from R_c = 1/rms curvature) and a grid spacing
// of ~1.5 ρ, where the notes report gap-based CG failing from a cold start. The solver
// must converge or report not-converged cleanly: never NaN, g ≥ 0 exactly.
TEST(AdhesiveSolver, ColdStartRoughPatchTabor3) {
  const int n = 128;
  SelfAffineSpec spec;
  spec.hurst = 0.8;
  spec.rolloff_wavelength = 0.25;
  spec.cutoff_wavelength = 16.0 / n;
  spec.rms_gradient = 0.36;
  spec.seed = 7;
  const auto surf = generate_self_affine(spec, n);
  const Grid& g = surf.map.grid;
  const auto stats = surface_statistics(g, surf.map.heights);
  const double Rc = stats.curvature_radius;
  const double rho = Rc / 27.0, w = rho;  // μ_T = (Rc/ρ)^{1/3} (w/ρ)^{2/3} = 3, w/ρ = E*
  ASSERT_NEAR(tabor_parameter(1.0, Rc, w, rho), 3.0, 1e-12);
  report("rough.dx/rho", g.dx() / rho);
  PeriodicHalfSpace hs(g, 1.0);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-6;
  o.max_iterations = 3000;
  AdhesiveSolver solver(hs, surf.map.heights, ExponentialAdhesion(w, rho), o);
  for (double q : {0.1, 0.5}) {  // penetration: min h + q × rms height
    ContactState st;
    const auto r = solver.solve({Control::Penetration, stats.min + q * stats.rms_height}, st);
    char key[64];
    std::snprintf(key, sizeof key, "rough.q%.1f.iterations", q);
    report(key, r.iterations);
    std::snprintf(key, sizeof key, "rough.q%.1f.contact_fraction", q);
    report(key, contact_fraction(st.gap));
    if (!r.converged) EXPECT_FALSE(r.message.empty());
    for (std::size_t i = 0; i < g.size(); ++i) {
      ASSERT_TRUE(std::isfinite(st.pressure[i]) && std::isfinite(st.gap[i]));
      ASSERT_GE(st.gap[i], 0.0);
    }
    EXPECT_TRUE(std::isfinite(r.residual));
    EXPECT_TRUE(r.converged) << r.message;  // it does converge here (measured)
  }
}

// Long-range adhesion, μ_T = 0.3 (DMT-like): an unloading path from contact through the
// pull-off. The pull-off lies between JKR's −1.5πwR and the rigid (Bradley/DMT) −2πwR and
// close to Maugis–Dugdale at matched peak tension, λ = 1.127 μ_T = 0.34 (−1.80πwR).
TEST(AdhesionLongRange, Tabor03PullOff) {
  const int n = 128;
  const double Es = 1, R = 1, s = 1.0 / 12, w = work_for_scale(s), muT = 0.3;
  const double rho = exponential_range_from_tabor(Es, R, w, muT);
  Grid g{n, n, 1.0, 1.0};
  auto topo = sphere(g, R, 0.5, 0.5, false);
  FreeHalfSpace hs(g, Es);
  AdhesiveSolver::Options o;
  o.tolerance = 1e-6;
  AdhesiveSolver solver(hs, topo.heights, ExponentialAdhesion(w, rho), o);
  const auto sc = an::md_scales(Es, R, w);
  LoadPathOptions lo;
  lo.pressure_floor = 2 * pi * w * R / g.area();  // the spread of F along the path
  lo.refine_pulloff = 8;
  ContactState st;
  const auto res = run_load_path(as_step_solver(solver),
                                 load_unload(Control::Penetration, -10 * rho, 1.5 * sc.penetration, -20 * rho, 6, 10),
                                 st, lo);
  print_path(res);
  ASSERT_TRUE(res.completed) << res.message;
  for (const auto& r : res.steps) ASSERT_TRUE(r.result.converged) << r.result.message;
  const double P = res.pulloff_mean_pressure * g.area() / (pi * w * R);
  report("long_range.pulloff/(pi w R)", P);
  report("long_range.md_lambda", an::md_lambda_from_tabor(muT));
  report("long_range.md_pulloff", an::md_pulloff(an::md_lambda_from_tabor(muT)).Pbar);
  EXPECT_LT(P, -1.5);
  EXPECT_GT(P, -2.0);
  EXPECT_LE(res.halved_steps, 4);
}

