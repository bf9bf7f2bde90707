// Kernel benchmarks: one FFT pair (the floor) and one Polonsky–Keer iteration on the
// peer's problem (periodic self-affine surface, H = 0.8, roll-off L/5, short cutoff 4
// grid spacings, rms gradient 1, mean pressure 0.01 E*), at 512² … 4096².
// The ratio that matters (iteration time / FFT-pair time) is read off the same run;
// scripts/bench_solve.py prints it side by side. Set CMC_THREADS to choose threads.
#include "cmc/contact/PolonskyKeer.hpp"
#include "cmc/surface/SelfAffine.hpp"

#include <benchmark/benchmark.h>

using namespace cmc;

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
static void BM_PolonskyKeerIteration(benchmark::State& state) {
  const int n = int(state.range(0));
  SelfAffineSpec spec;
  spec.cutoff_wavelength = 4.0 / n;
  spec.seed = 7;
  const auto surf = generate_self_affine(spec, n);
  PeriodicHalfSpace hs(surf.map.grid, 1.0);
  PolonskyKeer::Options o;
  o.tolerance = 0.0;  // never converge: run exactly max_iterations
  o.max_iterations = 20;
  PolonskyKeer pk(hs, surf.map.heights, o);
  double pairs = 0;
  long iterations = 0;
  for (auto _ : state) {
    ContactState st;
    const auto r = pk.solve({Control::MeanPressure, 0.01}, st);
    pairs += r.fft_pairs;
    iterations += r.iterations;
  }
  state.SetItemsProcessed(iterations);  // items/s = iterations per second
  state.counters["fft_pairs_per_iteration"] = double(pairs) / double(iterations);
}

BENCHMARK(BM_FFTPair)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PolonskyKeerIteration)->Arg(512)->Arg(1024)->Arg(2048)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
