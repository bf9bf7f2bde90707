// The thin grid layer: the field types, every FFT and every global reduction.
//
// Solvers and observables never call FFTW or sum over a whole field by hand across
// ranks: they call Fourier and the reductions below, so that a distributed backend
// (FFTW's MPI interface, slab decomposition along y) can replace this file without
// touching them. Today everything is local to one process; `Grid::sum` etc. are
// where an MPI_Allreduce would go.
//
// Layout: row-major, x fastest: value (ix, iy) sits at index iy*nx + ix.
// Reduced units inside cmc: lengths in units of the system size, pressures in units
// of E* (see Units.hpp for the single place where SI is converted).
#pragma once

#include <complex>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace cmc {

// Allocator aligned for FFTW's SIMD code paths (fftw_malloc).
template <class T>
struct FftwAllocator {
  using value_type = T;
  FftwAllocator() = default;
  template <class U>
  FftwAllocator(const FftwAllocator<U>&) noexcept {}
  T* allocate(std::size_t n);
  void deallocate(T* p, std::size_t) noexcept;
  template <class U>
  bool operator==(const FftwAllocator<U>&) const noexcept { return true; }
};

using Field = std::vector<double, FftwAllocator<double>>;
using Complex = std::complex<double>;
using Spectrum = std::vector<Complex, FftwAllocator<Complex>>;

// A uniform, rectangular grid of nx * ny points covering lx * ly (reduced units).
// ny == 1 is a genuinely one-dimensional (plane-strain) problem.
struct Grid {
  int nx = 0, ny = 0;
  double lx = 1.0, ly = 1.0;

  std::size_t size() const { return std::size_t(nx) * std::size_t(ny); }
  double dx() const { return lx / nx; }
  double dy() const { return ly / ny; }
  double cell_area() const { return dx() * dy(); }
  double area() const { return lx * ly; }
  int nqx() const { return nx / 2 + 1; }  // r2c keeps half of the x-modes
  std::size_t spectrum_size() const { return std::size_t(nqx()) * std::size_t(ny); }
  // Angular wavenumbers of mode (iqx, iqy) in the r2c layout.
  double qx(int iqx) const;
  double qy(int iqy) const;

  Field field(double value = 0.0) const { return Field(size(), value); }

  // Global reductions (the hook for a distributed backend).
  static double sum(std::span<const double> v);
  static double max(std::span<const double> v);
  static double min(std::span<const double> v);
  static double mean(std::span<const double> v) { return sum(v) / double(v.size()); }
  // In-place global sum of a few partial sums computed by a fused loop.
  template <std::size_t K>
  static void allreduce_sum(double (&)[K]) {}
  static void allreduce_max(double&) {}
};

// Real-to-complex and complex-to-real transforms of one grid shape. Plans are made
// once (FFTW_MEASURE unless CMC_FFTW_PLANNER says otherwise), with wisdom kept in
// $CMC_FFTW_WISDOM (default ~/.cache/cmc/fftw-wisdom), and reused for every call.
// forward() is unnormalised; inverse() is unnormalised too: callers fold 1/N into
// their Fourier-space multiply so that no extra pass over the data is needed.
class Fourier {
 public:
  Fourier(int nx, int ny);
  ~Fourier();
  Fourier(const Fourier&) = delete;
  Fourier& operator=(const Fourier&) = delete;

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  std::size_t real_size() const { return std::size_t(nx_) * ny_; }
  std::size_t spectrum_size() const { return std::size_t(nx_ / 2 + 1) * ny_; }
  double normalisation() const { return 1.0 / double(real_size()); }

  // The internal spectrum buffer that forward() fills and inverse() consumes.
  Spectrum& spectrum() { return spec_; }
  // in (real_size) -> spectrum(); input preserved.
  void forward(const double* in);
  void forward(const Field& in) { forward(in.data()); }
  // spectrum() -> out (real_size); the spectrum buffer is destroyed.
  void inverse(double* out);
  void inverse(Field& out) { inverse(out.data()); }
  // Transform an arbitrary buffer (must be FFTW-aligned and of the right size).
  void forward(const double* in, Complex* out);
  void inverse(Complex* in_destroyed, double* out);

  // Number of forward and inverse transforms done so far (an FFT pair = one each).
  long forward_count() const { return n_forward_; }
  long inverse_count() const { return n_inverse_; }

 private:
  int nx_, ny_;
  Spectrum spec_;
  void* plan_forward_ = nullptr;
  void* plan_inverse_ = nullptr;
  long n_forward_ = 0, n_inverse_ = 0;
};

// Threads used by FFTW (and by elementwise loops, where parallel): $CMC_THREADS or
// all hardware threads.
int thread_count();
// Write FFTW wisdom gathered so far (done automatically after planning).
void save_fftw_wisdom();

}  // namespace cmc
