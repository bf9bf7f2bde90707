#include "cmc/contact/QuasiStaticAdhesion.hpp"

#include "cmc/grid/Ranks.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cmc {

namespace {

// Newton steps of the jump prediction: from the right on a concave function, each step
// lands between the root and the previous point, so a few suffice; the cap only guards
// against a pathological start.
constexpr int kMaxNewton = 60;

// The next tension of one point (see the header, "Jump prediction"): the tension at the
// largest x <= g with k (g − x) = A(x) − t, A(x) the adhesive tension of gap x; A(0) when
// there is no such x (the point jumps into contact). A is the exponential law's, or one
// of the shape coarse-graining's laws (a linear head to g1, then an exponential tail;
// Interaction.hpp): convex and decreasing in x either way.
struct JumpPrediction {
  double k, w_rho, cutoff, x_peak, a_peak;
  double g1, kappa;                    // the head: A(x) = w_rho − kappa x for x < g1 (g1 = 0: none)
  double tail_a, inv_ell, tail_slope;  // the tail: A(x) = tail_a decay(x), −A'(x) = tail_slope decay(x)

  JumpPrediction(double self_stiffness, const ExponentialAdhesion& a)
      : k(self_stiffness), w_rho(a.peak_tension()), cutoff(a.cutoff()), g1(a.head()), kappa(a.head_slope()),
        tail_a(a.tail_tension()), inv_ell(a.tail_length() > 0.0 ? 1.0 / a.tail_length() : 0.0) {
    tail_slope = tail_a * inv_ell;
    // f(x) = k (g − x) − (A(x) − t) is concave with its maximum where A'(x) = −k: in the
    // tail when the law is steeper than k at contact, else at 0 (a head no steeper than
    // k: f' < 0 everywhere); at g1 for a triangle steeper than k.
    if (g1 > 0.0 && kappa <= k) {
      x_peak = 0.0;
    } else if (tail_a > 0.0) {
      x_peak = std::max(0.0, g1 + a.tail_length() * std::log(tail_a / (k * a.tail_length())));
    } else {
      x_peak = g1;
    }
    a_peak = tension(x_peak);
  }
  bool in_head(double x) const { return g1 > 0.0 && x < g1; }
  // exp(−(x − g1)/ℓ) in the tail, 0 beyond the cutoff, 1 in the head (unused there): what
  // the cascade keeps per point, so that a tension and its slope cost one exponential.
  double decay(double x) const {
    if (x >= cutoff) return 0.0;
    return in_head(x) ? 1.0 : std::exp(-(x - g1) * inv_ell);
  }
  double tension(double x, double e) const { return in_head(x) ? w_rho - kappa * x : tail_a * e; }
  double tension(double x) const { return tension(x, decay(x)); }
  double slope(double x, double e) const {  // −A'(x)
    if (x >= cutoff) return 0.0;
    return in_head(x) ? kappa : tail_slope * e;
  }

  // The predicted gap of a point at gap g under tension t, with the extra pull c (the
  // change of the elastic force from neighbours that moved; c >= 0 pulls in): the largest
  // x <= g with k (g − x) = A(x) − t + c, or 0 (into contact) if there is none. Returns g
  // itself when the point is not pulled further in. `eg` is decay(g), which the caller
  // keeps per point (the cascade asks again for the same g with a larger c).
  double gap(double g, double eg, double t, double c) const {
    if (g <= 0.0) return 0.0;
    if (g >= cutoff && c <= 0.0) return g;
    // f(x) = k (g − x) − (A(x) − t + c), from e = decay(x): one exponential per Newton
    // step, shared by f and f'.
    auto f = [&](double x, double ax) { return k * (g - x) - (ax - t + c); };
    double e = eg, fx = f(g, tension(g, e));
    if (fx >= 0.0) return g;
    if (x_peak >= g || f(x_peak, a_peak) < 0.0) return 0.0;  // no equilibrium below g: into contact
    double x = g;
    for (int i = 0; i < kMaxNewton; ++i) {
      if (i > 0) {
        e = decay(x);
        fx = f(x, tension(x, e));
      }
      if (fx >= 0.0) break;
      const double fp = -k + slope(x, e);  // < 0 on (x_peak, g]
      const double nx = x - fx / fp;
      if (!(nx < x) || nx <= x_peak) break;  // round-off floor reached
      x = nx;
    }
    return x;
  }
};

// Jumps that trigger jumps, within one outer step: a point that closes its gap by Δ pulls
// its neighbour m with the extra force K_mi Δ (K_mi < 0 off the diagonal), which may make
// m jump in turn. The cascade follows this with every other gap held (nonlinear
// Gauss-Seidel on the points near contact), over the exact real-space stiffness within
// `kRadius` points; the far field of K is negative (−E*/(4π r³)), so leaving it out pulls
// less than the truth and keeps the prediction above the maximal equilibrium. The first
// prediction of every point (no pull yet) is a parallel per-point pass; the cascade then
// runs point by point from a first-in-first-out queue that starts in index order: the
// same sequence on every run and thread count.
//
// Distributed (MPI slabs of rows): each rank runs the cascade on its own rows. A move
// that pulls a point of another slab (a neighbour across a slab boundary, or across the
// periodic seam) is sent, not applied: when every rank's queue is empty, the pulls are
// gathered on every rank in rank order and each rank applies those on its rows in that
// order, queueing the points they move; this repeats until a round sends nothing. The
// order of the moves differs from a serial run's (Gauss-Seidel in another order: the
// same kind of conservative prediction, so the same loading-branch state within the
// outer tolerance), and is the same on every run at the same number of ranks; with one
// rank nothing is sent and the sequence is the serial one.
//
// The stencil is the 8 nearest points. Measured on the challenge at 250 kPa (2048², dx =
// 24 ρ): within 4 points (80 neighbours) the queue took 24 s of a 59 s solve, 9 outer
// steps, 508 FFT pairs; with the nearest 8 it takes 1.9 s of 36 s, 10 outer steps, 517
// pairs, a_r 0.0295022 against 0.0295014 (3 points of 4.2 million) and the mean gap
// within 5e-7. Within 2 points: 10 outer steps, 8 s of queue. A larger move floor (1e-2,
// 1e-1 ρ) costs outer steps (1024²: 9 and 12 instead of 6).
constexpr int kRadius = 1;
constexpr int kSide = 2 * kRadius + 1;
constexpr double kMoveFloor = 1e-3;  // in ρ (w / peak tension): smaller predicted moves are not propagated

class Cascade {
 public:
  // `k_near`: K at the offsets (dx, dy) of the stencil, entry (dy + kRadius) (2 kRadius + 1)
  // + dx + kRadius (QuasiStaticAdhesion's constructor reads them off K's unit response).
  Cascade(const HalfSpace& hs, const std::vector<double>& k_near)
      : nx_(hs.grid().nx), ny_(hs.grid().ny), y0_(hs.grid().y0), rows_(hs.grid().rows()), periodic_(hs.periodic()) {
    // Each neighbour once. Where a periodic grid is narrower than the stencil (a line, ny =
    // 1; or 2 points across) offsets alias: the rows above and below a line are the line
    // itself, and (0, ±1) is the point itself. K's entry at the aliased offset already holds
    // every image, so a neighbour counted twice is pulled twice (a line's x-neighbours three
    // times), and the cascade predicts jumps that the next solve undoes: it cycled.
    std::vector<std::pair<int, int>> seen;
    for (int dy = -kRadius; dy <= kRadius; ++dy)
      for (int dx = -kRadius; dx <= kRadius; ++dx) {
        if (periodic_) {
          const std::pair<int, int> at{wrap(dx, nx_), wrap(dy, ny_)};
          if (at == std::pair<int, int>{0, 0} || std::find(seen.begin(), seen.end(), at) != seen.end()) continue;
          seen.push_back(at);
        } else if (dx == 0 && dy == 0) {
          continue;
        }
        stencil_.push_back({dx, dy, k_near[std::size_t((dy + kRadius) * kSide + dx + kRadius)]});
      }
  }

  // x: on exit the predicted gaps. Returns the number of points moved (on this rank).
  long run(const Field& g, const Field& t, const JumpPrediction& jp, Field& x, double move_floor) {
    const std::size_t n = g.size();
    pull_.resize(n);
    applied_.resize(n);
    eg_.resize(n);
    queued_.resize(n);
    // One pass per point, in parallel: decay(g), the first prediction, and the state of the
    // queue (pull 0, nothing passed on yet).
    Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        eg_[i] = jp.decay(g[i]);
        x[i] = jp.gap(g[i], eg_[i], t[i], 0.0);
        pull_[i] = 0.0;
        applied_[i] = g[i];
        queued_[i] = x[i] < g[i] - move_floor;
      }
    }, 8 * n);
    queue_.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (queued_[i]) queue_.push_back(i);
    long moved = 0;
    const int nx = nx_, ny = ny_, y0 = y0_, rows = rows_;
    // The pull c on local point m: its new prediction, queued if it moved far enough.
    auto pull = [&](std::size_t m, double c) {
      if (g[m] <= 0.0) return;  // in contact: held by the wall
      pull_[m] += c;
      const double xm = std::min(x[m], jp.gap(g[m], eg_[m], t[m], pull_[m]));
      if (xm < applied_[m] - move_floor && !queued_[m]) queue_.push_back(m), queued_[m] = 1;
      x[m] = xm;
    };
    for (std::size_t q = 0;;) {
      for (; q < queue_.size(); ++q) {
        const std::size_t i = queue_[q];
        queued_[i] = 0;
        const double d = x[i] - applied_[i];  // not yet passed on (< 0)
        applied_[i] = x[i];
        ++moved;
        const int iy = y0 + int(i / std::size_t(nx)), ix = int(i - std::size_t(iy - y0) * std::size_t(nx));
        for (const auto& s : stencil_) {
          int jx = ix + s.dx, jy = iy + s.dy;
          if (periodic_) {
            jx = wrap(jx, nx), jy = wrap(jy, ny);
          } else if (jx < 0 || jy < 0 || jx >= nx || jy >= ny) {
            continue;
          }
          if (jy >= y0 && jy < y0 + rows) {
            pull(std::size_t(jy - y0) * std::size_t(nx) + std::size_t(jx), s.k * d);
          } else {  // another rank's point: sent at the end of the round
            out_index_.push_back(std::int64_t(jy) * nx + jx);
            out_pull_.push_back(s.k * d);
          }
        }
      }
      if (ranks() == 1) break;
      // A round ends: every rank's pulls across slab boundaries, applied in rank order.
      const auto index = allgather(out_index_);
      const auto amount = allgather(out_pull_);
      out_index_.clear(), out_pull_.clear();
      bool sent = false;
      for (std::size_t r = 0; r < index.size(); ++r)
        for (std::size_t k = 0; k < index[r].size(); ++k) {
          sent = true;
          const int jy = int(index[r][k] / nx), jx = int(index[r][k] - std::int64_t(jy) * nx);
          if (jy >= y0 && jy < y0 + rows) pull(std::size_t(jy - y0) * std::size_t(nx) + std::size_t(jx), amount[r][k]);
        }
      if (!sent) break;  // the same answer on every rank: it saw the same lists
    }
    return moved;
  }

 private:
  struct Entry {
    int dx, dy;
    double k;
  };
  // j in [−kRadius, n + kRadius) to [0, n); one add where n > kRadius (no division).
  static int wrap(int j, int n) {
    if (n > kRadius) return j < 0 ? j + n : (j >= n ? j - n : j);
    return ((j % n) + n) % n;
  }
  int nx_, ny_, y0_, rows_;  // the whole grid, and this rank's rows [y0_, y0_ + rows_)
  bool periodic_;
  std::vector<Entry> stencil_;
  Field pull_, applied_, eg_;  // eg_: decay(g) of each point
  std::vector<unsigned char> queued_;
  std::vector<std::size_t> queue_;
  std::vector<std::int64_t> out_index_;  // pulls on other ranks' points (global index) ...
  std::vector<double> out_pull_;         // ... and their amounts
};

struct MaxReduction {
  double v = 0.0;
  void merge(const MaxReduction& o) { v = std::max(v, o.v); }
};

}  // namespace

QuasiStaticAdhesion::QuasiStaticAdhesion(HalfSpace& hs, const Field& heights, ExponentialAdhesion adhesion,
                                         Options o)
    : hs_(hs), h_(heights), adh_(adhesion), opt_(std::move(o)) {
  if (heights.size() != hs.grid().size())
    throw std::invalid_argument("QuasiStaticAdhesion: heights do not match the grid");
  if (!(opt_.tension_tolerance > 0.0)) throw std::invalid_argument("QuasiStaticAdhesion: tension_tolerance must be > 0");
  // The diagonal of K: the pressure at a point that holds a unit displacement there and
  // zero everywhere else (the same at every point of a translation-invariant grid); and
  // K's entries to the cascade's neighbours. Only these numbers are kept, not the response
  // (a field of the transform grid: 8.6 GB at 32768², issue 16).
  {
    const Field response = hs.unit_response();
    const int mx = hs.transform_nx(), my = hs.transform_ny();
    k_self_ = hs.transform_entry(response, 0, 0);
    k_near_.resize(std::size_t(kSide * kSide));
    for (int dy = -kRadius; dy <= kRadius; ++dy)
      for (int dx = -kRadius; dx <= kRadius; ++dx)
        k_near_[std::size_t((dy + kRadius) * kSide + dx + kRadius)] =
            hs.transform_entry(response, (dy + my) % my, (dx + mx) % mx);
  }
  if (!(k_self_ > 0.0)) throw std::logic_error("QuasiStaticAdhesion: the half-space's self-stiffness is not positive");
}

SolveResult QuasiStaticAdhesion::solve(const Target& target, ContactState& st, OuterPoint* from) {
  const SolveClock clock(hs_);
  SolveResult res;
  // A continued solve counts the outer steps of the process before it.
  double pairs_before = 0.0, seconds_before = 0.0, fft_s_before = 0.0;
  auto finish = [&](bool converged, std::string msg) {
    clock.finish(res, converged, std::move(msg));
    res.fft_pairs += pairs_before, res.wall_s += seconds_before, res.fft_s += fft_s_before;
    return res;
  };
  const std::size_t n = h_.size();
  const JumpPrediction jump(k_self_, adh_);
  if (target.control == Control::MeanPressure && !(target.value > 0.0))
    return finish(false, "quasi-static loading from out of contact reaches no contact at a mean pressure <= 0 (the "
                         "surfaces stay apart); tensile loads are on an unloading path: use [solver] kind = "
                         "\"adhesive_cg\"");

  // Polonsky-Keer on the shifted heights h − G t (hp), warm-started from its own state.
  // The tension and Polonsky-Keer's state live in `at`, where the solve stands between
  // outer steps (what on_outer is shown, without copies).
  OuterPoint at;
  if (from) {
    if (from->tension.size() != n || from->inner.pressure.size() != n || from->outer < 1)
      throw std::invalid_argument("QuasiStaticAdhesion: the solve to continue does not fit this grid");
    at = std::move(*from);
    res.iterations = at.so_far.iterations;
    res.diagnostics = at.so_far.diagnostics;
    pairs_before = at.so_far.fft_pairs, seconds_before = at.so_far.wall_s, fft_s_before = at.so_far.fft_s;
  } else {
    at.tension.assign(n, 0.0);
  }
  Field& t = at.tension;
  ContactState& inner = at.inner;
  // The solve's own fields (host memory, issue 16): the shifted heights, G t, the
  // predicted gaps; the next tension is computed twice from them instead of held.
  Field hp = h_, gt(n, 0.0), predicted(n, 0.0);
  Cascade cascade(hs_, k_near_);
  PolonskyKeer::Options po;
  po.tolerance = opt_.tolerance;
  po.max_iterations = opt_.max_iterations;
  po.recompute_every = opt_.recompute_every;
  po.precondition = opt_.precondition;
  po.backend = opt_.backend;
  po.keep_work = true;  // one solve an outer step: the same arrays each time
  int outer = from ? at.outer : 0;
  if (opt_.progress) {
    po.progress = [&](const ProgressPoint& p) { opt_.progress({res.iterations + p.iteration, p.residual, outer + 1, true}); };
    po.progress_every = opt_.progress_every;
  }
  // Each outer solve starts from the exact u of its pressure (Polonsky-Keer's first step),
  // so only the last one needs Polonsky-Keer's confirmation on an exact u: the others skip
  // it, and the converged tension is confirmed by one more solve at the same t (a "confirm"
  // step, usually 0 iterations: one FFT pair and a half instead of one per outer step).
  po.confirm = false;
  PolonskyKeer pk(hs_, hp, po);  // its residual scale is that of h (hp == h here)
  const bool warm = !from && st.gap.size() == n && st.pressure.size() == n;
  if (warm) {
    // Start from the previous (smaller) load's state: its tension, and its repulsive
    // pressure p + t as Polonsky-Keer's warm start. The state's fields move into the
    // solve's (and back at the end): the solve holds no second copy of them.
    const double* g = st.gap.data();
    Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) t[i] = jump.tension(g[i]);
    });
    double* sp = st.pressure.data();
    Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) sp[i] = std::max(0.0, sp[i] + t[i]);
    });
    inner.pressure = std::move(st.pressure);
    inner.displacement = std::move(st.displacement);
    inner.gap = std::move(st.gap);  // its buffer: Polonsky-Keer overwrites it
    inner.penetration = st.penetration;
  } else if (from) {
    // The state is not read: its fields would only sit beside the solve's.
    st.pressure = Field(), st.displacement = Field(), st.gap = Field();
  }

  double residual = 1.0;
  bool pk_ok = true;
  std::string pk_message;
  bool confirming = false;  // this solve repeats the last one (same t) on the exact u
  for (;; ++outer) {
    if (!confirming && (outer > 0 || warm)) {
      hs_.displacement(t, gt);
      Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) hp[i] = h_[i] - gt[i];
      });
    }
    Target tk = target;
    if (target.control == Control::MeanPressure) tk.value = target.value + Grid::mean(t);
    pk.set_confirm(confirming);
    const SolveResult r = pk.solve(tk, inner);
    res.iterations += r.iterations;
    res.diagnostics += r.diagnostics;
    if (!r.converged) {
      pk_ok = false;
      pk_message = "outer step " + std::to_string(outer) + ": " + r.message;
      break;
    }
    // The next tension (with jump prediction and cascade) and how much it changes.
    const double* g = inner.gap.data();
    if (opt_.predict_jumps) {
      cascade.run(inner.gap, t, jump, predicted, opt_.cascade ? kMoveFloor * adh_.range() : HUGE_VAL);
    } else {
      predicted = inner.gap;
    }
    const double* x = predicted.data();
    double* tp = t.data();
    // The next tension of point i (computed here for the residual, and again below where
    // it replaces t: one exponential more per point instead of a field).
    auto next_tension = [&](std::size_t i) { return g[i] <= 0.0 ? jump.w_rho : jump.tension(x[i]); };
    residual = Grid::parallel_reduce<MaxReduction>(n, [&](std::size_t b, std::size_t e, MaxReduction& acc) {
                 double m = 0.0;
                 for (std::size_t i = b; i < e; ++i) m = std::max(m, std::abs(next_tension(i) - tp[i]));
                 acc.v = std::max(acc.v, m);
               }).v / adh_.peak_tension();
    if (opt_.progress) opt_.progress({res.iterations, residual, outer + 1});
    if (!std::isfinite(residual)) {
      pk_ok = false;
      pk_message = "the adhesive tension became non-finite at outer step " + std::to_string(outer);
      break;
    }
    if (residual <= opt_.tension_tolerance) {
      if (confirming) break;
      confirming = true;  // not counted against max_outer
      continue;
    }
    if (outer + 1 >= opt_.max_outer) break;
    confirming = false;
    // Warm start of the next solve: keep the total pressure p − t of the points in contact,
    // i.e. raise their repulsion by the change of their tension. The first solve after the
    // hard-wall one then starts from the hard-wall state itself instead of a rescaled
    // pressure (measured at 512²: 119 -> 51 iterations for that solve). The same holds
    // for the points the jump prediction brings into contact (predicted gap 0): they start
    // with the repulsion t_next − t, which keeps their total pressure −t, instead of 0 (a
    // point that joins from overlap takes a projected step, and Polonsky-Keer finds its
    // pressure over many). Only the start changes: each solve is the same convex problem.
    // Measured on the challenge at 250 kPa (2048², dx = 24 ρ): 222 -> 164 iterations, 517
    // -> 378 FFT pairs, the same 10 outer steps, a_r within one point of 4.2 million (the
    // answer at tolerance 1e-7), mean gap within 3e-8 relative; s = 32 on 1024² (dx =
    // 1.6 ρ): 879 -> 769 iterations, 2032 -> 1714 pairs, the same a_r.
    double* pr = inner.pressure.data();
    Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const double tn = next_tension(i);
        if (pr[i] > 0.0 || x[i] <= 0.0) pr[i] = std::max(0.0, pr[i] + tn - tp[i]);
        tp[i] = tn;
      }
    });
    if (opt_.on_outer) {
      at.outer = outer + 1;
      at.so_far.iterations = res.iterations;
      at.so_far.diagnostics = res.diagnostics;
      at.so_far.fft_pairs = pairs_before + clock.pairs();
      at.so_far.wall_s = seconds_before + clock.seconds();
      at.so_far.fft_s = fft_s_before + clock.fft_seconds();
      opt_.on_outer(at);
    }
  }
  res.diagnostics.outer_iterations += outer + 1;
  res.residual = residual;

  // The solved state: total pressure p − t, displacement G (p − t), the gap of the solve.
  // (t and gt are those of the last Polonsky-Keer solve, so the fields are consistent.)
  if (!inner.empty()) {
    st.pressure = std::move(inner.pressure);
    st.displacement = std::move(inner.displacement);
    double* sp = st.pressure.data();
    double* su = st.displacement.data();
    Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        sp[i] -= t[i];
        su[i] -= gt[i];
      }
    });
    st.gap = std::move(inner.gap);
    st.penetration = inner.penetration;
    st.mean_pressure = Grid::mean(st.pressure);
    const double* g = st.gap.data();
    const double adhesion = Grid::parallel_reduce<SumReduction>(n, [&](std::size_t b, std::size_t e, SumReduction& acc) {
                              double s = 0.0;
                              for (std::size_t i = b; i < e; ++i) s += adh_.evaluate(g[i]).energy;
                              acc.v += s;
                            }).v;
    res.energy = hs_.energy(st.pressure, st.displacement) + adhesion * hs_.grid().cell_area();
  }
  if (!pk_ok) return finish(false, pk_message);
  if (residual > opt_.tension_tolerance) {
    std::ostringstream s;
    s << "quasi-static adhesion stopped after " << outer + 1 << " outer steps at tension change " << residual
      << " > tension_tolerance " << opt_.tension_tolerance;
    return finish(false, s.str());
  }
  return finish(true, "");
}

}  // namespace cmc
