// The per-point parts of the quasi-static solver (QuasiStaticAdhesion.hpp), written once for
// the CPU and the GPU (grid/Backend.hpp, CMC_HD): the jump prediction of one point, the
// cascade's stencil, and the parallel form of the cascade (rounds), which the GPU runs
// and the CPU can run (Options::cascade_rounds) to test it.
#pragma once

#include "cmc/contact/Interaction.hpp"
#include "cmc/grid/Backend.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
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


// The cascade's stencil: the 8 nearest points (see QuasiStaticAdhesion.cpp, "Jumps that
// trigger jumps"), each neighbour once, with K's entry to it.
constexpr int kRadius = 1;
constexpr int kSide = 2 * kRadius + 1;
constexpr double kMoveFloor = 1e-3;  // in ρ (w / peak tension): smaller predicted moves are not propagated

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

struct Count {
  double n = 0.0;
  CMC_HD void merge(const Count& o) { n += o.n; }
};
struct Max {
  double v = 0.0;
  CMC_HD void merge(const Max& o) { v = v < o.v ? o.v : v; }  // std::max(v, o.v)
};

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
// (mean gaps within 1e-9 relative, measured 2026-11-26); on the s = 32 member at 1.6 ρ
// (1024²) 92 outer steps against 90, the same a_r, the mean gap within 1e-8. Cost: a pass
// over the grid a round, 40 to 330 rounds an outer step there (a move that spreads by one
// stencil step a round); a frontier (only tiles whose neighbourhood changed) would cut it.
struct RoundStart {  // round 0: the prediction without pull; nothing passed on yet
  const double *g, *t;
  double *x, *a;
  JumpPrediction jp;
  CMC_HD void operator()(std::size_t i) const {
    x[i] = jp.gap(g[i], jp.decay(g[i]), t[i], 0.0);
    a[i] = g[i];
  }
};
struct Round {  // one round from (x0, a0) to (x1, a1); counts the points that pass a move on
  const double *g, *t, *x0, *a0;
  double *x1, *a1;
  JumpPrediction jp;
  Stencil st;
  int nx, ny;
  double floor;
  CMC_HD double told(std::size_t j) const { return x0[j] < a0[j] - floor ? x0[j] : a0[j]; }
  CMC_HD void operator()(std::size_t i, Count& c) const {
    const double ai = told(i);
    if (ai != a0[i]) c.n += 1.0;
    a1[i] = ai;
    double xi = x0[i];
    if (g[i] > 0.0) {
      const int iy = int(i / std::size_t(nx)), ix = int(i - std::size_t(iy) * std::size_t(nx));
      double pull = 0.0;
      for (int s = 0; s < st.count; ++s) {
        const std::size_t j = std::size_t(wrap(iy + st.dy[s], ny)) * std::size_t(nx) + std::size_t(wrap(ix + st.dx[s], nx));
        pull += st.k[s] * (told(j) - g[j]);
      }
      if (pull > 0.0) {
        const double xn = jp.gap(g[i], jp.decay(g[i]), t[i], pull);
        if (xn < xi) xi = xn;
      }
    }
    x1[i] = xi;
  }
};

// Runs the rounds over a backend b (b.all, b.reduce<Acc>), x and a ping-ponging between
// two pairs of the backend's buffers; returns the buffer that holds the predicted gaps
// and counts the rounds.
template <class B>
double* cascade_rounds(B& b, std::size_t n, const double* g, const double* t, const JumpPrediction& jp,
                       const Stencil& st, int nx, int ny, double floor, double* x0, double* a0, double* x1,
                       double* a1, int& rounds) {
  b.all(n, RoundStart{g, t, x0, a0, jp});
  for (rounds = 0;; ++rounds) {
    const Count c = b.template reduce<Count>(n, Round{g, t, x0, a0, x1, a1, jp, st, nx, ny, floor});
    std::swap(x0, x1), std::swap(a0, a1);
    if (c.n == 0.0) break;
  }
  return x0;
}

}  // namespace cmc::qs
