// What a backend of the Polonsky–Keer iteration provides (Iteration.hpp), as C++20
// concepts that pk::Run and pk::iterate require: a backend that lacks a pass does not
// compile, and the compiler names the concept and the pass (tests/compile_fail). The
// iteration holds the algorithm; a backend holds the fields and runs the passes: the CPU's
// (CpuBackend.hpp) with OpenMP over the contact set only, the GPU's (CudaBackend.cuh) as
// kernels with fixed-order reductions.
#pragma once

#include "cmc/contact/Reductions.hpp"
#include "cmc/contact/polonsky_keer/Parts.hpp"

#include <concepts>
#include <cstddef>
#include <cstdint>

namespace cmc::pk {

// The fields and sizes a backend hands the iteration (pointers are the backend's: host or
// device memory):
//   n, nspec            points held, spectrum modes held
//   points, transform_points
//                       points of the whole grid, and of its transform grid (padded when free)
//   p, w, t, z, m, h    pressure (times sigma), w = h + u, direction, preconditioned gap,
//                       contact mask (m[i] == (p[i] > 0), always), heights; p and t are
//                       zero off the mask whenever a combined operation starts (Run keeps
//                       them so, and a backend may take them as zero there unread)
//   out, ker            the transform's scratch spectrum (interleaved re, im), which holds
//                       t's spectrum from the direction's transform until the step
//                       overwrites it; the compliance (1/N folded in)
//   gt                  G t of a linear step (compose::), where a backend makes it
struct Fields {
  std::size_t n = 0, nspec = 0;
  double points = 0.0, transform_points = 0.0;
  double *p = nullptr, *w = nullptr, *t = nullptr, *z = nullptr;
  std::uint8_t* m = nullptr;
  const double* h = nullptr;
  double* out = nullptr;
  const double* ker = nullptr;
  double* gt = nullptr;
};

// Bodies of the shapes the iteration hands a backend besides Reductions.hpp's, for the
// concepts below (which only ask whether a call compiles; nothing calls these).
namespace archetype {
using cmc::archetype::PointBody;
using cmc::archetype::SumBody;
struct ProjectBody {
  CMC_HD void operator()(std::size_t, StepSums&) const {}
};
struct Choose {
  StepChoice operator()(const StepSums&) const { return {}; }
};
}  // namespace archetype

// The passes over points (each a kernel on the GPU):
//   all(k, f)                         f(i) for i in [0, k)
//   reduce_in<Acc>(m, k, f)           f(i, acc) for i in the mask, merged in a fixed order
//   reduce_in_or_below<Acc>(m, w, c, k, f)
//                                     the same for i in the mask or with w[i] < c; the CPU
//                                     calls f for the other points of a block of eight
//                                     too, so f must be a no-op there
//   sum(v)                            Σ v over the whole grid
template <class B>
concept PointPasses = requires(B& b, std::size_t k, const std::uint8_t* m, const double* v, double level) {
  b.all(k, archetype::PointBody{});
  { b.template reduce_in<Sum>(m, k, archetype::SumBody{}) } -> std::same_as<Sum>;
  { b.template reduce_in_or_below<Sum>(m, v, level, k, archetype::SumBody{}) } -> std::same_as<Sum>;
  { b.sum(v) } -> std::convertible_to<double>;
};

// A backend of the iteration: the fields, the passes, and five combined operations, each
// a pass, a transform and a pass. A backend may run them one after the other (compose::,
// Compose.hpp: the GPU's) or the passes inside the transforms' sweeps (the CPU's). The
// spectra's layout is the backend's: the iteration touches modes only through them.
//   direction_and_curvature<Acc>(m, f, c)
//                                     f(i, acc) for i in the mask (it writes t), then
//                                     out = FFT(t) and c = <t, G t>
//   exact_and_gap_sums<Acc>(s, m, level, f)
//                                     w = h + G (s p), then f(i, acc) as
//                                     reduce_in_or_below(m, w, level)
//   linear_and_gap_sums<Acc>(s, tau, m, level, f)
//                                     w = h + G p' for p' = s (p − τ t), from t's spectrum
//                                     in out (one inverse transform), then f as above
//   project_and_gap_sums<Acc>(pass, choose, likely_exact, m, level, f, st, c)
//                                     st = the sums of pass(i, st) for i in the mask or
//                                     with w < level (it writes p, m and t), c =
//                                     choose(st) (a StepChoice), then where c.ok the step
//                                     c names, as exact_ or linear_and_gap_sums; a backend
//                                     may run the pass inside p's transform where
//                                     likely_exact, and then makes the step exact (c.exact
//                                     says which step it made)
//   stiffness_and_sums<Acc>(fill, m, f)
//                                     fill(i) for every i (it writes z, and 0 off the
//                                     mask), z = K z (one FFT pair), then f(i, acc) for i
//                                     in the mask; afterwards z is defined on the mask
//                                     only (the CPU calls fill on the mask alone, takes z
//                                     as 0 elsewhere, and writes K z on the mask)
template <class B>
concept PolonskyKeerBackend =
    std::derived_from<B, Fields> && PointPasses<B> &&
    requires(B& b, const std::uint8_t* m, double x, bool flag, double& curvature, StepSums& st, StepChoice& c) {
      { b.template direction_and_curvature<Sum>(m, archetype::SumBody{}, curvature) } -> std::same_as<Sum>;
      { b.template exact_and_gap_sums<Sum>(x, m, x, archetype::SumBody{}) } -> std::same_as<Sum>;
      { b.template linear_and_gap_sums<Sum>(x, x, m, x, archetype::SumBody{}) } -> std::same_as<Sum>;
      {
        b.template project_and_gap_sums<Sum>(archetype::ProjectBody{}, archetype::Choose{}, flag, m, x,
                                             archetype::SumBody{}, st, c)
      } -> std::same_as<Sum>;
      { b.template stiffness_and_sums<Sum>(archetype::PointBody{}, m, archetype::SumBody{}) } -> std::same_as<Sum>;
    };

// What compose:: (Compose.hpp) makes the combined operations from: the passes and four
// transforms, each on the backend's own fields:
//   forward_p()      out = FFT(p), unnormalised
//   curvature_t()    out = FFT(t); returns <t, G t>
//   inverse_w()      w = the inverse FFT of out (out may be destroyed)
//   inverse_gt()     gt = the same (and gt points to it)
//   stiffness_z()    z = K z (one FFT pair)
template <class B>
concept TransformParts = std::derived_from<B, Fields> && PointPasses<B> && requires(B& b) {
  b.forward_p();
  { b.curvature_t() } -> std::convertible_to<double>;
  b.inverse_w();
  b.inverse_gt();
  b.stiffness_z();
};

}  // namespace cmc::pk
