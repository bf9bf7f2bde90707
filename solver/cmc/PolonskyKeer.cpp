#include "cmc/PolonskyKeer.hpp"

#include <chrono>
#include <cmath>
#include <sstream>
#include <tuple>
#include <stdexcept>

namespace cmc {

PolonskyKeer::PolonskyKeer(HalfSpace& hs, const Field& heights, Options o) : hs_(hs), h_(heights), opt_(std::move(o)) {
  if (heights.size() != hs.grid().size()) throw std::invalid_argument("PolonskyKeer: heights do not match the grid");
  const double hm = Grid::mean(heights);
  double s = 0.0;
  for (double h : heights) s += (h - hm) * (h - hm);
  double v[1] = {s};
  Grid::allreduce_sum(v);
  h_scale_ = std::sqrt(v[0] / double(hs.grid().size()));
  if (!(h_scale_ > 0.0)) h_scale_ = 1.0;
}

SolveResult PolonskyKeer::solve(const Target& target, ContactState& st) {
  const auto t0 = std::chrono::steady_clock::now();
  const long pairs0 = hs_.fft_pairs();
  const Grid& grid = hs_.grid();
  const std::size_t n = grid.size();
  const bool force_control = target.control == Control::MeanPressure;
  const double* h = h_.data();
  SolveResult res;

  auto finish = [&](bool converged, std::string msg) {
    res.converged = converged;
    res.message = std::move(msg);
    res.fft_pairs = hs_.fft_pairs() - pairs0;
    res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  };

  if (force_control && !(target.value >= 0.0))
    return finish(false, "Polonsky-Keer needs a non-negative mean pressure (no adhesion in a hard-wall solve)");

  Field& p = st.pressure;
  Field& u = st.displacement;
  double delta = force_control ? st.penetration : target.value;

  // ---- initial pressure: warm start, or PK's uniform guess (force control) or
  // a guess proportional to the geometric overlap (displacement control).
  const bool warm = p.size() == n && Grid::sum(p) > 0.0;
  if (!warm) {
    p.assign(n, 0.0);
    if (force_control) {
      std::fill(p.begin(), p.end(), target.value);
    } else {
      const double stiffness = hs_.contact_modulus() * M_PI / grid.lx;
      for (std::size_t i = 0; i < n; ++i) p[i] = std::max(0.0, delta - h[i]) * stiffness;
    }
  }
  if (force_control) {
    if (target.value == 0.0) {
      std::fill(p.begin(), p.end(), 0.0);
    } else {
      const double s = target.value / Grid::mean(p);
      for (auto& x : p) x *= s;
    }
  }
  u.resize(n);
  hs_.displacement(p, u);

  Field t(n, 0.0), r(n);
  double G_old = 1.0;
  bool conjugate = false;   // PK's δ flag: false restarts steepest descent
  bool exact_u = true;      // u == G p up to round-off
  int since_exact = 0;
  double pending_scale = 1.0, pending_tau = 0.0;  // deferred u ← s (u − τ r), p ← s p
  bool pending = false;
  const double mean_target = force_control ? target.value : 0.0;

  for (int it = 0;; ++it) {
    // ---- (a) gap statistics over the contact set, with the previous step's deferred
    // scaling fused in. Sums are shifted by the previous δ to avoid cancellation.
    const double c = delta;
    double s1 = 0.0, s2 = 0.0, nc = 0.0, ol = 0.0, nol = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (pending) {
        p[i] *= pending_scale;
        u[i] = pending_scale * (u[i] - pending_tau * r[i]);
      }
      const double x = h[i] + u[i] - c;
      if (p[i] > 0.0) {
        s1 += x;
        s2 += x * x;
        nc += 1.0;
      } else if (x < 0.0) {
        ol += x * x;
        nol += 1.0;
      }
    }
    pending = false;
    double sums[5] = {s1, s2, nc, ol, nol};
    Grid::allreduce_sum(sums);
    std::tie(s1, s2, nc, ol, nol) = std::tuple(sums[0], sums[1], sums[2], sums[3], sums[4]);

    if (nc == 0.0) {
      // No point carries pressure: either no contact at all (a valid solution of a
      // displacement-controlled step whose indenter does not reach the surface), or
      // the iteration lost its contact set.
      if (!force_control && nol == 0.0) {
        res.iterations = it;
        res.residual = 0.0;
        break;
      }
      if (force_control && mean_target == 0.0) {
        res.iterations = it;
        res.residual = 0.0;
        break;
      }
      // Restart from the geometric overlap.
      for (std::size_t i = 0; i < n; ++i) p[i] = std::max(0.0, delta - h[i]) * hs_.contact_modulus() * M_PI / grid.lx;
      if (Grid::sum(p) == 0.0) return finish(false, "Polonsky-Keer lost its contact set");
      hs_.displacement(p, u);
      conjugate = false;
      continue;
    }
    double G;
    if (force_control) {
      const double shift = s1 / nc;  // mean gap over Ic relative to c
      delta = c + shift;             // (b) the rigid-body position that zeroes it
      G = std::max(0.0, s2 - nc * shift * shift);
    } else {
      G = s2;
    }
    // Overlap term measured with the previous δ; it is zero at convergence either way.
    res.residual = std::sqrt((G + ol) / (nc + nol)) / h_scale_;
    res.iterations = it;
    if (opt_.progress && it % std::max(1, opt_.progress_every) == 0) opt_.progress(it, res.residual);

    if (res.residual <= opt_.tolerance) {
      if (exact_u) break;
      // Claimed convergence on an incrementally updated u: confirm on the exact one.
      hs_.displacement(p, u);
      exact_u = true;
      since_exact = 0;
      continue;
    }
    if (it >= opt_.max_iterations) break;

    // ---- (c) conjugate direction on Ic
    const double beta = conjugate ? G / G_old : 0.0;
    G_old = G;
    double sgt = 0.0, st_ = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (p[i] > 0.0) {
        const double g = h[i] + u[i] - delta;
        t[i] = g + beta * t[i];
        sgt += g * t[i];
        st_ += t[i];
      } else {
        t[i] = 0.0;
      }
    }
    // ---- (d) r = G t, one FFT pair
    hs_.displacement(t, r);
    double srt = 0.0, sr = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      if (p[i] > 0.0) {
        srt += r[i] * t[i];
        sr += r[i];
      }
    double red[4] = {sgt, st_, srt, sr};
    Grid::allreduce_sum(red);
    std::tie(sgt, st_, srt, sr) = std::tuple(red[0], red[1], red[2], red[3]);
    // Force control works with r − mean_Ic(r), which keeps the load fixed.
    const double denom = force_control ? srt - (sr / nc) * st_ : srt;
    if (!(denom > 0.0)) {
      // Loss of positive curvature along t (round-off at convergence): restart.
      if (!exact_u) {
        hs_.displacement(p, u);
        exact_u = true;
        since_exact = 0;
      }
      conjugate = false;
      if (it > 0 && G == 0.0) break;
      continue;
    }
    const double tau = sgt / denom;

    // ---- (e)–(g) pressure update, projection onto p ≥ 0, overlap points join
    bool changed = false;
    double psum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      double pn = p[i];
      if (pn > 0.0) {
        pn -= tau * t[i];
        if (pn < 0.0) {
          pn = 0.0;
          changed = true;
        }
      }
      if (pn == 0.0) {
        const double g = h[i] + u[i] - delta;
        if (g < 0.0) {
          pn = -tau * g;
          changed = true;
        }
      }
      p[i] = pn;
      psum += pn;
    }
    double ps[1] = {psum};
    Grid::allreduce_sum(ps);
    conjugate = !changed;
    // ---- (h) enforce the load
    double scale = 1.0;
    if (force_control) {
      const double mean_p = ps[0] / double(n);
      if (!(mean_p > 0.0)) return finish(false, "Polonsky-Keer: pressure vanished during the iteration");
      scale = mean_target / mean_p;
    }
    if (changed || ++since_exact >= opt_.recompute_every) {
      for (auto& x : p) x *= scale;
      hs_.displacement(p, u);
      exact_u = true;
      since_exact = 0;
    } else {
      pending = true;
      pending_scale = scale;
      pending_tau = tau;
      exact_u = false;
    }
  }

  // ---- the solved state
  st.penetration = delta;
  st.gap.resize(n);
  for (std::size_t i = 0; i < n; ++i) st.gap[i] = h[i] - delta + u[i];
  st.mean_pressure = Grid::mean(p);
  res.energy = hs_.energy(p, u);
  const bool ok = res.residual <= opt_.tolerance;
  std::string msg;
  if (!ok) {
    std::ostringstream s;
    s << "Polonsky-Keer stopped after " << res.iterations << " iterations at residual " << res.residual
      << " > tolerance " << opt_.tolerance;
    msg = s.str();
  }
  return finish(ok, msg);
}

}  // namespace cmc
