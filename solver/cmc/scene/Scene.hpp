// Case (SI, validated) -> Scene (reduced units): grid, topography, half-space,
// interaction and the load steps. The only place where case values are converted.
#pragma once

#include "cmc/input/Case.hpp"
#include "cmc/elastic/HalfSpace.hpp"
#include "cmc/contact/ContactRule.hpp"
#include "cmc/contact/Interaction.hpp"
#include "cmc/contact/Solver.hpp"
#include "cmc/surface/SelfAffine.hpp"
#include "cmc/surface/Topography.hpp"
#include "cmc/input/Units.hpp"

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace cmc {

// Facts about the surface and the resolution, in SI, for summary.json ("surface_facts")
// and `cmc surface`. Each is present only where it applies.
struct SurfaceFacts {
  std::optional<double> modes_dropped;  // self-affine: Fourier modes beyond the grid's Nyquist
  // Rough surfaces (self-affine or from a file): statistics of the heights.
  std::optional<double> mean_height, max_height, rms_height;  // m
  std::optional<double> rms_gradient;
  std::optional<double> curvature_radius;           // m: R_c = 1/(rms line-scan curvature)
  std::optional<double> dx_over_cutoff_wavelength;  // self-affine
  // Adhesion: the range, the resolution of it, and single-point bistability.
  std::optional<double> interaction_range;   // m: the range the solver uses
  std::optional<double> specified_range;     // m: the case's range, where coarse-graining changed it
  std::optional<double> law_head;            // m: the shape coarse-graining's linear head g1, where it has one
  std::optional<double> dx_over_range;
  std::optional<double> bistability_number;  // w dx / (E* range²)
  std::optional<double> tabor_parameter;     // with a sphere or R_c
};
// The facts that are present, named as in summary.json.
std::vector<std::pair<std::string, double>> surface_fact_entries(const SurfaceFacts& f);

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
  // What "in contact" means in this run (the interaction's noise cut, the case's
  // contact gap threshold, reduced): used by the driver, load path and observables.
  ContactRule contact_rule;
  SurfaceFacts surface_facts;
  std::vector<std::string> warnings;
};

Scene build_scene(const Case& c);
// The same with the indenter's heights given in place of the case's [surface] (metres, on
// the case's grid: nx x ny values, x fastest), e.g. an array from Python (cmc.solve); they
// get the statistics of a surface from a file. CaseError naming `heights` when the count
// does not fit the grid or a value is not finite.
Scene build_scene(const Case& c, std::span<const double> heights_m);

// The generator's spec of a case's self-affine surface (lengths in units of the grid size).
SelfAffineSpec self_affine_spec(const SurfaceSpec& sf, const Units& u);

}  // namespace cmc
