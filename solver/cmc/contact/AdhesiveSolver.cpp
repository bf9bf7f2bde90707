#include "cmc/contact/AdhesiveSolver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace cmc {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
// Relative size of an energy change that counts as an increase (round-off of the sums
// over the grid is ~1e-13 relative even at 10^8 points).
constexpr double kEnergySlack = 1e-11;
// Sufficient-descent factor: a conjugate direction must satisfy ψ·d <= −kDescent |ψ|².
constexpr double kDescent = 0.01;
// Grids below this many points run the elementwise passes on one thread (OpenMP's fork
// costs more than it saves there).
constexpr std::size_t kParallelPoints = 32768;
}  // namespace

// ---------------------------------------------------------------- work arrays

struct AdhesiveSolver::Work {
  int nx = 0, ny = 0, mx = 0, my = 0;
  bool periodic = true;
  std::size_t n = 0, M = 0;
  double norm = 1.0;
  std::unique_ptr<Fourier> fft;
  Field kmul;  // K multiplier (with 1/M), r2c layout
  Field cmul;  // C = K^-1 multiplier (free boundary only; warm starts)
  Field hf;    // heights on the full grid (patch part; 0 in the padding)
  Field u, Ku, d, Kd, r, c, trial, Ktrial;
  Field Kh;  // K h (periodic): makes the mean-gap rescale g <- s g an exact linear update
  std::vector<unsigned char> bound;
  double hmean = 0.0;

  // out = K in; returns in·K in (Parseval, inside the multiply loop). One FFT pair.
  double apply(const Field& in, Field& out, const Field& mul) {
    fft->forward(in.data());
    auto& s = fft->spectrum();
    const int nq = mx / 2 + 1;
    double acc = 0.0;
    const bool par = M >= kParallelPoints;
#pragma omp parallel for schedule(static) reduction(+ : acc) if (par)
    for (int iy = 0; iy < my; ++iy) {
      const std::size_t row = std::size_t(iy) * nq;
      double a = 0.0;
      for (int ix = 0; ix < nq; ++ix) {
        const double wgt = (ix == 0 || 2 * ix == mx) ? 1.0 : 2.0;
        const std::size_t k = row + ix;
        a += wgt * mul[k] * std::norm(s[k]);
        s[k] *= mul[k];
      }
      acc += a;
    }
    fft->inverse(out.data());
    return acc;
  }
};

// ---------------------------------------------------------------- construction

AdhesiveSolver::AdhesiveSolver(HalfSpace& hs, const Field& heights, Interaction interaction, Options o)
    : hs_(hs), h_(heights), interaction_(std::move(interaction)), opt_(std::move(o)), w_(std::make_unique<Work>()) {
  const Grid& g = hs.grid();
  if (heights.size() != g.size()) throw std::invalid_argument("AdhesiveSolver: heights do not match the grid");
  for (double x : heights)
    if (!std::isfinite(x)) throw std::invalid_argument("AdhesiveSolver: heights must be finite");
  Work& w = *w_;
  w.nx = g.nx;
  w.ny = g.ny;
  w.periodic = hs.periodic();
  w.mx = w.periodic ? g.nx : 2 * g.nx;
  w.my = w.periodic ? g.ny : 2 * g.ny;
  w.n = g.size();
  w.M = std::size_t(w.mx) * w.my;
  w.fft = std::make_unique<Fourier>(w.mx, w.my);
  w.norm = w.fft->normalisation();
  const int nq = w.mx / 2 + 1;
  w.kmul.assign(std::size_t(nq) * w.my, 0.0);
  const double estar = hs.contact_modulus();
  if (w.periodic) {
    // K = E*|q|/2 (the inverse of PeriodicHalfSpace's 2/(E*|q|)); 0 at q = 0.
    for (int iy = 0; iy < w.my; ++iy)
      for (int ix = 0; ix < nq; ++ix)
        w.kmul[std::size_t(iy) * nq + ix] = 0.5 * estar * std::hypot(g.qx(ix), g.qy(iy)) * w.norm;
  } else {
    // The padded circulant of FreeHalfSpace (same influence coefficients, same wrap).
    Field k(w.M);
    for (int j = 0; j < w.my; ++j)
      for (int i = 0; i < w.mx; ++i) {
        const int ii = i <= g.nx ? i : i - w.mx, jj = j <= g.ny ? j : j - w.my;
        k[std::size_t(j) * w.mx + i] = FreeHalfSpace::influence(ii * g.dx(), jj * g.dy(), g.dx(), g.dy(), estar);
      }
    w.fft->forward(k.data());
    const auto& s = w.fft->spectrum();
    w.cmul.resize(s.size());
    for (std::size_t q = 0; q < s.size(); ++q) {
      const double lambda = s[q].real();
      if (!(lambda > 0.0) || !std::isfinite(lambda))
        throw std::runtime_error("AdhesiveSolver: the padded free-boundary operator is not positive definite");
      w.kmul[q] = w.norm / lambda;
      w.cmul[q] = w.norm * lambda;
    }
  }
  w.hf.assign(w.M, 0.0);
  for (int iy = 0; iy < w.ny; ++iy)
    std::copy_n(&heights[std::size_t(iy) * w.nx], w.nx, &w.hf[std::size_t(iy) * w.mx]);
  w.hmean = Grid::mean(heights);
  for (Field* f : {&w.u, &w.Ku, &w.d, &w.Kd, &w.r, &w.c, &w.trial, &w.Ktrial}) f->assign(w.M, 0.0);
  w.bound.assign(w.M, 0);
  if (w.periodic) {
    w.Kh.assign(w.M, 0.0);
    w.apply(w.hf, w.Kh, w.kmul);
  }

  // Pressure scale: max(peak tension, E* x rms slope of the indenter).
  double s2 = 0.0;
  long cnt = 0;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const std::size_t k = std::size_t(iy) * g.nx + ix;
      double sx = 0.0, sy = 0.0;
      bool ok = true;
      if (w.periodic || ix + 1 < g.nx) sx = (heights[std::size_t(iy) * g.nx + (ix + 1) % g.nx] - heights[k]) / g.dx();
      else ok = false;
      if (g.ny > 1) {
        if (w.periodic || iy + 1 < g.ny) sy = (heights[std::size_t((iy + 1) % g.ny) * g.nx + ix] - heights[k]) / g.dy();
        else ok = false;
      }
      if (ok) {
        s2 += sx * sx + sy * sy;
        ++cnt;
      }
    }
  const double slope = cnt ? std::sqrt(s2 / cnt) : 0.0;
  pscale_ = std::max(peak_tension(interaction_), estar * slope);
  if (!(pscale_ > 0.0) || !std::isfinite(pscale_)) pscale_ = estar;
}

AdhesiveSolver::~AdhesiveSolver() = default;

// ---------------------------------------------------------------- public entry

SolveResult AdhesiveSolver::solve(const Target& target, ContactState& st) {
  diag_ = {};
  if (!std::isfinite(target.value)) {
    SolveResult r;
    r.message = "AdhesiveSolver: the target is not a finite number";
    return r;
  }
  if (target.control == Control::MeanPressure) return solve_load(target.value, st);
  return std::visit([&](const auto& inter) { return solve_displacement(inter, target.value, st); }, interaction_);
}

// ---------------------------------------------------------------- displacement control

namespace {

// Reductions of one pass over the grid (see the residual definition in the header).
struct Sums {
  double uKu = 0.0;   // Σ u·Ku (exact evaluation) or Σ Ku_old·d (incremental step)
  double phi = 0.0;   // Σ φ(g)
  double nF = 0.0;    // free set (patch part): count and moments of x = r − shift
  double sx = 0.0, sxx = 0.0;
  double sxHd = 0.0, sHd = 0.0;  // Daniel's β: Σ x·Hd, Σ Hd over the free set
  double sxd = 0.0, sd = 0.0;    // Σ x·d_old, Σ d_old over the free set
  double rmax = -kInf, rmin = kInf;  // over g > 0
  double rmin_contact = kInf;        // over g = 0
  double out_abs = 0.0;              // padding: max |r|
  double gsum = 0.0;                 // Σ g over the patch
  long changed = 0;                  // points whose wall-set membership changed (if tracked)
};

// The arrays of one solve, as raw pointers (the kernels promise no aliasing). x holds the
// gap g on the patch and the displacement u in the padding of a free boundary; on the
// patch u = g − (h − δ) is formed only where the energy needs it.
struct Arrays {
  double* x;
  double* Ku;
  double* r;
  double* c;
  double* d;
  double* Kd;
  unsigned char* bound;
};
struct Shape {
  int nx, ny, mx, my;
  const double* h;   // heights on the full grid
  const double* Kh;  // K h (periodic only)
  double delta;
};

// The evaluation pass: r = Ku + φ'(g) = Ku − f(g), c = φ''(g), and the sums. Step: fused
// with the incremental update x += a d, Ku += a Kd (then uKu = Σ Ku_old·d); Step and
// Scale: x <- s (x + a d) with the exact K u update through K h (then uKu = Σ u·Ku).
// Otherwise uKu = Σ u·Ku (reads h). `ml` classifies the wall set (g = 0 and r >= ml), `sh` shifts
// the free-set moments. Track: count wall-set changes against `bound`. Every accumulator
// is a local so that the loop runs from registers.
template <bool Step, bool Scale, bool Daniel, bool Track, class I>
Sums eval_pass(const I& inter, const Arrays& A, const Shape& S, double a, double sc, double ml, double sh) {
  double* __restrict x = A.x;
  double* __restrict Ku = A.Ku;
  double* __restrict r = A.r;
  double* __restrict c = A.c;
  const double* __restrict d = A.d;
  const double* __restrict Kd = A.Kd;
  const unsigned char* __restrict bound = A.bound;
  const double* __restrict h = S.h;
  const double* __restrict Kh = S.Kh;
  const double delta = S.delta;
  double uKu = 0, phi = 0, nF = 0, sx = 0, sxx = 0, sxHd = 0, sHd = 0, sxd = 0, sd = 0;
  double rmax = -kInf, rmin = kInf, rminc = kInf, out_abs = 0, gsum = 0;
  long changed = 0;
  const bool par = std::size_t(S.mx) * S.my >= kParallelPoints;
#pragma omp parallel for schedule(static) if (par) \
    reduction(+ : uKu, phi, nF, sx, sxx, sxHd, sHd, sxd, sd, gsum, changed) \
    reduction(max : rmax, out_abs) reduction(min : rmin, rminc)
  for (int iy = 0; iy < S.my; ++iy) {
    const std::size_t row = std::size_t(iy) * S.mx;
    const std::size_t pe = row + (iy < S.ny ? S.nx : 0), re = row + S.mx;
    // Blocks of B points: first the update and the interaction (which may call exp(): a
    // call clobbers every vector register, so no accumulator is live across it), then the
    // reductions from L1-resident values.
    constexpr std::size_t B = 256;
    double fb[B], cb[B];
    for (std::size_t k0 = row; k0 < pe; k0 += B) {
      const std::size_t k1 = std::min(pe, k0 + B);
      for (std::size_t k = k0; k < k1; ++k) {
        double g = x[k];
        if constexpr (Step && Scale) {
          // g <- s (g + a d) and, exactly, K u <- s (K u + a K d) + (s − 1) K h
          g = sc * (g + a * d[k]);
          x[k] = g;
        } else if constexpr (Step) {
          g += a * d[k];
          x[k] = g;
        }
        const InteractionValue iv = inter.evaluate(g);
        phi += iv.energy;
        fb[k - k0] = iv.force;
        cb[k - k0] = iv.curvature;
      }
      for (std::size_t k = k0; k < k1; ++k) {
        const double g = x[k], dk = d[k];
        double kuk = Ku[k];
        if constexpr (Step && Scale) {
          kuk = sc * (kuk + a * Kd[k]) + (sc - 1.0) * Kh[k];
          Ku[k] = kuk;
          uKu += (g - (h[k] - delta)) * kuk;
        } else if constexpr (Step) {
          uKu += kuk * dk;
          kuk += a * Kd[k];
          Ku[k] = kuk;
        } else {
          uKu += (g - (h[k] - delta)) * kuk;
        }
        double Hd = 0.0;
        if constexpr (Daniel) Hd = Kd[k] + c[k] * dk;
        const double rk = kuk - fb[k - k0];
        r[k] = rk;
        c[k] = cb[k - k0];
        gsum += g;
        bool is_bound = false;
        if (g <= 0.0) {
          rminc = std::min(rminc, rk);
          is_bound = rk >= ml;
        } else {
          rmax = std::max(rmax, rk);
          rmin = std::min(rmin, rk);
        }
        if constexpr (Track) changed += is_bound != bool(bound[k]);
        if (!is_bound) {
          const double xr = rk - sh;
          nF += 1.0;
          sx += xr;
          sxx += xr * xr;
          sxHd += xr * Hd;
          sHd += Hd;
          sxd += xr * dk;
          sd += dk;
        }
      }
    }
    // Padding of a free boundary: no interaction, no wall, μ = 0 (shift 0).
    for (std::size_t k = pe; k < re; ++k) {
      double uk = x[k], kuk = Ku[k];
      const double dk = d[k];
      if constexpr (Step) {
        uKu += kuk * dk;
        uk += a * dk;
        kuk += a * Kd[k];
        x[k] = uk;
        Ku[k] = kuk;
      } else {
        uKu += uk * kuk;
      }
      r[k] = kuk;
      out_abs = std::max(out_abs, std::abs(kuk));
      sxx += kuk * kuk;
      if constexpr (Daniel) sxHd += kuk * Kd[k];
      sxd += kuk * dk;
    }
  }
  Sums s;
  s.uKu = uKu;
  s.phi = phi;
  s.nF = nF;
  s.sx = sx;
  s.sxx = sxx;
  s.sxHd = sxHd;
  s.sHd = sHd;
  s.sxd = sxd;
  s.sd = sd;
  s.rmax = rmax;
  s.rmin = rmin;
  s.rmin_contact = rminc;
  s.out_abs = out_abs;
  s.gsum = gsum;
  s.changed = changed;
  return s;
}

struct DirSums {
  double psid = 0.0, cd2 = 0.0, dmax = 0.0, afeas = kInf, dsum = 0.0;
};
// The direction pass: d = −ψ + β (d_old − m_old) on the free set, 0 on the wall set, and
// projected on the feasible cone (d >= 0 where g = 0). dsum = Σ d over the patch (zero up
// to the projected points; a periodic step rescales the gaps to restore the mean).
template <bool Track>
DirSums direction_pass(const Arrays& A, const Shape& S, double mu, double ml, double beta, double m_old) {
  const double* __restrict x = A.x;
  const double* __restrict r = A.r;
  const double* __restrict c = A.c;
  double* __restrict d = A.d;
  unsigned char* __restrict bound = A.bound;
  double psid = 0, cd2 = 0, dmax = 0, afeas = kInf, dsum = 0;
  const bool par = std::size_t(S.mx) * S.my >= kParallelPoints;
#pragma omp parallel for schedule(static) if (par) reduction(+ : psid, cd2, dsum) reduction(max : dmax) \
    reduction(min : afeas)
  for (int iy = 0; iy < S.my; ++iy) {
    const std::size_t row = std::size_t(iy) * S.mx;
    const std::size_t pe = row + (iy < S.ny ? S.nx : 0), re = row + S.mx;
    for (std::size_t k = row; k < pe; ++k) {
      const double g = x[k];
      const double rk = r[k];
      const bool is_bound = g <= 0.0 && rk >= ml;
      if constexpr (Track) bound[k] = is_bound;
      double dk = 0.0;
      if (!is_bound) {
        const double psi = rk - mu;
        dk = -psi + beta * (d[k] - m_old);
        if (g <= 0.0 && dk < 0.0) dk = 0.0;  // feasible cone
        psid += psi * dk;
        cd2 += c[k] * dk * dk;
        dsum += dk;
        dmax = std::max(dmax, std::abs(dk));
        if (dk < 0.0) afeas = std::min(afeas, g / -dk);
      }
      d[k] = dk;
    }
    for (std::size_t k = pe; k < re; ++k) {
      const double dk = -r[k] + beta * d[k];
      psid += r[k] * dk;
      d[k] = dk;
    }
  }
  return {psid, cd2, dmax, afeas, dsum};
}

// The projected trial point t = x + α d with g clipped at 0; returns Σ g over the patch.
double trial_pass(const Arrays& A, const Shape& S, double alpha, double* __restrict t) {
  const double* __restrict x = A.x;
  const double* __restrict d = A.d;
  double gs = 0.0;
  const bool par = std::size_t(S.mx) * S.my >= kParallelPoints;
#pragma omp parallel for schedule(static) if (par) reduction(+ : gs)
  for (int iy = 0; iy < S.my; ++iy) {
    const std::size_t row = std::size_t(iy) * S.mx;
    const std::size_t pe = row + (iy < S.ny ? S.nx : 0), re = row + S.mx;
    for (std::size_t k = row; k < pe; ++k) {
      const double g = std::max(x[k] + alpha * d[k], 0.0);
      t[k] = g;
      gs += g;
    }
    for (std::size_t k = pe; k < re; ++k) t[k] = x[k] + alpha * d[k];
  }
  return gs;
}

// Scale the patch gaps by s (the periodic mean-gap projection; 1 otherwise) and form
// u = x − (h − δ) on the patch, x in the padding: the input of an exact K u.
void displacement_of(double* __restrict x, const Shape& S, double s, double* __restrict u) {
  const bool par = std::size_t(S.mx) * S.my >= kParallelPoints;
#pragma omp parallel for schedule(static) if (par)
  for (int iy = 0; iy < S.my; ++iy) {
    const std::size_t row = std::size_t(iy) * S.mx;
    const std::size_t pe = row + (iy < S.ny ? S.nx : 0), re = row + S.mx;
    if (s != 1.0)
      for (std::size_t k = row; k < pe; ++k) x[k] *= s;
    for (std::size_t k = row; k < pe; ++k) u[k] = x[k] - (S.h[k] - S.delta);
    for (std::size_t k = pe; k < re; ++k) u[k] = x[k];
  }
}

}  // namespace

template <class I>
SolveResult AdhesiveSolver::solve_displacement(const I& inter, double delta, ContactState& st) {
  const auto t0 = std::chrono::steady_clock::now();
  Work& w = *w_;
  const long pairs0 = w.fft->forward_count() + w.fft->inverse_count();
  SolveResult res;
  const int nx = w.nx, ny = w.ny, mx = w.mx, my = w.my;
  const bool periodic = w.periodic;
  const std::size_t n = w.n;
  const double* hf = w.hf.data();
  const double gbar = w.hmean - delta;  // prescribed mean gap (periodic)
  const double P = pscale_;
  const double tol = opt_.tolerance;
  const bool track = opt_.restart_on_active_set_change;

  auto finish = [&](bool converged, std::string msg) {
    res.converged = converged;
    res.message = std::move(msg);
    res.fft_pairs = 0.5 * double(w.fft->forward_count() + w.fft->inverse_count() - pairs0);
    res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  };
  if (periodic && gbar < 0.0) {
    std::ostringstream s;
    s << "AdhesiveSolver: penetration " << delta << " exceeds the mean height " << w.hmean
      << ": a periodic solid (mean(u) = 0) has no admissible state with mean gap " << gbar << " < 0";
    return finish(false, s.str());
  }

  Field &x = w.u, &Ku = w.Ku, &d = w.d, &Kd = w.Kd, &r = w.r, &c = w.c;
  auto& bound = w.bound;
  const Shape shape{nx, ny, mx, my, hf, periodic ? w.Kh.data() : nullptr, delta};
  std::fill(d.begin(), d.end(), 0.0);
  std::fill(c.begin(), c.end(), 0.0);
  std::fill(bound.begin(), bound.end(), 0);

  // Periodic: the factor s that restores the prescribed mean gap when the gaps are scaled
  // by it (keeps g >= 0 and the contact set; Bugnicourt et al. 2018), given their sum. A
  // patch in full contact with ḡ > 0 is lifted uniformly instead (then s = 1).
  auto mean_scale = [&](double* xs, double gs) {
    if (!periodic) return 1.0;
    const double gm = gs / double(n);
    if (gm > 0.0) return gm == gbar ? 1.0 : gbar / gm;
    std::fill(xs, xs + n, gbar);
    return 1.0;
  };
  auto patch_sum = [&](const double* xs) {  // periodic only (no padding)
    double gs = 0.0;
    const std::ptrdiff_t m = std::ptrdiff_t(n);
#pragma omp parallel for schedule(static) reduction(+ : gs) if (n >= kParallelPoints)
    for (std::ptrdiff_t k = 0; k < m; ++k) gs += xs[k];
    return gs;
  };

  // ---- initial gaps: warm start (contacts kept at g = 0, the displacement of every other
  // point kept), or cold (u = 0); projected on g >= 0 (and the mean gap)
  {
    const bool warm = st.gap.size() == n && st.displacement.size() == n;
    if (!periodic) {
      std::fill(x.begin(), x.end(), 0.0);
      if (warm && st.pressure.size() == n) {
        // Padding displacements of the previous solution: u = C p (one FFT pair).
        std::fill(w.trial.begin(), w.trial.end(), 0.0);
        for (int iy = 0; iy < ny; ++iy)
          std::copy_n(&st.pressure[std::size_t(iy) * nx], nx, &w.trial[std::size_t(iy) * mx]);
        w.apply(w.trial, x, w.cmul);
      }
    }
    for (int iy = 0; iy < ny; ++iy)
      for (int ix = 0; ix < nx; ++ix) {
        const std::size_t k = std::size_t(iy) * mx + ix, kp = std::size_t(iy) * nx + ix;
        double g = hf[k] - delta;  // cold: u = 0
        if (warm) g = st.gap[kp] <= 0.0 ? 0.0 : (hf[k] - delta) + st.displacement[kp];
        x[k] = g > 0.0 ? g : 0.0;  // also drops non-finite input
      }
  }

  // ---- the evaluation pass, dispatched on its compile-time flags
  double mu_lag = periodic ? -kInf : 0.0;  // wall-set classification uses the previous μ
  double shift = 0.0;                      // free-set moments are taken relative to this
  auto arrays = [&]() { return Arrays{x.data(), Ku.data(), r.data(), c.data(), d.data(), Kd.data(), bound.data()}; };
  auto pass = [&](bool step, double a, double sc, bool daniel) {
    const Arrays A = arrays();
    const double ml = mu_lag, sh = shift;
    const bool scale = step && sc != 1.0;
    if (track) {
      if (scale) return daniel ? eval_pass<true, true, true, true>(inter, A, shape, a, sc, ml, sh)
                               : eval_pass<true, true, false, true>(inter, A, shape, a, sc, ml, sh);
      if (step) return daniel ? eval_pass<true, false, true, true>(inter, A, shape, a, sc, ml, sh)
                              : eval_pass<true, false, false, true>(inter, A, shape, a, sc, ml, sh);
      return daniel ? eval_pass<false, false, true, true>(inter, A, shape, a, sc, ml, sh)
                    : eval_pass<false, false, false, true>(inter, A, shape, a, sc, ml, sh);
    }
    if (scale) return daniel ? eval_pass<true, true, true, false>(inter, A, shape, a, sc, ml, sh)
                             : eval_pass<true, true, false, false>(inter, A, shape, a, sc, ml, sh);
    if (step) return daniel ? eval_pass<true, false, true, false>(inter, A, shape, a, sc, ml, sh)
                            : eval_pass<true, false, false, false>(inter, A, shape, a, sc, ml, sh);
    return daniel ? eval_pass<false, false, true, false>(inter, A, shape, a, sc, ml, sh)
                  : eval_pass<false, false, false, false>(inter, A, shape, a, sc, ml, sh);
  };

  // State of the iteration derived from a pass.
  double U = 0.0, Phi = 0.0;  // ½ Σ u Ku and Σ φ (grid sums)
  double mu = 0.0, psi2 = 0.0, residual = kInf;
  Sums S;
  auto digest = [&](const Sums& s) {
    S = s;
    Phi = s.phi;
    if (periodic) mu = s.nF > 0.0 ? shift + s.sx / s.nF : s.rmin_contact;  // full contact: least compression
    else mu = 0.0;
    const double dm = mu - shift;
    psi2 = std::max(0.0, s.sxx - 2.0 * dm * s.sx + s.nF * dm * dm);
    double v = 0.0;
    if (s.rmax > -kInf) v = std::max({v, s.rmax - mu, mu - s.rmin});
    if (s.rmin_contact < kInf) v = std::max(v, mu - s.rmin_contact);
    v = std::max(v, s.out_abs);
    residual = v / P;
  };
  auto all_finite = [](const Sums& s) {
    return std::isfinite(s.uKu) && std::isfinite(s.phi) && std::isfinite(s.sxx) && std::isfinite(s.sx) &&
           std::isfinite(s.gsum);
  };

  // Exact K u (one FFT pair) and a full evaluation; on a periodic grid the mean gap is
  // re-imposed first (removes round-off drift).
  auto exact = [&]() {
    const double sc = periodic ? mean_scale(x.data(), patch_sum(x.data())) : 1.0;
    displacement_of(x.data(), shape, sc, w.trial.data());
    w.apply(w.trial, Ku, w.kmul);
    ++diag_.exact_recomputes;
    const Sums s = pass(false, 0.0, 1.0, false);
    U = 0.5 * s.uKu;
    digest(s);
    return all_finite(s);
  };

  std::string stop_msg;
  bool exact_now = true;
  if (!exact()) return finish(false, "AdhesiveSolver: non-finite values in the initial state");

  bool restart = true;
  double kappa_prev = 0.0, beta_num = 0.0;
  int since_exact = 0, stalls = 0;
  double floor_residual = kInf;  // smallest exact residual after a false convergence claim
  int floor_hits = 0;
  const double trust = opt_.trust_step > 0.0 ? opt_.trust_step
                       : interaction_range(interaction_) > 0.0 ? interaction_range(interaction_)
                                                                : 1.0;

  for (int it = 0;; ++it) {
    res.iterations = it;
    res.residual = residual;
    if (opt_.progress && it % std::max(1, opt_.progress_every) == 0) opt_.progress(it, residual);
    if (residual <= tol) {
      if (exact_now) break;
      // Claimed convergence on an incrementally updated K u: confirm on the exact one.
      if (!exact()) {
        stop_msg = "non-finite value on an exact recompute";
        break;
      }
      exact_now = true;
      since_exact = 0;
      res.residual = residual;
      if (residual <= tol) break;
      restart = true;
      // The exact residual does not go below the tolerance however often the incremental
      // one does: round-off (e.g. huge gaps, u = g − (h − δ) cancelling) sets a floor.
      if (residual < 0.9 * floor_residual) {
        floor_residual = residual;
        floor_hits = 0;
      } else if (++floor_hits >= 20) {
        std::ostringstream m;
        m << "residual stalled at " << residual << " (round-off floor above the tolerance)";
        stop_msg = m.str();
        break;
      }
    }
    if (it >= opt_.max_iterations) break;

    // ---- conjugate direction (the wall set is classified exactly as in the last pass,
    // so that d has zero mean over the free set)
    const double dm = mu - shift;
    double beta = 0.0;
    if (!restart && kappa_prev > 0.0) beta = std::max(0.0, beta_num / kappa_prev);
    if (track && S.changed > 0) beta = 0.0;
    const double m_old = (periodic && S.nF > 0.0) ? S.sd / S.nF : 0.0;
    const double psi_dold = S.sxd - dm * S.sd;  // Σ_F ψ (d_old − m_old), using Σ_F ψ = 0
    if (beta > 0.0 && -psi2 + beta * psi_dold > -kDescent * psi2) beta = 0.0;
    if (beta == 0.0) ++diag_.restarts;
    const DirSums D = track ? direction_pass<true>(arrays(), shape, mu, mu_lag, beta, m_old)
                            : direction_pass<false>(arrays(), shape, mu, mu_lag, beta, m_old);
    const double psid = D.psid, cd2 = D.cd2, dmax = D.dmax, afeas = D.afeas, dsum = D.dsum;
    // The next pass classifies with this iteration's μ and takes its sums relative to it.
    mu_lag = periodic ? mu : 0.0;
    shift = mu_lag;
    const double dKd = w.apply(d, Kd, w.kmul);  // one FFT pair
    const double kappa = dKd + cd2;
    if (!std::isfinite(kappa) || !std::isfinite(psid)) {
      stop_msg = "non-finite search direction";
      break;
    }
    if (!(psid < 0.0)) {
      // Not a descent direction: only round-off at the level of the tolerance does this.
      restart = true;
      if (++stalls > 3) {
        stop_msg = "no descent direction (residual at round-off level)";
        break;
      }
      continue;
    }

    // ---- line search along d
    const bool negc = !(kappa > 0.0);
    double alpha = negc ? trust / dmax : -psid / kappa;
    if (negc) ++diag_.negative_curvature;
    const double U0 = U, E0 = U + Phi;
    const double slack = kEnergySlack * (std::abs(U0) + std::abs(Phi)) + 1e-300;
    const Sums S0 = S;
    const double gsum0 = S.gsum;
    // Scale of a periodic step x <- s (x + α d) that keeps the mean gap (d has zero mean
    // over the free set up to points projected on the feasible cone and round-off).
    // Round-off in Σ d (~1e-16 relative) is left to the exact recomputes.
    auto step_scale = [&](double al) {
      if (!periodic || !(std::abs(al * dsum) > 1e-13 * std::abs(gsum0))) return 1.0;
      const double gs = gsum0 + al * dsum;
      return gs > 0.0 ? double(n) * gbar / gs : 1.0;
    };
    // In-place trial held by x, Ku: x = s_app (x0 + a_app d).
    double a_app = 0.0, s_app = 1.0, U_app = U0;
    auto move_to = [&](double a2, double s2, bool daniel) {
      const double sig = s2 / s_app, ap = s_app * (a2 - a_app);
      Sums sn = pass(true, ap, sig, daniel);
      U_app = sig != 1.0 ? 0.5 * sn.uKu : U_app + ap * sn.uKu + 0.5 * ap * ap * dKd;
      a_app = a2;
      s_app = s2;
      return sn;
    };
    bool accepted = false, clipped = false, first_try = true, base_dirty = false;
    Sums Snew;
    double Unew = U0;
    for (int bt = 0; bt <= opt_.max_backtracks; ++bt) {
      first_try = bt == 0;
      if (!(alpha > 0.0) || !std::isfinite(alpha)) break;
      const bool daniel = !negc && first_try;
      if (alpha <= afeas) {
        // No point reaches the wall: exact incremental update in place (no FFT).
        Snew = move_to(alpha, step_scale(alpha), daniel);
        Unew = U_app;
        clipped = false;
        base_dirty = false;
      } else {
        // Projected step into the trial arrays, then K u exactly (one more FFT pair).
        if (a_app != 0.0 || s_app != 1.0) move_to(0.0, 1.0, false);  // undo an in-place trial
        Field &t = w.trial, &Kt = w.Ktrial;
        const double gs = trial_pass(arrays(), shape, alpha, t.data());
        clipped = true;
        base_dirty = true;
        if (!std::isfinite(gs)) {
          Unew = kInf;
        } else {
          const double sc = mean_scale(t.data(), gs);
          displacement_of(t.data(), shape, sc, r.data());  // r is free until the pass below
          w.apply(r, Kt, w.kmul);
          std::swap(x, t);
          std::swap(Ku, Kt);
          Snew = pass(false, 0.0, 1.0, daniel);  // r, c of the trial; the base stays in t, Kt
          std::swap(x, t);
          std::swap(Ku, Kt);
          Unew = 0.5 * Snew.uKu;
        }
      }
      const double Enew = Unew + Snew.phi;
      if (std::isfinite(Enew) && all_finite(Snew) && Enew <= E0 + slack) {
        accepted = true;
        break;
      }
      ++diag_.backtracks;
      // Safeguarded quadratic interpolation of E(α) through E0, its slope psid and Enew.
      double next = 0.1 * alpha;
      if (std::isfinite(Enew)) {
        next = 0.5 * alpha;
        const double curv = 2.0 * (Enew - E0 - psid * alpha) / (alpha * alpha);
        if (curv > 0.0) next = std::clamp(-psid / curv, 0.1 * alpha, 0.5 * alpha);
      }
      alpha = next;
    }

    if (!accepted) {
      // Back to the base point; steepest descent next.
      if (a_app != 0.0 || s_app != 1.0) move_to(0.0, 1.0, false);
      else if (base_dirty) pass(false, 0.0, 1.0, false);  // r, c held the rejected trial
      U = U0;
      digest(S0);
      restart = true;
      if (++stalls > 3) {
        stop_msg = "line search failed to decrease the energy";
        break;
      }
      continue;
    }
    stalls = 0;
    if (clipped) {
      std::swap(x, w.trial);
      std::swap(Ku, w.Ktrial);
      ++diag_.clipped_steps;
    }
    U = Unew;
    kappa_prev = kappa;
    digest(Snew);
    beta_num = S.sxHd - (mu - shift) * S.sHd;
    // Daniel's β needs the Hessian at the base point along the full step: restart after a
    // negative-curvature or backtracked step.
    restart = negc || !first_try;
    exact_now = clipped;
    if (clipped) {
      since_exact = 0;
    } else if (++since_exact >= opt_.recompute_every) {
      if (!exact()) {
        stop_msg = "non-finite value on an exact recompute";
        break;
      }
      exact_now = true;
      since_exact = 0;
    }
  }

  // ---- the solved state (patch fields)
  const double pbar = periodic ? -mu : 0.0;
  st.gap.resize(n);
  st.displacement.resize(n);
  st.pressure.resize(n);
  double psum = 0.0;
  bool finite = true;
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const std::size_t k = std::size_t(iy) * mx + ix, kp = std::size_t(iy) * nx + ix;
      st.gap[kp] = x[k];
      st.displacement[kp] = x[k] - (hf[k] - delta);
      st.pressure[kp] = Ku[k] + pbar;
      psum += st.pressure[kp];
      finite = finite && std::isfinite(st.pressure[kp]) && std::isfinite(st.gap[kp]);
    }
  st.penetration = delta;
  st.mean_pressure = psum / double(n);
  res.energy = (U + Phi) * hs_.grid().cell_area();
  res.residual = residual;
  if (!finite && stop_msg.empty()) stop_msg = "non-finite values in the final state";
  const bool ok = stop_msg.empty() && residual <= tol && finite;
  std::string msg;
  if (!ok) {
    std::ostringstream s;
    s << "AdhesiveSolver stopped after " << res.iterations << " iterations at residual " << residual
      << (residual <= tol ? " <= " : " > ") << "tolerance " << tol;
    if (!stop_msg.empty()) s << ": " << stop_msg;
    msg = s.str();
  }
  return finish(ok, msg);
}

// ---------------------------------------------------------------- load control

SolveResult AdhesiveSolver::solve_load(double target, ContactState& st) {
  const auto t0 = std::chrono::steady_clock::now();
  SolveResult res;
  double pairs = 0.0;
  int iters = 0;
  Diagnostics total;
  auto inner = [&](double delta, ContactState& s) {
    diag_ = {};
    SolveResult r = std::visit([&](const auto& inter) { return solve_displacement(inter, delta, s); }, interaction_);
    pairs += r.fft_pairs;
    iters += r.iterations;
    total.restarts += diag_.restarts;
    total.backtracks += diag_.backtracks;
    total.negative_curvature += diag_.negative_curvature;
    total.clipped_steps += diag_.clipped_steps;
    total.exact_recomputes += diag_.exact_recomputes;
    ++total.load_iterations;
    return r;
  };
  auto finish = [&](bool ok, std::string msg, const SolveResult& last) {
    res = last;
    res.converged = ok;
    res.message = std::move(msg);
    res.fft_pairs = pairs;
    res.iterations = iters;
    res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    diag_ = total;
    return res;
  };

  const Grid& g = hs_.grid();
  const double ftol = 10.0 * opt_.tolerance * pscale_;
  const double hmin = Grid::min(h_), hmax = Grid::max(h_);
  const double span = std::max(hmax - hmin, interaction_range(interaction_));
  const bool warm = st.gap.size() == g.size();
  double step = std::max({(warm ? 1e-3 : 1e-2) * span, interaction_range(interaction_), 1e-12});
  double d0 = warm ? st.penetration : hmin;
  if (w_->periodic) d0 = std::min(d0, w_->hmean);

  ContactState s0 = st;
  SolveResult r0 = inner(d0, s0);
  if (!r0.converged) return finish(false, "load control: inner solve failed: " + r0.message, r0);
  double f0 = s0.mean_pressure - target;
  if (std::abs(f0) <= ftol) {
    st = std::move(s0);
    return finish(true, "", r0);
  }
  // Bracket: walk δ in the direction that changes p̄ towards the target (p̄ grows with δ on
  // a load-stable branch): secant steps from the last two points while the slope is
  // positive (at most 4x the previous step), doubling steps otherwise.
  const double dir = f0 < 0.0 ? 1.0 : -1.0;
  double a = d0, fa = f0;
  ContactState sa = s0;
  double b = d0, fb = f0;
  ContactState sb;
  SolveResult rb = r0;
  bool bracketed = false;
  bool have_slope = false;
  double slope = 0.0;
  int away = 0;
  for (int k = 0; k < opt_.max_load_iterations; ++k) {
    double next = step;
    if (have_slope && slope > 0.0) next = std::clamp(std::abs(fa / slope) * 1.05, 0.1 * step, 4.0 * step);
    b = a + dir * next;
    if (w_->periodic) b = std::min(b, w_->hmean);
    sb = sa;
    rb = inner(b, sb);
    if (!rb.converged) return finish(false, "load control: inner solve failed: " + rb.message, rb);
    fb = sb.mean_pressure - target;
    if (std::abs(fb) <= ftol) {
      st = std::move(sb);
      return finish(true, "", rb);
    }
    if ((fa < 0.0) != (fb < 0.0)) {
      bracketed = true;
      break;
    }
    if (w_->periodic && b >= w_->hmean) break;
    // Not moving towards the target three times in a row (past the pull-off, or out of
    // reach of the interaction, where p̄ stops changing): the branch does not reach it.
    away = std::abs(fb) >= std::abs(fa) ? away + 1 : 0;
    if (away >= 3) break;
    slope = (fb - fa) / (b - a);
    have_slope = true;
    step = std::abs(b - a) * (slope > 0.0 ? 1.0 : 2.0);
    a = b;
    fa = fb;
    sa = sb;
  }
  if (!bracketed) {
    std::ostringstream s;
    s << "load control: no penetration found that carries mean pressure " << target
      << " on this branch (beyond pull-off, or full contact); last mean pressure " << fb + target;
    st = std::move(sb);
    return finish(false, s.str(), rb);
  }
  // Illinois (modified regula falsi) on [a, b], warm-starting from the nearer state.
  int side = 0;
  for (int k = 0; k < opt_.max_load_iterations; ++k) {
    double x = b - fb * (b - a) / (fb - fa);
    if (!(x > std::min(a, b) && x < std::max(a, b))) x = 0.5 * (a + b);
    ContactState sx = std::abs(x - a) < std::abs(x - b) ? sa : sb;
    SolveResult rx = inner(x, sx);
    if (!rx.converged) return finish(false, "load control: inner solve failed: " + rx.message, rx);
    const double fx = sx.mean_pressure - target;
    if (std::abs(fx) <= ftol || std::abs(b - a) <= 1e-15 * std::max(1.0, std::abs(x))) {
      st = std::move(sx);
      std::string msg;
      const bool ok = std::abs(fx) <= ftol;
      if (!ok) {
        std::ostringstream s;
        s << "load control: the mean pressure jumps across penetration " << x << " (" << fa + target << " to "
          << fb + target << "): no stable state carries " << target;
        msg = s.str();
      }
      return finish(ok, msg, rx);
    }
    if ((fx < 0.0) == (fb < 0.0)) {
      b = x;
      fb = fx;
      sb = std::move(sx);
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = x;
      fa = fx;
      sa = std::move(sx);
      if (side == 1) fb *= 0.5;
      side = 1;
    }
  }
  st = std::abs(fa) < std::abs(fb) ? sa : sb;
  std::ostringstream s;
  s << "load control: no convergence in " << opt_.max_load_iterations << " outer iterations";
  return finish(false, s.str(), rb);
}

}  // namespace cmc
