// One Polonsky–Keer solve, written once for every backend: the steps (a)–(h) of Polonsky &
// Keer §3 (see PolonskyKeer.hpp) as named parts, over a backend B that holds the fields and
// runs the passes (what B provides: the concept PolonskyKeerBackend, Contract.hpp, which
// Run and iterate require). The CPU backend (CpuBackend.hpp) runs them with OpenMP over the
// contact set only; the CUDA backend (CudaBackend.cuh) as kernels with fixed-order
// reductions. Neither holds any of the algorithm.
#pragma once

#include "cmc/contact/polonsky_keer/Contract.hpp"
#include "cmc/contact/polonsky_keer/PolonskyKeer.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>

namespace cmc::pk {

// The conjugate directions survive a step whose projection (points that left the contact
// set or joined it) changed the step by at most this fraction of its length; a larger
// change restarts steepest descent, as Polonsky and Keer's δ flag does for any change.
// Near a smooth contact edge (the adhesive zone of the shape coarse-graining, a
// warm-started load step) one or two points of tens of thousands cross the edge in almost
// every step, and restarting there made the solve preconditioned steepest descent until the
// edge settled. Measured on the challenge's cases at their own tolerances (iterations with
// a restart at every change / with this fraction / with conjugacy always kept): hard wall at
// 250 kPa, 2048², 72 / 55 / 70; the hard-wall load sweep, 1024², 1140 / 714 / 1241; the
// adhesive load sweep, 512², 890 / 702 / 1070; the same states. Fractions of 0.32 and 0.55
// were faster on some cases and failed on others (a hard-wall sweep step stalled at 5000
// iterations; tests/test_polonsky_keer.cpp's solves to 1e-12 did not converge), 0.03 was
// slower (849 on the sweep). A kept direction that does not descend restarts.
inline constexpr double kConjugateAcross = 0.1;

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
template <PolonskyKeerBackend B>
class Run {
 public:
  Run(B& b, const PolonskyKeer::Options& o, double h_scale, const Target& target, const Start& start)
      : b_(b), opt_(o), h_scale_(h_scale), force_(target.control == Control::MeanPressure),
        target_(force_ ? target.value : 0.0), delta_(start.delta), warm_(start.warm),
        precondition_(start.precondition), overlap_k_(start.overlap_k), last_tau_(start.longest_compliance),
        warm_sum_(start.warm_sum) {}

  void run(SolveResult& res);
  double delta() const { return delta_; }
  double sigma() const { return sigma_; }
  std::string failure;

  // ---- the transforms of a step: each makes w for a new pressure, and with it the next
  // step (a)'s sums (gap_sums() takes them from there)
  // w = h + G (s p): one forward transform and one inverse.
  void set_pressure(double s) {
    keep_pending(b_.template exact_and_gap_sums<GapSums>(s, b_.m, delta_, gap_body()));
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
    exact();  // w = h + G p
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
    changed_ = true;
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
        const double dp = tau * t[i];
        s.step += dp * dp;
        pn -= dp;
        if (pn < 0.0) s.cut += pn * pn, pn = 0.0, s.changed += 1.0;
      }
      if (pn == 0.0) {
        const double g = w[i] - d;
        if (g < 0.0) pn = -tau * g, s.changed += 1.0, s.cut += pn * pn;
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
      c.exact = st.changed > 0.0 || recompute_due;
      return c;
    };
    // The step after one that changed the contact set usually changes it too: a backend
    // may then run the pass inside the new p's transform (and make that step exact).
    const bool likely_exact = changed_ || recompute_due;
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
    changed_ = st.changed > 0.0;
    conjugate_ = st.cut <= kConjugateAcross * kConjugateAcross * st.step;
    return true;
  }

  // ---- the parts of run(): what the loop does after each
  enum class Next { Return, Again, Go };  // end the solve; the next iteration; go on with this one
  // No point carries pressure: either no contact at all (a valid solution of a
  // displacement-controlled step whose indenter does not reach the surface, or of zero
  // load), or the iteration lost its contact set (then it starts again from the overlap).
  Next lost_contact(int it, const GapSums& S, SolveResult& res) {
    if ((!force_ && S.nol == 0.0) || (force_ && target_ == 0.0)) {
      res.iterations = it;
      res.residual = 0.0;
      return Next::Return;
    }
    const Restart r = restart_from_overlap();
    if (r == Restart::Failed) return Next::Return;
    if (r == Restart::NoContact) {
      res.iterations = it;
      res.residual = 0.0;
      return Next::Return;
    }
    ++res.diagnostics.restarts;
    return Next::Again;
  }
  // (b) under load control, the rigid-body position that zeroes the mean gap over Ic; the
  // residual. Returns G, the squared gap norm over Ic. `c`: the δ the sums were taken at.
  double measure(int it, double c, const GapSums& S, SolveResult& res) {
    double G;
    if (force_) {
      const double shift = S.s1 / S.nc;  // mean gap over Ic relative to c
      delta_ = c + shift;
      G = std::max(0.0, S.s2 - S.nc * shift * shift);
    } else {
      G = S.s2;
    }
    // Overlap term measured with the previous δ; it is zero at convergence either way.
    res.residual = std::sqrt((G + S.ol) / (S.nc + S.nol)) / h_scale_;
    res.iterations = it;
    if (opt_.progress && it % std::max(1, opt_.progress_every) == 0) opt_.progress({it, res.residual});
    return G;
  }
  // At the tolerance: done, or confirmed first on u recomputed from the real-space p
  // (removes the linear steps' drift). Else the limits: iterations, and the clock.
  Next stop_or_confirm(int it, SolveResult& res) {
    if (res.residual <= opt_.tolerance) {
      if (since_exact_ == 0 || !opt_.confirm) return Next::Return;
      exact();
      ++res.diagnostics.exact_recomputes;
      return Next::Again;
    }
    if (it >= opt_.max_iterations) return Next::Return;
    if (opt_.stop_at > 0.0 && steady_seconds() >= opt_.stop_at) {
      std::ostringstream s;
      s << kInnerTimeLimitMessage << "after " << it << " iterations at residual " << res.residual << " > tolerance "
        << opt_.tolerance;
      failure = s.str();
      return Next::Return;
    }
    return Next::Go;
  }
  // (d) the step length τ = Σ g t / <t, G t>. Where there is no descent on Ic, only the
  // overlapping points move (with the last τ), or, with no overlap either, the round-off
  // floor is reached: confirmed on an exact u, then the solve stops. `c`: as in measure().
  Next step_length(double sgt, double curvature, double nol, double c, int& it, SolveResult& res, double& tau) {
    if (curvature > 0.0 && sgt > 0.0) {
      tau = last_tau_ = sgt / curvature;
      return Next::Go;
    }
    if (nol > 0.0) {
      tau = last_tau_;
      conjugate_ = false;
      return Next::Go;
    }
    if (since_exact_ == 0) {
      // The sums were taken relative to the δ before this one: where δ moved, G = s2 −
      // nc shift² cancels, and its round-off (ε s2) can hold the residual above the
      // tolerance (a Hertz contact of 5 points at 16², its last step exact: 2.7e-11 against
      // 1e-12). Measure them once more at the new δ (a pass, no transform).
      if (!remeasured_ && c != delta_) {
        remeasured_ = true;
        has_pending_ = false;
        --it;  // not an iteration: nothing moved
        return Next::Again;
      }
      return Next::Return;
    }
    exact();
    ++res.diagnostics.exact_recomputes;
    conjugate_ = false;
    return Next::Again;
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
  int since_exact_ = 0;      // linear steps since w was last made from p
  bool conjugate_ = false;   // PK's δ flag: false restarts steepest descent
  bool changed_ = true;      // the last step changed the contact set (the first: made anew)
  double gz_old_ = 1.0;      // Σ_Ic g z of the previous direction
  GapSums pending_;          // step (a)'s sums, made with the last step's inverse transform
  double pending_level_ = 0.0;
  bool has_pending_ = false;
  bool remeasured_ = false;  // the round-off floor's sums taken again at the current δ
};

template <PolonskyKeerBackend B>
void Run<B>::run(SolveResult& res) {
  initial_pressure();
  double G_old = 1.0;
  for (int it = 0;; ++it) {
    const double c = delta_;
    const GapSums S = gap_sums();
    if (S.nc == 0.0) {
      if (lost_contact(it, S, res) == Next::Return) return;
      continue;
    }
    const double G = measure(it, c, S, res);
    const Next n = stop_or_confirm(it, res);
    if (n == Next::Return) return;
    if (n == Next::Again) continue;

    const double beta = conjugate_ ? G / G_old : 0.0;
    if (beta == 0.0) ++res.diagnostics.restarts;
    G_old = G;
    const double tbar = force_ ? S.tsum / S.nc : 0.0;
    double denom = 0.0;  // (d) curvature along t, from its transform alone
    const double sgt = precondition_ ? preconditioned_direction(tbar, S.nc, denom) : direction(beta, tbar, denom);
    if (conjugate_ && !(sgt > 0.0 && denom > 0.0)) {  // a direction kept across a change that does not descend
      conjugate_ = false;
      ++res.diagnostics.restarts;
      continue;
    }
    double tau = 0.0;
    const Next step = step_length(sgt, denom, S.nol, c, it, res, tau);
    if (step == Next::Return) return;
    if (step == Next::Again) continue;
    if (!project(tau)) return;
    if (changed_) ++res.diagnostics.clipped_steps;
  }
}

// One solve over backend b from `start`: the iteration, then σ, δ and why it failed.
template <PolonskyKeerBackend B>
End iterate(B& b, const PolonskyKeer::Options& o, double h_scale, const Target& target, const Start& start,
            SolveResult& res) {
  Run<B> run(b, o, h_scale, target, start);
  run.run(res);
  return {run.sigma(), run.delta(), run.failure};
}

// The solve on the CPU (CpuBackend.cpp): Run over the CPU backend on the state's own
// fields, which then hold p (times sigma) and w = h + u. `work` holds the work arrays
// (made on first use; kept while Options::keep_work).
End solve_on_cpu(std::unique_ptr<PolonskyKeer::Work>& work, HalfSpace& hs, const Field& h,
                 const PolonskyKeer::Options& o, double h_scale, const Target& target, ContactState& st,
                 const Start& start, SolveResult& res);

// The solve on the GPU (CudaBackend.cu): uploads the heights (and a warm start), runs Run
// over the device backend, and leaves p (times sigma) and w = h + u in st.pressure and
// st.displacement, as the CPU backend does. `dev` holds the device's work
// arrays (made on first use; kept while Options::keep_work). A build without CUDA throws.
End solve_on_device(std::unique_ptr<PolonskyKeer::Device, PolonskyKeer::DeviceDelete>& dev, HalfSpace& hs,
                    const Field& h, const PolonskyKeer::Options& o, double h_scale, const Target& target,
                    ContactState& st, const Start& start, SolveResult& res);

}  // namespace cmc::pk
