// cmc run: solve one case and write its results.
#include "commands.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/output/OutputLock.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace cmc::app {

namespace {
const char* kRunHelp = R"(usage: cmc run CASE.toml --out DIR [--set section.key=value ...] [--resume] [--quiet]
               [--checkpoint-every SECONDS] [--start-from COARSE_DIR]

Solves every load step of CASE.toml and writes, atomically:
  DIR/summary.json  the resolved case, units, grid, status, timing and one record per step
  DIR/result.h5     heights and, per step, pressure/displacement/gap (SI, units as attributes)
  DIR/result.xdmf   lets ParaView open result.h5
--set overrides any case key, e.g. --set grid.n=512 --set solver.tolerance=1e-8
(the value is TOML: numbers, "strings" or bare words, [arrays]).
Progress goes to stderr when it is a terminal; --quiet silences it.
Until the run finishes DIR holds no summary.json (an earlier run's results are removed
when it starts; a run that fails writes one with "status": "failed" and keeps its
checkpoints) but a file DIR/INCOMPLETE, and checkpoints (DIR/.partial/): after every
load step (but the last of a hard-wall or quasi-static run: only the output follows it)
and every pull-off refinement solve, and inside a load step of the quasi-static
solver between two of its outer steps, at most every SECONDS (--checkpoint-every, default
600; 0: after every outer step): a step that takes hours loses at most that much.
--resume continues an interrupted run of the same case (same file and --set values) from
its last checkpoint (a missing or damaged file in DIR/.partial/ is refused, exit 2;
where there is no checkpoint it starts afresh, saying so, unless DIR holds a finished
run: that is refused, exit 2, rather than replaced), with the same results, bit for bit, as a run that was not
interrupted (on the same machine and thread count). A run whose quasi-static solve stopped
at solver.max_outer_steps keeps its checkpoint (summary.json "continue"): --resume with a
larger --set solver.max_outer_steps=N goes on from the solve's last outer step and gives
what a fresh run with that limit gives; with the same limit the folder is left as it is.
--start-from COARSE_DIR starts the solve from the last state of a finished run of the
same case on a coarser grid (its points dividing this grid's by a whole factor, written
with --set output.fields=true), prolonged onto this grid: the quasi-static solver's
resolved runs then need fewer outer steps. One load step, quasi-static or Polonsky-Keer
solver, periodic boundary. Close to, not guaranteed to be, the loading-branch state of a
cold start (solver/cmc/output/CoarseStart.hpp); summary.json records it ("start_from").
One cmc process at a time writes into DIR: a second one stops at once (exit code 4)
naming the process that holds DIR/.cmc.lock.
Exit codes: 0 converged, 2 bad input, 3 not converged (results are still written,
with "status": "not_converged"), 4 failed (I/O, memory, DIR in use).
)";

// --resume where there is nothing to continue: a folder with a finished run and no
// checkpoint is refused (its results would be replaced by a fresh run, perhaps of another
// grid); a missing or empty one starts afresh, saying so (a batch job may always resume).
void check_resumable(const std::string& out, bool quiet) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool checkpoint = is_root() && fs::exists(fs::path(out) / ".partial" / "checkpoint.h5", ec);
  const bool finished = is_root() && !checkpoint && fs::exists(fs::path(out) / "summary.json", ec);
  if (any_rank(finished))
    throw CaseError(out + " holds a finished run (summary.json) and no partial run: --resume has nothing to continue; "
                    "run without --resume to replace it, or choose another --out");
  if (!any_rank(checkpoint) && is_root() && !quiet)
    std::fprintf(stderr, "cmc run: nothing to resume in %s (no checkpoint): starting afresh\n", out.c_str());
}

}  // namespace

double checkpoint_every(const Args& a) {
  const std::string e = a.option("--checkpoint-every");
  if (e.empty()) return kCheckpointEverySeconds;
  char* end = nullptr;
  const double every = std::strtod(e.c_str(), &end);
  if (end == e.c_str() || *end != '\0' || !(every >= 0.0) || !std::isfinite(every))
    throw CaseError("--checkpoint-every '" + e + "': expected seconds, a number >= 0");
  return every;
}

RunSummary run_case_folder(const Case& c, const std::string& out, bool resume, bool quiet, double checkpoint_every_s,
                           const std::string& start_from) {
  require_backend(c);
  if (resume) check_resumable(out, quiet);
  // Before the scene is built: a second run on DIR stops at once (rank 0 holds the lock).
  const OutputLock lock = is_root() ? OutputLock(out) : OutputLock();
  print_memory_plan(c, quiet);
  Scene scene = build_scene(c);
  return run_case_to(c, scene, out, resume, quiet, checkpoint_every_s, start_from);
}

int cmd_run(int argc, char** argv) {
  const Args a = parse_args(argc, argv, 2, {"--checkpoint-every", "--start-from"});
  if (a.help) return std::fputs(kRunHelp, stdout), kOk;
  if (a.positional.size() != 1) throw CaseError("cmc run takes exactly one case file (see cmc run --help)");
  if (a.out.empty()) throw CaseError("cmc run needs --out DIR (see cmc run --help)");
  const double every = checkpoint_every(a);
  const Case c = load_case(a.positional[0], a.overrides);
  const RunSummary run = run_case_folder(c, a.out, a.resume, a.quiet, every, a.option("--start-from"));
  if (run.status != RunStatus::Converged) {
    if (is_root()) std::fprintf(stderr, "cmc run: %s\n", run.message.c_str());
    return kNotConverged;
  }
  return kOk;
}

}  // namespace cmc::app
