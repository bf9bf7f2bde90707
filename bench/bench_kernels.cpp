// Kernel benchmarks: one FFT pair (the floor) and one Polonsky–Keer iteration, at 512² …
// 4096², with the stiffness preconditioner (the default) and without (/plain).
//
// The iteration runs on the ContactMechanics comparison surface: the problem on which
// ContactMechanics (the Pastewka group's Python contact stack, Polonsky–Keer CG), the tool
// most users would otherwise reach for, was timed on a 2-core machine like ours (132
// iterations and 148 s at 2048²; docs/performance.md, "Against ContactMechanics"), so that
// cmc's iterations can be set beside those. It is a periodic self-affine surface of side L on
// n² points (the challenge's generator, surface/SelfAffine.hpp) with Hurst exponent H = 0.8,
// roll-off wavelength L/5, short-wavelength cutoff 4 grid spacings (4L/n: every grid resolves
// its finest wavelength alike), rms gradient ḡ = 1, pressed by a hard wall to a mean
// pressure of 0.01 E* ḡ. scripts/bench_solvers.sh runs the same surface through `cmc run`
// (its runs named hardwall-peer).
// Every iteration benchmark times an FFT pair of its own grid in the same run (fft_pair_ms)
// and reports the ratios that matter: iteration_over_fft_pair (time of one iteration in
// units of that pair) and time_per_fft_pair (the same divided by the iteration's FFT
// pairs: 1 would be a solver that does nothing but transforms), and the same against the
// faster of FFTW's pair and cmc's row-column pair (_floor_pair; bench_common.hpp). Set
// CMC_THREADS to choose threads.
#include "bench_common.hpp"
#include "cmc/contact/polonsky_keer/PolonskyKeer.hpp"
#include "cmc/grid/RowColumnFourier.hpp"
#include "cmc/surface/SelfAffine.hpp"

#include <benchmark/benchmark.h>

using namespace cmc;
using namespace cmc::bench;

static void BM_FFTPair(benchmark::State& state) {
  const int n = int(state.range(0));
  Fourier f(n, n);
  Field x(std::size_t(n) * n, 1.0), y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.001 * double(i));
  for (auto _ : state) {
    f.forward(x);
    f.inverse(y);
    benchmark::DoNotOptimize(y.data());
  }
  state.SetLabel("r2c + c2r");
}

// The same pair made of 1-D transforms by rows and column blocks (RowColumnFourier, the
// Polonsky-Keer iteration's transform on periodic grids), with nothing fused into it.
static void BM_RowColumnPair(benchmark::State& state) {
  const int n = int(state.range(0));
  RowColumnFourier f(n, n);
  Field x(std::size_t(n) * n, 1.0), y(x.size());
  Spectrum s(f.spectrum_size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.001 * double(i));
  for (auto _ : state) {
    f.pair(x.data(), s.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
  state.SetLabel("rows + column blocks");
}

// Time per iteration: solves capped at 10 and at 30 iterations, warm-started from the same
// converged state at a 10 % lower load (so the iterations are those of a solve, not of
// PK's cold uniform guess); the counters are the 20 iterations between them, and the
// shorter solve's time beyond its iterations is setup_ms (MarginalCost, bench_common.hpp).
// One solve of 20 iterations over its iterations would count the setup and the final pass
// too (setup_ms at 2048², plain, measured 59.6 and 63.2 ms a solve: about 3 ms of each of
// the 20 iterations).
static void pk_iteration(benchmark::State& state, bool precondition, bool fused = true) {
  const int n = int(state.range(0));
  SelfAffineSpec spec;  // the ContactMechanics comparison surface (top of this file)
  spec.cutoff_wavelength = 4.0 / n;
  spec.seed = 7;
  const auto surf = generate_self_affine(spec, n);
  PeriodicHalfSpace hs(surf.map.grid, 1.0);
  PolonskyKeer::Options o;
  o.precondition = precondition;
  o.fused_sweeps = fused;
  o.tolerance = 1e-8;
  ContactState warm;
  PolonskyKeer(hs, surf.map.heights, o).solve({Control::MeanPressure, 0.01}, warm);  // not timed
  o.tolerance = 0.0;  // never converge: run exactly max_iterations
  o.max_iterations = 10;
  PolonskyKeer short_solve(hs, surf.map.heights, o);
  o.max_iterations = 30;
  PolonskyKeer long_solve(hs, surf.map.heights, o);
  MarginalCost cost;
  for (auto _ : state) {
    ContactState a = warm;
    cost.add_a(short_solve.solve({Control::MeanPressure, 0.011}, a));
    ContactState b = warm;
    cost.add_b(long_solve.solve({Control::MeanPressure, 0.011}, b));
  }
  cost.report(state, pair_times(n));
}
static void BM_PolonskyKeerIteration(benchmark::State& state) { pk_iteration(state, true); }
static void BM_PolonskyKeerIteration_plain(benchmark::State& state) { pk_iteration(state, false); }
// The same with the passes and FFTW's 2-D transforms one after the other
// (Options::fused_sweeps off): what the fused sweeps save.
static void BM_PolonskyKeerIteration_unfused(benchmark::State& state) { pk_iteration(state, true, false); }
static void BM_PolonskyKeerIteration_plain_unfused(benchmark::State& state) { pk_iteration(state, false, false); }

BENCHMARK(BM_FFTPair)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RowColumnPair)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PolonskyKeerIteration)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_PolonskyKeerIteration_plain)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_PolonskyKeerIteration_unfused)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_PolonskyKeerIteration_plain_unfused)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
