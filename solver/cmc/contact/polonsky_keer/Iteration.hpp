// One Polonsky–Keer solve, written once for every backend (grid/Backend.hpp): the steps
// (a)–(h) of Polonsky & Keer §3 (see PolonskyKeer.hpp) as named parts, over a backend B
// that holds the fields and runs the passes. The CPU backend (PolonskyKeer.cpp) runs them
// with OpenMP over the contact set only; the CUDA backend (contact/PolonskyKeerDevice.cu)
// as kernels with fixed-order reductions. Neither holds any of the algorithm.
//
// What B provides (pointers are the backend's: host or device memory):
//   n, nspec            points held, spectrum modes held
//   points, transform_points
//                       points of the whole grid, and of its transform grid (padded when free)
//   p, w, t, z, m, h    pressure (times sigma), w = h + u, direction, preconditioned gap,
//                       contact mask (m[i] == (p[i] > 0), always), heights; p and t are
//                       zero off the mask whenever a combined operation starts (Run keeps
//                       them so, and a backend may take them as zero there unread)
//   p_hat, h_hat, out, ker
//                       spectra as interleaved (re, im) doubles: of p, of h/N (both only
//                       where the backend runs the steps as compose:: does), and the
//                       transform's scratch, which holds t's spectrum from curvature_t()
//                       until the step overwrites it; ker: the compliance (1/N folded in)
//   all(k, f)                         f(i) for i in [0, k)
//   reduce_in<Acc>(m, k, f)           f(i, acc) for i in the mask, merged in a fixed order
//   reduce_in_or_below<Acc>(m, w, c, k, f)
//                                     the same for i in the mask or with w[i] < c; the CPU
//                                     calls f for the other points of a block of eight
//                                     too, so f must be a no-op there
//   sum(v)                            Σ v over the whole grid
//   forward_h(s)                      h_hat = s FFT(h), where the backend keeps it
//   four combined operations, each a pass, a transform and a pass; a backend may run
//   them one after the other (compose:: below) or the passes inside the transforms'
//   sweeps (the CPU's, PolonskyKeerHost.hpp). The spectra's layout is the backend's: Run
//   only touches modes through mode passes, which treat every mode alike.
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
//   and, for compose::, forward_p() (p_hat = FFT(p), unnormalised), curvature_t()
//   (out = FFT(t); returns <t, G t>), inverse_w() (w = inverse FFT of out) and
//   stiffness_z() (z = K z).
#pragma once

#include "cmc/contact/polonsky_keer/PolonskyKeer.hpp"
#include "cmc/grid/Backend.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>

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
struct Sum {
  double v = 0.0;
  CMC_HD void merge(const Sum& o) { v += o.v; }
};
struct GzSums {  // Σ_Ic z, Σ_Ic g z, Σ_Ic g
  double zsum = 0.0, gz = 0.0, gsum = 0.0;
  CMC_HD void merge(const GzSums& o) { zsum += o.zsum, gz += o.gz, gsum += o.gsum; }
};
struct StepSums {
  double psum = 0.0;
  bool changed = false;
  CMC_HD void merge(const StepSums& o) { psum += o.psum, changed = changed || o.changed; }
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

// The combined operations of a backend that runs their parts one after the other.
namespace compose {
template <class Acc, class B, class F>
Acc direction_and_curvature(B& b, const std::uint8_t* m, F f, double& curvature) {
  const Acc a = b.template reduce_in<Acc>(m, b.n, f);
  curvature = b.curvature_t();
  return a;
}
template <class Acc, class B, class S, class F>
Acc step_and_gap_sums(B& b, S step, const std::uint8_t* m, double level, F f) {
  b.all(b.nspec, step);
  b.inverse_w();
  return b.template reduce_in_or_below<Acc>(m, b.w, level, b.n, f);
}
template <class Acc, class B, class S, class F>
Acc pressure_and_gap_sums(B& b, S step, const std::uint8_t* m, double level, F f) {
  b.forward_p();
  return step_and_gap_sums<Acc>(b, step, m, level, f);
}
// The two steps of Run (set_pressure(), step()) over a spectral state: p̂ = s FFT(p), or
// p̂ ← s (p̂ − τ t̂) with t̂ in `out`, and then out = G p̂ + ĥ/N, whose inverse is w = h + G p
// (ĥ/N from forward_h(1/N), kept for the whole solve). On the real and imaginary parts as
// doubles (what std::complex computes, component by component, for a complex times a
// real). t̂ is read before it is overwritten: one spectrum less to hold and to stream than
// a t̂ of its own (issues 11, 16).
template <class Acc, class B, class F>
Acc exact_and_gap_sums(B& b, double s, const std::uint8_t* m, double level, F f) {
  double *out = b.out, *ph = b.p_hat;
  const double *off = b.h_hat, *ker = b.ker;
  return pressure_and_gap_sums<Acc>(
      b,
      [=] CMC_HD(std::size_t k) {
        const double re = s * ph[2 * k], im = s * ph[2 * k + 1];
        ph[2 * k] = re, ph[2 * k + 1] = im;
        out[2 * k] = re * ker[k] + off[2 * k], out[2 * k + 1] = im * ker[k] + off[2 * k + 1];
      },
      m, level, f);
}
template <class Acc, class B, class F>
Acc linear_and_gap_sums(B& b, double s, double tau, const std::uint8_t* m, double level, F f) {
  double *out = b.out, *ph = b.p_hat;
  const double *off = b.h_hat, *ker = b.ker;
  return step_and_gap_sums<Acc>(
      b,
      [=] CMC_HD(std::size_t k) {
        const double re = s * (ph[2 * k] - tau * out[2 * k]), im = s * (ph[2 * k + 1] - tau * out[2 * k + 1]);
        ph[2 * k] = re, ph[2 * k + 1] = im;
        out[2 * k] = re * ker[k] + off[2 * k], out[2 * k + 1] = im * ker[k] + off[2 * k + 1];
      },
      m, level, f);
}
// Run::project(): pass(i, st) for i in the mask or with w < level, then c = choose(st),
// then (where c.ok) the step it chose, with the gap sums f.
template <class Acc, class B, class StepAcc, class P, class C, class F>
Acc project_and_gap_sums(B& b, P pass, C choose, const std::uint8_t* m, double level, F f, StepAcc& st,
                         StepChoice& c) {
  st = b.template reduce_in_or_below<StepAcc>(m, b.w, level, b.n, pass);
  c = choose(st);
  if (!c.ok) return Acc{};
  return c.exact ? exact_and_gap_sums<Acc>(b, c.s, m, level, f) : linear_and_gap_sums<Acc>(b, c.s, c.tau, m, level, f);
}
template <class Acc, class B, class Fill, class F>
Acc stiffness_and_sums(B& b, Fill fill, const std::uint8_t* m, F f) {
  b.all(b.n, fill);
  b.stiffness_z();
  return b.template reduce_in<Acc>(m, b.n, f);
}
}  // namespace compose

// The fields and sizes a backend hands Run (see above for each): the CPU's point into the
// state and its work arrays, the GPU's into device memory.
struct Fields {
  std::size_t n = 0, nspec = 0;
  double points = 0.0, transform_points = 0.0;
  double *p = nullptr, *w = nullptr, *t = nullptr, *z = nullptr;
  std::uint8_t* m = nullptr;
  const double* h = nullptr;
  double *p_hat = nullptr, *h_hat = nullptr, *out = nullptr;
  const double* ker = nullptr;
};

// Where a solve starts (PolonskyKeer::solve works it out from the state, for any backend).
struct Start {
  bool warm = false;          // the backend's pressure holds a start (else it is made here)
  double delta = 0.0;         // the previous penetration (load control) or the target one
  bool precondition = false;  // the stiffness preconditioner (periodic boundary only)
  double overlap_k = 0.0;     // E* π / L, the stiffness of the longest wave: overlap -> pressure
  double longest_compliance = 0.0;  // L / (π E*): the first step's compliance
  // Σ p of a warm start where the caller has it (and the backend's own sum would give the
  // same bits: the CPU's); NaN: the solve sums it.
  double warm_sum = std::numeric_limits<double>::quiet_NaN();
};
// Where it ended: the lazy load scaling, the penetration, and why it failed (empty: it did not).
struct End {
  double sigma = 1.0, delta = 0.0;
  std::string failure;
};

// The start of a solve on `hs`: warm or not, the previous (load control) or the target
// (displacement control) penetration, and the half-space's constants.
inline Start make_start(const HalfSpace& hs, const Target& target, bool warm, double previous_penetration,
                        bool precondition) {
  Start s;
  s.warm = warm;
  s.delta = target.control == Control::MeanPressure ? previous_penetration : target.value;
  s.precondition = precondition && hs.periodic();
  s.overlap_k = hs.contact_modulus() * std::numbers::pi / hs.grid().lx;  // E* π / L
  s.longest_compliance = hs.grid().lx / (std::numbers::pi * hs.contact_modulus());
  return s;
}

// Whether a solve that ended at `end` with `res` converged; if not, `message` says why.
inline bool converged(const End& end, const SolveResult& res, double tolerance, std::string& message) {
  message = end.failure;
  const bool ok = end.failure.empty() && res.residual <= tolerance;
  if (!ok && message.empty()) {
    std::ostringstream s;
    s << "Polonsky-Keer stopped after " << res.iterations << " iterations at residual " << res.residual
      << " > tolerance " << tolerance;
    message = s.str();
  }
  return ok;
}

// Every member is public: nvcc's device lambdas may not sit in private member functions.
template <class B>
class Run {
 public:
  Run(B& b, const PolonskyKeer::Options& o, double h_scale, const Target& target, const Start& start)
      : b_(b), opt_(o), h_scale_(h_scale), force_(target.control == Control::MeanPressure),
        target_(force_ ? target.value : 0.0), delta_(start.delta), warm_(start.warm),
        precondition_(start.precondition), overlap_k_(start.overlap_k), last_tau_(start.longest_compliance),
        warm_sum_(start.warm_sum) {
    heights_spectrum();
  }

  void run(SolveResult& res);
  double delta() const { return delta_; }
  double sigma() const { return sigma_; }
  std::string failure;

  // ---- the transforms of a step: each makes w for a new pressure, and with it the next
  // step (a)'s sums (gap_sums() takes them from there)
  // ĥ/N where the backend keeps w = h + G p̂ in the spectrum (compose:: below).
  void heights_spectrum() { b_.forward_h(1.0 / b_.transform_points); }
  // w = h + G (s p): one forward transform and one inverse.
  void set_pressure(double s) {
    keep_pending(b_.template exact_and_gap_sums<GapSums>(s, b_.m, delta_, gap_body()));
  }
  // w = h + G p' for p' = s (p − τ t), from t's spectrum, which the direction's transform
  // left in `out`: one inverse transform. The caller applies the same step to the
  // real-space p.
  void step(double s, double tau) {
    keep_pending(b_.template linear_and_gap_sums<GapSums>(s, tau, b_.m, delta_, gap_body()));
  }
  // Step (a)'s sums relative to the current δ (GapBody).
  GapBody gap_body() const { return {b_.w, b_.t, b_.m, delta_}; }
  void keep_pending(const GapSums& sums) {
    pending_ = sums;
    pending_level_ = delta_;
    has_pending_ = true;
  }
  void exact() {
    set_pressure(sigma_);
    since_exact_ = 0;
  }

  // ---- the steps
  // Pressure from the geometric overlap, p = k max(0, δ − h).
  void overlap_pressure() {
    double* p = b_.p;
    const double* h = b_.h;
    const double d = delta_, k = overlap_k_;
    b_.all(b_.n, [=] CMC_HD(std::size_t i) { p[i] = (d - h[i] > 0.0 ? d - h[i] : 0.0) * k; });
  }
  // Ic from p, after p was set wholesale (scaled by s first, where s != 1), and p = 0 off
  // it (a warm start's negative or NaN values: the backends take p as zero off Ic); the
  // direction is zero, so that t holds no value from before (the backends do not clear
  // it): a steepest-descent step follows, which reads t only as 0 t.
  void set_contact_set(double s = 1.0) {
    double* p = b_.p;
    std::uint8_t* m = b_.m;
    double* t = b_.t;
    b_.all(b_.n, [=] CMC_HD(std::size_t i) {
      if (s != 1.0) p[i] *= s;
      m[i] = p[i] > 0.0;
      if (!m[i]) p[i] = 0.0;
      t[i] = 0.0;
    });
  }
  void initial_pressure() {
    // Warm start, or PK's uniform guess (force control), or a guess proportional to the
    // geometric overlap (displacement control).
    double* p = b_.p;
    if (!warm_) {
      if (force_) {
        const double v = target_;
        b_.all(b_.n, [=] CMC_HD(std::size_t i) { p[i] = v; });
      } else {
        overlap_pressure();
      }
    }
    double s = 1.0;
    if (force_) {
      if (target_ == 0.0) {
        b_.all(b_.n, [=] CMC_HD(std::size_t i) { p[i] = 0.0; });
      } else {
        // The caller's sum of a warm start (the same Σ p) saves a pass over p.
        const double sum = std::isnan(warm_sum_) ? b_.sum(p) : warm_sum_;
        s = target_ / (sum / b_.points);
      }
    }
    set_contact_set(s);
    exact();  // w = h + G p, and p̂ kept
  }
  // (a) gap statistics over Ic = {p > 0} (σ > 0 does not change it), shifted by the
  // previous δ to avoid cancellation; overlap (w < c) elsewhere.
  GapSums gap_sums() {
    if (has_pending_ && pending_level_ == delta_) {  // from the step that made w
      has_pending_ = false;
      return pending_;
    }
    has_pending_ = false;
    return b_.template reduce_in_or_below<GapSums>(b_.m, b_.w, delta_, b_.n, gap_body());
  }
  // The iteration lost its contact set: start again from the geometric overlap. Under
  // displacement control an indenter that overlaps the heights nowhere has p = 0 for its
  // solution: the overlap the iterate showed was the transforms' round-off (an indenter
  // that just touches, δ = min h, overlaps by 1e-17 after w = h + G p is transformed).
  enum class Restart { Again, NoContact, Failed };
  Restart restart_from_overlap() {
    overlap_pressure();
    const bool none = b_.sum(b_.p) == 0.0;
    if (none && force_) {
      failure = "Polonsky-Keer lost its contact set";
      return Restart::Failed;
    }
    sigma_ = 1.0;
    set_contact_set();
    exact();
    conjugate_ = false;
    return none ? Restart::NoContact : Restart::Again;
  }
  // (c) conjugate direction on Ic: t = g + β (t − t̄). Under load control the old direction
  // is made load-neutral on the current Ic (Σ_Ic t = 0), so the step keeps Σ p and the
  // exact line search needs only <t, G t> (PK subtract the Ic-mean of G t instead, which
  // costs a second transform). Returns Σ g t; (d) the curvature <t, G t> in `curvature`
  // (from t's transform, one forward transform).
  double direction(double beta, double tbar, double& curvature) {
    double* t = b_.t;
    const double* w = b_.w;
    const double d = delta_;
    return b_.template direction_and_curvature<Sum>(b_.m, [=] CMC_HD(std::size_t i, Sum& acc) {
             const double g = w[i] - d;
             t[i] = g + beta * (t[i] - tbar);
             acc.v += g * t[i];
           }, curvature).v;
  }
  // (c) with the stiffness preconditioner: z = P K P g (made load-neutral on Ic under load
  // control), β = Σ g z / (Σ g z)_old, t = z + β (t − t̄). One FFT pair. nc = |Ic| (> 0).
  // Returns Σ g t, and (d) the curvature as direction() does.
  double preconditioned_direction(double tbar, double nc, double& curvature) {
    double* z = b_.z;
    double* t = b_.t;
    const double* w = b_.w;
    const std::uint8_t* m = b_.m;
    const double d = delta_;
    // One pass for the Ic-mean of z and Σ g z: Σ g (z − z̄) = Σ g z − z̄ Σ g.
    const GzSums a = b_.template stiffness_and_sums<GzSums>(
        [=] CMC_HD(std::size_t i) { z[i] = m[i] ? w[i] - d : 0.0; }, m,
        [=] CMC_HD(std::size_t i, GzSums& s) {
          const double g = w[i] - d;
          s.zsum += z[i], s.gz += g * z[i], s.gsum += g;
        });
    const double zbar = force_ ? a.zsum / nc : 0.0;
    const double gz = a.gz - zbar * a.gsum;
    const double beta = conjugate_ && gz_old_ > 0.0 ? gz / gz_old_ : 0.0;
    gz_old_ = gz;
    return b_.template direction_and_curvature<Sum>(m, [=] CMC_HD(std::size_t i, Sum& acc) {
             t[i] = (z[i] - zbar) + beta * (t[i] - tbar);
             acc.v += (w[i] - d) * t[i];
           }, curvature).v;
  }
  // (e)–(g) pressure step p ← σ p − τ t on Ic, projection onto p ≥ 0, overlapping points
  // join with p = −τ g. Then (h) the load scaling (applied lazily through σ) and the new
  // displacement. Returns false if the pressure vanished under load control.
  bool project(double tau) {
    double* p = b_.p;
    const double* w = b_.w;
    double* t = b_.t;
    std::uint8_t* m = b_.m;
    const double sg = sigma_, d = delta_;
    // Off Ic and without overlap (w ≥ d) p stays 0 and adds nothing.
    const auto pass = [=] CMC_HD(std::size_t i, StepSums& s) {
      double pn = sg * p[i];
      if (pn > 0.0) {
        pn -= tau * t[i];
        if (pn < 0.0) pn = 0.0, s.changed = true;
      }
      if (pn == 0.0) {
        const double g = w[i] - d;
        if (g < 0.0) pn = -tau * g, s.changed = true;
      }
      p[i] = pn;
      s.psum += pn;
      m[i] = pn > 0.0;
      if (!m[i]) t[i] = 0.0;  // keeps the direction zero off Ic
    };
    // After the pass: the load scaling, and the step that makes w. A linear step is one
    // inverse transform; a projected one needs the transform of the new p (one forward
    // more), and so does every recompute_every-th linear one.
    const bool recompute_due = since_exact_ + 1 >= opt_.recompute_every;
    const auto choose = [&](const StepSums& st) {
      StepChoice c;
      c.tau = tau;
      if (force_) {
        const double mean_p = st.psum / b_.points;
        if (!(mean_p > 0.0)) {
          c.ok = false;
          return c;
        }
        c.s = target_ / mean_p;
      }
      c.exact = st.changed || recompute_due;
      return c;
    };
    // The step after one that changed the contact set usually changes it too: a backend
    // may then run the pass inside the new p's transform (and make that step exact).
    const bool likely_exact = !conjugate_ || recompute_due;
    StepSums st;
    StepChoice c;
    const GapSums sums = b_.template project_and_gap_sums<GapSums>(pass, choose, likely_exact, m, d,
                                                                   gap_body(), st, c);
    if (!c.ok) {
      failure = "Polonsky-Keer: pressure vanished during the iteration";
      return false;
    }
    keep_pending(sums);
    remeasured_ = false;
    since_exact_ = c.exact ? 0 : since_exact_ + 1;
    sigma_ = c.s;
    conjugate_ = !st.changed;
    return true;
  }

  B& b_;
  const PolonskyKeer::Options& opt_;
  double h_scale_;
  bool force_;
  double target_;
  double delta_;
  bool warm_;
  bool precondition_;
  double overlap_k_;
  double last_tau_;          // compliance of the last step (first: of the longest wave)
  double warm_sum_;          // Start::warm_sum
  double sigma_ = 1.0;       // the pressure is sigma_ p: the last load scaling, applied lazily
  int since_exact_ = 0;      // linear spectral steps since p̂ was last taken from p
  bool conjugate_ = false;   // PK's δ flag: false restarts steepest descent
  double gz_old_ = 1.0;      // Σ_Ic g z of the previous direction
  GapSums pending_;          // step (a)'s sums, made with the last step's inverse transform
  double pending_level_ = 0.0;
  bool has_pending_ = false;
  bool remeasured_ = false;  // the round-off floor's sums taken again at the current δ
};

template <class B>
void Run<B>::run(SolveResult& res) {
  initial_pressure();
  double G_old = 1.0;
  for (int it = 0;; ++it) {
    const double c = delta_;
    const GapSums S = gap_sums();
    if (S.nc == 0.0) {
      // No point carries pressure: either no contact at all (a valid solution of a
      // displacement-controlled step whose indenter does not reach the surface, or of
      // zero load), or the iteration lost its contact set.
      if ((!force_ && S.nol == 0.0) || (force_ && target_ == 0.0)) {
        res.iterations = it;
        res.residual = 0.0;
        return;
      }
      const Restart r = restart_from_overlap();
      if (r == Restart::Failed) return;
      if (r == Restart::NoContact) {
        res.iterations = it;
        res.residual = 0.0;
        return;
      }
      ++res.diagnostics.restarts;
      continue;
    }
    double G;
    if (force_) {
      const double shift = S.s1 / S.nc;  // mean gap over Ic relative to c
      delta_ = c + shift;                // (b) the rigid-body position that zeroes it
      G = std::max(0.0, S.s2 - S.nc * shift * shift);
    } else {
      G = S.s2;
    }
    // Overlap term measured with the previous δ; it is zero at convergence either way.
    res.residual = std::sqrt((G + S.ol) / (S.nc + S.nol)) / h_scale_;
    res.iterations = it;
    if (opt_.progress && it % std::max(1, opt_.progress_every) == 0) opt_.progress({it, res.residual});
    if (res.residual <= opt_.tolerance) {
      if (since_exact_ == 0 || !opt_.confirm) return;
      exact();  // confirm on u recomputed from the real-space p (removes spectral drift)
      ++res.diagnostics.exact_recomputes;
      continue;
    }
    if (it >= opt_.max_iterations) return;
    if (opt_.stop_at > 0.0 && steady_seconds() >= opt_.stop_at) {
      std::ostringstream s;
      s << kInnerTimeLimitMessage << "after " << it << " iterations at residual " << res.residual << " > tolerance "
        << opt_.tolerance;
      failure = s.str();
      return;
    }

    const double beta = conjugate_ ? G / G_old : 0.0;
    if (beta == 0.0) ++res.diagnostics.restarts;
    G_old = G;
    const double tbar = force_ ? S.tsum / S.nc : 0.0;
    double denom = 0.0;  // (d) curvature along t, from its transform alone
    const double sgt = precondition_ ? preconditioned_direction(tbar, S.nc, denom) : direction(beta, tbar, denom);
    double tau;
    if (denom > 0.0 && sgt > 0.0) {
      tau = last_tau_ = sgt / denom;
    } else if (S.nol > 0.0) {
      tau = last_tau_;  // nothing to gain on Ic: only overlapping points move
      conjugate_ = false;
    } else {
      // No descent left and no overlap: round-off floor. Confirm on an exact u, then stop.
      if (since_exact_ == 0) {
        // The sums were taken relative to the δ before this one: where δ moved, G = s2 −
        // nc shift² cancels, and its round-off (ε s2) can hold the residual above the
        // tolerance (a Hertz contact of 5 points at 16², its last step exact: 2.7e-11 against
        // 1e-12). Measure them once more at the new δ (a pass, no transform).
        if (!remeasured_ && c != delta_) {
          remeasured_ = true;
          has_pending_ = false;
          --it;  // not an iteration: nothing moved
          continue;
        }
        return;
      }
      exact();
      ++res.diagnostics.exact_recomputes;
      conjugate_ = false;
      continue;
    }
    if (!project(tau)) return;
    if (!conjugate_) ++res.diagnostics.clipped_steps;
  }
}

// One solve over backend b from `start`: the iteration, then σ, δ and why it failed.
template <class B>
End iterate(B& b, const PolonskyKeer::Options& o, double h_scale, const Target& target, const Start& start,
            SolveResult& res) {
  Run<B> run(b, o, h_scale, target, start);
  run.run(res);
  return {run.sigma(), run.delta(), run.failure};
}

// The solve on the GPU (contact/PolonskyKeerDevice.cu): uploads the heights (and a warm
// start), runs Run over the device backend, and leaves p (times sigma) and w = h + u in
// st.pressure and st.displacement, as the CPU backend does. `dev` holds the device's work
// arrays (made on first use; kept while Options::keep_work). A build without CUDA throws.
End solve_on_device(std::unique_ptr<PolonskyKeer::Device, PolonskyKeer::DeviceDelete>& dev, HalfSpace& hs,
                    const Field& h, const PolonskyKeer::Options& o, double h_scale, const Target& target,
                    ContactState& st, const Start& start, SolveResult& res);

}  // namespace cmc::pk
