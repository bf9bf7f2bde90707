#include "cmc/Driver.hpp"

#include "cmc/PolonskyKeer.hpp"

#include <chrono>

namespace cmc {

RunSummary run_scene(const Case& c, Scene& s, const StepCallback& on_step, const Progress& progress,
                     const std::vector<StepRecord>* done, const ContactState* warm) {
  const auto t0 = std::chrono::steady_clock::now();
  RunSummary run;
  PolonskyKeer::Options o;
  o.tolerance = c.solver.tolerance;
  o.max_iterations = c.solver.max_iterations;
  o.recompute_every = c.solver.recompute_every;
  o.progress = progress;
  PolonskyKeer solver(*s.half_space, s.topography.heights, o);
  ContactState state;
  if (warm) state = *warm;
  const std::size_t first = done ? done->size() : 0;
  for (std::size_t k = 0; k < first; ++k) {
    run.steps.push_back((*done)[k]);
    run.fft_pairs += (*done)[k].result.fft_pairs;
    if (!(*done)[k].result.converged && run.status == "converged") {
      run.status = "not_converged";
      run.message = "step " + std::to_string(k) + ": " + (*done)[k].result.message;
    }
  }
  const Units& u = s.units;
  for (std::size_t k = first; k < s.targets.size(); ++k) {
    StepRecord rec;
    rec.index = int(k);
    rec.result = solver.solve(s.targets[k], state);
    double in_contact = 0.0;
    for (double p : state.pressure) in_contact += p > 0.0 ? 1.0 : 0.0;
    double v[1] = {in_contact};
    Grid::allreduce_sum(v);
    rec.contact_fraction = v[0] / double(s.grid.size());
    rec.mean_pressure = u.to_pa(state.mean_pressure);
    rec.force = u.to_n(state.mean_pressure * s.grid.area());
    rec.penetration = u.to_m(state.penetration);
    rec.mean_gap = u.to_m(Grid::mean(state.gap));
    rec.elastic_energy = u.to_j(rec.result.energy);
    if (s.observables.enabled) rec.observables = measure_step(s, state);
    run.fft_pairs += rec.result.fft_pairs;
    if (!rec.result.converged && run.status == "converged") {
      run.status = "not_converged";
      run.message = "step " + std::to_string(k) + ": " + rec.result.message;
    }
    run.steps.push_back(rec);
    if (on_step) on_step(rec, state);
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return run;
}

}  // namespace cmc
