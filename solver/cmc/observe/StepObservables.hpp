// The challenge's observables of one solved load step, in one direction:
//
//   solved state --measure_step--> StepObservables (reduced units)
//                --to_record-----> ObservablesRecord (SI, named as in the outputs) --> Writer
//
// measure_step computes everything from the fields with the pure functions of
// Observables.hpp, under the run's ContactRule; to_record is the only place where
// observables meet SI.
#pragma once

#include "cmc/contact/Solver.hpp"
#include "cmc/input/Case.hpp"
#include "cmc/input/Units.hpp"
#include "cmc/observe/Observables.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cmc {

// Reduced units (lengths in L, pressures in E*).
struct StepObservables {
  ScalarObservables scalars;
  std::optional<Histogram> gap_histogram;     // absent when no gap is open
  std::optional<Histogram> stress_histogram;  // absent when the pressure is uniform
  std::optional<Histogram> patch_histogram;   // absent without contact patches
  RadialSpectrum stress_spectrum;
  std::optional<Profile> gap_section, pressure_section;  // along x = x0; absent for ny == 1
};

// `spec` holds reduced lengths (Scene::observables).
StepObservables measure_step(const Grid& grid, const ContactState& state, const ContactRule& rule,
                             const ObservablesSpec& spec);

// SI, as written: scalars to summary.json (steps[i].observables), arrays to result.h5
// (step_NNNN/observables/NAME with a "units" attribute).
struct ObservablesRecord {
  std::vector<std::pair<std::string, double>> scalars;
  struct Array {
    std::vector<double> values;
    std::string unit;
  };
  std::map<std::string, Array> arrays;
};

ObservablesRecord to_record(const StepObservables& o, const Units& units);

}  // namespace cmc
