#include "cmc/scene/Scene.hpp"

#include "cmc/surface/SelfAffine.hpp"
#include "cmc/surface/SurfaceIO.hpp"
#include "cmc/surface/SurfaceStats.hpp"

#include <filesystem>

namespace cmc {

namespace {

// Heights from a file, in reduced units, on the case's grid (Fourier-interpolated to a
// finer grid when the file is coarser; never down-sampled).
Topography load_surface_file(const Case& c, const Grid& grid) {
  const auto& sf = c.surface;
  std::filesystem::path path = sf.path;
  if (path.is_relative()) path = std::filesystem::path(c.file).parent_path() / path;
  const double scale = sf.height_unit / c.grid.size_x;  // file units -> reduced lengths
  HeightMap map;
  try {
    if (sf.format == "challenge_hdf5") map = read_challenge_hdf5(path);
    else if (sf.format == "challenge_ascii") map = read_challenge_ascii(path);
    else if (sf.format == "fourier") map = read_fourier_heights(path, grid.nx);
    else if (sf.format == "hdf5") map = read_hdf5_heights(path, sf.dataset, grid.lx, grid.ly);
    else map = read_ascii_heights(path, grid.lx, grid.ly);
  } catch (const std::exception& e) {
    throw CaseError(c.file + ": [surface] path: " + e.what());
  }
  for (auto& h : map.heights) h *= scale;
  if (map.grid.nx != grid.nx || map.grid.ny != grid.ny) {
    if (map.grid.nx > grid.nx || map.grid.ny > grid.ny || grid.nx % map.grid.nx || grid.ny % map.grid.ny)
      throw CaseError(c.file + ": [grid] n: the surface file " + path.string() + " has " + std::to_string(map.grid.nx) +
                      " x " + std::to_string(map.grid.ny) + " points; expected a grid equal to it or a multiple of it "
                      "(cmc interpolates band-limited surfaces to finer grids but never down-samples)");
    map = fourier_interpolate(map, grid.nx, grid.ny);
  }
  map.grid.lx = grid.lx, map.grid.ly = grid.ly;
  return {grid, std::move(map.heights), sf.format + " file " + path.string()};
}

}  // namespace

Scene build_scene(const Case& c) {
  Scene s;
  s.units.length_m = c.grid.size_x;
  s.units.pressure_pa = c.contact_modulus;
  const Units& u = s.units;
  s.grid = Grid{c.grid.nx, c.grid.ny, 1.0, u.length(c.grid.size_y)};
  const auto& sf = c.surface;
  if (sf.kind == "sphere") {
    s.sphere_radius = u.length(sf.radius);
    s.apex_x = sf.center ? u.length((*sf.center)[0]) : 0.5 * s.grid.lx;
    s.apex_y = sf.center ? u.length((*sf.center)[1]) : 0.5 * s.grid.ly;
    s.topography = sphere(s.grid, s.sphere_radius, s.apex_x, s.apex_y, c.grid.periodic);
  } else if (sf.kind == "wavy1d" || sf.kind == "wavy2d") {
    s.wave_amplitude = u.length(sf.amplitude), s.wavelength = u.length(sf.wavelength);
    s.topography = (sf.kind == "wavy1d" ? wavy1d : wavy2d)(s.grid, s.wave_amplitude, s.wavelength);
  } else if (sf.kind == "self_affine") {
    SelfAffineSpec spec;
    spec.hurst = sf.hurst;
    spec.rolloff_wavelength = u.length(sf.rolloff_wavelength);
    spec.cutoff_wavelength = u.length(sf.cutoff_wavelength);
    spec.rms_gradient = sf.rms_gradient;
    spec.seed = (unsigned long)sf.seed;
    SelfAffineSurface surf = generate_self_affine(spec, s.grid);
    s.topography = {s.grid, std::move(surf.map.heights),
                    "self-affine, H = " + std::to_string(sf.hurst) + ", seed " + std::to_string(sf.seed)};
    if (surf.low_passed())
      s.warnings.push_back("the grid holds " + std::to_string(surf.modes_total - surf.modes_dropped) + " of the " +
                           std::to_string(surf.modes_total) + " Fourier modes of the surface: it is low-passed at the grid's "
                           "Nyquist wavelength (use grid.n >= " + std::to_string(self_affine_modes(spec).full_grid()) +
                           " for the full spectrum)");
    s.surface_facts.push_back({"modes_dropped", double(surf.modes_dropped)});
  } else if (sf.kind == "file") {
    s.topography = load_surface_file(c, s.grid);
  } else {
    s.topography = flat(s.grid);
  }
  if (sf.kind == "self_affine" || sf.kind == "file") {
    const SurfaceStatistics st = surface_statistics(s.grid, s.topography.heights);
    const double L = u.length_m;
    s.surface_facts.insert(s.surface_facts.end(), {{"mean_height", st.mean * L},
                                                   {"max_height", st.max * L},
                                                   {"rms_height", st.rms_height * L},
                                                   {"rms_gradient", st.rms_gradient},
                                                   {"curvature_radius", st.curvature_radius * L}});
    if (sf.kind == "self_affine") s.surface_facts.push_back({"dx_over_cutoff_wavelength", s.grid.dx() / u.length(sf.cutoff_wavelength)});
  }
  s.mean_height = Grid::mean(s.topography.heights);
  // ---- interaction (reduced: w in E* L, ranges in L)
  const auto& in = c.interaction;
  if (in.kind != "hard_wall") {
    const double w = u.energy_per_area(in.work_of_adhesion);
    // The radius behind mu_T / lambda: the sphere's, or the rough surface's R_c.
    double R = s.sphere_radius;
    for (const auto& [k, v] : s.surface_facts)
      if (k == "curvature_radius") R = u.length(v);
    if (in.kind == "exponential") {
      const double rho = in.tabor > 0.0 ? exponential_range_from_tabor(1.0, R, w, in.tabor) : u.length(in.range);
      s.interaction = ExponentialAdhesion(w, rho);
    } else {
      const double sigma0 = in.maugis_lambda > 0.0 ? dugdale_stress_from_lambda(1.0, R, w, in.maugis_lambda)
                                                   : w / u.length(in.range);
      const double eps = in.smoothing > 0.0 ? u.length(in.smoothing) : dugdale_min_smoothing(1.0, sigma0, s.grid.dx());
      s.interaction = DugdaleAdhesion(w, w / sigma0, eps);
    }
    const double range = interaction_range(s.interaction);
    s.surface_facts.push_back({"interaction_range", u.to_m(range)});
    s.surface_facts.push_back({"dx_over_range", s.grid.dx() / range});
    // w dx / (E* rho²) above ~1 makes single grid points bistable (shared/notes).
    s.surface_facts.push_back({"bistability_number", w * s.grid.dx() / (range * range)});
    if (R > 0.0) s.surface_facts.push_back({"tabor_parameter", tabor_parameter(1.0, R, w, range)});
  }

  s.observables = c.observables;
  s.observables.cross_section_x = u.length(c.observables.cross_section_x);
  s.observables.contact_gap_threshold = u.length(c.observables.contact_gap_threshold);
  s.half_space = make_half_space(s.grid, 1.0, c.grid.periodic);  // E* = 1 in reduced units

  const std::string& ctl = c.loading.control;
  std::vector<double> values = c.loading.values;
  values.insert(values.end(), c.loading.unloading.begin(), c.loading.unloading.end());
  s.unloading_from = c.loading.values.size();
  for (double v : values) {
    if (ctl == "force") s.targets.push_back({Control::MeanPressure, u.force(v) / s.grid.area()});
    else if (ctl == "mean_pressure") s.targets.push_back({Control::MeanPressure, u.pressure(v)});
    else if (ctl == "penetration") s.targets.push_back({Control::Penetration, u.length(v)});
    else s.targets.push_back({Control::Penetration, s.mean_height - u.length(v)});  // periodic: <g> = <h> − δ
  }
  return s;
}

}  // namespace cmc
