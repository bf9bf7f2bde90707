#include "cmc/contact/quasi_static/QuasiStaticAdhesion.hpp"

#include "cmc/contact/quasi_static/Iteration.hpp"
#include "cmc/grid/Ranks.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace cmc {

namespace {

// Jumps that trigger jumps, within one outer step: a point that closes its gap by Δ pulls
// its neighbour m with the extra force K_mi Δ (K_mi < 0 off the diagonal), which may make
// m jump in turn. The cascade follows this with every other gap held (nonlinear
// Gauss-Seidel on the points near contact), over the exact real-space stiffness within
// `kRadius` points; the far field of K is negative (−E*/(4π r³)), so leaving it out pulls
// less than the truth and keeps the prediction above the maximal equilibrium. The first
// prediction of every point (no pull yet) is a parallel per-point pass.
//
// The cascade then runs in slabs of rows (Options::cascade_slab_rows rows each, at most
// kMaxSlabs; a number that follows from the grid alone, not from the thread count), each from its own
// first-in-first-out queue that starts in index order, the slabs in parallel. A move that
// pulls a point of another slab (a neighbour across a slab boundary, across the periodic
// seam, or on another MPI rank's rows) is sent, not applied: when every slab's queue is
// empty, the pulls are gathered in slab order (and, distributed, on every rank in rank
// order), and each is applied to its point in that order, queueing the points it moves;
// this repeats until a round sends nothing. Gauss-Seidel in another order than one queue
// over the whole grid: the same kind of conservative prediction, so the same loading-branch
// state within the outer tolerance, and the same sequence on every run and thread count.
// A grid of fewer than twice cascade_slab_rows rows is one slab: the whole grid's queue.
// Measured (the challenge at 250 kPa, 2048², 2 threads): the single queue took 1.66 s of an
// 11.9 s solve, 2,330,156 moves in the first outer step.
//
// The stencil is the 8 nearest points. Measured on the challenge at 250 kPa (2048², dx =
// 24 ρ): within 4 points (80 neighbours) the queue took 24 s of a 59 s solve, 9 outer
// steps, 508 FFT pairs; with the nearest 8 it takes 1.9 s of 36 s, 10 outer steps, 517
// pairs, a_r 0.0295022 against 0.0295014 (3 points of 4.2 million) and the mean gap
// within 5e-7. Within 2 points: 10 outer steps, 8 s of queue. A larger move floor (1e-2,
// 1e-1 ρ) costs outer steps (1024²: 9 and 12 instead of 6).
// (kRadius, kMoveFloor and the stencil: QuasiStaticParts.hpp.)
using qs::kRadius;
using qs::kSide;
class Cascade {
 public:
  static constexpr int kMaxSlabs = 64;
  // `k_near`: K at the offsets (dx, dy) of the stencil, entry (dy + kRadius) (2 kRadius + 1)
  // + dx + kRadius (QuasiStaticAdhesion's constructor reads them off K's unit response).
  // `slab_rows`: Options::cascade_slab_rows.
  Cascade(const HalfSpace& hs, const std::vector<double>& k_near, int slab_rows)
      : nx_(hs.grid().nx), ny_(hs.grid().ny), y0_(hs.grid().y0), rows_(hs.grid().rows()), periodic_(hs.periodic()),
        stencil_(qs::make_stencil(nx_, ny_, periodic_, k_near)) {
    const int count = std::clamp(rows_ / std::max(1, slab_rows), 1, kMaxSlabs);
    slabs_.resize(std::size_t(count));
    slab_of_row_.resize(std::size_t(std::max(rows_, 0)));
    for (int s = 0; s < count; ++s) {
      slabs_[std::size_t(s)].r0 = int(std::int64_t(rows_) * s / count);
      slabs_[std::size_t(s)].r1 = int(std::int64_t(rows_) * (s + 1) / count);
      for (int r = slabs_[std::size_t(s)].r0; r < slabs_[std::size_t(s)].r1; ++r) slab_of_row_[std::size_t(r)] = s;
    }
  }
  const qs::Stencil& stencil() const { return stencil_; }

  // x: on exit the predicted gaps. Returns the number of points moved (on this rank).
  long run(const Field& g, const Field& t, const qs::JumpPrediction& jp, Field& x, double move_floor) {
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
    const int nx = nx_, ny = ny_, y0 = y0_;
    const std::size_t unx = std::size_t(nx);
    // The pull c on local point m, a point of slab sl: its new prediction, queued if it moved
    // far enough.
    auto pull = [&](std::size_t m, double c, Slab& sl) {
      if (g[m] <= 0.0) return;  // in contact: held by the wall
      pull_[m] += c;
      const double xm = std::min(x[m], jp.gap(g[m], eg_[m], t[m], pull_[m]));
      if (xm < applied_[m] - move_floor && !queued_[m]) sl.queue.push_back(m), queued_[m] = 1;
      x[m] = xm;
    };
    // A slab's queue, to its end: pulls on its own points applied, the others sent.
    auto drain = [&](Slab& sl) {
      for (std::size_t q = 0; q < sl.queue.size(); ++q) {
        const std::size_t i = sl.queue[q];
        queued_[i] = 0;
        const double d = x[i] - applied_[i];  // not yet passed on (< 0)
        applied_[i] = x[i];
        ++sl.moved;
        const int iy = y0 + int(i / unx), ix = int(i - std::size_t(iy - y0) * unx);
        for (int s = 0; s < stencil_.count; ++s) {
          int jx = ix + stencil_.dx[s], jy = iy + stencil_.dy[s];
          if (periodic_) {
            jx = wrap(jx, nx), jy = wrap(jy, ny);
          } else if (jx < 0 || jy < 0 || jx >= nx || jy >= ny) {
            continue;
          }
          if (jy - y0 >= sl.r0 && jy - y0 < sl.r1) {
            pull(std::size_t(jy - y0) * unx + std::size_t(jx), stencil_.k[s] * d, sl);
          } else {  // another slab's point (or another rank's): sent at the end of the round
            sl.out_index.push_back(std::int64_t(jy) * nx + jx);
            sl.out_pull.push_back(stencil_.k[s] * d);
          }
        }
      }
      sl.queue.clear();
    };
    for (Slab& sl : slabs_) sl.queue.clear(), sl.out_index.clear(), sl.out_pull.clear(), sl.moved = 0;
    Grid::parallel_tasks(slabs_.size(), [&](std::size_t s) {
      Slab& sl = slabs_[s];
      for (std::size_t i = std::size_t(sl.r0) * unx; i < std::size_t(sl.r1) * unx; ++i)
        if (queued_[i]) sl.queue.push_back(i);
    }, n);
    // A pull sent to point (global index) k: applied where this rank holds it.
    auto receive = [&](std::int64_t k, double c) {
      const int jy = int(k / nx), jx = int(k - std::int64_t(jy) * nx);
      if (jy < y0 || jy >= y0 + rows_) return;
      pull(std::size_t(jy - y0) * unx + std::size_t(jx), c, slabs_[std::size_t(slab_of_row_[std::size_t(jy - y0)])]);
    };
    for (;;) {
      Grid::parallel_tasks(slabs_.size(), [&](std::size_t s) { drain(slabs_[s]); }, n);
      // A round ends: every slab's pulls across its boundaries, in slab order.
      out_index_.clear(), out_pull_.clear();
      for (Slab& sl : slabs_) {
        out_index_.insert(out_index_.end(), sl.out_index.begin(), sl.out_index.end());
        out_pull_.insert(out_pull_.end(), sl.out_pull.begin(), sl.out_pull.end());
        sl.out_index.clear(), sl.out_pull.clear();
      }
      if (ranks() == 1) {
        if (out_index_.empty()) break;
        for (std::size_t k = 0; k < out_index_.size(); ++k) receive(out_index_[k], out_pull_[k]);
        continue;
      }
      // Distributed: every rank's, applied in rank order.
      const auto index = allgather(out_index_);
      const auto amount = allgather(out_pull_);
      bool sent = false;
      for (std::size_t r = 0; r < index.size(); ++r)
        for (std::size_t k = 0; k < index[r].size(); ++k) {
          sent = true;
          receive(index[r][k], amount[r][k]);
        }
      if (!sent) break;  // the same answer on every rank: it saw the same lists
    }
    long moved = 0;
    for (const Slab& sl : slabs_) moved += sl.moved;
    return moved;
  }

 private:
  static int wrap(int j, int n) { return qs::wrap(j, n); }
  struct Slab {
    int r0 = 0, r1 = 0;  // local rows [r0, r1)
    std::vector<std::size_t> queue;
    std::vector<std::int64_t> out_index;  // pulls on other slabs' points (global index) ...
    std::vector<double> out_pull;         // ... and their amounts
    long moved = 0;
  };
  int nx_, ny_, y0_, rows_;  // the whole grid, and this rank's rows [y0_, y0_ + rows_)
  bool periodic_;
  qs::Stencil stencil_;
  std::vector<Slab> slabs_;
  std::vector<int> slab_of_row_;
  Field pull_, applied_, eg_;  // eg_: decay(g) of each point
  std::vector<unsigned char> queued_;
  std::vector<std::int64_t> out_index_;  // a round's sent pulls, in slab order ...
  std::vector<double> out_pull_;         // ... and their amounts
};

// The CPU backend of the outer iteration (QuasiStaticRun.hpp): host fields, any boundary
// and any number of processes, the cascade as a queue (or, with Options::cascade_rounds on
// a periodic grid held by one process, in the GPU's rounds). Polonsky-Keer runs on its own
// backend (Options::backend: the CPU, or the GPU with the outer step here).
class HostSteps {
 public:
  HostSteps(HalfSpace& hs, const Field& h, const std::vector<double>& k_near, const QuasiStaticAdhesion::Options& o)
      : n(h.size()), hs_(hs), h_(h), opt_(o), hp_(h), gt_(n, 0.0), predicted_(n, 0.0), cascade_(hs, k_near, o.cascade_slab_rows),
        pk_(hs, hp_, pk_options()) {  // the residual scale of Polonsky-Keer is that of h (hp == h here)
    if (o.cascade_rounds && (!hs.periodic() || hs.grid().split()))
      throw std::invalid_argument("QuasiStaticAdhesion: cascade_rounds needs a periodic grid held by one process");
  }
  const std::size_t n;

  template <class F>
  void all(std::size_t k, F f) {
    Grid::parallel_for(k, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) f(i);
    });
  }
  template <class Acc, class F>
  Acc reduce(std::size_t k, F f) {
    return Grid::parallel_reduce<Acc>(k, [&](std::size_t b, std::size_t e, Acc& acc) {
      for (std::size_t i = b; i < e; ++i) f(i, acc);
    });
  }

  // The tension and Polonsky-Keer's state live in the loop's OuterPoint (what on_outer is
  // shown, without copies).
  void bind(OuterPoint& at) { at_ = &at; }
  void start_cold() { at_->tension.assign(n, 0.0); }
  // The state's fields move into the solve's (and back at the end): no second copy.
  void start_warm(Field&& t, ContactState& st) {
    at_->tension = std::move(t);
    at_->inner.pressure = std::move(st.pressure);
    at_->inner.displacement = std::move(st.displacement);
    at_->inner.gap = std::move(st.gap);  // its buffer: Polonsky-Keer overwrites it
    at_->inner.penetration = st.penetration;
  }
  void start_from(OuterPoint& from) {
    at_->tension = std::move(from.tension);
    at_->inner = std::move(from.inner);
  }
  void shift_heights() {
    hs_.displacement(at_->tension, gt_);
    const double *h = h_.data(), *gt = gt_.data();
    double* hp = hp_.data();
    all(n, [=](std::size_t i) { hp[i] = h[i] - gt[i]; });
  }
  double mean_tension() const { return Grid::mean(at_->tension); }
  void stop_inner_at(double t) { pk_.set_stop_at(t); }
  SolveResult inner(const Target& tk, bool confirm, int outer, int iterations_before) {
    outer_ = outer, before_ = iterations_before;
    pk_.set_confirm(confirm);
    return pk_.solve(tk, at_->inner);
  }
  void predict(const qs::JumpPrediction& jump, double floor) {
    x_ = predicted_.data();
    if (!opt_.predict_jumps) {
      predicted_ = at_->inner.gap;
    } else if (opt_.cascade_rounds) {
      if (round_a_.size() != n) round_a_.assign(n, 0.0), moved_.assign(n, 0), told_.assign(n, 0);
      qs::cascade_rounds(*this, n, g(), t(), jump, cascade_.stencil(), hs_.grid().nx, hs_.grid().ny, floor,
                         predicted_.data(), round_a_.data(), moved_.data(), told_.data());
    } else {
      cascade_.run(at_->inner.gap, at_->tension, jump, predicted_, floor);
    }
  }
  double* t() { return at_->tension.data(); }
  const double* g() const { return at_->inner.gap.data(); }
  const double* x() const { return x_; }
  double* p() { return at_->inner.pressure.data(); }
  void outer_point(OuterPoint&) {}  // the fields are the solver's own, not copies
  bool solved() const { return !at_->inner.empty(); }
  // Total pressure p − t, displacement G (p − t): t and gt are those of the last
  // Polonsky-Keer solve, so the fields are consistent.
  void end(ContactState& st) {
    st.pressure = std::move(at_->inner.pressure);
    st.displacement = std::move(at_->inner.displacement);
    double* sp = st.pressure.data();
    double* su = st.displacement.data();
    const double *t = at_->tension.data(), *gt = gt_.data();
    all(n, [=](std::size_t i) {
      sp[i] -= t[i];
      su[i] -= gt[i];
    });
    st.gap = std::move(at_->inner.gap);
    st.penetration = at_->inner.penetration;
  }

 private:
  PolonskyKeer::Options pk_options() {
    const QuasiStaticAdhesion::Options& o = opt_;
    PolonskyKeer::Options po;
    if (o.progress) {
      po.progress = [this](const ProgressPoint& p) { opt_.progress({before_ + p.iteration, p.residual, outer_ + 1, true}); };
      po.progress_every = o.progress_every;
    }
    po.tolerance = o.tolerance;
    po.max_iterations = o.max_iterations;
    po.recompute_every = o.recompute_every;
    po.precondition = o.precondition;
    po.backend = o.backend;
    po.keep_work = true;  // one solve an outer step: the same arrays each time
    // Each outer solve starts from the exact u of its pressure (Polonsky-Keer's first step),
    // so only the last one needs Polonsky-Keer's confirmation on an exact u: the others skip
    // it, and the converged tension is confirmed by one more solve at the same t (a "confirm"
    // step, usually 0 iterations: one FFT pair and a half instead of one per outer step).
    po.confirm = false;
    return po;
  }
  HalfSpace& hs_;
  const Field& h_;
  const QuasiStaticAdhesion::Options& opt_;
  OuterPoint* at_ = nullptr;
  Field hp_, gt_, predicted_;  // the shifted heights, G t, the predicted gaps
  Field round_a_;                           // the rounds' passed-on gaps (cascade_rounds only)
  std::vector<std::uint8_t> moved_, told_;  // and their flags
  const double* x_ = nullptr;
  Cascade cascade_;
  PolonskyKeer pk_;
  int outer_ = 0, before_ = 0;
};

}  // namespace

QuasiStaticAdhesion::QuasiStaticAdhesion(HalfSpace& hs, const Field& heights, ExponentialAdhesion adhesion,
                                         Options o)
    : hs_(hs), h_(heights), adh_(adhesion), opt_(std::move(o)) {
  if (heights.size() != hs.grid().size())
    throw std::invalid_argument("QuasiStaticAdhesion: heights do not match the grid");
  if (!(opt_.tension_tolerance > 0.0)) throw std::invalid_argument("QuasiStaticAdhesion: tension_tolerance must be > 0");
  if (opt_.cascade_slab_rows < 1) throw std::invalid_argument("QuasiStaticAdhesion: cascade_slab_rows must be >= 1");
  // The diagonal of K: the pressure at a point that holds a unit displacement there and
  // zero everywhere else (the same at every point of a translation-invariant grid); and
  // K's entries to the cascade's neighbours. Only these numbers are kept, not the response
  // (a field of the transform grid: 8.6 GB at 32768², which a GPU run cannot spare).
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
  move_floor_ = qs::move_floor(adh_.range(), opt_.tolerance, PolonskyKeer::residual_scale(heights));
}

#ifndef CMC_CUDA
// A build without the CUDA backend: the case parser refuses backend = "cuda" before a solve.
SolveResult solve_on_device(HalfSpace&, const Field&, const ExponentialAdhesion&, const QuasiStaticAdhesion::Options&,
                            double, const std::vector<double>&, double, const Target&, ContactState&, OuterPoint*) {
  throw std::runtime_error("quasi-static adhesion: this build of cmc has no CUDA backend (configure with -DCMC_CUDA=ON)");
}
#endif

SolveResult QuasiStaticAdhesion::solve(const Target& target, ContactState& st, OuterPoint* from) {
  if (opt_.backend == Backend::Cuda && opt_.outer_on_device)
    return solve_on_device(hs_, h_, adh_, opt_, k_self_, k_near_, move_floor_, target, st, from);
  HostSteps b(hs_, h_, k_near_, opt_);
  return qs::solve(b, hs_, adh_, opt_, qs::JumpPrediction(k_self_, adh_), move_floor_, target, st, from);
}

}  // namespace cmc
