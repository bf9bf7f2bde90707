#include "cmc/run/Driver.hpp"

#include "cmc/contact/AdhesiveSolver.hpp"
#include "cmc/contact/LoadPath.hpp"
#include "cmc/contact/PolonskyKeer.hpp"

#include <chrono>
#include <cmath>
#include <variant>

namespace cmc {

RunSummary run_scene(const Case& c, Scene& s, const StepCallback& on_step, const Progress& progress,
                     const std::vector<StepRecord>* done, const ContactState* warm) {
  const auto t0 = std::chrono::steady_clock::now();
  RunSummary run;
  ContactState state;
  if (warm) state = *warm;
  // Adds a finished step to the run; the first unconverged one sets the status.
  auto account = [&](const StepRecord& rec) {
    run.fft_pairs += rec.result.fft_pairs;
    if (!rec.result.converged && run.status == "converged") {
      run.status = "not_converged";
      run.message = "step " + std::to_string(rec.index) + ": " + rec.result.message;
    }
    run.steps.push_back(rec);
  };
  const std::size_t first = done ? done->size() : 0;
  for (std::size_t k = 0; k < first; ++k) account((*done)[k]);
  const Units& u = s.units;
  const bool adhesive = !std::holds_alternative<HardWall>(s.interaction);
  // Fill an SI record of step k from its solved state.
  auto record = [&](std::size_t k, const SolveResult& r, const ContactState& st, double contact_fraction) {
    StepRecord rec;
    rec.index = int(k);
    rec.branch = k < s.unloading_from ? "loading" : "unloading";
    rec.result = r;
    rec.contact_fraction = contact_fraction;
    rec.mean_pressure = u.to_pa(st.mean_pressure);
    rec.force = u.to_n(st.mean_pressure * s.grid.area());
    rec.penetration = u.to_m(st.penetration);
    rec.mean_gap = u.to_m(Grid::mean(st.gap));
    rec.energy = u.to_j(r.energy);
    if (s.observables.enabled) rec.observables = measure_step(s, st);
    return rec;
  };
  auto keep = [&](const StepRecord& rec, const ContactState& st) {
    account(rec);
    if (on_step) on_step(run.steps.back(), st);
  };

  if (!adhesive) {
    // Hard wall: no instabilities, so the steps are solved one after the other.
    PolonskyKeer::Options o;
    o.tolerance = c.solver.tolerance;
    o.max_iterations = c.solver.max_iterations;
    o.recompute_every = c.solver.recompute_every;
    o.progress = progress;
    PolonskyKeer solver(*s.half_space, s.topography.heights, o);
    for (std::size_t k = first; k < s.targets.size(); ++k) {
      const SolveResult r = solver.solve(s.targets[k], state);
      double in_contact = 0.0;
      for (double p : state.pressure) in_contact += p > 0.0 ? 1.0 : 0.0;
      double v[1] = {in_contact};
      Grid::allreduce_sum(v);
      keep(record(k, r, state, v[0] / double(s.grid.size())), state);
    }
  } else {
    // Adhesion: a load path that halves steps which fail or jump (LoadPath.hpp).
    AdhesiveSolver::Options o;
    o.tolerance = c.solver.tolerance;
    o.max_iterations = c.solver.max_iterations;
    o.recompute_every = c.solver.recompute_every;
    o.progress = progress;
    AdhesiveSolver solver(*s.half_space, s.topography.heights, s.interaction, o);
    LoadPathOptions lo;
    lo.max_halvings = c.loading.max_halvings;
    lo.jump_fraction = c.loading.jump_fraction;
    lo.stop_on_failure = false;
    lo.pressure_floor = u.pressure(c.loading.jump_pressure_floor);
    lo.refine_pulloff = c.loading.refine_pulloff;
    const std::vector<Target> rest(s.targets.begin() + long(first), s.targets.end());
    std::size_t k = first;
    const LoadPathResult lp = run_load_path(
        [&](const Target& t, ContactState& st) { return solver.solve(t, st); }, rest, state, lo,
        [&](const LoadStep& ls, const ContactState& st) {
          SolveResult r = ls.result;
          r.iterations = ls.iterations, r.fft_pairs = ls.fft_pairs, r.wall_s = ls.wall_s;  // all solves of the step
          StepRecord rec = record(k++, r, st, ls.contact_fraction);
          rec.jump = ls.jump;
          rec.halvings = ls.halvings;
          keep(rec, st);
        });
    run.load_path = true;
    run.halved_steps = lp.halved_steps;
    run.jumps = lp.jumps;
    if (std::isfinite(lp.pulloff_mean_pressure)) {
      run.pulloff_mean_pressure = u.to_pa(lp.pulloff_mean_pressure);
      run.pulloff_force = u.to_n(lp.pulloff_mean_pressure * s.grid.area());
      run.pulloff_branch = branch_name(lp.pulloff_branch);
    }
    if (!lp.completed && run.status == "converged") {
      run.status = "not_converged";
      run.message = lp.message;
    }
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

}  // namespace cmc
