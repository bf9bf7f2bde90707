// The CUDA backend against the CPU backend (ctest label 'gpu'). Each test runs a
// case on both and compares what a user reads from the summary. Where this build has no
// CUDA backend, or the machine no usable GPU, every test is skipped (GTEST_SKIP: ctest
// reports it as skipped, not passed).
//
// Tolerances. Hard wall: 1e-9 relative (the bar the GPU backend is held to). Both solve the same
// linear complementarity problem with the same iteration, and differ only in round-off
// (cuFFT against FFTW, and the order of the sums: fixed trees against OpenMP chunks);
// Polonsky-Keer stops at the case's residual tolerance (1e-8 and tighter here), so the
// answers agree to far better than 1e-9 wherever the contact sets are equal (checked:
// equal point counts in contact). Adhesion (the quasi-static solver, whose Polonsky-Keer
// solves run on the GPU): at dx = 24 rho every point is bistable, and its outer tolerance
// (tension_tolerance 1e-3) leaves the points that creep slower than that undecided.
// QuasiStaticAdhesion.hpp measured that spread at 512²: a_r 0.0381279 against 0.0381317
// between tension tolerances 1e-3 and 1e-5 (1.0e-4 relative), the mean gap 4e-7. The
// bounds below are twice those.
#include "cmc/contact/quasi_static/QuasiStaticAdhesion.hpp"
#include "cmc/grid/Backend.hpp"
#include "cmc/input/Case.hpp"
#include "cmc/run/Driver.hpp"
#include "cmc/scene/Scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace cmc {
namespace {

#define SKIP_WITHOUT_GPU()                                  \
  do {                                                      \
    std::string why;                                        \
    if (!cuda::available(&why)) GTEST_SKIP() << why;        \
  } while (0)

// The checkout: $CMC_SOURCE_DIR where set (a packed build run in another checkout, as
// scripts/gpu/check.sh does), else the one this was built from.
std::string case_path(const std::string& rel) {
  const char* env = std::getenv("CMC_SOURCE_DIR");
  return std::string(env && *env ? env : CMC_SOURCE_DIR) + "/cases/" + rel;
}

RunSummary run(const std::string& file, std::vector<std::string> sets, const std::string& backend) {
  sets.push_back("grid.backend=" + backend);
  const Case c = load_case(case_path(file), sets);
  Scene s = build_scene(c);
  return run_scene(c, s, {});
}

double observable(const StepRecord& r, const std::string& name) {
  if (!r.observables) return NAN;
  for (const auto& [k, v] : r.observables->scalars)
    if (k == name) return v;
  return NAN;
}

void expect_rel(double a, double b, double tol, const char* what) {
  const double scale = std::max(std::abs(a), std::abs(b));
  EXPECT_LE(std::abs(a - b), tol * (scale > 0.0 ? scale : 1.0)) << what << ": cpu " << a << ", cuda " << b;
}

// Same answer within `tol` relative on every step; for the hard wall, the same points in
// contact and the same patches.
void compare(const RunSummary& cpu, const RunSummary& gpu, double tol, double ar_tol, bool same_set) {
  ASSERT_EQ(cpu.status, RunStatus::Converged) << cpu.message;
  ASSERT_EQ(gpu.status, RunStatus::Converged) << gpu.message;
  ASSERT_EQ(cpu.steps.size(), gpu.steps.size());
  for (std::size_t k = 0; k < cpu.steps.size(); ++k) {
    const StepRecord &a = cpu.steps[k], &b = gpu.steps[k];
    expect_rel(a.mean_pressure, b.mean_pressure, tol, "mean pressure");
    expect_rel(a.mean_gap, b.mean_gap, tol, "mean gap");
    expect_rel(a.penetration, b.penetration, tol, "penetration");
    expect_rel(a.contact_fraction, b.contact_fraction, ar_tol, "contact fraction");
    if (same_set) EXPECT_EQ(a.contact_fraction, b.contact_fraction) << "the same points in contact";
    const double ra = observable(a, "repulsive_fraction"), rb = observable(b, "repulsive_fraction");
    if (!std::isnan(ra)) expect_rel(ra, rb, ar_tol, "repulsive fraction");
    const double na = observable(a, "n_patches"), nb = observable(b, "n_patches");
    if (same_set && !std::isnan(na)) EXPECT_EQ(na, nb) << "number of contact patches";
    EXPECT_GT(b.result.fft_pairs, 0.0) << "the GPU's transforms are counted";
  }
}

TEST(GpuBackend, HertzPeriodic) {
  SKIP_WITHOUT_GPU();
  compare(run("validation/hertz-periodic.toml", {}, "cpu"), run("validation/hertz-periodic.toml", {}, "cuda"), 1e-9,
          1e-9, true);
}

TEST(GpuBackend, WestergaardLine) {
  SKIP_WITHOUT_GPU();
  compare(run("validation/westergaard.toml", {}, "cpu"), run("validation/westergaard.toml", {}, "cuda"), 1e-9, 1e-9,
          true);
}

TEST(GpuBackend, ChallengeHardWall512) {
  SKIP_WITHOUT_GPU();
  const std::vector<std::string> sets{"grid.n=512"};
  compare(run("challenge/reference-load-hardwall.toml", sets, "cpu"),
          run("challenge/reference-load-hardwall.toml", sets, "cuda"), 1e-9, 1e-9, true);
}

TEST(GpuBackend, ChallengeAdhesive512) {
  SKIP_WITHOUT_GPU();
  const std::vector<std::string> sets{"grid.n=512"};
  // Twice the spread between outer tolerances (header): 2e-4 on a_r, 1e-6 on the rest.
  compare(run("challenge/reference-load.toml", sets, "cpu"), run("challenge/reference-load.toml", sets, "cuda"), 1e-6,
          2e-4, false);
}

// The adhesive sinusoid's loading branch by the quasi-static solver on a line, through the
// jump into contact under displacement control (cases/validation/johnson-alpha03-loading.toml).
// The mean pressure within tension_tolerance x w/ρ (the scale the outer iteration stops at:
// test_quasi_static.cpp, LineThroughJumpIn) and a_r within 4 points of 4096 (points the outer
// tolerance leaves undecided: this case's loading branch from the adhesive CG differs from
// the quasi-static one by 2 points at 2 of 13 steps). Passes on an H200.
TEST(GpuBackend, JohnsonSinusoidLoading) {
  SKIP_WITHOUT_GPU();
  const std::string file = "validation/johnson-alpha03-loading.toml";
  const RunSummary cpu = run(file, {}, "cpu"), gpu = run(file, {}, "cuda");
  ASSERT_EQ(cpu.status, RunStatus::Converged) << cpu.message;
  ASSERT_EQ(gpu.status, RunStatus::Converged) << gpu.message;
  ASSERT_EQ(cpu.steps.size(), gpu.steps.size());
  const Case c = load_case(case_path(file));
  const double scale = c.solver.tension_tolerance * c.interaction.work_of_adhesion / c.interaction.range;  // Pa
  for (std::size_t k = 0; k < cpu.steps.size(); ++k) {
    EXPECT_NEAR(cpu.steps[k].mean_pressure, gpu.steps[k].mean_pressure, scale) << "step " << k;
    EXPECT_NEAR(cpu.steps[k].contact_fraction, gpu.steps[k].contact_fraction, 4.0 / 4096.0) << "step " << k;
  }
}

// Fixed-order reductions: the same case twice on the GPU gives the same bits.
TEST(GpuBackend, RerunGivesTheSameBits) {
  SKIP_WITHOUT_GPU();
  const std::vector<std::string> sets{"grid.n=512"};
  for (const char* file : {"challenge/reference-load-hardwall.toml", "challenge/reference-load.toml"}) {
    const RunSummary a = run(file, sets, "cuda"), b = run(file, sets, "cuda");
    ASSERT_EQ(a.steps.size(), b.steps.size());
    for (std::size_t k = 0; k < a.steps.size(); ++k) {
      EXPECT_EQ(a.steps[k].result.iterations, b.steps[k].result.iterations) << file;
      EXPECT_EQ(a.steps[k].result.residual, b.steps[k].result.residual) << file;
      EXPECT_EQ(a.steps[k].mean_gap, b.steps[k].mean_gap) << file;
      EXPECT_EQ(a.steps[k].penetration, b.steps[k].penetration) << file;
      EXPECT_EQ(a.steps[k].contact_fraction, b.steps[k].contact_fraction) << file;
      EXPECT_EQ(a.steps[k].energy, b.steps[k].energy) << file;
    }
  }
}

// The quasi-static solver's outer step on the device (contact/quasi_static/CudaBackend.cu): a solve
// interrupted after its second outer step (the checkpoint's fields copied down through
// OuterPoint::fetch, as the writer does) and continued from there, as a resumed run does,
// gives the uninterrupted solve's bits (the GPU's reductions and rounds are in a fixed
// order). Passes on an H200.
TEST(GpuBackend, QuasiStaticContinuesFromAnOuterStep) {
  SKIP_WITHOUT_GPU();
  const Case c = load_case(case_path("challenge/reference-load.toml"), {"grid.n=512", "grid.backend=cuda"});
  Scene s = build_scene(c);
  const auto& adh = std::get<ExponentialAdhesion>(s.interaction);
  QuasiStaticAdhesion::Options o;
  o.tolerance = c.solver.tolerance;
  o.backend = Backend::Cuda;
  ContactState whole;
  const SolveResult a = QuasiStaticAdhesion(*s.half_space, s.topography.heights, adh, o).solve(s.targets[0], whole);
  ASSERT_TRUE(a.converged) << a.message;
  ASSERT_GT(a.diagnostics.outer_iterations, 3);
  OuterPoint kept;
  QuasiStaticAdhesion::Options stop = o;
  stop.on_outer = [&](const OuterPoint& at) {
    if (at.outer != 2) return;
    ASSERT_TRUE(at.fetch) << "the fields live on the device";
    at.fetch();
    kept.outer = at.outer, kept.tension = at.tension, kept.inner = at.inner, kept.so_far = at.so_far;
  };
  stop.max_outer = 3;  // on_outer follows outer steps 1 and 2 (not the last)
  ContactState first;
  QuasiStaticAdhesion(*s.half_space, s.topography.heights, adh, stop).solve(s.targets[0], first);
  ASSERT_EQ(kept.outer, 2);
  ContactState rest;
  const SolveResult b = QuasiStaticAdhesion(*s.half_space, s.topography.heights, adh, o).solve(s.targets[0], rest, &kept);
  ASSERT_TRUE(b.converged) << b.message;
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.diagnostics.outer_iterations, b.diagnostics.outer_iterations);
  EXPECT_EQ(whole.penetration, rest.penetration);
  for (std::size_t i = 0; i < whole.gap.size(); ++i) {
    ASSERT_EQ(whole.gap[i], rest.gap[i]) << "point " << i;
    ASSERT_EQ(whole.pressure[i], rest.pressure[i]) << "point " << i;
  }
}

// The outer step on the device against the first GPU path (Polonsky-Keer on the device, the
// outer step on the host, Options::outer_on_device off) with the cascade in rounds on both:
// the same algorithm, so only round-off differs (device against host exponentials, the
// order of the sums). On the resolved line of JohnsonSinusoidLoading: the same points in
// contact, and the mean pressure on the scale the outer iteration stops at,
// tension_tolerance x w/ρ (round-off may end one path an outer step before the other).
TEST(GpuBackend, QuasiStaticOuterStepOnTheDeviceOrTheHost) {
  SKIP_WITHOUT_GPU();
  const Case c = load_case(case_path("validation/johnson-alpha03-loading.toml"), {"grid.backend=cuda"});
  std::vector<ContactState> end(2);
  double scale = 0.0;  // tension_tolerance x w/ρ, reduced
  for (int k = 0; k < 2; ++k) {
    Scene s = build_scene(c);
    const auto& adh = std::get<ExponentialAdhesion>(s.interaction);
    scale = c.solver.tension_tolerance * adh.peak_tension();
    QuasiStaticAdhesion::Options o;
    o.tolerance = c.solver.tolerance;
    o.backend = Backend::Cuda;
    o.cascade_rounds = true;
    o.outer_on_device = k == 0;
    QuasiStaticAdhesion qs(*s.half_space, s.topography.heights, adh, o);
    for (const Target& t : s.targets) {
      const SolveResult r = qs.solve(t, end[std::size_t(k)]);
      ASSERT_TRUE(r.converged) << (k == 0 ? "device: " : "host: ") << r.message;
    }
  }
  EXPECT_NEAR(end[0].mean_pressure, end[1].mean_pressure, scale);
  EXPECT_EQ(Grid::count_if(end[0].gap, [](double g) { return g <= 0.0; }),
            Grid::count_if(end[1].gap, [](double g) { return g <= 0.0; }));
}

// What the CUDA backend does not run is refused by the case parser, naming the key.
TEST(GpuBackend, RefusesWhatItDoesNotRun) {
  if (!cuda::built()) GTEST_SKIP() << "a CPU-only build refuses every case with backend = \"cuda\" (test_case.cpp)";
  try {
    load_case(case_path("validation/hertz-free.toml"), {"grid.backend=cuda"});
    FAIL() << "a free boundary on the GPU was accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("[grid] backend"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("periodic boundary only"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cmc
