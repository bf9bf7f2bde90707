#include "cmc/elastic/HalfSpace.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace cmc {

HalfSpace::HalfSpace(const Grid& g, double estar) : grid_(g), estar_(estar) {
  if (!(estar > 0.0) || !std::isfinite(estar)) throw std::invalid_argument("HalfSpace: contact modulus must be positive");
  if (g.nx <= 0 || g.ny <= 0) throw std::invalid_argument("HalfSpace: grid must have a positive number of points");
}

double HalfSpace::energy(const Field& p, const Field& u) const {
  double s = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) s += p[i] * u[i];
  double v[1] = {s};
  Grid::allreduce_sum(v);
  return 0.5 * v[0] * grid_.cell_area();
}

template <class F>
void HalfSpace::for_each_mode(F&& f) const {
  // r2c layout: rows of nx/2 + 1 modes; interior columns stand for a ±q pair.
  const int nxt = fourier_->nx(), nqx = nxt / 2 + 1, ny = fourier_->ny();
  for (int iy = 0; iy < ny; ++iy) {
    const std::size_t row = std::size_t(iy) * nqx;
    f(row, 1.0);
    for (int ix = 1; ix < nqx; ++ix) f(row + ix, 2 * ix == nxt ? 1.0 : 2.0);
  }
}

void HalfSpace::displacement(const Field& p, Field& u) {
  fourier_->forward(to_transform_grid(p));
  auto& s = fourier_->spectrum();
  for (std::size_t k = 0; k < s.size(); ++k) s[k] *= kernel_[k];
  u.resize(grid_.size());
  from_transform_grid(u);
}

void HalfSpace::set_offset(const Field& h) {
  offset_hat_.resize(fourier_->spectrum_size());
  fourier_->forward(to_transform_grid(h), offset_hat_.data());
  const double norm = fourier_->normalisation();
  for (auto& c : offset_hat_) c *= norm;
}

void HalfSpace::set_pressure(const Field& p, double scale, Field& u) {
  p_hat_.resize(fourier_->spectrum_size());
  fourier_->forward(to_transform_grid(p), p_hat_.data());
  step_pressure(scale, 0.0, u);
}

double HalfSpace::set_direction(const Field& t) {
  t_hat_.resize(fourier_->spectrum_size());
  fourier_->forward(to_transform_grid(t), t_hat_.data());
  // Parseval with the unnormalised forward transform: Σ_i t_i (G t)_i =
  // (1/N) Σ_q G(q) |t̂_q|², and kernel_ already holds G(q)/N.
  double d = 0.0;
  for_each_mode([&](std::size_t k, double w) { d += w * kernel_[k] * std::norm(t_hat_[k]); });
  double v[1] = {d};
  Grid::allreduce_sum(v);
  return v[0];
}

void HalfSpace::step_pressure(double scale, double tau, Field& u) {
  auto& s = fourier_->spectrum();
  Complex* ph = p_hat_.data();
  const Complex* th = tau != 0.0 ? t_hat_.data() : nullptr;
  const Complex* off = offset_hat_.empty() ? nullptr : offset_hat_.data();
  const double* ker = kernel_.data();
  Complex* out = s.data();
  const std::ptrdiff_t m = std::ptrdiff_t(s.size());
#pragma omp parallel for schedule(static) if (m > (1 << 15))
  for (std::ptrdiff_t k = 0; k < m; ++k) {
    const Complex pk = scale * (th ? ph[k] - tau * th[k] : ph[k]);
    ph[k] = pk;
    out[k] = off ? pk * ker[k] + off[k] : pk * ker[k];
  }
  u.resize(grid_.size());
  from_transform_grid(u);
}

// ---------------------------------------------------------------- periodic

PeriodicHalfSpace::PeriodicHalfSpace(const Grid& g, double estar) : HalfSpace(g, estar) {
  fourier_ = std::make_unique<Fourier>(g.nx, g.ny);
  kernel_.assign(g.spectrum_size(), 0.0);
  const double norm = fourier_->normalisation();
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nqx(); ++ix) {
      const double q = std::hypot(g.qx(ix), g.qy(iy));
      kernel_[std::size_t(iy) * g.nqx() + ix] = q > 0.0 ? 2.0 / (estar * q) * norm : 0.0;
    }
}

void PeriodicHalfSpace::from_transform_grid(Field& out) { fourier_->inverse(out); }

void PeriodicHalfSpace::pressure(const Field& u, Field& p, double) {
  fourier_->forward(u);
  auto& s = fourier_->spectrum();
  const double norm = fourier_->normalisation();
  for (std::size_t k = 0; k < s.size(); ++k)
    s[k] = kernel_[k] > 0.0 ? s[k] * (norm * norm / kernel_[k]) : Complex(0.0);
  p.resize(grid_.size());
  fourier_->inverse(p);
}

double PeriodicHalfSpace::energy_from_displacement(const Field& u) {
  fourier_->forward(u);
  const auto& s = fourier_->spectrum();
  const double norm = fourier_->normalisation();
  double sum = 0.0;
  for_each_mode([&](std::size_t k, double w) {
    const double q = std::hypot(grid_.qx(int(k % grid_.nqx())), grid_.qy(int(k / grid_.nqx())));
    sum += w * q * std::norm(s[k] * norm);
  });
  return grid_.area() * 0.25 * estar_ * sum;
}

// ---------------------------------------------------------------- free boundary

double FreeHalfSpace::influence(double x, double y, double dx, double dy, double estar) {
  // ∫∫ dx'dy' / sqrt(X² + Y²) over the cell, via the antiderivative
  // F(X, Y) = X ln(Y + r) + Y ln(X + r), r = sqrt(X² + Y²) (∂²F/∂X∂Y = 1/r).
  // ln(Y + r) for Y < 0 is rewritten as ln(X² / (r − Y)) to avoid cancellation.
  auto lnp = [](double a, double b, double r) {  // ln(a + r), r = hypot(a, b)
    if (a >= 0.0) return std::log(a + r);
    return std::log(b * b / (r - a));
  };
  auto F = [&](double X, double Y) {
    const double r = std::hypot(X, Y);
    if (r == 0.0) return 0.0;
    const double tx = X == 0.0 ? 0.0 : X * lnp(Y, X, r);
    const double ty = Y == 0.0 ? 0.0 : Y * lnp(X, Y, r);
    return tx + ty;
  };
  const double x1 = -0.5 * dx - x, x2 = 0.5 * dx - x;
  const double y1 = -0.5 * dy - y, y2 = 0.5 * dy - y;
  const double integral = F(x2, y2) - F(x1, y2) - F(x2, y1) + F(x1, y1);
  return integral / (std::numbers::pi * estar);  // Boussinesq: u = 1/(π E*) ∫ p / s dA
}

FreeHalfSpace::FreeHalfSpace(const Grid& g, double estar) : HalfSpace(g, estar) {
  if (g.ny < 2) throw std::invalid_argument("FreeHalfSpace: a free boundary needs a two-dimensional grid");
  const int mx = 2 * g.nx, my = 2 * g.ny;
  fourier_ = std::make_unique<Fourier>(mx, my);
  padded_.assign(std::size_t(mx) * my, 0.0);
  Field k(padded_.size());
  for (int j = 0; j < my; ++j)
    for (int i = 0; i < mx; ++i) {
      const int ii = i <= g.nx ? i : i - mx, jj = j <= g.ny ? j : j - my;
      k[std::size_t(j) * mx + i] = influence(ii * g.dx(), jj * g.dy(), g.dx(), g.dy(), estar);
    }
  fourier_->forward(k);
  const auto& s = fourier_->spectrum();
  kernel_.resize(s.size());
  // The kernel is even in x and y, so its transform is real.
  for (std::size_t q = 0; q < s.size(); ++q) kernel_[q] = s[q].real() * fourier_->normalisation();
}

const double* FreeHalfSpace::to_transform_grid(const Field& p) {
  const int nx = grid_.nx, ny = grid_.ny, mx = 2 * nx;
  for (int j = 0; j < ny; ++j) {
    double* row = &padded_[std::size_t(j) * mx];
    std::copy_n(&p[std::size_t(j) * nx], nx, row);
    std::fill(row + nx, row + mx, 0.0);
  }
  // Rows ny..2ny-1 stay zero: nothing else ever writes them before a forward transform.
  std::fill(padded_.begin() + std::size_t(ny) * mx, padded_.end(), 0.0);
  return padded_.data();
}

void FreeHalfSpace::from_transform_grid(Field& u) {
  const int nx = grid_.nx, ny = grid_.ny, mx = 2 * nx;
  fourier_->inverse(padded_);
  for (int j = 0; j < ny; ++j) std::copy_n(&padded_[std::size_t(j) * mx], nx, &u[std::size_t(j) * nx]);
}

void FreeHalfSpace::pressure(const Field& u, Field& p, double tol) {
  // G is symmetric positive definite on the patch: plain conjugate gradients.
  const std::size_t n = grid_.size();
  p.assign(n, 0.0);
  Field r(u.begin(), u.end()), d(r), Gd(n);
  double rr = 0.0;
  for (double v : r) rr += v * v;
  const double stop = tol * tol * rr;
  for (int it = 0; it < 10000 && rr > stop && rr > 0.0; ++it) {
    displacement(d, Gd);
    double dGd = 0.0;
    for (std::size_t i = 0; i < n; ++i) dGd += d[i] * Gd[i];
    const double a = rr / dGd;
    double rr_new = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      p[i] += a * d[i];
      r[i] -= a * Gd[i];
      rr_new += r[i] * r[i];
    }
    const double b = rr_new / rr;
    for (std::size_t i = 0; i < n; ++i) d[i] = r[i] + b * d[i];
    rr = rr_new;
  }
}

double FreeHalfSpace::energy_from_displacement(const Field& u) {
  Field p;
  pressure(u, p);
  return energy(p, u);
}

std::unique_ptr<HalfSpace> make_half_space(const Grid& g, double estar, bool periodic) {
  if (periodic) return std::make_unique<PeriodicHalfSpace>(g, estar);
  return std::make_unique<FreeHalfSpace>(g, estar);
}

}  // namespace cmc
