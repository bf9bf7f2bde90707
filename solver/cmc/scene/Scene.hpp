// Case (SI, validated) -> Scene (reduced units): grid, topography, half-space,
// interaction and the load steps. The only place where case values are converted.
#pragma once

#include "cmc/input/Case.hpp"
#include "cmc/elastic/HalfSpace.hpp"
#include "cmc/contact/Interaction.hpp"
#include "cmc/contact/Solver.hpp"
#include "cmc/surface/Topography.hpp"
#include "cmc/input/Units.hpp"

#include <memory>
#include <vector>

namespace cmc {

struct Scene {
  Units units;
  Grid grid;
  Topography topography;
  std::unique_ptr<HalfSpace> half_space;
  Interaction interaction;       // reduced units
  std::vector<Target> targets;  // one per load step, reduced
  std::size_t unloading_from = 0;  // targets from this index on are on the unloading branch
  double mean_height = 0.0;     // <h>, reduced
  // Shape parameters of analytic surfaces (reduced), for the validation harness.
  double sphere_radius = 0.0, apex_x = 0.0, apex_y = 0.0;
  double wave_amplitude = 0.0, wavelength = 0.0;
  // Observables to compute per step (lengths reduced).
  ObservablesSpec observables;
  // Facts about the surface and the resolution for summary.json, in SI
  // (e.g. rms_height, curvature_radius, dx_over_cutoff_wavelength), and warnings.
  std::vector<std::pair<std::string, double>> surface_facts;
  std::vector<std::string> warnings;
};

Scene build_scene(const Case& c);

}  // namespace cmc
