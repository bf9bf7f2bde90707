#include "cmc/observe/StepObservables.hpp"

#include <cmath>
#include <variant>

namespace cmc {

namespace {
std::vector<double> edges(const Bins& b, double scale) {
  std::vector<double> e(b.n + 1);
  for (int i = 0; i <= b.n; ++i) e[i] = b.edge(i) * scale;
  return e;
}
std::vector<double> scaled(const std::vector<double>& v, double scale) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = v[i] * scale;
  return out;
}
}  // namespace

StepObservables measure_step(const Scene& s, const ContactState& st) {
  const Units& u = s.units;
  const Grid& g = s.grid;
  const auto& spec = s.observables;
  StepObservables o;
  // Hard wall: contact where p > 0. Adhesion: contact where the gap is closed (the
  // adhesive solver keeps contact points at g = 0 exactly), or below the threshold.
  const bool adhesive = !std::holds_alternative<HardWall>(s.interaction);
  const ContactRule rule = spec.contact_gap_threshold > 0.0 || adhesive ? ContactRule::gap_below(spec.contact_gap_threshold)
                                                                       : ContactRule::repulsive();
  ScalarObservables sc = scalar_observables(g, st.gap, st.pressure, rule, Connectivity::Four, &st.displacement);
  if (adhesive) {
    // The adhesive solver's pressure is converged to a residual, not zero where the
    // interaction vanishes: count as repulsive / attractive only stresses beyond 1e-3 of
    // the peak tension w/rho (below that they are solver noise, not contact).
    const double cut = 1e-3 * peak_tension(s.interaction);
    double rep = 0.0, att = 0.0;
    for (double p : st.pressure) rep += p > cut ? 1.0 : 0.0, att += p < -cut ? 1.0 : 0.0;
    double v[2] = {rep, att};
    Grid::allreduce_sum(v);
    sc.repulsive_fraction = v[0] / double(g.size());
    sc.attractive_fraction = v[1] / double(g.size());
  }
  const double L = u.length_m, P = u.pressure_pa;
  o.scalars = {{"contact_fraction", sc.contact_fraction},
               {"contact_fraction_corrected", sc.contact_fraction_corrected},
               {"repulsive_fraction", sc.repulsive_fraction},
               {"attractive_fraction", sc.attractive_fraction},
               {"mean_gap", sc.mean_gap * L},
               {"mean_pressure", sc.mean_pressure * P},
               {"mean_displacement", sc.mean_displacement * L},
               {"n_patches", double(sc.n_patches)},
               {"largest_patch_area", sc.largest_patch_area * L * L},
               {"mean_patch_area", sc.mean_patch_area * L * L},
               {"contact_perimeter", sc.contact_perimeter / L},
               {"max_pressure", sc.max_pressure * P},
               {"min_pressure", sc.min_pressure * P},
               {"max_gap", sc.max_gap * L}};

  // Gap distribution (log bins: the challenge asks for log axes where asymptotics matter).
  if (sc.max_gap > 0.0) {
    const Histogram h = gap_distribution(st.gap, spec.gap_bins_per_decade);
    o.arrays["gap_hist_edges"] = {edges(h.bins, L), "m"};
    o.arrays["gap_hist_density"] = {scaled(h.density, 1.0 / L), "1/m"};
  }
  // Stress distribution: linear in p, the p == 0 peak left out (its weight is 1 - a_r).
  if (sc.max_pressure > sc.min_pressure) {
    const Histogram h = stress_distribution(st.pressure, spec.stress_bins);
    o.arrays["stress_hist_edges"] = {edges(h.bins, P), "Pa"};
    o.arrays["stress_hist_density"] = {scaled(h.density, 1.0 / P), "1/Pa"};
  }
  // Patch-size distribution (periodic 4-connected patches of the contact mask).
  const Patches patches = label_patches(g, contact_mask(st.gap, st.pressure, rule));
  if (patches.count() > 0) {
    const Histogram h = patch_size_distribution(g, patches, spec.patch_bins_per_decade);
    o.arrays["patch_area_edges"] = {edges(h.bins, L * L), "m^2"};
    o.arrays["patch_area_density"] = {scaled(h.density, 1.0 / (L * L)), "1/m^2"};
    o.arrays["patch_area_counts"] = {std::vector<double>(h.counts.begin(), h.counts.end()), "1"};
  }
  // Stress spectrum C_p(q) with ∫ d²q C = variance of p (isotropic PSD).
  {
    Fourier f(g.nx, g.ny);
    const RadialSpectrum r = radial_spectrum(g, f, st.pressure);
    o.arrays["stress_spectrum_q"] = {scaled(r.q, 1.0 / L), "1/m"};
    o.arrays["stress_spectrum_C"] = {scaled(r.psd, P * P * L * L), "Pa^2 m^2"};
  }
  // Cross-section at x = x0.
  if (g.ny > 1) {
    const Profile pg = cross_section_x(g, st.gap, spec.cross_section_x);
    const Profile pp = cross_section_x(g, st.pressure, spec.cross_section_x);
    o.arrays["cross_section_y"] = {scaled(pg.y, L), "m"};
    o.arrays["cross_section_gap"] = {scaled(pg.value, L), "m"};
    o.arrays["cross_section_pressure"] = {scaled(pp.value, P), "Pa"};
  }
  return o;
}

}  // namespace cmc
