// The documented default of every key (Case.hpp, case_defaults): what cases/README.md's
// tables say, from the spec structs' own defaults.
#include "cmc/input/CaseSection.hpp"

namespace cmc {

using case_parsing::number_text;


namespace {
std::string quoted_word(std::string_view word) {
  std::string q(1, '"');
  q.append(word).push_back('"');
  return q;
}
}  // namespace

std::vector<DocumentedDefault> case_defaults() {
  const GridSpec g;
  const SurfaceSpec sf;
  const InteractionSpec in;
  const LoadingSpec l;
  const SolverSpec sv;
  const ObservablesSpec o;
  const Case c;
  const auto n = [](double v) { return number_text(v); };
  const auto b = [](bool v) { return std::string(v ? "true" : "false"); };
  const std::string req = "required";
  return {
      {"case", "name", req},
      {"case", "description", quoted_word(c.description)},
      {"grid", "n", "—"},
      {"grid", "nx", "—"},
      {"grid", "ny", "—"},
      {"grid", "size", req},
      {"grid", "size_y", "size"},
      {"grid", "boundary", quoted_word(g.periodic ? "periodic" : "free")},
      {"grid", "backend", quoted_word(g.backend)},
      {"material", "contact_modulus", req},
      {"surface", "kind", req},
      {"surface", "radius", "required for sphere"},
      {"surface", "center", "box centre"},
      {"surface", "amplitude", "required for wavy*"},
      {"surface", "wavelength", "grid.size"},
      {"surface", "hurst", n(sf.hurst)},
      {"surface", "rolloff_wavelength", n(SurfaceSpec::kRolloffFraction) + " size"},
      {"surface", "cutoff_wavelength", n(SurfaceSpec::kCutoffFraction) + " size"},
      {"surface", "rms_gradient", n(sf.rms_gradient)},
      {"surface", "seed", n(double(sf.seed))},
      {"surface", "path", "required for file"},
      {"surface", "format", "required for file"},
      {"surface", "dataset", quoted_word(sf.dataset)},
      {"surface", "height_unit", "size for challenge formats, else 1"},
      {"interaction", "kind", quoted_word(kind_name(in.kind))},
      {"interaction", "work_of_adhesion", "required for adhesion"},
      {"interaction", "range", "one of three"},
      {"interaction", "tabor", "one of three"},
      {"interaction", "maugis_lambda", "one of three"},
      {"interaction", "smoothing", n(in.smoothing)},
      {"interaction", "coarse_graining", quoted_word(kind_name(in.coarse_graining))},
      {"loading", "control", req},
      {"loading", "values", req},
      {"loading", "unloading", "[]"},
      {"loading", "max_halvings", n(l.max_halvings)},
      {"loading", "jump_fraction", n(l.jump_fraction)},
      {"loading", "jump_pressure_floor", n(l.jump_pressure_floor)},
      {"loading", "refine_pulloff", n(l.refine_pulloff)},
      {"solver", "kind", quoted_word(kind_name(sv.kind))},
      {"solver", "tolerance",
       n(SolverSpec::kPolonskyKeerTolerance) + " PK, " + n(SolverSpec::kAdhesiveTolerance) + " adhesive"},
      {"solver", "max_iterations", n(sv.max_iterations)},
      {"solver", "recompute_every", n(sv.recompute_every)},
      {"solver", "tension_tolerance", n(sv.tension_tolerance)},
      {"solver", "max_outer_steps", n(sv.max_outer_steps)},
      {"solver", "max_seconds", n(sv.max_seconds)},
      {"solver", "precondition", b(sv.precondition)},
      {"output", "fields", b(c.write_fields)},
      {"observables", "enabled", b(o.enabled)},
      {"observables", "cross_section_x", n(ObservablesSpec::kCrossSectionFraction) + " size"},
      {"observables", "stress_bins", n(o.stress_bins)},
      {"observables", "gap_bins_per_decade", n(o.gap_bins_per_decade)},
      {"observables", "patch_bins_per_decade", n(o.patch_bins_per_decade)},
      {"observables", "contact_gap_threshold", n(o.contact_gap_threshold)},
  };
}

}  // namespace cmc
