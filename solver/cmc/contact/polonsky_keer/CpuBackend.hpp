// The CPU backend of a Polonsky-Keer solve (Iteration.hpp; its contract: Contract.hpp): the
// state's own fields, the operator's FFTW transforms, and OpenMP passes over the contact
// set only. In a header so that a test can run the iteration with another selection of
// points (tests/test_polonsky_keer.cpp: the GPU's, point by point) over the same
// transforms; CpuBackend.cpp runs the solve.
#pragma once

#include "cmc/contact/polonsky_keer/Compose.hpp"
#include "cmc/contact/polonsky_keer/Iteration.hpp"
#include "cmc/grid/Grid.hpp"
#include "cmc/grid/RowColumnFourier.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

namespace cmc {

namespace pk {

// Scans that touch only what they need. The contact set Ic = {p > 0} is kept as a byte
// mask beside p; at the challenge's loads it holds a few per cent of the points, so the
// passes that work on Ic alone skip eight points out of contact at a time, and the
// passes that must also find overlap elsewhere (w below a level) test eight points at a
// time with a comparison the compiler vectorises, and go point by point only through a
// block that holds something. Points are visited in index order, as a dense loop visits
// them, and a skipped point would have added nothing: every sum adds the same terms in the
// same order, so the result is the dense loop's to the last bit. (Measured on the
// ContactMechanics comparison surface of bench/bench_kernels.cpp at 2048², one thread: with
// dense loops the real-space passes took 6.1 of the 9.9 s a solve spent outside the
// transforms.)
//
// The fused sweeps go one step further (HostOf::sparse_row): the fields they transform
// (the direction t, the pressure p, the preconditioned gap z) are zero off the contact
// set, so each row is made in a buffer from the set's points alone, and the rest of the
// field is not read; the projection finds the points below the level from each block's
// least w, kept as w is made, instead of reading w. Of the four grid-sized streams a
// plain iteration read besides the transforms' own, three are gone: at 2048², 2 threads,
// 46.3-47.4 -> 38.6-44.5 ms an iteration (plain) and 74.7-79.0 -> 60.1-60.5 ms
// (preconditioned, whose z is now neither written whole nor read whole), the same bits.
// (cmc_bench BM_PolonskyKeerIteration; docs/performance.md.)
inline constexpr std::size_t kBlock = 8;
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

// The same over one row [b, e) whose blocks of eight (from b) have their least w in
// wmin (wmin[k] for the points b + 8k ... b + 8k + 7; row_minima() makes them): w itself
// is read only in the blocks that are visited. The least of eight below the level is one
// of them below it, so the same blocks are visited as by for_each_in_or_below. A row
// whose length is not a multiple of eight visits its last points always, as that does.
inline void row_minima(const double* w, std::size_t k, double* wmin) {
  for (std::size_t i = 0; i + kBlock <= k; i += kBlock) {
    double lo = HUGE_VAL;  // NaN never counts as below, as in any_below()
    for (std::size_t q = i; q < i + kBlock; ++q) lo = w[q] < lo ? w[q] : lo;
    wmin[i / kBlock] = lo;
  }
}
template <class F>
void for_each_in_or_below_row(const std::uint8_t* m, const double* wmin, double level, std::size_t b, std::size_t e,
                              F&& f) {
  std::size_t i = b;
  for (; i + kBlock <= e; i += kBlock)
    if (any_set(m + i) || wmin[(i - b) / kBlock] < level)
      for (std::size_t k = i; k < i + kBlock; ++k) f(k);
  for (; i < e; ++i) f(i);
}

// How the CPU backend visits the points of a pass: the block scans above. (A test visits
// them point by point instead: tests/test_polonsky_keer.cpp.) in_or_below_row() is
// in_or_below() over a row with its blocks' minima of w at hand (a visit may use them
// instead of w).
struct BlockVisit {
  template <class F>
  static void in(const std::uint8_t* m, std::size_t b, std::size_t e, F&& f) {
    for_each_in(m, b, e, f);
  }
  template <class F>
  static void in_or_below(const std::uint8_t* m, const double* w, double level, std::size_t b, std::size_t e, F&& f) {
    for_each_in_or_below(m, w, level, b, e, f);
  }
  template <class F>
  static void in_or_below_row(const std::uint8_t* m, const double*, const double* wmin, double level, std::size_t b,
                              std::size_t e, F&& f) {
    for_each_in_or_below_row(m, wmin, level, b, e, f);
  }
};

}  // namespace pk

// A solve's work arrays (PolonskyKeer::Options::keep_work keeps them between solves).
// Fused sweeps (a periodic grid held by one process): the row-column transform and the
// compliance in its layout. Unfused: G t for a linear step (made at the first one).
struct PolonskyKeer::Work {
  Field t, z, gt;
  Field wmin;  // fused: the least w of each block of eight of a row (pk::row_minima)
  std::vector<std::uint8_t> ic;
  std::unique_ptr<RowColumnFourier> rc;
  Field ker;
};

namespace pk {

// The CPU backend of a Polonsky-Keer solve (Iteration.hpp): the state's own fields,
// the operator's FFTW transforms, and OpenMP passes that visit the contact set only (the
// block scans above). The pressure and w = h + u are the state's pressure and
// displacement fields, so the solve works in place.
//
// On a periodic grid held by one process (and unless Options::fused_sweeps is off) the
// transforms are RowColumnFourier's, and the combined operations run their passes inside
// its sweeps, while the row or block is in cache: a pass over the points of a row next to
// that row's transform, a pass over modes between a block's column transforms. Elsewhere (a
// free boundary, a distributed grid) they are the passes and HalfSpace's transforms one
// after the other (compose::, Compose.hpp, as the GPU runs them).
template <class Visit>
struct HostOf : Fields, HostPasses {
  HalfSpace& hs;
  Field &P, &W;
  const Field& H;
  PolonskyKeer::Work& wk;
  RowColumnFourier* rc = nullptr;  // fused sweeps: the transform; else nullptr
  std::size_t nx = 0;
  std::size_t nb = 0;              // fused: blocks of eight a row (row_minima())
  double* wmin = nullptr;          // fused: their least w, ny × nb, made wherever w is
  Complex* spec = nullptr;         // the scratch spectrum (`out`)
  // Fused: rc's transforms count as the operator's (fft_pairs(), fft_seconds()).
  std::optional<TransformTally<HalfSpace>> tally;

  HostOf(HalfSpace& half_space, const Field& heights, ContactState& st, PolonskyKeer::Work& work, bool warm,
         bool precondition, bool fuse = true)
      : hs(half_space), P(st.pressure), W(st.displacement), H(heights), wk(work) {
    n = heights.size(), nspec = half_space.spectrum_size();
    points = double(half_space.grid().points()), transform_points = double(half_space.transform_points());
    nx = std::size_t(half_space.grid().nx);
    if (!warm) P.assign(n, 0.0);
    W.resize(n);
    // Not cleared: set_contact_set() fills t and the mask before any pass reads them, and
    // the preconditioner's fill writes all of z before its transform (two passes over the
    // grid less a solve; kept work arrays hold a previous solve's values).
    wk.t.resize(n);
    wk.ic.resize(n);
    if (precondition) wk.z.resize(n);
    p = P.data(), w = W.data(), t = wk.t.data(), z = wk.z.data(), m = wk.ic.data(), h = H.data();
    spec = hs.spectrum().data();
    ker = hs.compliance().data();
    const Grid& g = half_space.grid();
    if (fuse && half_space.row_column()) {
      if (!wk.rc || wk.rc->nx() != g.nx || wk.rc->ny() != g.ny) {
        wk.rc = std::make_unique<RowColumnFourier>(g.nx, g.ny);
        half_space.note_solver_plans("row-column (fused sweeps): " + wk.rc->plan_source());
        wk.ker.assign(wk.rc->spectrum_size(), 0.0);
        wk.rc->reorder(hs.compliance().data(), wk.ker.data());
      }
      rc = wk.rc.get();
      ker = wk.ker.data();
      nb = nx / kBlock;
      wk.wmin.resize(std::size_t(g.ny) * nb);
      wmin = wk.wmin.data();
      spec = hs.scratch_spectrum(rc->spectrum_size());  // its layout is longer than the half-space's
      const RowColumnFourier* r = rc;
      tally.emplace(hs, [r] { return TransformCounts{r->forward_count(), r->inverse_count(), r->seconds()}; });
    } else {
      wk.rc.reset();
      wk.ker = Field();
      wk.wmin = Field();
    }
    out = reinterpret_cast<double*>(spec);
  }
  HostOf(const HostOf&) = delete;
  HostOf& operator=(const HostOf&) = delete;

  template <class Acc, class F>
  Acc reduce_in(const std::uint8_t* mask, std::size_t k, F f) {
    // A local record, merged once: its sums stay in registers (acc is in memory, where the
    // compiler must assume the field writes may reach it).
    return Grid::parallel_reduce<Acc>(k, [&](std::size_t b, std::size_t e, Acc& acc) {
      Acc local;
      Visit::in(mask, b, e, [&](std::size_t i) { f(i, local); });
      acc.merge(local);
    });
  }
  template <class Acc, class F>
  Acc reduce_in_or_below(const std::uint8_t* mask, const double* v, double level, std::size_t k, F f) {
    return Grid::parallel_reduce<Acc>(k, [&](std::size_t b, std::size_t e, Acc& acc) {
      Acc local;
      Visit::in_or_below(mask, v, level, b, e, [&](std::size_t i) { f(i, local); });
      acc.merge(local);
    });
  }
  double sum(const double* v) const { return Grid::sum({v, n}); }

  using None = RowColumnFourier::None;
  static constexpr auto no_row_pass = [](std::size_t, None&) {};
  // The transforms of compose:: (Contract.hpp, TransformParts): unfused only, where the
  // combined operations below are compose::'s (rc is null).
  void forward_p() { hs.forward(P); }
  double curvature_t() {
    hs.forward(wk.t);
    return hs.quadratic_form(hs.spectrum(), hs.compliance());
  }
  void inverse_w() { hs.inverse(W); }
  void inverse_gt() {
    wk.gt.resize(n);
    hs.inverse(wk.gt);
    gt = wk.gt.data();
  }
  void stiffness_z() { hs.apply(z, z, hs.stiffness()); }

  // ---- the combined operations (Contract.hpp)
  // A row pass of forward_rows_from() for a field v that is zero off the mask (t, p and
  // z are: Run keeps them so): the row starts as zeros, and for each point i the visit
  // selects, f(i, acc) (which may write v[i]), then the row takes v[i]. So v is read only
  // where the visit goes, a few per cent of the grid at the challenge's loads, instead of
  // whole rows from memory. visit(j, b, e, g) calls g for row j's points [b, e) that the
  // pass visits: Visit::in over the mask, or the projection's Visit::in_or_below_row.
  template <class Acc, class F>
  auto sparse_row(const std::uint8_t* mask, const double* v, F f) const {
    return sparse_row_by<Acc>(v, f, [mask](std::size_t, std::size_t b, std::size_t e, auto&& g) {
      Visit::in(mask, b, e, g);
    });
  }
  template <class Acc, class F, class V>
  auto sparse_row_by(const double* v, F f, V visit) const {
    return [v, f, visit, nxx = nx](std::size_t j, double* row, Acc& acc) {
      const std::size_t b = j * nxx;
      std::memset(row, 0, nxx * sizeof(double));
      visit(j, b, b + nxx, [&](std::size_t i) {
        f(i, acc);
        row[i - b] = v[i];
      });
    };
  }
  template <class Acc, class F>
  Acc direction_and_curvature(const std::uint8_t* mask, F f, double& curvature) {
    if (!rc) return compose::direction_and_curvature<Acc>(*this, mask, f, curvature);
    const Acc a = rc->forward_rows_from<Acc>(spec, sparse_row<Acc>(mask, t, f));
    // <t, G t> = Σ_q weight(q) G(q) |t̂_q|² (HalfSpace::quadratic_form), block by block.
    const double* k = ker;
    const Complex* s = spec;
    const int nxi = int(nx);
    curvature = rc->columns<SumReduction>(spec, RowColumnFourier::kForward, [&](const RowColumnFourier::Block& B, SumReduction& acc) {
                    // Block B's columns one after the other, one weight a column.
                    double d = 0.0;
                    for (int c = 0; c < B.width; ++c) {
                      const std::size_t q0 = B.begin + std::size_t(c) * B.stride, q1 = q0 + std::size_t(B.rows);
                      double dc = 0.0;
                      for (std::size_t q = q0; q < q1; ++q) dc += k[q] * std::norm(s[q]);
                      d += r2c_mode_weight(B.iqx0 + c, nxi) * dc;
                    }
                    acc.v += d;
                  }).v;
    return a;
  }
  // How a step makes w along a row from the inverse transform's output u there (Parts.hpp:
  // exact_w after an exact step, LinearW after a linear one).
  static void add_heights(double* w_, const double* h_, const double* u, std::size_t k) {
    for (std::size_t i = 0; i < k; ++i) w_[i] = exact_w(h_[i], u[i]);
  }
  struct LinearRow {
    LinearW make;
    void operator()(double* w_, const double* h_, const double* u, std::size_t k) const {
      for (std::size_t i = 0; i < k; ++i) w_[i] = make(h_[i], w_[i], u[i]);
    }
  };
  // w = h + G (s p). Fused: p's rows, then per block its column transforms, the compliance
  // times s, and the inverse column transforms, all in the scratch spectrum, then row by
  // row the inverse into a buffer, w = h + that row, and the gap sums. No spectrum of p or
  // of h is held or streamed: the pass over the modes reads the compliance alone, and the
  // sweep works in place. (A sweep that transformed p into p̂, wrote s p̂ back, and wrote
  // G s p̂ + ĥ/N into a second spectrum took 27.3–27.9 ms at 2048², 2 threads, against
  // 26.2–26.7 ms in place and 22.4–22.6 ms for the bare pair.)
  template <class Acc, class F>
  Acc exact_and_gap_sums(double s, const std::uint8_t* mask, double level, F f) {
    if (!rc) return compose::exact_and_gap_sums<Acc>(*this, s, mask, level, f);
    rc->forward_rows_from<None>(spec, sparse_row<None>(mask, p, no_row_pass));
    return exact_after_rows<Acc>(s, mask, level, f);
  }
  // The rest of exact_and_gap_sums() once p's rows are transformed into the scratch.
  template <class Acc, class F>
  Acc exact_after_rows(double s, const std::uint8_t* mask, double level, F f) {
    return compliance_and_rows<Acc>(RowColumnFourier::kForward | RowColumnFourier::kInverse, s, mask, level, f,
                                    add_heights);
  }
  // w = h + G p' for p' = s (p − τ t): G t from t's spectrum in `out` (one inverse), then
  // w = h + s ((w − h) − τ G t), and the gap sums.
  template <class Acc, class F>
  Acc linear_and_gap_sums(double s, double tau, const std::uint8_t* mask, double level, F f) {
    if (!rc) return compose::linear_and_gap_sums<Acc>(*this, s, tau, mask, level, f);
    return compliance_and_rows<Acc>(RowColumnFourier::kInverse, 1.0, mask, level, f, LinearRow{{s, tau}});
  }
  // Fused: the column sweep `what` over the scratch with the compliance times `scale` on
  // every mode, then row by row the inverse into a buffer, make_w(w's row, h's row, that
  // row, nx), and the gap sums f on the row.
  template <class Acc, class F, class MakeW>
  Acc compliance_and_rows(int what, double scale, const std::uint8_t* mask, double level, F f, MakeW make_w) {
    const double* k = ker;
    Complex* o = spec;
    rc->columns<None>(spec, what, [&](const RowColumnFourier::Block& B, None&) {
      B.each([&](std::size_t q) { o[q] *= scale * k[q]; });
    });
    const double* hh = h;
    double* ww = w;
    const std::size_t nxx = nx;
    return rc->inverse_rows_through<Acc>(spec, [&](std::size_t j, const double* row, Acc& acc) {
      make_w(ww + j * nxx, hh + j * nxx, row, nxx);
      row_minima(ww + j * nxx, nxx, wmin + j * nb);
      Visit::in_or_below_row(mask, ww, wmin + j * nb, level, j * nxx, (j + 1) * nxx, [&](std::size_t i) { f(i, acc); });
    });
  }
  // Run::project(). Fused, the pass runs row by row: inside p's transform where the step
  // is likely exact (each row's points right before the row's r2c, which then finds them in
  // cache; the step is then made exact even where choose() would have allowed a linear one,
  // since the rows overwrote t's spectrum), else on its own; in both cases a thread's sums
  // run over its rows in order and merge in thread order, as the forward row sweep's do,
  // so the pass's sums, and the solve, do not depend on which route it took.
  template <class Acc, class StepAcc, class P, class C, class F>
  Acc project_and_gap_sums(P pass, C choose, bool likely_exact, const std::uint8_t* mask, double level, F f,
                           StepAcc& st, StepChoice& c) {
    const double* wv = w;
    const double* lo = wmin;
    const std::size_t nxx = nx, nbb = nb;
    // The points of row j in the mask or below the level, found from the blocks' minima.
    const auto visit = [=](std::size_t j, std::size_t b, std::size_t e, auto&& g) {
      Visit::in_or_below_row(mask, wv, lo + j * nbb, level, b, e, g);
    };
    const auto row = [&](std::size_t j, StepAcc& acc) {
      visit(j, j * nxx, (j + 1) * nxx, [&](std::size_t i) { pass(i, acc); });
    };
    if (rc && likely_exact) {
      // The pass writes p at the points it visits, and p is zero elsewhere.
      st = rc->forward_rows_from<StepAcc>(spec, sparse_row_by<StepAcc>(p, pass, visit));
      c = choose(st);
      c.exact = true;
      return c.ok ? exact_after_rows<Acc>(c.s, mask, level, f) : Acc{};
    }
    if (rc)
      st = Grid::parallel_reduce<StepAcc>(
          std::size_t(rc->ny()),
          [&](std::size_t j0, std::size_t j1, StepAcc& acc) {
            StepAcc local;
            for (std::size_t j = j0; j < j1; ++j) row(j, local);
            acc.merge(local);
          },
          std::size_t(rc->nx()) * std::size_t(rc->ny()));
    else
      st = reduce_in_or_below<StepAcc>(mask, w, level, n, pass);
    c = choose(st);
    if (!c.ok) return Acc{};
    return c.exact ? exact_and_gap_sums<Acc>(c.s, mask, level, f) : linear_and_gap_sums<Acc>(c.s, c.tau, mask, level, f);
  }
  // The stiffness is taken from the compliance, (1/N)² / G = E*|q|/(2N), 0 at q = 0, as the
  // GPU backend does (one multiplier less to hold and to stream).
  template <class Acc, class Fill, class F>
  Acc stiffness_and_sums(Fill fill, const std::uint8_t* mask, F f) {
    if (!rc) return compose::stiffness_and_sums<Acc>(*this, fill, mask, f);
    // fill gives z = 0 off the mask: the rows are made from the mask's points alone, and z
    // is written (and afterwards read) there only.
    rc->forward_rows_from<None>(spec, sparse_row<None>(mask, z, [fill](std::size_t i, None&) { fill(i); }));
    const double* k = ker;
    Complex* s = spec;
    const double nn = 1.0 / (transform_points * transform_points);
    rc->columns<None>(spec, RowColumnFourier::kForward | RowColumnFourier::kInverse,
                      [&](const RowColumnFourier::Block& B, None&) {
                        B.each([&](std::size_t q) { s[q] *= stiffness_from_compliance(k[q], nn); });
                      });
    double* zz = z;
    const std::size_t nxx = nx;
    return rc->inverse_rows_through<Acc>(spec, [&](std::size_t j, const double* row, Acc& acc) {
      const std::size_t b = j * nxx;
      Visit::in(mask, b, b + nxx, [&](std::size_t i) {
        zz[i] = row[i - b];
        f(i, acc);
      });
    });
  }
};
using Host = HostOf<BlockVisit>;

}  // namespace pk

}  // namespace cmc
