// The adhesive CG's CPU backend: its fields (AdhesiveSolver::Work, below) and the few fused
// per-point passes over whole transform-grid fields that an iteration (Iteration.hpp) is
// made of (see AdhesiveSolver.hpp for the algorithm). Each is one pass over memory; threads
// and the combination of partial sums are the grid layer's (Grid::parallel_reduce over
// rows), so another backend can replace them as a whole.
//
// Fields (transform grid, row-major, rows of mx points): x holds the gap g on the patch
// (the first nx points of the first ny rows) and the displacement u in the padding of a
// free boundary (everything else); on the patch u = g − (h − δ) is formed only where the
// energy needs it. Ku = K u, d the search direction, Kd = K d, r the gradient
// ∂E/∂u = K u + φ'(g) = K u − f(g), c = φ''(g), bound the wall set of the last pass.
#pragma once

#include "cmc/contact/Interaction.hpp"
#include "cmc/contact/adhesive_cg/AdhesiveSolver.hpp"
#include "cmc/grid/Grid.hpp"
#include "cmc/grid/Ranks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace cmc::adhesive {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Reductions of the evaluation pass (see the residual definition in AdhesiveSolver.hpp).
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
  void merge(const Sums& o);
  bool finite() const {
    return std::isfinite(uKu) && std::isfinite(phi) && std::isfinite(sxx) && std::isfinite(sx) && std::isfinite(gsum);
  }
};

// Reductions of the direction pass.
struct DirSums {
  double psid = 0.0;    // ψ·d
  double cd2 = 0.0;     // Σ φ''(g) d²: the interaction's curvature along d
  double dmax = 0.0;    // max |d|
  double afeas = kInf;  // largest step before a free point reaches the wall
  double dsum = 0.0;    // Σ d over the patch
  void merge(const DirSums& o);
};

// The arrays of one solve, as raw pointers (the kernels promise no aliasing).
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
  const double* h;   // heights on the transform grid (0 in the padding)
  const double* Kh;  // K h (periodic only)
  double delta;
  std::size_t size() const { return std::size_t(mx) * std::size_t(my); }
  std::size_t row(int iy) const { return std::size_t(iy) * std::size_t(mx); }
  std::size_t patch_end(int iy) const { return row(iy) + (iy < ny ? std::size_t(nx) : 0); }
};

// Parameters of one evaluation pass: a step x <- sc (x + a d) (Step; Scale when sc != 1),
// `ml` classifies the wall set (g = 0 and r >= ml), `sh` shifts the free-set moments.
struct EvalStep {
  double a = 0.0, sc = 1.0, ml = 0.0, sh = 0.0;
};

namespace detail {
template <bool Step, bool Scale, bool Daniel, bool Track, class I>
void eval_patch_row(const I& inter, const Arrays& A, const Shape& S, const EvalStep& p, std::size_t k0,
                    std::size_t k1, Sums& s);
template <bool Step, bool Daniel>
void eval_padding_row(const Arrays& A, const EvalStep& p, std::size_t k0, std::size_t k1, Sums& s);
}  // namespace detail

// The evaluation pass: r = Ku + φ'(g) = Ku − f(g), c = φ''(g), and the sums. Step: fused
// with the incremental update x += a d, Ku += a Kd (then uKu = Σ Ku_old·d); Step and Scale:
// x <- s (x + a d) with the exact K u update through K h (then uKu = Σ u·Ku). Otherwise
// uKu = Σ u·Ku (reads h). Daniel: also the sums of Daniel's β (reads Kd and the old c).
// Track: count wall-set changes against `bound`.
template <bool Step, bool Scale, bool Daniel, bool Track, class I>
Sums eval_pass(const I& inter, const Arrays& A, const Shape& S, const EvalStep& p) {
  return Grid::parallel_reduce<Sums>(
      std::size_t(S.my),
      [&](std::size_t r0, std::size_t r1, Sums& acc) {
        Sums s;
        for (std::size_t iy = r0; iy < r1; ++iy) {
          const std::size_t row = S.row(int(iy)), pe = S.patch_end(int(iy)), re = row + S.mx;
          detail::eval_patch_row<Step, Scale, Daniel, Track>(inter, A, S, p, row, pe, s);
          detail::eval_padding_row<Step, Daniel>(A, p, pe, re, s);
        }
        acc.merge(s);
      },
      S.size());
}

// The evaluation pass with its compile-time flags chosen at run time.
template <class I>
Sums evaluate(const I& inter, const Arrays& A, const Shape& S, const EvalStep& p, bool step, bool daniel, bool track) {
  const bool scale = step && p.sc != 1.0;
  auto go = [&]<bool St, bool Sc>() {
    if (track) return daniel ? eval_pass<St, Sc, true, true>(inter, A, S, p) : eval_pass<St, Sc, false, true>(inter, A, S, p);
    return daniel ? eval_pass<St, Sc, true, false>(inter, A, S, p) : eval_pass<St, Sc, false, false>(inter, A, S, p);
  };
  if (scale) return go.template operator()<true, true>();
  if (step) return go.template operator()<true, false>();
  return go.template operator()<false, false>();
}

// The direction pass: d = −ψ + β (d_old − m_old) on the free set (ψ = r − μ), 0 on the
// wall set, projected on the feasible cone (d >= 0 where g = 0); `ml` classifies the wall
// set as in the last evaluation pass. Track: record the wall set in `bound`.
DirSums direction_pass(const Arrays& A, const Shape& S, double mu, double ml, double beta, double m_old, bool track);

// The projected trial point t = x + α d with g clipped at 0; returns Σ g over the patch.
double trial_pass(const Arrays& A, const Shape& S, double alpha, double* t);

// Scale the patch gaps by s (the periodic mean-gap projection; 1 otherwise) and form
// u = x − (h − δ) on the patch, x in the padding: the input of an exact K u.
void displacement_of(double* x, const Shape& S, double s, double* u);

// Σ x over the first n points (the patch of a periodic grid, which has no padding).
double patch_sum(const double* x, std::size_t n);

// ---------------------------------------------------------------- row kernels

namespace detail {

// One row of the patch. Blocks of B points: first the update and the interaction (which
// may call exp(): a call clobbers every vector register, so no accumulator is live across
// it), then the reductions from L1-resident values.
template <bool Step, bool Scale, bool Daniel, bool Track, class I>
void eval_patch_row(const I& inter, const Arrays& A, const Shape& S, const EvalStep& p, std::size_t row,
                    std::size_t pe, Sums& s) {
  double* __restrict x = A.x;
  double* __restrict Ku = A.Ku;
  double* __restrict r = A.r;
  double* __restrict c = A.c;
  const double* __restrict d = A.d;
  const double* __restrict Kd = A.Kd;
  const double* __restrict h = S.h;
  const double* __restrict Kh = S.Kh;
  const double a = p.a, sc = p.sc, ml = p.ml, sh = p.sh, delta = S.delta;
  constexpr std::size_t B = 256;
  double fb[B], cb[B];
  for (std::size_t k0 = row; k0 < pe; k0 += B) {
    const std::size_t k1 = std::min(pe, k0 + B);
    double phi = s.phi;
    for (std::size_t k = k0; k < k1; ++k) {
      double g = x[k];
      if constexpr (Step && Scale) {
        g = sc * (g + a * d[k]);  // g <- s (g + a d)
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
    s.phi = phi;
    double uKu = s.uKu, nF = s.nF, sx = s.sx, sxx = s.sxx, sxHd = s.sxHd, sHd = s.sHd, sxd = s.sxd, sd = s.sd;
    double rmax = s.rmax, rmin = s.rmin, rminc = s.rmin_contact, gsum = s.gsum;
    long changed = s.changed;
    for (std::size_t k = k0; k < k1; ++k) {
      const double g = x[k], dk = d[k];
      double kuk = Ku[k];
      if constexpr (Step && Scale) {
        kuk = sc * (kuk + a * Kd[k]) + (sc - 1.0) * Kh[k];  // exact: K u <- s (K u + a K d) + (s − 1) K h
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
      if constexpr (Track) changed += is_bound != bool(A.bound[k]);
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
    s.uKu = uKu, s.nF = nF, s.sx = sx, s.sxx = sxx, s.sxHd = sxHd, s.sHd = sHd, s.sxd = sxd, s.sd = sd;
    s.rmax = rmax, s.rmin = rmin, s.rmin_contact = rminc, s.gsum = gsum, s.changed = changed;
  }
}

// One row of the padding of a free boundary: no interaction, no wall, μ = 0 (shift 0).
template <bool Step, bool Daniel>
void eval_padding_row(const Arrays& A, const EvalStep& p, std::size_t pe, std::size_t re, Sums& s) {
  double* __restrict x = A.x;
  double* __restrict Ku = A.Ku;
  double* __restrict r = A.r;
  const double* __restrict d = A.d;
  const double* __restrict Kd = A.Kd;
  for (std::size_t k = pe; k < re; ++k) {
    double uk = x[k], kuk = Ku[k];
    const double dk = d[k];
    if constexpr (Step) {
      s.uKu += kuk * dk;
      uk += p.a * dk;
      kuk += p.a * Kd[k];
      x[k] = uk;
      Ku[k] = kuk;
    } else {
      s.uKu += uk * kuk;
    }
    r[k] = kuk;
    s.out_abs = std::max(s.out_abs, std::abs(kuk));
    s.sxx += kuk * kuk;
    if constexpr (Daniel) s.sxHd += kuk * Kd[k];
    s.sxd += kuk * dk;
  }
}

}  // namespace detail
}  // namespace cmc::adhesive

namespace cmc {

// The transform-grid fields of the solver (made in its constructor, kept for the whole run).
struct AdhesiveSolver::Work {
  adhesive::Shape shape{};  // dimensions, heights and K h; delta is set per solve
  bool periodic = true;
  std::size_t n = 0, M = 0;  // patch and transform-grid sizes (this rank's slab of them)
  double N = 0.0;            // points of the whole patch (all ranks)
  Field hf;  // heights on the transform grid (patch part; 0 in the padding)
  Field x, Ku, d, Kd, r, c, trial, Ktrial;
  Field Kh;  // K h (periodic): makes the mean-gap rescale g <- s g an exact linear update
  std::vector<unsigned char> bound;
  double hmean = 0.0;
  // A free boundary in a distributed run: the padded grid's rows are split on their own
  // (HalfSpace.hpp), so the patch's rows move between the contact grid's slabs and the
  // padded slabs (the patch is the first ny of its 2ny rows). Null otherwise.
  std::unique_ptr<RowExchange> exchange;
  // A contact-grid field as the padded slab's rows (0 in the padding), and back.
  void to_padded(const Field& f, Field& out) const {
    out.assign(M, 0.0);
    if (exchange) {
      exchange->forward(f.data(), out.data());
    } else {
      for (int iy = 0; iy < shape.ny; ++iy) std::copy_n(&f[std::size_t(iy) * shape.nx], shape.nx, &out[shape.row(iy)]);
    }
  }
  adhesive::Arrays arrays() { return {x.data(), Ku.data(), r.data(), c.data(), d.data(), Kd.data(), bound.data()}; }
};

}  // namespace cmc
