// Analytic reference solutions of non-adhesive and wavy contact (Hertz, periodic images, flat
// punches, Westergaard, Johnson 1995); the adhesive sphere (JKR, DMT, Maugis-Dugdale) is in
// SphereAdhesion.cpp, the GSL numerics in Numerics.cpp. See Analytic.hpp for the conventions.
//
// Sources. "Derived" marks results derived here (derivation in the comment) and checked
// independently in tests/test_analytic.cpp. Equation numbers: [J95] eq. (4), [CM04] eq. (39)
// and [M92] eq. (6.17) are as cited by the ContactEngineering ContactMechanics/Adhesion
// reference solutions; the [J85] numbers (4.22)-(4.24) are the standard citations but were
// not re-checked against the book here.
//   [J85]  K. L. Johnson, Contact Mechanics, Cambridge University Press (1985).
//   [J95]  K. L. Johnson, Int. J. Solids Struct. 32, 423 (1995), "The adhesion of two
//          elastic bodies with slightly wavy surfaces".
//   [CM04] G. Carbone, L. Mangialardi, J. Mech. Phys. Solids 52, 1267 (2004).
//   [JKR]  K. L. Johnson, K. Kendall, A. D. Roberts, Proc. R. Soc. Lond. A 324, 301 (1971).
//   [DMT]  B. V. Derjaguin, V. M. Muller, Yu. P. Toporov, J. Colloid Interface Sci. 53, 314 (1975).
//   [M92]  D. Maugis, J. Colloid Interface Sci. 150, 243 (1992).
//   [M00]  D. Maugis, Contact, Adhesion and Rupture of Elastic Solids, Springer (2000).
#include "cmc/analytic/Analytic.hpp"
#include "cmc/analytic/AnalyticParts.hpp"

#include <gsl/gsl_sf_zeta.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cmc::analytic {

using namespace parts;

// ============================================================================ Hertz
// [J85] §4.2.1, eqs. (4.22)-(4.24): a^3 = 3FR/(4E*), delta = a^2/R, p0 = 3F/(2 pi a^2)
// = 2E* a/(pi R); everything follows from the contact radius.
HertzContact hertz_from_radius(double Estar, double R, double a) {
  require(positive(Estar) && positive(R) && nonnegative(a), "hertz_from_radius",
          "need Estar > 0, R > 0, a >= 0");
  return {a, a * a / R, 4 * Estar * a * a * a / (3 * R), 2 * Estar * a / (pi * R)};
}

HertzContact hertz_from_force(double Estar, double R, double F) {
  require(positive(Estar) && positive(R) && nonnegative(F), "hertz_from_force",
          "need Estar > 0, R > 0, F >= 0");
  HertzContact c = hertz_from_radius(Estar, R, std::cbrt(3 * F * R / (4 * Estar)));
  c.force = F;
  return c;
}

HertzContact hertz_from_penetration(double Estar, double R, double delta) {
  require(positive(Estar) && positive(R) && nonnegative(delta), "hertz_from_penetration",
          "need Estar > 0, R > 0, delta >= 0");
  HertzContact c = hertz_from_radius(Estar, R, std::sqrt(R * delta));
  c.penetration = delta;
  return c;
}

// [J85] §4.2.1: p(r) = p0 (1 - r^2/a^2)^{1/2}.
double hertz_pressure(double Estar, double R, double a, double r) {
  const double p0 = hertz_from_radius(Estar, R, a).max_pressure;
  r = std::abs(r);
  return r < a ? p0 * std::sqrt((a - r) * (a + r)) / a : 0.0;
}

// dF/d delta = 2 E* a, from F = (4/3) E* R^{1/2} delta^{3/2} [J85] §4.2.1 (the flat-punch
// stiffness of the contact circle, [J85] §3.8).
double hertz_stiffness(double Estar, double a) {
  require(positive(Estar) && nonnegative(a), "hertz_stiffness", "need Estar > 0, a >= 0");
  return 2 * Estar * a;
}

double hertz_gap(double R, double a, double r) {
  require(positive(R) && positive(a) && nonnegative(r), "hertz_gap", "need R > 0, a > 0, r >= 0");
  if (r <= a) return 0.0;
  const double s = r / a;
  return a * a / R * ((s * s / 2 - 1) + ((2 - s * s) * std::asin(1 / s) + std::sqrt(s * s - 1)) / std::numbers::pi);
}

// ============================================================================ periodic images
// Shift of the penetration of a sphere in a periodic square cell (formula and sign from
// the project notes, reference-solutions.md): delta_per = delta_Hertz - c F/(E* L), with
// c = -Z(1/2)/pi and Z(s) = sum'_{(m,n)} (m^2+n^2)^{-s} the square-lattice Epstein zeta.
// Z(s) = 4 zeta(s) beta(s) (Lorenz 1871 / Hardy 1919; e.g. Borwein et al., Lattice Sums
// Then and Now, CUP 2013, ch. 1), valid for all s by analytic continuation.
// beta(1/2): from 1/(2 cosh x) = sum_k (-1)^k e^{-(2k+1)x} and the Mellin transform,
//   beta(s) Gamma(s) = int_0^inf x^{s-1} dx / (2 cosh x);  x = t^2, s = 1/2:
//   beta(1/2) = (1/sqrt(pi)) int_0^inf sech(t^2) dt   (smooth integrand, gsl qagiu).
double periodic_sphere_shift_coefficient() {
  static const double c = [] {
    gsl_sf_result zeta;
    {
      GslErrorsOff off;
      const int status = gsl_sf_zeta_e(0.5, &zeta);
      if (status != GSL_SUCCESS)
        throw std::runtime_error(std::string("periodic_sphere_shift_coefficient: gsl_sf_zeta: ") +
                                 gsl_strerror(status));
    }
    const double beta = numerics::integrate_to_infinity(
                            [](double t) { return 1.0 / std::cosh(t * t); }, 0.0,
                            "periodic_sphere_shift_coefficient: Dirichlet beta(1/2)", 1e-13) /
                        std::sqrt(pi);
    return -4.0 * zeta.val * beta / pi;
  }();
  return c;
}

double hertz_periodic_penetration(double Estar, double R, double F, double L) {
  require(positive(L), "hertz_periodic_penetration", "need L > 0");
  return hertz_from_force(Estar, R, F).penetration -
         periodic_sphere_shift_coefficient() * F / (Estar * L);
}

// ============================================================================ flat punches
// [J85] §3.8: p(r) = F/(2 pi a sqrt(a^2 - r^2)), delta = F/(2 E* a).
double flat_punch_pressure(double F, double a, double r) {
  require(std::isfinite(F) && positive(a), "flat_punch_pressure", "need finite F and a > 0");
  r = std::abs(r);
  return r < a ? F / (2 * pi * a * std::sqrt((a - r) * (a + r))) : 0.0;
}

double flat_punch_penetration(double Estar, double a, double F) {
  require(positive(Estar) && positive(a) && std::isfinite(F), "flat_punch_penetration",
          "need Estar > 0, a > 0, finite F");
  return F / (2 * Estar * a);
}

namespace {
// Position reduced to [-wavelength/2, wavelength/2].
double reduce_periodic(double x, double wavelength) {
  return x - wavelength * std::round(x / wavelength);
}
// sin^2(pi a/L) - sin^2(pi x/L) = sin(pi (a-x)/L) sin(pi (a+x)/L), accurate at the edge.
double sin2_difference(double a, double x, double wavelength) {
  return std::sin(pi * (a - x) / wavelength) * std::sin(pi * (a + x) / wavelength);
}
void check_half_width(double wavelength, double a, const char* fn) {
  require(positive(wavelength) && nonnegative(a) && a <= wavelength / 2, fn,
          "need wavelength > 0 and 0 <= a <= wavelength/2");
}
}  // namespace

// Periodic strip punch (W. T. Koiter, Ing.-Arch. 28, 168 (1959), as used by [J95]; notes): uniform
// displacement on |x| < a, p(x) = pbar cos(pi x/L) / sqrt(sin^2(pi a/L) - sin^2(pi x/L)); its mean
// is pbar (substitute s = sin(pi x/L)).
double periodic_strip_punch_pressure(double pbar, double wavelength, double a, double x) {
  check_half_width(wavelength, a, "periodic_strip_punch_pressure");
  require(std::isfinite(pbar), "periodic_strip_punch_pressure", "need finite pbar");
  x = std::abs(reduce_periodic(x, wavelength));
  if (pbar == 0 || !(x < a)) return 0.0;
  const double d = sin2_difference(a, x, wavelength);
  return d > 0 ? pbar * std::cos(pi * x / wavelength) / std::sqrt(d) : 0.0;
}

// ============================================================================ Westergaard
// H. M. Westergaard, J. Appl. Mech. 6, A49 (1939); [J85] §13.2; [J95] eq. (4) (mean
// pressure); profile as restated in the notes:
// p* = pi E* h/L, pbar = p* sin^2(pi a/L),
// p(x) = 2 p* cos(pi x/L) sqrt(sin^2(pi a/L) - sin^2(pi x/L)) for |x| < a.
double westergaard_full_contact_pressure(double Estar, double h, double wavelength) {
  require(positive(Estar) && positive(h) && positive(wavelength),
          "westergaard_full_contact_pressure", "need Estar > 0, h > 0, wavelength > 0");
  return pi * Estar * h / wavelength;
}

double westergaard_mean_pressure(double Estar, double h, double wavelength, double a) {
  check_half_width(wavelength, a, "westergaard_mean_pressure");
  const double s = std::sin(pi * a / wavelength);
  return westergaard_full_contact_pressure(Estar, h, wavelength) * s * s;
}

double westergaard_half_width(double Estar, double h, double wavelength, double pbar) {
  const double pstar = westergaard_full_contact_pressure(Estar, h, wavelength);
  require(nonnegative(pbar), "westergaard_half_width", "need pbar >= 0");
  if (pbar >= pstar) return wavelength / 2;
  return wavelength / pi * std::asin(std::sqrt(pbar / pstar));
}

double westergaard_pressure(double Estar, double h, double wavelength, double a, double x) {
  check_half_width(wavelength, a, "westergaard_pressure");
  const double pstar = westergaard_full_contact_pressure(Estar, h, wavelength);
  x = std::abs(reduce_periodic(x, wavelength));
  if (!(x < a)) return 0.0;
  const double d = sin2_difference(a, x, wavelength);
  return d > 0 ? 2 * pstar * std::cos(pi * x / wavelength) * std::sqrt(d) : 0.0;
}

// Mean gap of the wavy contact with half-width a and mean pressure pbar (Westergaard or
// adhesive). With t = sin^2(pi a/L):  gbar = h [1 - t + (pbar/p*) ln t].
// This is [CM04] eq. (39) as used by the Pastewka group's Adhesion package
// (ReferenceSolutions/sinewave/JKR.py, mean_gap), and it was derived here independently:
// gbar = mean(h) - delta + mean(u) = h - u(0), since h(0) = 0 and mean(u) = 0. The
// periodic kernel with zero-mean displacement is u(x) = -(2/(pi E*)) int p(s)
// ln|2 sin(pi (x-s)/L)| ds (from sum_n cos(n th)/n = -ln|2 sin(th/2)| and
// u_k = 2 p_k/(E* |q_k|)). With s = sin(pi x/L) = S sin(phi), S^2 = t, this gives
//   Westergaard part:       u(0) = h t (1 - ln t)
//                           [int_0^{pi/2} cos^2(phi) ln sin(phi) dphi = -(pi/4)(ln 2 + 1/2)],
//   strip punch of mean P:  u(0) = -(h/p*) P ln t
//                           [int_0^{pi/2} ln sin(phi) dphi = -(pi/2) ln 2],
// and with P = pbar - p* t the sum is u(0) = h [t - (pbar/p*) ln t]. (The Westergaard
// part also follows from dU/d delta = pbar.) The test checks it by quadrature.
double sinusoid_mean_gap(double Estar, double h, double wavelength, double a, double pbar) {
  const double pbar_w = westergaard_mean_pressure(Estar, h, wavelength, a);
  const double pstar = westergaard_full_contact_pressure(Estar, h, wavelength);
  require(std::isfinite(pbar) && pbar <= pbar_w + 1e-12 * pstar, "sinusoid_mean_gap",
          "need pbar <= p* sin^2(pi a/wavelength) (no compressive edge singularity)");
  if (a == 0) {
    require(pbar == 0, "sinusoid_mean_gap", "a = 0 carries no load");
    return h;
  }
  const double t = pbar_w / pstar;
  return h * (1 - t + pbar / pstar * std::log(t));
}

// Inverting pbar = p* t gives gbar/h = 1 - x + x ln x with x = pbar/p* (derived).
double westergaard_mean_gap(double Estar, double h, double wavelength, double pbar) {
  const double pstar = westergaard_full_contact_pressure(Estar, h, wavelength);
  require(nonnegative(pbar), "westergaard_mean_gap", "need pbar >= 0");
  if (pbar >= pstar) return 0.0;
  if (pbar == 0) return h;
  const double x = pbar / pstar;
  return h * (1 - x + x * std::log(x));
}

// Superposition (linear elasticity): Westergaard for the conforming part plus the strip
// punch carrying the remaining mean pressure pbar - p* t, as in [J95].
double sinusoid_pressure(double Estar, double h, double wavelength, double a, double pbar,
                         double x) {
  return westergaard_pressure(Estar, h, wavelength, a, x) +
         periodic_strip_punch_pressure(pbar - westergaard_mean_pressure(Estar, h, wavelength, a),
                                       wavelength, a, x);
}

// ============================================================================ Johnson 1995
// alpha = (sqrt 2/pi)(L/h) sqrt(w/(E* L)) = sqrt(2 w L/(E*))/(pi h) [J95]; matches the
// Pastewka group's Adhesion package (sinewave/JKR.py), where alpha = K_Ic/(p* sqrt(L)).
// Derivation (checks the definition): the strip punch of mean P has the edge stress
// intensity factor K = |P| sqrt(L cot(pi a/L)); Griffith's K^2/(2E*) = w gives
// |P| = sqrt(2 E* w/L) sqrt(tan(pi a/L)), i.e. P = -alpha p* sqrt(tan(pi a/L)).
double johnson_alpha(double Estar, double w, double h, double wavelength) {
  westergaard_full_contact_pressure(Estar, h, wavelength);  // validates Estar, h, wavelength
  require(nonnegative(w), "johnson_alpha", "need w >= 0");
  return std::sqrt(2 * w * wavelength / Estar) / (pi * h);
}

// [J95]: pbar/p* = sin^2(pi a/L) - alpha sqrt(tan(pi a/L)) (the eq. (4) Westergaard term
// minus the adhesive strip-punch term derived above).
double johnson_mean_pressure(double Estar, double w, double h, double wavelength, double a) {
  const double alpha = johnson_alpha(Estar, w, h, wavelength);
  check_half_width(wavelength, a, "johnson_mean_pressure");
  const double pbar_w = westergaard_mean_pressure(Estar, h, wavelength, a);
  if (alpha == 0) return pbar_w;
  require(a < wavelength / 2, "johnson_mean_pressure",
          "a = wavelength/2 (full contact) needs infinite tension when w > 0");
  return pbar_w - alpha * westergaard_full_contact_pressure(Estar, h, wavelength) *
                      std::sqrt(std::tan(pi * a / wavelength));
}

double johnson_pressure(double Estar, double w, double h, double wavelength, double a, double x) {
  return sinusoid_pressure(Estar, h, wavelength, a,
                           johnson_mean_pressure(Estar, w, h, wavelength, a), x);
}

double johnson_mean_gap(double Estar, double w, double h, double wavelength, double a) {
  return sinusoid_mean_gap(Estar, h, wavelength, a,
                           johnson_mean_pressure(Estar, w, h, wavelength, a));
}

namespace {
// With psi = pi a/L: d(pbar/p*)/d psi = (g(psi) - alpha) / (2 sqrt(tan psi) cos^2 psi),
// g = 4 sin^{3/2} cos^{5/2} (derived). g rises from 0 to its maximum at tan^2 psi = 3/5 and
// falls back to 0 at pi/2, so for 0 < alpha < max g, pbar has a local minimum psi_min
// (load-controlled pull-off) and a local maximum psi_max (jump into full contact), and the
// load-controlled stable branch is psi_min < psi < psi_max.
struct JohnsonStationary {
  double psi_min, psi_max;
};
JohnsonStationary johnson_stationary(double alpha) {
  if (alpha == 0) return {0.0, pi / 2};
  const auto g = [](double psi) {
    return 4 * std::pow(std::sin(psi), 1.5) * std::pow(std::cos(psi), 2.5);
  };
  const double psi_g = std::atan(std::sqrt(0.6));
  if (!(alpha < g(psi_g)))
    throw std::runtime_error(
        "cmc::analytic::johnson: alpha >= 4 (3/8)^{3/4} (5/8)^{5/4} ~ 1.065: mean pressure "
        "decreases monotonically with a, no stable partial contact exists");
  const auto f = [&](double psi) { return g(psi) - alpha; };
  return {numerics::find_root(f, 0.0, psi_g, "johnson: pull-off point"),
          numerics::find_root(f, psi_g, pi / 2, "johnson: jump-to-full-contact point")};
}
}  // namespace

SinusoidPoint johnson_pulloff(double Estar, double w, double h, double wavelength) {
  const auto st = johnson_stationary(johnson_alpha(Estar, w, h, wavelength));
  const double a = st.psi_min * wavelength / pi;
  return {a, johnson_mean_pressure(Estar, w, h, wavelength, a)};
}

double johnson_half_width(double Estar, double w, double h, double wavelength, double pbar) {
  const double alpha = johnson_alpha(Estar, w, h, wavelength);
  require(std::isfinite(pbar), "johnson_half_width", "need finite pbar");
  if (alpha == 0) return westergaard_half_width(Estar, h, wavelength, pbar);
  const auto st = johnson_stationary(alpha);
  const auto f = [&](double psi) {
    return johnson_mean_pressure(Estar, w, h, wavelength, psi * wavelength / pi) - pbar;
  };
  require(f(st.psi_min) <= 0 && f(st.psi_max) >= 0, "johnson_half_width",
          "pbar outside the stable branch [pull-off, jump into full contact]");
  return numerics::find_root(f, st.psi_min, st.psi_max, "johnson_half_width") * wavelength / pi;
}

// Zero load has a partial-contact equilibrium only while max_psi (sin^2 psi - alpha
// sqrt(tan psi)) >= 0, i.e. alpha <= max_psi sin^{3/2}psi cos^{1/2}psi (derived; the
// maximum is at tan^2 psi = 3, value 3^{3/4}/4 ~ 0.570; [J95] quotes ~0.57).
double johnson_full_contact_alpha() {
  static const double alpha = [] {
    const auto f = [](double psi) {
      return -std::pow(std::sin(psi), 1.5) * std::sqrt(std::cos(psi));
    };
    return -f(numerics::minimize(f, 0.0, pi / 4, pi / 2, "johnson_full_contact_alpha"));
  }();
  return alpha;
}

}  // namespace cmc::analytic
