// Observables of a solved contact state: contact area (raw and perimeter-corrected),
// means, contact patches, histograms, radial power spectra, cross-sections and the
// contact stiffness along a load path. Pure functions over (Grid, Field); no IO.
//
// Conventions (see notes/reference-solutions.md): compressive pressure p > 0,
// adhesive tension p < 0, gap g >= 0. Reduced units: lengths in L, pressure in E*.
// Grid point (ix, iy) sits at x = ix*dx, y = iy*dy (index iy*nx + ix); all
// neighbourhoods are periodic.
//
// Contact: the mask, the fractions and what counts as repulsive or attractive come
// from the one ContactRule of contact/ContactRule.hpp.
#pragma once

#include "cmc/contact/ContactRule.hpp"
#include "cmc/grid/Grid.hpp"

#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

namespace cmc {

// ---- Contact area ----------------------------------------------------------------
// Number of contact/non-contact faces between 4-neighbours (periodic), each counted
// once. For ny == 1 only x-neighbours exist.
long long contact_edges(const Grid& grid, const Mask& mask);

// Perimeter-corrected contact area (Yastrebov, Anciaux, Molinari, "On the accurate
// computation of the true contact-area in mechanical contact of random rough
// surfaces", Tribol. Int. 114 (2017) 161, arXiv:1701.02727; used in their JMPS 107
// (2017) 469, arXiv:1704.05650). A discrete solver closes a thin layer of points
// just outside the continuum contact line, so the pixel count overestimates the area
// by an amount proportional to the contact-line length. The correction subtracts
//     alpha * N_edges * dx * dy,   alpha = (pi - 1 + ln 2) / 24 ~= 0.1181,
// with N_edges the number of contact/non-contact faces counted on the grid.
// Sources read:
// - the paper itself (ar5iv.labs.arxiv.org/html/1701.02727): only its abstract and the
//   opening of the introduction could be read. Verified there: the correction is
//   geometric and needs only the length of the contact/non-contact interfaces.
// - a third-party reproduction of the paper (github.com/cofebem/aspher,
//   doc/convergence_study/repro/REPORT.md, citing Tribol. Int. 114 (2017) 161-171)
//   states the paper's correction as A* = A_d - (pi - 1 + ln 2)/24 * S_d * dx with
//   S_d = M dx and M the number of contact/non-contact switches along all grid lines,
//   i.e. exactly alpha * N_edges * dx * dy as here, and explains the coefficient as
//   beta * pi/4: beta = (pi - 1 + ln 2)/(6 pi) ~ 0.1504, the mean area of the smaller
//   part of a unit cell cut by a random line, and pi/4 turning the grid (Manhattan)
//   perimeter into the Euclidean one.
// NOT verified: the number of the equation in the paper (its body text was not
// reachable), and the value against the paper's own text rather than that secondary
// source. Observables.cpp records the check made here (Hertz on 1024^2: 0.056-0.14 dx^2
// per edge, mean ~0.095, the size of alpha).
// Returns a fraction of the nominal area. For ny == 1 the 2-D correction does not
// apply and the raw fraction is returned.
inline constexpr double kYastrebovAlpha = (std::numbers::pi - 1.0 + std::numbers::ln2) / 24.0;
double corrected_contact_fraction(const Grid& grid, const Mask& mask);

// ---- Contact patches (periodic connected components) --------------------------
enum class Connectivity { Four = 4, Eight = 8 };

struct Patches {
  // Per grid point: -1 outside every patch, else 0..count()-1, numbered in scan
  // order of each patch's first point.
  std::vector<std::int32_t> label;
  std::vector<double> area;       // per patch, in L^2 (points * dx * dy)
  std::vector<double> perimeter;  // per patch, in L: summed length of its faces to
                                  // non-contact 4-neighbours ("staircase" length,
                                  // ~4/pi times the Euclidean one for isotropic lines)
  std::size_t count() const { return area.size(); }
};
// Union-find over the periodic grid; a patch that wraps across x and/or y counts once.
// Single-process (labels are global); requires size() < 2^31.
Patches label_patches(const Grid& grid, const Mask& mask, Connectivity c = Connectivity::Four);

// ---- Histograms ------------------------------------------------------------------
// n bins on [lo, hi], uniform in v (linear) or in log v (log, lo > 0). Bins are
// [e_i, e_{i+1}); the last one also holds v == hi.
struct Bins {
  double lo = 0.0, hi = 1.0;
  int n = 1;
  bool log = false;
  static Bins linear(double lo, double hi, int n);
  static Bins logarithmic(double lo, double hi, int n);
  // ceil(per_decade * log10(hi/lo)) log bins from lo, each 10^(1/per_decade) wide.
  static Bins per_decade(double lo, double hi, int per_decade);
  // [min, max] of the finite values (positive ones only for log; for log the lower
  // end is raised to max * min_ratio at most, so rounding noise near 0 does not
  // stretch the axis).
  static Bins spanning(std::span<const double> values, int n, bool log = false, double min_ratio = 1e-12);
  double edge(int i) const;    // i = 0..n
  double width(int i) const { return edge(i + 1) - edge(i); }
  double center(int i) const;  // arithmetic (linear) or geometric (log) midpoint
  int index(double v) const;   // -1 below lo (or NaN), n above hi
};

// Normalisation: density[i] = counts[i] / (total * width(i)), total = ALL values
// passed (binned, out of range and excluded). So sum_i density[i]*width(i) equals
// the fraction of values that were binned, and density is a probability density per
// unit of v (for log bins too: plot density against center() on log-log axes).
struct Histogram {
  Bins bins;
  std::vector<long long> counts;
  std::vector<double> density;
  long long total = 0, below = 0, above = 0;
  long long excluded = 0;  // v == 0 exactly when exclude_zero, and non-finite values
  double fraction(long long c) const { return total ? double(c) / double(total) : 0.0; }
  double binned_fraction() const { return fraction(total - below - above - excluded); }
};
Histogram histogram(std::span<const double> values, const Bins& bins, bool exclude_zero = false);

// Stress distribution P(p): linear bins over [min p, max p]; the p == 0 delta peak
// (non-contact points) goes to `excluded` (its fraction is 1 - contact area).
Histogram stress_distribution(const Field& pressure, int nbins);
// Gap distribution P(g): log bins, per_decade per decade, from the smallest positive
// gap (floored at 1e-12 max g) to the largest; g == 0 (contact) goes to `excluded`.
// Throws std::invalid_argument when no gap is positive (full contact).
Histogram gap_distribution(const Field& gap, int per_decade);
// Patch-size distribution (Campana, Müser, Robbins, J. Phys.: Condens. Matter 20
// (2008) 354013, Figs. 4-5): counts = number of patches per log bin of area,
// density = probability density of patch area (normalised over patches). Bins start
// half a bin below one cell, so integer multiples of a cell never sit on a bin edge.
Histogram patch_size_distribution(const Grid& grid, const Patches& patches, int per_decade = 5);

// ---- Radially averaged power spectrum ----------------------------------------
// With f^(q) = (1/N) sum_x f(x) exp(-i q.x) (so f(x) = sum_q f^(q) exp(i q.x)),
// Parseval gives  variance(f) = sum_{q != 0} |f^(q)|^2.  Per |q| bin:
//   power[b] = sum of |f^(q)|^2 over all modes (full q-plane) with |q| in bin b, so
//              sum_b power[b] + outside == variance;
//   psd[b]   = (A/(2 pi)^2) * mean |f^(q)|^2 over those modes: the isotropic spectral
//              density C(|q|) with  integral d^2q C(q) = variance  (1-D, ny == 1:
//              L/(2 pi) instead, integral dq over q in (-inf, inf)).
// A cosine A cos(k.x) puts A^2/2 into the bin holding |k|.
struct RadialSpectrum {
  Bins bins;                      // in |q|, angular wavenumber in 1/L
  std::vector<double> q;          // mean |q| of the modes in the bin (0 if empty)
  std::vector<double> power;
  std::vector<double> psd;
  std::vector<long long> modes;   // number of q-plane modes in the bin
  double variance = 0.0;          // sum over all q != 0
  double outside = 0.0;           // power of q != 0 modes outside the bins
};
// Uses `fourier` (its spectrum buffer is overwritten); it must match the grid.
RadialSpectrum radial_spectrum(const Grid& grid, Fourier& fourier, const Field& f, const Bins& qbins);
// Default bins: width q0 = 2 pi / max(lx, ly), centred on q0, 2 q0, ..., up to the
// corner of the Brillouin zone.
RadialSpectrum radial_spectrum(const Grid& grid, Fourier& fourier, const Field& f);

// ---- Cross-section -----------------------------------------------------------------
// Values along the line x = x0 (periodic, in L), linearly interpolated between the
// two nearest columns; y[iy] = iy * dy.
struct Profile {
  std::vector<double> y, value;
};
Profile cross_section_x(const Grid& grid, const Field& f, double x0);

// ---- Contact stiffness along a load path ------------------------------------------
// k_i = -dp/d(mean gap) at each point of a path (mean_gap[i], mean_pressure[i]).
// Three-point finite differences valid for unequal spacing: centred in the interior
// (second order; the plain centred difference for equal spacing), one-sided three-
// point at the ends (second order); two points give the secant. Gaps must be
// distinct; throws otherwise. Units: E*/L in reduced units.
std::vector<double> contact_stiffness(std::span<const double> mean_gap, std::span<const double> mean_pressure);

// ---- Scalars for summary.json ------------------------------------------------------
struct ScalarObservables {
  double contact_fraction = 0;            // points in contact / N (ContactRule)
  double contact_fraction_corrected = 0;  // Yastrebov et al. 2017 (see above)
  double repulsive_fraction = 0;          // ContactRule::repulsive
  double attractive_fraction = 0;         // ContactRule::attractive
  double mean_gap = 0, mean_pressure = 0;
  double mean_displacement = 0;           // NaN when no displacement field is given
  double max_pressure = 0, min_pressure = 0, max_gap = 0;
  long long contact_edges = 0;
  double contact_perimeter = 0;           // staircase length per nominal area (1/L)
  long long n_patches = 0;
  double largest_patch_area = 0, mean_patch_area = 0;  // in L^2
};
ScalarObservables scalar_observables(const Grid& grid, const Field& gap, const Field& pressure,
                                     const ContactRule& rule = {}, Connectivity c = Connectivity::Four,
                                     const Field* displacement = nullptr);
// The same from the contact mask of `rule` and its patches, computed by the caller.
ScalarObservables scalar_observables(const Grid& grid, const Field& gap, const Field& pressure, const ContactRule& rule,
                                     const Mask& mask, const Patches& patches, const Field* displacement = nullptr);

}  // namespace cmc
