// cmc: the command-line program. Parses arguments, calls the library, reports.
#include "cmc/Case.hpp"
#include "cmc/Driver.hpp"
#include "cmc/Writer.hpp"
#include "Validate.hpp"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

using namespace cmc;

namespace {

// Exit codes (documented in the README and `cmc --help`).
constexpr int kOk = 0, kUsage = 2, kNotConverged = 3, kFailed = 4, kValidationFailed = 5;

const char* kHelp = R"(cmc — rough adhesive contact mechanics: solver and validation suite

usage: cmc <command> [options]

commands:
  run CASE.toml --out DIR [--set section.key=value ...] [--quiet]
        solve a case; writes DIR/summary.json, DIR/result.h5, DIR/result.xdmf
  validate CASE.toml [CASE.toml ...] [--out DIR] [--set ...] [--quiet]
        solve each case and compare it with the reference its [validation]
        section names; prints a table; exits non-zero if a check fails

options:
  -h, --help     this help (also: cmc <command> --help)
  --version      print the version

exit codes: 0 ok, 2 bad input (case file or arguments), 3 a solve did not reach its
tolerance, 4 run failed (I/O, memory), 5 a validation check failed.
Case files: see cases/README.md. Units: SI in case files and outputs.
)";

const char* kRunHelp = R"(usage: cmc run CASE.toml --out DIR [--set section.key=value ...] [--quiet]

Solves every load step of CASE.toml and writes, atomically:
  DIR/summary.json  the resolved case, units, grid, status, timing and one record per step
  DIR/result.h5     heights and, per step, pressure/displacement/gap (SI, units as attributes)
  DIR/result.xdmf   lets ParaView open result.h5
--set overrides any case key, e.g. --set grid.n=512 --set solver.tolerance=1e-8
(the value is TOML: numbers, "strings" or bare words, [arrays]).
Progress goes to stderr when it is a terminal; --quiet silences it.
Exit codes: 0 converged, 2 bad input, 3 not converged (results are still written,
with "status": "not_converged"), 4 failed.
)";

const char* kValidateHelp = R"(usage: cmc validate CASE.toml [CASE.toml ...] [--out DIR] [--set ...] [--quiet]

Solves each case and compares it with the analytic reference named in its
[validation] section: each [[validation.check]] gives a quantity and a tolerance, and
an optional [validation.refinement] runs the case on several grids and requires an
observed order of convergence. Prints one table row per check; with --out, writes
DIR/<case name>/summary.json (with a "validation" entry) and the fields.
Exit code 5 when any check fails.
)";

struct Args {
  std::vector<std::string> positional, overrides;
  std::string out;
  bool quiet = false, help = false;
};

Args parse_args(int argc, char** argv, int first) {
  Args a;
  for (int i = first; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&](const char* name) {
      if (i + 1 >= argc) throw CaseError(std::string(name) + " needs a value");
      return std::string(argv[++i]);
    };
    if (s == "-h" || s == "--help") a.help = true;
    else if (s == "--quiet" || s == "-q") a.quiet = true;
    else if (s == "--out" || s == "-o") a.out = value("--out");
    else if (s == "--set") a.overrides.push_back(value("--set"));
    else if (s.rfind("--set=", 0) == 0) a.overrides.push_back(s.substr(6));
    else if (s.rfind("--out=", 0) == 0) a.out = s.substr(6);
    else if (s.size() > 1 && s[0] == '-') throw CaseError("unknown option " + s + " (see --help)");
    else a.positional.push_back(s);
  }
  return a;
}

// Progress on stderr, only for a terminal and without --quiet.
Progress make_progress(bool quiet, int* step, std::chrono::steady_clock::time_point t0) {
  if (quiet || !isatty(STDERR_FILENO)) return {};
  return [step, t0](int it, double residual) {
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "\r  step %d  iteration %5d  residual %.3e  elapsed %7.1f s ", *step, it, residual, el);
    std::fflush(stderr);
  };
}

int cmd_run(const Args& a) {
  if (a.help) return std::fputs(kRunHelp, stdout), kOk;
  if (a.positional.size() != 1) throw CaseError("cmc run takes exactly one case file (see cmc run --help)");
  if (a.out.empty()) throw CaseError("cmc run needs --out DIR (see cmc run --help)");
  const Case c = load_case(a.positional[0], a.overrides);
  Scene scene = build_scene(c);
  Writer writer(a.out, c, scene);
  int step = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const bool tty = !a.quiet && isatty(STDERR_FILENO);
  RunSummary run;
  try {
    run = run_scene(
        c, scene,
        [&](const StepRecord& r, const ContactState& st) {
          writer.add_step(r, st);
          if (tty) std::fputc('\n', stderr);
          if (!a.quiet)
            std::fprintf(stderr, "step %d: %s after %d iterations (residual %.2e, %.2f s): p = %.6g Pa, "
                                 "contact %.4f\n",
                         r.index, r.result.converged ? "converged" : "NOT CONVERGED", r.result.iterations,
                         r.result.residual, r.result.wall_s, r.mean_pressure, r.contact_fraction);
          step = r.index + 1;
        },
        make_progress(a.quiet, &step, t0));
    writer.finish(run);
  } catch (const std::exception& e) {
    writer.fail(e.what());
    throw;
  }
  if (!a.quiet)
    std::fprintf(stderr, "%s: %zu steps, %s, %.2f s, %ld FFT pairs -> %s/summary.json\n", c.name.c_str(),
                 run.steps.size(), run.status.c_str(), run.wall_s, run.fft_pairs, a.out.c_str());
  if (run.status != "converged") {
    std::fprintf(stderr, "cmc run: %s\n", run.message.c_str());
    return kNotConverged;
  }
  return kOk;
}

int cmd_validate(const Args& a) {
  if (a.help) return std::fputs(kValidateHelp, stdout), kOk;
  if (a.positional.empty()) throw CaseError("cmc validate needs at least one case file (see cmc validate --help)");
  bool all_pass = true;
  std::printf("%-28s %-18s %12s %12s %6s %8s\n", "case", "quantity", "error", "tolerance", "result", "time_s");
  for (const auto& file : a.positional) {
    const Case c = load_case(file, a.overrides);
    if (!c.validation) throw CaseError(file + ": no [validation] section: nothing to compare with");
    const auto t0 = std::chrono::steady_clock::now();
    int step = 0;
    SolvedCase sc = solve_case(c, {}, make_progress(a.quiet, &step, t0));
    auto checks = evaluate_checks(c, sc.scene, sc.states);
    if (sc.run.status != "converged") {
      checks.push_back({"convergence", sc.run.message, 1.0, 0.0, false});
    }
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    toml::array json_checks;
    for (const auto& r : checks) {
      std::printf("%-28s %-18s %12.4e %12.4e %6s %8.2f\n", c.name.c_str(), r.quantity.c_str(), r.error, r.tolerance,
                  r.pass ? "pass" : "FAIL", seconds);
      all_pass &= r.pass;
      json_checks.push_back(toml::table{{"reference", c.validation->reference}, {"quantity", r.quantity},
                                        {"definition", r.definition}, {"error", r.error},
                                        {"tolerance", r.tolerance}, {"pass", r.pass}});
    }
    if (c.validation->refinement) {
      const auto t1 = std::chrono::steady_clock::now();
      const RefinementResult rr = run_refinement(c);
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
      std::string grids, errors;
      toml::array g, e;
      for (std::size_t k = 0; k < rr.grids.size(); ++k) {
        grids += (k ? "," : "") + std::to_string(rr.grids[k]);
        char buf[32];
        std::snprintf(buf, sizeof buf, "%s%.3e", k ? "," : "", rr.errors[k]);
        errors += buf;
        g.push_back(rr.grids[k]);
        e.push_back(rr.errors[k]);
      }
      const std::string q = "order(" + c.validation->refinement->quantity + ")";
      std::printf("%-28s %-18s %12.4f %12.4f %6s %8.2f   grids %s errors %s\n", c.name.c_str(), q.c_str(), rr.order,
                  rr.min_order, rr.pass ? "pass" : "FAIL", seconds, grids.c_str(), errors.c_str());
      all_pass &= rr.pass;
      json_checks.push_back(toml::table{{"reference", c.validation->reference}, {"quantity", q},
                                        {"grids", g}, {"errors", e}, {"observed_order", rr.order},
                                        {"min_order", rr.min_order}, {"pass", rr.pass}});
    }
    if (!a.out.empty()) {
      Writer w(std::filesystem::path(a.out) / c.name, c, sc.scene);
      for (std::size_t k = 0; k < sc.states.size(); ++k) w.add_step(sc.run.steps[k], sc.states[k]);
      w.finish(sc.run, toml::table{{"validation", json_checks}});
    }
  }
  return all_pass ? kOk : kValidationFailed;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fputs(kHelp, stderr);
    return kUsage;
  }
  const std::string cmd = argv[1];
  if (cmd == "-h" || cmd == "--help" || cmd == "help") return std::fputs(kHelp, stdout), kOk;
  if (cmd == "--version" || cmd == "version") return std::printf("cmc %s\n", CMC_VERSION), kOk;
  try {
    const Args a = parse_args(argc, argv, 2);
    if (cmd == "run") return cmd_run(a);
    if (cmd == "validate") return cmd_validate(a);
    std::fprintf(stderr, "cmc: unknown command '%s' (see cmc --help)\n", cmd.c_str());
    return kUsage;
  } catch (const CaseError& e) {
    std::fprintf(stderr, "cmc: error: %s\n", e.what());
    return kUsage;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "cmc: error: out of memory (reduce grid.n)\n");
    return kFailed;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmc: error: %s\n", e.what());
    return kFailed;
  }
}
