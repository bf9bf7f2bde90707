// The CPU backend of a Polonsky-Keer solve (PolonskyKeerRun.hpp): the state's own fields,
// the operator's FFTW transforms, and OpenMP passes over the contact set only. In a header
// of its own so that a test can run the iteration with another selection of points
// (tests/test_polonsky_keer.cpp: the GPU's, point by point) over the same transforms.
#pragma once

#include "cmc/contact/PolonskyKeerRun.hpp"
#include "cmc/grid/Grid.hpp"

#include <cstdint>
#include <cstring>
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
// same order, so the result is the dense loop's to the last bit. (Measured on the peer's
// problem at 2048², one thread: the real-space passes of an iteration took 6.1 of its
// 9.9 s outside the transforms before.)
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

}  // namespace pk

// A solve's work arrays (PolonskyKeer::Options::keep_work keeps them between solves).
struct PolonskyKeer::Work {
  Spectrum p_hat, h_hat;
  Field t, z;
  std::vector<std::uint8_t> ic;
};

namespace pk {

// The CPU backend of a Polonsky-Keer solve (PolonskyKeerRun.hpp): the state's own fields,
// the operator's FFTW transforms, and OpenMP passes that visit the contact set only (the
// block scans above). The pressure and w = h + u are the state's pressure and
// displacement fields, so the solve works in place.
struct Host : Fields {
  HalfSpace& hs;
  Field &P, &W;
  const Field& H;
  PolonskyKeer::Work& wk;

  Host(HalfSpace& half_space, const Field& heights, ContactState& st, PolonskyKeer::Work& work, bool warm,
       bool precondition)
      : hs(half_space), P(st.pressure), W(st.displacement), H(heights), wk(work) {
    n = heights.size(), nspec = half_space.spectrum_size();
    points = double(half_space.grid().points()), transform_points = double(half_space.transform_points());
    if (!warm) P.assign(n, 0.0);
    W.resize(n);
    wk.t.assign(n, 0.0);
    wk.ic.resize(n);  // filled by set_contact_set() before any pass reads it
    if (precondition) wk.z.assign(n, 0.0);
    for (Spectrum* s : {&wk.p_hat, &wk.h_hat}) s->resize(nspec);
    p = P.data(), w = W.data(), t = wk.t.data(), z = wk.z.data(), m = wk.ic.data(), h = H.data();
    p_hat = reinterpret_cast<double*>(wk.p_hat.data());
    h_hat = reinterpret_cast<double*>(wk.h_hat.data());
    out = reinterpret_cast<double*>(hs.spectrum().data());
    ker = hs.compliance().data();
  }

  template <class F>
  void all(std::size_t k, F f) {
    Grid::parallel_for(k, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) f(i);
    });
  }
  template <class Acc, class F>
  Acc reduce_in(const std::uint8_t* mask, std::size_t k, F f) {
    // A local record, merged once: its sums stay in registers (acc is in memory, where the
    // compiler must assume the field writes may reach it).
    return Grid::parallel_reduce<Acc>(k, [&](std::size_t b, std::size_t e, Acc& acc) {
      Acc local;
      for_each_in(mask, b, e, [&](std::size_t i) { f(i, local); });
      acc.merge(local);
    });
  }
  template <class Acc, class F>
  Acc reduce_in_or_below(const std::uint8_t* mask, const double* v, double level, std::size_t k, F f) {
    return Grid::parallel_reduce<Acc>(k, [&](std::size_t b, std::size_t e, Acc& acc) {
      Acc local;
      for_each_in_or_below(mask, v, level, b, e, [&](std::size_t i) { f(i, local); });
      acc.merge(local);
    });
  }
  double sum(const double* v) const { return Grid::sum({v, n}); }

  void forward_p() { hs.forward(P, wk.p_hat); }
  void forward_h() { hs.forward(H, wk.h_hat); }
  double curvature_t() {
    hs.forward(wk.t);
    return hs.quadratic_form(hs.spectrum(), hs.compliance());
  }
  void inverse_w() { hs.inverse(W); }
  void stiffness_z() { hs.apply(z, z, hs.stiffness()); }
};

}  // namespace pk

}  // namespace cmc
