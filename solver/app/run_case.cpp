// Solving one case into an output folder: what `cmc run` does, shared with `cmc refine`.
#include "commands.hpp"

#include "cmc/output/Writer.hpp"

#include <unistd.h>

#include <cstdio>

namespace cmc::app {

RunSummary run_case_to(const Case& c, Scene& scene, const std::string& out, bool resume, bool quiet) {
  Writer writer(out, c, scene, resume);
  const RunPoint& rp = writer.resume_point();
  if (!writer.notice().empty()) std::fprintf(stderr, "cmc: warning: %s\n", writer.notice().c_str());
  if (writer.resuming() && !quiet) {
    std::fprintf(stderr, "resuming %s: %zu of %zu steps finished", c.name.c_str(), rp.done.size(), scene.targets.size());
    if (rp.path.refinement != PathState::Refinement::NotStarted)
      std::fprintf(stderr, ", %d pull-off refinement solves done", rp.path.refinement_solves);
    std::fputc('\n', stderr);
  }
  // The step being solved, numbered as in summary.json (a resumed run goes on from its
  // first unfinished step).
  int step = int(rp.done.size());
  const auto t0 = std::chrono::steady_clock::now();
  const bool tty = !quiet && isatty(STDERR_FILENO);
  RunSummary run;
  try {
    run = run_scene(
        c, scene,
        [&](const StepRecord& r, const ContactState& st) {
          writer.add_step(r, st);
          if (tty) std::fputc('\n', stderr);
          if (!quiet)
            std::fprintf(stderr, "step %d: %s after %d iterations (residual %.2e, %.2f s): p = %.6g Pa, "
                                 "contact %.4f\n",
                         r.index, r.result.converged ? "converged" : "NOT CONVERGED", r.result.iterations,
                         r.result.residual, r.result.wall_s, r.mean_pressure, r.contact_fraction);
          step = r.index + 1;
        },
        make_progress(quiet, &step, t0, int(scene.targets.size()), step), writer.resuming() ? &rp : nullptr,
        [&](const ContactState& st, const PathState* path) { writer.checkpoint(st, path); });
    writer.finish(run);
  } catch (const std::exception& e) {
    writer.fail(e.what());
    throw;
  }
  if (!quiet)
    std::fprintf(stderr, "%s: %zu steps, %s, %.2f s, %.0f FFT pairs -> %s/summary.json\n", c.name.c_str(),
                 run.steps.size(), status_name(run.status), run.wall_s, run.fft_pairs, out.c_str());
  return run;
}

}  // namespace cmc::app
