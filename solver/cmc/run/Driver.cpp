#include "cmc/run/Driver.hpp"

#include "cmc/grid/Backend.hpp"

#include "cmc/contact/adhesive_cg/AdhesiveSolver.hpp"
#include "cmc/contact/polonsky_keer/PolonskyKeer.hpp"
#include "cmc/contact/quasi_static/QuasiStaticAdhesion.hpp"
#include "cmc/run/TestPoints.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace cmc {

const char* status_name(RunStatus s) {
  switch (s) {
    case RunStatus::Converged: return "converged";
    case RunStatus::NotConverged: return "not_converged";
    case RunStatus::Failed: return "failed";
  }
  return "?";
}

namespace {

// A converged step whose numbers are not all finite did not converge: a run whose summary
// holds Infinity or NaN is never "converged" (scene/SceneChecks.hpp refuses the inputs
// that lead there; this is the last guard).
void flag_non_finite(StepRecord& rec) {
  if (!rec.result.converged) return;
  std::string bad;
  for (const auto& [name, v] : {std::pair<std::string, double>{"mean_pressure", rec.mean_pressure},
                                {"force", rec.force}, {"penetration", rec.penetration}, {"mean_gap", rec.mean_gap},
                                {"contact_fraction", rec.contact_fraction}, {"energy", rec.energy},
                                {"residual", rec.result.residual}})
    if (bad.empty() && !std::isfinite(v)) bad = name;
  if (rec.observables)
    for (const auto& [name, v] : rec.observables->scalars)
      if (bad.empty() && !std::isfinite(v)) bad = "observables." + name;
  if (bad.empty()) return;
  rec.result.converged = false;
  rec.result.message = "its " + bad + " is not finite (the numbers overflowed): not a result";
}

// One run in progress: the finished steps, and how to record and hand on a new one.
class Run {
 public:
  Run(const Scene& s, const StepCallback& on_step, const CheckpointCallback& on_checkpoint)
      : s_(s), on_step_(on_step), on_checkpoint_(on_checkpoint) {}

  RunSummary summary;

  // Adds a finished step to the run; the first unconverged one sets the status.
  void account(const StepRecord& rec) {
    summary.fft_pairs += rec.result.fft_pairs;
    if (!rec.result.converged) not_converged("step " + std::to_string(rec.index) + ": " + rec.result.message);
    summary.steps.push_back(rec);
  }
  void not_converged(const std::string& message) {
    if (summary.status != RunStatus::Converged) return;
    summary.status = RunStatus::NotConverged;
    summary.message = message;
  }
  // The SI record of step k from its solved state (reduced).
  StepRecord record(std::size_t k, const SolveResult& r, const ContactState& st) const {
    const Units& u = s_.units;
    StepRecord rec;
    rec.index = int(k);
    rec.branch = k < s_.unloading_from ? Branch::Loading : Branch::Unloading;
    rec.result = r;
    rec.contact_fraction = contact_fraction(st.gap, s_.contact_rule);
    rec.mean_pressure = u.to_pa(st.mean_pressure);
    rec.force = u.to_n(st.mean_pressure * s_.grid.area());
    rec.penetration = u.to_m(st.penetration);
    rec.mean_gap = u.to_m(Grid::mean(st.gap));
    rec.energy = u.to_j(r.energy);
    if (s_.observables.enabled)
      rec.observables = to_record(measure_step(s_.grid, st, s_.contact_rule, s_.observables), u);
    flag_non_finite(rec);
    return rec;
  }
  void keep(const StepRecord& rec, const ContactState& st) {
    account(rec);
    if (on_step_) on_step_(summary.steps.back(), st);
  }
  // A point the run can be continued from; `point` names it for the test points.
  void checkpoint(const ContactState& st, const PathState* path, const char* point,
                  const OuterPoint* inside = nullptr) {
    if (on_checkpoint_) on_checkpoint_(st, path, inside);
    test_point(point);
  }
  // After step k of n: a checkpoint, unless k was the last solve of the run. Then only the
  // observables and the writing remain, and a checkpoint would write three fields that are
  // written next (result.h5) or not wanted (output.fields = false): 26 GB at 32768², longer
  // than a GPU's solve there. An interruption after it redoes the last step from the last
  // checkpoint before it (after the step before, inside the step, or none: from the start).
  void after_step(std::size_t k, std::size_t n, const ContactState& st) {
    if (k + 1 < n) checkpoint(st, nullptr, "step");
    else test_point("step");
  }

 private:
  const Scene& s_;
  const StepCallback& on_step_;
  const CheckpointCallback& on_checkpoint_;
};

Backend backend_of(const Case& c) { return c.grid.backend == "cuda" ? Backend::Cuda : Backend::Cpu; }

template <class Options>
Options solver_options(const SolverSpec& spec, const Progress& progress) {
  Options o;
  o.tolerance = spec.tolerance;
  o.max_iterations = spec.max_iterations;
  o.recompute_every = spec.recompute_every;
  o.progress = progress;
  o.progress_every = spec.progress_every;
  return o;
}

// Polonsky–Keer (hard wall): no instabilities, so the steps are solved one after the other.
void run_polonsky_keer(const Case& c, const Scene& s, Run& run, std::size_t first, ContactState& state,
                       const Progress& progress) {
  auto po = solver_options<PolonskyKeer::Options>(c.solver, progress);
  po.precondition = c.solver.precondition;
  po.backend = backend_of(c);
  // On the GPU the device arrays, plans and multipliers stay from one load step to the next
  // (their set-up took 1.8 s of a 13 s solve at 16384²); on the CPU a solve's work arrays
  // are freed between steps (what the host memory estimate counts).
  po.keep_work = po.backend == Backend::Cuda;
  PolonskyKeer solver(*s.half_space, s.topography.heights, po);
  for (std::size_t k = first; k < s.targets.size(); ++k) {
    test_point("solve");
    const SolveResult r = solver.solve(s.targets[k], state);
    run.keep(run.record(k, r, state), state);
    run.after_step(k, s.targets.size(), state);
  }
}

// Quasi-static adhesion: the loading branch, each step starting from the previous one
// (a smaller load), which is the start from above that the solver needs. The solver keeps
// nothing between solves beyond the state, and within a solve nothing between outer steps
// beyond an OuterPoint, so a resumed run continues exactly, from a step's start or from
// inside it (`inside`: where the first step's solve stood).
void run_quasi_static(const Case& c, const Scene& s, Run& run, std::size_t first, ContactState& state,
                      std::optional<OuterPoint>& inside, const Progress& progress) {
  auto o = solver_options<QuasiStaticAdhesion::Options>(c.solver, progress);
  o.tension_tolerance = c.solver.tension_tolerance;
  o.max_outer = c.solver.max_outer_steps;
  o.max_seconds = c.solver.max_seconds;
  o.precondition = c.solver.precondition;
  o.backend = backend_of(c);
  o.on_outer = [&](const OuterPoint& at) { run.checkpoint(state, nullptr, "outer", &at); };
  QuasiStaticAdhesion solver(*s.half_space, s.topography.heights, std::get<ExponentialAdhesion>(s.interaction), o);
  for (std::size_t k = first; k < s.targets.size(); ++k) {
    test_point("solve");
    const SolveResult r = solver.solve(s.targets[k], state, k == first && inside ? &*inside : nullptr);
    inside.reset();
    run.keep(run.record(k, r, state), state);
    run.after_step(k, s.targets.size(), state);
  }
}

// Adhesive CG: a load path that halves steps which fail or jump (LoadPath.hpp), continued
// from `path` (where an interrupted run's walk stood, or the start).
void run_adhesive_cg(const Case& c, const Scene& s, Run& run, PathState& path, ContactState& state,
                     const Progress& progress) {
  AdhesiveSolver solver(*s.half_space, s.topography.heights, s.interaction,
                        solver_options<AdhesiveSolver::Options>(c.solver, progress));
  LoadPathOptions lo;
  lo.max_halvings = c.loading.max_halvings;
  lo.jump_fraction = c.loading.jump_fraction;
  lo.stop_on_failure = false;
  lo.pressure_floor = s.units.pressure(c.loading.jump_pressure_floor);
  lo.refine_pulloff = c.loading.refine_pulloff;
  lo.contact_rule = s.contact_rule;
  std::size_t k = path.next;
  const LoadPathResult lp = run_load_path(
      [&](const Target& t, ContactState& st) {
        test_point("solve");
        return solver.solve(t, st);
      },
      s.targets, state, path, lo,
      [&](const LoadStep& ls, const ContactState& st) {
        SolveResult r = ls.result;
        r.iterations = ls.iterations, r.fft_pairs = ls.fft_pairs, r.wall_s = ls.wall_s, r.fft_s = ls.fft_s;  // all solves of the step
        r.diagnostics = ls.diagnostics;
        StepRecord rec = run.record(k++, r, st);
        rec.jump = ls.jump;
        rec.halvings = ls.halvings;
        run.keep(rec, st);
      },
      [&](const PathState& ps, const ContactState& st) {
        run.checkpoint(st, &ps, ps.refinement == PathState::Refinement::NotStarted ? "step" : "refine");
      });
  RunSummary& sum = run.summary;
  sum.load_path = true;
  sum.halved_steps = lp.halved_steps;
  sum.jumps = lp.jumps;
  if (std::isfinite(lp.pulloff_mean_pressure)) {
    sum.pulloff_mean_pressure = s.units.to_pa(lp.pulloff_mean_pressure);
    sum.pulloff_force = s.units.to_n(lp.pulloff_mean_pressure * s.grid.area());
    sum.pulloff_branch = lp.pulloff_branch;
  }
  if (!lp.completed) run.not_converged(lp.message);
}

}  // namespace

RunSummary run_scene(const Case& c, Scene& s, const StepCallback& on_step, const Progress& progress,
                     RunPoint* from, const CheckpointCallback& on_checkpoint) {
  check_test_points();
  // The unit of cost: one FFT pair where the solver's transforms run (cuFFT on the GPU).
  const bool cuda = backend_of(c) == Backend::Cuda;
  const double pair_s = cuda ? cuda::time_fft_pair(s.grid.nx, s.grid.ny) : s.half_space->time_fft_pair();
  // Polonsky-Keer's fused sweeps (alone, and inside the quasi-static solver) run the
  // row-column pair on the CPU: time it too, for 0.1 s (at least 5 pairs; FFTW's pair
  // takes 0.25 s, and every run pays both, the tests' many small runs included).
  const double row_column_s =
      cuda || c.solver.kind == SolverKind::AdhesiveCg ? 0.0 : s.half_space->time_row_column_pair(0.1);
  const auto t0 = std::chrono::steady_clock::now();
  Run run(s, on_step, on_checkpoint);
  ContactState state;
  PathState path;
  std::optional<OuterPoint> inside;
  if (from) state = std::move(from->state), path = from->path, inside = std::move(from->inside);
  if (inside && c.solver.kind != SolverKind::QuasiStatic)
    throw std::invalid_argument("run_scene: a run continued from inside a step needs the quasi-static solver");
  const std::size_t first = from ? from->done.size() : 0;
  if (first > s.targets.size() || (path.started && path.next != first) || (inside && first >= s.targets.size()))
    throw std::invalid_argument("run_scene: the run to continue does not fit the case's load steps");
  for (std::size_t k = 0; k < first; ++k) run.account(from->done[k]);
  // The case's solver, resolved by the parser (never Auto here).
  switch (c.solver.kind) {
    case SolverKind::PolonskyKeer: run_polonsky_keer(c, s, run, first, state, progress); break;
    case SolverKind::AdhesiveCg: run_adhesive_cg(c, s, run, path, state, progress); break;
    case SolverKind::QuasiStatic: run_quasi_static(c, s, run, first, state, inside, progress); break;
    case SolverKind::Auto: throw std::logic_error("run_scene: the case's solver kind was not resolved");
  }
  RunSummary& sum = run.summary;
  sum.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sum.fft_pair_s = pair_s;
  double solve_s = 0.0, fft_s = 0.0;
  for (const StepRecord& r : sum.steps)
    solve_s += r.result.wall_s, fft_s += r.result.fft_s, sum.iterations += r.result.iterations;
  if (solve_s > 0.0) sum.fft_share = fft_s / solve_s;
  if (sum.fft_pairs > 0.0) sum.time_per_fft_pair = solve_s / (sum.fft_pairs * pair_s);
  if (sum.iterations > 0) sum.time_per_iteration = solve_s / (sum.iterations * pair_s);
  sum.row_column_pair_s = row_column_s;
  sum.floor_pair_s = row_column_s > 0.0 ? std::min(pair_s, row_column_s) : pair_s;
  if (sum.fft_pairs > 0.0) sum.time_per_floor_pair = solve_s / (sum.fft_pairs * sum.floor_pair_s);
  return sum;
}

}  // namespace cmc
