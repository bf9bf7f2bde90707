// cmc: the command-line program. Dispatches to one file per command (cmd_*.cpp).
#include "commands.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/output/Writer.hpp"
#include "cmc/run/TestPoints.hpp"

#include <cstdio>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

using namespace cmc::app;

namespace {
const char* kHelp = R"(cmc — rough adhesive contact mechanics: solver and validation suite

usage: cmc <command> [options]

commands:
  run CASE.toml --out DIR [--set section.key=value ...] [--quiet]
        solve a case; writes DIR/summary.json, DIR/result.h5, DIR/result.xdmf
  validate CASE.toml [CASE.toml ...] [--out DIR] [--set ...] [--quiet]
        solve each case and compare it with the reference its [validation]
        section names; prints a table; exits non-zero if a check fails
  refine CASE.toml --grids N1 N2 [N3 ...] [--out DIR] [--set ...] [--quiet]
        grid-refinement study: the case on each grid (resumable), the change of
        every observable between grids and its observed order
  sweep CASE.toml --out DIR --over section.key=V1,V2,... [--grids N1 N2 ...] [--set ...]
        the case once per value (and grid), each point as `cmc run` would run it
        into a folder of its own (resumable); then DIR/sweep.json and DIR/sweep.md
  surface CASE.toml [--write FILE.h5]
        the case's surface: statistics (rms height, gradient, R_c, Tabor) and the map
  reference [NAME ...] [--out DIR] [--list]
        regenerate the stored analytic reference curves (reference/*.csv)
  check PREDICTION.csv --quantity Q [--reference FILE] [--out DIR]
        score a submitted prediction against the reference curve

options:
  -h, --help     this help (also: cmc <command> --help)
  --version      print the version

exit codes: 0 ok, 2 bad input (case file or arguments), 3 a solve did not reach its
tolerance, 4 run failed (I/O, memory, output folder in use by another cmc process),
5 a validation check failed.
Case files: see cases/README.md. Units: SI in case files and outputs.
Output files: new paths or regular files only (a folder, device, FIFO or symbolic
link as a target is refused, exit 2); rules in cases/README.md, "Output folders".
Environment: CMC_THREADS=N threads (a whole number >= 1; unset: all of them).
)";

}  // namespace

namespace {
// In a distributed run (mpirun -np N, MPI build) only `cmc run` is distributed.
bool distributed_command(const std::string& cmd) { return cmd == "run"; }

int dispatch(int argc, char** argv);

// An error: printed once (by rank 0, or with its rank by another); an error that need
// not have happened on every rank (anything but bad input) ends all ranks at once.
int fail(int code, const char* what, bool every_rank_alike) {
  if (cmc::is_root()) std::fprintf(stderr, "cmc: error: %s\n", what);
  else if (!every_rank_alike) std::fprintf(stderr, "cmc: error (MPI rank %d): %s\n", cmc::rank(), what);
  if (!every_rank_alike && cmc::ranks() > 1) cmc::abort_all_ranks(code);
  return code;
}
}  // namespace

int main(int argc, char** argv) {
  cmc::RankSession mpi(argc, argv);
  cmc::set_memory_split({cmc::ranks(), cmc::ranks_on_this_machine()});
  return dispatch(argc, argv);
}

namespace {
int dispatch(int argc, char** argv) {
  if (argc < 2) {
    std::fputs(kHelp, stderr);
    return kUsage;
  }
  const std::string cmd = argv[1];
  if (cmd == "-h" || cmd == "--help" || cmd == "help") return std::fputs(kHelp, stdout), kOk;
  if (cmd == "--version" || cmd == "version") return std::printf("cmc %s\n", CMC_VERSION), kOk;
  try {
    if (cmc::ranks() > 1 && !distributed_command(cmd))
      throw cmc::CaseError("cmc " + cmd + " runs on one rank: under mpirun only 'cmc run' is distributed");
    cmc::check_test_points();  // a malformed CMC_TEST_* variable is bad input, before anything runs
    if (cmd == "run") return cmd_run(argc, argv);
    if (cmd == "validate") return cmd_validate(argc, argv);
    if (cmd == "refine") return cmd_refine(argc, argv);
    if (cmd == "sweep") return cmd_sweep(argc, argv);
    if (cmd == "reference") return cmd_reference(argc, argv);
    if (cmd == "check") return cmd_check(argc, argv);
    if (cmd == "surface") return cmd_surface(argc, argv);
    std::fprintf(stderr, "cmc: unknown command '%s' (see cmc --help)\n", cmd.c_str());
    return kUsage;
  } catch (const cmc::RunStopped& e) {  // a run that stopped at its limit, resumed with it: unchanged
    if (cmc::is_root()) std::fprintf(stderr, "cmc run: %s\n", e.what());
    return kNotConverged;
  } catch (const cmc::CaseError& e) {
    return fail(kUsage, e.what(), true);
  } catch (const cmc::OutputPathError& e) {  // an output path cmc will not write (grid/FilePaths.hpp)
    return fail(kUsage, e.what(), true);
  } catch (const std::bad_alloc&) {
    return fail(kFailed, cmc::ranks() > 1 ? "out of memory (reduce grid.n or use more ranks)" : "out of memory (reduce grid.n)",
                false);
  } catch (const std::exception& e) {
    return fail(kFailed, e.what(), false);
  }
}
}  // namespace
