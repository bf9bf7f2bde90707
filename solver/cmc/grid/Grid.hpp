// The thin grid layer: the field types, every FFT and every global reduction.
//
// Solvers and observables never call FFTW or sum over a whole field by hand across
// ranks: they call Fourier and the reductions below. In the MPI build (-DCMC_MPI=ON,
// grid/Ranks.hpp) a grid can be a slab: this process holds rows [y0, y0 + rows()) of
// the global ny (FFTW's MPI slab decomposition along y; the r2c spectrum is split along
// qy into the same rows, not transposed), every field holds only those rows, and every
// reduction combines the partial results of all ranks in rank order (the same bits on
// a rerun at the same number of ranks). Serial runs, and one rank, are unchanged.
//
// Layout: row-major, x fastest: value (ix, iy) sits at index (iy - y0)*nx + ix.
// Reduced units inside cmc: lengths in units of the system size, pressures in units
// of E* (see Units.hpp for the single place where SI is converted).
#pragma once

#include <algorithm>
#include <chrono>
#include <complex>
#include <cstring>
#include <type_traits>
#include <cstdint>
#include <cstddef>
#include <functional>
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

// The bytes that fields and spectra (everything FftwAllocator makes) hold in this process
// now, and the most they held since the last reset_field_peak(): what a run allocates for
// its fields, counted where they are allocated (summary.json "model";
// tests/test_scene_needs.cpp holds a hard-wall run to no adhesive field with it).
std::size_t field_bytes_now();
std::size_t field_bytes_peak();
void reset_field_peak();
using Complex = std::complex<double>;
using Spectrum = std::vector<Complex, FftwAllocator<Complex>>;

// A uniform, rectangular grid of nx * ny points covering lx * ly (reduced units).
// ny == 1 is a genuinely one-dimensional (plane-strain) problem.
struct Grid {
  int nx = 0, ny = 0;
  double lx = 1.0, ly = 1.0;
  // The slab this process holds in a distributed run (Ranks.hpp, distribute()): rows
  // [y0, y0 + local_ny) of ny. local_ny < 0: the whole grid (every serial run).
  int y0 = 0, local_ny = -1;

  int rows() const { return local_ny < 0 ? ny : local_ny; }
  bool split() const { return local_ny >= 0 && local_ny != ny; }
  // Points this process holds: the length of a field. points(): of the whole grid.
  std::size_t size() const { return std::size_t(nx) * std::size_t(rows()); }
  std::size_t points() const { return std::size_t(nx) * std::size_t(ny); }
  double dx() const { return lx / nx; }
  double dy() const { return ly / ny; }
  double cell_area() const { return dx() * dy(); }
  double area() const { return lx * ly; }
  int nqx() const { return nx / 2 + 1; }  // r2c keeps half of the x-modes
  // Angular wavenumbers of mode (iqx, iqy) in the r2c layout (iqy global: y0 + local row).
  double qx(int iqx) const;
  double qy(int iqy) const;

  Field field(double value = 0.0) const { return Field(size(), value); }

  // Global reductions over whole fields. Every sum, count, extremum and dot product of
  // cmc goes through these or through parallel_reduce below: they are where a distributed
  // backend (MPI slabs, a GPU) combines its partial results. Nothing outside grid/ loops
  // over a field to reduce it (tests/test_grid_layer.cpp checks the sources). In a
  // distributed run they reduce over all ranks (each holding its slab), except inside a
  // LocalReductions scope (Ranks.hpp), for data every rank holds whole.
  static double sum(std::span<const double> v);
  static double max(std::span<const double> v);
  static double min(std::span<const double> v);
  static double mean(std::span<const double> v) { return sum(v) / double(total(v.size())); }
  // The number of entries over all ranks of a field of which this process holds n.
  static std::size_t total(std::size_t n);
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
  // Tasks 0..k-1 of uneven size, each handed to the next thread that is free (OpenMP's
  // dynamic schedule): for work split by the data, not by the thread count, so that the
  // result does not depend on the thread count. task(i) writes only what task i owns.
  // `work`: the points behind all of them (below parallel_min: one thread, in task order).
  template <class Task>
  static void parallel_tasks(std::size_t k, Task&& task, std::size_t work);
  // Passes smaller than this many points of work run on one thread: OpenMP's fork/join
  // costs more than it saves below it (measured on 2 cores).
  static constexpr std::size_t parallel_min = std::size_t(1) << 15;
};

// Where the modes of a spectrum sit in this process's part of it: `rows` rows of `cols`
// modes, entry (r, c) at index r * cols + c. Not transposed (every serial transform): row
// r holds the modes of qy index row0 + r, column c the qx index c (nx/2 + 1 columns).
// Transposed (a distributed transform, FFTW_MPI_TRANSPOSED_OUT: two of the four global
// transposes of an FFT pair saved): row r holds the qx index row0 + r, column c the qy
// index c (ny columns). Every loop over modes goes through iqx()/iqy().
struct SpectrumLayout {
  int rows = 0, cols = 0, row0 = 0;
  bool transposed = false;
  int iqx(int r, int c) const { return transposed ? row0 + r : c; }
  int iqy(int r, int c) const { return transposed ? c : row0 + r; }
  std::size_t size() const { return std::size_t(rows) * std::size_t(cols); }
  // Index of mode (iqx, iqy) if this process holds it, else -1.
  long index(int iqx, int iqy) const {
    const int r = (transposed ? iqx : iqy) - row0, c = transposed ? iqy : iqx;
    return r >= 0 && r < rows ? long(r) * cols + c : -1;
  }
};

// The weight of r2c mode iqx (of nx/2 + 1) in a sum over the whole spectrum: the modes
// iqx = 0 and, for even nx, iqx = nx/2 stand for themselves, every other one for itself and
// its conjugate, so Σ over the full spectrum = Σ over the half with these weights.
inline double r2c_mode_weight(int iqx, int nx) { return (iqx == 0 || 2 * iqx == nx) ? 1.0 : 2.0; }

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
  // A transform of the whole nx x ny grid, held by this process alone.
  Fourier(int nx, int ny);
  // A transform of grid g: distributed over the ranks (FFTW's MPI interface) when g is a
  // slab of a distributed run, else as Fourier(g.nx, g.ny). Every rank constructs it.
  explicit Fourier(const Grid& g);
  Fourier(const Fourier&) = delete;
  Fourier& operator=(const Fourier&) = delete;

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  // Entries of a real field and of a spectrum this process holds (its rows).
  std::size_t real_size() const { return std::size_t(nx_) * rows_; }
  std::size_t spectrum_size() const { return layout_.size(); }
  const SpectrumLayout& layout() const { return layout_; }
  // 1 / (nx ny): the whole grid's.
  double normalisation() const { return 1.0 / (double(nx_) * double(ny_)); }

  // The internal spectrum buffer that forward() fills and inverse() consumes
  // (spectrum_size() modes; a distributed transform works in place in it).
  std::span<Complex> spectrum() { return {spec_.data(), spectrum_size()}; }
  // The same buffer made at least `modes` long, as scratch for a spectrum of a longer
  // layout (RowColumnFourier's); it may move, and its contents are not kept. spectrum()
  // still shows the first spectrum_size(). A transform of one process only.
  Complex* scratch(std::size_t modes);
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
  // Seconds spent inside the transforms so far (wall clock): with the counts, what a
  // solve's time owes to the FFTs and what to everything else.
  double seconds() const { return seconds_; }
  // Where the plans came from: "built-in wisdom", "estimate", "measure" or "patient".
  const char* plan_source() const { return plan_source_; }

 private:
  Fourier(int nx, int ny, const Grid* slab);
  void make_local();
  void make_distributed(const Grid& slab);
  int nx_, ny_, rows_;
  SpectrumLayout layout_;
  Spectrum spec_;
  FftwPlan plan_forward_, plan_inverse_;
  // Distributed only: FFTW's MPI r2c works in place on rows padded to 2 (nx/2 + 1) reals
  // and may use more complex entries than the local spectrum as scratch (its
  // alloc_local): spec_ holds that many, spectrum() shows the first spectrum_size().
  bool distributed_ = false;
  const char* plan_source_ = "";
  long n_forward_ = 0, n_inverse_ = 0;
  double seconds_ = 0.0;
};

// Threads used by FFTW (and by elementwise loops, where parallel): $CMC_THREADS, or
// the hardware threads shared among the ranks that run on this machine.
int thread_count();

// A fingerprint of the FFT plans compiled into this build (FNV-1a 64 of the built-in
// wisdom, 16 hex digits). Every build plans at build time (FFTW_MEASURE), and two builds
// may pick plans that round differently: runs at the same thread count with the same
// fingerprint give the same bits, others may differ by round-off (summary.json grid).
const std::string& builtin_wisdom_fingerprint();

// ---------------------------------------------------------------- pass templates

// Combining the partial results of the ranks of a distributed run (Ranks.cpp; without
// MPI, or with one rank, or inside a LocalReductions scope, `local` itself). The ranks'
// partials are merged in rank order into a default-constructed Acc, so a rerun at the
// same number of ranks gives the same bits. A trivially copyable Acc travels as bytes;
// one holding vectors (histogram tallies) provides pack() -> std::vector<double> and a
// static unpack(std::span<const double>) -> Acc.
namespace detail {
bool reductions_span_ranks();
// Every rank's `bytes`, concatenated in rank order (each the same size).
std::vector<unsigned char> allgather_bytes(const void* bytes, std::size_t n);
// Every rank's vector, in rank order (sizes may differ).
std::vector<std::vector<double>> allgather_doubles(const std::vector<double>& v);
}  // namespace detail
template <class Acc>
Acc combine_ranks(const Acc& local) {
  if (!detail::reductions_span_ranks()) return local;
  Acc acc{};
  if constexpr (requires(const Acc& a) { a.pack(); }) {
    for (const auto& part : detail::allgather_doubles(local.pack())) acc.merge(Acc::unpack(part));
  } else {
    static_assert(std::is_trivially_copyable_v<Acc>, "a reduction crossing ranks needs a trivially copyable Acc or pack()/unpack()");
    const auto all = detail::allgather_bytes(&local, sizeof(Acc));
    for (std::size_t off = 0; off < all.size(); off += sizeof(Acc)) {
      Acc part;
      std::memcpy(static_cast<void*>(&part), all.data() + off, sizeof(Acc));
      acc.merge(part);
    }
  }
  return acc;
}

// The partial result of a pass that only sums (for Grid::parallel_reduce).
struct SumReduction {
  double v = 0.0;
  void merge(const SumReduction& o) { v += o.v; }
};

namespace detail {
// Adds the wall time of its scope to a counter (the transforms' share of a solve).
class ScopeTimer {
 public:
  explicit ScopeTimer(double& total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
  ~ScopeTimer() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  ScopeTimer(const ScopeTimer&) = delete;
  ScopeTimer& operator=(const ScopeTimer&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point t0_;
};
// Plans made under the FFTW planner's lock and the run's policy ($CMC_FFTW_PLANNER, see
// Fourier): make(flags) makes them (plans it already holds are replaced) and returns
// whether FFTW made them all; by default it is asked with FFTW_MEASURE | FFTW_WISDOM_ONLY
// (the built-in wisdom) and then with FFTW_ESTIMATE. `threads`: FFTW's threads for them.
// Returns where the plans came from, in Fourier::plan_source()'s words; throws if none.
const char* plan_under_policy(int threads, const std::function<bool(unsigned)>& make);
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
    return combine_ranks(acc);
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
  return combine_ranks(acc);
}

template <class Body>
void Grid::parallel_for(std::size_t n, Body&& body, std::size_t work) {
  const int nt = detail::omp_threads_for(work ? work : n);
  if (nt <= 1) {
    if (n) body(std::size_t(0), n);
    return;
  }
#pragma omp parallel num_threads(nt)
  {
    const int t = detail::omp_thread_id(), m = detail::omp_thread_total();
    const std::size_t b = n * std::size_t(t) / std::size_t(m), e = n * std::size_t(t + 1) / std::size_t(m);
    if (e > b) body(b, e);
  }
}

template <class Task>
void Grid::parallel_tasks(std::size_t k, Task&& task, std::size_t work) {
  const std::size_t nt = std::min(std::size_t(detail::omp_threads_for(work)), k);
  if (nt <= 1) {
    for (std::size_t i = 0; i < k; ++i) task(i);
    return;
  }
#pragma omp parallel for num_threads(int(nt)) schedule(dynamic, 1)
  for (std::size_t i = 0; i < k; ++i) task(i);
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
