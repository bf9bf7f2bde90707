// Solving one case into an output folder: what `cmc run` does, shared with `cmc refine`.
#include "commands.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/output/CoarseStart.hpp"
#include "cmc/output/Writer.hpp"

#include <unistd.h>

#include <cstdio>
#include <optional>

namespace cmc::app {

namespace {

// Where a resumed run stands, as its checkpoint says.
void print_resuming(const Writer& writer, const Case& c, const Scene& scene) {
  const RunPoint& rp = writer.resume_point();
  std::fprintf(stderr, "resuming %s: %zu of %zu steps finished", c.name.c_str(), rp.done.size(), scene.targets.size());
  if (rp.path.refinement != PathState::Refinement::NotStarted)
    std::fprintf(stderr, ", %d pull-off refinement solves done", rp.path.refinement_solves);
  if (rp.inside)
    std::fprintf(stderr, ", step %zu inside: %d outer steps, %d iterations, %.0f FFT pairs, %.0f s done",
                 rp.done.size(), rp.inside->outer, rp.inside->so_far.iterations, rp.inside->so_far.fft_pairs,
                 rp.inside->so_far.wall_s);
  if (!writer.start().empty())
    std::fprintf(stderr, " (started from %s)", writer.start()["folder"].value_or(std::string("?")).c_str());
  std::fputc('\n', stderr);
}

}  // namespace

RunSummary run_case_to(const Case& c, Scene& scene, const std::string& out, bool resume, bool quiet,
                       double checkpoint_every_s, const std::string& start_from) {
  // A start from a coarser run, read and checked before the output folder is touched (a
  // wrong folder there leaves an earlier run's results in `out` as they were). Raised by
  // the interaction's range (0 for the hard wall): CoarseStart.hpp.
  std::optional<CoarseStart> start;
  if (!start_from.empty()) start = read_coarse_start(start_from, c, scene, interaction_range(scene.interaction));
  Writer writer(out, c, scene, resume);
  RunPoint& rp = writer.resume_point();
  if (!writer.notice().empty()) std::fprintf(stderr, "cmc: warning: %s\n", writer.notice().c_str());
  if (writer.resuming() && !quiet) print_resuming(writer, c, scene);
  // A resumed run goes on from its checkpoint instead (which records how it started).
  bool started = false;
  if (start && writer.resuming()) {
    if (writer.start().empty())
      std::fprintf(stderr, "cmc: warning: --start-from %s ignored: the run resumed in %s started from scratch\n",
                   start_from.c_str(), out.c_str());
    start.reset();
  } else if (start) {
    rp.state = std::move(start->state);
    writer.set_start(start->record);
    started = true;
    if (!quiet)
      std::fprintf(stderr, "starting %s from %s (%lld x %lld points, prolonged by %lld, gaps raised by %.4g m)\n",
                   c.name.c_str(), start_from.c_str(), start->record["grid"][0].value_or(0LL),
                   start->record["grid"][1].value_or(0LL), start->record["factor"].value_or(0LL),
                   start->record["gap_lift"].value_or(0.0));
    start.reset();
  }
  // The step being solved, numbered as in summary.json (a resumed run goes on from its
  // first unfinished step).
  int step = int(rp.done.size());
  const auto t0 = std::chrono::steady_clock::now();
  const bool tty = !quiet && isatty(STDERR_FILENO);
  RunSummary run;
  // Checkpoints inside a step (between the quasi-static solver's outer steps) are written
  // at most every checkpoint_every_s seconds: each holds two fields of the grid.
  auto last_checkpoint = std::chrono::steady_clock::now();
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
        make_progress(quiet, &step, t0, int(scene.targets.size()), step), writer.resuming() || started ? &rp : nullptr,
        [&](const ContactState& st, const PathState* path, const OuterPoint* inside) {
          const auto now = std::chrono::steady_clock::now();
          // The same choice on every rank of a distributed run (each writes its slab). The
          // point before a solve's last allowed outer step is always written: should the
          // solve stop at its limit, a larger one continues from there (Writer.hpp).
          const bool last_before_limit = inside && inside->outer + 1 >= c.solver.max_outer_steps;
          if (inside && !last_before_limit &&
              !any_rank(std::chrono::duration<double>(now - last_checkpoint).count() >= checkpoint_every_s))
            return;
          writer.checkpoint(st, path, inside);
          last_checkpoint = std::chrono::steady_clock::now();
        });
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
