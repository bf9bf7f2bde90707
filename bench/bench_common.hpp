// What the iteration benchmarks share: the FFT pairs of the benchmark's own grid timed in
// the same run, and the counters that put an iteration's time in units of them.
//
// Two pairs are timed: FFTW's 2-D r2c + c2r (Fourier; `fft_pair_ms`, the first yardstick)
// and cmc's own row-column pair (RowColumnFourier, the transforms
// the Polonsky-Keer iteration runs on a periodic grid; `row_column_pair_ms`). Which one is
// faster depends on the grid and on the plan FFTW's timing picked when the build made its
// wisdom; `floor_pair_ms` is the faster of the two, the strictest yardstick this run has,
// and the `_floor_pair` ratios divide by it. (On the 2-core machine a single timing of
// FFTW's 2-D pair at 2048² moved between 16.5 and 30.9 ms across runs of one build, which
// moved the old ratios by as much; the row-column pair stayed within 13.7-15.7 ms in the
// same runs.)
#pragma once

#include "cmc/contact/Solver.hpp"
#include "cmc/grid/Grid.hpp"
#include "cmc/grid/RowColumnFourier.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

namespace cmc::bench {

// Milliseconds of the fastest of 5 means of 4 calls of pair(), after one untimed call
// (plans made, pages touched).
template <class Pair>
double best_pair_ms(Pair&& pair) {
  pair();
  double best = HUGE_VAL;
  for (int rep = 0; rep < 5; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < 4; ++k) pair();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / 4);
  }
  return 1e3 * best;
}

// One r2c + c2r pair on an n × n grid: FFTW's 2-D transforms (Fourier).
inline double fft_pair_ms(int n) {
  Fourier f(n, n);
  Field x(std::size_t(n) * std::size_t(n)), y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.001 * double(i));
  const double ms = best_pair_ms([&] {
    f.forward(x);
    f.inverse(y);
  });
  benchmark::DoNotOptimize(y.data());
  return ms;
}

// The same pair as rows and column blocks (RowColumnFourier::pair), nothing fused into it.
inline double row_column_pair_ms(int n) {
  RowColumnFourier f(n, n);
  Field x(std::size_t(n) * std::size_t(n)), y(x.size());
  Spectrum s(f.spectrum_size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.001 * double(i));
  const double ms = best_pair_ms([&] { f.pair(x.data(), s.data(), y.data()); });
  benchmark::DoNotOptimize(y.data());
  return ms;
}

struct PairTimes {
  double fftw_ms = 0.0, row_column_ms = 0.0;
  double floor_ms() const { return std::min(fftw_ms, row_column_ms); }
};
inline PairTimes pair_times(int n) {
  PairTimes p;
  p.fftw_ms = fft_pair_ms(n);
  p.row_column_ms = row_column_pair_ms(n);
  return p;
}

// The counters of an iteration that took ms_it milliseconds and made pairs_it FFT pairs,
// fft_ms_it of its milliseconds inside the transforms (the passes fused into them
// included).
inline void report_ratios(benchmark::State& state, double ms_it, double pairs_it, double fft_ms_it,
                          const PairTimes& pair) {
  state.counters["ms_per_iteration"] = ms_it;
  state.counters["fft_pairs_per_iteration"] = pairs_it;
  state.counters["fft_pair_ms"] = pair.fftw_ms;
  state.counters["row_column_pair_ms"] = pair.row_column_ms;
  state.counters["floor_pair_ms"] = pair.floor_ms();
  // Time of one iteration in units of a pair, and the same divided by the iteration's
  // FFT pairs (1 would be a solver that does nothing but transforms).
  state.counters["iteration_over_fft_pair"] = ms_it / pair.fftw_ms;
  state.counters["time_per_fft_pair"] = pairs_it > 0.0 ? ms_it / (pairs_it * pair.fftw_ms) : 0.0;
  state.counters["iteration_over_floor_pair"] = ms_it / pair.floor_ms();
  state.counters["time_per_floor_pair"] = pairs_it > 0.0 ? ms_it / (pairs_it * pair.floor_ms()) : 0.0;
  // Where the time goes: the share inside the transforms, and the solver's own transforms
  // timed against FFTW's pair measured alone (above 1: they ran slower than it).
  state.counters["fft_share"] = ms_it > 0.0 ? fft_ms_it / ms_it : 0.0;
  state.counters["own_pair_over_fft_pair"] = pairs_it > 0.0 ? fft_ms_it / (pairs_it * pair.fftw_ms) : 0.0;
}

// Sums of the solves of one benchmark, and the counters made from them: a whole solve's
// time over its iterations (setup and outer steps included), for solves that are the
// thing measured (BM_QuasiStaticSolve).
struct IterationCost {
  double pairs = 0.0, seconds = 0.0, fft_seconds = 0.0;
  long iterations = 0;
  void add(const SolveResult& r) {
    pairs += r.fft_pairs;
    seconds += r.wall_s;
    fft_seconds += r.fft_s;
    iterations += r.iterations;
  }
  void report(benchmark::State& state, const PairTimes& pair) const {
    const double it = double(std::max(1L, iterations));
    state.SetItemsProcessed(iterations);  // items/s = iterations per second
    report_ratios(state, 1e3 * seconds / it, pairs / it, 1e3 * fft_seconds / it, pair);
  }
};

// The cost of an iteration inside a solve's loop, without the solve's setup (work arrays,
// the heights' transform, the start's exact pair) and its final pass: solves of a and of
// b > a iterations from the same start, each kept as the fastest of the benchmark's
// repetitions (the same iterations and FFT pairs every time: a rerun gives the same bits).
// Per iteration: (t_b − t_a)/(b − a), and the same for FFT pairs and transform seconds;
// setup_ms is what a solve costs beyond its iterations, t_a − a × that. Differences of
// two timings carry the noise of both: on a loaded machine fft_share can come out above 1.
struct MarginalCost {
  std::optional<SolveResult> fastest_a, fastest_b;
  static void keep(std::optional<SolveResult>& best, const SolveResult& r) {
    if (!best || r.wall_s < best->wall_s) best = r;
  }
  void add_a(const SolveResult& r) { keep(fastest_a, r); }
  void add_b(const SolveResult& r) { keep(fastest_b, r); }
  void report(benchmark::State& state, const PairTimes& pair) const {
    if (!fastest_a || !fastest_b || fastest_b->iterations <= fastest_a->iterations) {
      state.SkipWithError("the longer solve did not run more iterations than the shorter one");
      return;
    }
    const SolveResult &a = *fastest_a, &b = *fastest_b;
    const int di = b.iterations - a.iterations;
    const double ms_it = 1e3 * (b.wall_s - a.wall_s) / di;
    report_ratios(state, ms_it, (b.fft_pairs - a.fft_pairs) / di, 1e3 * (b.fft_s - a.fft_s) / di, pair);
    state.counters["setup_ms"] = 1e3 * a.wall_s - a.iterations * ms_it;
    state.counters["clipped_per_iteration"] =
        double(b.diagnostics.clipped_steps - a.diagnostics.clipped_steps) / di;
    state.counters["iterations_measured"] = di;
    state.SetItemsProcessed(long(state.iterations()) * (a.iterations + b.iterations));
  }
};

}  // namespace cmc::bench
