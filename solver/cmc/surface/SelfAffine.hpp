// The Contact Mechanics Challenge's self-affine random surface, and Fourier synthesis /
// analysis / interpolation of band-limited height maps.
//
// Spectrum (Müser & Dapp, problem definition, eq. 1), with k = q L / (2 pi) the integer
// wave index of the periodic box of side L:
//   C(q) / C(q_r) = 1                     for lambda_r < 2 pi / q <= L   (1 <= |k| < L/lambda_r)
//                 = (q / q_r)^(-2(1+H))   for lambda_s <= 2 pi / q < lambda_r
//                 = 0                     otherwise (q = 0 included: zero mean).
// Each mode of the band gets c_k = A sqrt(S(k)/2) (g1 + i g2), g1, g2 independent standard
// normal deviates (a complex Gaussian: Gaussian amplitude, uniform random phase), with
// c_{-k} = conj(c_k). A is fixed so that the rms gradient of the FULL band,
// sqrt(sum_k |2 pi k / L|^2 |c_k|^2), equals spec.rms_gradient: the normalisation and the
// modes therefore do not depend on the grid.
//
// Grid independence: the band's modes are enumerated in one canonical order that depends
// only on the spec (kx = 0..K, then ky = -K..K, half-plane kx > 0 or kx == 0 && ky > 0,
// K = floor(L/lambda_s)), drawing two deviates per mode from one GSL mt19937 stream
// (gsl_ran_gaussian_ziggurat): a seed gives the same c_k on every platform (GSL's integer
// stream is exact; the deviates use libm exp/log only in rare tails) and at every grid size.
// Enumeration costs ~0.1 s for the challenge band (1.57e6 half-plane modes). A grid holds the modes with |kx| < nx/2 and |ky| < ny/2 (Nyquist modes are
// not representable by a real band-limited field and are dropped). For the challenge
// (lambda_s = L/1000) only n >= 2048 holds every mode; on a smaller grid the surface is
// low-passed at the grid's Nyquist (modes_dropped > 0, its rms gradient is then below
// spec.rms_gradient) and the caller should warn. The final shift to min h = 0 is taken on
// the grid's points, so it differs slightly between grid sizes (the finer grid samples
// deeper minima); every k != 0 coefficient is identical.
#pragma once

#include "cmc/grid/Grid.hpp"
#include "cmc/surface/SurfaceIO.hpp"

#include <vector>

namespace cmc {

// Lengths in units of the box side L.
struct SelfAffineSpec {
  double hurst = 0.8;                // H
  double rolloff_wavelength = 0.2;   // lambda_r / L
  double cutoff_wavelength = 0.001;  // lambda_s / L
  double rms_gradient = 1.0;         // g-bar, target rms |grad h| of the full band
  // GSL mt19937 seed (its low 32 bits; 0 means 4357). The default, 28, was picked among
  // seeds 1..60 as the realisation whose mean / max / rms height at 2048^2 (2.670, 5.692,
  // 0.750 µm for L = 100 µm) come closest to the distributed challenge surface (2.633,
  // 5.642, 0.762 µm); the ensemble has rms height 0.78 ± 0.03 µm.
  unsigned long seed = 28;
};

// The spectral shape S(k) = C(q)/C(q_r) at wave index |k| = q L / 2 pi (0 outside the band).
double self_affine_shape(const SelfAffineSpec& spec, double k);

struct SelfAffineModes {
  std::vector<FourierMode> modes;  // half-plane, canonical order, box side 1, normalised
  int max_index = 0;               // K: every mode has |kx|, |ky| <= K
  double amplitude = 0.0;          // A above: E|c_k|^2 = A^2 S(k)
  // Expected PSD in Persson's convention for a box of side 1 (<dh^2> = integral d^2q C):
  // C(q) = A^2 S(q / 2 pi) / (2 pi)^2.
  double expected_psd(const SelfAffineSpec& spec, double q) const;
  // Smallest power-of-two n whose n x n grid holds every mode (n/2 > K).
  int full_grid() const;
};

// Draw the band's modes (grid independent). Throws std::invalid_argument for a bad spec.
SelfAffineModes self_affine_modes(const SelfAffineSpec& spec);

struct Synthesis {
  HeightMap map;
  long modes_placed = 0;
  long modes_dropped = 0;  // modes with |kx| >= nx/2 or |ky| >= ny/2
};
// h = sum over the listed modes and their conjugates (k -> -k) of c_k exp(2 pi i k.x / L),
// evaluated on the grid with one inverse FFT (k are integer wave indices of the box).
// Modes given in the other half-plane are folded onto it; (0,0) sets the mean.
Synthesis synthesize(const std::vector<FourierMode>& modes, const Grid& grid);

struct SelfAffineSurface {
  HeightMap map;           // heights in the grid's length units, min = 0
  long modes_total = 0;    // modes of the band (half-plane)
  long modes_dropped = 0;  // of those, not representable on the grid
  double shift = 0.0;      // added to the zero-mean synthesis to make min h = 0
  double rms_gradient_band = 0.0;  // of the full band (= spec.rms_gradient)
  bool low_passed() const { return modes_dropped > 0; }
};
// The grid's box must be square (lx == ly = L); spec lengths are in units of L and the
// heights come out in the grid's length units (multiplied by L).
SelfAffineSurface generate_self_affine(const SelfAffineSpec& spec, const Grid& grid);
inline SelfAffineSurface generate_self_affine(const SelfAffineSpec& spec, int n) {
  return generate_self_affine(spec, Grid{n, n, 1.0, 1.0});
}

// The non-zero Fourier coefficients c_k of a height map (half-plane, |c_k| > threshold,
// (0,0) included when non-zero). With threshold 0 rounding noise counts as non-zero: pass
// e.g. 1e-12 * rms height to list only the band of a generated surface. Nyquist rows/columns (kx = nx/2, ky = ny/2 for even
// n) are left out: they have no unique band-limited continuation.
std::vector<FourierMode> fourier_modes(const HeightMap& map, double threshold = 0.0);

// Band-limited (trigonometric) interpolation onto a finer nx x ny grid of the same box by
// zero padding in Fourier space: exact for any field without Nyquist content. Nyquist
// components of the coarse grid are split equally between +k and -k (the standard
// symmetric choice), so the coarse points are reproduced exactly.
HeightMap fourier_interpolate(const HeightMap& map, int nx, int ny);

}  // namespace cmc
