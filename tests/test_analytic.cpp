// Unit tests of the analytic reference module (solver/cmc/analytic/Analytic.*): every check
// compares two different routes to the same number (closed form vs. quadrature, limit vs.
// general model, closed form vs. root finding), so a wrong formula on either side fails.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "cmc/analytic/Analytic.hpp"

namespace {

using namespace cmc::analytic;
using numerics::integrate;
constexpr double pi = std::numbers::pi;

// Reduced units: arbitrary O(1) values that are not 1, so a misplaced factor shows.
constexpr double Es = 1.3, R = 2.1, w = 0.07;
constexpr double h = 0.11, L = 1.7;  // wavy profile: amplitude h, wavelength L
// Work of adhesion giving Johnson parameter alpha for this profile (inverts johnson_alpha).
double w_for_alpha(double alpha) { return std::pow(alpha * pi * h, 2) * Es / (2 * L); }
const double w_j = w_for_alpha(0.3);  // a stable partial-contact branch exists (alpha < 1.065)

// Relative deviation.
double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

// Mean over one period of a pressure supported on |x| < a (QAGS copes with the sqrt or
// 1/sqrt behaviour at the contact edges).
template <class Pressure>
double period_mean(const Pressure& p, double a) {
  return integrate(p, -a, a, "period mean") / L;
}

// Displacement at x = 0 (relative to the mean plane of the elastic surface) of a periodic
// half-plane under an even pressure supported on |x| < a, from the periodic kernel
// -(2/(pi E*)) ln|2 sin(pi x/L)|, which is the Fourier sum u_k = 2 p_k/(E* |q_k|)
// (sum_n cos(n t)/n = -ln|2 sin(t/2)|, Gradshteyn-Ryzhik 1.441.2).
template <class Pressure>
double centre_displacement(const Pressure& p, double a) {
  return -4 / (pi * Es) *
         integrate([&](double s) { return p(s) * std::log(2 * std::sin(pi * s / L)); }, 0, a,
                   "u(0)", 1e-10);
}

// ------------------------------------------------------------------------- Hertz
TEST(AnalyticHertz, ForcePenetrationRadiusRoundTrip) {
  for (double F : {1e-3, 0.37, 52.0}) {
    const HertzContact c = hertz_from_force(Es, R, F);
    const HertzContact d = hertz_from_penetration(Es, R, c.penetration);
    const HertzContact e = hertz_from_radius(Es, R, c.radius);
    // Closed-form algebra (cbrt, sqrt, a few products): round-off only.
    EXPECT_LT(rel(d.force, F), 1e-13);
    EXPECT_LT(rel(e.force, F), 1e-13);
    EXPECT_LT(rel(d.radius, c.radius), 1e-13);
    EXPECT_LT(rel(e.max_pressure, 3 * F / (2 * pi * c.radius * c.radius)), 1e-13);
    // F = (4/3) E* R^{1/2} delta^{3/2} (Johnson 1985, §4.2.1).
    EXPECT_LT(rel(F, 4.0 / 3 * Es * std::sqrt(R) * std::pow(c.penetration, 1.5)), 1e-13);
  }
}

TEST(AnalyticHertz, PressureIntegratesToForce) {
  const HertzContact c = hertz_from_force(Es, R, 0.8);
  const double F =
      integrate([&](double r) { return 2 * pi * r * hertz_pressure(Es, R, c.radius, r); }, 0,
                c.radius, "Hertz force");
  // QAGS asked for 1e-11 relative; the sqrt edge is handled by its extrapolation.
  EXPECT_LT(rel(F, c.force), 1e-9);
  EXPECT_DOUBLE_EQ(hertz_pressure(Es, R, c.radius, 0), c.max_pressure);
  EXPECT_EQ(hertz_pressure(Es, R, c.radius, 1.01 * c.radius), 0.0);
}

TEST(AnalyticHertz, StiffnessIsDerivativeOfForce) {
  const double delta = 0.05, d = 1e-4 * delta;
  const double dFdd = (hertz_from_penetration(Es, R, delta + d).force -
                       hertz_from_penetration(Es, R, delta - d).force) /
                      (2 * d);
  // Central difference: truncation ~ (d/delta)^2 = 1e-8, round-off ~ 1e-16/1e-4.
  EXPECT_LT(rel(dFdd, hertz_stiffness(Es, hertz_from_penetration(Es, R, delta).radius)), 1e-7);
}

TEST(AnalyticFlatPunch, PressureIntegratesToForceAndStiffnessMatchesHertz) {
  const double F = 0.6, a = 0.3;
  const double Fi = integrate([&](double r) { return 2 * pi * r * flat_punch_pressure(F, a, r); },
                              0, a, "punch force");
  EXPECT_LT(rel(Fi, F), 1e-9);  // 1/sqrt edge singularity: QAGS extrapolation
  // The incremental Hertz stiffness is that of a flat punch of the contact radius.
  EXPECT_LT(rel(F / flat_punch_penetration(Es, a, F), hertz_stiffness(Es, a)), 1e-14);
}

// ------------------------------------------------------------------------- periodic images
TEST(AnalyticPeriodic, ShiftCoefficient) {
  const double c = periodic_sphere_shift_coefficient();
  EXPECT_NEAR(c, 1.2415, 1e-4);  // the value in the notes (4 digits)
  // Independent route to Z(1/2) (Riemann's theta-function method, derived):
  //   pi^{-s} Gamma(s) Z(s) = -1/s - 1/(1-s) + int_1^inf (t^{s-1} + t^{-s}) (theta(t)^2 - 1) dt,
  //   theta(t) = sum_n exp(-pi n^2 t);  s = 1/2:  Z(1/2) = -4 + 2 int_1^inf (theta^2 - 1)/sqrt(t).
  const auto theta = [](double t) {
    double s = 1;
    for (int n = 1; n < 30; ++n) s += 2 * std::exp(-pi * n * n * t);
    return s;
  };
  const double Z = -4 + 2 * numerics::integrate_to_infinity(
                                [&](double t) { return (theta(t) * theta(t) - 1) / std::sqrt(t); },
                                1.0, "theta integral", 1e-12);
  EXPECT_NEAR(c, -Z / pi, 1e-10);  // both quadratures converge to ~1e-12
  const double F = 0.4, Lc = 3.0;
  EXPECT_NEAR(hertz_periodic_penetration(Es, R, F, Lc),
              hertz_from_force(Es, R, F).penetration - c * F / (Es * Lc), 1e-15);
}

// ------------------------------------------------------------------------- Westergaard
TEST(AnalyticWestergaard, MeanPressureInverseAndIntegral) {
  const double pstar = westergaard_full_contact_pressure(Es, h, L);
  EXPECT_LT(rel(pstar, pi * Es * h / L), 1e-15);
  for (double frac : {0.02, 0.17, 0.33, 0.49}) {
    const double a = frac * L;
    const double pbar = westergaard_mean_pressure(Es, h, L, a);
    EXPECT_LT(rel(westergaard_half_width(Es, h, L, pbar), a), 1e-12);
    // Mean of the profile over one period; the integrand has a sqrt edge.
    const double mean =
        period_mean([&](double x) { return westergaard_pressure(Es, h, L, a, x); }, a);
    EXPECT_LT(rel(mean, pbar), 1e-9);
    // Periodic, and zero outside the contact.
    EXPECT_NEAR(westergaard_pressure(Es, h, L, a, 0.3 * a + 2 * L),
                westergaard_pressure(Es, h, L, a, 0.3 * a), 1e-13 * pstar);  // x reduced mod L
    EXPECT_EQ(westergaard_pressure(Es, h, L, a, a + 0.01 * L), 0.0);
  }
  // Full contact: the pressure is the sinusoid that flattens the profile exactly.
  for (double x : {0.0, 0.1, 0.3, 0.45})
    EXPECT_NEAR(westergaard_pressure(Es, h, L, L / 2, x * L), pstar * (1 + std::cos(2 * pi * x)),
                1e-13 * pstar);
}

TEST(AnalyticWestergaard, MeanGapMatchesQuadrature) {
  const double pstar = westergaard_full_contact_pressure(Es, h, L);
  EXPECT_EQ(westergaard_mean_gap(Es, h, L, 0.0), h);
  EXPECT_EQ(westergaard_mean_gap(Es, h, L, pstar), 0.0);
  double previous = h;
  for (double frac : {0.01, 0.1, 0.25, 0.4, 0.49}) {
    const double a = frac * L;
    const double pbar = westergaard_mean_pressure(Es, h, L, a);
    const double gap = westergaard_mean_gap(Es, h, L, pbar);
    // mean gap = mean(h) - delta + mean(u) = h - u(0), by quadrature of the exact pressure.
    const double u0 =
        centre_displacement([&](double x) { return westergaard_pressure(Es, h, L, a, x); }, a);
    EXPECT_NEAR(gap, h - u0, 1e-9 * h);  // log singularity at 0, sqrt edge: QAGS to 1e-10
    EXPECT_NEAR(sinusoid_mean_gap(Es, h, L, a, pbar), gap, 1e-13 * h);
    EXPECT_LT(gap, previous);
    previous = gap;
  }
}

TEST(AnalyticWestergaard, CentreDisplacementFromFourierModes) {
  // Checks the kernel used above against the explicit mode sum u(0) = sum_n 2 c_n/(E* q_n),
  // c_n = (2/L) int p(x) cos(q_n x) dx, q_n = 2 pi n/L. With sin(pi x/L) = S sin(phi):
  //   c_n = (4 p* S^2/pi) int_{-pi/2}^{pi/2} cos^2(phi) cos(2 n theta(phi)) dphi,
  //   theta = asin(S sin phi).
  // The integrand is analytic and pi-periodic in phi, so the M-point trapezoidal rule is
  // exact up to aliasing, which is negligible while M/2 >> 2 n S (here 4096 vs 1600).
  const double a = 0.3 * L, S = std::sin(pi * a / L);
  const double pstar = westergaard_full_contact_pressure(Es, h, L);
  constexpr int N = 1000, M = 8192;
  std::vector<double> c(N + 1, 0.0);
  for (int j = 0; j < M; ++j) {
    const double phi = -pi / 2 + pi * j / M, cp = std::cos(phi);
    const double theta = std::asin(S * std::sin(phi)), c2 = std::cos(2 * theta);
    double cm = 1, cn = c2;  // cos(2 n theta) by the Chebyshev recurrence
    for (int n = 1; n <= N; ++n) {
      c[n] += cp * cp * cn;
      const double next = 2 * c2 * cn - cm;
      cm = cn, cn = next;
    }
  }
  double u0 = 0;
  for (int n = 1; n <= N; ++n)
    u0 += 2 * (4 * pstar * S * S / pi * (pi / M) * c[n]) / (Es * 2 * pi * n / L);
  // c_n ~ n^{-3/2} cos(q_n a + const) (sqrt edge); the oscillating tail of sum c_n/n then
  // falls as N^{-5/2}: 9e-9 h at N = 1000 (2.8e-7 at N = 250, 1.6e-9 at N = 2000).
  const double gap = westergaard_mean_gap(Es, h, L, westergaard_mean_pressure(Es, h, L, a));
  EXPECT_NEAR(h - u0, gap, 1e-7 * h);
}

TEST(AnalyticWestergaard, StripPunchMeanPressure) {
  const double a = 0.2 * L, pbar = -0.3;
  const double mean =
      period_mean([&](double x) { return periodic_strip_punch_pressure(pbar, L, a, x); }, a);
  EXPECT_LT(rel(mean, pbar), 1e-9);
  EXPECT_DOUBLE_EQ(periodic_strip_punch_pressure(pbar, L, L / 2, 0.1), pbar);  // uniform
}

// ------------------------------------------------------------------------- Johnson 1995
TEST(AnalyticJohnson, ZeroAdhesionIsWestergaard) {
  EXPECT_EQ(johnson_alpha(Es, 0, h, L), 0.0);
  for (double frac : {0.05, 0.2, 0.45}) {
    const double a = frac * L, pbar = westergaard_mean_pressure(Es, h, L, a);
    EXPECT_DOUBLE_EQ(johnson_mean_pressure(Es, 0, h, L, a), pbar);
    EXPECT_DOUBLE_EQ(johnson_mean_gap(Es, 0, h, L, a), westergaard_mean_gap(Es, h, L, pbar));
    EXPECT_DOUBLE_EQ(johnson_half_width(Es, 0, h, L, pbar), a);
    for (double x : {0.0, 0.5 * a, 0.99 * a})
      EXPECT_DOUBLE_EQ(johnson_pressure(Es, 0, h, L, a, x), westergaard_pressure(Es, h, L, a, x));
  }
  EXPECT_EQ(johnson_pulloff(Es, 0, h, L).mean_pressure, 0.0);
}

TEST(AnalyticJohnson, AlphaAndGriffithCriterion) {
  const double pstar = westergaard_full_contact_pressure(Es, h, L);
  const double alpha = johnson_alpha(Es, w_j, h, L);
  EXPECT_LT(rel(alpha, std::sqrt(2.0) / pi * (L / h) * std::sqrt(w_j / (Es * L))), 1e-14);
  // Independent check of alpha: the tensile stress intensity factor at the contact edge,
  // K = lim sqrt(2 pi (a-x)) (-p(x)), must satisfy Griffith K^2/(2 E*) = w. At a - x = eps
  // the relative error is O(eps/L) = 1e-8 (plus round-off in the edge difference).
  const double a = 0.2 * L, eps = 1e-8 * L;
  const double K = std::sqrt(2 * pi * eps) * -johnson_pressure(Es, w_j, h, L, a, a - eps);
  EXPECT_LT(rel(K * K / (2 * Es), w_j), 1e-6);
  // The mean of the profile is the mean pressure (superposition is consistent).
  const double mean =
      period_mean([&](double x) { return johnson_pressure(Es, w_j, h, L, a, x); }, a);
  EXPECT_NEAR(mean, johnson_mean_pressure(Es, w_j, h, L, a), 1e-9 * pstar);
}

TEST(AnalyticJohnson, MeanGapMatchesQuadrature) {
  for (double frac : {0.05, 0.2, 0.35}) {
    const double a = frac * L;
    const double u0 =
        centre_displacement([&](double x) { return johnson_pressure(Es, w_j, h, L, a, x); }, a);
    EXPECT_NEAR(johnson_mean_gap(Es, w_j, h, L, a), h - u0, 1e-9 * h);
  }
}

TEST(AnalyticJohnson, PulloffIsMinimumOfStableBranch) {
  const double pstar = westergaard_full_contact_pressure(Es, h, L);
  const SinusoidPoint p = johnson_pulloff(Es, w_j, h, L);
  ASSERT_GT(p.half_width, 0);
  EXPECT_LT(p.mean_pressure, 0);
  // No sampled a on the small-a side of the local maximum goes lower than the pull-off.
  double scan_min = 0;
  for (int k = 1; k < 4000; ++k) {
    const double a = 0.25 * L * k / 4000;
    scan_min = std::min(scan_min, johnson_mean_pressure(Es, w_j, h, L, a));
  }
  EXPECT_LE(p.mean_pressure, scan_min + 1e-14 * pstar);
  // Quadratic minimum, grid spacing 6e-5 L: the scan is within ~1e-8 p* of it.
  EXPECT_NEAR(p.mean_pressure, scan_min, 1e-7 * pstar);
  // Half-width from load on the stable branch.
  for (double pbar : {0.9 * p.mean_pressure, 0.0, 0.3 * pstar}) {
    const double a = johnson_half_width(Es, w_j, h, L, pbar);
    EXPECT_GT(a, p.half_width);
    EXPECT_NEAR(johnson_mean_pressure(Es, w_j, h, L, a), pbar, 1e-12 * pstar);
  }
  EXPECT_THROW(johnson_half_width(Es, w_j, h, L, 1.01 * p.mean_pressure), std::invalid_argument);
}

TEST(AnalyticJohnson, SpontaneousFullContactAlpha) {
  const double ac = johnson_full_contact_alpha();
  EXPECT_NEAR(ac, std::pow(3.0, 0.75) / 4, 1e-12);  // maximum at tan^2 = 3 (derived)
  EXPECT_NEAR(ac, 0.57, 1e-3);                      // Johnson (1995): ~0.57
  // Just below ac a zero-load partial contact exists (max pbar >= 0), just above it does not.
  const auto max_pbar = [](double alpha) {
    double m = -1e300;
    for (int k = 1; k < 20000; ++k) {
      const double psi = pi / 2 * k / 20000;
      m = std::max(m, std::sin(psi) * std::sin(psi) - alpha * std::sqrt(std::tan(psi)));
    }
    return m;
  };
  EXPECT_GT(max_pbar(0.999 * ac), 0);
  EXPECT_LT(max_pbar(1.001 * ac), 0);
  // Past alpha = 4 (3/8)^{3/4} (5/8)^{5/4} = 1.0652 there is no stable partial contact.
  const double alpha_max = 4 * std::pow(3.0 / 8, 0.75) * std::pow(5.0 / 8, 1.25);
  EXPECT_NEAR(alpha_max, 1.0652, 1e-4);
  EXPECT_LT(johnson_pulloff(Es, w_for_alpha(0.999 * alpha_max), h, L).mean_pressure, 0);
  EXPECT_THROW(johnson_pulloff(Es, w_for_alpha(1.001 * alpha_max), h, L), std::runtime_error);
}

// ------------------------------------------------------------------------- JKR / DMT
TEST(AnalyticJKR, ZeroAdhesionIsHertz) {
  for (double a : {0.01, 0.2, 1.5}) {
    const HertzContact c = hertz_from_radius(Es, R, a);
    EXPECT_DOUBLE_EQ(jkr_force(Es, R, 0, a), c.force);
    EXPECT_DOUBLE_EQ(jkr_penetration(Es, R, 0, a), c.penetration);
    EXPECT_LT(rel(jkr_radius_from_force(Es, R, 0, c.force), a), 1e-13);
  }
}

TEST(AnalyticJKR, RadiusFromForceMatchesClosedForm) {
  // JKR (1971): a^3 = (3R/(4E*)) [F + 3 pi w R + sqrt(6 pi w R F + (3 pi w R)^2)].
  const double Fc = 3 * pi * w * R;
  for (double F : {-0.45 * Fc, -0.2 * Fc, 0.0, 0.5, 7.0}) {
    const double a3 = 3 * R / (4 * Es) * (F + Fc + std::sqrt(2 * Fc * F + Fc * Fc));
    const double a = jkr_radius_from_force(Es, R, w, F);
    EXPECT_LT(rel(a, std::cbrt(a3)), 1e-12);  // Brent to 1e-14 relative
    EXPECT_NEAR(jkr_force(Es, R, w, a), F, 1e-12 * Fc);
  }
  EXPECT_LT(rel(jkr_radius_from_force(Es, R, w, 0.0), jkr_zero_load_radius(Es, R, w)), 1e-12);
  EXPECT_THROW(jkr_radius_from_force(Es, R, w, -0.51 * Fc), std::invalid_argument);
}

TEST(AnalyticJKR, PulloffPoints) {
  const double unit = pi * w * R, a0 = jkr_zero_load_radius(Es, R, w);
  const AdhesiveContact lc = jkr_pulloff_load_controlled(Es, R, w);
  const AdhesiveContact dc = jkr_pulloff_displacement_controlled(Es, R, w);
  EXPECT_NEAR(lc.force, -1.5 * unit, 1e-13 * unit);
  EXPECT_NEAR(dc.force, -5.0 / 6 * unit, 1e-13 * unit);
  EXPECT_LT(rel(std::pow(lc.radius / a0, 3), 0.25), 1e-13);
  EXPECT_LT(rel(std::pow(dc.radius / a0, 3), 1.0 / 36), 1e-13);
  // Load control: minimum of F(a); displacement control: minimum of delta(a). Scan spacing
  // 5e-4 a0 around quadratic minima: scan minima sit within ~1e-6 (relative) above them.
  double Fmin = 1e300, dmin = 1e300;
  for (int k = 1; k <= 4000; ++k) {
    const double a = 2 * a0 * k / 4000;
    Fmin = std::min(Fmin, jkr_force(Es, R, w, a));
    dmin = std::min(dmin, jkr_penetration(Es, R, w, a));
  }
  EXPECT_LE(lc.force, Fmin);
  EXPECT_NEAR(lc.force, Fmin, 1e-6 * unit);
  EXPECT_LE(dc.penetration, dmin);
  EXPECT_NEAR(dc.penetration, dmin, 1e-6 * std::abs(dmin));
  const double da = 1e-5 * dc.radius;  // d delta/da = 0 there (central difference)
  const auto delta = [&](double a) { return jkr_penetration(Es, R, w, a); };
  EXPECT_NEAR((delta(dc.radius + da) - delta(dc.radius - da)) / (2 * da), 0.0, 1e-8);
}

TEST(AnalyticDMT, ForceRadiusRoundTrip) {
  EXPECT_DOUBLE_EQ(dmt_force(Es, R, w, 0), -2 * pi * w * R);
  for (double a : {0.0, 0.1, 0.9}) {
    const double F = dmt_force(Es, R, w, a);
    EXPECT_NEAR(dmt_radius_from_force(Es, R, w, F), a, 1e-13);
    EXPECT_NEAR(F + 2 * pi * w * R, hertz_from_radius(Es, R, a).force, 1e-14);
    EXPECT_DOUBLE_EQ(dmt_penetration(R, a), hertz_from_radius(Es, R, a).penetration);
  }
}

// ------------------------------------------------------------------------- Maugis-Dugdale
TEST(AnalyticMD, SolutionSatisfiesMaugisEquation) {
  for (double lambda : {0.05, 0.7, 20.0})
    for (double A : {0.05, 0.6, 2.0}) {
      const MDPoint p = md_point(lambda, A);
      // Maugis (1992) eq. 6.17 in its original m-form (the solver uses mu = sqrt(m^2-1)).
      const double m = p.m, mu = std::sqrt(m * m - 1), at = std::atan(mu);
      const double lhs = lambda * A * A / 2 * (mu + (m * m - 2) * at) +
                         4 * lambda * lambda * A / 3 * (mu * at - m + 1);
      EXPECT_NEAR(lhs, 1.0, 1e-9);  // m - 1 may be ~1e-4: m^2 - 1 loses ~4 digits here
      EXPECT_GT(p.m, 1.0);
    }
}

TEST(AnalyticMD, SmallLambdaIsDMT) {
  // Leading corrections (derived from eq. 6.17 for m >> 1): Pbar - (A^3 - 2) = O(lambda),
  // Delta - A^2 = O(lambda^{1/2}). Check the values and that the errors shrink at these rates.
  const auto errors = [](double lambda) {
    double eP = 0, eD = 0;
    for (double A : {0.2, 0.5, 1.0, 2.0}) {
      const MDPoint p = md_point(lambda, A);
      eP = std::max(eP, std::abs(p.Pbar - (A * A * A - 2)));
      eD = std::max(eD, std::abs(p.Delta - A * A));
    }
    return std::pair{eP, eD};
  };
  const auto [eP4, eD4] = errors(1e-4);
  const auto [eP6, eD6] = errors(1e-6);
  EXPECT_LT(eP4, 2e-3);
  EXPECT_LT(eD4, 2e-2);
  EXPECT_NEAR(eP4 / eP6, 100.0, 5.0);  // linear in lambda
  EXPECT_NEAR(eD4 / eD6, 10.0, 1.0);   // sqrt(lambda)
}

TEST(AnalyticMD, LargeLambdaIsJKR) {
  // Compare with the JKR functions through the dimensional wrapper: choose sigma0 so that
  // lambda = 1e3; JKR is approached as O(lambda^-2) (observed below: ~3e-6 (1 + |value|)).
  const double lambda = 1e3, sigma0 = lambda / md_lambda(Es, R, w, 1.0);
  const MDScales s = md_scales(Es, R, w);
  for (double A : {0.2, 0.8, 1.5, 3.0}) {
    const double a = A * s.radius;
    const MDContact c = md_contact(Es, R, w, sigma0, a);
    const double P = jkr_force(Es, R, w, a) / s.force,
                 D = jkr_penetration(Es, R, w, a) / s.penetration;
    EXPECT_NEAR(c.force / s.force, P, 1e-5 * (1 + std::abs(P)));
    EXPECT_NEAR(c.penetration / s.penetration, D, 1e-5 * (1 + std::abs(D)));
    EXPECT_LT(c.zone_radius / a - 1, 1e-3);  // cohesive zone shrinks to the contact edge
  }
  const double e2 = std::abs(md_point(1e2, 1.0).Pbar - (1 - std::sqrt(6.0)));
  const double e3 = std::abs(md_point(1e3, 1.0).Pbar - (1 - std::sqrt(6.0)));
  EXPECT_NEAR(e2 / e3, 100.0, 5.0);
}

TEST(AnalyticMD, ZeroRadiusLimit) {
  const MDPoint end = md_zero_radius_limit(0.5);
  const MDPoint p = md_point(0.5, 1e-7);
  EXPECT_NEAR(p.Pbar, end.Pbar, 1e-6);  // corrections are O(A)
  EXPECT_NEAR(p.Delta, end.Delta, 1e-6);
}

TEST(AnalyticMD, PulloffBetweenDMTAndJKRAndMonotone) {
  double previous = -2.0;
  for (double lambda : {1e-3, 0.01, 0.05, 0.1, 0.3, 0.5, 1.0, 2.0, 5.0, 20.0, 100.0}) {
    const MDPoint p = md_pulloff(lambda);
    EXPECT_GT(p.Pbar, -2.0);
    EXPECT_LT(p.Pbar, -1.5);
    EXPECT_GT(p.Pbar, previous) << "lambda = " << lambda;
    previous = p.Pbar;
    // A minimum: neighbours are not lower.
    for (double dA : {1e-3, 1e-2})
      if (p.A > dA) {
        EXPECT_GE(md_point(lambda, p.A - dA).Pbar, p.Pbar);
        EXPECT_GE(md_point(lambda, p.A + dA).Pbar, p.Pbar);
      }
  }
  EXPECT_NEAR(md_pulloff(1e-3).Pbar, -2.0, 1e-3);  // DMT end (error O(lambda^{3/2}))
  // JKR end: -3/2 at A = (3/2)^{1/3}; O(lambda^-2) corrections.
  const MDPoint jkr = md_pulloff(1e3);
  EXPECT_NEAR(jkr.Pbar, -1.5, 1e-5);
  EXPECT_NEAR(jkr.A, std::cbrt(1.5), 1e-4);
  const std::vector<MDPoint> curve = md_curve(1.0, 0.1, 2.0, 20);
  ASSERT_EQ(curve.size(), 20u);
  for (const MDPoint& q : curve) EXPECT_GE(q.Pbar, md_pulloff(1.0).Pbar);
}

TEST(AnalyticMD, LambdaFromTabor) {
  // mu_T = R^{1/3} (w/E*)^{2/3}/rho; sigma0 = w/rho (peak tension of exponential adhesion).
  const double rho = 0.013;
  const double muT = std::cbrt(R) * std::pow(w / Es, 2.0 / 3) / rho;
  EXPECT_LT(rel(md_lambda_from_tabor(muT), md_lambda(Es, R, w, w / rho)), 1e-14);
  EXPECT_NEAR(md_lambda_from_tabor(1.0), 1.1272, 1e-4);  // the notes' ~1.127
}

// ------------------------------------------------------------------------- argument checks
TEST(AnalyticErrors, InvalidArgumentsThrow) {
  EXPECT_THROW(hertz_from_force(Es, R, -1), std::invalid_argument);
  EXPECT_THROW(hertz_from_force(-Es, R, 1), std::invalid_argument);
  EXPECT_THROW(hertz_from_penetration(Es, R, std::nan("")), std::invalid_argument);
  EXPECT_THROW(westergaard_mean_pressure(Es, h, L, 0.6 * L), std::invalid_argument);
  EXPECT_THROW(westergaard_half_width(Es, h, L, -0.1), std::invalid_argument);
  EXPECT_THROW(johnson_mean_pressure(Es, w, h, L, L / 2), std::invalid_argument);
  EXPECT_THROW(md_point(0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(md_point(1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(dmt_radius_from_force(Es, R, w, -7 * w * R), std::invalid_argument);
  EXPECT_THROW(
      sinusoid_mean_gap(Es, h, L, 0.2 * L, 2 * westergaard_mean_pressure(Es, h, L, 0.2 * L)),
      std::invalid_argument);
  // Failed numerics are runtime errors, and exceptions inside callbacks propagate.
  EXPECT_THROW(numerics::find_root([](double x) { return x * x + 1; }, -1, 1, "no root"),
               std::runtime_error);
  EXPECT_THROW(
      numerics::integrate([](double) -> double { throw std::logic_error("cb"); }, 0, 1, "cb"),
      std::logic_error);
}

}  // namespace
