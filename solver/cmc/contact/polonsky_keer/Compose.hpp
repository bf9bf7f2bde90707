// The combined operations of a Polonsky–Keer backend (Contract.hpp) made from their parts,
// one after the other: a pass, a transform, a pass. The GPU's backend runs them so, and
// the CPU's where it cannot fuse its passes into its sweeps (a free boundary, a
// distributed grid). A step makes w with the per-point parts of Parts.hpp, as the CPU's
// fused sweeps do: no spectrum of p or of h is held.
#pragma once

#include "cmc/contact/polonsky_keer/Contract.hpp"

#include <cstddef>
#include <cstdint>

namespace cmc::pk::compose {

template <class Acc, class B, class F>
  requires TransformParts<B>
Acc direction_and_curvature(B& b, const std::uint8_t* m, F f, double& curvature) {
  const Acc a = b.template reduce_in<Acc>(m, b.n, f);
  curvature = b.curvature_t();
  return a;
}

// out = scale G out, on the real and imaginary parts of every mode.
template <class B>
  requires TransformParts<B>
void times_compliance(B& b, double scale) {
  double* out = b.out;
  const double* ker = b.ker;
  b.all(b.nspec, [=] CMC_HD(std::size_t k) {
    const double g = scale * ker[k];
    out[2 * k] *= g, out[2 * k + 1] *= g;
  });
}

// w = h + G (s p): p's transform, the compliance times s, the inverse into w, h added.
template <class Acc, class B, class F>
  requires TransformParts<B>
Acc exact_and_gap_sums(B& b, double s, const std::uint8_t* m, double level, F f) {
  b.forward_p();
  times_compliance(b, s);
  b.inverse_w();
  double* w = b.w;
  const double* h = b.h;
  b.all(b.n, [=] CMC_HD(std::size_t i) { w[i] = exact_w(h[i], w[i]); });
  return b.template reduce_in_or_below<Acc>(m, b.w, level, b.n, f);
}
// w = h + G p' for p' = s (p − τ t): G t from t's spectrum in `out` (one inverse into gt),
// then w = h + s ((w − h) − τ G t).
template <class Acc, class B, class F>
  requires TransformParts<B>
Acc linear_and_gap_sums(B& b, double s, double tau, const std::uint8_t* m, double level, F f) {
  times_compliance(b, 1.0);
  b.inverse_gt();
  double* w = b.w;
  const double *h = b.h, *u = b.gt;
  const LinearW make{s, tau};
  b.all(b.n, [=] CMC_HD(std::size_t i) { w[i] = make(h[i], w[i], u[i]); });
  return b.template reduce_in_or_below<Acc>(m, b.w, level, b.n, f);
}
// Run::project(): pass(i, st) for i in the mask or with w < level, then c = choose(st),
// then (where c.ok) the step it chose, with the gap sums f.
template <class Acc, class B, class StepAcc, class P, class C, class F>
  requires TransformParts<B>
Acc project_and_gap_sums(B& b, P pass, C choose, const std::uint8_t* m, double level, F f, StepAcc& st,
                         StepChoice& c) {
  st = b.template reduce_in_or_below<StepAcc>(m, b.w, level, b.n, pass);
  c = choose(st);
  if (!c.ok) return Acc{};
  return c.exact ? exact_and_gap_sums<Acc>(b, c.s, m, level, f) : linear_and_gap_sums<Acc>(b, c.s, c.tau, m, level, f);
}
template <class Acc, class B, class Fill, class F>
  requires TransformParts<B>
Acc stiffness_and_sums(B& b, Fill fill, const std::uint8_t* m, F f) {
  b.all(b.n, fill);
  b.stiffness_z();
  return b.template reduce_in<Acc>(m, b.n, f);
}

}  // namespace cmc::pk::compose
