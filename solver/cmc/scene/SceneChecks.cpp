#include "cmc/scene/SceneChecks.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/scene/Scene.hpp"

#include <cfloat>
#include <cmath>
#include <cstdio>

namespace cmc {

std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

namespace {
const auto num = short_number;
bool outside(double reduced) {
  const double a = std::abs(reduced);
  return !std::isfinite(reduced) || (a != 0.0 && (a < kMinReduced || a > kMaxReduced));
}
const std::string kWindow = "expected a magnitude from " + num(kMinReduced) + " to " + num(kMaxReduced) +
                            " in cmc's reduced units (lengths over [grid] size, pressures over [material] "
                            "contact_modulus), or 0";

// The key whose value sets the heights of the case's surface.
std::string height_key(const SurfaceSpec& sf) {
  switch (sf.kind) {
    case SurfaceKind::Sphere: return "[surface] radius";
    case SurfaceKind::Wavy1d:
    case SurfaceKind::Wavy2d: return "[surface] amplitude";
    case SurfaceKind::SelfAffine: return "[surface] rms_gradient";
    case SurfaceKind::File: return "[surface] path (with height_unit)";
    case SurfaceKind::Flat: break;
  }
  return "[surface] kind";
}
}  // namespace

void check_unit_scales(const Case& c) {
  const double L = c.grid.size_x, E = c.contact_modulus;
  for (const auto& [what, v] : {std::pair{"E* size (energy per area)", E * L}, {"E* size^2 (force)", E * L * L},
                                {"E* size^3 (energy)", E * L * L * L}})
    if (!std::isfinite(v) || v < DBL_MIN)
      throw CaseError(c.file + ": [grid] size = " + num(L) + " m with [material] contact_modulus = " + num(E) +
                      " Pa: the unit " + what + " is " + num(v) + ", beyond a double (expected a finite, normal "
                      "number: a size and a modulus within physical reason)");
}

void require_reduced(const Case& c, const std::string& key, double si, const std::string& unit, double scale,
                     double reduced) {
  if (!outside(reduced)) return;
  throw CaseError(c.file + ": " + key + " = " + num(si) + " " + unit + ", which is " + num(reduced) +
                  " in reduced units (over " + num(scale) + " " + unit + "): " + kWindow);
}

void require_curvature_radius(const Case& c, double radius) {
  if (std::isfinite(radius) && radius > 0.0 && !outside(radius)) return;
  const std::string key = c.interaction.tabor > 0.0 ? "tabor" : "maugis_lambda";
  throw CaseError(c.file + ": [interaction] " + key + ": expected a surface with a radius of curvature to define it, "
                  "but the radius (the sphere's, or the surface's R_c on this grid of " + std::to_string(c.grid.nx) +
                  " x " + std::to_string(c.grid.ny) + " points) is " + num(radius * c.grid.size_x) +
                  " m; give [interaction] range instead, or a grid that resolves the surface's curvature");
}

void require_dugdale_smoothing(const Case& c, double smoothing, double twice_range) {
  if (smoothing < twice_range) return;
  if (c.interaction.smoothing > 0.0)
    throw CaseError(c.file + ": [interaction] smoothing = " + num(smoothing) + " m: expected a width below 2 h0 = " +
                    num(twice_range) + " m (twice the Dugdale range)");
  throw CaseError(c.file + ": [grid] n: the grid is too coarse for this Dugdale law: the least smoothing that keeps its "
                  "points stable, 2 sigma0 dx / (1.2 E*) = " + num(smoothing) + " m, is not below 2 h0 = " +
                  num(twice_range) + " m; expected a finer grid (or give [interaction] smoothing below 2 h0)");
}

void check_surface_numbers(const Case& c, const Scene& s, const char* given_heights) {
  const double L = s.units.length_m;
  require_reduced(c, "[grid] size_y", c.grid.size_y, "m", L, s.grid.ly);
  if (c.surface.kind == SurfaceKind::Sphere) {
    require_reduced(c, "[surface] radius", c.surface.radius, "m", L, s.sphere_radius);
    if (c.surface.center)
      for (double x : *c.surface.center) require_reduced(c, "[surface] center", x, "m", L, x / L);
  }
  if (c.surface.kind == SurfaceKind::Wavy1d || c.surface.kind == SurfaceKind::Wavy2d) {
    require_reduced(c, "[surface] amplitude", c.surface.amplitude, "m", L, s.wave_amplitude);
    require_reduced(c, "[surface] wavelength", c.surface.wavelength, "m", L, s.wavelength);
  }
  // The heights relative to their mean, on every rank's slab.
  bool bad = false;
  for (double h : s.topography.heights) bad |= !(std::abs(h - s.mean_height) <= kMaxReduced);  // NaN too
  if (any_rank(bad))
    throw CaseError(c.file + ": " + (given_heights ? std::string(given_heights) : height_key(c.surface)) +
                    ": the surface's heights are not finite or beyond " +
                    num(kMaxReduced) + " grid sizes (" + s.topography.description + "); " + kWindow);
}

void check_load_numbers(const Case& c, const Scene& s) {
  const double L = s.units.length_m, E = s.units.pressure_pa;
  const LoadingSpec& l = c.loading;
  const bool force = l.control == LoadControl::Force, pressure = l.control == LoadControl::MeanPressure;
  const std::string unit = force ? "N" : pressure ? "Pa" : "m";
  const double scale = force ? E * L * L : pressure ? E : L;
  for (std::size_t k = 0; k < l.values.size() + l.unloading.size(); ++k) {
    const bool up = k < l.values.size();
    const double v = up ? l.values[k] : l.unloading[k - l.values.size()];
    const std::string key = std::string(up ? "[loading] values[" : "[loading] unloading[") +
                            std::to_string(up ? k : k - l.values.size()) + "]";
    require_reduced(c, key, v, unit, scale, v / scale);
    require_reduced(c, key, v, unit, scale, s.targets[k].value);
  }
  require_reduced(c, "[loading] jump_pressure_floor", l.jump_pressure_floor, "Pa", E, l.jump_pressure_floor / E);
  const double threshold = c.observables.contact_gap_threshold;
  require_reduced(c, "[observables] contact_gap_threshold", threshold, "m", L, threshold / L);
}

}  // namespace cmc
