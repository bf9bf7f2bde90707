// What a backend of the quasi-static solver's outer iteration provides (Iteration.hpp), as
// a C++20 concept that qs::solve requires: a backend that lacks a pass does not compile,
// and the compiler names the concept and the pass (tests/compile_fail). The iteration
// holds the steps, the residual, the warm start and the end; a backend holds the fields
// and runs the passes: the CPU's (CpuBackend.cpp: host fields, Polonsky-Keer on either
// backend, the cascade as a queue per slab of rows) and the GPU's (CudaBackend.cuh: every
// field of the outer step on the device, the cascade in rounds).
#pragma once

#include "cmc/contact/Reductions.hpp"
#include "cmc/contact/quasi_static/Parts.hpp"
#include "cmc/contact/quasi_static/QuasiStaticAdhesion.hpp"

#include <concepts>
#include <cstddef>
#include <utility>

namespace cmc::qs {

// What B provides (pointers are the backend's memory):
//   n                                  points held
//   all(k, f), reduce<Acc>(k, f)       f(i) / f(i, acc) for i in [0, k), as grid/Backend.hpp
//   bind(at)                           the OuterPoint the solve keeps where it stands
//   start_cold(), start_warm(t, st), start_from(from)
//                                      where the first solve starts: nothing (the hard-wall
//                                      solve), the previous load's state (t and st's repulsive
//                                      pressure, made here on the host; moved from), or an
//                                      interrupted solve's OuterPoint (moved from)
//   shift_heights()                    hp = h − G t (one FFT pair)
//   mean_tension()                     the mean of t over the grid
//   stop_inner_at(t)                   the inner solves stop at steady_seconds() t (max_seconds)
//   inner(target, confirm, outer, its) Polonsky-Keer on hp from its own state; then g()
//                                      (outer, its: the step and the iterations before it,
//                                      for progress lines)
//   predict(jump, floor)               the predicted gaps x() (jump prediction and cascade)
//   t(), g(), x(), p()                 the tension, the gap of the last inner solve, the
//                                      predicted gaps, and the inner solve's pressure (the
//                                      next solve's warm start)
//   outer_point(at)                    makes `at` show where the solve stands (on_outer)
//   solved()                           whether an inner solve left a state
//   end(st)                            the solved state into st (host): total pressure
//                                      p − t, displacement, gap, penetration
template <class B>
concept QuasiStaticBackend = requires(B& b, std::size_t k, OuterPoint& at, Field&& t, ContactState& st,
                                      const Target& target, const JumpPrediction& jump, double x, bool flag, int i) {
  { b.n } -> std::convertible_to<std::size_t>;
  b.all(k, archetype::PointBody{});
  { b.template reduce<Sum>(k, archetype::SumBody{}) } -> std::same_as<Sum>;
  b.bind(at);
  b.start_cold();
  b.start_warm(std::move(t), st);
  b.start_from(at);
  b.shift_heights();
  { b.mean_tension() } -> std::convertible_to<double>;
  b.stop_inner_at(x);
  { b.inner(target, flag, i, i) } -> std::same_as<SolveResult>;
  b.predict(jump, x);
  { b.t() } -> std::same_as<double*>;
  { b.g() } -> std::convertible_to<const double*>;
  { b.x() } -> std::convertible_to<const double*>;
  { b.p() } -> std::same_as<double*>;
  b.outer_point(at);
  { b.solved() } -> std::convertible_to<bool>;
  b.end(st);
};

}  // namespace cmc::qs
