// Case -> Scene: unit conversion in one place, surfaces from generators and files.
#include "cmc/run/Driver.hpp"
#include "cmc/scene/Scene.hpp"
#include "cmc/surface/SurfaceIO.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

using namespace cmc;

namespace {
toml::table base() {
  return toml::parse(R"(
[case]
name = "s"
[grid]
n = 64
size = 2e-3
[material]
contact_modulus = 4e6
[surface]
kind = "sphere"
radius = 1e-2
[loading]
control = "force"
values = [8.0]
)");
}
}  // namespace

TEST(Scene, ConvertsToReducedUnits) {
  const Case c = parse_case(base(), "mem");
  const Scene s = build_scene(c);
  EXPECT_DOUBLE_EQ(s.grid.lx, 1.0);
  EXPECT_DOUBLE_EQ(s.sphere_radius, 5.0);              // 1e-2 m / 2e-3 m
  ASSERT_EQ(s.targets.size(), 1u);
  EXPECT_NEAR(s.targets[0].value, 8.0 / (4e6 * 4e-6), 1e-12);  // F / (E* L²) over unit area
  EXPECT_DOUBLE_EQ(s.units.to_n(s.targets[0].value * s.grid.area()), 8.0);
}

TEST(Scene, SurfaceFileIsReadAndInterpolated) {
  const auto dir = std::filesystem::temp_directory_path() / ("cmc_scene_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  // A 16 x 16 challenge-format file (heights in units of L) holding one cosine.
  HeightMap m{Grid{16, 16, 1.0, 1.0}, Field(256)};
  for (int iy = 0; iy < 16; ++iy)
    for (int ix = 0; ix < 16; ++ix) m.heights[iy * 16 + ix] = 1e-3 * (1 + std::cos(2 * M_PI * 3 * ix / 16.0));
  write_hdf5_heights(dir / "surf.h5", m);
  toml::table t = base();
  t.insert_or_assign("surface", toml::table{{"kind", "file"}, {"path", "surf.h5"}, {"format", "challenge_hdf5"}});
  Case c = parse_case(t, (dir / "case.toml").string());
  const Scene s = build_scene(c);  // 64² from a 16² file: Fourier interpolation
  for (int ix = 0; ix < 64; ++ix)
    ASSERT_NEAR(s.topography.heights[5 * 64 + ix], 1e-3 * (1 + std::cos(2 * M_PI * 3 * ix / 64.0)), 1e-15);
  // A grid coarser than the file is refused, naming the key.
  t.insert_or_assign("grid", toml::table{{"n", 8}, {"size", 2e-3}});
  c = parse_case(t, (dir / "case.toml").string());
  try {
    build_scene(c);
    ADD_FAILURE() << "no error";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("[grid] n"), std::string::npos) << e.what();
  }
  // A missing file names the file.
  t.insert_or_assign("surface", toml::table{{"kind", "file"}, {"path", "nope.h5"}, {"format", "challenge_hdf5"}});
  t.insert_or_assign("grid", toml::table{{"n", 16}, {"size", 2e-3}});
  c = parse_case(t, (dir / "case.toml").string());
  try {
    build_scene(c);
    ADD_FAILURE() << "no error";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("nope.h5"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// The driver runs the solver the case names (one dispatch on the typed kind): the
// adhesive CG's load path shows in the summary, Polonsky–Keer has none.
TEST(Scene, DriverRunsTheCasesSolver) {
  toml::table t = base();
  t["grid"].as_table()->insert_or_assign("n", 32);
  t["loading"].as_table()->insert_or_assign("values", toml::array{0.5});  // a Hertz contact well inside the cell
  for (const char* kind : {"polonsky_keer", "adhesive_cg"}) {
    t.insert_or_assign("solver", toml::table{{"kind", kind}});
    const Case c = parse_case(t, "mem");
    Scene s = build_scene(c);
    const RunSummary run = run_scene(c, s, {});
    EXPECT_EQ(run.status, RunStatus::Converged) << kind;
    EXPECT_EQ(run.load_path, std::string(kind) == "adhesive_cg") << kind;
    ASSERT_EQ(run.steps.size(), 1u);
    EXPECT_GT(run.steps[0].contact_fraction, 0.0) << kind;
  }
}

// Every run reports its cost against an FFT pair of its own operator, timed in the same
// run: the ratios are the steps' solve time over (pairs x pair time) and over (iterations
// x pair time), and an iteration costs at least one pair (PK: one pair per iteration).
TEST(Scene, RunReportsCostInFftPairs) {
  toml::table t = base();
  t["grid"].as_table()->insert_or_assign("n", 64);
  t["loading"].as_table()->insert_or_assign("values", toml::array{0.25, 0.5});
  const Case c = parse_case(t, "mem");
  Scene s = build_scene(c);
  const RunSummary run = run_scene(c, s, {});
  ASSERT_EQ(run.steps.size(), 2u);
  EXPECT_GT(run.fft_pair_s, 0.0);
  double solve_s = 0.0;
  int iterations = 0;
  for (const StepRecord& r : run.steps) solve_s += r.result.wall_s, iterations += r.result.iterations;
  EXPECT_EQ(run.iterations, iterations);
  EXPECT_GE(run.fft_pairs, double(iterations));
  EXPECT_DOUBLE_EQ(run.time_per_fft_pair, solve_s / (run.fft_pairs * run.fft_pair_s));
  EXPECT_DOUBLE_EQ(run.time_per_iteration, solve_s / (iterations * run.fft_pair_s));
  // A periodic grid held by one process, Polonsky-Keer: the fused sweeps' row-column pair
  // is timed too, and the floor is the faster of the two.
  EXPECT_GT(run.row_column_pair_s, 0.0);
  EXPECT_EQ(run.floor_pair_s, std::min(run.fft_pair_s, run.row_column_pair_s));
  EXPECT_DOUBLE_EQ(run.time_per_floor_pair, solve_s / (run.fft_pairs * run.floor_pair_s));
  // The time inside the transforms is part of each step's time, and the share is their ratio.
  double fft_s = 0.0;
  for (const StepRecord& r : run.steps) {
    EXPECT_GT(r.result.fft_s, 0.0);
    EXPECT_LE(r.result.fft_s, r.result.wall_s);
    fft_s += r.result.fft_s;
  }
  EXPECT_DOUBLE_EQ(run.fft_share, fft_s / solve_s);
}

// One contact rule: the step record's contact_fraction and the observables' are the same
// number, with and without a contact gap threshold (which widens both).
TEST(Scene, StepRecordAndObservablesShareTheContactRule) {
  toml::table t = base();
  t["grid"].as_table()->insert_or_assign("n", 32);
  t["loading"].as_table()->insert_or_assign("values", toml::array{0.5});
  double without = 0.0;
  for (double threshold : {0.0, 2e-6}) {
    t.insert_or_assign("observables", toml::table{{"enabled", true}, {"contact_gap_threshold", threshold}});
    const Case c = parse_case(t, "mem");
    Scene s = build_scene(c);
    const RunSummary run = run_scene(c, s, {});
    ASSERT_EQ(run.steps.size(), 1u);
    const StepRecord& r = run.steps[0];
    ASSERT_TRUE(r.observables);
    double observed = -1.0;
    for (const auto& [name, v] : r.observables->scalars)
      if (name == "contact_fraction") observed = v;
    EXPECT_EQ(r.contact_fraction, observed) << threshold;
    if (threshold == 0.0) without = r.contact_fraction;
    else EXPECT_GT(r.contact_fraction, without);
  }
  EXPECT_GT(without, 0.0);
}

// coarse_graining = "shape" (Scene.cpp, shape_coarse_grained): on a grid that resolves rho
// nothing changes; on one where the exponential is bistable but the triangle is not, w and
// the peak tension w/rho (the Tabor parameter) are kept and the law gets a head of slope
// theta K_ii (summary: law_head); where even the triangle is bistable, the peak falls
// (summary: specified_range). The law the scene holds is the one shape_coarse_grained makes.
TEST(Scene, ShapeCoarseGrainingKeepsWAndPeakWherePossible) {
  int regimes[3] = {0, 0, 0};
  for (double range : {1e-6, 7e-7, 1e-9}) {  // m: resolved; a head, peak kept; triangle with a lower peak
    toml::table t = base();
    t.insert_or_assign("interaction", toml::table{{"kind", "exponential"}, {"work_of_adhesion", 0.05},
                                                   {"range", range}, {"coarse_graining", "shape"}});
    const Case c = parse_case(t, "mem");
    Scene s = build_scene(c);
    const auto& law = std::get<ExponentialAdhesion>(s.interaction);
    const double w = s.units.energy_per_area(0.05), rho = s.units.length(range);
    const double k = s.half_space->self_stiffness(), kappa = kCoarseGrainingMargin * k;
    const ExponentialAdhesion want = shape_coarse_grained(w, rho, k);
    EXPECT_EQ(law.w, want.w);
    EXPECT_EQ(law.rho, want.rho);
    EXPECT_EQ(law.head(), want.head());
    EXPECT_DOUBLE_EQ(law.w, w);
    const double b = w / (rho * rho) / kappa, tri = (w / rho) * (w / rho) / (2 * w) / kappa;
    ++regimes[b <= 1 ? 0 : tri <= 1 ? 1 : 2];
    if (b <= 1) {
      EXPECT_EQ(law.rho, rho) << range;
      EXPECT_EQ(law.head(), 0.0) << range;
      EXPECT_FALSE(s.surface_facts.specified_range) << range;
      EXPECT_FALSE(s.surface_facts.law_head) << range;
    } else {
      ASSERT_TRUE(s.surface_facts.law_head) << range;
      EXPECT_NEAR(*s.surface_facts.law_head, s.units.to_m(law.head()), 1e-12 * range);
      EXPECT_NEAR(law.largest_curvature(), kappa, 1e-12 * kappa) << range;
      EXPECT_EQ(bool(s.surface_facts.specified_range), tri > 1) << range;
      if (tri <= 1) EXPECT_DOUBLE_EQ(law.rho, rho) << range;  // the peak tension kept
      else EXPECT_GT(law.rho, rho) << range;
    }
  }
  EXPECT_EQ(regimes[0] * regimes[1] * regimes[2], 1);  // each regime once
}

// coarse_graining = "range" (Scene.cpp, coarse_grained_range): on a grid that does not
// resolve rho, the range becomes sqrt(w / K_ii), so that the law's largest curvature
// w/rho² equals the point's own stiffness (no bistable point), with w kept; on a grid
// that resolves rho nothing changes. Dugdale's law refuses the key.
TEST(Scene, RangeCoarseGrainingRemovesBistabilityAndKeepsW) {
  for (double range : {1e-6, 1e-9}) {  // m: resolved (w/rho² = 25 E*/L < K_ii/2 = 38 E*/L), unresolved
    toml::table t = base();
    t.insert_or_assign("interaction", toml::table{{"kind", "exponential"}, {"work_of_adhesion", 0.05},
                                                   {"range", range}, {"coarse_graining", "range"}});
    const Case c = parse_case(t, "mem");
    Scene s = build_scene(c);
    const auto& law = std::get<ExponentialAdhesion>(s.interaction);
    const double w = s.units.energy_per_area(0.05), rho = s.units.length(range);
    EXPECT_DOUBLE_EQ(law.w, w);
    const double k = s.half_space->self_stiffness();
    EXPECT_NEAR(k * s.grid.dx(), 1.2, 0.1);  // the stiffness of one point, ≈ 1.2 E*/dx
    if (w / (rho * rho) <= kCoarseGrainingMargin * k) {
      EXPECT_DOUBLE_EQ(law.rho, rho) << range;
      EXPECT_FALSE(s.surface_facts.specified_range) << range;
    } else {
      EXPECT_NEAR(w / (law.rho * law.rho), kCoarseGrainingMargin * k, 1e-12 * k) << range;
      EXPECT_LT(kCoarseGrainingMargin, 1.0);  // monostable: k_ii + φ''(0) = (1 − θ) k_ii > 0
      ASSERT_TRUE(s.surface_facts.specified_range) << range;
      EXPECT_NEAR(*s.surface_facts.specified_range, range, 1e-12 * range);
      EXPECT_GT(law.rho, rho);
    }
  }
  toml::table t = base();
  t.insert_or_assign("interaction", toml::table{{"kind", "dugdale"}, {"work_of_adhesion", 0.05},
                                                 {"range", 1e-9}, {"coarse_graining", "shape"}});
  try {
    parse_case(t, "mem");
    FAIL() << "coarse_graining = shape with Dugdale accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("coarse_graining"), std::string::npos) << e.what();
  }
  t = base();
  t.insert_or_assign("interaction", toml::table{{"kind", "dugdale"}, {"work_of_adhesion", 0.05},
                                                 {"range", 1e-9}, {"coarse_graining", "range"}});
  try {
    parse_case(t, "mem");
    FAIL() << "coarse_graining with Dugdale accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("coarse_graining"), std::string::npos) << e.what();
  }
}
