// The linear-elastic half-space under normal surface pressure, small-slope approximation:
// cmc's one elastic operator. Every solver, observable and test that needs the elastic
// response uses this class; no solver builds Green's-function kernels of its own.
//
// Convention: compressive pressure p > 0 pushes the surface into the solid; the
// displacement u > 0 points into the solid. Two boundaries:
//  * periodic: u~(q) = 2 p~(q) / (E* |q|) for q != 0 (Johnson, Contact Mechanics (1985),
//    §13.2; Johnson, Greenwood & Higginson, Int. J. Mech. Sci. 27, 383 (1985), App. A.2).
//    The mean displacement is not defined by a periodic load; cmc fixes it to zero, so
//    penetrations are measured from the mean plane of the deformed elastic surface.
//  * free: an isolated (non-periodic) surface patch. Pressure is uniform on each cell and
//    the displacement is collocated at cell centres, with Love's closed-form influence
//    coefficient of a uniformly loaded rectangle (Love 1929; Johnson 1985 eq. 3.25). The
//    convolution is done by FFT on a grid zero-padded to twice the size per side (Hockney
//    1970; Liu, Wang & Liu, Wear 243, 101 (2000), "DC-FFT"), so no periodic image reaches
//    the patch.
//
// The operator works on two grids: the contact grid (the case's grid, where pressures,
// gaps and displacements live) and the transform grid (the contact grid itself when
// periodic, the zero-padded 2nx x 2ny grid when free). It offers
//  * contact-grid operations: u = G p, p = G⁻¹ u, the elastic energy;
//  * transform-grid operations for solvers that iterate on whole transform-grid fields
//    (the adhesive solver keeps the padding displacements as unknowns): out = M in for a
//    Fourier multiplier M (the compliance G or the stiffness K = G⁻¹), with in·M in from
//    Parseval in the same pass;
//  * spectral primitives for solvers that keep a field's transform between iterations
//    (Polonsky–Keer): forward() into a caller's spectrum, inverse() from the scratch
//    spectrum back onto the contact grid, and quadratic_form().
// It counts its transforms: fft_pairs() is the unit of cost cmc reports.
#pragma once

#include "cmc/grid/Grid.hpp"
#include "cmc/grid/Ranks.hpp"

#include <memory>
#include <string>

namespace cmc {

class HalfSpace {
 public:
  enum class Boundary { Periodic, Free };
  HalfSpace(const Grid& g, double estar, Boundary boundary);
  virtual ~HalfSpace();
  HalfSpace(const HalfSpace&) = delete;
  HalfSpace& operator=(const HalfSpace&) = delete;

  const Grid& grid() const { return grid_; }
  double contact_modulus() const { return estar_; }
  bool periodic() const { return boundary_ == Boundary::Periodic; }
  // Whether the row-column transform (grid/RowColumnFourier.hpp) can run this operator: a
  // periodic grid held by one process, of more than one row (Polonsky-Keer's fused sweeps).
  bool row_column() const { return periodic() && !grid_.split() && grid_.ny > 1; }

  // ---- contact grid
  // u = G p. One FFT pair. `u` may not alias `p`.
  void displacement(const Field& p, Field& u);
  // p = G⁻¹ u. Periodic: exact, one FFT pair, and the returned pressure has zero mean (a
  // periodic displacement field carries no information on the mean load: add it
  // yourself). Free: solved by conjugate gradients to `tol` relative.
  void pressure(const Field& u, Field& p, double tol = 1e-12);
  // Elastic energy stored by the pair (p, u = G p): (1/2) ∫ p u dA.
  double energy(const Field& p, const Field& u) const;
  // The same from Σ p u over the grid (for a caller that summed it in a pass of its own).
  double energy_from_sum(double sum_pu) const { return 0.5 * sum_pu * grid_.cell_area(); }
  // Elastic energy from u alone. Periodic: U = A (E*/4) Σ_q |q| |ũ_q|² (ũ_q the
  // Fourier-series coefficients of u); free: (1/2) ∫ p u with p = G⁻¹ u.
  double energy_from_displacement(const Field& u);

  // ---- transform grid
  int transform_nx() const { return mx_; }
  int transform_ny() const { return my_; }
  // Points of the transform grid this process holds (a field's length there), and of
  // the whole transform grid.
  std::size_t transform_size() const { return tgrid_.size(); }
  // The transform grid's rows that this process holds (its y0 and rows()).
  const Grid& transform_slab() const { return tgrid_; }
  std::size_t transform_points() const { return std::size_t(mx_) * std::size_t(my_); }
  std::size_t spectrum_size() const { return fourier_.spectrum_size(); }
  // Fourier multipliers on the transform grid (r2c layout) with the normalisation 1/M of
  // the unnormalised inverse transform folded in. compliance: G (0 at q = 0 when
  // periodic). stiffness: K = G⁻¹ (periodic: E*|q|/2, 0 at q = 0; free: the inverse of
  // the padded circulant, which is positive definite), made on first use.
  const Field& compliance() const { return compliance_; }
  const Field& stiffness();
  // out = M in on the transform grid (both of transform_size()); returns in·(M in)
  // = Σ_i in_i (M in)_i, from Parseval inside the multiply. One FFT pair.
  double apply(const double* in, double* out, const Field& multiplier);
  // K applied to a unit displacement at point 0 of the transform grid: the pressure
  // field that holds u = 1 there and u = 0 everywhere else. By translation invariance
  // (of the padded circulant when free) its entry 0 is the diagonal K_ii of every
  // point: self_stiffness(), ≈ 1.2 E*/Δx on a periodic square grid. One FFT pair each.
  Field unit_response();
  double self_stiffness();
  // Entry (row, col) of the whole transform grid of a field f of which this process holds
  // its slab (transform_size()), on every rank: from the rank that holds it (collective).
  double transform_entry(const Field& f, int row, int col) const;

  // ---- spectral primitives (contact-grid fields, zero-padded when free)
  // out = FFT(f) on the transform grid (unnormalised). One forward transform.
  void forward(const Field& f, Spectrum& out);
  // spectrum() = FFT(f) on the transform grid (unnormalised). One forward transform.
  void forward(const Field& f);
  // The scratch spectrum that inverse() consumes.
  std::span<Complex> spectrum() { return fourier_.spectrum(); }
  // That buffer made at least `modes` long, as a longer layout's scratch (Fourier::scratch).
  Complex* scratch_spectrum(std::size_t modes) { return fourier_.scratch(modes); }
  // out = inverse FFT of spectrum() restricted to the contact grid (unnormalised; the
  // scratch spectrum is destroyed). One inverse transform.
  void inverse(Field& out);
  // Σ_i f_i (M f)_i for f with transform s (= (1/M) Σ_q M(q) |s_q|², the 1/M being in M).
  double quadratic_form(std::span<const Complex> s, const Field& multiplier) const;

  // FFT pairs done so far by this operator ((forward + inverse transforms) / 2).
  // Transforms done for this operator elsewhere (a solver's device backend, the CPU
  // backend's fused sweeps: RowColumnFourier) count too.
  double fft_pairs() const {
    return 0.5 * double(fourier_.forward_count() + fourier_.inverse_count() + device_forward_ + device_inverse_);
  }
  // Seconds spent inside those transforms (wall clock).
  double fft_seconds() const { return fourier_.seconds() + device_seconds_; }
  // Add transforms done on this operator's grid by another transform object (a device
  // backend, RowColumnFourier), and their seconds.
  void count_transforms(long forward, long inverse, double seconds) {
    device_forward_ += forward, device_inverse_ += inverse, device_seconds_ += seconds;
  }
  // Seconds of one FFT pair (forward + inverse on the transform grid), timed here and now:
  // the fastest of at least `min_repeats` pairs taking `min_seconds`, after one untimed
  // pair. The unit a run's cost is reported in, measured in the same run. Counts in
  // fft_pairs().
  double time_fft_pair(double min_seconds = 0.25, int min_repeats = 5);
  // The same for the row-column pair (grid/RowColumnFourier.hpp: rows, then column blocks,
  // and back), the transforms Polonsky-Keer's fused sweeps run on a periodic grid held by
  // one process, in the scratch spectrum those sweeps use; 0 where they do not run (a free
  // boundary, a distributed grid, one row). Not counted in fft_pairs().
  double time_row_column_pair(double min_seconds = 0.25, int min_repeats = 5);
  // Where the operator's FFT plans came from (Fourier::plan_source: "built-in wisdom", ...).
  const char* plan_source() const { return fourier_.plan_source(); }
  // Transforms a solver makes of its own for this grid, and where their plans came from
  // (Polonsky-Keer's fused sweeps: "row-column (fused sweeps): built-in wisdom"): noted by
  // the solver, reported beside plan_source() in summary.json. Empty: none.
  void note_solver_plans(std::string what) { solver_plans_ = std::move(what); }
  const std::string& solver_plans() const { return solver_plans_; }

  // Displacement at (x, y) from unit pressure on one cell of size dx x dy centred at the
  // origin (Love 1929): the free boundary's influence coefficient.
  static double influence(double x, double y, double dx, double dy, double estar);

 private:
  static Grid checked(const Grid& g, double estar, Boundary b);  // throws on bad input
  static Grid transform_grid(const Grid& g, Boundary b);
  template <class F>
  Field periodic_multiplier(F f) const;
  const double* to_transform_grid(const Field& f);  // zero-padded copy when free
  void make_periodic_compliance();
  void make_free_compliance();
  double spectral_sum(const Complex* s, const double* mul, std::size_t r0, std::size_t r1) const;

  Grid grid_;
  std::string solver_plans_;
  double estar_;
  Boundary boundary_;
  int mx_, my_;
  Grid tgrid_;  // the transform grid (this process's slab of it)
  Fourier fourier_;
  Field compliance_, stiffness_;
  Field abs_q_;   // periodic: |q| / N², made by the first energy_from_displacement
  Field padded_;  // free only: transform-grid work array
  std::unique_ptr<RowExchange> exchange_;  // free and distributed: contact rows <-> padded slab
  long device_forward_ = 0, device_inverse_ = 0;
  double device_seconds_ = 0.0;
};

// The two boundaries by name (constructors only; the operator is the same class).
struct PeriodicHalfSpace final : HalfSpace {
  PeriodicHalfSpace(const Grid& g, double estar) : HalfSpace(g, estar, Boundary::Periodic) {}
};
struct FreeHalfSpace final : HalfSpace {
  FreeHalfSpace(const Grid& g, double estar) : HalfSpace(g, estar, Boundary::Free) {}
};

std::unique_ptr<HalfSpace> make_half_space(const Grid& g, double estar, bool periodic);

}  // namespace cmc
