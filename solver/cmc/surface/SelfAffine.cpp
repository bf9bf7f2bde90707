#include "cmc/surface/SelfAffine.hpp"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cmc {

namespace {
constexpr double two_pi = 2.0 * std::numbers::pi;
// Relative slack on the band edge |k| <= L/lambda_s, so that e.g. 1/0.001 keeps |k| = 1000.
constexpr double edge_slack = 1e-12;

void check_spec(const SelfAffineSpec& s) {
  auto bad = [](const std::string& what) { throw std::invalid_argument("SelfAffineSpec: " + what); };
  if (!std::isfinite(s.hurst)) bad("hurst must be finite");
  if (!(s.cutoff_wavelength > 0.0 && s.cutoff_wavelength <= 1.0))
    bad("cutoff_wavelength (lambda_s/L) must lie in (0, 1], got " + std::to_string(s.cutoff_wavelength));
  if (!(s.rolloff_wavelength > 0.0) || !std::isfinite(s.rolloff_wavelength))
    bad("rolloff_wavelength (lambda_r/L) must be positive");
  if (!(s.rms_gradient > 0.0) || !std::isfinite(s.rms_gradient)) bad("rms_gradient must be positive");
  if (1.0 / s.cutoff_wavelength > 1e6) bad("cutoff_wavelength below 1e-6 L: band too large");
}

// S(k) from |k|^2 (avoids a sqrt): (k/k_r)^(-2(1+H)) = (k^2/k_r^2)^(-(1+H)).
inline double shape_k2(double k2, double kr2, double hurst) {
  return k2 < kr2 ? 1.0 : std::pow(k2 / kr2, -(1.0 + hurst));
}
}  // namespace

double self_affine_shape(const SelfAffineSpec& spec, double k) {
  const double kmax = 1.0 / spec.cutoff_wavelength, kr = 1.0 / spec.rolloff_wavelength;
  if (k < 1.0 || k > kmax * (1.0 + edge_slack)) return 0.0;
  return shape_k2(k * k, kr * kr, spec.hurst);
}

double SelfAffineModes::expected_psd(const SelfAffineSpec& spec, double q) const {
  return amplitude * amplitude * self_affine_shape(spec, q / two_pi) / (two_pi * two_pi);
}

int SelfAffineModes::full_grid() const {
  int n = 2;
  while (n / 2 <= max_index) n *= 2;
  return n;
}

SelfAffineModes self_affine_modes(const SelfAffineSpec& spec) {
  check_spec(spec);
  const double kmax = 1.0 / spec.cutoff_wavelength;
  const double kmax2 = kmax * kmax * (1.0 + 2.0 * edge_slack);
  const double kr = 1.0 / spec.rolloff_wavelength, kr2 = kr * kr;
  const long K = long(std::floor(kmax * (1.0 + edge_slack)));

  std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  if (!rng) throw std::runtime_error("self_affine_modes: gsl_rng_alloc failed");
  gsl_rng_set(rng.get(), spec.seed);

  SelfAffineModes out;
  out.max_index = int(K);
  out.modes.reserve(std::size_t(std::numbers::pi * 0.5 * double(K + 1) * double(K + 1)) + 4 * K + 8);
  long double grad2 = 0.0L;  // sum over the full plane of |k|^2 |c_k|^2 (before 2 pi and A)
  for (long kx = 0; kx <= K; ++kx) {
    long kyM = long(std::sqrt(std::max(0.0, kmax2 - double(kx * kx))));
    while (kyM > 0 && double(kx * kx + kyM * kyM) > kmax2) --kyM;
    while (double(kx * kx + (kyM + 1) * (kyM + 1)) <= kmax2) ++kyM;
    for (long ky = kx == 0 ? 1 : -kyM; ky <= kyM; ++ky) {
      const double k2 = double(kx * kx + ky * ky);
      const double a = std::sqrt(0.5 * shape_k2(k2, kr2, spec.hurst));
      // Two deviates per mode, real part first, always drawn (keeps the stream canonical).
      const double g1 = gsl_ran_gaussian_ziggurat(rng.get(), 1.0);
      const double g2 = gsl_ran_gaussian_ziggurat(rng.get(), 1.0);
      const Complex c(a * g1, a * g2);
      grad2 += 2.0L * k2 * std::norm(c);  // k and -k
      out.modes.push_back({int(kx), int(ky), c});
    }
  }
  // <|grad h|^2> = sum_k (2 pi |k| / L)^2 |c_k|^2 (Parseval), L = 1.
  out.amplitude = spec.rms_gradient / (two_pi * std::sqrt(double(grad2)));
  for (auto& m : out.modes) m.c *= out.amplitude;
  return out;
}

Synthesis synthesize(const std::vector<FourierMode>& modes, const Grid& grid) {
  if (grid.nx < 1 || grid.ny < 1) throw std::invalid_argument("synthesize: empty grid");
  // On a slab of a distributed run, each rank places the modes of its part of the
  // spectrum (fft.layout()) and the inverse transform is distributed: no rank holds more
  // than its slab (the list of modes is the band's, the same on every rank).
  Fourier fft(grid);
  const auto s = fft.spectrum();
  std::fill(s.begin(), s.end(), Complex(0.0));
  const SpectrumLayout& L = fft.layout();
  auto put = [&](long iy, std::size_t iqx, Complex c) {
    const long k = L.index(int(iqx), int(iy));
    if (k >= 0) s[std::size_t(k)] += c;
  };
  Synthesis out;
  for (FourierMode m : modes) {
    if (m.kx < 0 || (m.kx == 0 && m.ky < 0)) m = {-m.kx, -m.ky, std::conj(m.c)};
    if (m.kx == 0 && m.ky == 0) {
      put(0, 0, m.c.real());
      ++out.modes_placed;
      continue;
    }
    if (2L * m.kx >= grid.nx || 2L * std::abs(long(m.ky)) >= grid.ny) {
      ++out.modes_dropped;
      continue;
    }
    ++out.modes_placed;
    const long iy = m.ky >= 0 ? m.ky : m.ky + grid.ny;
    if (m.kx > 0) {
      put(iy, std::size_t(m.kx), m.c);
    } else {  // kx == 0 column: c2r needs both members of the pair
      put(iy, 0, m.c);
      put(grid.ny - m.ky, 0, std::conj(m.c));
    }
  }
  out.map.grid = grid;
  out.map.heights = grid.field();
  fft.inverse(out.map.heights);  // unnormalised c2r: h(x) = sum_k c_k e^{+i q.x}
  return out;
}

SelfAffineSurface generate_self_affine(const SelfAffineSpec& spec, const Grid& grid) {
  if (!(grid.lx > 0.0) || std::abs(grid.lx - grid.ly) > 1e-12 * grid.lx)
    throw std::invalid_argument("generate_self_affine: the box must be square (lx == ly)");
  if (grid.nx < 2 || grid.ny < 2) throw std::invalid_argument("generate_self_affine: grid must be at least 2 x 2");
  const SelfAffineModes band = self_affine_modes(spec);
  Synthesis syn = synthesize(band.modes, grid);
  SelfAffineSurface out;
  out.modes_total = long(band.modes.size());
  out.modes_dropped = syn.modes_dropped;
  out.rms_gradient_band = spec.rms_gradient;
  out.map = std::move(syn.map);
  Field& h = out.map.heights;
  const double L = grid.lx;  // spec lengths are in units of L: heights scale with L
  if (L != 1.0)
    for (double& v : h) v *= L;
  out.shift = -Grid::min(h);
  for (double& v : h) v += out.shift;
  return out;
}

std::vector<FourierMode> fourier_modes(const HeightMap& map, double threshold) {
  const Grid& g = map.grid;
  if (map.heights.size() != g.size()) throw std::invalid_argument("fourier_modes: heights do not match the grid");
  Fourier fft(g.nx, g.ny);
  fft.forward(map.heights);
  const auto s = fft.spectrum();
  const double norm = fft.normalisation();
  const int nqx = g.nqx();
  std::vector<FourierMode> out;
  for (int iqx = 0; iqx < nqx; ++iqx) {
    if (g.nx % 2 == 0 && iqx == g.nx / 2 && g.nx > 1) continue;  // Nyquist column
    for (int iqy = 0; iqy < g.ny; ++iqy) {
      if (g.ny % 2 == 0 && iqy == g.ny / 2) continue;  // Nyquist row
      const int ky = iqy <= g.ny / 2 ? iqy : iqy - g.ny;
      if (iqx == 0 && ky < 0) continue;  // other half-plane
      const Complex c = s[std::size_t(iqy) * nqx + iqx] * norm;
      if (std::abs(c) > threshold)
        out.push_back({iqx, ky, iqx == 0 && ky == 0 ? Complex(c.real(), 0.0) : c});
    }
  }
  return out;
}

HeightMap fourier_interpolate(const HeightMap& map, int nx, int ny) {
  const Grid& g = map.grid;
  if (map.heights.size() != g.size()) throw std::invalid_argument("fourier_interpolate: heights do not match the grid");
  if (nx < g.nx || ny < g.ny) throw std::invalid_argument("fourier_interpolate: target grid is coarser than the map");
  Fourier coarse(g.nx, g.ny), fine(nx, ny);
  coarse.forward(map.heights);
  const auto c = coarse.spectrum();
  const auto f = fine.spectrum();
  std::fill(f.begin(), f.end(), Complex(0.0));
  const double norm = coarse.normalisation();
  const std::size_t cq = std::size_t(g.nqx()), fq = std::size_t(nx / 2 + 1);
  const bool split_x = g.nx % 2 == 0 && nx > g.nx, split_y = g.ny % 2 == 0 && ny > g.ny;
  auto put = [&](std::size_t iqx, int ky, Complex v) { f[std::size_t(ky >= 0 ? ky : ky + ny) * fq + iqx] += v; };
  for (int iqy = 0; iqy < g.ny; ++iqy) {
    const int ky = iqy <= g.ny / 2 ? iqy : iqy - g.ny;
    for (std::size_t iqx = 0; iqx < cq; ++iqx) {
      Complex v = c[std::size_t(iqy) * cq + iqx] * norm;
      // A coarse Nyquist mode equals its own alias -k on the coarse points: split it.
      // (The -kx half of a split x-Nyquist column is implied by the c2r Hermitian symmetry.)
      if (split_x && iqx == std::size_t(g.nx / 2)) v *= 0.5;
      if (split_y && iqy == g.ny / 2) {
        put(iqx, ky, 0.5 * v);
        put(iqx, -ky, 0.5 * v);
      } else {
        put(iqx, ky, v);
      }
    }
  }
  HeightMap out{Grid{nx, ny, g.lx, g.ly}, Field(std::size_t(nx) * ny)};
  fine.inverse(out.heights);
  return out;
}

}  // namespace cmc
