#include "cmc/elastic/HalfSpace.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/grid/RowColumnFourier.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace cmc {

namespace {
// Weight of r2c mode column ix in a sum over the full (Hermitian) spectrum of a transform
// nx points wide: interior columns stand for a ±q pair.
}  // namespace

Grid HalfSpace::checked(const Grid& g, double estar, Boundary b) {
  if (!(estar > 0.0) || !std::isfinite(estar)) throw std::invalid_argument("HalfSpace: contact modulus must be positive");
  if (g.nx <= 0 || g.ny <= 0) throw std::invalid_argument("HalfSpace: grid must have a positive number of points");
  if (b == Boundary::Free && g.ny < 2)
    throw std::invalid_argument("FreeHalfSpace: a free boundary needs a two-dimensional grid");
  return g;
}

// The grid the transforms work on: the contact grid when periodic, the zero-padded
// 2nx x 2ny grid when free; in a distributed run this rank's slab of it (the padded grid's
// 2ny rows are split on their own: its contact rows [0, ny) sit on other ranks than the
// contact grid's, and RowExchange moves them).
Grid HalfSpace::transform_grid(const Grid& g, Boundary b) {
  if (b == Boundary::Periodic) return g;
  const Grid padded{2 * g.nx, 2 * g.ny, 2 * g.lx, 2 * g.ly};
  return g.split() ? distribute(padded) : padded;
}

HalfSpace::HalfSpace(const Grid& g, double estar, Boundary b)
    : grid_(checked(g, estar, b)),
      estar_(estar),
      boundary_(b),
      mx_(b == Boundary::Free ? 2 * g.nx : g.nx),
      my_(b == Boundary::Free ? 2 * g.ny : g.ny),
      tgrid_(transform_grid(grid_, b)),
      fourier_(tgrid_) {
  if (periodic()) {
    make_periodic_compliance();
  } else {
    padded_.assign(transform_size(), 0.0);
    if (grid_.split()) exchange_ = std::make_unique<RowExchange>(grid_, tgrid_, grid_.ny);
    make_free_compliance();
  }
}

HalfSpace::~HalfSpace() = default;

// A multiplier of the periodic transform grid's modes: m[k] = f(|q|) for every mode k this
// process holds (in the Fourier layout's order: rows of qy, or of qx when distributed).
template <class F>
Field HalfSpace::periodic_multiplier(F f) const {
  const SpectrumLayout& L = fourier_.layout();
  Field m(L.size(), 0.0);
  for (int r = 0; r < L.rows; ++r)
    for (int c = 0; c < L.cols; ++c)
      m[std::size_t(r) * L.cols + c] = f(std::hypot(grid_.qx(L.iqx(r, c)), grid_.qy(L.iqy(r, c))));
  return m;
}

void HalfSpace::make_periodic_compliance() {
  const double norm = fourier_.normalisation();
  compliance_ = periodic_multiplier([&](double q) { return q > 0.0 ? 2.0 / (estar_ * q) * norm : 0.0; });
}

void HalfSpace::make_free_compliance() {
  // The influence coefficients wrapped onto the padded grid: offsets 0..nx to the right,
  // −(nx−1)..−1 to the left (the patch is nx wide, so no offset aliases another).
  const Grid& g = grid_;
  Field k(transform_size());
  for (int lj = 0; lj < tgrid_.rows(); ++lj)  // this rank's rows of the padded grid
    for (int i = 0; i < mx_; ++i) {
      const int j = tgrid_.y0 + lj;
      const int ii = i <= g.nx ? i : i - mx_, jj = j <= g.ny ? j : j - my_;
      k[std::size_t(lj) * mx_ + i] = influence(ii * g.dx(), jj * g.dy(), g.dx(), g.dy(), estar_);
    }
  fourier_.forward(k);
  const auto s = fourier_.spectrum();
  compliance_.resize(s.size());
  stiffness_.resize(s.size());
  const double norm = fourier_.normalisation();
  // The kernel is even in x and y, so its transform is real: its values are the
  // eigenvalues of the padded circulant, all positive (it is an integral of 1/r over
  // cells, a positive-definite kernel), and K is their inverse.
  for (std::size_t q = 0; q < s.size(); ++q) {
    const double lambda = s[q].real();
    if (!(lambda > 0.0) || !std::isfinite(lambda))
      throw std::runtime_error("HalfSpace: the padded free-boundary operator is not positive definite");
    compliance_[q] = lambda * norm;
    stiffness_[q] = norm / lambda;
  }
}

const Field& HalfSpace::stiffness() {
  if (!stiffness_.empty()) return stiffness_;  // free: made with the compliance
  // Periodic: K = E*|q|/2 (the inverse of 2/(E*|q|)); 0 at q = 0.
  const double norm = fourier_.normalisation();
  stiffness_ = periodic_multiplier([&](double q) { return 0.5 * estar_ * q * norm; });
  return stiffness_;
}

// ---------------------------------------------------------------- transform grid

Field HalfSpace::unit_response() {
  Field delta(transform_size(), 0.0), response(transform_size(), 0.0);
  if (tgrid_.y0 == 0) delta[0] = 1.0;  // point 0 of the whole grid: on the first slab
  apply(delta.data(), response.data(), stiffness());
  return response;
}

double HalfSpace::apply(const double* in, double* out, const Field& mul) {
  fourier_.forward(in);
  Complex* s = fourier_.spectrum().data();
  const double* m = mul.data();
  const SpectrumLayout& L = fourier_.layout();
  const int mx = mx_;
  // Rows of modes in parallel; each row's partial sum is formed first (fewer round-off
  // steps in the long sum).
  const SumReduction acc = Grid::parallel_reduce<SumReduction>(
      std::size_t(L.rows),
      [&](std::size_t r0, std::size_t r1, SumReduction& a) {
        for (std::size_t r = r0; r < r1; ++r) {
          const std::size_t row = r * std::size_t(L.cols);
          double rs = 0.0;
          for (int c = 0; c < L.cols; ++c) {
            const std::size_t k = row + c;
            rs += r2c_mode_weight(L.iqx(int(r), c), mx) * m[k] * std::norm(s[k]);
            s[k] *= m[k];
          }
          a.v += rs;
        }
      },
      transform_size());
  fourier_.inverse(out);
  return acc.v;
}

// Σ_q w_q M_q |s_q|² over the r2c rows [r0, r1), in mode order.
double HalfSpace::spectral_sum(const Complex* s, const double* mul, std::size_t r0, std::size_t r1) const {
  const SpectrumLayout& L = fourier_.layout();
  double d = 0.0;
  for (std::size_t r = r0; r < r1; ++r) {
    const std::size_t row = r * L.cols;
    for (int c = 0; c < L.cols; ++c) d += r2c_mode_weight(L.iqx(int(r), c), mx_) * mul[row + c] * std::norm(s[row + c]);
  }
  return d;
}

double HalfSpace::quadratic_form(std::span<const Complex> s, const Field& mul) const {
  return Grid::parallel_reduce<SumReduction>(
             std::size_t(fourier_.layout().rows),
             [&](std::size_t r0, std::size_t r1, SumReduction& acc) { acc.v += spectral_sum(s.data(), mul.data(), r0, r1); },
             transform_size())
      .v;
}

const double* HalfSpace::to_transform_grid(const Field& p) {
  if (periodic()) return p.data();
  if (exchange_) {  // distributed: the contact rows come from the ranks that hold them
    std::fill(padded_.begin(), padded_.end(), 0.0);
    exchange_->forward(p.data(), padded_.data());
    return padded_.data();
  }
  const int nx = grid_.nx, ny = grid_.ny;
  for (int j = 0; j < ny; ++j) {
    double* row = &padded_[std::size_t(j) * mx_];
    std::copy_n(&p[std::size_t(j) * nx], nx, row);
    std::fill(row + nx, row + mx_, 0.0);
  }
  std::fill(padded_.begin() + std::size_t(ny) * mx_, padded_.end(), 0.0);
  return padded_.data();
}

void HalfSpace::forward(const Field& f, Spectrum& out) {
  out.resize(fourier_.spectrum_size());
  fourier_.forward(to_transform_grid(f), out.data());
}

void HalfSpace::forward(const Field& f) { fourier_.forward(to_transform_grid(f)); }

void HalfSpace::inverse(Field& out) {
  out.resize(grid_.size());
  if (periodic()) {
    fourier_.inverse(out);
    return;
  }
  fourier_.inverse(padded_);
  if (exchange_) {
    exchange_->backward(padded_.data(), out.data());
    return;
  }
  const int nx = grid_.nx;
  for (int j = 0; j < grid_.ny; ++j) std::copy_n(&padded_[std::size_t(j) * mx_], nx, &out[std::size_t(j) * nx]);
}

double HalfSpace::self_stiffness() { return transform_entry(unit_response(), 0, 0); }

double HalfSpace::transform_entry(const Field& f, int row, int col) const {
  const bool here = row >= tgrid_.y0 && row < tgrid_.y0 + tgrid_.rows();
  const double mine = here ? f[std::size_t(row - tgrid_.y0) * std::size_t(mx_) + std::size_t(col)] : 0.0;
  return Grid::sum(std::span<const double>(&mine, 1));
}

namespace {
// Seconds of the fastest of at least min_repeats calls of pair() taking min_seconds, after
// one untimed call (first touch of the buffers and threads). A distributed pair is
// collective: every rank times as many as the rank that needs the most (a rank deciding
// alone from its own clock would leave the others waiting), and the result is the slowest
// rank's fastest pair (the same number on every rank).
template <class Pair>
double fastest_pair_seconds(Pair&& pair, double min_seconds, int min_repeats) {
  const auto timed = [&] {
    const auto t0 = std::chrono::steady_clock::now();
    pair();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  timed();
  std::vector<double> t;
  double total = 0.0;
  while (any_rank(int(t.size()) < min_repeats || total < min_seconds)) total += t.emplace_back(timed());
  // The fastest pair: the floor this machine reaches now. Single pairs at 2048² varied
  // from 23 to 40 ms here (other processes); the median of a few was still as noisy.
  const double fastest = *std::min_element(t.begin(), t.end());
  return Grid::max(std::span<const double>(&fastest, 1));
}
}  // namespace

double HalfSpace::time_fft_pair(double min_seconds, int min_repeats) {
  Field in(transform_size(), 0.0), out(transform_size());
  return fastest_pair_seconds(
      [&] {
        fourier_.forward(in.data());
        fourier_.inverse(out.data());
      },
      min_seconds, min_repeats);
}

double HalfSpace::time_row_column_pair(double min_seconds, int min_repeats) {
  if (!row_column()) return 0.0;
  RowColumnFourier f(grid_.nx, grid_.ny);
  Complex* s = scratch_spectrum(f.spectrum_size());
  Field in(grid_.size(), 0.0), out(grid_.size());
  return fastest_pair_seconds([&] { f.pair(in.data(), s, out.data()); }, min_seconds, min_repeats);
}

// ---------------------------------------------------------------- contact grid

void HalfSpace::displacement(const Field& p, Field& u) {
  fourier_.forward(to_transform_grid(p));
  const auto s = fourier_.spectrum();
  for (std::size_t k = 0; k < s.size(); ++k) s[k] *= compliance_[k];
  inverse(u);
}

void HalfSpace::pressure(const Field& u, Field& p, double tol) {
  if (periodic()) {
    fourier_.forward(u);
    const auto s = fourier_.spectrum();
    const double norm = fourier_.normalisation();
    for (std::size_t k = 0; k < s.size(); ++k)
      s[k] = compliance_[k] > 0.0 ? s[k] * (norm * norm / compliance_[k]) : Complex(0.0);
    inverse(p);
    return;
  }
  // G is symmetric positive definite on the patch: plain conjugate gradients.
  const std::size_t n = grid_.size();
  p.assign(n, 0.0);
  Field r(u.begin(), u.end()), d(r), Gd(n);
  double rr = Grid::dot(r, r);
  const double stop = tol * tol * rr;
  for (int it = 0; it < 10000 && rr > stop && rr > 0.0; ++it) {
    displacement(d, Gd);
    const double a = rr / Grid::dot(d, Gd);
    const double rr_new = Grid::parallel_reduce<SumReduction>(n, [&](std::size_t b, std::size_t e, SumReduction& acc) {
                            double s = 0.0;
                            for (std::size_t i = b; i < e; ++i) {
                              p[i] += a * d[i];
                              r[i] -= a * Gd[i];
                              s += r[i] * r[i];
                            }
                            acc.v += s;
                          }).v;
    const double beta = rr_new / rr;
    Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) d[i] = r[i] + beta * d[i];
    });
    rr = rr_new;
  }
}

double HalfSpace::energy(const Field& p, const Field& u) const { return energy_from_sum(Grid::dot(p, u)); }

double HalfSpace::energy_from_displacement(const Field& u) {
  if (!periodic()) {
    Field p;
    pressure(u, p);
    return energy(p, u);
  }
  // Σ_q |q| |ũ_q|² with ũ = FFT(u)/N: the multiplier |q| N^-2 (the free case returned above).
  if (abs_q_.empty()) {
    const double n2 = fourier_.normalisation() * fourier_.normalisation();
    abs_q_ = periodic_multiplier([&](double q) { return q * n2; });
  }
  fourier_.forward(u);
  return grid_.area() * 0.25 * estar_ * quadratic_form(fourier_.spectrum(), abs_q_);
}

double HalfSpace::influence(double x, double y, double dx, double dy, double estar) {
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

std::unique_ptr<HalfSpace> make_half_space(const Grid& g, double estar, bool periodic) {
  if (periodic) return std::make_unique<PeriodicHalfSpace>(g, estar);
  return std::make_unique<FreeHalfSpace>(g, estar);
}

}  // namespace cmc
