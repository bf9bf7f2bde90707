// Adhesive CG benchmarks on a rough patch: the challenge's surface family (H = 0.8,
// roll-off L/5, rms gradient 1) at n² with the short cutoff at 4 grid spacings, and the
// challenge's dimensionless adhesion on the grid scale: range ρ = Δx/0.75 (the challenge's
// reference runs had Δx = 0.75 ρ) and peak tension w/ρ = 0.97 E*, so w Δx/(E* ρ²) = 0.73
// (no bistable grid point). The penetration is min h + 1 rms height (about 1 % of the
// 1024² patch and 4 % of the 256² patch end up in contact).
//
//  * BM_AdhesiveIteration: solves capped at 10 and at 40 iterations from the same warm
//    state; reports the 30 iterations between them (bench_common.hpp, MarginalCost): ms
//    per iteration, FFT pairs per iteration, the FFT-pair times measured in the same run
//    and their ratios.
//  * BM_AdhesiveStep: one displacement step of a load path (δ → δ + 1 % of the rms
//    height) from the previous solution to tolerance 1e-6: iterations and FFT pairs per
//    step, ms per iteration.
// The warm state is prepared once per size (a cold solve, not timed).
//
//  * BM_QuasiStaticSolve: the main job's adhesive solve, cases/challenge/reference-load.toml
//    (the challenge at 250 kPa, μ_T = 3, the quasi-static loading-branch solver) at n²:
//    iterations (Polonsky–Keer's, summed over the outer steps), FFT pairs, outer steps and
//    the same ratios as the kernels (bench_common.hpp). Its time per FFT pair above the
//    Polonsky–Keer kernel's is the outer loop: jump prediction, cascade, tension update.
// Set CMC_THREADS to choose threads.
#include "bench_common.hpp"
#include "cmc/contact/adhesive_cg/AdhesiveSolver.hpp"
#include "cmc/contact/quasi_static/QuasiStaticAdhesion.hpp"
#include "cmc/input/Case.hpp"
#include "cmc/scene/Scene.hpp"
#include "cmc/surface/SelfAffine.hpp"
#include "cmc/surface/SurfaceStats.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>

using namespace cmc;
using namespace cmc::bench;

namespace {

struct Problem {
  SelfAffineSurface surf;
  std::unique_ptr<PeriodicHalfSpace> hs;
  std::unique_ptr<AdhesiveSolver> solver;
  ContactState warm;
  double delta = 0.0, step = 0.0;
  SolveResult warm_result;
};

Problem& problem(int n) {
  static std::map<int, std::unique_ptr<Problem>> cache;
  auto& p = cache[n];
  if (p) return *p;
  p = std::make_unique<Problem>();
  SelfAffineSpec spec;
  spec.cutoff_wavelength = 4.0 / n;
  spec.seed = 7;
  p->surf = generate_self_affine(spec, n);
  const Grid& g = p->surf.map.grid;
  const auto stats = surface_statistics(g, p->surf.map.heights);
  p->hs = std::make_unique<PeriodicHalfSpace>(g, 1.0);
  const double rho = g.dx() / 0.75, w = 0.97 * rho;
  AdhesiveSolver::Options o;
  o.tolerance = 1e-6;
  o.max_iterations = 20000;
  p->solver = std::make_unique<AdhesiveSolver>(*p->hs, p->surf.map.heights, ExponentialAdhesion(w, rho), o);
  p->delta = stats.min + 1.0 * stats.rms_height;
  p->step = 0.01 * stats.rms_height;
  p->warm_result = p->solver->solve({Control::Penetration, p->delta}, p->warm);
  return *p;
}

}  // namespace

static void BM_AdhesiveIteration(benchmark::State& state) {
  const int n = int(state.range(0));
  Problem& p = problem(n);
  auto& opt = p.solver->options();
  const auto saved = opt;
  opt.tolerance = 0.0;  // never converge: run exactly max_iterations
  MarginalCost cost;
  for (auto _ : state) {
    opt.max_iterations = 10;
    ContactState a = p.warm;
    cost.add_a(p.solver->solve({Control::Penetration, p.delta + p.step}, a));
    opt.max_iterations = 40;
    ContactState b = p.warm;
    cost.add_b(p.solver->solve({Control::Penetration, p.delta + p.step}, b));
  }
  opt = saved;
  cost.report(state, pair_times(n));
  state.counters["warm_solve_iterations"] = p.warm_result.iterations;
  state.counters["contact_fraction_percent"] = [&] {
    double c = 0;
    for (double x : p.warm.gap) c += x <= 0.0;
    return 100.0 * c / double(p.warm.gap.size());
  }();
}

static void BM_AdhesiveStep(benchmark::State& state) {
  const int n = int(state.range(0));
  Problem& p = problem(n);
  double pairs = 0, seconds = 0;
  long iterations = 0, steps = 0;
  bool all_converged = true;
  for (auto _ : state) {
    ContactState st = p.warm;
    const auto r = p.solver->solve({Control::Penetration, p.delta + p.step}, st);
    all_converged = all_converged && r.converged;
    pairs += r.fft_pairs;
    iterations += r.iterations;
    seconds += r.wall_s;
    ++steps;
  }
  state.counters["iterations_per_step"] = double(iterations) / double(steps);
  state.counters["fft_pairs_per_step"] = pairs / double(steps);
  state.counters["ms_per_iteration"] = 1e3 * seconds / double(iterations);
  state.counters["converged"] = all_converged ? 1.0 : 0.0;
}

static void BM_QuasiStaticSolve(benchmark::State& state) {
  const int n = int(state.range(0));
  const std::string file = std::string(CMC_SOURCE_DIR) + "/cases/challenge/reference-load.toml";
  const Case c = load_case(file, {"grid.n=" + std::to_string(n)});
  const Scene s = build_scene(c);
  QuasiStaticAdhesion::Options o;
  o.tolerance = c.solver.tolerance;
  o.max_iterations = c.solver.max_iterations;
  o.tension_tolerance = c.solver.tension_tolerance;
  QuasiStaticAdhesion solver(*s.half_space, s.topography.heights, std::get<ExponentialAdhesion>(s.interaction), o);
  IterationCost cost;
  int outer = 0;
  bool converged = true;
  double contact = 0.0;
  for (auto _ : state) {
    ContactState st;
    const SolveResult r = solver.solve(s.targets.at(0), st);
    cost.add(r);
    outer += r.diagnostics.outer_iterations;
    converged = converged && r.converged;
    contact = double(Grid::count_if(st.gap, [](double g) { return g <= 0.0; })) / double(st.gap.size());
  }
  cost.report(state, pair_times(n));
  state.counters["outer_steps"] = outer / double(state.iterations());
  state.counters["fft_pairs_per_solve"] = cost.pairs / double(state.iterations());
  state.counters["converged"] = converged ? 1.0 : 0.0;
  state.counters["contact_fraction"] = contact;
}

BENCHMARK(BM_QuasiStaticSolve)->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_AdhesiveIteration)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_AdhesiveStep)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
