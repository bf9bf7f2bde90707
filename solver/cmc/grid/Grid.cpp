#include "cmc/grid/Grid.hpp"
#include "cmc/grid/FilePaths.hpp"
#include "cmc/grid/Ranks.hpp"

#include <fftw3.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <mutex>
#include <new>
#include <numbers>
#include <stdexcept>
#include <thread>

#include <sys/mman.h>
#include <unistd.h>

#ifdef CMC_MPI
#include <fftw3-mpi.h>
#include <mpi.h>
#endif

namespace cmc {

namespace detail {
extern const char* const kBuiltinWisdom;  // generated at build time (solver/tools/make_wisdom.cpp)
}

// Arrays of 16 MiB and more (a 1448² field of doubles and up) ask the kernel for
// transparent huge pages (madvise; a no-op where THP is "never" or absent): a 2-D FFT
// and the Polonsky-Keer sweeps walk such arrays with strides of a row or a column block,
// touching a new 4 KiB page at almost every step, and with 2 MiB pages the TLB covers the
// whole grid. FFTW's 2-D pair (BM_FFTPair, 2 threads, same wisdom, best of 5, two rounds)
// took 131-133 ms instead of 144-153 ms at 4096² and 16.5-17.0 ms instead of 17.6-19.0 ms
// at 2048²; the Polonsky-Keer solves of the challenge did not change (10.6-10.9 s at
// 2048², 26.2-26.9 s hard wall at 4096², either way). Such an array is aligned to 2 MiB so
// that its pages are whole huge pages. Smaller arrays stay with fftw_malloc: posix_memalign
// for all of them raised the measured peak of small runs by up to 8 MB
// (Limits.MemoryEstimateBoundsMeasuredPeak). deallocate() gets the same n, so it knows
// which of the two made an array.
namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
bool huge_pages_for(std::size_t bytes) { return bytes >= 8 * kHugePage; }
std::atomic<std::size_t> fields_now{0}, fields_peak{0};
void count_field(std::size_t bytes) {
  const std::size_t now = fields_now.fetch_add(bytes) + bytes;
  std::size_t peak = fields_peak.load();
  while (now > peak && !fields_peak.compare_exchange_weak(peak, now)) {
  }
}
}  // namespace
std::size_t field_bytes_now() { return fields_now.load(); }
std::size_t field_bytes_peak() { return fields_peak.load(); }
void reset_field_peak() { fields_peak.store(fields_now.load()); }

template <class T>
T* FftwAllocator<T>::allocate(std::size_t n) {
  if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_alloc();
  const std::size_t bytes = n * sizeof(T);
  void* p = nullptr;
  if (huge_pages_for(bytes)) {
    if (posix_memalign(&p, kHugePage, bytes) != 0) throw std::bad_alloc();
    madvise(p, bytes / kHugePage * kHugePage, MADV_HUGEPAGE);
  } else {
    p = fftw_malloc(bytes);
    if (!p && n) throw std::bad_alloc();
  }
  count_field(bytes);
  return static_cast<T*>(p);
}
template <class T>
void FftwAllocator<T>::deallocate(T* p, std::size_t n) noexcept {
  fields_now.fetch_sub(n * sizeof(T));
  if (huge_pages_for(n * sizeof(T)))
    std::free(p);
  else
    fftw_free(p);
}
template struct FftwAllocator<double>;
template struct FftwAllocator<Complex>;

double Grid::qx(int iqx) const { return 2.0 * std::numbers::pi * iqx / lx; }
double Grid::qy(int iqy) const {
  const int k = iqy <= ny / 2 ? iqy : iqy - ny;
  return 2.0 * std::numbers::pi * k / ly;
}

namespace {
// The partials of the reductions below, combined across ranks by combine_ranks.
struct MaxOf {
  double v = -std::numeric_limits<double>::infinity();
  void merge(const MaxOf& o) { v = std::max(v, o.v); }
};
struct MinOf {
  double v = std::numeric_limits<double>::infinity();
  void merge(const MinOf& o) { v = std::min(v, o.v); }
};
struct CountOf {
  std::size_t v = 0;
  void merge(const CountOf& o) { v += o.v; }
};
}  // namespace

double Grid::sum(std::span<const double> v) {
  // Pairwise-blocked sum: accurate to ~1e-16 relative even at 65536^2 points.
  constexpr std::size_t B = 4096;
  SumReduction total;
  for (std::size_t i = 0; i < v.size(); i += B) {
    double s = 0.0;
    const std::size_t e = std::min(v.size(), i + B);
    for (std::size_t j = i; j < e; ++j) s += v[j];
    total.v += s;
  }
  return combine_ranks(total).v;
}
double Grid::max(std::span<const double> v) {
  MaxOf m;
  for (double x : v) m.v = std::max(m.v, x);
  return combine_ranks(m).v;
}
double Grid::min(std::span<const double> v) {
  MinOf m;
  for (double x : v) m.v = std::min(m.v, x);
  return combine_ranks(m).v;
}

double Grid::dot(std::span<const double> a, std::span<const double> b) {
  SumReduction s;
  for (std::size_t i = 0; i < a.size(); ++i) s.v += a[i] * b[i];
  return combine_ranks(s).v;
}
std::size_t Grid::count(std::span<const std::uint8_t> mask) {
  CountOf n;
  for (auto m : mask) n.v += m ? 1 : 0;
  return combine_ranks(n).v;
}

namespace detail {
int omp_threads_for(std::size_t work) { return work < Grid::parallel_min ? 1 : thread_count(); }
int omp_thread_id() { return omp_get_thread_num(); }
int omp_thread_total() { return omp_get_num_threads(); }
}  // namespace detail

int thread_count() {
  if (const char* s = std::getenv("CMC_THREADS")) {
    const int n = std::atoi(s);
    if (n > 0) return n;
  }
  const unsigned h = std::thread::hardware_concurrency();
  // Ranks started on this machine by mpirun share its threads.
  return std::max(1, (h ? int(h) : 1) / ranks_on_this_machine());
}

const std::string& builtin_wisdom_fingerprint() {
  static const std::string id = [] {
    std::uint64_t h = 14695981039346656037ull;  // FNV-1a, 64 bit
    for (const char* c = detail::kBuiltinWisdom; *c; ++c) h = (h ^ std::uint8_t(*c)) * 1099511628211ull;
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", (unsigned long long)h);
    return std::string(buf);
  }();
  return id;
}

namespace {
std::recursive_mutex planner_mutex;  // the FFTW planner is not thread safe (recursive: a plan may be freed while planning)
bool fftw_ready = false;

std::filesystem::path wisdom_path() {
  if (const char* s = std::getenv("CMC_FFTW_WISDOM")) return s;
  if (const char* h = std::getenv("HOME")) return std::filesystem::path(h) / ".cache/cmc/fftw-wisdom";
  return {};
}

// How plans are made ($CMC_FFTW_PLANNER): "builtin" (default) uses only the wisdom
// compiled in at build time (solver/tools/make_wisdom.cpp) and FFTW_ESTIMATE for the
// transforms it lacks: no timing at run time, so every run of a build gets the same
// plans. "measure" and "patient" time candidates at run time and keep wisdom in
// $CMC_FFTW_WISDOM (faster for grids the build did not plan, e.g. 8192², but two
// plannings may differ in round-off). "estimate": FFTW_ESTIMATE only.
enum class Planner { Builtin, Estimate, Measure, Patient };
Planner planner() {
  const char* s = std::getenv("CMC_FFTW_PLANNER");
  const std::string p = s ? s : "builtin";
  if (p == "estimate") return Planner::Estimate;
  if (p == "measure") return Planner::Measure;
  if (p == "patient") return Planner::Patient;
  if (p == "builtin") return Planner::Builtin;
  throw std::invalid_argument("CMC_FFTW_PLANNER: expected builtin, estimate, measure or patient, got '" + p + "'");
}
bool keeps_wisdom_file(Planner p) { return p == Planner::Measure || p == Planner::Patient; }

void init_fftw() {
  if (fftw_ready) return;
  fftw_init_threads();
#ifdef CMC_MPI
  if (ranks() > 1) fftw_mpi_init();
#endif
  fftw_plan_with_nthreads(thread_count());
  omp_set_num_threads(thread_count());
  if (planner() == Planner::Builtin) {
    fftw_import_wisdom_from_string(detail::kBuiltinWisdom);
  } else if (keeps_wisdom_file(planner())) {
    const auto w = wisdom_path();
    if (!w.empty() && std::filesystem::is_regular_file(w)) fftw_import_wisdom_from_filename(w.c_str());
  }
  fftw_ready = true;
}

// Plans r2c and c2r for one shape with `flags`; false if FFTW made none (with
// FFTW_WISDOM_ONLY: no wisdom for it).
bool make_plans(int nx, int ny, double* r, fftw_complex* c, unsigned flags, FftwPlan& f, FftwPlan& b) {
  if (ny == 1) {
    f.reset(fftw_plan_dft_r2c_1d(nx, r, c, flags));
    b.reset(fftw_plan_dft_c2r_1d(nx, c, r, flags));
  } else {
    f.reset(fftw_plan_dft_r2c_2d(ny, nx, r, c, flags));
    b.reset(fftw_plan_dft_c2r_2d(ny, nx, c, r, flags));
  }
  return f && b;
}
}  // namespace

void save_fftw_wisdom() {
  if (!keeps_wisdom_file(planner())) return;
  std::lock_guard lock(planner_mutex);
  const auto w = wisdom_path();
  if (w.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(w.parent_path(), ec);
  // Atomic, so a concurrent run never reads half a file; only into a new path or a regular
  // file (FilePaths.hpp). A cache: a target it refuses is left as it is, with a warning.
  try {
    write_output_file(w, [](const std::filesystem::path& tmp) {
      if (!fftw_export_wisdom_to_filename(tmp.c_str())) throw std::runtime_error("FFTW could not write it");
    });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmc: warning: FFTW wisdom not saved: %s\n", e.what());
  }
}

Fourier::Fourier(const Grid& g) : Fourier(g.nx, g.ny, g.split() ? &g : nullptr) {}
Fourier::Fourier(int nx, int ny) : Fourier(nx, ny, nullptr) {}

Fourier::Fourier(int nx, int ny, const Grid* slab) : nx_(nx), ny_(ny), rows_(slab ? slab->rows() : ny) {
  if (nx <= 0 || ny <= 0) throw std::invalid_argument("Fourier: grid must be positive");
  if (slab) make_distributed(*slab);
  else make_local();
}

void Fourier::make_distributed(const Grid& g) {
#ifdef CMC_MPI
  distributed_ = true;
  std::lock_guard lock(planner_mutex);
  init_fftw();
  ptrdiff_t n0 = 0, start = 0, n1 = 0, start1 = 0;
  const ptrdiff_t alloc =
      fftw_mpi_local_size_2d_transposed(ny_, nx_ / 2 + 1, MPI_COMM_WORLD, &n0, &start, &n1, &start1);
  if (n0 != rows_ || start != g.y0) throw std::logic_error("Fourier: the grid's slab differs from FFTW's");
  layout_ = SpectrumLayout{int(n1), ny_, int(start1), true};
  spec_.resize(std::max<std::size_t>(std::size_t(std::max<ptrdiff_t>(alloc, 1)), spectrum_size()));
  fftw_plan_with_nthreads(thread_count());
  // No wisdom is timed or compiled in for distributed plans: FFTW_ESTIMATE (the same
  // plans, so the same bits, on every run at the same number of ranks) unless
  // CMC_FFTW_PLANNER asks for timed plans. In place: spec_ holds the padded real rows
  // (2 (nx/2 + 1) reals each) on the way in and the spectrum on the way out, so a
  // distributed transform needs one buffer of FFTW's alloc_local besides the field.
  const Planner p = planner();
  const unsigned flags = p == Planner::Measure ? FFTW_MEASURE : p == Planner::Patient ? FFTW_PATIENT : FFTW_ESTIMATE;
  plan_source_ = p == Planner::Measure ? "measure (MPI)" : p == Planner::Patient ? "patient (MPI)" : "estimate (MPI)";
  auto* c = reinterpret_cast<fftw_complex*>(spec_.data());
  auto* r = reinterpret_cast<double*>(spec_.data());
  plan_forward_.reset(fftw_mpi_plan_dft_r2c_2d(ny_, nx_, r, c, MPI_COMM_WORLD, flags | FFTW_MPI_TRANSPOSED_OUT));
  plan_inverse_.reset(fftw_mpi_plan_dft_c2r_2d(ny_, nx_, c, r, MPI_COMM_WORLD, flags | FFTW_MPI_TRANSPOSED_IN));
  if (!plan_forward_ || !plan_inverse_) throw std::runtime_error("FFTW could not plan a distributed transform");
#else
  (void)g;
  throw std::logic_error("Fourier: a split grid needs the MPI build");
#endif
}

void Fourier::make_local() {
  const int nx = nx_, ny = ny_;
  layout_ = SpectrumLayout{ny, nx / 2 + 1, 0, false};
  spec_.resize(spectrum_size());
  Field scratch(real_size());
  auto* c = reinterpret_cast<fftw_complex*>(spec_.data());
  // Threads only pay on large transforms: on small (e.g. 1-D) ones they cost 3-8x.
  plan_source_ = detail::plan_under_policy(real_size() < (std::size_t(1) << 16) ? 1 : thread_count(), [&](unsigned flags) {
    return make_plans(nx, ny, scratch.data(), c, flags, plan_forward_, plan_inverse_);
  });
  save_fftw_wisdom();
}

namespace detail {
const char* plan_under_policy(int threads, const std::function<bool(unsigned)>& make) {
  std::lock_guard lock(planner_mutex);
  init_fftw();
  fftw_plan_with_nthreads(threads);
  const Planner p = planner();
  if (p == Planner::Builtin && make(FFTW_MEASURE | FFTW_WISDOM_ONLY)) return "built-in wisdom";
  const unsigned flags = p == Planner::Measure ? FFTW_MEASURE : p == Planner::Patient ? FFTW_PATIENT : FFTW_ESTIMATE;
  if (!make(flags)) throw std::runtime_error("FFTW could not plan a transform");
  return p == Planner::Measure ? "measure" : p == Planner::Patient ? "patient" : "estimate";
}
}  // namespace detail

void FftwPlanDeleter::operator()(void* plan) const noexcept {
  std::lock_guard lock(planner_mutex);
  fftw_destroy_plan(static_cast<fftw_plan>(plan));
}


void Fourier::forward(const double* in, Complex* out) {
  const detail::ScopeTimer timer(seconds_);
  if (distributed_) {
#ifdef CMC_MPI
    const std::size_t nx = std::size_t(nx_), stride = 2 * std::size_t(nx_ / 2 + 1);
    double* pad = reinterpret_cast<double*>(spec_.data());
    for (std::size_t r = 0; r < std::size_t(rows_); ++r) std::copy_n(in + r * nx, nx, pad + r * stride);
    fftw_mpi_execute_dft_r2c(static_cast<fftw_plan>(plan_forward_.get()), pad,
                             reinterpret_cast<fftw_complex*>(spec_.data()));
    if (out != spec_.data()) std::copy_n(spec_.data(), spectrum_size(), out);
#endif
  } else {
    fftw_execute_dft_r2c(static_cast<fftw_plan>(plan_forward_.get()), const_cast<double*>(in),
                         reinterpret_cast<fftw_complex*>(out));
  }
  ++n_forward_;
}
void Fourier::inverse(Complex* in, double* out) {
  const detail::ScopeTimer timer(seconds_);
  if (distributed_) {
#ifdef CMC_MPI
    if (in != spec_.data()) std::copy_n(in, spectrum_size(), spec_.data());
    double* pad = reinterpret_cast<double*>(spec_.data());
    fftw_mpi_execute_dft_c2r(static_cast<fftw_plan>(plan_inverse_.get()), reinterpret_cast<fftw_complex*>(spec_.data()),
                             pad);
    const std::size_t nx = std::size_t(nx_), stride = 2 * std::size_t(nx_ / 2 + 1);
    for (std::size_t r = 0; r < std::size_t(rows_); ++r) std::copy_n(pad + r * stride, nx, out + r * nx);
#endif
  } else {
    fftw_execute_dft_c2r(static_cast<fftw_plan>(plan_inverse_.get()), reinterpret_cast<fftw_complex*>(in), out);
  }
  ++n_inverse_;
}
Complex* Fourier::scratch(std::size_t modes) {
  if (distributed_) throw std::logic_error("Fourier::scratch: a distributed transform works in place in its buffer");
  if (spec_.size() < modes) Spectrum(modes).swap(spec_);
  return spec_.data();
}
void Fourier::forward(const double* in) { forward(in, spec_.data()); }
void Fourier::inverse(double* out) { inverse(spec_.data(), out); }

}  // namespace cmc
