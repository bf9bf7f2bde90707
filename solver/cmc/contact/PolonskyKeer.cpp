#include "cmc/contact/PolonskyKeer.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace cmc {

namespace {

// Scans that touch only what they need. The contact set Ic = {p > 0} is kept as a byte
// mask beside p; at the challenge's loads it holds a few per cent of the points, so the
// passes that work on Ic alone skip eight points out of contact at a time, and the
// passes that must also find overlap elsewhere (w below a level) test eight points at a
// time with a comparison the compiler vectorises, and go point by point only through a
// block that holds something. Points are visited in index order, as a dense loop visits
// them, and a skipped point would have added nothing: every sum adds the same terms in the
// same order, so the result is the dense loop's to the last bit. (Measured on the peer's
// problem at 2048², one thread: the real-space passes of an iteration took 6.1 of its
// 9.9 s outside the transforms before.)
constexpr std::size_t kBlock = 8;
inline bool any_set(const std::uint8_t* m) {
  std::uint64_t word;
  std::memcpy(&word, m, sizeof word);
  return word != 0;
}
inline bool any_below(const double* w, double level) {
  int found = 0;
  for (std::size_t k = 0; k < kBlock; ++k) found |= int(w[k] < level);
  return found != 0;
}
// f(i) for every i of [b, e) in the mask, in index order.
template <class F>
void for_each_in(const std::uint8_t* m, std::size_t b, std::size_t e, F&& f) {
  std::size_t i = b;
  for (; i + kBlock <= e; i += kBlock)
    if (any_set(m + i))
      for (std::size_t k = i; k < i + kBlock; ++k)
        if (m[k]) f(k);
  for (; i < e; ++i)
    if (m[i]) f(i);
}
// f(i), in index order, for every i of [b, e) of a block of eight that holds a point in
// the mask or one with w < level (f sees the block's other points too, and must check).
template <class F>
void for_each_in_or_below(const std::uint8_t* m, const double* w, double level, std::size_t b, std::size_t e, F&& f) {
  std::size_t i = b;
  for (; i + kBlock <= e; i += kBlock)
    if (any_set(m + i) || any_below(w + i, level))
      for (std::size_t k = i; k < i + kBlock; ++k) f(k);
  for (; i < e; ++i) f(i);
}

// The spectral state that makes an iteration cost one FFT pair: the transform p̂ of the
// current pressure, t̂ of the search direction and ĥ/N of the heights (so that the
// operator returns w = h + G p without a pass that reads h).
class SpectralPressure {
 public:
  SpectralPressure(HalfSpace& hs, const Field& h, Spectrum& p_hat, Spectrum& t_hat, Spectrum& h_hat)
      : hs_(hs), p_hat_(p_hat), t_hat_(t_hat), h_hat_(h_hat) {
    hs_.forward(h, h_hat_);
    const double norm = 1.0 / double(hs_.transform_points());
    for (auto& c : h_hat_) c *= norm;
  }
  // p̂ = s FFT(p) (one forward) and w = h + G p̂ (one inverse).
  void set_pressure(const Field& p, double s, Field& w) {
    hs_.forward(p, p_hat_);
    step(s, 0.0, w);
  }
  // t̂ = FFT(t) (one forward); returns <t, G t>.
  double set_direction(const Field& t) {
    hs_.forward(t, t_hat_);
    return hs_.quadratic_form(t_hat_, hs_.compliance());
  }
  // p̂ ← s (p̂ − τ t̂) and w = h + G p̂ (one inverse). The caller applies the same step to
  // its real-space p.
  void step(double s, double tau, Field& w) {
    // On the real and imaginary parts as doubles (what std::complex computes, component by
    // component, for a complex times a real; written out so the compiler keeps them in
    // registers instead of spilling each product).
    double* out = reinterpret_cast<double*>(hs_.spectrum().data());
    double* ph = reinterpret_cast<double*>(p_hat_.data());
    const double* th = reinterpret_cast<const double*>(t_hat_.data());
    const double* off = reinterpret_cast<const double*>(h_hat_.data());
    const double* ker = hs_.compliance().data();
    const bool move = tau != 0.0;
    Grid::parallel_for(p_hat_.size(), [&](std::size_t b, std::size_t e) {
      if (move) {
        for (std::size_t k = b; k < e; ++k) {
          const double re = s * (ph[2 * k] - tau * th[2 * k]), im = s * (ph[2 * k + 1] - tau * th[2 * k + 1]);
          ph[2 * k] = re, ph[2 * k + 1] = im;
          out[2 * k] = re * ker[k] + off[2 * k], out[2 * k + 1] = im * ker[k] + off[2 * k + 1];
        }
      } else {
        for (std::size_t k = b; k < e; ++k) {
          const double re = s * ph[2 * k], im = s * ph[2 * k + 1];
          ph[2 * k] = re, ph[2 * k + 1] = im;
          out[2 * k] = re * ker[k] + off[2 * k], out[2 * k + 1] = im * ker[k] + off[2 * k + 1];
        }
      }
    });
    hs_.inverse(w);
  }

 private:
  HalfSpace& hs_;
  Spectrum &p_hat_, &t_hat_, &h_hat_;
};

// Sums of step (a) over the contact set Ic = {p > 0} and the overlap set, relative to c.
struct GapSums {
  double s1 = 0.0, s2 = 0.0, nc = 0.0;  // Σ_Ic (w − c), Σ_Ic (w − c)², |Ic|
  double ol = 0.0, nol = 0.0;           // Σ overlap², number of overlapping points
  double tsum = 0.0;                    // Σ_Ic t: keeps the next direction load-neutral
  void merge(const GapSums& o) {
    s1 += o.s1, s2 += o.s2, nc += o.nc, ol += o.ol, nol += o.nol, tsum += o.tsum;
  }
};

}  // namespace

// A solve's work arrays (PolonskyKeer::Options::keep_work keeps them between solves).
struct PolonskyKeer::Work {
  Spectrum p_hat, t_hat, h_hat;
  Field t, z;
  std::vector<std::uint8_t> ic;
};

namespace {

// One solve: the iterate and the steps (a)–(h) of Polonsky & Keer §3 as named parts.
class PkRun {
 public:
  PkRun(HalfSpace& hs, const Field& h, const PolonskyKeer::Options& o, double h_scale, const Target& target,
        ContactState& st, PolonskyKeer::Work& work)
      : hs_(hs), h_(h), opt_(o), h_scale_(h_scale), n_(h.size()), force_(target.control == Control::MeanPressure),
        target_(force_ ? target.value : 0.0), p_(st.pressure), w_(st.displacement), t_(work.t),
        delta_(force_ ? st.penetration : target.value), spectral_(hs, h, work.p_hat, work.t_hat, work.h_hat),
        precondition_(o.precondition && hs.periodic()), z_(work.z), ic_(work.ic) {
    t_.assign(n_, 0.0);
    ic_.resize(n_);  // filled by set_contact_set() before any pass reads it
    if (precondition_) z_.assign(n_, 0.0);
  }

  void run(SolveResult& res);
  std::string failure;
  double delta() const { return delta_; }
  double sigma() const { return sigma_; }

 private:
  // Stiffness of the longest wave, E* π / L: turns an overlap into a first pressure.
  double overlap_stiffness() const { return hs_.contact_modulus() * std::numbers::pi / hs_.grid().lx; }
  void initial_pressure();
  void set_contact_set();
  GapSums gap_sums() const;
  bool restart_from_overlap();
  double direction(double beta, double tbar);
  double preconditioned_direction(double tbar, double nc);
  bool project(double tau);
  void exact() {
    spectral_.set_pressure(p_, sigma_, w_);
    since_exact_ = 0;
  }

  HalfSpace& hs_;
  const Field& h_;
  const PolonskyKeer::Options& opt_;
  double h_scale_;
  std::size_t n_;
  bool force_;
  double target_;
  Field &p_, &w_;  // pressure (times sigma_), and w = h + u (the gap plus δ)
  Field& t_;       // search direction: zero off Ic
  double delta_;
  SpectralPressure spectral_;
  double sigma_ = 1.0;  // the pressure is sigma_ p_: the last load scaling, applied lazily
  int since_exact_ = 0;  // linear spectral steps since p̂ was last taken from p
  bool conjugate_ = false;  // PK's δ flag: false restarts steepest descent
  bool precondition_;
  Field& z_;                // preconditioned gap K g on Ic (precondition_ only)
  double gz_old_ = 1.0;     // Σ_Ic g z of the previous direction
  std::vector<std::uint8_t>& ic_;  // the contact set Ic: ic_[i] == (p_[i] > 0), always
};

// Ic from p, after p was set wholesale; the direction is zero off Ic.
void PkRun::set_contact_set() {
  const double* p = p_.data();
  std::uint8_t* m = ic_.data();
  double* t = t_.data();
  Grid::parallel_for(n_, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      m[i] = p[i] > 0.0;
      if (!m[i]) t[i] = 0.0;
    }
  });
}

void PkRun::initial_pressure() {
  // Warm start, or PK's uniform guess (force control), or a guess proportional to the
  // geometric overlap (displacement control).
  const bool warm = p_.size() == n_ && Grid::sum(p_) > 0.0;
  if (!warm) {
    p_.assign(n_, 0.0);
    if (force_) {
      std::fill(p_.begin(), p_.end(), target_);
    } else {
      const double k = overlap_stiffness();
      for (std::size_t i = 0; i < n_; ++i) p_[i] = std::max(0.0, delta_ - h_[i]) * k;
    }
  }
  if (force_) {
    if (target_ == 0.0) {
      std::fill(p_.begin(), p_.end(), 0.0);
    } else {
      const double s = target_ / Grid::mean(p_);
      for (auto& x : p_) x *= s;
    }
  }
  w_.resize(n_);
  set_contact_set();
  exact();  // w = h + G p, and p̂ kept
}

// (a) gap statistics over Ic = {p > 0} (σ > 0 does not change it), shifted by the
// previous δ to avoid cancellation; overlap (w < c) elsewhere.
GapSums PkRun::gap_sums() const {
  const double c = delta_;
  const double* w = w_.data();
  const std::uint8_t* m = ic_.data();
  const double* t = t_.data();
  return Grid::parallel_reduce<GapSums>(n_, [&](std::size_t b, std::size_t e, GapSums& acc) {
    GapSums s;
    for_each_in_or_below(m, w, c, b, e, [&](std::size_t i) {
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
    });
    acc.merge(s);
  });
}

// The iteration lost its contact set: start again from the geometric overlap.
bool PkRun::restart_from_overlap() {
  const double k = overlap_stiffness();
  for (std::size_t i = 0; i < n_; ++i) p_[i] = std::max(0.0, delta_ - h_[i]) * k;
  if (Grid::sum(p_) == 0.0) {
    failure = "Polonsky-Keer lost its contact set";
    return false;
  }
  sigma_ = 1.0;
  set_contact_set();
  exact();
  conjugate_ = false;
  return true;
}

// (c) conjugate direction on Ic: t = g + β (t − t̄). Under load control the old direction
// is made load-neutral on the current Ic (Σ_Ic t = 0), so the step keeps Σ p and the exact
// line search needs only <t, G t> (PK subtract the Ic-mean of G t instead, which costs a
// second transform). Returns Σ g t.
double PkRun::direction(double beta, double tbar) {
  double* t = t_.data();
  const double* w = w_.data();
  const std::uint8_t* m = ic_.data();
  const double d = delta_;
  return Grid::parallel_reduce<SumReduction>(n_, [&](std::size_t b, std::size_t e, SumReduction& acc) {
           double sgt = 0.0;
           for_each_in(m, b, e, [&](std::size_t i) {
             const double g = w[i] - d;
             t[i] = g + beta * (t[i] - tbar);
             sgt += g * t[i];
           });
           acc.v += sgt;
         }).v;
}

// (c) with the stiffness preconditioner: z = P K P g (made load-neutral on Ic under load
// control), β = Σ g z / (Σ g z)_old, t = z + β (t − t̄). One FFT pair. nc = |Ic| (> 0).
// Returns Σ g t.
double PkRun::preconditioned_direction(double tbar, double nc) {
  double* z = z_.data();
  double* t = t_.data();
  const double* w = w_.data();
  const std::uint8_t* m = ic_.data();
  const double d = delta_;
  Grid::parallel_for(n_, [&](std::size_t b, std::size_t e) {
    std::size_t i = b;
    for (; i + kBlock <= e; i += kBlock)
      if (any_set(m + i)) {
        for (std::size_t k = i; k < i + kBlock; ++k) z[k] = m[k] ? w[k] - d : 0.0;
      } else {
        std::fill_n(z + i, kBlock, 0.0);
      }
    for (; i < e; ++i) z[i] = m[i] ? w[i] - d : 0.0;
  });
  hs_.apply(z, z, hs_.stiffness());
  // One pass for the Ic-mean of z and Σ g z: Σ g (z − z̄) = Σ g z − z̄ Σ g.
  struct Acc {
    double zsum = 0.0, gz = 0.0, gsum = 0.0;
    void merge(const Acc& o) { zsum += o.zsum, gz += o.gz, gsum += o.gsum; }
  };
  const Acc a = Grid::parallel_reduce<Acc>(n_, [&](std::size_t b, std::size_t e, Acc& acc) {
    Acc s;
    for_each_in(m, b, e, [&](std::size_t i) {
      const double g = w[i] - d;
      s.zsum += z[i], s.gz += g * z[i], s.gsum += g;
    });
    acc.merge(s);
  });
  const double zbar = force_ ? a.zsum / nc : 0.0;
  const double gz = a.gz - zbar * a.gsum;
  const double beta = conjugate_ && gz_old_ > 0.0 ? gz / gz_old_ : 0.0;
  gz_old_ = gz;
  return Grid::parallel_reduce<SumReduction>(n_, [&](std::size_t b, std::size_t e, SumReduction& acc) {
           double sgt = 0.0;
           for_each_in(m, b, e, [&](std::size_t i) {
             t[i] = (z[i] - zbar) + beta * (t[i] - tbar);
             sgt += (w[i] - d) * t[i];
           });
           acc.v += sgt;
         }).v;
}

// (e)–(g) pressure step p ← σ p − τ t on Ic, projection onto p ≥ 0, overlapping points
// join with p = −τ g. Then (h) the load scaling (applied lazily through σ) and the new
// displacement. Returns false if the pressure vanished under load control.
bool PkRun::project(double tau) {
  struct Step {
    double psum = 0.0;
    bool changed = false;
    void merge(const Step& o) { psum += o.psum, changed = changed || o.changed; }
  };
  double* p = p_.data();
  const double* w = w_.data();
  double* t = t_.data();
  std::uint8_t* m = ic_.data();
  const double sg = sigma_, d = delta_;
  // Off Ic and without overlap (w ≥ d) p stays 0 and adds nothing: those blocks are skipped.
  const Step st = Grid::parallel_reduce<Step>(n_, [&](std::size_t b, std::size_t e, Step& acc) {
    Step s;
    for_each_in_or_below(m, w, d, b, e, [&](std::size_t i) {
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
    });
    acc.merge(s);
  });
  double scale = 1.0;
  if (force_) {
    const double mean_p = st.psum / double(hs_.grid().points());
    if (!(mean_p > 0.0)) {
      failure = "Polonsky-Keer: pressure vanished during the iteration";
      return false;
    }
    scale = target_ / mean_p;
  }
  // A linear step is one inverse transform; a projected one needs the transform of the
  // new p (one forward more).
  if (st.changed || ++since_exact_ >= opt_.recompute_every) {
    spectral_.set_pressure(p_, scale, w_);
    since_exact_ = 0;
  } else {
    spectral_.step(scale, tau, w_);
  }
  sigma_ = scale;
  conjugate_ = !st.changed;
  return true;
}

void PkRun::run(SolveResult& res) {
  initial_pressure();
  double G_old = 1.0;
  double last_tau = hs_.grid().lx / (std::numbers::pi * hs_.contact_modulus());  // compliance of the longest wave
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
      if (!restart_from_overlap()) return;
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

    const double beta = conjugate_ ? G / G_old : 0.0;
    if (beta == 0.0) ++res.diagnostics.restarts;
    G_old = G;
    const double tbar = force_ ? S.tsum / S.nc : 0.0;
    const double sgt = precondition_ ? preconditioned_direction(tbar, S.nc) : direction(beta, tbar);
    // (d) curvature along t from its transform alone (one forward transform)
    const double denom = spectral_.set_direction(t_);
    double tau;
    if (denom > 0.0 && sgt > 0.0) {
      tau = last_tau = sgt / denom;
    } else if (S.nol > 0.0) {
      tau = last_tau;  // nothing to gain on Ic: only overlapping points move
      conjugate_ = false;
    } else {
      // No descent left and no overlap: round-off floor. Confirm on an exact u, then stop.
      if (since_exact_ == 0) return;
      exact();
      ++res.diagnostics.exact_recomputes;
      conjugate_ = false;
      continue;
    }
    if (!project(tau)) return;
    if (!conjugate_) ++res.diagnostics.clipped_steps;
  }
}

}  // namespace

PolonskyKeer::PolonskyKeer(HalfSpace& hs, const Field& heights, Options o) : hs_(hs), h_(heights), opt_(std::move(o)) {
  if (heights.size() != hs.grid().size()) throw std::invalid_argument("PolonskyKeer: heights do not match the grid");
  const double hm = Grid::mean(heights);
  const double var = Grid::parallel_reduce<SumReduction>(heights.size(), [&](std::size_t b, std::size_t e, SumReduction& acc) {
                       double s = 0.0;
                       for (std::size_t i = b; i < e; ++i) s += (heights[i] - hm) * (heights[i] - hm);
                       acc.v += s;
                     }).v;
  h_scale_ = std::sqrt(var / double(hs.grid().points()));
  if (!(h_scale_ > 0.0)) h_scale_ = 1.0;
}

PolonskyKeer::~PolonskyKeer() = default;

SolveResult PolonskyKeer::solve(const Target& target, ContactState& st) {
  const SolveClock clock(hs_);
  SolveResult res;
  auto finish = [&](bool converged, std::string msg) { return clock.finish(res, converged, std::move(msg)); };
  if (target.control == Control::MeanPressure && !(target.value >= 0.0))
    return finish(false, "Polonsky-Keer needs a non-negative mean pressure (no adhesion in a hard-wall solve)");

  if (!work_) work_ = std::make_unique<Work>();
  PkRun run(hs_, h_, opt_, h_scale_, target, st, *work_);
  run.run(res);
  if (!opt_.keep_work) work_.reset();
  // ---- the solved state. The reported gap is the solution's: zero where pressure is
  // carried, and the non-negative gap elsewhere; how far the iterate is from that is the
  // residual. w = h + u becomes the displacement again.
  Field &p = st.pressure, &u = st.displacement;
  const double sigma = run.sigma(), delta = run.delta();
  const std::size_t n = p.size();
  st.gap.resize(n);
  Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (sigma != 1.0) p[i] *= sigma;
      st.gap[i] = p[i] > 0.0 ? 0.0 : std::max(0.0, u[i] - delta);
      u[i] -= h_[i];
    }
  });
  st.penetration = delta;
  st.mean_pressure = Grid::mean(p);
  res.energy = hs_.energy(p, u);
  const bool ok = run.failure.empty() && res.residual <= opt_.tolerance;
  std::string msg = run.failure;
  if (!ok && msg.empty()) {
    std::ostringstream s;
    s << "Polonsky-Keer stopped after " << res.iterations << " iterations at residual " << res.residual
      << " > tolerance " << opt_.tolerance;
    msg = s.str();
  }
  return finish(ok, msg);
}

}  // namespace cmc
