// Analytic reference solutions for validating cmc: Hertz, flat punch, periodic images,
// Westergaard and Johnson (1995) wavy contact, JKR, DMT and Maugis-Dugdale.
//
// Conventions (cmc-wide): compressive pressure p > 0, gap g >= 0, penetration delta > 0
// into the solid, Estar = contact modulus, w = work of adhesion. Every function is pure
// and unit-agnostic (any consistent units). Invalid arguments throw std::invalid_argument;
// a failed root search, minimisation or quadrature throws std::runtime_error: no function
// returns NaN silently.
//
// The numerics use GSL. Its error handler is switched off only for the duration of each
// call (the handler is process-global, so do not call these concurrently with code that
// relies on GSL's default abort handler).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace cmc::analytic {

// ---------------------------------------------------------------- GSL numerics
// Thin wrappers that check every GSL return code and throw std::runtime_error (with
// `what` in the message) on failure. Exceptions thrown by f are propagated.
namespace numerics {
using Function = std::function<double(double)>;
// Root of f in [lo, hi] (gsl_root_fsolver_brent); f(lo) and f(hi) must differ in sign.
double find_root(const Function& f, double lo, double hi, const std::string& what);
// Argument of the minimum of f in (lo, hi) (gsl_min_fminimizer_brent); needs
// f(guess) < f(lo) and f(guess) < f(hi).
double minimize(const Function& f, double lo, double guess, double hi, const std::string& what);
// Integral of f over [lo, hi] (gsl_integration_qags: copes with integrable endpoint
// singularities) and over [lo, inf) (gsl_integration_qagiu), to max(epsabs, epsrel |I|).
double integrate(const Function& f, double lo, double hi, const std::string& what,
                 double epsrel = 1e-11, double epsabs = 0);
double integrate_to_infinity(const Function& f, double lo, const std::string& what,
                             double epsrel = 1e-11);
}  // namespace numerics

// ---------------------------------------------------------------- Hertz (paraboloid h = r^2/2R)
struct HertzContact {
  double radius;        // a
  double penetration;   // delta
  double force;         // F
  double max_pressure;  // p0
};
HertzContact hertz_from_force(double Estar, double R, double F);
HertzContact hertz_from_penetration(double Estar, double R, double delta);
HertzContact hertz_from_radius(double Estar, double R, double a);
// p(r) = p0 sqrt(1 - r^2/a^2) for r < a, 0 outside.
double hertz_pressure(double Estar, double R, double a, double r);
// dF/d delta = 2 Estar a.
double hertz_stiffness(double Estar, double a);
// Gap between the sphere and the deformed half-space at radius r (0 for r <= a), for
// contact radius a (Johnson 1985 eq. 3.42b), with s = r/a and delta = a^2/R:
// g = delta [(s^2/2 - 1) + ((2 - s^2) asin(1/s) + sqrt(s^2 - 1)) / pi]. Independent
// of Estar.
double hertz_gap(double R, double a, double r);

// ---------------------------------------------------------------- periodic images
// c = -Z(1/2)/pi ~ 1.2415, Z the square-lattice Epstein zeta (computed, not tabulated).
double periodic_sphere_shift_coefficient();
// delta_periodic = delta_Hertz(F) - c F/(Estar L): sphere in a periodic square cell of
// side L, penetration measured from the mean plane of the elastic surface.
double hertz_periodic_penetration(double Estar, double R, double F, double L);

// ---------------------------------------------------------------- flat punches
// Axisymmetric rigid flat punch of radius a under force F.
double flat_punch_pressure(double F, double a, double r);         // 0 for r >= a
double flat_punch_penetration(double Estar, double a, double F);  // F/(2 Estar a)
// Periodic array (period wavelength) of 1-D flat strips of half-width a, mean pressure
// pbar; x is measured from a strip centre (periodic).
double periodic_strip_punch_pressure(double pbar, double wavelength, double a, double x);

// ---------------------------------------------------------------- Westergaard wavy contact
// Rigid profile h(x) = 2h sin^2(pi x/wavelength) = h (1 - cos(2 pi x/wavelength)) on an
// elastic half-plane: h is the amplitude, 2h the peak-to-valley height; a is the contact
// half-width, x is measured from the contact centre (periodic).
double westergaard_full_contact_pressure(double Estar, double h, double wavelength);  // p*
double westergaard_mean_pressure(double Estar, double h, double wavelength, double a);
// Inverse of the above; wavelength/2 (full contact) for pbar >= p*.
double westergaard_half_width(double Estar, double h, double wavelength, double pbar);
double westergaard_pressure(double Estar, double h, double wavelength, double a, double x);
// Mean gap (mean of indenter minus elastic surface) at mean pressure pbar, with the
// displacement measured from the mean plane of the elastic surface; 0 for pbar >= p*.
double westergaard_mean_gap(double Estar, double h, double wavelength, double pbar);

// The same profile with contact half-width a carrying an arbitrary mean pressure pbar
// (Westergaard plus a periodic strip punch): pressure and mean gap.
double sinusoid_pressure(double Estar, double h, double wavelength, double a, double pbar,
                         double x);
double sinusoid_mean_gap(double Estar, double h, double wavelength, double a, double pbar);

// ---------------------------------------------------------------- Johnson (1995) adhesive sinusoid
struct SinusoidPoint {
  double half_width;     // a
  double mean_pressure;  // pbar
};
double johnson_alpha(double Estar, double w, double h, double wavelength);
double johnson_mean_pressure(double Estar, double w, double h, double wavelength, double a);
double johnson_pressure(double Estar, double w, double h, double wavelength, double a, double x);
double johnson_mean_gap(double Estar, double w, double h, double wavelength, double a);
// Half-width on the branch that is stable under load control (between the pull-off point
// and the jump into full contact); throws if pbar has no such solution.
double johnson_half_width(double Estar, double w, double h, double wavelength, double pbar);
// Load-controlled pull-off: the local minimum of pbar(a) on the small-a side.
// Throws if alpha >= 4 (3/8)^{3/4} (5/8)^{5/4} ~ 1.065 (no partial-contact branch at all).
SinusoidPoint johnson_pulloff(double Estar, double w, double h, double wavelength);
// alpha above which the contact jumps into full contact at zero load (3^{3/4}/4 ~ 0.570).
double johnson_full_contact_alpha();

// ---------------------------------------------------------------- JKR and DMT spheres
struct AdhesiveContact {
  double radius;       // a
  double penetration;  // delta
  double force;        // F
};
double jkr_force(double Estar, double R, double w, double a);
double jkr_penetration(double Estar, double R, double w, double a);
// Contact radius on the stable (load-controlled) branch; F >= -(3/2) pi w R.
double jkr_radius_from_force(double Estar, double R, double w, double F);
double jkr_zero_load_radius(double Estar, double R, double w);
// Pull-off under load control (F = -3/2 pi w R) and displacement control (F = -5/6 pi w R).
AdhesiveContact jkr_pulloff_load_controlled(double Estar, double R, double w);
AdhesiveContact jkr_pulloff_displacement_controlled(double Estar, double R, double w);

double dmt_force(double Estar, double R, double w, double a);
double dmt_penetration(double R, double a);
double dmt_radius_from_force(double Estar, double R, double w, double F);  // F >= -2 pi w R

// ---------------------------------------------------------------- Maugis-Dugdale
// Reduced units of Maugis (1992), K = 4 Estar/3:
//   A = a/(pi w R^2/K)^{1/3}, Pbar = F/(pi w R), Delta = delta/(pi^2 w^2 R/K^2)^{1/3},
//   lambda = 2 sigma0 (R/(pi w K^2))^{1/3}, m = c/a (c = outer radius of the cohesive zone).
struct MDScales {
  double radius, force, penetration;  // the units of A, Pbar and Delta
};
MDScales md_scales(double Estar, double R, double w);
double md_lambda(double Estar, double R, double w, double sigma0);
// lambda when sigma0 equals the peak tension w/rho of exponential adhesion, in terms of the
// Tabor parameter mu_T = R^{1/3} (w/Estar)^{2/3}/rho: lambda = 2 (9/(16 pi))^{1/3} mu_T.
double md_lambda_from_tabor(double mu_T);

struct MDPoint {
  double A, m, Pbar, Delta;
};
MDPoint md_point(double lambda, double A);  // lambda > 0, A > 0
// The end of the curve A -> 0 (c stays finite; m = +inf).
MDPoint md_zero_radius_limit(double lambda);
// Load-controlled pull-off: the minimum of Pbar over A >= 0 (may be the A -> 0 end).
MDPoint md_pulloff(double lambda);
// n >= 2 points, A equally spaced in [A_min, A_max], A_min > 0.
std::vector<MDPoint> md_curve(double lambda, double A_min, double A_max, int n);

struct MDContact {
  double radius;       // a
  double zone_radius;  // c
  double force;        // F
  double penetration;  // delta
};
MDContact md_contact(double Estar, double R, double w, double sigma0, double a);

}  // namespace cmc::analytic
