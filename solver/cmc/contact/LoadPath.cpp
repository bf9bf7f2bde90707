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

// A walk along the path: the last accepted solve (state, target value, contact fraction,
// mean pressure), the branch, and the pull-off bookkeeping.
class PathWalk {
 public:
  PathWalk(const StepSolver& solve, const LoadPathOptions& opt, Control control, double first_value, ContactState& state,
           LoadPathResult& out)
      : solve_(solve), opt_(opt), control_(control), state_(state), out_(out), have_prev_(!state.empty()) {
    v_prev_ = have_prev_ ? value_of(state, control) : first_value;
    a_prev_ = have_prev_ ? contact_fraction(state.gap, opt.contact_rule) : 0.0;
    p_prev_ = have_prev_ ? state.mean_pressure : 0.0;
    p_scale_ = have_prev_ ? std::abs(p_prev_) : 0.0;
    last_value_ = v_prev_;
    have_last_ = have_prev_;
  }

  // Reach target `t` from the last accepted value, halving the increment where a solve
  // fails or jumps (see LoadPath.hpp); `failed` tells whether its final solve did not converge.
  LoadStep step(const Target& t, bool& failed);
  // Golden-section search for the pull-off between the best solve's accepted neighbours.
  void refine_pulloff();
  double reached() const { return v_prev_; }  // the target value of the last accepted solve

 private:
  bool is_jump(double a_new, double p_new) const {
    if (!have_prev_) return false;
    const double f = opt_.jump_fraction, pf = opt_.pressure_floor > 0.0 ? opt_.pressure_floor : p_scale_;
    const bool ja = std::abs(a_new - a_prev_) > f * std::max(a_prev_, opt_.contact_fraction_floor);
    const bool jp = std::abs(p_new - p_prev_) > f * std::max(std::abs(p_prev_), pf);
    return ja || jp;
  }
  void note_pulloff(double v);
  void accept(ContactState&& trial, double a_new) {
    state_ = std::move(trial);
    have_prev_ = true;
    a_prev_ = a_new;
    p_prev_ = state_.mean_pressure;
    p_scale_ = std::max(p_scale_, std::abs(p_prev_));
  }

  const StepSolver& solve_;
  const LoadPathOptions& opt_;
  const Control control_;
  ContactState& state_;
  LoadPathResult& out_;
  bool have_prev_;
  double v_prev_, a_prev_, p_prev_, p_scale_;  // p_scale_: the largest |p| accepted so far
  Branch branch_ = Branch::Loading;
  // Pull-off: the best solve, the accepted values just before and after it.
  ContactState best_state_;
  double best_prev_ = std::numeric_limits<double>::quiet_NaN(), best_next_ = best_prev_;
  bool best_is_last_ = false;
  double last_value_;
  bool have_last_;
};

void PathWalk::note_pulloff(double v) {
  if (best_is_last_) {  // the previous best's right-hand neighbour
    best_next_ = v;
    best_is_last_ = false;
  }
  if (std::isnan(out_.pulloff_mean_pressure) || state_.mean_pressure < out_.pulloff_mean_pressure) {
    out_.pulloff_mean_pressure = state_.mean_pressure;
    out_.pulloff_target = {control_, v};
    out_.pulloff_branch = branch_;
    if (opt_.refine_pulloff > 0) best_state_ = state_;
    best_prev_ = have_last_ ? last_value_ : std::numeric_limits<double>::quiet_NaN();
    best_next_ = std::numeric_limits<double>::quiet_NaN();
    best_is_last_ = true;
  }
  last_value_ = v;
  have_last_ = true;
}

LoadStep PathWalk::step(const Target& t, bool& failed) {
  const double vk = t.value;
  if (vk > v_prev_) branch_ = Branch::Loading;
  else if (vk < v_prev_) branch_ = Branch::Unloading;
  LoadStep rec;
  rec.target = t;
  rec.branch = branch_;
  const double v0 = v_prev_;
  double pos = v0;
  int level = 0;
  failed = false;
  for (;;) {
    const double h = (vk - v0) / std::ldexp(1.0, level);
    // The last sub-step lands on the target exactly (1e-9: round-off in pos).
    const bool last = !have_prev_ || std::abs(vk - pos) <= std::abs(h) * (1.0 + 1e-9) || h == 0.0;
    const double next = last ? vk : pos + h;
    ContactState trial = state_;
    const SolveResult r = solve_({control_, next}, trial);
    ++rec.solves;
    rec.iterations += r.iterations;
    rec.fft_pairs += r.fft_pairs;
    rec.wall_s += r.wall_s;
    rec.diagnostics += r.diagnostics;
    const double a_new = contact_fraction(trial.gap, opt_.contact_rule);
    const bool jumped = r.converged && is_jump(a_new, trial.mean_pressure);
    if ((!r.converged || jumped) && level < opt_.max_halvings && have_prev_) {
      ++level;
      continue;  // retry from the last accepted sub-step with half the increment
    }
    // Accept (a jump at the finest level is real; a failure there is recorded).
    accept(std::move(trial), a_new);
    rec.result = r;
    if (jumped) rec.jump = true;
    if (!r.converged) {
      failed = true;
      best_is_last_ = false;
    } else {
      note_pulloff(next);
    }
    pos = next;
    if ((failed && opt_.stop_on_failure) || last) break;
  }
  v_prev_ = pos;
  rec.halvings = level;
  rec.mean_pressure = state_.mean_pressure;
  rec.penetration = state_.penetration;
  rec.contact_fraction = a_prev_;
  return rec;
}

void PathWalk::refine_pulloff() {
  if (!(opt_.refine_pulloff > 0 && std::isfinite(best_prev_) && std::isfinite(best_next_) && !best_state_.empty()))
    return;
  const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = std::min(best_prev_, best_next_), hi = std::max(best_prev_, best_next_);
  double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo);
  auto eval = [&](double v, double& p) {
    ContactState s = best_state_;
    const SolveResult r = solve_({control_, v}, s);
    ++out_.pulloff_refinement_solves;
    if (!r.converged) return false;
    p = s.mean_pressure;
    if (p < out_.pulloff_mean_pressure) {
      out_.pulloff_mean_pressure = p;
      out_.pulloff_target = {control_, v};
    }
    return true;
  };
  double f1 = 0.0, f2 = 0.0;
  bool ok = eval(x1, f1) && eval(x2, f2);
  while (ok && out_.pulloff_refinement_solves < opt_.refine_pulloff) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - gr * (hi - lo);
      ok = eval(x1, f1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + gr * (hi - lo);
      ok = eval(x2, f2);
    }
  }
}

}  // namespace

LoadPathResult run_load_path(const StepSolver& solve, const std::vector<Target>& targets, ContactState& state,
                             const LoadPathOptions& opt, const LoadStepCallback& on_step) {
  LoadPathResult out;
  out.pulloff_mean_pressure = std::numeric_limits<double>::quiet_NaN();
  if (targets.empty()) {
    out.completed = true;
    return out;
  }
  const Control control = targets.front().control;
  for (const auto& t : targets)
    if (t.control != control) throw std::invalid_argument("run_load_path: all targets must share one control");
  if (!solve) throw std::invalid_argument("run_load_path: no solver");
  PathWalk walk(solve, opt, control, targets.front().value, state, out);
  for (std::size_t k = 0; k < targets.size(); ++k) {
    bool failed = false;
    const LoadStep rec = walk.step(targets[k], failed);
    out.max_halvings = std::max(out.max_halvings, rec.halvings);
    if (rec.halvings > 0) ++out.halved_steps;
    if (rec.jump) ++out.jumps;
    if (failed) ++out.failed_steps;
    out.steps.push_back(rec);
    if (on_step) on_step(out.steps.back(), state);
    if (failed && opt.stop_on_failure) {
      std::ostringstream s;
      s << "load path stopped at step " << k << " (target " << targets[k].value << ", reached "
        << walk.reached() << "): " << rec.result.message;
      out.message = s.str();
      return out;
    }
  }
  walk.refine_pulloff();
  out.completed = out.failed_steps == 0;
  if (!out.completed) {
    std::ostringstream s;
    s << out.failed_steps << " step(s) did not converge";
    out.message = s.str();
  }
  return out;
}

}  // namespace cmc
