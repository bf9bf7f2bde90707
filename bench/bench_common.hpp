// What the iteration benchmarks share: an FFT pair of the benchmark's own grid timed in
// the same run, and the counters that put an iteration's time in units of it.
#pragma once

#include "cmc/contact/Solver.hpp"
#include "cmc/grid/Grid.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace cmc::bench {

// Milliseconds of one r2c + c2r pair on an n × n grid: the fastest of 5 means of 4 pairs,
// after one untimed pair (plans made, pages touched).
inline double fft_pair_ms(int n) {
  Fourier f(n, n);
  Field x(std::size_t(n) * std::size_t(n)), y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.001 * double(i));
  f.forward(x);
  f.inverse(y);
  double best = HUGE_VAL;
  for (int rep = 0; rep < 5; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < 4; ++k) {
      f.forward(x);
      f.inverse(y);
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / 4);
  }
  benchmark::DoNotOptimize(y.data());
  return 1e3 * best;
}

// Sums of the solves of one benchmark, and the counters made from them.
struct IterationCost {
  double pairs = 0.0, seconds = 0.0, fft_seconds = 0.0;
  long iterations = 0;
  void add(const SolveResult& r) {
    pairs += r.fft_pairs;
    seconds += r.wall_s;
    fft_seconds += r.fft_s;
    iterations += r.iterations;
  }
  void report(benchmark::State& state, double pair_ms) const {
    const double it = double(std::max(1L, iterations)), ms_it = 1e3 * seconds / it, pairs_it = pairs / it;
    state.SetItemsProcessed(iterations);  // items/s = iterations per second
    state.counters["ms_per_iteration"] = ms_it;
    state.counters["fft_pairs_per_iteration"] = pairs_it;
    state.counters["fft_pair_ms"] = pair_ms;
    state.counters["iteration_over_fft_pair"] = ms_it / pair_ms;
    state.counters["time_per_fft_pair"] = pairs_it > 0.0 ? ms_it / (pairs_it * pair_ms) : 0.0;
    // Where the time goes: the share inside the transforms, and the solver's own transforms
    // timed against the pair measured alone (above 1: they ran slower than the floor).
    state.counters["fft_share"] = seconds > 0.0 ? fft_seconds / seconds : 0.0;
    state.counters["own_pair_over_fft_pair"] = pairs > 0.0 ? 1e3 * fft_seconds / (pairs * pair_ms) : 0.0;
  }
};

}  // namespace cmc::bench
