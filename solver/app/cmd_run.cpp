// cmc run: solve one case and write its results.
#include "commands.hpp"

#include "cmc/run/Driver.hpp"
#include "cmc/output/Writer.hpp"

#include <unistd.h>

#include <cstdio>

namespace cmc::app {

namespace {
const char* kRunHelp = R"(usage: cmc run CASE.toml --out DIR [--set section.key=value ...] [--resume] [--quiet]

Solves every load step of CASE.toml and writes, atomically:
  DIR/summary.json  the resolved case, units, grid, status, timing and one record per step
  DIR/result.h5     heights and, per step, pressure/displacement/gap (SI, units as attributes)
  DIR/result.xdmf   lets ParaView open result.h5
--set overrides any case key, e.g. --set grid.n=512 --set solver.tolerance=1e-8
(the value is TOML: numbers, "strings" or bare words, [arrays]).
Progress goes to stderr when it is a terminal; --quiet silences it.
After every load step a checkpoint is kept in DIR (hidden files); --resume continues
an interrupted run of the same case (same file and --set values) from its last
finished step instead of starting afresh.
Exit codes: 0 converged, 2 bad input, 3 not converged (results are still written,
with "status": "not_converged"), 4 failed.
)";

}  // namespace

int cmd_run(int argc, char** argv) {
  const Args a = parse_args(argc, argv, 2);
  if (a.help) return std::fputs(kRunHelp, stdout), kOk;
  if (a.positional.size() != 1) throw CaseError("cmc run takes exactly one case file (see cmc run --help)");
  if (a.out.empty()) throw CaseError("cmc run needs --out DIR (see cmc run --help)");
  const Case c = load_case(a.positional[0], a.overrides);
  Scene scene = build_scene(c);
  Writer writer(a.out, c, scene, a.resume);
  const ResumePoint& rp = writer.resume_point();
  if (!rp.done.empty() && !a.quiet)
    std::fprintf(stderr, "resuming %s after step %d of %zu\n", c.name.c_str(), rp.done.back().index, scene.targets.size());
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
        make_progress(a.quiet, &step, t0, int(scene.targets.size())), &rp.done, rp.done.empty() ? nullptr : &rp.state);
    writer.finish(run);
  } catch (const std::exception& e) {
    writer.fail(e.what());
    throw;
  }
  if (!a.quiet)
    std::fprintf(stderr, "%s: %zu steps, %s, %.2f s, %.0f FFT pairs -> %s/summary.json\n", c.name.c_str(),
                 run.steps.size(), status_name(run.status), run.wall_s, run.fft_pairs, a.out.c_str());
  if (run.status != RunStatus::Converged) {
    std::fprintf(stderr, "cmc run: %s\n", run.message.c_str());
    return kNotConverged;
  }
  return kOk;
}

}  // namespace cmc::app
