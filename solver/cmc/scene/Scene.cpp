#include "cmc/scene/Scene.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/scene/SceneChecks.hpp"
#include "cmc/surface/SelfAffine.hpp"
#include "cmc/surface/SurfaceIO.hpp"
#include "cmc/surface/SurfaceStats.hpp"

#include <algorithm>
#include <cmath>
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
  // No file map is larger than the case's grid: the readers check a file's declared
  // shape against it before they allocate anything.
  const MapLimit limit{grid.nx, grid.ny};
  try {
    switch (sf.format) {
      case SurfaceFormat::ChallengeHdf5: map = read_challenge_hdf5(path, limit); break;
      case SurfaceFormat::ChallengeAscii: map = read_challenge_ascii(path, 1.0, limit); break;
      case SurfaceFormat::Fourier: map = read_fourier_heights(path, grid.nx); break;
      case SurfaceFormat::Hdf5: map = read_hdf5_heights(path, sf.dataset, grid.lx, grid.ly, 1.0, false, limit); break;
      case SurfaceFormat::Ascii: map = read_ascii_heights(path, grid.lx, grid.ly, 1.0, false, limit); break;
    }
  } catch (const SurfaceShapeError& e) {
    throw CaseError(c.file + ": [grid] n: " + e.what() + " (cmc interpolates band-limited surfaces to finer grids "
                    "but never down-samples)");
  } catch (const std::exception& e) {
    throw CaseError(c.file + ": [surface] path: " + e.what());
  }
  for (auto& h : map.heights) h *= scale;
  if (map.grid.nx != grid.nx || map.grid.ny != grid.ny) {
    // A coarser map is interpolated: it must divide the grid by the same factor along x
    // and y (a 1-D line only along x). Anything else, e.g. an ASCII file cut short at
    // the end of a row (fewer rows than the grid has), is refused, not resampled.
    const std::string has = "the surface file " + path.string() + " has " + std::to_string(map.grid.nx) + " x " +
                            std::to_string(map.grid.ny) + " points (x by y, " +
                            std::to_string(map.grid.size()) + " values)";
    if (map.grid.nx > grid.nx || map.grid.ny > grid.ny || grid.nx % map.grid.nx || grid.ny % map.grid.ny)
      throw CaseError(c.file + ": [grid] n: " + has + "; expected a grid equal to it or a multiple of it "
                      "(cmc interpolates band-limited surfaces to finer grids but never down-samples)");
    if (grid.ny > 1 && grid.nx / map.grid.nx != grid.ny / map.grid.ny)
      throw CaseError(c.file + ": [surface] path: " + has + "; expected the case's " + std::to_string(grid.nx) +
                      " x " + std::to_string(grid.ny) + " points or a coarser map with the same factor along x and y "
                      "(a truncated file? it has " + std::to_string(grid.nx / map.grid.nx) + "x fewer points along x "
                      "but " + std::to_string(grid.ny / map.grid.ny) + "x fewer along y)");
    map = fourier_interpolate(map, grid.nx, grid.ny);
  }
  map.grid.lx = grid.lx, map.grid.ly = grid.ly;
  return {grid, std::move(map.heights), std::string(kind_name(sf.format)) + " file " + path.string()};
}
}  // namespace

SelfAffineSpec self_affine_spec(const SurfaceSpec& sf, const Units& u) {
  SelfAffineSpec spec;
  spec.hurst = sf.hurst;
  spec.rolloff_wavelength = u.length(sf.rolloff_wavelength);
  spec.cutoff_wavelength = u.length(sf.cutoff_wavelength);
  spec.rms_gradient = sf.rms_gradient;
  spec.seed = (unsigned long)sf.seed;
  return spec;
}

namespace {

void build_self_affine(const SurfaceSpec& sf, Scene& s) {
  const SelfAffineSpec spec = self_affine_spec(sf, s.units);
  SelfAffineSurface surf = generate_self_affine(spec, s.grid);
  s.topography = {s.grid, std::move(surf.map.heights),
                  "self-affine, H = " + std::to_string(sf.hurst) + ", seed " + std::to_string(sf.seed)};
  if (surf.low_passed())
    s.warnings.push_back("the grid holds " + std::to_string(surf.modes_total - surf.modes_dropped) + " of the " +
                         std::to_string(surf.modes_total) + " Fourier modes of the surface: it is low-passed at the grid's "
                         "Nyquist wavelength (use grid.n >= " + std::to_string(self_affine_modes(spec).full_grid()) +
                         " for the full spectrum)");
  s.surface_facts.modes_dropped = double(surf.modes_dropped);
  s.surface_facts.dx_over_cutoff_wavelength = s.grid.dx() / spec.cutoff_wavelength;
}

// The indenter's heights (reduced), its shape parameters and, for rough surfaces,
// their statistics. `given`: heights in metres in place of the case's surface.
void build_topography(const Case& c, Scene& s, const std::span<const double>* given) {
  const Units& u = s.units;
  const auto& sf = c.surface;
  if (given) {
    Field h(given->size());
    const double to_reduced = 1.0 / u.length_m;
    for (std::size_t i = 0; i < h.size(); ++i) h[i] = (*given)[i] * to_reduced;
    s.topography = {s.grid, std::move(h), "heights given by the caller"};
  } else switch (sf.kind) {
    case SurfaceKind::Sphere:
      s.sphere_radius = u.length(sf.radius);
      s.apex_x = sf.center ? u.length((*sf.center)[0]) : 0.5 * s.grid.lx;
      s.apex_y = sf.center ? u.length((*sf.center)[1]) : 0.5 * s.grid.ly;
      s.topography = sphere(s.grid, s.sphere_radius, s.apex_x, s.apex_y, c.grid.periodic);
      break;
    case SurfaceKind::Wavy1d:
    case SurfaceKind::Wavy2d:
      s.wave_amplitude = u.length(sf.amplitude), s.wavelength = u.length(sf.wavelength);
      s.topography = (sf.kind == SurfaceKind::Wavy1d ? wavy1d : wavy2d)(s.grid, s.wave_amplitude, s.wavelength);
      break;
    case SurfaceKind::SelfAffine: build_self_affine(sf, s); break;
    case SurfaceKind::File: s.topography = load_surface_file(c, s.grid); break;
    case SurfaceKind::Flat: s.topography = flat(s.grid); break;
  }
  if (given || sf.kind == SurfaceKind::SelfAffine || sf.kind == SurfaceKind::File) {
    const SurfaceStatistics st = surface_statistics(s.grid, s.topography.heights);
    const double L = u.length_m;
    auto& f = s.surface_facts;
    f.mean_height = st.mean * L, f.max_height = st.max * L, f.rms_height = st.rms_height * L;
    f.rms_gradient = st.rms_gradient;
    f.curvature_radius = st.curvature_radius * L;
  }
  s.mean_height = Grid::mean(s.topography.heights);
}


// The interaction in reduced units (w in E* L, ranges in L), and what it means for the
// resolution.
// Every value is checked in reduced units before a law is made of it (SceneChecks.hpp).
void build_interaction(const Case& c, Scene& s) {
  const InteractionSpec& in = c.interaction;
  if (in.kind == InteractionKind::HardWall) return;
  const Units& u = s.units;
  const double w = u.energy_per_area(in.work_of_adhesion);
  require_reduced(c, "[interaction] work_of_adhesion", in.work_of_adhesion, "J/m^2", u.to_j_per_m2(1.0), w);
  // The radius behind mu_T / lambda: the sphere's, or the rough surface's R_c.
  const double R = s.surface_facts.curvature_radius ? u.length(*s.surface_facts.curvature_radius) : s.sphere_radius;
  if (in.tabor > 0.0 || in.maugis_lambda > 0.0) require_curvature_radius(c, R);
  const std::string range_key = in.tabor > 0.0           ? "[interaction] tabor = " + short_number(in.tabor) + " sets "
                                : in.maugis_lambda > 0.0 ? "[interaction] maugis_lambda = " +
                                                               short_number(in.maugis_lambda) + " sets "
                                                         : "[interaction] range: ";
  if (in.kind == InteractionKind::Exponential) {
    const double rho = in.tabor > 0.0 ? exponential_range_from_tabor(1.0, R, w, in.tabor) : u.length(in.range);
    require_reduced(c, range_key + "the range rho", u.to_m(rho), "m", u.length_m, rho);
    if (in.coarse_graining == CoarseGraining::Range) {
      const double rho_c = coarse_grained_range(w, rho, s.half_space->self_stiffness());
      if (rho_c > rho) s.surface_facts.specified_range = u.to_m(rho);
      s.interaction = ExponentialAdhesion(w, rho_c);
    } else if (in.coarse_graining == CoarseGraining::Shape) {
      const ExponentialAdhesion law = shape_coarse_grained(w, rho, s.half_space->self_stiffness());
      if (law.range() > rho) s.surface_facts.specified_range = u.to_m(rho);  // the peak had to fall too
      if (law.head() > 0.0) s.surface_facts.law_head = u.to_m(law.head());
      s.interaction = law;
    } else {
      s.interaction = ExponentialAdhesion(w, rho);
    }
  } else {
    const double sigma0 = in.maugis_lambda > 0.0 ? dugdale_stress_from_lambda(1.0, R, w, in.maugis_lambda)
                                                 : w / u.length(in.range);
    require_reduced(c, range_key + "the range h0", u.to_m(w / sigma0), "m", u.length_m, w / sigma0);
    const double eps = in.smoothing > 0.0 ? u.length(in.smoothing) : dugdale_min_smoothing(1.0, sigma0, s.grid.dx());
    require_dugdale_smoothing(c, u.to_m(eps), u.to_m(2.0 * w / sigma0));
    require_reduced(c, "[interaction] smoothing", u.to_m(eps), "m", u.length_m, eps);
    s.interaction = DugdaleAdhesion(w, w / sigma0, eps);
  }
  const double range = interaction_range(s.interaction);
  auto& f = s.surface_facts;
  f.interaction_range = u.to_m(range);
  f.dx_over_range = s.grid.dx() / range;
  // w dx / (E* rho²) above ~1 makes single grid points bistable (shared/notes).
  f.bistability_number = w * s.grid.dx() / (range * range);
  if (R > 0.0 && std::isfinite(R)) f.tabor_parameter = tabor_parameter(1.0, R, w, range);
}

// One target per load step (reduced): force and mean gap become the two controls the
// solvers know.
void build_targets(const LoadingSpec& l, Scene& s) {
  const Units& u = s.units;
  std::vector<double> values = l.values;
  values.insert(values.end(), l.unloading.begin(), l.unloading.end());
  s.unloading_from = l.values.size();
  for (double v : values) switch (l.control) {
      case LoadControl::Force: s.targets.push_back({Control::MeanPressure, u.force(v) / s.grid.area()}); break;
      case LoadControl::MeanPressure: s.targets.push_back({Control::MeanPressure, u.pressure(v)}); break;
      case LoadControl::Penetration: s.targets.push_back({Control::Penetration, u.length(v)}); break;
      case LoadControl::MeanGap:  // periodic: <g> = <h> − δ
        s.targets.push_back({Control::Penetration, s.mean_height - u.length(v)});
        break;
    }
}

}  // namespace

std::vector<std::pair<std::string, double>> surface_fact_entries(const SurfaceFacts& f) {
  std::vector<std::pair<std::string, double>> out;
  const std::pair<const char*, const std::optional<double>*> all[] = {
      {"modes_dropped", &f.modes_dropped},
      {"mean_height", &f.mean_height},
      {"max_height", &f.max_height},
      {"rms_height", &f.rms_height},
      {"rms_gradient", &f.rms_gradient},
      {"curvature_radius", &f.curvature_radius},
      {"dx_over_cutoff_wavelength", &f.dx_over_cutoff_wavelength},
      {"interaction_range", &f.interaction_range},
      {"specified_range", &f.specified_range},
      {"law_head", &f.law_head},
      {"dx_over_range", &f.dx_over_range},
      {"bistability_number", &f.bistability_number},
      {"tabor_parameter", &f.tabor_parameter}};
  for (const auto& [name, value] : all)
    if (*value) out.emplace_back(name, **value);
  return out;
}

namespace {
// The scene of case `c`; `given`: the heights in metres in place of its surface (null: its own).
Scene make_scene(const Case& c, const std::span<const double>* given) {
  check_unit_scales(c);
  Scene s;
  s.units.length_m = c.grid.size_x;
  s.units.pressure_pa = c.contact_modulus;
  const Units& u = s.units;
  const Grid whole{c.grid.nx, c.grid.ny, 1.0, u.length(c.grid.size_y)};
  Grid slab;
  try {
    slab = distribute(whole);  // the whole grid with one rank
  } catch (const std::invalid_argument& e) {
    throw CaseError(c.file + ": [grid]: " + e.what());
  }
  if (c.surface.kind == SurfaceKind::SelfAffine && !given) {
    // Made on the slab (each rank its rows of the spectrum, a distributed inverse
    // transform): no rank holds the whole surface.
    s.grid = slab;
    build_topography(c, s, nullptr);
  } else {
    // Analytic shapes and files: every rank makes the whole map and its statistics (the
    // same heights as a serial run, bit for bit), then keeps its slab of it.
    LocalReductions whole_surface;
    s.grid = whole;
    build_topography(c, s, given);
    s.grid = slab;
    if (slab.split()) {
      s.topography.heights = slab_of(slab, s.topography.heights);
      s.topography.grid = slab;
    }
  }
  check_surface_numbers(c, s, given ? "heights (given in place of the case's surface)" : nullptr);  // before anything is made of them
  try {
    s.half_space = make_half_space(s.grid, 1.0, c.grid.periodic);  // E* = 1 in reduced units
  } catch (const std::invalid_argument& e) {
    if (ranks() == 1) throw;
    throw CaseError(c.file + ": [grid]: " + e.what());
  }
  build_interaction(c, s);
  s.observables = c.observables;
  s.observables.cross_section_x = u.length(c.observables.cross_section_x);
  s.observables.contact_gap_threshold = u.length(c.observables.contact_gap_threshold);
  s.contact_rule = ContactRule::of(s.interaction, s.observables.contact_gap_threshold);
  build_targets(c.loading, s);
  check_load_numbers(c, s);
  return s;
}
}  // namespace

Scene build_scene(const Case& c) { return make_scene(c, nullptr); }

Scene build_scene(const Case& c, std::span<const double> heights_m) {
  const std::size_t points = std::size_t(c.grid.nx) * std::size_t(c.grid.ny);
  if (heights_m.size() != points)
    throw CaseError(c.file + ": heights: " + std::to_string(heights_m.size()) + " values, expected the grid's " +
                    std::to_string(c.grid.nx) + " x " + std::to_string(c.grid.ny));
  LocalReductions every_rank_holds_them;
  const std::size_t bad = Grid::count_if(heights_m, [](double h) { return !std::isfinite(h); });
  if (bad) {
    const std::size_t first = std::size_t(std::find_if(heights_m.begin(), heights_m.end(),
                                                       [](double h) { return !std::isfinite(h); }) - heights_m.begin());
    throw CaseError(c.file + ": heights: " + std::to_string(bad) + " of " + std::to_string(points) +
                    " values are not finite (NaN or infinite), the first at row " + std::to_string(first / c.grid.nx) +
                    ", column " + std::to_string(first % c.grid.nx) + "; expected finite heights in metres");
  }
  return make_scene(c, &heights_m);
}

}  // namespace cmc
