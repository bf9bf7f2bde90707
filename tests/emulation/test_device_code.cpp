// The GPU backends' own code run on the host (grid/CudaEmulation.hpp, CMC_CUDA_EMULATION;
// built in CPU builds only, label quick): Polonsky-Keer's device backend
// (contact/polonsky_keer/CudaBackend.cuh) and the quasi-static solver's outer step on the device
// (contact/quasi_static/CudaBackend.cuh), against the CPU backends on the same problems. What this can
// catch: a buffer that holds two things at once, a pass in the wrong order, a field that
// is not uploaded or copied back, a checkpoint that does not continue. What it cannot:
// anything of CUDA itself (kernels, cuFFT, the device reductions' trees), which the gpu
// tests check on a GPU (tests/gpu). These tests are what a change to the device code can
// be checked with on a machine without a GPU.
//
// Tolerances. The emulated device and the CPU run the same iteration; they differ in
// round-off only (FFTW's 2-D plans against the CPU's row-column transform, and the order of
// the sums: one serial loop against OpenMP chunks). Polonsky-Keer: the same contact set and
// the pressures within 1e-9 of the peak (measured: 1.8e-14 of it), the iteration counts
// within 2 (a last step decided at the tolerance; measured: equal). Quasi-static: the same
// points in contact and the gaps within the outer tolerance's 0.02 ρ
// (tests/test_quasi_static.cpp derives it; here the same algorithm on both sides,
// measured: the same outer steps, iterations and FFT pairs, gaps within 3.6e-13 ρ).
#include "cmc/contact/quasi_static/CudaBackend.cuh"
#include "cmc/input/Case.hpp"
#include "cmc/scene/Scene.hpp"
#include "cmc/surface/SelfAffine.hpp"
#include "../rough_patch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cmc {
void pk::report_profile(const PolonskyKeer::Device&) {}
// contact/polonsky_keer/CudaBackend.cu's, which a CPU build does not compile.
pk::End pk::run_on_device(PolonskyKeer::Device& d, const PolonskyKeer::Options& o, double h_scale,
                          const Target& target, const Start& start, SolveResult& res) {
  return iterate(d, o, h_scale, target, start, res);
}
}  // namespace cmc

using namespace cmc;

namespace {

using Patch = RoughPatch;  // tests/test_quasi_static.cpp's patch: 128², Δx = 24 ρ, peak tension E*

long contact(const Field& gap) { return long(std::count_if(gap.begin(), gap.end(), [](double g) { return g <= 0.0; })); }

double max_difference(const Field& a, const Field& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

// Polonsky-Keer over the emulated device backend, as pk::solve_on_device runs it: the
// heights up, the iteration, p and w down, then the host's finish (PolonskyKeer::solve).
ContactState device_hard_wall(HalfSpace& hs, const Field& h, bool precondition, const Target& target, int& iterations) {
  PolonskyKeer::Options o;
  o.tolerance = 1e-10;
  o.precondition = precondition;
  PolonskyKeer::Device d(hs, precondition);
  d.H.upload(h.data(), d.n);
  const pk::Start start = pk::make_start(hs, target, false, 0.0, precondition);
  SolveResult res;
  const pk::End end = pk::run_on_device(d, o, PolonskyKeer::residual_scale(h), target, start, res);
  EXPECT_TRUE(end.failure.empty()) << end.failure;
  EXPECT_LE(res.residual, o.tolerance);
  iterations = res.iterations;
  ContactState st;
  st.pressure.resize(d.n), st.displacement.resize(d.n), st.gap.resize(d.n);
  d.P.download(st.pressure.data(), d.n);
  d.W.download(st.displacement.data(), d.n);
  for (std::size_t i = 0; i < d.n; ++i) {
    st.pressure[i] *= end.sigma;
    st.gap[i] = st.pressure[i] > 0.0 ? 0.0 : std::max(0.0, st.displacement[i] - end.delta);
  }
  return st;
}

}  // namespace

TEST(DeviceCode, PolonskyKeerMatchesTheHost) {
  Patch s;
  PeriodicHalfSpace hs(s.map.grid, 1.0);
  for (bool pre : {true, false}) {
    PolonskyKeer::Options o;
    o.tolerance = 1e-10;
    o.precondition = pre;
    ContactState host;
    const SolveResult r = PolonskyKeer(hs, s.map.heights, o).solve({Control::MeanPressure, s.load}, host);
    ASSERT_TRUE(r.converged) << r.message;
    int its = 0;
    const ContactState dev = device_hard_wall(hs, s.map.heights, pre, {Control::MeanPressure, s.load}, its);
    const double peak = *std::max_element(host.pressure.begin(), host.pressure.end());
    const double dp = max_difference(host.pressure, dev.pressure);
    std::printf("    [device code] Polonsky-Keer%s: iterations %d / %d, contact %ld / %ld, max dp %.3g of the peak\n",
                pre ? " (preconditioned)" : "", r.iterations, its, contact(host.gap), contact(dev.gap), dp / peak);
    EXPECT_EQ(contact(host.gap), contact(dev.gap));
    EXPECT_LE(dp, 1e-9 * peak);
    EXPECT_NEAR(r.iterations, its, 2);
  }
}

namespace {

struct QuasiStaticRun {
  SolveResult result;
  ContactState state;
};

// The same load path (half the load, then the load: a warm start) with the outer step on
// the emulated device or on the CPU (the cascade in rounds on both).
std::vector<QuasiStaticRun> quasi_static(const Patch& s, bool device, OuterPoint* resume_at_two = nullptr) {
  PeriodicHalfSpace hs(s.map.grid, 1.0);
  const ExponentialAdhesion adh(s.w, s.rho);
  QuasiStaticAdhesion::Options o;
  o.tolerance = 1e-10;
  o.cascade_rounds = true;
  QuasiStaticAdhesion host(hs, s.map.heights, adh, o);
  std::vector<QuasiStaticRun> out;
  ContactState st;
  for (double f : {0.5, 1.0}) {
    const Target t{Control::MeanPressure, f * s.load};
    QuasiStaticRun r;
    if (device) {
      qs::DeviceSteps b(hs, s.map.heights, o, host.near_stiffness());
      r.result = qs::solve(b, hs, adh, o, qs::JumpPrediction(host.self_stiffness(), adh), host.move_floor(), t, st,
                            nullptr);
    } else {
      r.result = host.solve(t, st);
    }
    r.state = st;
    out.push_back(r);
  }
  return out;
}

}  // namespace

TEST(DeviceCode, QuasiStaticOuterStepMatchesTheHost) {
  Patch s;
  const auto host = quasi_static(s, false), dev = quasi_static(s, true);
  for (std::size_t k = 0; k < host.size(); ++k) {
    const QuasiStaticRun &a = host[k], &b = dev[k];
    ASSERT_TRUE(a.result.converged) << a.result.message;
    ASSERT_TRUE(b.result.converged) << b.result.message;
    const double dg = max_difference(a.state.gap, b.state.gap);
    std::printf("    [device code] quasi-static step %zu: outer %d / %d, iterations %d / %d, FFT pairs %.1f / %.1f, "
                "contact %ld / %ld, max dg %.3g rho\n",
                k, a.result.diagnostics.outer_iterations, b.result.diagnostics.outer_iterations, a.result.iterations,
                b.result.iterations, a.result.fft_pairs, b.result.fft_pairs, contact(a.state.gap), contact(b.state.gap),
                dg / s.rho);
    EXPECT_EQ(contact(a.state.gap), contact(b.state.gap)) << "step " << k;
    EXPECT_LT(dg, 2e-2 * s.rho) << "step " << k;
    EXPECT_NEAR(a.state.mean_pressure, b.state.mean_pressure, 1e-9 * s.load) << "step " << k;
    EXPECT_NEAR(a.state.penetration, b.state.penetration, 2e-2 * s.rho) << "step " << k;
    // The displacement: the device's w − h against the host's u − G t.
    const double du = max_difference(a.state.displacement, b.state.displacement);
    EXPECT_LT(du, 2e-2 * s.rho) << "step " << k;
    EXPECT_GT(b.result.fft_pairs, 0.0) << "the device's transforms are counted";
  }
  EXPECT_GT(contact(dev.back().state.gap), 0);
}

// A checkpoint inside a step (OuterPoint::fetch copies the device's tension and pressure
// down) and the continued solve (start_from uploads them) give the uninterrupted solve's
// bits: what a resumed GPU run relies on.
TEST(DeviceCode, QuasiStaticContinuesFromAnOuterStep) {
  Patch s;
  PeriodicHalfSpace hs(s.map.grid, 1.0);
  const ExponentialAdhesion adh(s.w, s.rho);
  QuasiStaticAdhesion::Options o;
  o.tolerance = 1e-10;
  const QuasiStaticAdhesion host(hs, s.map.heights, adh, o);
  const qs::JumpPrediction jump(host.self_stiffness(), adh);
  const Target t{Control::MeanPressure, s.load};
  auto solve = [&](const QuasiStaticAdhesion::Options& opt, ContactState& st, OuterPoint* from) {
    qs::DeviceSteps b(hs, s.map.heights, opt, host.near_stiffness());
    return qs::solve(b, hs, adh, opt, jump, host.move_floor(), t, st, from);
  };
  ContactState whole;
  const SolveResult a = solve(o, whole, nullptr);
  ASSERT_TRUE(a.converged) << a.message;
  ASSERT_GT(a.diagnostics.outer_iterations, 3);

  OuterPoint kept;
  QuasiStaticAdhesion::Options stop = o;
  stop.max_outer = 3;  // on_outer follows outer steps 1 and 2 (not the last)
  stop.on_outer = [&](const OuterPoint& at) {
    ASSERT_TRUE(at.fetch) << "the fields live on the device";
    if (at.outer != 2) return;
    EXPECT_TRUE(at.tension.empty()) << "copied down only when asked";
    at.fetch();
    kept.outer = at.outer, kept.tension = at.tension, kept.inner = at.inner, kept.so_far = at.so_far;
  };
  ContactState first;
  solve(stop, first, nullptr);
  ASSERT_EQ(kept.outer, 2);
  ASSERT_EQ(kept.tension.size(), whole.gap.size());
  ContactState rest;
  const SolveResult b = solve(o, rest, &kept);
  ASSERT_TRUE(b.converged) << b.message;
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.diagnostics.outer_iterations, b.diagnostics.outer_iterations);
  EXPECT_EQ(whole.penetration, rest.penetration);
  EXPECT_EQ(max_difference(whole.gap, rest.gap), 0.0);
  EXPECT_EQ(max_difference(whole.pressure, rest.pressure), 0.0);
  EXPECT_EQ(max_difference(whole.displacement, rest.displacement), 0.0);
}

// The resolved adhesive sinusoid on a line (ny = 1: the stencil's aliased offsets, the
// device's rounds' wrap) under displacement control, through the jump into contact
// (cases/validation/johnson-alpha03-loading.toml; the gpu test JohnsonSinusoidLoading runs
// it through the case on a GPU): every step converges, with the same points in contact as
// the CPU's rounds and the mean pressure within the solves' tolerance (1e-8) of w/ρ: two
// solves each converged to it agree within it, and how closely depends on the FFT plans'
// rounding (measured over five plan sets, CMC_FFTW_PLANNER builtin from two plannings,
// estimate, measure, patient: 4.4e-10 to 1.9e-9).
TEST(DeviceCode, QuasiStaticOnALineUnderDisplacementControl) {
  const Case c = load_case(std::string(CMC_SOURCE_DIR) + "/cases/validation/johnson-alpha03-loading.toml");
  ASSERT_EQ(c.grid.ny, 1);
  Scene s = build_scene(c);
  ASSERT_EQ(s.targets.front().control, Control::Penetration);
  const auto& adh = std::get<ExponentialAdhesion>(s.interaction);
  QuasiStaticAdhesion::Options o;
  o.tolerance = 1e-8;
  o.cascade_rounds = true;
  QuasiStaticAdhesion host(*s.half_space, s.topography.heights, adh, o);
  const qs::JumpPrediction jump(host.self_stiffness(), adh);
  ContactState a, b;
  double worst = 0.0;
  bool jumped = false;
  for (const Target& t : s.targets) {
    const SolveResult ra = host.solve(t, a);
    qs::DeviceSteps steps(*s.half_space, s.topography.heights, o, host.near_stiffness());
    const SolveResult rb = qs::solve(steps, *s.half_space, adh, o, jump, host.move_floor(), t, b, nullptr);
    ASSERT_TRUE(ra.converged) << ra.message;
    ASSERT_TRUE(rb.converged) << rb.message;
    EXPECT_EQ(contact(a.gap), contact(b.gap));
    worst = std::max(worst, std::abs(a.mean_pressure - b.mean_pressure));
    jumped = jumped || contact(b.gap) > 0;
  }
  std::printf("    [device code] line: mean pressure, device vs host / (w/rho): %.3g\n", worst / adh.peak_tension());
  EXPECT_LE(worst, o.tolerance * adh.peak_tension());
  EXPECT_TRUE(jumped) << "the path should reach contact";
}
