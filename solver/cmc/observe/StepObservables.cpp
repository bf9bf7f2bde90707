#include "cmc/observe/StepObservables.hpp"

namespace cmc {

StepObservables measure_step(const Grid& g, const ContactState& st, const ContactRule& rule,
                             const ObservablesSpec& spec) {
  StepObservables o;
  const Mask mask = contact_mask(st.gap, rule);
  // Periodic 4-connected patches of the contact mask, labelled once for the scalars and
  // the patch-size distribution.
  const Patches patches = label_patches(g, mask, Connectivity::Four);
  o.scalars = scalar_observables(g, st.gap, st.pressure, rule, mask, patches, &st.displacement);
  // Gap distribution (log bins: the challenge asks for log axes where asymptotics matter).
  if (o.scalars.max_gap > 0.0) o.gap_histogram = gap_distribution(st.gap, spec.gap_bins_per_decade);
  // Stress distribution: linear in p, the p == 0 peak left out (its weight is 1 - a_r).
  if (o.scalars.max_pressure > o.scalars.min_pressure)
    o.stress_histogram = stress_distribution(st.pressure, spec.stress_bins);
  if (patches.count() > 0) o.patch_histogram = patch_size_distribution(g, patches, spec.patch_bins_per_decade);
  // Stress spectrum C_p(q) with ∫ d²q C = variance of p (isotropic PSD).
  Fourier f(g);
  o.stress_spectrum = radial_spectrum(g, f, st.pressure);
  if (g.ny > 1) {
    o.gap_section = cross_section_x(g, st.gap, spec.cross_section_x);
    o.pressure_section = cross_section_x(g, st.pressure, spec.cross_section_x);
  }
  return o;
}

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
// NAME_edges and NAME_density of a histogram of a quantity in `unit`, scaled by `scale`.
void add_histogram(ObservablesRecord& r, const std::string& name, const Histogram& h, double scale,
                   const std::string& unit) {
  r.arrays[name + "_edges"] = {edges(h.bins, scale), unit};
  r.arrays[name + "_density"] = {scaled(h.density, 1.0 / scale), "1/" + unit};
}
}  // namespace

ObservablesRecord to_record(const StepObservables& o, const Units& u) {
  const double L = u.length_m, P = u.pressure_pa;
  const ScalarObservables& sc = o.scalars;
  ObservablesRecord r;
  r.scalars = {{"contact_fraction", sc.contact_fraction},
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
  if (o.gap_histogram) add_histogram(r, "gap_hist", *o.gap_histogram, L, "m");
  if (o.stress_histogram) add_histogram(r, "stress_hist", *o.stress_histogram, P, "Pa");
  if (o.patch_histogram) {
    add_histogram(r, "patch_area", *o.patch_histogram, L * L, "m^2");
    const auto& c = o.patch_histogram->counts;
    r.arrays["patch_area_counts"] = {std::vector<double>(c.begin(), c.end()), "1"};
  }
  r.arrays["stress_spectrum_q"] = {scaled(o.stress_spectrum.q, 1.0 / L), "1/m"};
  r.arrays["stress_spectrum_C"] = {scaled(o.stress_spectrum.psd, P * P * L * L), "Pa^2 m^2"};
  if (o.gap_section) {
    r.arrays["cross_section_y"] = {scaled(o.gap_section->y, L), "m"};
    r.arrays["cross_section_gap"] = {scaled(o.gap_section->value, L), "m"};
    r.arrays["cross_section_pressure"] = {scaled(o.pressure_section->value, P), "Pa"};
  }
  return r;
}

}  // namespace cmc
