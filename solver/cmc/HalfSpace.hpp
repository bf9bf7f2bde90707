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

#include "cmc/Grid.hpp"

#include <memory>

namespace cmc {

class HalfSpace {
 public:
  virtual ~HalfSpace() = default;
  const Grid& grid() const { return grid_; }
  double contact_modulus() const { return estar_; }
  virtual bool periodic() const = 0;

  // u = G p. One FFT pair. `u` may not alias `p`.
  virtual void displacement(const Field& p, Field& u) = 0;
  // p = G^{-1} u. Periodic: exact, one FFT pair, and the returned pressure has zero
  // mean (a periodic displacement field carries no information on the mean load:
  // add it yourself). Free: solved by conjugate gradients to `tol` relative.
  virtual void pressure(const Field& u, Field& p, double tol = 1e-12) = 0;
  // Elastic energy stored by the pair (p, u = G p): (1/2) ∫ p u dA.
  double energy(const Field& p, const Field& u) const;
  // Elastic energy computed in Fourier space from u alone (periodic only):
  // U = A (E*/4) Σ_q |q| |ũ_q|², ũ_q the Fourier-series coefficients of u.
  virtual double energy_from_displacement(const Field& u) = 0;

  // FFT pairs done so far by this operator (the unit of cost cmc reports).
  long fft_pairs() const { return fourier_ ? fourier_->inverse_count() : 0; }
  // Size of the transform behind one apply (for cost reports).
  std::size_t transform_size() const { return fourier_ ? fourier_->real_size() : 0; }

 protected:
  HalfSpace(const Grid& g, double estar);
  Grid grid_;
  double estar_;
  std::unique_ptr<Fourier> fourier_;
};

class PeriodicHalfSpace final : public HalfSpace {
 public:
  PeriodicHalfSpace(const Grid& g, double estar);
  bool periodic() const override { return true; }
  void displacement(const Field& p, Field& u) override;
  void pressure(const Field& u, Field& p, double tol = 1e-12) override;
  double energy_from_displacement(const Field& u) override;
  // Multiplier 2/(E*|q|) times the FFT normalisation, r2c layout (0 at q = 0).
  const Field& kernel() const { return kernel_; }

 private:
  Field kernel_;
};

class FreeHalfSpace final : public HalfSpace {
 public:
  FreeHalfSpace(const Grid& g, double estar);
  bool periodic() const override { return false; }
  void displacement(const Field& p, Field& u) override;
  void pressure(const Field& u, Field& p, double tol = 1e-12) override;
  double energy_from_displacement(const Field& u) override;
  // Displacement at (x, y) from unit pressure on one cell centred at the origin.
  static double influence(double x, double y, double dx, double dy, double estar);

 private:
  Field padded_;   // (2nx) x (2ny) work array
  Field kernel_;   // Fourier transform of the influence coefficients (real, even)
};

std::unique_ptr<HalfSpace> make_half_space(const Grid& g, double estar, bool periodic);

}  // namespace cmc
