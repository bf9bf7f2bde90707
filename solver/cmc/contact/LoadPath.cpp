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
  const double f = opt.jump_fraction;

  bool have_prev = !state.empty();
  double v_prev = have_prev ? value_of(state, control) : targets.front().value;
  double a_prev = have_prev ? contact_fraction(state.gap, opt.contact_rule) : 0.0;
  double p_prev = have_prev ? state.mean_pressure : 0.0;
  double p_scale = have_prev ? std::abs(p_prev) : 0.0;  // largest |p| accepted so far
  Branch branch = Branch::Loading;

  auto is_jump = [&](double a_new, double p_new) {
    if (!have_prev) return false;
    const double pf = opt.pressure_floor > 0.0 ? opt.pressure_floor : p_scale;
    const bool ja = std::abs(a_new - a_prev) > f * std::max(a_prev, opt.contact_fraction_floor);
    const bool jp = std::abs(p_new - p_prev) > f * std::max(std::abs(p_prev), pf);
    return ja || jp;
  };
  // Pull-off bookkeeping: the best solve, the accepted values just before and after it.
  ContactState best_state;
  double best_prev = std::numeric_limits<double>::quiet_NaN(), best_next = best_prev;
  bool best_is_last = false;
  double last_value = v_prev;
  bool have_last = have_prev;
  auto note_pulloff = [&](const ContactState& s, double v) {
    if (best_is_last) {  // the previous best's right-hand neighbour
      best_next = v;
      best_is_last = false;
    }
    if (std::isnan(out.pulloff_mean_pressure) || s.mean_pressure < out.pulloff_mean_pressure) {
      out.pulloff_mean_pressure = s.mean_pressure;
      out.pulloff_target = {control, v};
      out.pulloff_branch = branch;
      if (opt.refine_pulloff > 0) best_state = s;
      best_prev = have_last ? last_value : std::numeric_limits<double>::quiet_NaN();
      best_next = std::numeric_limits<double>::quiet_NaN();
      best_is_last = true;
    }
    last_value = v;
    have_last = true;
  };

  for (std::size_t k = 0; k < targets.size(); ++k) {
    const double vk = targets[k].value;
    if (vk > v_prev) branch = Branch::Loading;
    else if (vk < v_prev) branch = Branch::Unloading;
    LoadStep rec;
    rec.target = targets[k];
    rec.branch = branch;
    const double v0 = v_prev;
    double pos = v0;
    int level = 0;
    bool failed = false;
    for (;;) {
      const double h = (vk - v0) / std::ldexp(1.0, level);
      const bool last = !have_prev || std::abs(vk - pos) <= std::abs(h) * (1.0 + 1e-9) || h == 0.0;
      const double next = last ? vk : pos + h;
      ContactState trial = state;
      const SolveResult r = solve({control, next}, trial);
      ++rec.solves;
      rec.iterations += r.iterations;
      rec.fft_pairs += r.fft_pairs;
      rec.wall_s += r.wall_s;
      const double a_new = contact_fraction(trial.gap, opt.contact_rule);
      const bool jumped = r.converged && is_jump(a_new, trial.mean_pressure);
      if ((!r.converged || jumped) && level < opt.max_halvings && have_prev) {
        ++level;
        continue;  // retry from the last accepted sub-step with half the increment
      }
      // Accept (a jump at the finest level is real; a failure there is recorded).
      state = std::move(trial);
      rec.result = r;
      if (jumped) rec.jump = true;
      if (!r.converged) {
        failed = true;
        best_is_last = false;
      } else {
        note_pulloff(state, next);
      }
      have_prev = true;
      a_prev = a_new;
      p_prev = state.mean_pressure;
      p_scale = std::max(p_scale, std::abs(p_prev));
      pos = next;
      if (failed && opt.stop_on_failure) break;
      if (last) break;
    }
    v_prev = pos;
    rec.halvings = level;
    rec.mean_pressure = state.mean_pressure;
    rec.penetration = state.penetration;
    rec.contact_fraction = a_prev;
    out.max_halvings = std::max(out.max_halvings, level);
    if (level > 0) ++out.halved_steps;
    if (rec.jump) ++out.jumps;
    if (failed) ++out.failed_steps;
    out.steps.push_back(rec);
    if (on_step) on_step(out.steps.back(), state);
    if (failed && opt.stop_on_failure) {
      std::ostringstream s;
      s << "load path stopped at step " << k << " (target " << vk << ", reached " << pos
        << "): " << rec.result.message;
      out.message = s.str();
      return out;
    }
  }
  // ---- golden-section refinement of the pull-off between its accepted neighbours
  if (opt.refine_pulloff > 0 && std::isfinite(best_prev) && std::isfinite(best_next) && !best_state.empty()) {
    const double gr = 0.5 * (std::sqrt(5.0) - 1.0);
    const double v_best = out.pulloff_target.value;
    double lo = std::min(best_prev, best_next), hi = std::max(best_prev, best_next);
    double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo);
    auto eval = [&](double v, double& p) {
      ContactState s = best_state;
      const SolveResult r = solve({control, v}, s);
      ++out.pulloff_refinement_solves;
      if (!r.converged) return false;
      p = s.mean_pressure;
      if (p < out.pulloff_mean_pressure) {
        out.pulloff_mean_pressure = p;
        out.pulloff_target = {control, v};
      }
      return true;
    };
    (void)v_best;
    double f1 = 0.0, f2 = 0.0;
    bool ok = eval(x1, f1) && eval(x2, f2);
    while (ok && out.pulloff_refinement_solves < opt.refine_pulloff) {
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

  out.completed = out.failed_steps == 0;
  if (!out.completed) {
    std::ostringstream s;
    s << out.failed_steps << " step(s) did not converge";
    out.message = s.str();
  }
  return out;
}

}  // namespace cmc
