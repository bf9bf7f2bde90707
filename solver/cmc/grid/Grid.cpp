#include "cmc/grid/Grid.hpp"

#include <fftw3.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <mutex>
#include <new>
#include <numbers>
#include <stdexcept>
#include <thread>

#include <unistd.h>

namespace cmc {

namespace detail {
extern const char* const kBuiltinWisdom;  // generated at build time (solver/tools/make_wisdom.cpp)
}

template <class T>
T* FftwAllocator<T>::allocate(std::size_t n) {
  if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_alloc();
  void* p = fftw_malloc(n * sizeof(T));
  if (!p && n) throw std::bad_alloc();
  return static_cast<T*>(p);
}
template <class T>
void FftwAllocator<T>::deallocate(T* p, std::size_t) noexcept {
  fftw_free(p);
}
template struct FftwAllocator<double>;
template struct FftwAllocator<Complex>;

double Grid::qx(int iqx) const { return 2.0 * std::numbers::pi * iqx / lx; }
double Grid::qy(int iqy) const {
  const int k = iqy <= ny / 2 ? iqy : iqy - ny;
  return 2.0 * std::numbers::pi * k / ly;
}

double Grid::sum(std::span<const double> v) {
  // Pairwise-blocked sum: accurate to ~1e-16 relative even at 65536^2 points.
  constexpr std::size_t B = 4096;
  double total = 0.0;
  for (std::size_t i = 0; i < v.size(); i += B) {
    double s = 0.0;
    const std::size_t e = std::min(v.size(), i + B);
    for (std::size_t j = i; j < e; ++j) s += v[j];
    total += s;
  }
  return total;
}
double Grid::max(std::span<const double> v) {
  double m = -std::numeric_limits<double>::infinity();
  for (double x : v) m = std::max(m, x);
  return m;
}
double Grid::min(std::span<const double> v) {
  double m = std::numeric_limits<double>::infinity();
  for (double x : v) m = std::min(m, x);
  return m;
}

double Grid::dot(std::span<const double> a, std::span<const double> b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}
std::size_t Grid::count(std::span<const std::uint8_t> mask) {
  std::size_t n = 0;
  for (auto m : mask) n += m ? 1 : 0;
  return n;
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
  return h ? int(h) : 1;
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
  fftw_plan_with_nthreads(thread_count());
  omp_set_num_threads(thread_count());
  if (planner() == Planner::Builtin) {
    fftw_import_wisdom_from_string(detail::kBuiltinWisdom);
  } else if (keeps_wisdom_file(planner())) {
    const auto w = wisdom_path();
    if (!w.empty() && std::filesystem::exists(w)) fftw_import_wisdom_from_filename(w.c_str());
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
  // Atomic: write beside, then rename, so a concurrent run never reads half a file.
  const auto tmp = w.string() + ".tmp" + std::to_string(::getpid());
  if (fftw_export_wisdom_to_filename(tmp.c_str())) std::filesystem::rename(tmp, w, ec);
}

Fourier::Fourier(int nx, int ny) : nx_(nx), ny_(ny), spec_(std::size_t(nx / 2 + 1) * ny) {
  if (nx <= 0 || ny <= 0) throw std::invalid_argument("Fourier: grid must be positive");
  {
    std::lock_guard lock(planner_mutex);
    init_fftw();
    Field scratch(real_size());
    // Threads only pay on large transforms: on small (e.g. 1-D) ones they cost 3-8x.
    fftw_plan_with_nthreads(real_size() < (std::size_t(1) << 16) ? 1 : thread_count());
    auto* c = reinterpret_cast<fftw_complex*>(spec_.data());
    const Planner p = planner();
    bool ok = false;
    if (p == Planner::Builtin) {
      ok = make_plans(nx, ny, scratch.data(), c, FFTW_MEASURE | FFTW_WISDOM_ONLY, plan_forward_, plan_inverse_);
      plan_source_ = "built-in wisdom";
      if (!ok) {
        plan_forward_.reset(), plan_inverse_.reset();
        plan_source_ = "estimate";
      }
    }
    if (!ok) {
      const unsigned flags = p == Planner::Measure ? FFTW_MEASURE : p == Planner::Patient ? FFTW_PATIENT : FFTW_ESTIMATE;
      if (p == Planner::Measure) plan_source_ = "measure";
      if (p == Planner::Patient) plan_source_ = "patient";
      if (p == Planner::Estimate) plan_source_ = "estimate";
      ok = make_plans(nx, ny, scratch.data(), c, flags, plan_forward_, plan_inverse_);
    }
    if (!ok) throw std::runtime_error("FFTW could not plan a transform");
  }
  save_fftw_wisdom();
}

void FftwPlanDeleter::operator()(void* plan) const noexcept {
  std::lock_guard lock(planner_mutex);
  fftw_destroy_plan(static_cast<fftw_plan>(plan));
}

void Fourier::forward(const double* in, Complex* out) {
  fftw_execute_dft_r2c(static_cast<fftw_plan>(plan_forward_.get()), const_cast<double*>(in),
                       reinterpret_cast<fftw_complex*>(out));
  ++n_forward_;
}
void Fourier::inverse(Complex* in, double* out) {
  fftw_execute_dft_c2r(static_cast<fftw_plan>(plan_inverse_.get()), reinterpret_cast<fftw_complex*>(in), out);
  ++n_inverse_;
}
void Fourier::forward(const double* in) { forward(in, spec_.data()); }
void Fourier::inverse(double* out) { inverse(spec_.data(), out); }

}  // namespace cmc
