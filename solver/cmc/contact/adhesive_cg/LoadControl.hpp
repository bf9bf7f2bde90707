// Load control on top of a displacement-controlled solve: find the penetration δ at which
// the solved mean pressure equals a target. Each evaluation is a solve warm-started from
// the nearest state already solved, so the search stays on the branch (loading or
// unloading, in or out of contact) that its start state is on.
//
// Algorithm: secant steps from the start until the target is bracketed (at most 4x the
// previous step; doubling while the slope is not positive), then Illinois, the modified
// regula falsi (Dowell & Jarratt, BIT 11, 168 (1971)): it keeps the bracket and, unlike
// plain regula falsi, does not stall on one end. The mean pressure grows with δ on a
// load-stable branch; where no δ on the branch carries the target (beyond pull-off, at
// full contact, or across a jump) the result says so and is not converged.
#pragma once

#include "cmc/contact/Solver.hpp"

#include <functional>
#include <limits>

namespace cmc::adhesive {

// One displacement-controlled solve: δ in, state (warm start in, solution out).
using DisplacementSolve = std::function<SolveResult(double delta, ContactState& state)>;

struct LoadControlOptions {
  double tolerance = 0.0;     // on the mean pressure, absolute (reduced units)
  int max_iterations = 60;    // of each phase (bracketing, Illinois)
  double start = 0.0;         // δ of the first evaluation
  double first_step = 0.0;    // |Δδ| of the first bracketing step
  // Largest admissible δ (a periodic solid: the mean height, where the mean gap is 0).
  double max_penetration = std::numeric_limits<double>::infinity();
};

// Solves for mean pressure `target`. On return `state` holds the last accepted solution;
// the result's iterations, FFT pairs and diagnostics are the totals over every inner
// solve (diagnostics.outer_iterations counts them).
SolveResult solve_for_mean_pressure(const DisplacementSolve& solve, double target, ContactState& state,
                                    const LoadControlOptions& options);

}  // namespace cmc::adhesive
