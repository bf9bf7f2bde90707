// The per-point parts of the quasi-static solver (QuasiStaticAdhesion.hpp), written once for
// the CPU and the GPU (grid/Backend.hpp, CMC_HD): the jump prediction of one point, the
// cascade's stencil, and the parallel form of the cascade (rounds), which the GPU runs
// and the CPU can run (Options::cascade_rounds) to test it.
#pragma once

#include "cmc/contact/Interaction.hpp"
#include "cmc/contact/Reductions.hpp"
#include "cmc/grid/Backend.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

namespace cmc::qs {

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
  double k = 0.0, w_rho = 0.0, cutoff = 0.0, x_peak = 0.0, a_peak = 0.0;
  double g1 = 0.0, kappa = 0.0;                    // the head: A(x) = w_rho − kappa x for x < g1 (g1 = 0: none)
  double tail_a = 0.0, inv_ell = 0.0, tail_slope = 0.0;  // the tail: A(x) = tail_a decay(x), −A'(x) = tail_slope decay(x)

  JumpPrediction() = default;
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
  CMC_HD bool in_head(double x) const { return g1 > 0.0 && x < g1; }
  // exp(−(x − g1)/ℓ) in the tail, 0 beyond the cutoff, 1 in the head (unused there): what
  // the cascade keeps per point, so that a tension and its slope cost one exponential.
  CMC_HD double decay(double x) const {
    if (x >= cutoff) return 0.0;
    return in_head(x) ? 1.0 : ::exp(-(x - g1) * inv_ell);
  }
  CMC_HD double tension(double x, double e) const { return in_head(x) ? w_rho - kappa * x : tail_a * e; }
  CMC_HD double tension(double x) const { return tension(x, decay(x)); }
  CMC_HD double slope(double x, double e) const {  // −A'(x)
    if (x >= cutoff) return 0.0;
    return in_head(x) ? kappa : tail_slope * e;
  }

  // The predicted gap of a point at gap g under tension t, with the extra pull c (the
  // change of the elastic force from neighbours that moved; c >= 0 pulls in): the largest
  // x <= g with k (g − x) = A(x) − t + c, or 0 (into contact) if there is none. Returns g
  // itself when the point is not pulled further in. `eg` is decay(g), which the caller
  // keeps per point (the cascade asks again for the same g with a larger c).
  CMC_HD double gap(double g, double eg, double t, double c) const {
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


// The cascade's stencil: the 8 nearest points (see CpuBackend.cpp, "Jumps that
// trigger jumps"), each neighbour once, with K's entry to it.
constexpr int kRadius = 1;
constexpr int kSide = 2 * kRadius + 1;
constexpr double kMoveFloor = 1e-3;  // in ρ (w / peak tension): the largest move floor (move_floor)
constexpr double kMonostableMoveFloor = 1e-4;  // in ρ: the largest where no point is bistable
constexpr double kMinMoveFloor = 1e-6;  // in ρ: the smallest
constexpr double kNoiseMargin = 100.0;  // the floor over the inner solves' gap error

// The cascade's move floor: a predicted move smaller than this is not passed on. At most
// kMoveFloor ρ, a move that changes the point's own tension by at most the default tension
// tolerance (1e-3 of the peak: the slope of the law is at most w/ρ²). Below that, a point
// that creeps towards its fold with neighbours that would follow it (a collective
// instability the one-point prediction misses) moves by about the floor an outer step and
// needs many outer steps, each a Polonsky-Keer solve, to reach it; passing smaller moves
// on finds such a jump inside the step, by the cascade's Gauss-Seidel sweeps. But a move
// at the inner solves' own error is noise, and passing noise on makes creep of its own.
// So: kNoiseMargin times that error, tolerance × h_scale (Polonsky-Keer's residual is the
// rms gap error on the contact set over the rms height h_scale), between kMinMoveFloor ρ
// and kMoveFloor ρ. At the challenge cases' inner tolerance 1e-6 (h_scale 750 nm, ρ =
// 2.1 to 6.2 nm at mu_T = 3 to 1) that is kMoveFloor, the fixed floor it replaced. Measured
// (2 threads; mu_T = 1 at 250 kPa, inner tolerance 1e-8, this rule's 1.2e-4 ρ
// against 1e-3 ρ): 2048² 21 outer steps against 50, 4096² 39 against 74 (648 inner
// iterations against 1084, 220 s against 428 s), a_r 0.0320333 against 0.0320330, mean gap
// within 2e-7. The floor at the noise itself (1e-4 ρ at inner tolerance 1e-6, mu_T = 1,
// 2048²) crept: 52 outer steps against 41 at 1e-3 ρ. Smaller floors cost cascade time
// (2048², inner tolerance 1e-8: 1e-6 ρ 18 outer steps and 45 s, against 30.5 s at 1e-4 ρ).
// Where no point is bistable (`monostable`: the law's largest curvature below the
// self-stiffness, as the shape coarse-graining makes it), the largest floor is
// kMonostableMoveFloor ρ: there every move is continuous, a cluster of points near a
// collective fold creeps by about the floor an outer step unless the cascade passes its
// moves on, and a move passed on from noise is undone by the next solve instead of locking
// in a jump. Measured (1 thread, inner tolerance 1e-6, the floor at 1e-3 ρ against 1e-4 ρ):
// the challenge with `shape` at 2048², 153 outer steps and 429 iterations against 20 and 189,
// the same a_r, mean gap within 1.5e-7; at 1024², 22 and 137 against 14 and 117; the s = 128
// member (plain law, dx = 0.8 ρ) at 512², 136 and 833 against 78 and 617, a_r 2.3e-5 higher,
// towards the state of a tighter tension tolerance. At 1e-5 ρ a point of 4.2 million
// differed. That cap can fall below the inner solves' error (`shape` at 4096², inner
// tolerance 1e-6: 0.85 of it); inner_tolerance() below then tightens the inner solves.
// Where points are bistable, 1e-4 ρ at inner tolerance 1e-6 passed noise on to
// jumps: at μ_T = 1 on 1024², 5 points of a million more in contact and more outer steps
// (docs/developer/decisions.md).
inline double move_floor(double range, double inner_tolerance, double h_scale, bool monostable) {
  const double f = kNoiseMargin * inner_tolerance * h_scale;
  const double largest = monostable ? kMonostableMoveFloor : kMoveFloor;
  return std::min(largest * range, std::max(kMinMoveFloor * range, f));
}

constexpr double kInnerErrorTrigger = 1.0;     // a monostable floor under this many gap errors...
constexpr double kFloorOverInnerError = 10.0;  // ...tightens the inner solves to this many

// The tolerance the inner solves run at: the user's, except where the move floor of a
// monostable law (capped at kMonostableMoveFloor ρ) is under kInnerErrorTrigger times the
// inner solves' gap error (tolerance × h_scale); there the tolerance that puts the error at
// the floor over kFloorOverInnerError. The floor stays what the user's tolerance gives (the
// cap), and the user's tolerance stays the one the run reports. Why: with the floor under
// the error the cascade passes that error on, clusters near a collective fold jump below
// their equilibrium and open again outer step after outer step. Measured (`shape`, inner
// tolerance 1e-6, 1 thread, cold): 4096² (floor 0.85 of the error) 812 iterations and not
// converged before, 475 and 43 outer steps with this (plain: 240), a_r as at 1e-8 and the
// mean gap within 6e-9. The trigger at 1: at 2048² (1.2 of the error) the user's
// tolerance converges in 200 iterations, tightened in 253 (docs/developer/decisions.md).
inline double inner_tolerance(double range, double tolerance, double h_scale, bool monostable) {
  if (!monostable || !(tolerance > 0.0) || !(h_scale > 0.0)) return tolerance;
  const double floor = move_floor(range, tolerance, h_scale, true);
  if (floor >= kInnerErrorTrigger * tolerance * h_scale) return tolerance;
  return floor / (kFloorOverInnerError * h_scale);
}

// j in [−kRadius, n + kRadius) to [0, n); one add where n > kRadius (no division).
CMC_HD inline int wrap(int j, int n) {
  if (n > kRadius) return j < 0 ? j + n : (j >= n ? j - n : j);
  return ((j % n) + n) % n;
}

struct Stencil {
  int count = 0;
  int dx[kSide * kSide - 1] = {}, dy[kSide * kSide - 1] = {};
  double k[kSide * kSide - 1] = {};
};

// `k_near`: K at the offsets (dx, dy), entry (dy + kRadius) kSide + dx + kRadius. Each
// neighbour once. Where a periodic grid is narrower than the stencil (a line, ny = 1; or 2
// points across) offsets alias: the rows above and below a line are the line itself, and
// (0, ±1) is the point itself. K's entry at the aliased offset already holds every image,
// so a neighbour counted twice is pulled twice (a line's x-neighbours three times), and
// the cascade predicts jumps that the next solve undoes: it cycled.
inline Stencil make_stencil(int nx, int ny, bool periodic, const std::vector<double>& k_near) {
  Stencil s;
  std::vector<std::pair<int, int>> seen;
  for (int dy = -kRadius; dy <= kRadius; ++dy)
    for (int dx = -kRadius; dx <= kRadius; ++dx) {
      if (periodic) {
        const std::pair<int, int> at{wrap(dx, nx), wrap(dy, ny)};
        if (at == std::pair<int, int>{0, 0} || std::find(seen.begin(), seen.end(), at) != seen.end()) continue;
        seen.push_back(at);
      } else if (dx == 0 && dy == 0) {
        continue;
      }
      s.dx[s.count] = dx, s.dy[s.count] = dy;
      s.k[s.count] = k_near[std::size_t((dy + kRadius) * kSide + dx + kRadius)];
      ++s.count;
    }
  return s;
}

// The cascade in rounds (Jacobi instead of the CPU's Gauss-Seidel queue; for a periodic
// grid held by one process). Every point with a gap keeps x (its predicted gap) and a (the
// gap its neighbours are told of: a move is passed on once it exceeds the floor, as in
// the queue). A round: every point takes the a of its neighbours as the last round left
// them, computes its pull c = Σ K_mj (a_j − g_j) (K_mj < 0, moves a_j − g_j ≤ 0: c ≥ 0)
// and its new prediction x = min(x, gap(g, t, c)); the round's a follows from its x. The
// rounds end when one passes nothing on. Why it stays above the maximal equilibrium, as
// the queue does: a point's prediction is its own largest equilibrium with its
// neighbours held where the last round put them, which is above where they end (by
// induction over the rounds), and the map is order-preserving. The queue and the rounds
// pass moves on in another order, so they may stop a move below the floor apart; on the
// challenge at 512² and 2048² they reach the same outer steps, iterations and contact set
// (mean gaps within 1.2e-9 and 3.6e-10 relative); on the s = 32 member at 1.6 ρ
// (1024²) 92 outer steps against 90, the same a_r, the mean gap within 1e-8. Rounds there:
// 40 to 330 an outer step (a move spreads by one stencil step a round); the solve took
// 29.7 s on 2 CPU threads with the frontier below (84.5 s before the interior's flags were
// read as one 3 x 3 block; the queue: 17.5 s).
//
// A round is two passes, each over every point but each doing its work only where the
// last one changed something (the frontier): each point keeps two flags, its own. The
// first pass (Propagate) tells the neighbours of the points whose prediction changed in
// the last round: a ← x where x < a − floor, flag `told` where a changed, and counts those.
// The second (Pull) recomputes the prediction of the points next to a told one, from the
// neighbours' a; flag `moved` where x fell. Elsewhere a point's neighbours are where they
// were when its prediction was last made, so it would come out the same: skipping it
// changes no bit. A pass reads and writes only its own point's flags (and the other's
// flags and its neighbours' a): no two threads write one place, no atomics.
struct RoundStart {  // round 0: the prediction without pull; nothing passed on yet
  const double *g, *t;
  double *x, *a;
  std::uint8_t* moved;
  JumpPrediction jp;
  CMC_HD void operator()(std::size_t i) const {
    x[i] = jp.gap(g[i], jp.decay(g[i]), t[i], 0.0);
    a[i] = g[i];
    moved[i] = 1;
  }
};
struct Propagate {  // a ← x where x fell below a by more than the floor; counts the points told
  const double* x;
  double* a;
  const std::uint8_t* moved;
  std::uint8_t* told;
  double floor;
  CMC_HD void operator()(std::size_t i, Count& c) const {
    std::uint8_t f = 0;
    if (moved[i] && x[i] < a[i] - floor) {
      a[i] = x[i];
      f = 1;
      c.n += 1.0;
    }
    told[i] = f;
  }
};
struct Pull {  // x = min(x, gap(g, t, pull)) where a neighbour was told, pull = Σ K_mj (a_j − g_j)
  const double *g, *t, *a;
  double* x;
  const std::uint8_t* told;
  std::uint8_t* moved;
  JumpPrediction jp;
  Stencil st;
  int nx, ny;
  CMC_HD void operator()(std::size_t i) const {
    // The flags first (a byte each, mostly cached): most points stop there. Away from the
    // edges the 3 x 3 block around the point is read without wrapping: a superset of the
    // stencil (the point itself), which only adds work, never changes a bit (a point whose
    // neighbours were not told recomputes the prediction it already has).
    std::uint8_t m = 0;
    const int iy = i < 0xffffffffu ? int(unsigned(i) / unsigned(nx)) : int(i / std::size_t(nx));
    const int ix = int(i - std::size_t(iy) * std::size_t(nx));
    bool any = false;
    if (ix > 0 && ix + 1 < nx && iy > 0 && iy + 1 < ny) {
      const std::uint8_t *up = told + (i - std::size_t(nx) - 1), *mid = told + (i - 1), *down = told + (i + std::size_t(nx) - 1);
      any = (up[0] | up[1] | up[2] | mid[0] | mid[1] | mid[2] | down[0] | down[1] | down[2]) != 0;
    } else {
      for (int s = 0; s < st.count; ++s)
        any = any || told[std::size_t(wrap(iy + st.dy[s], ny)) * std::size_t(nx) + std::size_t(wrap(ix + st.dx[s], nx))];
    }
    if (any && g[i] > 0.0) {
      std::size_t j[kSide * kSide - 1];
      for (int s = 0; s < st.count; ++s)
        j[s] = std::size_t(wrap(iy + st.dy[s], ny)) * std::size_t(nx) + std::size_t(wrap(ix + st.dx[s], nx));
      double pull = 0.0;
      for (int s = 0; s < st.count; ++s) pull += st.k[s] * (a[j[s]] - g[j[s]]);
      if (pull > 0.0) {
        const double xn = jp.gap(g[i], jp.decay(g[i]), t[i], pull);
        if (xn < x[i]) x[i] = xn, m = 1;
      }
    }
    moved[i] = m;
  }
};

// Eight points at a time (a word of each flag array, one 8-byte load instead of eight byte
// loads). Most points of a round are far from its frontier, where each pass only reads a
// flag and writes one: on a GPU such byte passes are bound by the loads in flight, not by
// the bytes (an H200 at 8192²: 0.92 ms a round point by point, two passes over 67 million
// points, where the bytes alone take about 0.1 ms). A word whose flags are all clear is
// done with a word store; any other goes point by point through the same bodies, so the
// result is the same, bit for bit. For rows of whole words (nx a multiple of 8), the flag
// arrays 8-byte aligned (cascade_rounds checks both).
CMC_HD inline std::uint64_t load_word(const std::uint8_t* p) {
#ifdef __CUDA_ARCH__
  return *reinterpret_cast<const std::uint64_t*>(p);  // aligned: cascade_rounds checks
#else
  std::uint64_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
#endif
}
CMC_HD inline void clear_word(std::uint8_t* p) {
#ifdef __CUDA_ARCH__
  *reinterpret_cast<std::uint64_t*>(p) = 0;
#else
  std::memset(p, 0, 8);
#endif
}
struct PropagateWords {  // word w: points 8w to 8w + 7
  Propagate one;
  CMC_HD void operator()(std::size_t w, Count& c) const {
    const std::size_t i0 = 8 * w;
    if (load_word(one.moved + i0) == 0) return clear_word(one.told + i0);
    for (std::size_t i = i0; i < i0 + 8; ++i) one(i, c);
  }
};
struct PullWords {  // word w: points 8w to 8w + 7 of one row
  Pull one;
  CMC_HD void operator()(std::size_t w) const {
    // The told flags of the 3 x 10 block around the word's points (wrapped): a superset of
    // each point's stencil. All clear: no point moves.
    const std::size_t i0 = 8 * w, nx = std::size_t(one.nx);
    const int iy = int(i0 / nx), ix0 = int(i0 - std::size_t(iy) * nx);
    const int left = wrap(ix0 - 1, one.nx), right = wrap(ix0 + 8, one.nx);
    std::uint64_t any = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      const std::uint8_t* row = one.told + std::size_t(wrap(iy + dy, one.ny)) * nx;
      any |= load_word(row + ix0) | row[left] | row[right];
    }
    if (any == 0) return clear_word(one.moved + i0);
    for (std::size_t i = i0; i < i0 + 8; ++i) one(i);
  }
};

// Runs the rounds over a backend b (b.all, b.reduce<Acc>) on the backend's buffers x, a
// (n doubles) and moved, told (n bytes); on return x holds the predicted gaps. Returns the
// number of rounds that moved something. `words`: eight points at a time where the grid
// and the buffers allow it (above); false: point by point (the tests compare the two).
template <class B>
long cascade_rounds(B& b, std::size_t n, const double* g, const double* t, const JumpPrediction& jp, const Stencil& st,
                    int nx, int ny, double floor, double* x, double* a, std::uint8_t* moved, std::uint8_t* told,
                    bool words = true) {
  const auto aligned = [](const std::uint8_t* p) { return reinterpret_cast<std::uintptr_t>(p) % 8 == 0; };
  words = words && nx % 8 == 0 && ny >= 3 && aligned(moved) && aligned(told);
  const Propagate propagate{x, a, moved, told, floor};
  const Pull pull{g, t, a, x, told, moved, jp, st, nx, ny};
  b.all(n, RoundStart{g, t, x, a, moved, jp});
  for (long rounds = 0;; ++rounds) {
    const Count c = words ? b.template reduce<Count>(n / 8, PropagateWords{propagate})
                          : b.template reduce<Count>(n, propagate);
    if (c.n == 0.0) return rounds;
    if (words) b.all(n / 8, PullWords{pull});
    else b.all(n, pull);
  }
}

}  // namespace cmc::qs
