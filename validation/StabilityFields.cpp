// The stability checks on a solved case's fields (Stability.hpp): force balance, the hard
// wall, the contact fraction, and that every number is finite.
#include "StabilityParts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace cmc::stability {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The largest |p| of the step, at least its |mean pressure| and the interaction's peak tension
// (a step out of contact has neither).
double pressure_scale(const Scene& s, const ContactState& st) {
  const double p = largest(s.grid.size(), [&](std::size_t k) { return std::abs(st.pressure[k]); });
  return std::max({p, std::abs(st.mean_pressure), peak_tension(s.interaction), std::numeric_limits<double>::min()});
}

// |u - G p| over the height scale (zero-mean parts on a periodic grid, where the mean
// displacement is a convention).
double elastic_mismatch(Scene& s, const ContactState& st, double height) {
  Field u;
  s.half_space->displacement(st.pressure, u);
  const bool periodic = s.half_space->periodic();
  const double shift = periodic ? Grid::mean(st.displacement) - Grid::mean(u) : 0.0;
  return largest(s.grid.size(), [&](std::size_t k) { return std::abs(st.displacement[k] - u[k] - shift); }) / height;
}

// Where the gap is open, |p - f(g)|; where it is closed, how far p falls below f(0).
double traction_mismatch(const Scene& s, const ContactState& st) {
  const double f0 = evaluate(s.interaction, 0.0).force;
  return largest(s.grid.size(), [&](std::size_t k) {
    const double g = st.gap[k], p = st.pressure[k];
    return g > 0.0 ? std::abs(p - evaluate(s.interaction, g).force) : std::max(0.0, f0 - p);
  });
}

}  // namespace

std::string text(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

double height_scale(const Scene& s, const std::vector<ContactState>& states) {
  const Field& h = s.topography.heights;
  double scale = h.empty() ? 0.0 : Grid::max(h) - Grid::min(h);
  for (const ContactState& st : states) {
    scale = std::max(scale, std::abs(st.penetration));
    if (!st.displacement.empty())
      scale = std::max({scale, std::abs(Grid::max(st.displacement)), std::abs(Grid::min(st.displacement))});
  }
  return std::max(scale, std::numeric_limits<double>::min());
}

Measure force_balance(Scene& s, const RunSummary& run, const std::vector<ContactState>& states) {
  const double height = height_scale(s, states);
  double load = 0.0, local = 0.0, elastic = 0.0;
  for (std::size_t k = 0; k < states.size(); ++k) {
    const ContactState& st = states[k];
    const double P = pressure_scale(s, st), mean = Grid::mean(st.pressure);
    load = std::max(load, relative_difference(mean, st.mean_pressure, P));
    // The load is met by a converged step only (one beyond pull-off has no state that carries it).
    const bool converged = k < run.steps.size() && run.steps[k].result.converged;
    if (converged && k < s.targets.size() && s.targets[k].control == Control::MeanPressure)
      load = std::max(load, relative_difference(mean, s.targets[k].value, P));
    local = std::max(local, traction_mismatch(s, st) / P);
    elastic = std::max(elastic, elastic_mismatch(s, st, height));
  }
  return {std::max({load, local, elastic}),
          "the largest of: the mean of p against the step's mean pressure and load (" + text(load) +
              "), p against the interaction's traction (" + text(local) +
              "), both over the pressure scale; u against G p over the height scale (" + text(elastic) + ")"};
}

Measure gap_below_wall(const Scene& s, const std::vector<ContactState>& states) {
  const double height = height_scale(s, states);
  const Field& h = s.topography.heights;
  double below = 0.0;
  for (const ContactState& st : states) {
    below = std::max(below, largest(s.grid.size(), [&](std::size_t k) {
      return std::max({0.0, -st.gap[k], -(h[k] - st.penetration + st.displacement[k])});
    }));
  }
  return {below / height, "the most negative of the gap and of h - delta + u, over the height scale"};
}

Measure contact_fraction_counted(const Scene& s, const RunSummary& run, const std::vector<ContactState>& states) {
  double worst = 0.0;
  for (std::size_t k = 0; k < states.size() && k < run.steps.size(); ++k) {
    const double a = run.steps[k].contact_fraction;
    if (!std::isfinite(a)) return {kInf, "a contact fraction is not finite"};
    const double counted = contact_fraction(states[k].gap, s.contact_rule);
    worst = std::max({worst, std::abs(a - counted), -a, a - 1.0});
  }
  return {worst, "the largest |a_r - a_r counted in the gap|, or distance of a_r outside [0, 1]"};
}

Measure non_finite(const RunSummary& run, const std::vector<ContactState>& states) {
  double count = 0.0;
  for (const ContactState& st : states)
    for (const Field* f : {&st.pressure, &st.displacement, &st.gap})
      count += double(Grid::count_if(*f, [](double v) { return !std::isfinite(v); }));
  for (const StepRecord& r : run.steps) {
    const double v[] = {r.mean_pressure, r.penetration, r.mean_gap, r.contact_fraction};
    count += double(std::count_if(std::begin(v), std::end(v), [](double x) { return !std::isfinite(x); }));
  }
  return {count, "the number of values that are not finite in the steps' fields (p, u, g) and records"};
}

}  // namespace cmc::stability
