// cmc validate: solve cases and compare them with their analytic references.
#include "commands.hpp"

#include "Profiles.hpp"
#include "Stability.hpp"
#include "Validate.hpp"
#include "cmc/output/OutputLock.hpp"
#include "cmc/input/ValidationRules.hpp"
#include "cmc/output/RunFolder.hpp"

#include <vector>
#include "cmc/output/Writer.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace cmc::app {

namespace {
const char* kValidateHelp = R"(usage: cmc validate CASE.toml [CASE.toml ...] [--out DIR] [--set ...] [--quiet]

Solves each case and compares it with the analytic reference named in its
[validation] section: each [[validation.check]] gives a quantity and a tolerance, and
an optional [validation.refinement] runs the case on several grids and requires an
observed order of convergence. A [[validation.check]] with a `kind` is a stability
check (iterations, residual_growth, energy_rise, same_bits, threads, continuity,
force_balance, gap, contact_fraction, pulloff, hysteresis: cases/README.md); a case
with one also gets `finite`, and keeps every iteration's residual
(summary.json "residual_history"). A check marked expected_failure prints xfail when
it fails and XPASS (a failure of the command) when it passes. Prints one table row per check; with --out, writes
DIR/<case name>/summary.json (with a "validation" entry: every check's error, and a
refinement study's errors, observed order and fitted line), the fields, and, for
hertz, hertz_periodic and westergaard, DIR/<case name>/profiles.csv: the solved
pressure and gap beside the analytic ones at every grid point near the contact.
Each case needs a case.name of its own (two cases of one name are refused, exit 2).
Exit code 5 when any check fails (or an expected failure passes); 4 when DIR/<case name> is in use by another cmc
process (one process at a time writes into a folder).
)";

// Every case file, read and checked (bad input stops the command) before anything is written.
std::vector<Case> read_cases(const Args& a) {
  std::vector<Case> cases;
  for (const auto& file : a.positional) {
    cases.push_back(load_case(file, a.overrides));
    require_backend(cases.back());
    if (!cases.back().validation) throw CaseError(file + ": no [validation] section: nothing to compare with");
    check_validation_fits(cases.back());  // the problem and quantities of its reference (exit 2)
    // The name labels the table's rows and names the folder DIR/<case name>/: one case per name.
    for (std::size_t k = 0; k + 1 < cases.size(); ++k)
      if (cases[k].name == cases.back().name)
        throw CaseError(file + ": [case] name '" + cases.back().name + "' is also the name of " + cases[k].file +
                        ": expected a distinct case.name for each case validated together (it labels the table's "
                        "rows and names the folder DIR/<case name>/); give one with --set case.name=... in a run "
                        "of its own, or rename it");
  }
  return cases;
}

// A number for summary.json; where JSON has none (infinity, NaN), its word.
template <class T>
void insert_number(toml::table& t, const std::string& key, T v) {
  if (std::isfinite(double(v))) t.insert(key, v);
  else t.insert(key, std::isnan(double(v)) ? "nan" : double(v) > 0 ? "inf" : "-inf");
}

// A case's results: the table's rows printed, their summary.json entries, and whether every
// one is what the suite expects (a pass, or an expected failure).
struct CaseOutcome {
  toml::array json;
  bool as_expected = true;
};

void report_check(const Case& c, const CheckResult& r, double seconds, CaseOutcome& out) {
  std::printf("%-28s %-18s %12.4e %12.4e %6s %8.2f\n", c.name.c_str(), r.quantity.c_str(), r.error, r.tolerance,
              r.verdict(), seconds);
  out.as_expected &= r.as_expected();
  toml::table t{{"quantity", r.quantity}, {"definition", r.definition}, {"pass", r.pass}, {"verdict", r.verdict()}};
  insert_number(t, "error", r.error);
  insert_number(t, "tolerance", r.tolerance);
  if (c.validation->reference) t.insert("reference", std::string(kind_name(*c.validation->reference)));
  if (!r.expected_failure.empty()) t.insert("expected_failure", r.expected_failure);
  out.json.push_back(t);
}

void report_refinement(const Case& c, CaseOutcome& out) {
  const auto t1 = std::chrono::steady_clock::now();
  const RefinementResult rr = run_refinement(c);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  std::string grids, errors;
  toml::array g, e, fitted, required;
  for (std::size_t k = 0; k < rr.grids.size(); ++k) {
    grids += (k ? "," : "") + std::to_string(rr.grids[k]);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.3e", k ? "," : "", rr.errors[k]);
    errors += buf;
    g.push_back(rr.grids[k]);
    e.push_back(rr.errors[k]);
    fitted.push_back(rr.fitted[k]);
    required.push_back(rr.required[k]);
  }
  const std::string q = "order(" + std::string(kind_name(c.validation->refinement->quantity)) + ")";
  std::printf("%-28s %-18s %12.4f %12.4f %6s %8.2f   grids %s errors %s\n", c.name.c_str(), q.c_str(), rr.order,
              rr.min_order, rr.pass ? "pass" : "FAIL", seconds, grids.c_str(), errors.c_str());
  out.as_expected &= rr.pass;
  out.json.push_back(toml::table{{"reference", std::string(kind_name(*c.validation->reference))}, {"quantity", q},
                                 {"grids", g}, {"errors", e}, {"observed_order", rr.order},
                                 {"min_order", rr.min_order}, {"fitted_errors", fitted},
                                 {"required_order_errors", required}, {"pass", rr.pass}});
}

// The residual history of the solves for summary.json, at most about kHistoryPoints points
// (every k-th, and each solve's first and last): the reports draw it.
constexpr std::size_t kHistoryPoints = 400;
toml::table history_json(const std::vector<SolveHistory>& history) {
  std::size_t total = 0;
  for (const auto& h : history) total += h.residual.size();
  const std::size_t stride = std::max<std::size_t>(1, (total + kHistoryPoints - 1) / kHistoryPoints);
  toml::array solve, iteration, residual;
  for (std::size_t s = 0; s < history.size(); ++s)
    for (std::size_t k = 0; k < history[s].residual.size(); ++k) {
      if (k % stride != 0 && k + 1 != history[s].residual.size()) continue;
      solve.push_back(int64_t(s));
      iteration.push_back(history[s].iteration[k]);
      const double r = history[s].residual[k];
      if (std::isfinite(r)) residual.push_back(r);
      else residual.push_back(std::isnan(r) ? "nan" : "inf");
    }
  return toml::table{{"solves", int64_t(history.size())}, {"points", int64_t(total)}, {"solve", solve},
                     {"iteration", iteration}, {"residual", residual}};
}

// Solves one case, prints its rows and writes its folder (with --out).
bool validate_case(const Case& c, const Args& a) {
  const auto t0 = std::chrono::steady_clock::now();
  int step = 0;
  RecordedCase rc = c.validation->stability.empty()
                        ? RecordedCase{solve_case(c, {}, make_progress(a.quiet, &step, t0)), {}}
                        : solve_recorded(c, make_progress(a.quiet, &step, t0));
  SolvedCase& sc = rc.solved;
  auto checks = evaluate_checks(c, sc.scene, sc.states, sc.run);
  for (CheckResult& r : evaluate_stability(c, rc)) checks.push_back(std::move(r));
  if (sc.run.status != RunStatus::Converged) {
    // Expected where the case says its iterations check is (the solver stops, as it should).
    std::string expected;
    for (const StabilityCheck& ch : c.validation->stability)
      if (ch.kind == StabilityKind::Iterations) expected = ch.expected_failure;
    checks.push_back({"convergence", sc.run.message, 1.0, 0.0, false, expected});
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CaseOutcome out;
  for (const auto& r : checks) report_check(c, r, seconds, out);
  if (c.validation->refinement) report_refinement(c, out);
  if (!a.out.empty()) {
    Writer w(std::filesystem::path(a.out) / c.name, c, sc.scene);
    for (std::size_t k = 0; k < sc.states.size(); ++k) w.add_step(sc.run.steps[k], sc.states[k]);
    toml::table extra{{"validation", out.json}};
    if (!rc.history.empty()) extra.insert("residual_history", history_json(rc.history));
    w.finish(sc.run, extra);
    if (c.validation->reference && has_profiles(*c.validation->reference))
      write_output_text(std::filesystem::path(a.out) / c.name / "profiles.csv",
                        profiles_csv(*c.validation->reference, sc.scene, sc.states));
  }
  return out.as_expected;
}

}  // namespace

int cmd_validate(int argc, char** argv) {
  const Args a = parse_args(argc, argv, 2);
  if (a.help) return std::fputs(kValidateHelp, stdout), kOk;
  if (a.positional.empty()) throw CaseError("cmc validate needs at least one case file (see cmc validate --help)");
  const std::vector<Case> cases = read_cases(a);
  // One owner per output folder, from the start (the results are written after the solves).
  // A validation writes only DIR/<case name>/, so that is what it locks: validations of
  // different cases may share one --out (ctest runs them in parallel into build/validation).
  std::vector<OutputLock> locks;
  if (!a.out.empty())
    for (const Case& c : cases) {
      locks.emplace_back(std::filesystem::path(a.out) / c.name);
      check_earlier_results(std::filesystem::path(a.out) / c.name);  // before the solves (exit 2)
      check_output_file(std::filesystem::path(a.out) / c.name / "profiles.csv");
    }
  bool all_as_expected = true;
  std::printf("%-28s %-18s %12s %12s %6s %8s\n", "case", "quantity", "error", "tolerance", "result", "time_s");
  for (const Case& c : cases) all_as_expected &= validate_case(c, a);
  return all_as_expected ? kOk : kValidationFailed;
}


}  // namespace cmc::app
