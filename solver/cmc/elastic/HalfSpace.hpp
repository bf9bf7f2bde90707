// Linear-elastic half-space under normal surface pressure, small-slope approximation.
//
// Convention: compressive pressure p > 0 pushes the surface into the solid; the
// displacement u > 0 points into the solid. Two Green's functions:
//  * PeriodicHalfSpace: u~(q) = 2 p~(q) / (E* |q|) for q != 0 (Johnson, Contact
//    Mechanics (1985), §13.2; Johnson, Greenwood & Higginson, Int. J. Mech. Sci. 27,
//    383 (1985), App. A.2). The mean displacement is not defined by a periodic load;
//    cmc fixes it to zero, so penetrations are measured from the mean plane of the
//    deformed elastic surface.
//  * FreeHalfSpace: an isolated (non-periodic) surface patch. Pressure is uniform on
//    each cell and the displacement is collocated at cell centres, with Love's
//    closed-form influence coefficient of a uniformly loaded rectangle (Love 1929;
//    Johnson 1985 eq. 3.25). The convolution is done by FFT on a grid zero-padded to
//    twice the size per side (Hockney 1970; Liu, Wang & Liu, Wear 243, 101 (2000),
//    "DC-FFT"), so no periodic image reaches the patch.
//
// Each apply of the Green's function costs one FFT pair on the operator's grid.
#pragma once

#include "cmc/grid/Grid.hpp"

#include <memory>

namespace cmc {

class HalfSpace {
 public:
  virtual ~HalfSpace() = default;
  const Grid& grid() const { return grid_; }
  double contact_modulus() const { return estar_; }
  virtual bool periodic() const = 0;

  // u = G p. One FFT pair. `u` may not alias `p`.
  void displacement(const Field& p, Field& u);
  // p = G^{-1} u. Periodic: exact, one FFT pair, and the returned pressure has zero
  // mean (a periodic displacement field carries no information on the mean load:
  // add it yourself). Free: solved by conjugate gradients to `tol` relative.
  virtual void pressure(const Field& u, Field& p, double tol = 1e-12) = 0;
  // Elastic energy stored by the pair (p, u = G p): (1/2) ∫ p u dA.
  double energy(const Field& p, const Field& u) const;
  // Elastic energy computed in Fourier space from u alone (periodic only):
  // U = A (E*/4) Σ_q |q| |ũ_q|², ũ_q the Fourier-series coefficients of u.
  virtual double energy_from_displacement(const Field& u) = 0;

  // ---- Spectral pressure state, for solvers that need one FFT pair per iteration:
  // the operator keeps the transform p̂ of the current pressure and of one search
  // direction t̂, so that u = G p after a linear step p ← s (p − τ t) costs one
  // inverse transform only.
  // Transform p (one forward), keep s p̂, and set u = G (s p) (one inverse).
  void set_pressure(const Field& p, double s, Field& u);
  // Transform t (one forward), keep t̂, and return <t, G t> = Σ_i t_i (G t)_i.
  double set_direction(const Field& t);
  // p̂ ← s (p̂ − τ t̂) and u = G p (one inverse). The caller applies the same step to
  // its real-space p.
  void step_pressure(double s, double tau, Field& u);
  // From now on set_pressure and step_pressure return h + G p instead of G p (the
  // offset is added in Fourier space, so it costs no pass over the grid): solvers that
  // only ever need h + u save reading h. One forward transform.
  void set_offset(const Field& h);
  void clear_offset() { offset_hat_.clear(); }

  // FFT pairs done so far by this operator (forward + inverse transforms, halved):
  // the unit of cost cmc reports.
  double fft_pairs() const {
    return fourier_ ? 0.5 * double(fourier_->forward_count() + fourier_->inverse_count()) : 0.0;
  }
  // Size of the transform behind one apply (for cost reports).
  std::size_t transform_size() const { return fourier_ ? fourier_->real_size() : 0; }

 protected:
  HalfSpace(const Grid& g, double estar);
  // Fill the transform grid from a field on the contact grid (zero padding where the
  // transform grid is larger) and return it; and the way back.
  virtual const double* to_transform_grid(const Field& f) = 0;
  virtual void from_transform_grid(Field& out) = 0;  // inverse transform of spectrum() into out
  // Calls f(k, w) for every r2c mode k with its weight w in a sum over the full
  // (Hermitian) spectrum.
  template <class F>
  void for_each_mode(F&& f) const;

  Grid grid_;
  double estar_;
  std::unique_ptr<Fourier> fourier_;
  Field kernel_;  // real Fourier multiplier of G on the transform grid, times 1/N
  Spectrum p_hat_, t_hat_, offset_hat_;  // offset_hat_ = FFT(h)/N, or empty
};

class PeriodicHalfSpace final : public HalfSpace {
 public:
  PeriodicHalfSpace(const Grid& g, double estar);
  bool periodic() const override { return true; }
  void pressure(const Field& u, Field& p, double tol = 1e-12) override;
  double energy_from_displacement(const Field& u) override;
  // Multiplier 2/(E*|q|) times the FFT normalisation, r2c layout (0 at q = 0).
  const Field& kernel() const { return kernel_; }

 private:
  const double* to_transform_grid(const Field& f) override { return f.data(); }
  void from_transform_grid(Field& out) override;
};

class FreeHalfSpace final : public HalfSpace {
 public:
  FreeHalfSpace(const Grid& g, double estar);
  bool periodic() const override { return false; }
  void pressure(const Field& u, Field& p, double tol = 1e-12) override;
  double energy_from_displacement(const Field& u) override;
  // Displacement at (x, y) from unit pressure on one cell centred at the origin.
  static double influence(double x, double y, double dx, double dy, double estar);

 private:
  const double* to_transform_grid(const Field& f) override;
  void from_transform_grid(Field& out) override;
  Field padded_;  // (2nx) x (2ny) work array
};

std::unique_ptr<HalfSpace> make_half_space(const Grid& g, double estar, bool periodic);

}  // namespace cmc
