// The quasi-static solver's outer iteration on the CPU: its backend (qs::Contract.hpp) with
// host fields, any boundary and any number of processes, the cascade as a queue per slab of
// rows; Polonsky-Keer on its own backend (Options::backend: the CPU, or the GPU with the
// outer step here).
#include "cmc/contact/quasi_static/Iteration.hpp"
#include "cmc/grid/Ranks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

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
// (kRadius, kMoveFloor and the stencil: Parts.hpp.)
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
    in_ = {g.data(), t.data(), &jp, x.data(), move_floor};
    first_predictions(g.size());
    for (Slab& sl : slabs_) sl.queue.clear(), sl.out_index.clear(), sl.out_pull.clear(), sl.moved = 0;
    const std::size_t n = g.size(), unx = std::size_t(nx_);
    Grid::parallel_tasks(slabs_.size(), [&](std::size_t s) {
      Slab& sl = slabs_[s];
      for (std::size_t i = std::size_t(sl.r0) * unx; i < std::size_t(sl.r1) * unx; ++i)
        if (queued_[i]) sl.queue.push_back(i);
    }, n);
    do {
      Grid::parallel_tasks(slabs_.size(), [&](std::size_t s) { drain(slabs_[s]); }, n);
    } while (exchange());
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
  // The run in progress: the gaps, the tension, the prediction, the predicted gaps x, the
  // move floor.
  struct Inputs {
    const double *g = nullptr, *t = nullptr;
    const qs::JumpPrediction* jp = nullptr;
    double* x = nullptr;
    double floor = 0.0;
  };
  // One pass per point, in parallel: decay(g), the first prediction, and the state of the
  // queue (pull 0, nothing passed on yet).
  void first_predictions(std::size_t n) {
    pull_.resize(n);
    applied_.resize(n);
    eg_.resize(n);
    queued_.resize(n);
    const Inputs in = in_;
    Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        eg_[i] = in.jp->decay(in.g[i]);
        in.x[i] = in.jp->gap(in.g[i], eg_[i], in.t[i], 0.0);
        pull_[i] = 0.0;
        applied_[i] = in.g[i];
        queued_[i] = in.x[i] < in.g[i] - in.floor;
      }
    }, 8 * n);
  }
  // The pull c on local point m, a point of slab sl: its new prediction, queued if it moved
  // far enough.
  void pull(std::size_t m, double c, Slab& sl) {
    const Inputs& in = in_;
    if (in.g[m] <= 0.0) return;  // in contact: held by the wall
    pull_[m] += c;
    const double xm = std::min(in.x[m], in.jp->gap(in.g[m], eg_[m], in.t[m], pull_[m]));
    if (xm < applied_[m] - in.floor && !queued_[m]) sl.queue.push_back(m), queued_[m] = 1;
    in.x[m] = xm;
  }
  // A slab's queue, to its end: pulls on its own points applied, the others sent.
  void drain(Slab& sl) {
    const std::size_t unx = std::size_t(nx_);
    double* x = in_.x;
    for (std::size_t q = 0; q < sl.queue.size(); ++q) {
      const std::size_t i = sl.queue[q];
      queued_[i] = 0;
      const double d = x[i] - applied_[i];  // not yet passed on (< 0)
      applied_[i] = x[i];
      ++sl.moved;
      const int iy = y0_ + int(i / unx), ix = int(i - std::size_t(iy - y0_) * unx);
      for (int s = 0; s < stencil_.count; ++s) {
        int jx = ix + stencil_.dx[s], jy = iy + stencil_.dy[s];
        if (periodic_) {
          jx = wrap(jx, nx_), jy = wrap(jy, ny_);
        } else if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) {
          continue;
        }
        if (jy - y0_ >= sl.r0 && jy - y0_ < sl.r1) {
          pull(std::size_t(jy - y0_) * unx + std::size_t(jx), stencil_.k[s] * d, sl);
        } else {  // another slab's point (or another rank's): sent at the end of the round
          sl.out_index.push_back(std::int64_t(jy) * nx_ + jx);
          sl.out_pull.push_back(stencil_.k[s] * d);
        }
      }
    }
    sl.queue.clear();
  }
  // A pull sent to point (global index) k: applied where this rank holds it.
  void receive(std::int64_t k, double c) {
    const int jy = int(k / nx_), jx = int(k - std::int64_t(jy) * nx_);
    if (jy < y0_ || jy >= y0_ + rows_) return;
    pull(std::size_t(jy - y0_) * std::size_t(nx_) + std::size_t(jx), c,
         slabs_[std::size_t(slab_of_row_[std::size_t(jy - y0_)])]);
  }
  // A round ends: every slab's pulls across its boundaries, in slab order (distributed:
  // every rank's, applied in rank order). Returns whether any was sent (the same answer on
  // every rank: it saw the same lists).
  bool exchange() {
    out_index_.clear(), out_pull_.clear();
    for (Slab& sl : slabs_) {
      out_index_.insert(out_index_.end(), sl.out_index.begin(), sl.out_index.end());
      out_pull_.insert(out_pull_.end(), sl.out_pull.begin(), sl.out_pull.end());
      sl.out_index.clear(), sl.out_pull.clear();
    }
    if (ranks() == 1) {
      for (std::size_t k = 0; k < out_index_.size(); ++k) receive(out_index_[k], out_pull_[k]);
      return !out_index_.empty();
    }
    const auto index = allgather(out_index_);
    const auto amount = allgather(out_pull_);
    bool sent = false;
    for (std::size_t r = 0; r < index.size(); ++r)
      for (std::size_t k = 0; k < index[r].size(); ++k) {
        sent = true;
        receive(index[r][k], amount[r][k]);
      }
    return sent;
  }
  int nx_, ny_, y0_, rows_;  // the whole grid, and this rank's rows [y0_, y0_ + rows_)
  bool periodic_;
  qs::Stencil stencil_;
  std::vector<Slab> slabs_;
  std::vector<int> slab_of_row_;
  Field pull_, applied_, eg_;  // eg_: decay(g) of each point
  std::vector<unsigned char> queued_;
  std::vector<std::int64_t> out_index_;  // a round's sent pulls, in slab order ...
  std::vector<double> out_pull_;         // ... and their amounts
  Inputs in_;
};


// The CPU backend of the outer iteration (Iteration.hpp): host fields, any boundary
// and any number of processes, the cascade as a queue (or, with Options::cascade_rounds on
// a periodic grid held by one process, in the GPU's rounds). Polonsky-Keer runs on its own
// backend (Options::backend: the CPU, or the GPU with the outer step here).
class HostSteps : public HostPasses {
 public:
  HostSteps(HalfSpace& hs, const Field& h, const std::vector<double>& k_near, const QuasiStaticAdhesion::Options& o)
      : n(h.size()), hs_(hs), h_(h), opt_(o), hp_(h), gt_(n, 0.0), predicted_(n, 0.0),
        cascade_(hs, k_near, o.cascade_slab_rows), inner_(o, o.backend),
        pk_(hs, hp_, inner_.options()) {  // the residual scale of Polonsky-Keer is that of h (hp == h here)
    if (o.cascade_rounds && (!hs.periodic() || hs.grid().split()))
      throw std::invalid_argument("QuasiStaticAdhesion: cascade_rounds needs a periodic grid held by one process");
  }
  const std::size_t n;

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
    inner_.at(outer, iterations_before);
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
  HalfSpace& hs_;
  const Field& h_;
  const QuasiStaticAdhesion::Options& opt_;
  OuterPoint* at_ = nullptr;
  Field hp_, gt_, predicted_;  // the shifted heights, G t, the predicted gaps
  Field round_a_;                           // the rounds' passed-on gaps (cascade_rounds only)
  std::vector<std::uint8_t> moved_, told_;  // and their flags
  const double* x_ = nullptr;
  Cascade cascade_;
  qs::InnerSolves inner_;
  PolonskyKeer pk_;
};

}  // namespace

SolveResult qs::solve_on_cpu(const Problem& p, const Target& target, ContactState& st, OuterPoint* from) {
  HostSteps b(p.hs, p.heights, p.k_near, p.options);
  return solve(b, p.hs, p.adhesion, p.options, JumpPrediction(p.self_stiffness, p.adhesion), p.move_floor, target, st,
               from);
}

}  // namespace cmc
