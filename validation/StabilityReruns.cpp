// The stability checks that solve a case again (Stability.hpp): the same bits on a rerun,
// 1 against 2 threads, and continuity under a small change of one parameter.
#include "StabilityParts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>

namespace cmc::stability {

namespace {

// CMC_THREADS set for a scope (grid/Grid.hpp thread_count() reads it at every pass and plan)
// and restored after it.
class ScopedThreads {
 public:
  explicit ScopedThreads(int n) {
    if (const char* v = std::getenv("CMC_THREADS")) before_ = v;
    ::setenv("CMC_THREADS", std::to_string(n).c_str(), 1);
  }
  ~ScopedThreads() {
    if (before_) ::setenv("CMC_THREADS", before_->c_str(), 1);
    else ::unsetenv("CMC_THREADS");
  }
  ScopedThreads(const ScopedThreads&) = delete;
  ScopedThreads& operator=(const ScopedThreads&) = delete;

 private:
  std::optional<std::string> before_;
};

bool same_bits_of(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The number of values that differ in their bits.
double differing(const Field& a, const Field& b) {
  if (a.size() != b.size()) return double(std::max(a.size(), b.size()));
  return double(Grid::parallel_reduce<SumReduction>(a.size(), [&](std::size_t s, std::size_t e, SumReduction& acc) {
    for (std::size_t k = s; k < e; ++k) acc.v += same_bits_of(a[k], b[k]) ? 0.0 : 1.0;
  }).v);
}

// The largest |a - b| of two fields over `scale`.
double field_difference(const Field& a, const Field& b, double scale) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  return largest(a.size(), [&](std::size_t k) { return relative_difference(a[k], b[k], scale); });
}

// The largest difference of two solutions of one case, step by step (Stability.hpp, threads).
double solution_difference(const SolvedCase& a, const SolvedCase& b) {
  if (a.states.size() != b.states.size()) return std::numeric_limits<double>::infinity();
  const double height = height_scale(a.scene, a.states);
  double worst = 0.0;
  for (std::size_t k = 0; k < a.states.size(); ++k) {
    const ContactState &x = a.states[k], &y = b.states[k];
    const double P =
        std::max(std::abs(x.mean_pressure), largest(x.pressure.size(), [&](std::size_t k) { return std::abs(x.pressure[k]); }));
    worst = std::max({worst, field_difference(x.pressure, y.pressure, P), field_difference(x.gap, y.gap, height),
                      relative_difference(x.mean_pressure, y.mean_pressure, P),
                      relative_difference(x.penetration, y.penetration, height),
                      relative_difference(a.run.steps[k].contact_fraction, b.run.steps[k].contact_fraction, 1.0)});
  }
  return worst;
}

// The observable of a continuity check at step k (SI), or the path's pull-off.
double observable(const RunSummary& run, PathObservable o, std::size_t k) {
  const StepRecord& r = run.steps[k];
  switch (o) {
    case PathObservable::ContactFraction: return r.contact_fraction;
    case PathObservable::MeanGap: return r.mean_gap;
    case PathObservable::MeanPressure: return r.mean_pressure;
    case PathObservable::Penetration: return r.penetration;
    case PathObservable::Pulloff: return run.pulloff_mean_pressure;
  }
  return 0.0;
}

// The case with `parameter` (a number or an array of numbers) scaled by 1 + change.
Case scaled_case(const Case& c, const StabilityCheck& ch) {
  toml::table t = c.resolved;
  const auto dot = ch.parameter.rfind('.');
  toml::table* section = t.at_path(ch.parameter.substr(0, dot)).as_table();
  const std::string key = ch.parameter.substr(dot + 1);
  const double f = 1.0 + ch.change;
  if (const toml::array* a = section->get(key)->as_array()) {
    toml::array scaled;
    for (const auto& e : *a) scaled.push_back(e.value_or(0.0) * f);
    section->insert_or_assign(key, scaled);
  } else {
    section->insert_or_assign(key, section->get(key)->value_or(0.0) * f);
  }
  return parse_case(t, c.file + " (" + ch.parameter + " x " + text(f) + ")");
}

// The case's loading branch (no unloading steps) solved by another solver.
Case other_solver_case(const Case& c, const StabilityCheck& ch) {
  toml::table t = c.resolved;
  t["loading"].as_table()->erase("unloading");
  t["solver"].as_table()->insert_or_assign("kind", std::string(kind_name(ch.solver)));
  return parse_case(t, c.file + " (loading branch, solver " + std::string(kind_name(ch.solver)) + ")");
}

// The largest relative change of the observable between two runs of a path, over the steps
// both have but those left out; infinity when `all` steps must be in both and are not.
double path_change(const RunSummary& a, const RunSummary& b, const StabilityCheck& ch, bool all) {
  const std::size_t steps = std::min(a.steps.size(), b.steps.size());
  if (all && a.steps.size() != b.steps.size()) return std::numeric_limits<double>::infinity();
  double largest = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < steps; ++k) largest = std::max(largest, std::abs(observable(a, ch.observable, k)));
  for (std::size_t k = 0; k < steps; ++k) {
    if (std::find(ch.skip_steps.begin(), ch.skip_steps.end(), int(k)) != ch.skip_steps.end()) continue;
    const double v = observable(a, ch.observable, k), w = observable(b, ch.observable, k);
    worst = std::max(worst, relative_difference(v, w, std::max(std::abs(v), 1e-3 * largest)));
  }
  return worst;
}

std::string left_out(const StabilityCheck& ch) {
  return ch.skip_steps.empty() ? "" : " (" + std::to_string(ch.skip_steps.size()) + " steps left out)";
}

}  // namespace

Measure same_bits(const Case& c, const SolvedCase& first) {
  const SolvedCase again = solve_case(c);
  double n = double(std::max(first.states.size(), again.states.size()) - std::min(first.states.size(), again.states.size()));
  for (std::size_t k = 0; k < std::min(first.states.size(), again.states.size()); ++k) {
    const ContactState &x = first.states[k], &y = again.states[k];
    n += differing(x.pressure, y.pressure) + differing(x.displacement, y.displacement) + differing(x.gap, y.gap);
    const SolveResult &rx = first.run.steps[k].result, &ry = again.run.steps[k].result;
    for (const auto& [a, b] : {std::pair{x.mean_pressure, y.mean_pressure}, std::pair{x.penetration, y.penetration},
                               std::pair{rx.residual, ry.residual}, std::pair{double(rx.iterations), double(ry.iterations)}})
      n += same_bits_of(a, b) ? 0.0 : 1.0;
  }
  return {n, "the number of field values, step values and iteration counts that differ when the case is solved again"};
}

Measure threads(const Case& c, const SolvedCase& first) {
  const int now = thread_count();
  std::optional<SolvedCase> one, two;
  if (now != 1) {
    ScopedThreads t(1);
    one = solve_case(c);
  }
  if (now != 2) {
    ScopedThreads t(2);
    two = solve_case(c);
  }
  const SolvedCase& a = one ? *one : first;
  const SolvedCase& b = two ? *two : first;
  return {solution_difference(a, b), "the largest difference between the solutions on 1 and on 2 threads: p and "
                                     "mean pressure over the largest |p|, g and delta over the height scale, a_r"};
}

Measure continuity(const Case& c, const StabilityCheck& ch, const SolvedCase& first) {
  const SolvedCase moved = solve_case(scaled_case(c, ch));
  return {path_change(first.run, moved.run, ch, true),
          "the largest relative change of " + std::string(kind_name(ch.observable)) + " over the steps when " +
              ch.parameter + " changes by " + text(100.0 * ch.change) + " %" + left_out(ch)};
}

Measure agreement(const Case& c, const StabilityCheck& ch, const SolvedCase& first) {
  const SolvedCase other = solve_case(other_solver_case(c, ch));
  const double change = other.run.status == RunStatus::Converged ? path_change(first.run, other.run, ch, false)
                                                                 : std::numeric_limits<double>::infinity();
  return {change, "the largest relative difference of " + std::string(kind_name(ch.observable)) +
                      " on the loading branch between this solver and " + std::string(kind_name(ch.solver)) +
                      left_out(ch) + (other.run.status == RunStatus::Converged ? "" : "; it did not converge: " +
                                                                                          other.run.message)};
}

}  // namespace cmc::stability
