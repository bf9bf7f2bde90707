// The adhesive CG's iteration (AdhesiveSolver.hpp: the algorithm, its safeguards and its
// residual): one displacement-controlled solve on the transform-grid fields of
// AdhesiveSolver::Work, over the CPU backend's passes (CpuBackend.hpp). Written once for
// every interaction law (a template on it); instantiated in AdhesiveSolver.cpp alone.
#pragma once

#include "cmc/contact/adhesive_cg/CpuBackend.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

namespace cmc::adhesive {

// Relative size of an energy change that counts as an increase (round-off of the sums
// over the grid is ~1e-13 relative even at 10^8 points).
inline constexpr double kEnergySlack = 1e-11;
// Sufficient-descent factor: a conjugate direction must satisfy ψ·d <= −kDescent |ψ|²,
// or it is reset to −ψ (the usual safeguard of nonlinear CG; Nocedal & Wright,
// Numerical Optimization, 2nd ed., §5.2).
inline constexpr double kDescent = 0.01;
// Consecutive iterations without progress (no descent direction, or a line search that
// found no lower energy) after which the solve stops and says why.
inline constexpr int kMaxStalls = 3;
// Backtracking: the next trial step is the minimiser of the quadratic through E(0), E'(0)
// and E(α), clamped to [0.1 α, 0.5 α] (safeguarded interpolation, Nocedal & Wright §3.5);
// 0.1 α when E(α) is not finite.
inline constexpr double kBacktrackMin = 0.1, kBacktrackMax = 0.5;
// A step's change of Σ g below this fraction of Σ g is round-off: the periodic mean-gap
// rescale is skipped (the exact recomputes remove the drift).
inline constexpr double kMeanGapRoundoff = 1e-13;
// Round-off floor of the exact residual: a claimed convergence that the exact K u does
// not confirm, kFloorHits times without the exact residual falling below kFloorGain of its
// best, is a floor above the tolerance (huge gaps make u = g − (h − δ) cancel).
inline constexpr double kFloorGain = 0.9;
inline constexpr int kFloorHits = 20;


// The state of one line search along d. The trial point is held in place by x, Ku as
// x = s_app (x0 + a_app d) (an unclipped step), or in w.trial, w.Ktrial (a clipped one).
struct LineSearch {
  double psid = 0.0, dKd = 0.0, dsum = 0.0, afeas = 0.0;  // from the direction
  double U0 = 0.0, E0 = 0.0, slack = 0.0, gsum0 = 0.0;    // the base point
  Sums S0;
  double a_app = 0.0, s_app = 1.0, U_app = 0.0;
  bool clipped = false, base_dirty = false, first_try = true;
  Sums Snew;
  double Unew = 0.0;
};

template <class I>
class Iteration {
 public:
  using Options = AdhesiveSolver::Options;
  Iteration(AdhesiveSolver::Work& w, HalfSpace& hs, const I& inter, const Options& o, double P, double trust,
            double delta, SolveDiagnostics& diag)
      : w_(w), hs_(hs), inter_(inter), opt_(o), P_(P), trust_(trust), gbar_(w.hmean - delta), K_(hs.stiffness()),
        diag_(diag), mu_lag_(w.periodic ? -kInf : 0.0) {
    w_.shape.delta = delta;
  }
  // Initial gaps from `st` (warm) or u = 0 (cold), then an exact evaluation.
  bool start(const ContactState& st);
  // Iterate to the tolerance or a stop; res gets iterations and residual.
  void run(SolveResult& res);
  // The solved state on the patch; returns false if it is not finite.
  bool write_state(ContactState& st, double& energy) const;
  double residual() const { return residual_; }
  const std::string& stop_message() const { return stop_msg_; }

 private:
  enum class Verdict { Converged, Continue, Stop };
  Sums pass(bool step, double a, double sc, bool daniel) {
    return adhesive::evaluate(inter_, w_.arrays(), w_.shape, {a, sc, mu_lag_, shift_}, step, daniel,
                              opt_.restart_on_active_set_change);
  }
  double mean_scale(double* xs, double gs) const;
  void digest(const Sums& s);
  bool exact();
  Verdict check_convergence(SolveResult& res);
  bool iterate();
  double conjugate_beta();
  // Step rule.
  double step_scale(const LineSearch& ls, double al) const;
  Sums move_to(LineSearch& ls, double a2, double s2, bool daniel);
  void try_projected(LineSearch& ls, double alpha, bool daniel);
  bool line_search(LineSearch& ls, double alpha, bool negc);
  void reject(LineSearch& ls);
  void accept(LineSearch& ls, double kappa, bool negc);
  bool stop(std::string msg) {
    stop_msg_ = std::move(msg);
    return false;
  }

  AdhesiveSolver::Work& w_;
  HalfSpace& hs_;
  const I& inter_;
  const Options& opt_;
  const double P_, trust_, gbar_;  // pressure scale, trust step, prescribed mean gap (periodic)
  const Field& K_;
  SolveDiagnostics& diag_;
  double mu_lag_;       // the wall set is classified with the previous μ
  double shift_ = 0.0;  // free-set moments are taken relative to this
  double U_ = 0.0, Phi_ = 0.0;  // ½ Σ u Ku and Σ φ (grid sums)
  double mu_ = 0.0, psi2_ = 0.0, residual_ = kInf;
  Sums S_;
  bool restart_ = true, exact_now_ = true;
  double kappa_prev_ = 0.0, beta_num_ = 0.0;
  int since_exact_ = 0, stalls_ = 0;
  double floor_residual_ = kInf;  // smallest exact residual after a false convergence claim
  int floor_hits_ = 0;
  std::string stop_msg_;
};

// Periodic: the factor s that restores the prescribed mean gap when the gaps are scaled by
// it (keeps g >= 0 and the contact set; Bugnicourt et al. 2018), given their sum. A patch
// in full contact with ḡ > 0 is lifted uniformly instead (then s = 1).
template <class I>
double Iteration<I>::mean_scale(double* xs, double gs) const {
  if (!w_.periodic) return 1.0;
  const double gm = gs / w_.N;
  if (gm > 0.0) return gm == gbar_ ? 1.0 : gbar_ / gm;
  std::fill(xs, xs + w_.n, gbar_);
  return 1.0;
}

// Convergence measure: μ (= −p̄, the Lagrange multiplier of the mean gap), |ψ|² and the
// KKT residual of the header, from the sums of a pass.
template <class I>
void Iteration<I>::digest(const Sums& s) {
  S_ = s;
  Phi_ = s.phi;
  if (w_.periodic) mu_ = s.nF > 0.0 ? shift_ + s.sx / s.nF : s.rmin_contact;  // full contact: least compression
  else mu_ = 0.0;
  const double dm = mu_ - shift_;
  psi2_ = std::max(0.0, s.sxx - 2.0 * dm * s.sx + s.nF * dm * dm);
  double v = 0.0;
  if (s.rmax > -kInf) v = std::max({v, s.rmax - mu_, mu_ - s.rmin});
  if (s.rmin_contact < kInf) v = std::max(v, mu_ - s.rmin_contact);
  v = std::max(v, s.out_abs);
  residual_ = v / P_;
}

// Exact K u (one FFT pair) and a full evaluation; on a periodic grid the mean gap is
// re-imposed first (removes round-off drift).
template <class I>
bool Iteration<I>::exact() {
  const double sc = w_.periodic ? mean_scale(w_.x.data(), adhesive::patch_sum(w_.x.data(), w_.n)) : 1.0;
  adhesive::displacement_of(w_.x.data(), w_.shape, sc, w_.trial.data());
  hs_.apply(w_.trial.data(), w_.Ku.data(), K_);
  ++diag_.exact_recomputes;
  const Sums s = pass(false, 0.0, 1.0, false);
  U_ = 0.5 * s.uKu;
  digest(s);
  return s.finite();
}

template <class I>
bool Iteration<I>::start(const ContactState& st) {
  auto& w = w_;
  const Shape& S = w.shape;
  std::fill(w.d.begin(), w.d.end(), 0.0);
  std::fill(w.c.begin(), w.c.end(), 0.0);
  std::fill(w.bound.begin(), w.bound.end(), 0);
  // Warm start: contacts kept at g = 0, the displacement of every other point kept; cold:
  // u = 0. Projected on g >= 0 (and the mean gap, in exact()).
  const bool warm = st.gap.size() == w.n && st.displacement.size() == w.n;
  if (!w.periodic) {
    std::fill(w.x.begin(), w.x.end(), 0.0);
    if (warm && st.pressure.size() == w.n) {
      // Padding displacements of the previous solution: u = C p (one FFT pair).
      w.to_padded(st.pressure, w.trial);
      hs_.apply(w.trial.data(), w.x.data(), hs_.compliance());
    }
  }
  // The warm state's gap and displacement on this rank's patch rows: the contact grid's
  // own rows, or (distributed free boundary) those rows moved to the padded slab.
  Field gap_rows, disp_rows;
  const bool moved = w.exchange && warm;
  if (moved) w.to_padded(st.gap, gap_rows), w.to_padded(st.displacement, disp_rows);
  const Field &gp = moved ? gap_rows : st.gap, &up = moved ? disp_rows : st.displacement;
  for (int iy = 0; iy < S.ny; ++iy)
    for (int ix = 0; ix < S.nx; ++ix) {
      const std::size_t k = S.row(iy) + ix, kp = moved ? k : std::size_t(iy) * S.nx + ix;
      double g = S.h[k] - S.delta;  // cold: u = 0
      if (warm) g = gp[kp] <= 0.0 ? 0.0 : (S.h[k] - S.delta) + up[kp];
      w.x[k] = g > 0.0 ? g : 0.0;  // also drops non-finite input
    }
  return exact();
}

// Convergence check at the top of an iteration. A residual below the tolerance on an
// incrementally updated K u is confirmed on the exact one; a round-off floor above the
// tolerance ends the solve.
template <class I>
typename Iteration<I>::Verdict Iteration<I>::check_convergence(SolveResult& res) {
  if (residual_ > opt_.tolerance) return Verdict::Continue;
  if (exact_now_) return Verdict::Converged;
  if (!exact()) return stop("non-finite value on an exact recompute"), Verdict::Stop;
  exact_now_ = true;
  since_exact_ = 0;
  res.residual = residual_;
  if (residual_ <= opt_.tolerance) return Verdict::Converged;
  restart_ = true;
  if (residual_ < kFloorGain * floor_residual_) {
    floor_residual_ = residual_;
    floor_hits_ = 0;
  } else if (++floor_hits_ >= kFloorHits) {
    std::ostringstream m;
    m << "residual stalled at " << residual_ << " (round-off floor above the tolerance)";
    return stop(m.str()), Verdict::Stop;
  }
  return Verdict::Continue;
}

// Search direction: Daniel's β = ψ·Hd_old / d_old·Hd_old (clipped at 0; reset when the
// direction would not be one of sufficient descent, after a restart, or when the wall set
// changed and restart_on_active_set_change is set).
template <class I>
double Iteration<I>::conjugate_beta() {
  const double dm = mu_ - shift_;
  double beta = 0.0;
  if (!restart_ && kappa_prev_ > 0.0) beta = std::max(0.0, beta_num_ / kappa_prev_);
  if (opt_.restart_on_active_set_change && S_.changed > 0) beta = 0.0;
  const double psi_dold = S_.sxd - dm * S_.sd;  // Σ_F ψ (d_old − m_old), using Σ_F ψ = 0
  if (beta > 0.0 && -psi2_ + beta * psi_dold > -kDescent * psi2_) beta = 0.0;
  if (beta == 0.0) ++diag_.restarts;
  return beta;
}

// One iteration: direction, one FFT pair for K d, line search, acceptance. Returns false
// when the solve must stop (stop_msg_ says why).
template <class I>
bool Iteration<I>::iterate() {
  // The direction pass classifies the wall set exactly as the last evaluation pass did, so
  // that d has zero mean over the free set.
  const double beta = conjugate_beta();
  const double m_old = (w_.periodic && S_.nF > 0.0) ? S_.sd / S_.nF : 0.0;
  const DirSums D = adhesive::direction_pass(w_.arrays(), w_.shape, mu_, mu_lag_, beta, m_old,
                                             opt_.restart_on_active_set_change);
  // The next pass classifies with this iteration's μ and takes its sums relative to it.
  mu_lag_ = w_.periodic ? mu_ : 0.0;
  shift_ = mu_lag_;
  const double dKd = hs_.apply(w_.d.data(), w_.Kd.data(), K_);  // one FFT pair
  const double kappa = dKd + D.cd2;
  if (!std::isfinite(kappa) || !std::isfinite(D.psid)) return stop("non-finite search direction");
  if (!(D.psid < 0.0)) {
    // Not a descent direction: only round-off at the level of the tolerance does this.
    restart_ = true;
    return ++stalls_ > kMaxStalls ? stop("no descent direction (residual at round-off level)") : true;
  }
  const bool negc = !(kappa > 0.0);
  if (negc) ++diag_.negative_curvature;
  LineSearch ls;
  ls.psid = D.psid, ls.dKd = dKd, ls.dsum = D.dsum, ls.afeas = D.afeas;
  ls.U0 = U_, ls.E0 = U_ + Phi_, ls.slack = kEnergySlack * (std::abs(U_) + std::abs(Phi_)) + 1e-300;
  ls.S0 = S_, ls.gsum0 = S_.gsum, ls.U_app = U_, ls.Unew = U_;
  // Exact step along the curvature, or a trust step along negative curvature.
  const double alpha = negc ? trust_ / D.dmax : -D.psid / kappa;
  if (!line_search(ls, alpha, negc)) {
    reject(ls);
    return ++stalls_ > kMaxStalls ? stop("line search failed to decrease the energy") : true;
  }
  stalls_ = 0;
  accept(ls, kappa, negc);
  if (ls.clipped || ++since_exact_ < opt_.recompute_every) return true;
  if (!exact()) return stop("non-finite value on an exact recompute");
  exact_now_ = true;
  since_exact_ = 0;
  return true;
}

// Scale of a periodic step x <- s (x + α d) that keeps the mean gap (d has zero mean over
// the free set up to points projected on the feasible cone and round-off).
template <class I>
double Iteration<I>::step_scale(const LineSearch& ls, double al) const {
  if (!w_.periodic || !(std::abs(al * ls.dsum) > kMeanGapRoundoff * std::abs(ls.gsum0))) return 1.0;
  const double gs = ls.gsum0 + al * ls.dsum;
  return gs > 0.0 ? double(w_.n) * gbar_ / gs : 1.0;
}

// Move the in-place trial to x = s2 (x0 + a2 d): an exact incremental update (no FFT).
template <class I>
Sums Iteration<I>::move_to(LineSearch& ls, double a2, double s2, bool daniel) {
  const double sig = s2 / ls.s_app, ap = ls.s_app * (a2 - ls.a_app);
  const Sums sn = pass(true, ap, sig, daniel);
  ls.U_app = sig != 1.0 ? 0.5 * sn.uKu : ls.U_app + ap * sn.uKu + 0.5 * ap * ap * ls.dKd;
  ls.a_app = a2;
  ls.s_app = s2;
  return sn;
}

// A step that takes some point to the wall: the projected trial point in w.trial, its K u
// computed exactly (one FFT pair) into w.Ktrial, and its evaluation; the base point stays
// in x, Ku (but r, c hold the trial's values afterwards).
template <class I>
void Iteration<I>::try_projected(LineSearch& ls, double alpha, bool daniel) {
  auto& w = w_;
  if (ls.a_app != 0.0 || ls.s_app != 1.0) move_to(ls, 0.0, 1.0, false);  // undo an in-place trial
  const double gs = adhesive::trial_pass(w.arrays(), w.shape, alpha, w.trial.data());
  ls.clipped = true;
  ls.base_dirty = true;
  if (!std::isfinite(gs)) {
    ls.Unew = kInf;
    return;
  }
  const double sc = mean_scale(w.trial.data(), gs);
  adhesive::displacement_of(w.trial.data(), w.shape, sc, w.r.data());  // r is free until the pass below
  hs_.apply(w.r.data(), w.Ktrial.data(), K_);
  std::swap(w.x, w.trial);
  std::swap(w.Ku, w.Ktrial);
  ls.Snew = pass(false, 0.0, 1.0, daniel);
  std::swap(w.x, w.trial);
  std::swap(w.Ku, w.Ktrial);
  ls.Unew = 0.5 * ls.Snew.uKu;
}

// Step rule: try α; accept if the exact energy did not rise beyond round-off, otherwise
// backtrack by safeguarded quadratic interpolation, up to max_backtracks times.
template <class I>
bool Iteration<I>::line_search(LineSearch& ls, double alpha, bool negc) {
  for (int bt = 0; bt <= opt_.max_backtracks; ++bt) {
    ls.first_try = bt == 0;
    if (!(alpha > 0.0) || !std::isfinite(alpha)) return false;
    // Daniel's β needs the Hessian along d at the base point: only a full, first step
    // with positive curvature gives it.
    const bool daniel = !negc && ls.first_try;
    if (alpha <= ls.afeas) {
      // No point reaches the wall: exact incremental update in place (no FFT).
      ls.Snew = move_to(ls, alpha, step_scale(ls, alpha), daniel);
      ls.Unew = ls.U_app;
      ls.clipped = false;
      ls.base_dirty = false;
    } else {
      try_projected(ls, alpha, daniel);
    }
    const double Enew = ls.Unew + ls.Snew.phi;
    if (std::isfinite(Enew) && ls.Snew.finite() && Enew <= ls.E0 + ls.slack) return true;
    ++diag_.backtracks;
    double next = kBacktrackMin * alpha;
    if (std::isfinite(Enew)) {
      next = kBacktrackMax * alpha;
      const double curv = 2.0 * (Enew - ls.E0 - ls.psid * alpha) / (alpha * alpha);
      if (curv > 0.0) next = std::clamp(-ls.psid / curv, kBacktrackMin * alpha, kBacktrackMax * alpha);
    }
    alpha = next;
  }
  return false;
}

// No acceptable step: back to the base point, steepest descent next.
template <class I>
void Iteration<I>::reject(LineSearch& ls) {
  if (ls.a_app != 0.0 || ls.s_app != 1.0) move_to(ls, 0.0, 1.0, false);
  else if (ls.base_dirty) pass(false, 0.0, 1.0, false);  // r, c held the rejected trial
  U_ = ls.U0;
  digest(ls.S0);
  restart_ = true;
}

template <class I>
void Iteration<I>::accept(LineSearch& ls, double kappa, bool negc) {
  if (ls.clipped) {
    std::swap(w_.x, w_.trial);
    std::swap(w_.Ku, w_.Ktrial);
    ++diag_.clipped_steps;
    since_exact_ = 0;
  }
  U_ = ls.Unew;
  kappa_prev_ = kappa;
  digest(ls.Snew);
  beta_num_ = S_.sxHd - (mu_ - shift_) * S_.sHd;
  // Daniel's β needs the Hessian at the base point along the full step: restart after a
  // negative-curvature or backtracked step.
  restart_ = negc || !ls.first_try;
  exact_now_ = ls.clipped;
}

template <class I>
void Iteration<I>::run(SolveResult& res) {
  for (int it = 0;; ++it) {
    res.iterations = it;
    res.residual = residual_;
    if (opt_.progress && it % std::max(1, opt_.progress_every) == 0) opt_.progress({it, residual_, 0, false, U_ + Phi_});
    if (check_convergence(res) != Verdict::Continue) return;
    if (it >= opt_.max_iterations || !iterate()) return;
  }
}

template <class I>
bool Iteration<I>::write_state(ContactState& st, double& energy) const {
  const Shape& S = w_.shape;
  const double pbar = w_.periodic ? -mu_ : 0.0;
  const std::size_t n = w_.n;
  st.gap.resize(n);
  st.displacement.resize(n);
  st.pressure.resize(n);
  // Distributed free boundary: the state is formed on the padded slab's patch rows, then
  // moved to the contact grid's slabs.
  Field gap_rows, disp_rows, pres_rows;
  if (w_.exchange) gap_rows.assign(w_.M, 0.0), disp_rows.assign(w_.M, 0.0), pres_rows.assign(w_.M, 0.0);
  Field &gap = w_.exchange ? gap_rows : st.gap, &disp = w_.exchange ? disp_rows : st.displacement,
        &pres = w_.exchange ? pres_rows : st.pressure;
  struct Acc {
    double psum = 0.0;
    bool finite = true;
    void merge(const Acc& o) { psum += o.psum, finite = finite && o.finite; }
  };
  const Acc a = Grid::parallel_reduce<Acc>(std::size_t(S.ny), [&](std::size_t r0, std::size_t r1, Acc& acc) {
    for (int iy = int(r0); iy < int(r1); ++iy)
      for (int ix = 0; ix < S.nx; ++ix) {
        const std::size_t k = S.row(iy) + ix, kp = w_.exchange ? k : std::size_t(iy) * S.nx + ix;
        gap[kp] = w_.x[k];
        disp[kp] = w_.x[k] - (S.h[k] - S.delta);
        pres[kp] = w_.Ku[k] + pbar;
        acc.psum += pres[kp];
        acc.finite = acc.finite && std::isfinite(pres[kp]) && std::isfinite(gap[kp]);
      }
  });
  if (w_.exchange) {
    w_.exchange->backward(gap_rows.data(), st.gap.data());
    w_.exchange->backward(disp_rows.data(), st.displacement.data());
    w_.exchange->backward(pres_rows.data(), st.pressure.data());
  }
  st.penetration = S.delta;
  st.mean_pressure = a.psum / w_.N;
  energy = (U_ + Phi_) * hs_.grid().cell_area();
  return a.finite;
}


}  // namespace cmc::adhesive
