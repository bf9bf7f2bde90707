// The stability checks' pieces shared by their files (Stability.cpp: the checks on one
// solved case; StabilityFields.cpp: the checks on its fields; StabilityReruns.cpp: those
// that solve the case again). Internal to the harness.
#pragma once

#include "Stability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cmc::stability {

// One check's number and its words; pass is decided by the caller unless `decided`.
struct Measure {
  double error = 0.0;
  std::string definition;
};

Measure force_balance(Scene& s, const RunSummary& run, const std::vector<ContactState>& states);
Measure gap_below_wall(const Scene& s, const std::vector<ContactState>& states);
Measure contact_fraction_counted(const Scene& s, const RunSummary& run, const std::vector<ContactState>& states);
// Non-finite numbers among the steps' fields and records.
Measure non_finite(const RunSummary& run, const std::vector<ContactState>& states);

Measure same_bits(const Case& c, const SolvedCase& first);
Measure threads(const Case& c, const SolvedCase& first);
Measure continuity(const Case& c, const StabilityCheck& ch, const SolvedCase& first);
Measure agreement(const Case& c, const StabilityCheck& ch, const SolvedCase& first);

// The largest of term(k) over k < n, through the grid layer (a NaN term counts as infinite).
template <class Term>
double largest(std::size_t n, Term term) {
  struct MaxOf {
    double v = 0.0;
    void merge(const MaxOf& o) { v = std::max(v, o.v); }
  };
  return Grid::parallel_reduce<MaxOf>(n, [&](std::size_t b, std::size_t e, MaxOf& acc) {
    for (std::size_t k = b; k < e; ++k) {
      const double t = term(k);
      acc.v = std::isnan(t) ? std::numeric_limits<double>::infinity() : std::max(acc.v, t);
    }
  }).v;
}

// A number as the checks' words write it (3 significant digits).
std::string text(double v);

// The height scale of a scene: its peak-to-valley height, at least max |u| and |delta| of
// the states (never zero).
double height_scale(const Scene& s, const std::vector<ContactState>& states);

}  // namespace cmc::stability
