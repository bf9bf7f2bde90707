#include "cmc/surface/SurfaceStats.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace cmc {

namespace {
// Multiplicity of r2c column iqx in the full spectrum: the kx = 0 and (even nx) Nyquist
// columns appear once, every other column stands for itself and its conjugate.
inline double column_weight(const Grid& g, int iqx) {
  return (iqx == 0 || (g.nx % 2 == 0 && iqx == g.nx / 2)) ? 1.0 : 2.0;
}
void check(const Grid& g, const Field& h, const char* who) {
  if (g.size() == 0 || h.size() != g.size())
    throw std::invalid_argument(std::string(who) + ": field size does not match the grid");
}
}  // namespace

SurfaceStatistics surface_statistics(const Grid& grid, const Field& h) {
  check(grid, h, "surface_statistics");
  Fourier fft(grid);  // distributed when the grid is a slab
  return surface_statistics(grid, h, fft);
}

SurfaceStatistics surface_statistics(const Grid& g, const Field& h, Fourier& fft) {
  check(g, h, "surface_statistics");
  if (fft.nx() != g.nx || fft.ny() != g.ny) throw std::invalid_argument("surface_statistics: transform shape differs from the grid");
  SurfaceStatistics s;
  s.mean = Grid::mean(h);
  s.min = Grid::min(h);
  s.max = Grid::max(h);
  double var[1] = {0.0};
  {
    // Two-pass variance (no cancellation against the mean).
    Field d(h.size());
    for (std::size_t i = 0; i < h.size(); ++i) d[i] = (h[i] - s.mean) * (h[i] - s.mean);
    var[0] = Grid::sum(d) / double(g.points());
  }
  s.rms_height = std::sqrt(var[0]);

  // Parseval: <(d^a h/dx^a ...)^2> = sum_k |(i q)^a c_k|^2 with c_k = FFT(h)/N.
  fft.forward(h);
  const auto c = fft.spectrum();
  const double n2 = fft.normalisation() * fft.normalisation();
  struct Moments {  // long double: 1e-12 at 4096^2
    long double x2 = 0, y2 = 0, x4 = 0, y4 = 0, l4 = 0;
    void merge(const Moments& o) { x2 += o.x2, y2 += o.y2, x4 += o.x4, y4 += o.y4, l4 += o.l4; }
  };
  const SpectrumLayout& L = fft.layout();
  const Moments m = Grid::parallel_reduce<Moments>(std::size_t(L.rows), [&](std::size_t r0, std::size_t r1, Moments& acc) {
    for (int r = int(r0); r < int(r1); ++r) {  // rows of the spectrum held here (of qy; of qx when distributed)
      double rx2 = 0, ry2 = 0, rx4 = 0, ry4 = 0, rl4 = 0;
      for (int col = 0; col < L.cols; ++col) {
        const int iqx = L.iqx(r, col);
        const double qx = g.qx(iqx), qx2 = qx * qx, qy = g.qy(L.iqy(r, col)), qy2 = qy * qy;
        const double p = column_weight(g, iqx) * std::norm(c[std::size_t(r) * L.cols + col]);
        rx2 += qx2 * p;
        ry2 += qy2 * p;
        rx4 += qx2 * qx2 * p;
        ry4 += qy2 * qy2 * p;
        rl4 += (qx2 + qy2) * (qx2 + qy2) * p;
      }
      acc.x2 += rx2, acc.y2 += ry2, acc.x4 += rx4, acc.y4 += ry4, acc.l4 += rl4;
    }
  });
  const double sums[5] = {double(m.x2 * n2), double(m.y2 * n2), double(m.x4 * n2), double(m.y4 * n2), double(m.l4 * n2)};
  s.rms_slope_x = std::sqrt(sums[0]);
  s.rms_slope_y = std::sqrt(sums[1]);
  s.rms_gradient = std::sqrt(sums[0] + sums[1]);
  s.rms_curvature = std::sqrt(0.5 * (sums[2] + sums[3]));
  s.rms_mean_curvature = 0.5 * std::sqrt(sums[4]);
  s.curvature_radius = s.rms_curvature > 0 ? 1.0 / s.rms_curvature : INFINITY;
  return s;
}

RadialPsd radial_psd(const Grid& g, const Field& h, int bins, bool logarithmic) {
  check(g, h, "radial_psd");
  constexpr double two_pi = 2.0 * std::numbers::pi;
  Fourier fft(g.nx, g.ny);
  fft.forward(h);
  const auto c = fft.spectrum();
  const double dq = two_pi / std::max(g.lx, g.ly);
  const double qnyq = std::min(std::numbers::pi * g.nx / g.lx, g.ny > 1 ? std::numbers::pi * g.ny / g.ly : INFINITY);
  // Persson: C(q) = A |c_k|^2 / (2 pi)^2, so that sum_k C dq_x dq_y = sum_k |c_k|^2.
  const double factor = g.area() * fft.normalisation() * fft.normalisation() / (two_pi * two_pi);
  int nb;
  auto bin_of = [&](double q) -> int {
    if (bins == 0) return int(std::lround(q / dq));
    if (logarithmic) return q < dq ? -1 : int(std::floor(bins * std::log(q / dq) / std::log(qnyq / dq)));
    return int(std::floor(bins * q / qnyq));
  };
  nb = bins == 0 ? int(std::lround(qnyq / dq)) + 1 : bins;
  if (nb <= 0) throw std::invalid_argument("radial_psd: bad bin count");
  std::vector<double> qs(nb, 0.0), cs(nb, 0.0), ws(nb, 0.0);
  const int nqx = g.nqx();
  for (int iqy = 0; iqy < g.ny; ++iqy)
    for (int iqx = 0; iqx < nqx; ++iqx) {
      const double q = std::hypot(g.qx(iqx), g.qy(iqy));
      if (q == 0.0 || q > qnyq * (1 + 1e-12)) continue;
      int b = bin_of(q);
      if (b == nb && bins > 0) b = nb - 1;  // q == q_nyquist exactly
      if (b < 0 || b >= nb) continue;
      const double w = column_weight(g, iqx);
      qs[b] += w * q;
      cs[b] += w * factor * std::norm(c[std::size_t(iqy) * nqx + iqx]);
      ws[b] += w;
    }
  RadialPsd out;
  for (int b = 0; b < nb; ++b)
    if (ws[b] > 0) {
      out.q.push_back(qs[b] / ws[b]);
      out.C.push_back(cs[b] / ws[b]);
      out.count.push_back(long(ws[b]));
    }
  return out;
}

}  // namespace cmc
