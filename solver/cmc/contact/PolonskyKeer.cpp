#include "cmc/contact/PolonskyKeer.hpp"

#include <chrono>
#include <cmath>
#include <sstream>
#include <tuple>
#include <stdexcept>

namespace cmc {

namespace {
constexpr std::size_t kParallelMin = 1 << 15;  // smaller grids: one thread (no fork/join cost)
}

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
  const double pairs0 = hs_.fft_pairs();
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
  // The iteration works with w = h + u (the gap plus δ): the operator adds h in
  // Fourier space, so no pass reads h. u = w − h at the end.
  Field& w = u;
  hs_.set_offset(h_);
  struct ClearOffset {
    HalfSpace& hs;
    ~ClearOffset() { hs.clear_offset(); }
  } clear_offset{hs_};
  std::string failure;
  hs_.set_pressure(p, 1.0, w);  // w = h + G p, and the operator keeps p̂

  Field t(n, 0.0);
  double G_old = 1.0;
  double last_tau = grid.lx / (M_PI * hs_.contact_modulus());  // compliance of the longest wave
  bool conjugate = false;     // PK's δ flag: false restarts steepest descent
  int since_exact = 0;        // linear spectral steps since p̂ was last taken from p
  double sigma = 1.0;         // the pressure is sigma * p: the last load scaling, applied lazily
  const double mean_target = force_control ? target.value : 0.0;

  for (int it = 0;; ++it) {
    // ---- (a) gap statistics over the contact set Ic = {p > 0} (σ > 0 does not change
    // it). Sums are shifted by the previous δ to avoid cancellation. Σ_Ic t is gathered
    // to keep the next direction load-neutral.
    const double c = delta;
    double s1 = 0.0, s2 = 0.0, nc = 0.0, ol = 0.0, nol = 0.0, tsum = 0.0;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(+ : s1, s2, nc, ol, nol, tsum)
    for (std::size_t i = 0; i < n; ++i) {
      const double x = w[i] - c;
      if (p[i] > 0.0) {
        s1 += x;
        s2 += x * x;
        nc += 1.0;
        tsum += t[i];
      } else if (x < 0.0) {
        ol += x * x;
        nol += 1.0;
      }
    }
    double sums[6] = {s1, s2, nc, ol, nol, tsum};
    Grid::allreduce_sum(sums);
    std::tie(s1, s2, nc, ol, nol, tsum) = std::tuple(sums[0], sums[1], sums[2], sums[3], sums[4], sums[5]);

    if (nc == 0.0) {
      // No point carries pressure: either no contact at all (a valid solution of a
      // displacement-controlled step whose indenter does not reach the surface, or of
      // zero load), or the iteration lost its contact set.
      if ((!force_control && nol == 0.0) || (force_control && mean_target == 0.0)) {
        res.iterations = it;
        res.residual = 0.0;
        break;
      }
      // Restart from the geometric overlap.
      for (std::size_t i = 0; i < n; ++i) p[i] = std::max(0.0, delta - h[i]) * hs_.contact_modulus() * M_PI / grid.lx;
      if (Grid::sum(p) == 0.0) {
        failure = "Polonsky-Keer lost its contact set";
        break;
      }
      sigma = 1.0;
      hs_.set_pressure(p, 1.0, w);
      since_exact = 0;
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
      if (since_exact == 0) break;
      // Confirm on u recomputed from the real-space p (removes spectral round-off drift).
      hs_.set_pressure(p, sigma, w);
      since_exact = 0;
      continue;
    }
    if (it >= opt_.max_iterations) break;

    // ---- (c) conjugate direction on Ic. Under load control the old direction is
    // made load-neutral on the current Ic (Σ_Ic t = 0), so the step keeps Σ p and the
    // exact line search needs only <t, G t> (PK subtract the Ic-mean of G t instead,
    // which costs a second transform).
    const double beta = conjugate ? G / G_old : 0.0;
    const double tbar = force_control ? tsum / nc : 0.0;
    G_old = G;
    double sgt = 0.0;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(+ : sgt)
    for (std::size_t i = 0; i < n; ++i) {
      if (p[i] > 0.0) {
        const double g = w[i] - delta;
        t[i] = g + beta * (t[i] - tbar);
        sgt += g * t[i];
      } else {
        t[i] = 0.0;
      }
    }
    double red[1] = {sgt};
    Grid::allreduce_sum(red);
    sgt = red[0];
    // ---- (d) curvature along t from its transform alone (one forward transform)
    const double denom = hs_.set_direction(t);
    double tau;
    if (denom > 0.0 && sgt > 0.0) {
      tau = last_tau = sgt / denom;
    } else if (nol > 0.0) {
      tau = last_tau;  // nothing to gain on Ic: only overlapping points move
      conjugate = false;
    } else {
      // No descent left and no overlap: round-off floor. Confirm on an exact u, then stop.
      if (since_exact > 0) {
        hs_.set_pressure(p, sigma, w);
        since_exact = 0;
        conjugate = false;
        continue;
      }
      break;
    }

    // ---- (e)–(g) pressure update, projection onto p ≥ 0, overlap points join
    bool changed = false;
    double psum = 0.0;
#pragma omp parallel for schedule(static) if (n > kParallelMin) reduction(+ : psum) reduction(|| : changed)
    for (std::size_t i = 0; i < n; ++i) {
      double pn = sigma * p[i];
      if (pn > 0.0) {
        pn -= tau * t[i];
        if (pn < 0.0) {
          pn = 0.0;
          changed = true;
        }
      }
      if (pn == 0.0) {
        const double g = w[i] - delta;
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
      if (!(mean_p > 0.0)) {
        failure = "Polonsky-Keer: pressure vanished during the iteration";
        break;
      }
      scale = mean_target / mean_p;
    }
    // ---- new displacement: a linear step is one inverse transform; a projected one
    // needs the transform of the new p (one forward more).
    if (changed || ++since_exact >= opt_.recompute_every) {
      hs_.set_pressure(p, scale, w);
      since_exact = 0;
    } else {
      hs_.step_pressure(scale, tau, w);
    }
    sigma = scale;
  }
  if (sigma != 1.0)
    for (auto& x : p) x *= sigma;

  // ---- the solved state
  st.penetration = delta;
  st.gap.resize(n);
  // The reported gap is the solution's: zero where pressure is carried, and the
  // non-negative gap elsewhere. How far the iterate is from that is the residual.
  for (std::size_t i = 0; i < n; ++i) {
    st.gap[i] = p[i] > 0.0 ? 0.0 : std::max(0.0, w[i] - delta);
    u[i] = w[i] - h[i];  // w becomes the displacement again
  }
  st.mean_pressure = Grid::mean(p);
  res.energy = hs_.energy(p, u);
  const bool ok = failure.empty() && res.residual <= opt_.tolerance;
  std::string msg = failure;
  if (!ok && msg.empty()) {
    std::ostringstream s;
    s << "Polonsky-Keer stopped after " << res.iterations << " iterations at residual " << res.residual
      << " > tolerance " << opt_.tolerance;
    msg = s.str();
  }
  return finish(ok, msg);
}

}  // namespace cmc
