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
#include <cstdint>
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

  // Global reductions over whole fields. Every sum, count, extremum and dot product of
  // cmc goes through these or through parallel_reduce below: they are where a distributed
  // backend (MPI slabs, a GPU) combines its partial results. Nothing outside grid/ loops
  // over a field to reduce it (tests/test_grid_layer.cpp checks the sources).
  static double sum(std::span<const double> v);
  static double max(std::span<const double> v);
  static double min(std::span<const double> v);
  static double mean(std::span<const double> v) { return sum(v) / double(v.size()); }
  static double dot(std::span<const double> a, std::span<const double> b);
  // Number of set entries of a mask, and of entries for which pred(v) holds.
  static std::size_t count(std::span<const std::uint8_t> mask);
  template <class Pred>
  static std::size_t count_if(std::span<const double> v, Pred pred);

  // A fused per-point pass with partial results: body(begin, end, acc) handles the
  // index range [begin, end) of [0, n) and accumulates into acc. The range is split into
  // one contiguous chunk per thread (OpenMP, static: the split and the order in which
  // the partials are merged depend only on the thread count, so a rerun gives the same
  // bits), each chunk starts from a default-constructed Acc, and the partials are merged
  // in chunk order with acc.merge(other). Passes over fewer than `parallel_min` indices
  // of work run on one thread. Acc must be default-constructible with the identity of
  // every reduction it holds (0 for sums, -inf for maxima).
  template <class Acc, class Body>
  static Acc parallel_reduce(std::size_t n, Body&& body, std::size_t work = 0);
  // The same without partial results (a pure per-point pass).
  template <class Body>
  static void parallel_for(std::size_t n, Body&& body, std::size_t work = 0);
  // Passes smaller than this many points of work run on one thread: OpenMP's fork/join
  // costs more than it saves below it (measured on 2 cores, wave 1).
  static constexpr std::size_t parallel_min = std::size_t(1) << 15;
};

// Real-to-complex and complex-to-real transforms of one grid shape, planned once and
// reused for every call. By default ($CMC_FFTW_PLANNER unset or "builtin") the plans come
// from wisdom made with FFTW_MEASURE at build time and compiled in (square grids of 2^k
// points up to 4096 per side, 1-D lines up to 65536; solver/tools/make_wisdom.cpp), and
// from FFTW_ESTIMATE for other shapes: nothing is timed at run time, so every run of a
// build computes with the same plans (the same bits on a rerun) and a first run does not
// wait for planning. CMC_FFTW_PLANNER=measure (or patient) times plans at run time and
// keeps wisdom in $CMC_FFTW_WISDOM (default ~/.cache/cmc/fftw-wisdom): faster for shapes
// the build did not plan, but not reproducible bit for bit. "estimate": ESTIMATE only.
// forward() is unnormalised; inverse() is unnormalised too: callers fold 1/N into
// their Fourier-space multiply so that no extra pass over the data is needed.
// Owner of one FFTW plan (destroyed under the planner lock, FFTW's planner is not thread
// safe): a plan cannot leak, even when a constructor throws half-way.
struct FftwPlanDeleter {
  void operator()(void* plan) const noexcept;
};
using FftwPlan = std::unique_ptr<void, FftwPlanDeleter>;

class Fourier {
 public:
  Fourier(int nx, int ny);
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
  // Where the plans came from: "built-in wisdom", "estimate", "measure" or "patient".
  const char* plan_source() const { return plan_source_; }

 private:
  int nx_, ny_;
  Spectrum spec_;
  FftwPlan plan_forward_, plan_inverse_;
  const char* plan_source_ = "";
  long n_forward_ = 0, n_inverse_ = 0;
};

// Threads used by FFTW (and by elementwise loops, where parallel): $CMC_THREADS or
// all hardware threads.
int thread_count();

// ---------------------------------------------------------------- pass templates

// The partial result of a pass that only sums (for Grid::parallel_reduce).
struct SumReduction {
  double v = 0.0;
  void merge(const SumReduction& o) { v += o.v; }
};

namespace detail {
int omp_threads_for(std::size_t work);  // 1 below Grid::parallel_min, else thread_count()
int omp_thread_id();
int omp_thread_total();
}  // namespace detail

template <class Acc, class Body>
Acc Grid::parallel_reduce(std::size_t n, Body&& body, std::size_t work) {
  const int nt = detail::omp_threads_for(work ? work : n);
  if (nt <= 1) {
    Acc acc{};
    if (n) body(std::size_t(0), n, acc);
    return acc;
  }
  // One partial per requested thread; a thread the runtime did not start leaves the
  // identity, which merges exactly.
  std::vector<Acc> part(std::size_t(nt), Acc{});
#pragma omp parallel num_threads(nt)
  {
    const int t = detail::omp_thread_id(), m = detail::omp_thread_total();
    const std::size_t b = n * std::size_t(t) / std::size_t(m), e = n * std::size_t(t + 1) / std::size_t(m);
    if (e > b) body(b, e, part[std::size_t(t)]);
  }
  Acc acc{};
  for (const Acc& p : part) acc.merge(p);
  return acc;
}

template <class Body>
void Grid::parallel_for(std::size_t n, Body&& body, std::size_t work) {
  struct None {
    void merge(const None&) {}
  };
  parallel_reduce<None>(n, [&](std::size_t b, std::size_t e, None&) { body(b, e); }, work);
}

template <class Pred>
std::size_t Grid::count_if(std::span<const double> v, Pred pred) {
  struct Count {
    std::size_t n = 0;
    void merge(const Count& o) { n += o.n; }
  };
  return parallel_reduce<Count>(v.size(), [&](std::size_t b, std::size_t e, Count& c) {
    std::size_t k = 0;
    for (std::size_t i = b; i < e; ++i) k += pred(v[i]) ? 1 : 0;
    c.n += k;
  }).n;
}
// Write FFTW wisdom gathered so far (done automatically after planning).
void save_fftw_wisdom();

}  // namespace cmc
