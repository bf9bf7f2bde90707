// Analytic reference solutions; see Analytic.hpp for the conventions.
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

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_min.h>
#include <gsl/gsl_roots.h>
#include <gsl/gsl_sf_zeta.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cmc::analytic {

namespace {

constexpr double pi = std::numbers::pi;

// ---- argument checks (NaN fails every one of them)
void require(bool ok, const char* fn, const char* message) {
  if (!ok) throw std::invalid_argument(std::string("cmc::analytic::") + fn + ": " + message);
}
bool positive(double x) { return x > 0 && std::isfinite(x); }
bool nonnegative(double x) { return x >= 0 && std::isfinite(x); }

// ---- GSL plumbing
// Switches GSL's abort-on-error handler off for the lifetime of the object.
class GslErrorsOff {
 public:
  GslErrorsOff() : previous_(gsl_set_error_handler_off()) {}
  ~GslErrorsOff() { gsl_set_error_handler(previous_); }
  GslErrorsOff(const GslErrorsOff&) = delete;
  GslErrorsOff& operator=(const GslErrorsOff&) = delete;

 private:
  gsl_error_handler_t* previous_;
};

// Lets GSL's C code call a std::function. An exception must not unwind through C frames:
// it is stored, GSL sees NaN (and stops with an error), and the exception is rethrown.
struct Callback {
  const numerics::Function* f;
  std::exception_ptr error{};

  static double call(double x, void* self) noexcept {
    auto* cb = static_cast<Callback*>(self);
    if (cb->error) return std::numeric_limits<double>::quiet_NaN();
    try {
      return (*cb->f)(x);
    } catch (...) {
      cb->error = std::current_exception();
      return std::numeric_limits<double>::quiet_NaN();
    }
  }
  gsl_function gsl() { return gsl_function{&Callback::call, this}; }
  void after(int status, const std::string& what, const char* step) const {
    if (error) std::rethrow_exception(error);
    if (status != GSL_SUCCESS)
      throw std::runtime_error(what + ": GSL " + step + " failed: " + gsl_strerror(status));
  }
};

template <class T, void (*Free)(T*)>
std::unique_ptr<T, void (*)(T*)> owned(T* p, const std::string& what) {
  if (!p) throw std::runtime_error(what + ": GSL allocation failed");
  return {p, Free};
}

}  // namespace

// ============================================================================ numerics
namespace numerics {

double find_root(const Function& f, double lo, double hi, const std::string& what) {
  if (!(lo < hi)) throw std::invalid_argument(what + ": empty root bracket");
  const double flo = f(lo), fhi = f(hi);
  if (!std::isfinite(flo) || !std::isfinite(fhi))
    throw std::runtime_error(what + ": function not finite at the ends of the root bracket");
  if (flo == 0) return lo;
  if (fhi == 0) return hi;
  if ((flo < 0) == (fhi < 0)) throw std::runtime_error(what + ": root not bracketed");

  GslErrorsOff off;
  Callback cb{&f};
  gsl_function F = cb.gsl();
  auto s = owned<gsl_root_fsolver, gsl_root_fsolver_free>(
      gsl_root_fsolver_alloc(gsl_root_fsolver_brent), what);
  cb.after(gsl_root_fsolver_set(s.get(), &F, lo, hi), what, "root bracket");
  const double epsabs = 1e-300;  // relative accuracy decides unless the root is 0
  for (int it = 0; it < 1000; ++it) {
    cb.after(gsl_root_fsolver_iterate(s.get()), what, "root iteration");
    const int status = gsl_root_test_interval(gsl_root_fsolver_x_lower(s.get()),
                                              gsl_root_fsolver_x_upper(s.get()), epsabs, 1e-14);
    if (status == GSL_SUCCESS) return gsl_root_fsolver_root(s.get());
    if (status != GSL_CONTINUE) cb.after(status, what, "root convergence test");
  }
  throw std::runtime_error(what + ": root search did not converge");
}

double minimize(const Function& f, double lo, double guess, double hi, const std::string& what) {
  if (!(lo < guess && guess < hi)) throw std::invalid_argument(what + ": bad minimum bracket");
  const double flo = f(lo), fg = f(guess), fhi = f(hi);
  if (!(fg < flo && fg < fhi)) throw std::runtime_error(what + ": minimum not bracketed");

  GslErrorsOff off;
  Callback cb{&f};
  gsl_function F = cb.gsl();
  auto s = owned<gsl_min_fminimizer, gsl_min_fminimizer_free>(
      gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent), what);
  cb.after(gsl_min_fminimizer_set_with_values(s.get(), &F, guess, fg, lo, flo, hi, fhi), what,
           "minimum bracket");
  // The location of a smooth minimum is only defined to ~sqrt(DBL_EPSILON); the value
  // there is then accurate to ~DBL_EPSILON.
  const double epsabs = 1e-12 * (hi - lo), epsrel = 1e-7;
  for (int it = 0; it < 500; ++it) {
    cb.after(gsl_min_fminimizer_iterate(s.get()), what, "minimiser iteration");
    const int status = gsl_min_test_interval(gsl_min_fminimizer_x_lower(s.get()),
                                             gsl_min_fminimizer_x_upper(s.get()), epsabs, epsrel);
    if (status == GSL_SUCCESS) return gsl_min_fminimizer_x_minimum(s.get());
    if (status != GSL_CONTINUE) cb.after(status, what, "minimiser convergence test");
  }
  throw std::runtime_error(what + ": minimisation did not converge");
}

namespace {
template <class Quadrature>
double quadrature(const Function& f, const std::string& what, Quadrature&& q) {
  constexpr std::size_t limit = 2000;
  GslErrorsOff off;
  Callback cb{&f};
  gsl_function F = cb.gsl();
  auto ws = owned<gsl_integration_workspace, gsl_integration_workspace_free>(
      gsl_integration_workspace_alloc(limit), what);
  double result = 0, abserr = 0;
  cb.after(q(&F, limit, ws.get(), &result, &abserr), what, "integration");
  return result;
}
}  // namespace

double integrate(const Function& f, double lo, double hi, const std::string& what, double epsrel,
                 double epsabs) {
  return quadrature(
      f, what,
      [&](gsl_function* F, std::size_t n, gsl_integration_workspace* w, double* r, double* e) {
        return gsl_integration_qags(F, lo, hi, epsabs, epsrel, n, w, r, e);
      });
}

double integrate_to_infinity(const Function& f, double lo, const std::string& what, double epsrel) {
  return quadrature(
      f, what,
      [&](gsl_function* F, std::size_t n, gsl_integration_workspace* w, double* r, double* e) {
        return gsl_integration_qagiu(F, lo, 0.0, epsrel, n, w, r, e);
      });
}

}  // namespace numerics

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
