// The challenge's observables of one solved load step, in SI, ready for the Writer:
// scalars for summary.json and the distributions, spectrum and cross-section for
// result.h5 (group step_NNNN/observables). Computed from the fields with the pure
// functions of Observables.hpp.
#pragma once

#include "cmc/observe/Observables.hpp"
#include "cmc/scene/Scene.hpp"

#include <map>
#include <string>
#include <vector>

namespace cmc {

struct StepObservables {
  // SI scalars (summary.json "observables"): contact_fraction, contact_fraction_corrected,
  // repulsive_fraction, attractive_fraction, mean_gap (m), mean_pressure (Pa),
  // n_patches, largest_patch_area (m^2), mean_patch_area (m^2), contact_perimeter (1/m),
  // max_pressure (Pa), min_pressure (Pa), max_gap (m).
  std::vector<std::pair<std::string, double>> scalars;
  // SI arrays (result.h5), each with its unit.
  struct Array {
    std::vector<double> values;
    std::string unit;
  };
  std::map<std::string, Array> arrays;
};

StepObservables measure_step(const Scene& s, const ContactState& st);

}  // namespace cmc
