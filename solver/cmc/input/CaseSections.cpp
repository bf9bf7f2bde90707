// The sections of a case file that describe the problem: [grid], [surface], [interaction],
// [loading], [solver] and [observables] (input/CaseSection.hpp).
#include "cmc/input/CaseSection.hpp"

#include <algorithm>

namespace cmc::case_parsing {

namespace {


// Whether this build has the CUDA backend (grid/Backend.hpp; CMakeLists.txt defines CMC_CUDA).
#ifdef CMC_CUDA
constexpr bool kCudaBuilt = true;
#else
constexpr bool kCudaBuilt = false;
#endif

}  // namespace

void parse_grid(Section s, GridSpec& g) {
  // Sizes are bounded before they are narrowed to int (a larger one would wrap); whether
  // the grid fits in memory is checked once the whole case is known (check_memory).
  constexpr long long side = CaseLimits::kMaxGridSide;
  if (s.has("n")) {
    if (s.has("nx") || s.has("ny")) s.fail("n", "either n or nx/ny, not both");
    g.nx = g.ny = int(s.integer("n", {}, "a positive number of points per side", 1, side));
  } else {
    g.nx = int(s.integer("nx", {}, "a positive number of points along x (or give n)", 1, side));
    g.ny = int(s.integer("ny", {}, "a positive number of points along y (1 for a 1-D problem)", 1, side));
  }
  g.size_x = s.number("size", {}, "the side length along x in m", true);
  g.size_y = s.number("size_y", g.size_x, "the side length along y in m", true);
  g.periodic = s.string("boundary", std::string(g.periodic ? "periodic" : "free"), {"periodic", "free"}) == "periodic";
  if (!g.periodic && g.ny < 2) s.fail("ny", "at least 2 points: a free boundary needs a 2-D grid");
  g.backend = s.string("backend", g.backend, {"cpu", "cuda"});
  if (g.backend == "cuda" && !kCudaBuilt)
    s.fail("backend", "\"cpu\": this build of cmc has no CUDA backend (configure a build folder with -DCMC_CUDA=ON; "
                      "README, \"GPU\")");
  if (g.backend == "cuda" && !g.periodic)
    s.fail("backend", "\"cpu\" with boundary = \"free\": the CUDA backend has the periodic boundary only");
  s.finish();
}

void parse_surface(Section s, const GridSpec& grid, SurfaceSpec& sf) {
  sf.kind = s.choice<SurfaceKind>("kind");
  switch (sf.kind) {
    case SurfaceKind::Sphere:
      sf.radius = s.number("radius", {}, "the sphere radius in m", true);
      if (s.has("center")) {
        auto v = s.numbers("center", "[x, y] in m", 2);
        if (v.size() != 2) s.fail("center", "[x, y] in m");
        sf.center = v;
      }
      break;
    case SurfaceKind::Wavy1d:
    case SurfaceKind::Wavy2d: {
      sf.amplitude = s.number("amplitude", {}, "the amplitude a in m of h = a (1 - cos(2 pi x / wavelength))", true);
      sf.wavelength = s.number("wavelength", grid.size_x, "the wavelength in m", true);
      const double periods = grid.size_x / sf.wavelength;
      if (grid.periodic && std::abs(periods - std::round(periods)) > 1e-9)
        s.fail("wavelength", "a wavelength that divides the periodic grid size " + std::to_string(grid.size_x));
      // Fewer than two points a wavelength sample the cosine as a constant: a flat punch.
      double per_wavelength = grid.nx * sf.wavelength / grid.size_x;
      if (sf.kind == SurfaceKind::Wavy2d) per_wavelength = std::min(per_wavelength, grid.ny * sf.wavelength / grid.size_y);
      if (per_wavelength < 2.0)
        s.fail("wavelength", "at least 2 grid points a wavelength (here " + number_text(per_wavelength) +
                                 "): a longer wavelength or a larger [grid] n");
      break;
    }
    case SurfaceKind::SelfAffine:
      if (grid.size_x != grid.size_y) s.fail("kind", "a square grid (size_y = size) for a self-affine surface");
      if (grid.nx < 2 || grid.ny < 2)
        s.fail("kind", "a grid of at least 2 x 2 points for a self-affine surface ([grid] n = " +
                           std::to_string(std::min(grid.nx, grid.ny)) + " here)");
      sf.hurst = s.number("hurst", sf.hurst, "the Hurst exponent H in (0, 1]", true);
      if (sf.hurst > 1.0) s.fail("hurst", "the Hurst exponent H in (0, 1]");
      sf.rolloff_wavelength = s.number("rolloff_wavelength", SurfaceSpec::kRolloffFraction * grid.size_x,
                                       "the roll-off wavelength in m", true);
      sf.cutoff_wavelength = s.number("cutoff_wavelength", SurfaceSpec::kCutoffFraction * grid.size_x,
                                      "the short-wavelength cutoff in m", true);
      if (!(sf.cutoff_wavelength < sf.rolloff_wavelength) || sf.rolloff_wavelength > grid.size_x)
        s.fail("cutoff_wavelength", "cutoff_wavelength < rolloff_wavelength <= grid size");
      // The whole band is generated whatever the grid: (pi/2) (size/cutoff)^2 modes.
      if (grid.size_x / sf.cutoff_wavelength > CaseLimits::kMaxBandRatio)
        s.fail("cutoff_wavelength", "at least 1e-6 x the grid size, " + number_text(grid.size_x * 1e-6) +
                                        " m (the generator makes every mode of the band, whatever the grid)");
      sf.rms_gradient = s.number("rms_gradient", sf.rms_gradient, "the rms gradient of the surface", true);
      sf.seed = s.integer("seed", sf.seed, "a non-negative random seed", 0, CaseLimits::kMaxSeed);
      break;
    case SurfaceKind::File: {
      sf.path = s.string("path");
      sf.format = s.choice<SurfaceFormat>("format");
      sf.dataset = s.string("dataset", sf.dataset);
      // The challenge's own files hold heights in units of L; generic files say what they hold.
      const bool in_units_of_l = sf.format == SurfaceFormat::ChallengeHdf5 ||
                                 sf.format == SurfaceFormat::ChallengeAscii || sf.format == SurfaceFormat::Fourier;
      sf.height_unit = s.number("height_unit", in_units_of_l ? grid.size_x : 1.0, "metres per height unit of the file", true);
      break;
    }
    case SurfaceKind::Flat:
      break;
  }
  const std::string wavy = "kind = \"wavy1d\" or \"wavy2d\"", rough = "kind = \"self_affine\"", file = "kind = \"file\"";
  s.finish({{"radius", "kind = \"sphere\""}, {"center", "kind = \"sphere\""}, {"amplitude", wavy}, {"wavelength", wavy},
            {"hurst", rough}, {"rolloff_wavelength", rough}, {"cutoff_wavelength", rough}, {"rms_gradient", rough},
            {"seed", rough}, {"path", file}, {"format", file}, {"dataset", file}, {"height_unit", file}});
}

void parse_interaction(Section s, SurfaceKind surface, InteractionSpec& in) {
  in.kind = s.choice<InteractionKind>("kind", in.kind);
  if (in.kind != InteractionKind::HardWall) {
    const bool exponential = in.kind == InteractionKind::Exponential;
    in.work_of_adhesion = s.number("work_of_adhesion", {}, "the work of adhesion in J/m^2", true);
    const bool sphere = surface == SurfaceKind::Sphere;
    const bool rough = surface == SurfaceKind::SelfAffine || surface == SurfaceKind::File;
    int given = 0;
    if (s.has("range")) in.range = s.number("range", {}, "the interaction range in m", true), ++given;
    if (exponential && s.has("tabor")) {
      if (!sphere && !rough) s.fail("tabor", "a sphere or rough surface (a radius of curvature to define mu_T); give range");
      in.tabor = s.number("tabor", {}, "the Tabor parameter mu_T", true), ++given;
    }
    if (!exponential && s.has("maugis_lambda")) {
      if (!sphere) s.fail("maugis_lambda", "a sphere (Maugis' lambda needs its radius); give range");
      in.maugis_lambda = s.number("maugis_lambda", {}, "Maugis' parameter lambda", true), ++given;
    }
    if (given != 1)
      s.fail("range", exponential ? "exactly one of range (m) or tabor" : "exactly one of range (h0, m) or maugis_lambda");
    if (!exponential) in.smoothing = s.number("smoothing", in.smoothing, "a smoothing width in m", false, true);
    if (s.has("coarse_graining")) {
      if (!exponential) s.fail("coarse_graining", "kind = \"exponential\" (Dugdale's law has its own smoothing)");
      in.coarse_graining = s.choice<CoarseGraining>("coarse_graining", in.coarse_graining);
    }
  }
  const std::string adhesive = "kind = \"exponential\" or \"dugdale\"";
  s.finish({{"work_of_adhesion", adhesive}, {"range", adhesive}, {"tabor", "kind = \"exponential\""},
            {"coarse_graining", "kind = \"exponential\""}, {"maugis_lambda", "kind = \"dugdale\""},
            {"smoothing", "kind = \"dugdale\""}});
}

void parse_loading(Section s, bool adhesive, bool periodic, LoadingSpec& l) {
  l.control = s.choice<LoadControl>("control");
  const bool pressure_like = l.control == LoadControl::Force || l.control == LoadControl::MeanPressure;
  const std::string what = pressure_like ? "a non-empty array of loads (N or Pa)" : "a non-empty array of lengths in m";
  l.values = s.numbers("values", what);
  if (s.has("unloading")) l.unloading = s.numbers("unloading", what);
  if (l.values.size() + l.unloading.size() > CaseLimits::kMaxLoadSteps)
    s.fail(l.unloading.empty() ? "values" : "unloading",
           "at most " + std::to_string(CaseLimits::kMaxLoadSteps) + " load steps in values and unloading together (got " +
               std::to_string(l.values.size() + l.unloading.size()) + ")");
  if (pressure_like && !adhesive)
    for (const char* key : {"values", "unloading"})
      for (double v : key == std::string("values") ? l.values : l.unloading)
        if (v < 0.0) s.fail(key, "non-negative loads for a hard-wall (non-adhesive) contact");
  if (l.control == LoadControl::MeanGap)  // g >= 0 at every point (no interaction lets the solids overlap)
    for (const char* key : {"values", "unloading"})
      for (double v : key == std::string("values") ? l.values : l.unloading)
        if (v < 0.0) s.fail(key, "non-negative mean gaps in m (the gap is never negative)");
  if (l.control == LoadControl::MeanGap && !periodic)
    s.fail("control", "\"force\" or \"penetration\": a mean gap needs a periodic grid");
  // Bounded: a step that still fails at the finest level is walked in 2^max_halvings sub-steps.
  l.max_halvings = int(s.integer("max_halvings", l.max_halvings, "a non-negative number of halvings", 0,
                                 CaseLimits::kMaxHalvings));
  l.jump_fraction = s.number("jump_fraction", l.jump_fraction, "a relative change that counts as a jump", true);
  l.jump_pressure_floor = s.number("jump_pressure_floor", l.jump_pressure_floor,
                                   "a pressure in Pa (0: the largest |mean pressure| so far)", false, true);
  l.refine_pulloff = int(s.integer("refine_pulloff", l.refine_pulloff, "a non-negative number of extra solves", 0,
                                   CaseLimits::kMaxRefinePulloff));
  s.finish();
}

namespace {

// A loading path: the load grows (the mean gap shrinks) from each value to the next, and
// nothing is unloaded. The quasi-static solver follows only such paths.
bool loading_only(const LoadingSpec& l) {
  if (!l.unloading.empty()) return false;
  for (std::size_t k = 1; k < l.values.size(); ++k) {
    const bool grows = l.control == LoadControl::MeanGap ? l.values[k] <= l.values[k - 1] : l.values[k] >= l.values[k - 1];
    if (!grows) return false;
  }
  return true;
}

}  // namespace

// "auto" picks the solver that can solve the interaction and the path; a solver that
// cannot is an error naming the key. The resolved case records the solver that runs.
void parse_solver(Section s, const InteractionSpec& in, const LoadingSpec& l, SolverSpec& sv) {
  const bool adhesive = in.kind != InteractionKind::HardWall;
  const bool exponential = in.kind == InteractionKind::Exponential;
  sv.kind = s.choice<SolverKind>("kind", sv.kind);
  if (sv.kind == SolverKind::Auto)
    sv.kind = !adhesive                         ? SolverKind::PolonskyKeer
              : exponential && loading_only(l) ? SolverKind::QuasiStatic
                                               : SolverKind::AdhesiveCg;
  if (adhesive && sv.kind == SolverKind::PolonskyKeer)
    s.fail("kind", "\"adhesive_cg\", \"quasi_static\" or \"auto\" with an adhesive interaction (Polonsky-Keer solves "
                   "hard-wall contact only)");
  if (sv.kind == SolverKind::QuasiStatic && !exponential)
    s.fail("kind", "\"adhesive_cg\" or \"auto\": \"quasi_static\" needs [interaction] kind = \"exponential\"");
  if (sv.kind == SolverKind::QuasiStatic && !loading_only(l))
    s.fail("kind", "\"adhesive_cg\" or \"auto\": \"quasi_static\" follows a loading path only ([loading] values in "
                   "the loading direction, no unloading)");
  s.resolve("kind", std::string(kind_name(sv.kind)));
  const bool pk = sv.kind == SolverKind::PolonskyKeer;
  sv.tolerance = s.number("tolerance", pk ? SolverSpec::kPolonskyKeerTolerance : SolverSpec::kAdhesiveTolerance,
                          "a relative residual", true);
  if (sv.tolerance > CaseLimits::kMaxSolverTolerance)
    s.fail("tolerance", "a relative residual of at most " + number_text(CaseLimits::kMaxSolverTolerance) +
                            " (a looser one stops a solve after a few iterations, far from the answer)");
  sv.max_iterations =
      int(s.integer("max_iterations", sv.max_iterations, "a positive iteration cap", 1, CaseLimits::kMaxIterations));
  sv.recompute_every = int(
      s.integer("recompute_every", sv.recompute_every, "a positive number of iterations", 1, CaseLimits::kMaxIterations));
  sv.tension_tolerance = s.number("tension_tolerance", sv.tension_tolerance,
                                  "a relative change of the adhesive tension (quasi_static)", true);
  sv.max_outer_steps = int(s.integer("max_outer_steps", sv.max_outer_steps,
                                     "a positive number of outer steps (quasi_static)", 1, CaseLimits::kMaxIterations));
  sv.max_seconds = s.number("max_seconds", sv.max_seconds,
                             "seconds a load step's solve may take (quasi_static), 0 for no limit", false, true);
  sv.precondition = s.boolean("precondition", sv.precondition);
  s.finish();
}

void parse_observables(Section s, double size_x, ObservablesSpec& o) {
  o.enabled = s.boolean("enabled", o.enabled);
  o.cross_section_x = s.number("cross_section_x", ObservablesSpec::kCrossSectionFraction * size_x,
                               "the x of the cross-section in m", false, true);
  // Inside the cell: a larger x would be wrapped around the period without a word.
  if (!(o.cross_section_x < size_x))
    s.fail("cross_section_x", "an x inside the cell, 0 <= x < size = " + number_text(size_x) + " m");
  o.stress_bins =
      int(s.integer("stress_bins", o.stress_bins, "a positive number of bins", 1, CaseLimits::kMaxStressBins));
  o.gap_bins_per_decade = int(s.integer("gap_bins_per_decade", o.gap_bins_per_decade, "a positive number of bins", 1,
                                        CaseLimits::kMaxBinsPerDecade));
  o.patch_bins_per_decade = int(s.integer("patch_bins_per_decade", o.patch_bins_per_decade,
                                          "a positive number of bins", 1, CaseLimits::kMaxBinsPerDecade));
  o.contact_gap_threshold = s.number("contact_gap_threshold", o.contact_gap_threshold,
                                     "a gap in m (a point is in contact where g <= this)", false, true);
  s.finish();
}

}  // namespace cmc::case_parsing
