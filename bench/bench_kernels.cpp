// Kernel benchmarks: one FFT pair (the floor) and one Polonsky–Keer iteration on the
// peer's problem (periodic self-affine surface, H = 0.8, roll-off L/5, short cutoff 4
// grid spacings, rms gradient 1, mean pressure 0.01 E*), at 512² … 4096², with the
// stiffness preconditioner (the default) and without (/plain).
// Every iteration benchmark times an FFT pair of its own grid in the same run (fft_pair_ms)
// and reports the ratios that matter: iteration_over_fft_pair (time of one iteration in
// units of that pair) and time_per_fft_pair (the same divided by the iteration's FFT
// pairs: 1 would be a solver that does nothing but transforms). Set CMC_THREADS to choose
// threads.
#include "bench_common.hpp"
#include "cmc/contact/PolonskyKeer.hpp"
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

// Time per iteration: a solve capped at a fixed number of iterations from the same
// start, so every benchmark repetition does identical work.
// Time per iteration: a solve capped at a fixed number of iterations, warm-started from
// the same converged state at a 10 % higher load (so the iterations are those of a solve,
// not of PK's cold uniform guess), setup and the final recompute included.
static void pk_iteration(benchmark::State& state, bool precondition) {
  const int n = int(state.range(0));
  SelfAffineSpec spec;
  spec.cutoff_wavelength = 4.0 / n;
  spec.seed = 7;
  const auto surf = generate_self_affine(spec, n);
  PeriodicHalfSpace hs(surf.map.grid, 1.0);
  PolonskyKeer::Options o;
  o.precondition = precondition;
  o.tolerance = 1e-8;
  ContactState warm;
  PolonskyKeer(hs, surf.map.heights, o).solve({Control::MeanPressure, 0.01}, warm);  // not timed
  o.tolerance = 0.0;  // never converge: run exactly max_iterations
  o.max_iterations = 20;
  PolonskyKeer pk(hs, surf.map.heights, o);
  IterationCost cost;
  for (auto _ : state) {
    ContactState st = warm;
    cost.add(pk.solve({Control::MeanPressure, 0.011}, st));
  }
  cost.report(state, fft_pair_ms(n));
}
static void BM_PolonskyKeerIteration(benchmark::State& state) { pk_iteration(state, true); }
static void BM_PolonskyKeerIteration_plain(benchmark::State& state) { pk_iteration(state, false); }

BENCHMARK(BM_FFTPair)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PolonskyKeerIteration)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_PolonskyKeerIteration_plain)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
