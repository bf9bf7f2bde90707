// The stability checks (Stability.hpp): the case solved with its history, the checks on the
// history and the path, and the dispatch to the checks on fields and on reruns.
#include "StabilityParts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cmc {

using namespace stability;

RecordedCase solve_recorded(const Case& c, const Progress& progress) {
  Case recorded = c;
  recorded.solver.progress_every = 1;
  RecordedCase rc;
  int last_iteration = std::numeric_limits<int>::max(), last_outer = std::numeric_limits<int>::max();
  const Progress keep = [&](const ProgressPoint& p) {
    if (progress && p.iteration % 25 == 0) progress(p);
    if (p.inner) return;  // the quasi-static solver's Polonsky-Keer solves: its outer steps count
    const bool fresh = p.outer > 0 ? p.outer <= last_outer : p.iteration <= last_iteration;
    if (fresh || rc.history.empty()) rc.history.emplace_back();
    last_iteration = p.iteration, last_outer = p.outer;
    SolveHistory& h = rc.history.back();
    h.iteration.push_back(p.iteration);
    h.residual.push_back(p.residual);
    h.energy.push_back(p.energy);
  };
  rc.solved = solve_case(recorded, {}, keep);
  return rc;
}

double largest_growth(const std::vector<double>& residuals) {
  double best = std::numeric_limits<double>::infinity(), growth = 1.0;
  for (double r : residuals) {
    if (!std::isfinite(r)) return std::numeric_limits<double>::infinity();
    if (!(r > 0.0)) continue;
    if (std::isfinite(best)) growth = std::max(growth, r / best);
    best = std::min(best, r);
  }
  return growth;
}

double largest_rise(const std::vector<double>& energies) {
  double lowest = std::numeric_limits<double>::infinity(), rise = 0.0, scale = 0.0;
  for (double e : energies) {
    if (std::isnan(e)) continue;
    if (!std::isfinite(e)) return std::numeric_limits<double>::infinity();
    if (std::isfinite(lowest)) rise = std::max(rise, e - lowest);
    lowest = std::min(lowest, e);
    scale = std::max(scale, std::abs(e));
  }
  return rise > 0.0 ? rise / scale : 0.0;
}

double relative_difference(double a, double b, double scale) {
  if (!std::isfinite(a) || !std::isfinite(b)) return std::numeric_limits<double>::infinity();
  if (a == b) return 0.0;
  return std::abs(a - b) / std::max(scale, std::numeric_limits<double>::min());
}

namespace {

using K = StabilityKind;

// Every step converged, in at most the budget's iterations; the first that did not, named.
Measure iterations(const RunSummary& run, bool& all_converged) {
  Measure m{0.0, "the most iterations of a load step (" + std::to_string(run.steps.size()) + " steps"};
  std::string stop;
  for (const StepRecord& r : run.steps) {
    m.error = std::max(m.error, double(r.result.iterations));
    if (!r.result.converged && stop.empty())
      stop = "; step " + std::to_string(r.index) + " did not converge: " + r.result.message;
  }
  all_converged = run.status == RunStatus::Converged && stop.empty();
  if (run.status != RunStatus::Converged && stop.empty()) stop = "; the run did not converge: " + run.message;
  m.definition += all_converged ? ", all converged)" : stop + ")";
  return m;
}

Measure residual_growth(const std::vector<SolveHistory>& history) {
  Measure m{1.0, "the largest r_k / min_{j<k} r_j of the residual within a solve (" +
                     std::to_string(history.size()) + " solves)"};
  for (const SolveHistory& h : history) m.error = std::max(m.error, largest_growth(h.residual));
  return m;
}

Measure energy_rise(const std::vector<SolveHistory>& history) {
  Measure m{0.0, "the largest rise of the energy above its lowest earlier value within a solve, over its largest "
                 "magnitude (" + std::to_string(history.size()) + " solves)"};
  for (const SolveHistory& h : history) m.error = std::max(m.error, largest_rise(h.energy));
  return m;
}

Measure pulloff(const Scene& s, const RunSummary& run) {
  const double p = s.units.pressure(run.pulloff_mean_pressure);
  return {p, "the most negative mean pressure of the path over E* (finite and below zero; " +
                 std::string(run.pulloff_branch ? "found" : "no converged solve") + ")"};
}

// At each load of both branches, the contact fraction lost on unloading.
Measure hysteresis(const Scene& s, const RunSummary& run) {
  Measure m{-std::numeric_limits<double>::infinity(),
            "the largest a_r(loading) - a_r(unloading) at the same load"};
  int pairs = 0;
  for (std::size_t u = s.unloading_from; u < run.steps.size(); ++u)
    for (std::size_t l = 0; l < std::min(s.unloading_from, run.steps.size()); ++l) {
      const double a = s.targets[l].value, b = s.targets[u].value;
      if (std::abs(a - b) > 1e-12 * std::max(std::abs(a), std::abs(b))) continue;
      m.error = std::max(m.error, run.steps[l].contact_fraction - run.steps[u].contact_fraction);
      ++pairs;
    }
  m.definition += " (" + std::to_string(pairs) + " pairs of steps)";
  if (pairs == 0) m.error = std::numeric_limits<double>::infinity(), m.definition += ": none to compare";
  return m;
}

CheckResult measured(const StabilityCheck& ch, const Measure& m, bool pass) {
  CheckResult r;
  r.quantity = std::string(kind_name(ch.kind));
  r.definition = m.definition;
  r.error = m.error;
  r.tolerance = ch.bound;
  r.pass = pass;
  r.expected_failure = ch.expected_failure;
  return r;
}

CheckResult evaluate_one(const Case& c, const StabilityCheck& ch, RecordedCase& rc) {
  SolvedCase& sc = rc.solved;
  const double b = ch.bound;
  auto within = [&](const Measure& m) { return measured(ch, m, m.error <= b); };
  switch (ch.kind) {
    case K::Iterations: {
      bool converged = false;
      const Measure m = iterations(sc.run, converged);
      return measured(ch, m, converged && m.error <= b);
    }
    case K::ResidualGrowth: return within(residual_growth(rc.history));
    case K::EnergyRise: return within(energy_rise(rc.history));
    case K::SameBits: return within(same_bits(c, sc));
    case K::Threads: return within(threads(c, sc));
    case K::Continuity: return within(continuity(c, ch, sc));
    case K::Agreement: return within(agreement(c, ch, sc));
    case K::ForceBalance: return within(force_balance(sc.scene, sc.run, sc.states));
    case K::Gap: return within(gap_below_wall(sc.scene, sc.states));
    case K::ContactFraction: return within(contact_fraction_counted(sc.scene, sc.run, sc.states));
    case K::Hysteresis: return within(hysteresis(sc.scene, sc.run));
    case K::Pulloff: {
      const Measure m = pulloff(sc.scene, sc.run);
      return measured(ch, m, std::isfinite(m.error) && m.error < 0.0 && sc.run.pulloff_branch.has_value());
    }
  }
  return {};
}

}  // namespace

std::vector<CheckResult> evaluate_stability(const Case& c, RecordedCase& rc) {
  std::vector<CheckResult> out;
  if (!c.validation || c.validation->stability.empty()) return out;
  for (const StabilityCheck& ch : c.validation->stability) out.push_back(evaluate_one(c, ch, rc));
  const Measure f = non_finite(rc.solved.run, rc.solved.states);
  CheckResult r;
  r.quantity = "finite";
  r.definition = f.definition;
  r.error = f.error;
  r.pass = f.error == 0.0;
  out.push_back(r);
  return out;
}

}  // namespace cmc
