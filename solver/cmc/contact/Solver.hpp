// What every cmc solver takes and returns.
//
// A solver is handed a half-space, the indenter heights and a load target, and it
// returns a SolveResult: whether it reached its tolerance, after how many
// iterations, the residual it stopped at, the energy, the wall time and the number
// of FFT pairs (the unit of cost cmc reports against). A solve that stops before its
// tolerance says so (converged = false, and a message); it never throws for that.
#pragma once

#include "cmc/grid/Grid.hpp"

#include <chrono>
#include <functional>
#include <limits>
#include <string>

namespace cmc {

// What a solve did on the way, beyond its iteration count (0 for events a solver does
// not have).
struct SolveDiagnostics {
  int restarts = 0;            // directions reset to steepest descent
  int backtracks = 0;          // rejected trial steps (energy increase)
  int negative_curvature = 0;  // trust steps along negative curvature
  int clipped_steps = 0;       // steps where the projection on the constraints acted
  int exact_recomputes = 0;    // elastic response recomputed from scratch (one more FFT pair)
  int outer_iterations = 0;    // inner solves of an outer load-control search
  SolveDiagnostics& operator+=(const SolveDiagnostics& o) {
    restarts += o.restarts, backtracks += o.backtracks, negative_curvature += o.negative_curvature;
    clipped_steps += o.clipped_steps, exact_recomputes += o.exact_recomputes, outer_iterations += o.outer_iterations;
    return *this;
  }
};

struct SolveResult {
  bool converged = false;
  int iterations = 0;
  double residual = std::numeric_limits<double>::quiet_NaN();
  double energy = 0.0;  // elastic energy (+ interaction energy, where there is one), reduced
  double wall_s = 0.0;
  double fft_pairs = 0.0;  // (forward + inverse transforms) / 2
  double fft_s = 0.0;      // seconds of wall_s spent inside those transforms
  std::string message;  // why it stopped, when it did not converge
  SolveDiagnostics diagnostics;
};

// Seconds of the steady clock (a deadline's unit: PolonskyKeer::Options::stop_at).
inline double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The cost of one solve, measured from construction: wall time, and the FFT pairs of an
// operator (anything with fft_pairs() and fft_seconds(), e.g. the HalfSpace) and the
// seconds spent in them. finish() stamps a result.
template <class Operator>
class SolveClock {
 public:
  explicit SolveClock(const Operator& op)
      : op_(op), pairs0_(op.fft_pairs()), fft_s0_(op.fft_seconds()), t0_(std::chrono::steady_clock::now()) {}
  SolveResult finish(SolveResult& r, bool converged, std::string message) const {
    r.converged = converged;
    r.message = std::move(message);
    r.fft_pairs = op_.fft_pairs() - pairs0_;
    r.fft_s = op_.fft_seconds() - fft_s0_;
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    return r;
  }
  // The FFT pairs, the seconds inside them and the seconds since construction.
  double pairs() const { return op_.fft_pairs() - pairs0_; }
  double fft_seconds() const { return op_.fft_seconds() - fft_s0_; }
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }

 private:
  const Operator& op_;
  double pairs0_, fft_s0_;
  std::chrono::steady_clock::time_point t0_;
};

// Transforms a solve runs outside the half-space's own (the CPU's fused sweeps, the GPU's
// cuFFT): how many forward and inverse, and the seconds inside them.
struct TransformCounts {
  long forward = 0, inverse = 0;
  double seconds = 0.0;
};
// Counts them with an operator (count_transforms(), e.g. the HalfSpace) over its lifetime,
// so that they show in the solve's FFT pairs: `read` gives the transforms' counts so far.
template <class Operator>
class TransformTally {
 public:
  TransformTally(Operator& op, std::function<TransformCounts()> read)
      : op_(op), read_(std::move(read)), start_(read_()) {}
  ~TransformTally() {
    const TransformCounts now = read_();
    op_.count_transforms(now.forward - start_.forward, now.inverse - start_.inverse, now.seconds - start_.seconds);
  }
  TransformTally(const TransformTally&) = delete;
  TransformTally& operator=(const TransformTally&) = delete;

 private:
  Operator& op_;
  std::function<TransformCounts()> read_;
  TransformCounts start_;
};

// The solved state of one load step (reduced units). Also the warm start of the next.
struct ContactState {
  Field pressure;      // p, compressive > 0
  Field displacement;  // u, into the solid > 0
  Field gap;           // g = h − δ + u, projected on the constraints (0 in contact, ≥ 0)
  double penetration = 0.0;    // δ: rigid-body approach of the indenter
  double mean_pressure = 0.0;  // mean of p over the grid
  bool empty() const { return pressure.empty(); }
};

// Which scalar a load step fixes. Force and mean gap are converted to these two by
// the scene (force = mean pressure x area; mean gap = <h> − δ on a periodic grid).
enum class Control { MeanPressure, Penetration };
struct Target {
  Control control;
  double value;
};

// Progress report hook; the solver never prints. A point: the iterations so far and the
// residual. For a solver with outer steps (the quasi-static solver) `outer` counts them:
// after outer step `outer` the residual is its tension change; with `inner` set the solve
// of outer step `outer` is under way and the residual is that inner (Polonsky-Keer) solve's,
// so that a long first solve (minutes on 8192²) shows it is alive. `outer` is 0 for the
// other solvers.
// `energy`: the objective the solver lowers, where it reports one (the adhesive CG: elastic
// plus interaction energy, grid sums), else NaN.
struct ProgressPoint {
  int iteration = 0;
  double residual = 0.0;
  int outer = 0;
  bool inner = false;
  double energy = std::numeric_limits<double>::quiet_NaN();
};
using Progress = std::function<void(const ProgressPoint&)>;

struct SolverOptions {
  double tolerance = 1e-10;  // on the solver's residual (see each solver)
  int max_iterations = 2000;
  Progress progress;          // optional
  int progress_every = 25;
};

}  // namespace cmc
