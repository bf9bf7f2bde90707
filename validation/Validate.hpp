// The validation harness: compares a solved case with its analytic reference.
//
// A case's [validation] section names the reference (hertz, hertz_periodic,
// westergaard), the quantities to compare and their tolerances, and optionally a
// refinement study (the same case on several grids, with a required observed order
// of convergence). Error definitions, one per quantity, are documented in
// validation/README.md and next to each function below.
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
};

// The error of `quantity` over all steps of a solved case (the largest over steps).
// `run` supplies the pull-off of adhesive load paths (quantity "pulloff").
double validation_error(ValidationReference reference, ValidationQuantity quantity, const Scene& s,
                        const std::vector<ContactState>& states, const RunSummary& run,
                        std::string* definition = nullptr);

std::vector<CheckResult> evaluate_checks(const Case& c, const Scene& s, const std::vector<ContactState>& states,
                                         const RunSummary& run);

struct RefinementResult {
  std::vector<int> grids;
  std::vector<double> errors;
  double order = 0.0;  // least-squares slope of −log(error) against log(n)
  double min_order = 0.0;
  bool pass = false;
};

// Runs `c` once per grid of its refinement study (through the same Case → Scene →
// solver path as `cmc run`) and fits the observed order.
RefinementResult run_refinement(const Case& c);

// Solve a case and keep every step's fields (validation grids are small).
struct SolvedCase {
  Scene scene;
  RunSummary run;
  std::vector<ContactState> states;
};
SolvedCase solve_case(const Case& c, const StepCallback& also = {}, const Progress& progress = {});

}  // namespace cmc
