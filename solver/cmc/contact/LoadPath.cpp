#include "cmc/contact/LoadPath.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace cmc {

std::vector<Target> ramp(Control control, double from, double to, int n) {
  if (n < 1) throw std::invalid_argument("ramp: need at least one step");
  std::vector<Target> t;
  for (int i = 0; i <= n; ++i) t.push_back({control, i == n ? to : from + (to - from) * double(i) / n});
  return t;
}

std::vector<Target> load_unload(Control control, double start, double peak, double end, int n_load, int n_unload) {
  auto t = ramp(control, start, peak, n_load);
  const auto u = ramp(control, peak, end, n_unload);
  t.insert(t.end(), u.begin() + 1, u.end());
  return t;
}

namespace {

double value_of(const ContactState& s, Control c) { return c == Control::Penetration ? s.penetration : s.mean_pressure; }

// A walk along a path. Everything it carries from one solve to the next is in the
// PathState (LoadPath.hpp), so that a walk continued from a copy of it does the same.
class PathWalk {
 public:
  PathWalk(const StepSolver& solve, const LoadPathOptions& opt, Control control, double first_value, ContactState& state,
           PathState& ps, const PathCheckpoint& on_checkpoint)
      : solve_(solve), opt_(opt), control_(control), state_(state), ps_(ps), on_checkpoint_(on_checkpoint) {
    if (ps_.started) return;  // continued from a checkpoint
    ps_.started = true;
    ps_.have_prev = !state.empty();
    ps_.value = ps_.have_prev ? value_of(state, control) : first_value;
    ps_.contact_fraction = ps_.have_prev ? contact_fraction(state.gap, opt.contact_rule) : 0.0;
    ps_.mean_pressure = ps_.have_prev ? state.mean_pressure : 0.0;
    ps_.pressure_scale = ps_.have_prev ? std::abs(ps_.mean_pressure) : 0.0;
    ps_.last_value = ps_.value;
    ps_.have_last = ps_.have_prev;
  }

  // Reach target `t` from the last accepted value, halving the increment where a solve
  // fails or jumps (see LoadPath.hpp); `failed` tells whether its final solve did not converge.
  LoadStep step(const Target& t, bool& failed);
  // Golden-section search for the pull-off between the best solve's accepted neighbours,
  // continued from where the path state says it stands.
  void refine_pulloff();
  double reached() const { return ps_.value; }  // the target value of the last accepted solve

 private:
  bool is_jump(double a_new, double p_new) const {
    if (!ps_.have_prev) return false;
    const double f = opt_.jump_fraction, pf = opt_.pressure_floor > 0.0 ? opt_.pressure_floor : ps_.pressure_scale;
    const double a_prev = ps_.contact_fraction, p_prev = ps_.mean_pressure;
    const bool ja = std::abs(a_new - a_prev) > f * std::max(a_prev, opt_.contact_fraction_floor);
    const bool jp = std::abs(p_new - p_prev) > f * std::max(std::abs(p_prev), pf);
    return ja || jp;
  }
  void note_pulloff(double v);
  void accept(ContactState&& trial, double a_new) {
    state_ = std::move(trial);
    ps_.have_prev = true;
    ps_.contact_fraction = a_new;
    ps_.mean_pressure = state_.mean_pressure;
    ps_.pressure_scale = std::max(ps_.pressure_scale, std::abs(ps_.mean_pressure));
  }
  bool refinement_solve(double v, double& p);

  const StepSolver& solve_;
  const LoadPathOptions& opt_;
  const Control control_;
  ContactState& state_;
  PathState& ps_;
  const PathCheckpoint& on_checkpoint_;
};

void PathWalk::note_pulloff(double v) {
  if (ps_.pulloff_is_last) {  // the previous best's right-hand neighbour
    ps_.pulloff_after = v;
    ps_.pulloff_is_last = false;
  }
  if (std::isnan(ps_.pulloff_mean_pressure) || state_.mean_pressure < ps_.pulloff_mean_pressure) {
    ps_.pulloff_mean_pressure = state_.mean_pressure;
    ps_.pulloff_value = v;
    ps_.pulloff_branch = ps_.branch;
    if (opt_.refine_pulloff > 0) ps_.pulloff_state = state_;
    ps_.pulloff_before = ps_.have_last ? ps_.last_value : std::numeric_limits<double>::quiet_NaN();
    ps_.pulloff_after = std::numeric_limits<double>::quiet_NaN();
    ps_.pulloff_is_last = true;
  }
  ps_.last_value = v;
  ps_.have_last = true;
}

LoadStep PathWalk::step(const Target& t, bool& failed) {
  const double vk = t.value;
  if (vk > ps_.value) ps_.branch = Branch::Loading;
  else if (vk < ps_.value) ps_.branch = Branch::Unloading;
  LoadStep rec;
  rec.target = t;
  rec.branch = ps_.branch;
  const double v0 = ps_.value;
  double pos = v0;
  int level = 0;
  failed = false;
  for (;;) {
    const double h = (vk - v0) / std::ldexp(1.0, level);
    // The last sub-step lands on the target exactly (1e-9: round-off in pos).
    const bool last = !ps_.have_prev || std::abs(vk - pos) <= std::abs(h) * (1.0 + 1e-9) || h == 0.0;
    const double next = last ? vk : pos + h;
    ContactState trial = state_;
    const SolveResult r = solve_({control_, next}, trial);
    ++rec.solves;
    rec.iterations += r.iterations;
    rec.fft_pairs += r.fft_pairs;
    rec.wall_s += r.wall_s;
    rec.fft_s += r.fft_s;
    rec.diagnostics += r.diagnostics;
    const double a_new = contact_fraction(trial.gap, opt_.contact_rule);
    const bool jumped = r.converged && is_jump(a_new, trial.mean_pressure);
    if ((!r.converged || jumped) && level < opt_.max_halvings && ps_.have_prev) {
      ++level;
      continue;  // retry from the last accepted sub-step with half the increment
    }
    // Accept (a jump at the finest level is real; a failure there is recorded).
    accept(std::move(trial), a_new);
    rec.result = r;
    if (jumped) rec.jump = true;
    if (!r.converged) {
      failed = true;
      ps_.pulloff_is_last = false;
    } else {
      note_pulloff(next);
    }
    pos = next;
    if ((failed && opt_.stop_on_failure) || last) break;
  }
  ps_.value = pos;
  rec.halvings = level;
  rec.mean_pressure = state_.mean_pressure;
  rec.penetration = state_.penetration;
  rec.contact_fraction = ps_.contact_fraction;
  return rec;
}

// One solve of the refinement at target value v, warm-started from the best solve's
// state (the branch is kept); p gets its mean pressure. False if it did not converge.
bool PathWalk::refinement_solve(double v, double& p) {
  ContactState s = ps_.pulloff_state;
  const SolveResult r = solve_({control_, v}, s);
  ++ps_.refinement_solves;
  if (!r.converged) return false;
  p = s.mean_pressure;
  if (p < ps_.pulloff_mean_pressure) {
    ps_.pulloff_mean_pressure = p;
    ps_.pulloff_value = v;
  }
  return true;
}

void PathWalk::refine_pulloff() {
  using R = PathState::Refinement;
  const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
  if (ps_.refinement == R::NotStarted) {
    if (!(opt_.refine_pulloff > 0 && std::isfinite(ps_.pulloff_before) && std::isfinite(ps_.pulloff_after) &&
          !ps_.pulloff_state.empty())) {
      ps_.refinement = R::Done;
      return;
    }
    ps_.lo = std::min(ps_.pulloff_before, ps_.pulloff_after);
    ps_.hi = std::max(ps_.pulloff_before, ps_.pulloff_after);
    ps_.x1 = ps_.hi - gr * (ps_.hi - ps_.lo);
    ps_.x2 = ps_.lo + gr * (ps_.hi - ps_.lo);
    ps_.have_f1 = ps_.have_f2 = false;
    ps_.refinement = R::Running;
  }
  // Every solve is followed by a checkpoint. The bracket moves only once both inner
  // points are solved, so a walk continued from any checkpoint makes the same solves.
  while (ps_.refinement == R::Running) {
    if (!ps_.have_f1 || !ps_.have_f2) {
      const bool first = !ps_.have_f1;
      if (refinement_solve(first ? ps_.x1 : ps_.x2, first ? ps_.f1 : ps_.f2)) (first ? ps_.have_f1 : ps_.have_f2) = true;
      else ps_.refinement = R::Done;  // a solve that failed ends the search
      if (on_checkpoint_) on_checkpoint_(ps_, state_);
      continue;
    }
    if (ps_.refinement_solves >= opt_.refine_pulloff) {
      ps_.refinement = R::Done;
    } else if (ps_.f1 < ps_.f2) {
      ps_.hi = ps_.x2;
      ps_.x2 = ps_.x1;
      ps_.f2 = ps_.f1;
      ps_.x1 = ps_.hi - gr * (ps_.hi - ps_.lo);
      ps_.have_f1 = false;
    } else {
      ps_.lo = ps_.x1;
      ps_.x1 = ps_.x2;
      ps_.f1 = ps_.f2;
      ps_.x2 = ps_.lo + gr * (ps_.hi - ps_.lo);
      ps_.have_f2 = false;
    }
  }
}

}  // namespace

LoadPathResult run_load_path(const StepSolver& solve, const std::vector<Target>& targets, ContactState& state,
                             const LoadPathOptions& opt, const LoadStepCallback& on_step) {
  PathState path;
  return run_load_path(solve, targets, state, path, opt, on_step);
}

LoadPathResult run_load_path(const StepSolver& solve, const std::vector<Target>& targets, ContactState& state,
                             PathState& path, const LoadPathOptions& opt, const LoadStepCallback& on_step,
                             const PathCheckpoint& on_checkpoint) {
  LoadPathResult out;
  // The whole path's counters and pull-off, however this returns.
  auto result = [&]() -> LoadPathResult& {
    out.failed_steps = path.failed_steps;
    out.halved_steps = path.halved_steps;
    out.jumps = path.jumps;
    out.max_halvings = path.max_halvings;
    out.pulloff_mean_pressure = path.pulloff_mean_pressure;
    out.pulloff_target = {targets.empty() ? Control::Penetration : targets.front().control, path.pulloff_value};
    out.pulloff_branch = path.pulloff_branch;
    out.pulloff_refinement_solves = path.refinement_solves;
    return out;
  };
  if (targets.empty()) {
    out.completed = true;
    return result();
  }
  const Control control = targets.front().control;
  for (const auto& t : targets)
    if (t.control != control) throw std::invalid_argument("run_load_path: all targets must share one control");
  if (!solve) throw std::invalid_argument("run_load_path: no solver");
  if (path.next > targets.size()) throw std::invalid_argument("run_load_path: the path state is past the last target");
  PathWalk walk(solve, opt, control, targets.front().value, state, path, on_checkpoint);
  for (std::size_t k = path.next; k < targets.size(); ++k) {
    bool failed = false;
    const LoadStep rec = walk.step(targets[k], failed);
    path.max_halvings = std::max(path.max_halvings, rec.halvings);
    if (rec.halvings > 0) ++path.halved_steps;
    if (rec.jump) ++path.jumps;
    if (failed) ++path.failed_steps;
    path.next = k + 1;
    out.steps.push_back(rec);
    if (on_step) on_step(out.steps.back(), state);
    if (on_checkpoint) on_checkpoint(path, state);
    if (failed && opt.stop_on_failure) {
      std::ostringstream s;
      s << "load path stopped at step " << k << " (target " << targets[k].value << ", reached " << walk.reached()
        << "): " << rec.result.message;
      out.message = s.str();
      return result();
    }
  }
  walk.refine_pulloff();
  out.completed = path.failed_steps == 0;
  if (!out.completed) {
    std::ostringstream s;
    s << path.failed_steps << " step(s) did not converge";
    out.message = s.str();
  }
  return result();
}

}  // namespace cmc
