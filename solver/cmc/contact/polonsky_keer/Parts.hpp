// The per-point and per-mode parts of a Polonsky–Keer solve, written once for the CPU and
// the GPU (grid/Backend.hpp, CMC_HD): the sums of a step, the pass of step (a), the two
// ways a step makes w = h + u, and the stiffness taken from the compliance. The iteration
// (Iteration.hpp) and both backends (CpuBackend.hpp, CudaBackend.cuh) use these; none
// writes its own.
#pragma once

#include "cmc/grid/Backend.hpp"

#include <cstddef>
#include <cstdint>

namespace cmc::pk {

// Sums of step (a) over the contact set Ic = {p > 0} and the overlap set, relative to c.
struct GapSums {
  double s1 = 0.0, s2 = 0.0, nc = 0.0;  // Σ_Ic (w − c), Σ_Ic (w − c)², |Ic|
  double ol = 0.0, nol = 0.0;           // Σ overlap², number of overlapping points
  double tsum = 0.0;                    // Σ_Ic t: keeps the next direction load-neutral
  CMC_HD void merge(const GapSums& o) {
    s1 += o.s1, s2 += o.s2, nc += o.nc, ol += o.ol, nol += o.nol, tsum += o.tsum;
  }
};
struct GzSums {  // Σ_Ic z, Σ_Ic g z, Σ_Ic g
  double zsum = 0.0, gz = 0.0, gsum = 0.0;
  CMC_HD void merge(const GzSums& o) { zsum += o.zsum, gz += o.gz, gsum += o.gsum; }
};
struct StepSums {
  double psum = 0.0;
  double changed = 0.0;  // points that left or joined the contact set (a count: the same sum in any order)
  double step = 0.0, cut = 0.0;  // Σ (τ t)² over Ic; Σ of the projection's changes² to the step
  CMC_HD void merge(const StepSums& o) { psum += o.psum, changed += o.changed, step += o.step, cut += o.cut; }
};

// What Run::project() makes of its pass's sums: whether the pressure survived (ok), the
// load scaling s, and whether the step that makes w transforms the new p (exact) or
// updates from the direction's spectrum, p' = s (p − τ t).
struct StepChoice {
  bool ok = true, exact = true;
  double s = 1.0, tau = 0.0;
};

// The pass of step (a) that gap_sums() runs: the sums of GapSums for the points in the
// contact set or overlapping (w < c). A functor, so that the same body can run inside a
// backend's inverse transform (Run::step) and on its own.
struct GapBody {
  const double *w, *t;
  const std::uint8_t* m;
  double c;
  CMC_HD void operator()(std::size_t i, GapSums& s) const {
    const double x = w[i] - c;
    if (m[i]) {
      s.s1 += x;
      s.s2 += x * x;
      s.nc += 1.0;
      s.tsum += t[i];
    } else if (x < 0.0) {
      s.ol += x * x;
      s.nol += 1.0;
    }
  }
};

// How a step makes w at a point from the inverse transform's output u there: after an
// exact step (u = G s p) w = h + u; after a linear one (u = G t) w = h + s ((w − h) − τ u),
// p' = s (p − τ t). (Round-off gathers in w from one linear step to the next:
// Options::recompute_every bounds the run of them.) The CPU applies them row by row inside
// its sweeps, the GPU point by point after its inverse transform: the same bits of w from
// the same u.
CMC_HD inline double exact_w(double h, double u) { return h + u; }
struct LinearW {
  double s, tau;
  CMC_HD double operator()(double h, double w, double u) const { return h + s * ((w - h) - tau * u); }
};

// The stiffness multiplier of a mode from its compliance (1/N folded in): (1/N)² / G =
// E*|q| / (2N), 0 at q = 0; nn = 1/N². One multiplier less to hold and to stream.
CMC_HD inline double stiffness_from_compliance(double compliance, double nn) {
  return compliance > 0.0 ? nn / compliance : 0.0;
}

}  // namespace cmc::pk
