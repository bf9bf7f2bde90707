#include "Profiles.hpp"

#include "cmc/analytic/Analytic.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace cmc {

namespace an = cmc::analytic;

namespace {

double min_image(double d, double l) { return d - l * std::round(d / l); }

void row(std::string& out, std::initializer_list<double> values) {
  char buf[32];
  bool first = true;
  for (double v : values) {
    std::snprintf(buf, sizeof buf, "%s%.9e", first ? "" : ",", v == 0.0 ? 0.0 : v);
    out += buf, first = false;
  }
  out += '\n';
}

// Sphere: every grid point within 3 Hertz radii of the apex, per step with F > 0.
// Distances from the apex as in Validate.cpp's hertz_error (periodic: nearest image).
std::string hertz_profiles(bool periodic, const Scene& s, const std::vector<ContactState>& states) {
  std::string out =
      "# cmc validate: solved pressure and gap of a sphere against Hertz, per grid point within r < 3a\n"
      "# source: Hertz (1882); Johnson, Contact Mechanics (1985) eqs. 4.22-4.23 (p), 3.42b (gap outside r = a)\n"
      "# a, p0, delta = a^2/R from the step's force (analytic::hertz_from_force); r from the apex"
      + std::string(periodic ? " (nearest periodic image)" : "") + "\n"
      "step,a_over_dx,r_over_a,p_over_p0,p_hertz_over_p0,p_error_over_p0,gap_over_delta,gap_hertz_over_delta\n";
  const Grid& g = s.grid;
  const double R = s.sphere_radius;
  for (std::size_t k = 0; k < states.size(); ++k) {
    const ContactState& st = states[k];
    const double F = st.mean_pressure * g.area();
    if (!(F > 0)) continue;
    const auto H = an::hertz_from_force(1.0, R, F);
    const double delta = H.radius * H.radius / R;
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix) {
        double dx = ix * g.dx() - s.apex_x, dy = iy * g.dy() - s.apex_y;
        if (periodic) dx = min_image(dx, g.lx), dy = min_image(dy, g.ly);
        const double r = std::hypot(dx, dy);
        if (r >= 3 * H.radius) continue;
        const std::size_t i = std::size_t(iy) * g.nx + ix;
        const double p = st.pressure[i] / H.max_pressure;
        const double ph = an::hertz_pressure(1.0, R, H.radius, r) / H.max_pressure;
        row(out, {double(k), H.radius / g.dx(), r / H.radius, p, ph, p - ph, st.gap[i] / delta,
                  an::hertz_gap(R, H.radius, r) / delta});
      }
  }
  return out;
}

// Wavy 1-D surface: every grid point of row 0, x from the contact centre (x = 0,
// periodic), per step with 0 < pbar < p*; the step's pbar/p* and mean gap/h repeated
// on its rows.
std::string westergaard_profiles(const Scene& s, const std::vector<ContactState>& states) {
  std::string out =
      "# cmc validate: solved pressure of a wavy surface against Westergaard, row 0, x from the contact centre\n"
      "# source: Westergaard (1939); Johnson, Contact Mechanics (1985) 13.2; mean gap: analytic::westergaard_mean_gap\n"
      "# p* = pi E* h / lambda (full-contact pressure); a from pbar (analytic::westergaard_half_width)\n"
      "step,pbar_over_pstar,mean_gap_over_h,mean_gap_westergaard_over_h,x_over_lambda,p_over_pstar,"
      "p_westergaard_over_pstar,p_error_over_pstar\n";
  const Grid& g = s.grid;
  const double h = s.wave_amplitude, lambda = s.wavelength;
  const double pstar = an::westergaard_full_contact_pressure(1.0, h, lambda);
  for (std::size_t k = 0; k < states.size(); ++k) {
    const ContactState& st = states[k];
    const double pbar = st.mean_pressure;
    if (!(pbar > 0 && pbar < pstar)) continue;
    const double a = an::westergaard_half_width(1.0, h, lambda, pbar);
    const double gap = Grid::mean(st.gap) / h, gap_w = an::westergaard_mean_gap(1.0, h, lambda, pbar) / h;
    for (int ix = 0; ix < g.nx; ++ix) {
      const double x = min_image(ix * g.dx(), lambda);
      const double p = st.pressure[std::size_t(ix)] / pstar;
      const double pw = an::westergaard_pressure(1.0, h, lambda, a, x) / pstar;
      row(out, {double(k), pbar / pstar, gap, gap_w, x / lambda, p, pw, p - pw});
    }
  }
  return out;
}

}  // namespace

bool has_profiles(ValidationReference reference) {
  using R = ValidationReference;
  return reference == R::Hertz || reference == R::HertzPeriodic || reference == R::Westergaard;
}

std::string profiles_csv(ValidationReference reference, const Scene& s, const std::vector<ContactState>& states) {
  using R = ValidationReference;
  switch (reference) {
    case R::Hertz:
    case R::HertzPeriodic:
      return hertz_profiles(reference == R::HertzPeriodic, s, states);
    case R::Westergaard:
      return westergaard_profiles(s, states);
    default:
      throw std::invalid_argument("profiles: reference '" + std::string(kind_name(reference)) +
                                  "' has no field-wise closed form");
  }
}

}  // namespace cmc
