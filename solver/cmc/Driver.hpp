// Runs a scene's load steps with the case's solver, one after the other, each warm
// started from the previous one. Knows algorithms, not files: the caller decides
// what to do with each solved step (the Writer saves it).
#pragma once

#include "cmc/Scene.hpp"
#include "cmc/StepObservables.hpp"

#include <optional>

#include <functional>
#include <string>
#include <vector>

namespace cmc {

// One load step in SI units, as written to summary.json.
struct StepRecord {
  int index = 0;
  std::string branch = "loading";
  double mean_pressure = 0.0;    // Pa
  double force = 0.0;            // N (mean pressure x nominal area)
  double penetration = 0.0;      // m, rigid-body approach δ
  double mean_gap = 0.0;         // m
  double contact_fraction = 0.0; // fraction of grid points carrying pressure
  double elastic_energy = 0.0;   // J
  SolveResult result;
  std::optional<StepObservables> observables;  // when the case asks for them
};

struct RunSummary {
  std::string status = "converged";  // converged | not_converged | failed
  std::string message;
  std::vector<StepRecord> steps;
  double wall_s = 0.0;
  double fft_pairs = 0.0;
};

using StepCallback = std::function<void(const StepRecord&, const ContactState&)>;

// `done`: steps already finished by an interrupted run (skipped, kept in the summary);
// `warm`: the state to warm-start the next step from.
RunSummary run_scene(const Case& c, Scene& s, const StepCallback& on_step, const Progress& progress = {},
                     const std::vector<StepRecord>* done = nullptr, const ContactState* warm = nullptr);

}  // namespace cmc
