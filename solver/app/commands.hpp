// Shared pieces of the cmc command-line program: argument parsing, progress, exit
// codes, and the command entry points (one file per command in solver/app/).
#pragma once

#include "cmc/input/Case.hpp"
#include "cmc/contact/Solver.hpp"
#include "cmc/run/Driver.hpp"

#include <chrono>
#include <string>
#include <vector>

namespace cmc::app {

// Exit codes (documented in the README and `cmc --help`).
constexpr int kOk = 0, kUsage = 2, kNotConverged = 3, kFailed = 4, kValidationFailed = 5;

struct Args {
  std::vector<std::string> positional, overrides;
  std::string out;
  bool quiet = false, help = false, resume = false;
  // Options of the form --name value that a command accepts besides the common ones.
  std::vector<std::pair<std::string, std::string>> options;
  std::string option(const std::string& name, const std::string& def = "") const;
};

// Common options: --help, --quiet, --out DIR, --set k=v. A command lists its own
// options (taking one value each) in `valued`; anything else starting with '-' is an
// error (CaseError, exit code 2), and so is --out or a valued option given twice, unless
// it is listed in `repeatable` (--set always is).
Args parse_args(int argc, char** argv, int first, const std::vector<std::string>& valued = {},
                const std::vector<std::string>& repeatable = {});

// Progress on stderr without --quiet: step (*step, numbered as in summary.json),
// iteration, residual (for the quasi-static solver: outer steps done and the last one's
// tension change, over w/ρ, which the tension tolerance bounds), elapsed time and, once a
// step has finished, the estimated time left
// (elapsed per step finished since `first_step` x steps left; a resumed run starts at its
// first unfinished step). On a terminal one line rewritten in place; into a file or pipe
// (a batch job's log) a line of its own at most every 30 s (CMC_PROGRESS_EVERY = seconds,
// >= 0; parse_args refuses a malformed value).
// One line on stderr before anything large is allocated: the grid, the memory the run
// will hold at its peak (estimate_memory, counted from the code) and what is available.
void print_memory_plan(const Case& c, bool quiet);
// A case with grid.backend = "cuda" on a machine without a usable GPU stops here, before
// any output folder is made (exit 4, the message says what to do).
void require_backend(const Case& c);
Progress make_progress(bool quiet, int* step, std::chrono::steady_clock::time_point t0, int total_steps = 0,
                       int first_step = 0);

// Solve `c` on `scene` into the folder `out` (summary.json, result.h5, result.xdmf),
// continuing a partial run there when `resume` is set (run_case.cpp; `cmc run` and
// `cmc refine` both use it). Progress and per-step lines on stderr unless `quiet`.
// checkpoint_every_s: the least time between two checkpoints inside a load step (the
// quasi-static solver's outer steps; cmc run --checkpoint-every). Steps always end in one.
constexpr double kCheckpointEverySeconds = 600.0;
// start_from: a finished run of the same case on a coarser grid whose last state starts
// the first solve (cmc run --start-from; output/CoarseStart.hpp); empty: from scratch.
RunSummary run_case_to(const Case& c, Scene& scene, const std::string& out, bool resume, bool quiet,
                       double checkpoint_every_s = kCheckpointEverySeconds, const std::string& start_from = "");

// --checkpoint-every SECONDS (a number >= 0; absent: kCheckpointEverySeconds), CaseError
// naming the option when malformed.
double checkpoint_every(const Args& a);
// What `cmc run CASE --out OUT [--resume]` does once its arguments are read: checks the
// backend (and, with `resume`, that OUT holds no finished run without a checkpoint), locks
// OUT, prints the memory plan, builds the scene and runs it with run_case_to (cmd_run.cpp;
// `cmc sweep` runs each point through it, so a point's folder is what `cmc run` writes).
RunSummary run_case_folder(const Case& c, const std::string& out, bool resume, bool quiet,
                           double checkpoint_every_s = kCheckpointEverySeconds, const std::string& start_from = "");

// The key of a --set assignment: "grid.n" of " grid.n = 64".
std::string override_key(const std::string& assignment);
// Whether `key` sets the grid's points (grid.n, grid.nx, grid.ny).
bool is_grid_key(const std::string& key);
// --grids N1 N2 ...: the increasing whole numbers (2 .. CaseLimits::kMaxGridSide) after
// --grids; every other argument goes to `rest` (for parse_args). Empty without --grids.
std::vector<int> take_grids(int argc, char** argv, std::vector<char*>& rest);
// A --set of grid.n, grid.nx or grid.ny beside --grids would run every grid at that one
// size, labelled as the grids of --grids: bad input naming both (`command` sets the grid).
void refuse_grid_overrides(const std::vector<std::string>& overrides, const std::vector<int>& grids,
                           const std::string& command);

int cmd_run(int argc, char** argv);
int cmd_refine(int argc, char** argv);     // cmd_refine.cpp
int cmd_validate(int argc, char** argv);
int cmd_reference(int argc, char** argv);  // cmd_reference.cpp
// cmc reference --run-curve SPEC.toml --out FILE: a curve from a run's numbers (run_curve.cpp).
int write_run_curve(const std::string& spec_file, const std::string& out);
int cmd_check(int argc, char** argv);      // cmd_check.cpp
int cmd_surface(int argc, char** argv);    // cmd_surface.cpp
int cmd_sweep(int argc, char** argv);      // cmd_sweep.cpp

}  // namespace cmc::app
