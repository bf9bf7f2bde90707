// The validation harness: compares a solved case with its analytic reference.
//
// A case's [validation] section names the reference (hertz, hertz_periodic,
// westergaard, jkr, maugis_dugdale, johnson), the quantities to compare with their
// tolerances ([[validation.check]]), and optionally a refinement study (the same case
// on several grids, with a required observed order of convergence). The error
// definition of each reference and quantity is next to its function in Validate.cpp;
// `validation_error` also returns it in words, and `cmc validate` writes it into
// summary.json ("validation" entries) and prints it in its table.
#pragma once

#include "cmc/run/Driver.hpp"

#include <string>
#include <vector>

namespace cmc {

struct CheckResult {
  std::string quantity;
  std::string definition;  // how the error is measured, in words
  double error = 0.0;
  double tolerance = 0.0;
  bool pass = false;
  // A check cmc does not pass yet, and why (the case file says): its failure is expected.
  std::string expected_failure;
  // Whether the result is what the suite expects: a pass, or a failure that was expected.
  bool as_expected() const { return expected_failure.empty() ? pass : !pass; }
  // "pass", "FAIL", "xfail" (an expected failure) or "XPASS" (an expected failure that
  // passed: the case file should say so).
  const char* verdict() const;
};

// The error of `quantity` for a solved case. For hertz, hertz_periodic and westergaard
// it is the largest over all steps; for jkr/maugis_dugdale "force" the largest over the
// steps in contact (out-of-contact steps lie off the reference curve); for johnson
// "mean_pressure" and "mean_gap" the largest over the steps with a closed gap ("mean_gap":
// p̄ against Johnson's at the solved mean gap, where Johnson has a state). "pulloff" (adhesive
// references) is one number for the whole path, from `run`. Throws
// std::invalid_argument for an unknown reference or quantity.
double validation_error(ValidationReference reference, ValidationQuantity quantity, const Scene& s,
                        const std::vector<ContactState>& states, const RunSummary& run,
                        std::string* definition = nullptr);

std::vector<CheckResult> evaluate_checks(const Case& c, const Scene& s, const std::vector<ContactState>& states,
                                         const RunSummary& run);

// The observed order of convergence of values v_k on grids n_k: the least-squares
// straight line log v = log_c - order * log n (v ~ n^-order). The line passes through
// the centroid (mean log n, mean log v) of the points. Values at or below 1e-300 count
// as 1e-300 (a zero error would give log 0). Needs two or more distinct grids.
struct OrderFit {
  double order = 0.0;
  double mean_log_n = 0.0, mean_log_v = 0.0;  // the centroid
  // The fitted line at grid n, and a line of slope -p through the same centroid (the
  // guide for a required order in the reports).
  double at(double n) const { return line(n, order); }
  double line(double n, double p) const;
};
OrderFit fit_order(const std::vector<int>& grids, const std::vector<double>& values);

struct RefinementResult {
  std::vector<int> grids;
  std::vector<double> errors;
  double order = 0.0;  // fit_order(grids, errors).order
  double min_order = 0.0;
  bool pass = false;
  // For the report's figure: the fitted line, and the line of the required order
  // through the same centroid, at each grid.
  std::vector<double> fitted, required;
};

// Runs `c` once per grid of its refinement study (through the same Case → Scene →
// solver path as `cmc run`, via solve_case, setting grid.n, or grid.nx (and ny when it
// is above 1) for a case given by nx/ny),
// takes the error of the study's quantity on each, and fits the observed order. Throws
// std::runtime_error if a run does not converge.
RefinementResult run_refinement(const Case& c);

// Solve a case and keep every step's fields (validation grids are small).
struct SolvedCase {
  Scene scene;
  RunSummary run;
  std::vector<ContactState> states;
};
SolvedCase solve_case(const Case& c, const StepCallback& also = {}, const Progress& progress = {});

}  // namespace cmc
