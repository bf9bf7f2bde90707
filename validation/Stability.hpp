// Stability checks: properties every solved case must have, whatever its physics, for the
// [[validation.check]] entries with a `kind` (cases/hard/ uses them; any case may). Each
// measures one number and compares it with the bound its case file states:
//
//   iterations        every load step converged, in at most `budget` iterations (the adhesive
//                     CG's step: all its solves); a run that stops says so, never with NaN
//   residual_growth   within each solve, the largest r_k / min_{j<k} r_j of the residual the
//                     solver reports at every iteration (the quasi-static solver: its outer
//                     steps' tension change); at most `factor`
//   energy_rise       the adhesive CG's energy: the largest E_k - min_{j<k} E_j within a
//                     solve over max |E| of that solve; at most `tolerance`
//   same_bits         the case solved again in this process: every field and step value
//                     identical (the number that differ, 0)
//   threads           the case on 1 and on 2 threads: the largest difference of a step's
//                     pressure, gap, mean pressure, penetration or contact fraction over that
//                     quantity's largest magnitude; at most `tolerance`
//   continuity        the case with `parameter` scaled by 1 + `change`: the largest relative
//                     change of `observable` over the steps (not those in `skip_steps`)
//   agreement         the case's loading branch solved by `solver` (another solver): the
//                     largest relative difference of `observable` at the loading steps (not
//                     those in `skip_steps`)
//   force_balance     per step the largest of: |mean(p) - the step's mean pressure| and, under
//                     load control, |mean(p) - load| (converged steps), over the pressure
//                     scale; where the gap is
//                     open |p - f(g)| (f the interaction's traction), where closed the amount by
//                     which p falls below f(0), over the same scale; |u - G p| over the height
//                     scale (the elastic state is the half-space's response to the pressure)
//   gap               the most negative of the solved gap and of h - delta + u, over the
//                     height scale: the hard wall holds
//   contact_fraction  0 <= a_r <= 1, and a_r is what the contact rule counts in the gap field
//   pulloff           the most negative mean pressure of the path is finite and below zero
//   hysteresis        at every load of both branches, a_r(loading) - a_r(unloading) <=
//                     `tolerance` (unloading keeps at least the contact of loading)
//
// The pressure scale of a step is the largest |p| of its field (at least its |mean pressure|
// and the interaction's peak tension);
// the height scale the surface's peak-to-valley height (at least max |u|, |delta|).
// Every case with a stability check also gets `finite`: every step's fields and numbers
// are finite (never NaN), whatever its status.
#pragma once

#include "Validate.hpp"

#include <string>
#include <vector>

namespace cmc {

// One solve's residuals (and energies, NaN where the solver reports none) at each
// iteration, as the solver reported them.
struct SolveHistory {
  std::vector<int> iteration;
  std::vector<double> residual, energy;
};

// A case solved with every iteration's residual kept (solver.progress_every = 1): one history
// per solve (a new one starts where the iteration count, or the quasi-static outer step,
// starts again). `progress` still sees every 25th point.
struct RecordedCase {
  SolvedCase solved;
  std::vector<SolveHistory> history;
};
RecordedCase solve_recorded(const Case& c, const Progress& progress = {});

// The stability checks of the case (its [[validation.check]] entries with `kind`, in order,
// then `finite`). Re-solves the case where a check needs it (same_bits, threads,
// continuity). The scene's half-space is used for G p (force_balance).
std::vector<CheckResult> evaluate_stability(const Case& c, RecordedCase& rc);

// The measures behind the checks, one number each (tests/test_stability.cpp).
// The largest r_k / min_{j<k} r_j of a sequence (positive finite values only; 1 when it
// never rises, NaN or infinity count as infinite growth).
double largest_growth(const std::vector<double>& residuals);
// The largest E_k - min_{j<k} E_j over max_k |E_k| (0 when it never rises; NaN entries are
// skipped).
double largest_rise(const std::vector<double>& energies);
// |a - b| over a scale, 0 when both are equal (infinity when either is not finite).
double relative_difference(double a, double b, double scale);

}  // namespace cmc
