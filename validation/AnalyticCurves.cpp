// The analytic reference curves (Hertz, Westergaard, JKR, Maugis-Dugdale, Johnson's
// sinusoid) sampled from cmc/analytic, and their names (References.hpp).
#include "ReferenceParts.hpp"

#include "cmc/analytic/Analytic.hpp"

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

namespace cmc::reference {

using namespace parts;

namespace {

constexpr double pi = std::numbers::pi;
namespace an = cmc::analytic;

Curve base(const std::string& name, const std::string& quantity, const std::string& title, const std::string& source) {
  Curve c;
  c.name = name;
  c.quantity = quantity;
  c.title = title;
  c.source = "analytic: " + source;
  c.extra.emplace_back("generator", "cmc reference " + name + " (validation/References.cpp, solver/cmc/analytic/Analytic.cpp)");
  return c;
}
// The same, with the units and sampling lines that most curves state next.
Curve base(const std::string& name, const std::string& quantity, const std::string& title, const std::string& source,
           const std::string& units, const std::string& sampling) {
  Curve c = base(name, quantity, title, source);
  c.extra.emplace_back("units", units);
  c.extra.emplace_back("sampling", sampling);
  return c;
}

// Samples a curve at x = k / div, k = k0..k1: x goes to `x`, the values f(x) returns (an
// array, one per column) to `ys`.
template <std::size_t K, class F>
void sample(Column& x, const std::array<Column*, K>& ys, int k0, int k1, double div, F f) {
  for (int k = k0; k <= k1; ++k) {
    const double v = k / div;
    const std::array<double, K> y = f(v);
    x.values.push_back(v);
    for (std::size_t i = 0; i < K; ++i) ys[i]->values.push_back(y[i]);
  }
}

const char* kRoundOff = "closed form evaluated in double precision, stored with 13 significant digits: "
                        "< 1e-12 relative";

Curve hertz_penetration_force() {
  Curve c = base("hertz_penetration_force", "penetration_vs_force", "Hertz: penetration and contact radius vs force",
                 "Hertz (1882); Johnson, Contact Mechanics (1985) eqs. 4.22-4.23: a^3 = 3FR/(4E*), delta = a^2/R, "
                 "i.e. F = (4/3) E* R^(1/2) delta^(3/2)",
                 "reduced: force in E* R^2, lengths in R (R = sphere radius, E* = contact modulus)",
                 "F/(E* R^2) = 10^(-9 + k/10), k = 0..60");
  Column F{"F_over_EstarR2", "1", "F/(E* R^2)", {}}, d{"delta_over_R", "1", "penetration delta/R", {}},
      a{"a_over_R", "1", "contact radius a/R", {}};
  for (int k = 0; k <= 60; ++k) {
    const double f = std::pow(10.0, -9.0 + k / 10.0);
    const auto h = an::hertz_from_force(1.0, 1.0, f);
    F.values.push_back(f);
    d.values.push_back(h.penetration);
    a.values.push_back(h.radius);
  }
  // the validation suite's penetration tolerance (cases/validation/hertz-*.toml)
  return with_axes(std::move(c), {F, d, a}, F.name, d.name, "log-log",
                   kRoundOff, 1e-3, "max_rel");
}

Curve hertz_pressure_profile() {
  Curve c = base("hertz_pressure_profile", "pressure_profile", "Hertz: pressure profile p(r)/p0 vs r/a",
                 "Hertz (1882); Johnson, Contact Mechanics (1985) eq. 4.22: p(r) = p0 sqrt(1 - r^2/a^2) for r < a, "
                 "0 outside, p0 = 2 E* a/(pi R) = 3F/(2 pi a^2)",
                 "reduced: r in the contact radius a, p in the peak pressure p0 (independent of load)",
                 "r/a = k/100, k = 0..150");
  Column r{"r_over_a", "1", "radial distance r/a", {}}, p{"p_over_p0", "1", "pressure p/p0", {}};
  const double a = 0.1;
  const double p0 = an::hertz_from_radius(1.0, 1.0, a).max_pressure;
  sample<1>(r, {&p}, 0, 150, 100.0, [&](double x) { return std::array{an::hertz_pressure(1.0, 1.0, a, x * a) / p0}; });
  // the validation suite's pressure_profile tolerance (in units of p0)
  return with_axes(std::move(c), {r, p}, r.name, p.name, "lin-lin",
                   kRoundOff, 1e-2, "max_abs");
}

const char* kWestergaardSource =
    "Westergaard (1939); Johnson, Contact Mechanics (1985) sec. 13.2; Johnson, Int. J. Solids Struct. 32, 423 "
    "(1995) eq. 4: profile h(x) = 2h sin^2(pi x/lambda), p* = pi E* h/lambda, pbar = p* sin^2(pi a/lambda), "
    "p(x) = 2 p* cos(pi x/lambda) sqrt(sin^2(pi a/lambda) - sin^2(pi x/lambda)) for |x| < a";

Curve westergaard_mean_pressure() {
  Curve c = base("westergaard_mean_pressure", "mean_pressure_vs_half_width",
                 "Westergaard wavy contact: mean pressure vs contact half-width", kWestergaardSource,
                 "reduced: lengths in the wavelength lambda, pressure in p* = pi E* h/lambda",
                 "a/lambda = k/200, k = 0..100");
  Column a{"a_over_lambda", "1", "contact half-width a/lambda", {}}, p{"pbar_over_pstar", "1", "mean pressure pbar/p*", {}};
  const double pstar = an::westergaard_full_contact_pressure(1.0, 1.0, 1.0);
  sample<1>(a, {&p}, 0, 100, 200.0,
            [&](double x) { return std::array{an::westergaard_mean_pressure(1.0, 1.0, 1.0, x) / pstar}; });
  return with_axes(std::move(c), {a, p}, a.name, p.name, "lin-lin",
                   kRoundOff, 1e-3, "max_abs");
}

Curve westergaard_mean_gap() {
  Curve c = base("westergaard_mean_gap", "mean_gap_vs_pressure", "Westergaard wavy contact: mean gap vs mean pressure",
                 std::string(kWestergaardSource) +
                     "; mean gap gbar = h (1 - t + t ln t), t = pbar/p* (Carbone & Mangialardi, JMPS 52, 1267 "
                     "(2004) eq. 39)",
                 "reduced: pressure in p* = pi E* h/lambda, gap in the amplitude h",
                 "pbar/p* = 10^(-4 + k/10), k = 0..40");
  Column p{"pbar_over_pstar", "1", "mean pressure pbar/p*", {}}, g{"mean_gap_over_h", "1", "mean gap / h", {}};
  const double pstar = an::westergaard_full_contact_pressure(1.0, 1.0, 1.0);
  for (int k = 0; k <= 40; ++k) {
    const double x = std::pow(10.0, -4.0 + k / 10.0);
    p.values.push_back(x);
    g.values.push_back(an::westergaard_mean_gap(1.0, 1.0, 1.0, x * pstar));
  }
  return with_axes(std::move(c), {p, g}, p.name, g.name, "log-lin",
                   kRoundOff, 1e-3, "max_abs");
}

Curve westergaard_pressure_profile() {
  Curve c = base("westergaard_pressure_profile", "pressure_profile",
                 "Westergaard wavy contact: pressure profiles at pbar/p* = 0.1, 0.3, 0.6, 0.9", kWestergaardSource,
                 "reduced: x in the wavelength lambda (from the contact centre), pressure in p*",
                 "x/lambda = k/200, k = -100..100");
  const std::vector<double> loads = {0.1, 0.3, 0.6, 0.9};
  const double pstar = an::westergaard_full_contact_pressure(1.0, 1.0, 1.0);
  Column x{"x_over_lambda", "1", "position x/lambda from the contact centre", {}};
  std::vector<Column> cols;
  for (double l : loads) {
    char name[64];
    std::snprintf(name, sizeof name, "p_over_pstar_at_%.1f", l);
    Column col{name, "1", "p/p* at pbar/p* = " + short_num(l), {}};
    const double a = an::westergaard_half_width(1.0, 1.0, 1.0, l * pstar);
    for (int k = -100; k <= 100; ++k) col.values.push_back(an::westergaard_pressure(1.0, 1.0, 1.0, a, k / 200.0) / pstar);
    cols.push_back(col);
  }
  for (int k = -100; k <= 100; ++k) x.values.push_back(k / 200.0);
  cols.insert(cols.begin(), x);
  // the validation suite's pressure_profile tolerance (in units of p*)
  return with_axes(std::move(c), cols, x.name, cols[1].name, "lin-lin", kRoundOff, 1e-2, "max_abs");
}

Curve jkr_force_penetration() {
  Curve c = base("jkr_force_penetration", "force_vs_penetration",
                 "JKR: force and penetration vs contact radius (both branches)",
                 "Johnson, Kendall & Roberts, Proc. R. Soc. A 324, 301 (1971); Maugis, Contact, Adhesion and "
                 "Rupture of Elastic Solids (2000) ch. 5: F = 4E* a^3/(3R) - sqrt(8 pi w E* a^3), "
                 "delta = a^2/R - sqrt(2 pi w a/E*); in Maugis' units Pbar = A^3 - sqrt(6 A^3), "
                 "Delta = A^2 - (2/3) sqrt(6 A)");
  c.extra.emplace_back("units",
                       "reduced (Maugis, J. Colloid Interface Sci. 150, 243 (1992)), K = 4E*/3: A = a/(pi w R^2/K)^(1/3), "
                       "Pbar = F/(pi w R), Delta = delta/(pi^2 w^2 R/K^2)^(1/3)");
  const double Es = 1.0, R = 1.0, w = 1.0;
  const auto s = an::md_scales(Es, R, w);
  const auto lc = an::jkr_pulloff_load_controlled(Es, R, w);
  const auto dc = an::jkr_pulloff_displacement_controlled(Es, R, w);
  c.extra.emplace_back("branches",
                       "parametrised by A (monotonic); under load control A < " + short_num(lc.radius / s.radius) +
                           " is unstable (pull-off at Pbar = " + short_num(lc.force / s.force) +
                           "); under displacement control A < " + short_num(dc.radius / s.radius) +
                           " is unstable (pull-off at Delta = " + short_num(dc.penetration / s.penetration) +
                           ", Pbar = " + short_num(dc.force / s.force) + ")");
  c.extra.emplace_back("sampling", "A = k/50, k = 0..150");
  Column A{"A", "1", "reduced contact radius", {}}, P{"Pbar", "1", "reduced force F/(pi w R)", {}},
      D{"Delta", "1", "reduced penetration", {}};
  sample<2>(A, {&P, &D}, 0, 150, 50.0, [&](double x) {
    return std::array{an::jkr_force(Es, R, w, x * s.radius) / s.force,
                      an::jkr_penetration(Es, R, w, x * s.radius) / s.penetration};
  });
  return with_axes(std::move(c), {A, P, D}, A.name, P.name, "lin-lin",
                   kRoundOff, 1e-2, "max_abs");
}

Curve maugis_dugdale(double lambda, const std::string& tag) {
  Curve c = base("maugis_dugdale_lambda_" + tag, "force_vs_penetration",
                 "Maugis-Dugdale: force and penetration vs contact radius at lambda = " + tag,
                 "Maugis, J. Colloid Interface Sci. 150, 243 (1992) eqs. 6.17-6.19 with m = c/a, mu = sqrt(m^2-1): "
                 "(lambda A^2/2)[mu + (m^2-2) atan mu] + (4 lambda^2 A/3)[mu atan mu - m + 1] = 1, "
                 "Pbar = A^3 - lambda A^2 [mu + m^2 atan mu], Delta = A^2 - (4/3) lambda A mu");
  c.extra.emplace_back("parameters", "lambda = " + tag + " (lambda = 2 sigma0 (R/(pi w K^2))^(1/3); for exponential "
                                     "adhesion with sigma0 = w/rho, lambda = 2 (9/(16 pi))^(1/3) mu_T ~ 1.127 mu_T)");
  c.extra.emplace_back("units",
                       "reduced (Maugis 1992), K = 4E*/3: A = a/(pi w R^2/K)^(1/3), Pbar = F/(pi w R), "
                       "Delta = delta/(pi^2 w^2 R/K^2)^(1/3), m = c/a (c = outer radius of the cohesive zone)");
  const auto end = an::md_zero_radius_limit(lambda);
  const auto po = an::md_pulloff(lambda);
  c.extra.emplace_back("limits", "A -> 0: Pbar = " + short_num(end.Pbar) + ", Delta = " + short_num(end.Delta) +
                                     "; load-controlled pull-off at A = " + short_num(po.A) + ", Pbar = " +
                                     short_num(po.Pbar));
  c.extra.emplace_back("sampling", "A = k/50, k = 1..150");
  Column A{"A", "1", "reduced contact radius", {}}, m{"m", "1", "c/a", {}}, P{"Pbar", "1", "reduced force F/(pi w R)", {}},
      D{"Delta", "1", "reduced penetration", {}};
  for (int k = 1; k <= 150; ++k) {
    const auto pt = an::md_point(lambda, k / 50.0);
    A.values.push_back(pt.A);
    m.values.push_back(pt.m);
    P.values.push_back(pt.Pbar);
    D.values.push_back(pt.Delta);
  }
  return with_axes(std::move(c), {A, P, D, m}, A.name, P.name, "lin-lin",
                   "root of the Maugis equation for m to 1e-14 relative (GSL Brent), stored with 13 significant "
                      "digits: < 1e-12 relative", 1e-2, "max_abs");
}

Curve johnson_sinusoid(double alpha, const std::string& tag) {
  Curve c = base("johnson_sinusoid_alpha_" + tag, "mean_pressure_vs_half_width",
                 "Johnson (1995) adhesive wavy contact: mean pressure and mean gap vs half-width at alpha = " + tag,
                 "Johnson, Int. J. Solids Struct. 32, 423 (1995): pbar/p* = sin^2(pi a/lambda) - alpha "
                 "sqrt(tan(pi a/lambda)), alpha = sqrt(2 w lambda/E*)/(pi h), p* = pi E* h/lambda; mean gap "
                 "gbar = h [1 - t + (pbar/p*) ln t], t = sin^2(pi a/lambda) (Carbone & Mangialardi, JMPS 52, 1267 "
                 "(2004) eq. 39)");
  c.extra.emplace_back("parameters", "alpha = " + tag + "; profile h(x) = 2h sin^2(pi x/lambda)");
  c.extra.emplace_back("units", "reduced: lengths in the wavelength lambda, pressure in p*, gap in the amplitude h");
  const double Es = 1.0, h = 1.0, L = 1.0;
  const double w = std::pow(alpha * pi * h, 2) * Es / (2 * L);
  const double pstar = an::westergaard_full_contact_pressure(Es, h, L);
  const auto po = an::johnson_pulloff(Es, w, h, L);
  c.extra.emplace_back("branches", "load-controlled pull-off at a/lambda = " + short_num(po.half_width / L) +
                                       ", pbar/p* = " + short_num(po.mean_pressure / pstar) +
                                       "; smaller a is unstable under load control; spontaneous full contact at "
                                       "zero load for alpha > " + short_num(an::johnson_full_contact_alpha()));
  c.extra.emplace_back("sampling", "a/lambda = k/200, k = 1..99");
  Column a{"a_over_lambda", "1", "contact half-width a/lambda", {}}, p{"pbar_over_pstar", "1", "mean pressure pbar/p*", {}},
      g{"mean_gap_over_h", "1", "mean gap / h", {}};
  sample<2>(a, {&p, &g}, 1, 99, 200.0, [&](double x) {
    return std::array{an::johnson_mean_pressure(Es, w, h, L, x * L) / pstar, an::johnson_mean_gap(Es, w, h, L, x * L) / h};
  });
  // mean pressure within 1e-2 p* (the ContactMechanics test suite's bound)
  return with_axes(std::move(c), {a, p, g}, a.name, p.name, "lin-lin",
                   kRoundOff, 1e-2, "max_abs");
}

struct Generator {
  std::string name;
  std::function<Curve()> make;
};

const std::vector<Generator>& generators() {
  static const std::vector<Generator> g = {
      {"hertz_penetration_force", hertz_penetration_force},
      {"hertz_pressure_profile", hertz_pressure_profile},
      {"westergaard_mean_pressure", westergaard_mean_pressure},
      {"westergaard_mean_gap", westergaard_mean_gap},
      {"westergaard_pressure_profile", westergaard_pressure_profile},
      {"jkr_force_penetration", jkr_force_penetration},
      {"maugis_dugdale_lambda_0.3", [] { return maugis_dugdale(0.3, "0.3"); }},
      {"maugis_dugdale_lambda_1", [] { return maugis_dugdale(1.0, "1"); }},
      {"maugis_dugdale_lambda_3", [] { return maugis_dugdale(3.0, "3"); }},
      {"johnson_sinusoid_alpha_0.1", [] { return johnson_sinusoid(0.1, "0.1"); }},
      {"johnson_sinusoid_alpha_0.3", [] { return johnson_sinusoid(0.3, "0.3"); }},
      {"johnson_sinusoid_alpha_0.5", [] { return johnson_sinusoid(0.5, "0.5"); }},
  };
  return g;
}

}  // namespace

std::vector<std::string> analytic_curve_names() {
  std::vector<std::string> n;
  for (const auto& g : generators()) n.push_back(g.name);
  return n;
}

Curve generate(const std::string& name) {
  for (const auto& g : generators())
    if (g.name == name) return g.make();
  std::string known;
  for (const auto& g : generators()) known += (known.empty() ? "" : ", ") + g.name;
  throw std::invalid_argument("unknown reference curve '" + name + "' (known: " + known + ")");
}

std::string analytic_curve_title(const std::string& name) { return generate(name).title; }

}  // namespace cmc::reference
