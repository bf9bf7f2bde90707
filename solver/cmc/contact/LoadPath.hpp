// Load paths: a sequence of load targets (loading, unloading, or both) solved one after
// another, each step warm-started from the previous solution, with automatic step
// halving where a step fails or "jumps".
//
// Any solver can be used: it is passed as a callable (Target, ContactState&) ->
// SolveResult (e.g. a lambda around AdhesiveSolver::solve or PolonskyKeer::solve).
//
// Step control. Requested step k goes from the previous accepted target value v to v_k.
// It is first tried in one solve. If that solve does not converge, or the state "jumps"
// (below), the increment is halved and the step is walked in sub-steps of
// (v_k − v)/2^level from the last accepted sub-step, up to level = max_halvings. At the
// finest level a jump is accepted as real (an elastic instability: jump into contact,
// snap-off, a patch popping in or out) and recorded; a solve that still fails is
// recorded as failed and, with stop_on_failure, ends the path. The level is not raised
// again within a step.
//
// Jump (between two consecutive solves, previous → new), with f = jump_fraction:
//   |a_new − a_prev| > f · max(a_prev, contact_fraction_floor)             or
//   |p_new − p_prev| > f · max(|p_prev|, p_floor)
// a = contact fraction (ContactRule.hpp: fraction of points with a closed gap), p = mean pressure,
// p_floor = pressure_floor, or when that is 0 the largest |p| accepted so far on the path
// (a problem-independent default; give pressure_floor a physical scale, e.g. the
// pull-off pressure, when the path starts out of contact, where the tail of a finite-range
// interaction makes |p| tiny).
//
// What is recorded: one LoadStep per requested target, holding the state at exactly that
// target (sub-steps are solved but not recorded), the branch (Loading when the target
// value increases, i.e. pressing harder, Unloading when it decreases; the first step is
// Loading unless the start state says otherwise), whether a jump happened in any solve
// since the previous recorded step, the halving level reached, and the number of solves,
// iterations and FFT pairs spent on it. The pull-off is the most negative mean pressure of
// every converged solve of the path, sub-steps included (so that halving near the
// instability sharpens it), optionally sharpened further by refine_pulloff.
#pragma once

#include "cmc/contact/ContactRule.hpp"
#include "cmc/contact/Solver.hpp"

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace cmc {

// The branch of a load path a step is on. Its name ("loading" / "unloading") is
// written only by the Writer (output/Writer.cpp).
enum class Branch { Loading, Unloading };

using StepSolver = std::function<SolveResult(const Target&, ContactState&)>;

struct LoadPathOptions {
  int max_halvings = 5;
  double jump_fraction = 0.5;
  double contact_fraction_floor = 1e-3;
  double pressure_floor = 0.0;  // 0: the largest |mean pressure| accepted so far
  ContactRule contact_rule;     // what the contact fraction a counts
  bool stop_on_failure = true;
  // Pull-off refinement: when > 0 and the most negative mean pressure is at a sub-step with
  // accepted neighbours on both sides, up to this many extra solves do a golden-section
  // search for the minimum of the mean pressure between those neighbours, each warm-started
  // from the state at the best solve so far (the branch is kept). 0: off.
  int refine_pulloff = 0;
};

struct LoadStep {
  Target target{Control::Penetration, 0.0};
  Branch branch = Branch::Loading;
  SolveResult result;  // the solve that reached the target (its own iterations, pairs, message)
  double mean_pressure = 0.0;
  double penetration = 0.0;
  double contact_fraction = 0.0;
  bool jump = false;   // a jump happened in a solve since the previous recorded step
  int halvings = 0;    // halving level reached (0: reached in one solve)
  int solves = 0;      // solves spent on this step (retries and sub-steps included)
  int iterations = 0;  // their iterations, summed
  double fft_pairs = 0.0;  // their FFT pairs, summed
  double wall_s = 0.0;
  double fft_s = 0.0;      // their seconds inside the FFTs, summed
  SolveDiagnostics diagnostics;  // their diagnostics, summed
};

struct LoadPathResult {
  std::vector<LoadStep> steps;
  bool completed = false;  // every requested step reached with a converged solve
  std::string message;     // why not, when not
  int failed_steps = 0;    // recorded steps whose final solve did not converge
  int halved_steps = 0;    // recorded steps that needed halving
  int jumps = 0;           // recorded steps with a jump
  int max_halvings = 0;    // deepest level over the path
  // Pull-off: the most negative mean pressure of every converged solve (NaN if none).
  double pulloff_mean_pressure = 0.0;
  Target pulloff_target{Control::Penetration, 0.0};
  Branch pulloff_branch = Branch::Loading;
  int pulloff_refinement_solves = 0;  // extra solves spent by refine_pulloff
};

// Where a walk along a path stands between two solves, besides the state it continues
// from: what the next jump test compares with, the branch, the pull-off and its
// refinement, and the path's counters. A walk continued from a copy of it and of the
// state, with the same targets and options, makes exactly the solves the uninterrupted
// walk makes (this is what a run's checkpoint holds: output/Writer.cpp).
struct PathState {
  bool started = false;   // false: nothing solved yet; the walk starts from the state it is given
  std::size_t next = 0;   // targets recorded so far: the next one to reach
  // The last accepted solve (have_prev false: none, the next solve starts cold).
  bool have_prev = false;
  double value = 0.0;             // its target value
  double contact_fraction = 0.0;  // a
  double mean_pressure = 0.0;     // p
  double pressure_scale = 0.0;    // the largest |p| accepted so far (the jump test's floor)
  Branch branch = Branch::Loading;
  // Pull-off: the most negative mean pressure of every converged solve (NaN: none yet),
  // its target value and branch, and the accepted values just before and after it.
  double pulloff_mean_pressure = std::numeric_limits<double>::quiet_NaN();
  double pulloff_value = 0.0;
  Branch pulloff_branch = Branch::Loading;
  double pulloff_before = std::numeric_limits<double>::quiet_NaN();
  double pulloff_after = std::numeric_limits<double>::quiet_NaN();
  bool pulloff_is_last = false;  // the best solve is the last converged one (its right neighbour to come)
  bool have_last = false;        // a converged solve was accepted; last_value is its target value
  double last_value = 0.0;
  ContactState pulloff_state;    // the state at the best solve (kept only with refine_pulloff)
  // Counters over the recorded steps.
  int failed_steps = 0, halved_steps = 0, jumps = 0, max_halvings = 0;
  // Pull-off refinement: a golden-section search on [lo, hi] with inner points x1 < x2
  // and their mean pressures f1, f2 (have_f*: solved); `solves` spent so far.
  enum class Refinement { NotStarted, Running, Done };
  Refinement refinement = Refinement::NotStarted;
  double lo = 0.0, hi = 0.0, x1 = 0.0, x2 = 0.0, f1 = 0.0, f2 = 0.0;
  bool have_f1 = false, have_f2 = false;
  int refinement_solves = 0;
};

using LoadStepCallback = std::function<void(const LoadStep&, const ContactState&)>;
// Called wherever a walk can be continued from: the path's state and the state it continues from.
using PathCheckpoint = std::function<void(const PathState&, const ContactState&)>;

// Run `targets` in order from `state` (empty: the first target starts cold). On return
// `state` holds the last accepted solution. All targets must share one Control.
LoadPathResult run_load_path(const StepSolver& solve, const std::vector<Target>& targets, ContactState& state,
                             const LoadPathOptions& options = {}, const LoadStepCallback& on_step = {});
// The same, continuing from `path` (a PathState{}: from the start) and keeping it up to
// date; `on_checkpoint` gets it after every recorded step (after on_step) and after every
// pull-off refinement solve: copies of `path` and `state` taken there, handed back here
// with the same targets and options, continue the walk exactly. The result's steps are
// those recorded by this call; its counters and pull-off are the whole path's.
LoadPathResult run_load_path(const StepSolver& solve, const std::vector<Target>& targets, ContactState& state,
                             PathState& path, const LoadPathOptions& options, const LoadStepCallback& on_step = {},
                             const PathCheckpoint& on_checkpoint = {});

// ---- target sequences
// n + 1 equally spaced values from `from` to `to` (both included); n >= 1.
std::vector<Target> ramp(Control control, double from, double to, int n);
// Loading from `start` to `peak` in n_load steps, then unloading to `end` in n_unload
// steps (the peak appears once).
std::vector<Target> load_unload(Control control, double start, double peak, double end, int n_load, int n_unload);

}  // namespace cmc
