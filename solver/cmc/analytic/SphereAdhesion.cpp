// Analytic references of the adhesive sphere: JKR, DMT and Maugis-Dugdale (Analytic.hpp
// for the conventions). Sources, as cited in Analytic.cpp:
//   [JKR]  K. L. Johnson, K. Kendall, A. D. Roberts, Proc. R. Soc. Lond. A 324, 301 (1971).
//   [DMT]  B. V. Derjaguin, V. M. Muller, Yu. P. Toporov, J. Colloid Interface Sci. 53, 314 (1975).
//   [M92]  D. Maugis, J. Colloid Interface Sci. 150, 243 (1992).
//   [M00]  D. Maugis, Contact, Adhesion and Rupture of Elastic Solids, Springer (2000).
#include "cmc/analytic/Analytic.hpp"
#include "cmc/analytic/AnalyticParts.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cmc::analytic {

using namespace parts;

// ============================================================================ JKR
// [JKR]; reduced forms as in [M00] ch. 5: F = 4E* a^3/(3R) - sqrt(8 pi w E* a^3),
// delta = a^2/R - sqrt(2 pi w a/E*).
namespace {
void check_sphere(double Estar, double R, double w, const char* fn) {
  require(positive(Estar) && positive(R) && nonnegative(w), fn, "need Estar > 0, R > 0, w >= 0");
}
AdhesiveContact jkr_at(double Estar, double R, double w, double a) {
  return {a, jkr_penetration(Estar, R, w, a), jkr_force(Estar, R, w, a)};
}
}  // namespace

double jkr_force(double Estar, double R, double w, double a) {
  check_sphere(Estar, R, w, "jkr_force");
  require(nonnegative(a), "jkr_force", "need a >= 0");
  return 4 * Estar * a * a * a / (3 * R) - std::sqrt(8 * pi * w * Estar * a * a * a);
}

double jkr_penetration(double Estar, double R, double w, double a) {
  check_sphere(Estar, R, w, "jkr_penetration");
  require(nonnegative(a), "jkr_penetration", "need a >= 0");
  return a * a / R - std::sqrt(2 * pi * w * a / Estar);
}

// F(a0) = 0: a0^3 = 9 pi w R^2/(2 E*).
double jkr_zero_load_radius(double Estar, double R, double w) {
  check_sphere(Estar, R, w, "jkr_zero_load_radius");
  return std::cbrt(9 * pi * w * R * R / (2 * Estar));
}

// dF/da = 0: a^3 = 9 pi w R^2/(8 E*) = a0^3/4, F = -(3/2) pi w R [JKR].
AdhesiveContact jkr_pulloff_load_controlled(double Estar, double R, double w) {
  check_sphere(Estar, R, w, "jkr_pulloff_load_controlled");
  return jkr_at(Estar, R, w, std::cbrt(9 * pi * w * R * R / (8 * Estar)));
}

// d delta/da = 0: a^3 = pi w R^2/(8 E*) = a0^3/36, F = -(5/6) pi w R ([M00] ch. 5).
AdhesiveContact jkr_pulloff_displacement_controlled(double Estar, double R, double w) {
  check_sphere(Estar, R, w, "jkr_pulloff_displacement_controlled");
  return jkr_at(Estar, R, w, std::cbrt(pi * w * R * R / (8 * Estar)));
}

// F(a) increases for a > a_c (the load-controlled pull-off radius): Brent on [a_c, hi].
double jkr_radius_from_force(double Estar, double R, double w, double F) {
  check_sphere(Estar, R, w, "jkr_radius_from_force");
  require(std::isfinite(F), "jkr_radius_from_force", "need finite F");
  if (w == 0) return hertz_from_force(Estar, R, F).radius;
  const AdhesiveContact c = jkr_pulloff_load_controlled(Estar, R, w);
  const double tol = 1e-13 * pi * w * R;
  require(F >= c.force - tol, "jkr_radius_from_force", "F below the pull-off force -3/2 pi w R");
  if (F <= c.force + tol) return c.radius;
  const auto f = [&](double a) { return jkr_force(Estar, R, w, a) - F; };
  double hi = 2 * std::max(c.radius, std::cbrt(3 * std::abs(F) * R / (4 * Estar)));
  while (f(hi) <= 0) hi *= 2;
  return numerics::find_root(f, c.radius, hi, "jkr_radius_from_force");
}

// ============================================================================ DMT
// [DMT]; as in [M00] ch. 5: F = 4E* a^3/(3R) - 2 pi w R, delta = a^2/R.
double dmt_force(double Estar, double R, double w, double a) {
  check_sphere(Estar, R, w, "dmt_force");
  require(nonnegative(a), "dmt_force", "need a >= 0");
  return 4 * Estar * a * a * a / (3 * R) - 2 * pi * w * R;
}

double dmt_penetration(double R, double a) {
  require(positive(R) && nonnegative(a), "dmt_penetration", "need R > 0, a >= 0");
  return a * a / R;
}

double dmt_radius_from_force(double Estar, double R, double w, double F) {
  check_sphere(Estar, R, w, "dmt_radius_from_force");
  require(std::isfinite(F) && F >= -2 * pi * w * R, "dmt_radius_from_force",
          "F below the DMT pull-off force -2 pi w R");
  return hertz_from_force(Estar, R, F + 2 * pi * w * R).radius;
}

// ============================================================================ Maugis-Dugdale
MDScales md_scales(double Estar, double R, double w) {
  require(positive(Estar) && positive(R) && positive(w), "md_scales",
          "need Estar > 0, R > 0, w > 0");
  const double K = 4 * Estar / 3;
  return {std::cbrt(pi * w * R * R / K), pi * w * R, std::cbrt(pi * pi * w * w * R / (K * K))};
}

// [M92]: lambda = 2 sigma0 (R/(pi w K^2))^{1/3}, K = 4E*/3.
double md_lambda(double Estar, double R, double w, double sigma0) {
  require(positive(Estar) && positive(R) && positive(w) && positive(sigma0), "md_lambda",
          "need Estar, R, w, sigma0 > 0");
  const double K = 4 * Estar / 3;
  return 2 * sigma0 * std::cbrt(R / (pi * w * K * K));
}

// Derived: with sigma0 = w/rho (peak tension of exponential adhesion) and K = 4E*/3,
//   lambda = 2 (w/rho) R^{1/3} / (pi w (16/9) E*^2)^{1/3}
//          = 2 (9/(16 pi))^{1/3} R^{1/3} (w/E*)^{2/3} / rho = 2 (9/(16 pi))^{1/3} mu_T
// ~ 1.1272 mu_T (mu_T in Müser's form, see the notes). For Lennard-Jones matching
// (sigma0 = 16 w/(9 sqrt 3 z0)) the same algebra gives Maugis' lambda ~ 1.157 mu.
double md_lambda_from_tabor(double mu_T) {
  require(positive(mu_T), "md_lambda_from_tabor", "need mu_T > 0");
  return 2 * std::cbrt(9 / (16 * pi)) * mu_T;
}

namespace {
void check_lambda(double lambda, const char* fn) {
  require(positive(lambda), fn, "need lambda > 0 (lambda -> 0 is DMT: use dmt_*)");
}

// [M92] eq. (6.17), written in mu = sqrt(m^2 - 1) to avoid the cancellation in m^2 - 1
// for m -> 1 (JKR limit):
//   (lambda A^2/2)[mu + (m^2-2) atan mu] + (4 lambda^2 A/3)[mu atan mu - m + 1] - 1,
// with mu + (m^2-2) atan mu = (mu - atan mu) + mu^2 atan mu and m - 1 = mu^2/(m+1).
double md_residual(double lambda, double A, double mu) {
  const double m = std::sqrt(1 + mu * mu), at = std::atan(mu);
  const double mu2 = mu * mu;
  const double mu_minus_atan =
      mu < 1e-2 ? mu * mu2 * (1.0 / 3 - mu2 * (1.0 / 5 - mu2 * (1.0 / 7 - mu2 / 9))) : mu - at;
  return 0.5 * lambda * A * A * (mu_minus_atan + mu2 * at) +
         4.0 / 3 * lambda * lambda * A * (mu * at - mu2 / (m + 1)) - 1;
}
}  // namespace

// The residual increases monotonically in m (derived: both brackets have positive
// m-derivatives), from -1 at m = 1, so the root is unique; the bracket is grown by doubling.
// Load and penetration: Pbar = A^3 - lambda A^2 [mu + m^2 atan mu],
// Delta = A^2 - (4/3) lambda A mu ([M92] §6, the relations following eq. (6.17)).
MDPoint md_point(double lambda, double A) {
  check_lambda(lambda, "md_point");
  require(positive(A), "md_point", "need A > 0 (A -> 0: md_zero_radius_limit)");
  const auto f = [&](double mu) { return md_residual(lambda, A, mu); };
  double hi = 1;
  while (f(hi) <= 0) {
    hi *= 2;
    if (hi > 1e150) throw std::runtime_error("md_point: cannot bracket m");
  }
  const double mu = numerics::find_root(f, 0.0, hi, "md_point: cohesive-zone ratio m");
  const double m = std::sqrt(1 + mu * mu), at = std::atan(mu);
  return {A, m, A * A * A - lambda * A * A * (mu + m * m * at), A * A - 4.0 / 3 * lambda * A * mu};
}

// A -> 0 with y = A m fixed (derived from eq. (6.17): mu ~ m, atan mu ~ pi/2 - 1/m):
//   (pi lambda/4) y^2 + (4 lambda^2/3)(pi/2 - 1) y = 1,
//   Pbar -> -(pi/2) lambda y^2,  Delta -> -(4/3) lambda y.
MDPoint md_zero_radius_limit(double lambda) {
  check_lambda(lambda, "md_zero_radius_limit");
  const double qa = pi * lambda / 4, qb = 4 * lambda * lambda / 3 * (pi / 2 - 1);
  const double y = 2 / (qb + std::sqrt(qb * qb + 4 * qa));
  return {0.0, std::numeric_limits<double>::infinity(), -pi / 2 * lambda * y * y,
          -4.0 / 3 * lambda * y};
}

// Minimum of Pbar(A) over A >= 0. A coarse scan (200 points on [0, 3]; the JKR pull-off is
// at A = (3/2)^{1/3} ~ 1.14 and Pbar(A) is smooth on a scale of ~0.1) brackets it; GSL Brent
// refines an interior minimum, and a minimum at the first sample is the A -> 0 end.
MDPoint md_pulloff(double lambda) {
  check_lambda(lambda, "md_pulloff");
  const MDPoint end = md_zero_radius_limit(lambda);
  const auto pbar = [&](double A) { return A > 0 ? md_point(lambda, A).Pbar : end.Pbar; };
  constexpr int n = 200;
  constexpr double A_max = 3.0;
  int k_min = 0;
  double p_min = end.Pbar;
  for (int k = 1; k <= n; ++k) {
    const double p = pbar(A_max * k / n);
    if (p < p_min) p_min = p, k_min = k;
  }
  if (k_min == n) throw std::runtime_error("md_pulloff: no minimum of Pbar for A <= 3");
  if (k_min == 0) return end;
  const double dA = A_max / n;
  return md_point(lambda, numerics::minimize(pbar, dA * (k_min - 1), dA * k_min, dA * (k_min + 1),
                                             "md_pulloff"));
}

std::vector<MDPoint> md_curve(double lambda, double A_min, double A_max, int n) {
  require(positive(A_min) && A_max > A_min && std::isfinite(A_max) && n >= 2, "md_curve",
          "need 0 < A_min < A_max and n >= 2");
  std::vector<MDPoint> curve;
  curve.reserve(std::size_t(n));
  for (int k = 0; k < n; ++k)
    curve.push_back(md_point(lambda, A_min + (A_max - A_min) * k / (n - 1)));
  return curve;
}

MDContact md_contact(double Estar, double R, double w, double sigma0, double a) {
  const double lambda = md_lambda(Estar, R, w, sigma0);
  const MDScales s = md_scales(Estar, R, w);
  require(positive(a), "md_contact", "need a > 0");
  const MDPoint p = md_point(lambda, a / s.radius);
  return {a, p.m * a, p.Pbar * s.force, p.Delta * s.penetration};
}

}  // namespace cmc::analytic
