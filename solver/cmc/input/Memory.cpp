// The memory a run holds (estimate_memory) and the memory this machine has
// (available_memory): declared in input/Case.hpp, which the parser's check of a case's
// grid uses (check_memory in input/Case.cpp).
#include "cmc/input/Case.hpp"

#include "cmc/contact/Memory.hpp"  // each solver's count (the one include of contact/ here)
#include "cmc/contact/adhesive_cg/Memory.hpp"
#include "cmc/contact/polonsky_keer/Memory.hpp"
#include "cmc/contact/quasi_static/Memory.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <numbers>
#include <string>

namespace cmc {

// ---------------------------------------------------------------- memory

std::string memory_text(double bytes) {
  char buf[48];
  if (bytes >= 1e9) std::snprintf(buf, sizeof buf, "%.3g GB", bytes / 1e9);
  else if (bytes >= 1e6) std::snprintf(buf, sizeof buf, "%.3g MB", bytes / 1e6);
  else std::snprintf(buf, sizeof buf, "%.3g kB", bytes / 1e3);
  return buf;
}

namespace {
MemorySplit split_now;
}  // namespace
const MemorySplit& memory_split() { return split_now; }
void set_memory_split(const MemorySplit& s) { split_now = s; }

namespace {

// The fields a run holds, in doubles (8 bytes): n per field of the grid, m per field of
// the transform grid (the grid itself when periodic, 2nx x 2ny zero-padded when free),
// sp per r2c spectrum of the transform grid ((mx/2 + 1) my complex numbers).
struct FieldSizes {
  double n, my, m, sp;
  bool periodic;
};
// In units of n and m doubles: the whole run's fields, a solve's, a solved step's, and the
// set-up of a solver.
struct FieldCounts {
  double run_grid = 0.0, run_transform = 0.0, solve_grid = 0.0, solve_transform = 0.0, step_grid = 0.0;
  double setup_transform = 0.0;
};

void count_every_run(const FieldSizes& z, FieldCounts& f) {
  const double sp = z.sp, m = z.m;
  const bool periodic = z.periodic;
  // Every run: the heights, the state the driver carries (pressure, displacement, gap).
  f.run_grid += 4.0;
  // The half-space (elastic/HalfSpace.cpp): its FFT's spectrum and the compliance (half a
  // spectrum), FFTW's work array (one transform field; measured: its 2-D r2c/c2r plans
  // buffer); free: the padded work array and the stiffness made with the compliance.
  f.run_transform += (sp + sp / 2.0) / m + 1.0;
  if (!periodic) f.run_transform += 1.0 + sp / 2.0 / m;
  // Set-up arrays that are freed before the solve but stay with the process (glibc keeps
  // freed blocks of this size in its heap once one was unmapped): the planning scratch,
  // the two fields of the timed FFT pair, and on a free boundary the influence kernel.
  f.run_transform += 3.0 + (periodic ? 0.0 : 1.0);
}

// The solver's own count (contact/*/Memory.hpp).
FieldCount solver_count(const Case& c) {
  const bool load_control = c.loading.control == LoadControl::Force || c.loading.control == LoadControl::MeanPressure;
  const MemoryShape shape{double(c.grid.nx), double(c.grid.ny), c.grid.periodic, memory_split().ranks,
                          c.grid.backend == "cuda"};
  return c.solver.kind == SolverKind::AdhesiveCg ? adhesive::host_memory(shape, c.loading.refine_pulloff > 0, load_control)
         : c.solver.kind == SolverKind::QuasiStatic ? qs::host_memory(shape, c.solver.precondition)
                                                    : pk::host_memory(shape, c.solver.precondition);
}

// The solver's fields, counted beside it (contact/*/Memory.hpp); returns whether it
// measures and writes a step inside its run (the adhesive CG's load path).
bool count_solver(const Case& c, FieldCounts& f) {
  const MemoryShape shape{double(c.grid.nx), double(c.grid.ny), c.grid.periodic, memory_split().ranks,
                          c.grid.backend == "cuda"};
  const FieldCount solver = solver_count(c);
  f.run_grid += solver.run_grid, f.run_transform += solver.run_transform;
  f.solve_grid += solver.solve_grid, f.solve_transform += solver.solve_transform;
  f.setup_transform = solver.setup_transform;
  // A run on the GPU times no FFT pair on the host: the two fields counted above are not made.
  if (shape.cuda) f.run_transform -= 2.0;
  return solver.steps_inside_run;
}

// Making the surface: the self-affine generator holds every mode of the band (about
// (pi/2) K^2 of them, K = size/cutoff, 24 bytes each) beside a spectrum and the heights.
double surface_bytes(const Case& c, double n, double share) {
  double bytes = 8.0 * 3.0 * n * share;
  if (c.surface.kind == SurfaceKind::SelfAffine) {
    const double K = std::floor(c.grid.size_x / c.surface.cutoff_wavelength);
    bytes += 24.0 * (0.5 * std::numbers::pi * (K + 1.0) * (K + 1.0) + 4.0 * K + 8.0);
  }
  return bytes;
}

}  // namespace

SolverFields solver_fields(const Case& c) {
  const FieldCount f = solver_count(c);
  return {f.run_grid, f.run_transform, f.solve_grid, f.solve_transform};
}

MemoryEstimate estimate_memory(const Case& c) {
  // Counted from the code (FieldSizes). By phase: what the whole run holds, plus the larger
  // of what a solve holds while it runs and what measuring and writing a solved step holds
  // after it (a solve's own fields are freed when it returns; glibc hands their blocks to
  // the next allocations, or to the system).
  const double nx = c.grid.nx, ny = c.grid.ny, n = nx * ny;
  const bool periodic = c.grid.periodic;
  const double mx = periodic ? nx : 2.0 * nx, my = periodic ? ny : 2.0 * ny, m = mx * my;
  const double sp = 2.0 * (std::floor(mx / 2.0) + 1.0) * my;
  const FieldSizes z{n, my, m, sp, periodic};
  FieldCounts f;
  count_every_run(z, f);
  const bool steps_inside_run = count_solver(c, f);
  // A solved step: the observables (the contact mask (bytes), patch labels (ints) and their
  // union-find parents, a Fourier transform of the pressure (its spectrum and scratch), the
  // distributions' per-thread counts). The writer scales and writes a field a block of
  // rows at a time (8 MB), so it holds no copy of a field.
  f.step_grid = 0.0;
  if (c.observables.enabled) f.step_grid = 1.0 / 8.0 + 1.0 + 2.0 + 1.0;
  // A solver that measures and writes inside its run (the adhesive CG's load path), beside
  // its work arrays.
  if (steps_inside_run) f.run_grid += f.step_grid, f.step_grid = 0.0;
  const double phase_grid =
      std::max({f.solve_grid * n + f.solve_transform * m, f.step_grid * n, f.setup_transform * m});
  const double grid_fields = f.run_grid + phase_grid / n, transform = f.run_transform;
  // The allocator: glibc's heap keeps freed copies of states (the load path's and the
  // load control's) and fragments; measured peak memory was up to 1.2x the fields
  // counted above (tests/test_limits.cpp, Limits.MemoryEstimateBoundsMeasuredPeak).
  constexpr double kAllocatorAllowance = 1.25;
  // A distributed run (MPI) splits the grid among its ranks: the estimate is one rank's
  // (its slab of every field; the whole band of modes, which every rank lists).
  const double share = 1.0 / double(memory_split().ranks);
  const double solve_bytes = kAllocatorAllowance * 8.0 * (grid_fields * n + transform * m) * share;
  const double surface = surface_bytes(c, n, share);
  MemoryEstimate e;
  e.bytes = std::max(solve_bytes, surface);
  char what[200];
  if (solve_bytes >= surface)
    std::snprintf(what, sizeof what,
                  "%.4g fields of the grid and %.4g of the %s transform grid, 8 bytes a point, and 25 %% for the "
                  "allocator%s", grid_fields, transform, periodic ? "periodic" : "zero-padded 2nx x 2ny",
                  memory_split().ranks > 1 ? "; per MPI rank, each holding its slab" : "");
  else
    std::snprintf(what, sizeof what, "the self-affine surface's %.3g Fourier modes while it is made",
                  0.5 * std::numbers::pi * std::pow(std::floor(c.grid.size_x / c.surface.cutoff_wavelength), 2));
  e.what = what;
  return e;
}

namespace {
// The first number in a file (e.g. /sys/fs/cgroup/memory.max), if it is one.
std::optional<double> number_in(const std::string& path) {
  std::ifstream in(path);
  double v = 0.0;
  if (in >> v) return v;
  return std::nullopt;
}

// What the machine has now, read afresh (available_memory keeps it for a moment).
std::optional<double> read_available_memory() {
  std::optional<double> avail;
  if (std::ifstream in("/proc/meminfo"); in) {
    std::string key;
    double kb = 0.0;
    std::string unit;
    while (in >> key >> kb) {
      std::getline(in, unit);
      if (key == "MemAvailable:") {
        avail = kb * 1024.0;
        break;
      }
    }
  }
  if (!avail) {
    const long pages = ::sysconf(_SC_AVPHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) avail = double(pages) * double(page);
  }
  // A container's limit (cgroup v2, then v1): what is left of it, if that is less.
  for (const auto& [limit, usage] : {std::pair{"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"},
                                     std::pair{"/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                               "/sys/fs/cgroup/memory/memory.usage_in_bytes"}}) {
    const auto l = number_in(limit), u = number_in(usage);  // "max" (no limit) is not a number
    if (l && u && *l < 1e18) {
      const double left = std::max(0.0, *l - *u);
      if (!avail || left < *avail) avail = left;
      break;
    }
  }
  return avail;
}
}  // namespace

// Read at most once a second: a sweep checks thousands of cases in a row, and the kernel
// makes /proc/meminfo afresh for every read (tens of microseconds each).
std::optional<double> available_memory() {
  using Clock = std::chrono::steady_clock;
  static std::mutex guard;
  static Clock::time_point when{};
  static std::optional<double> last;
  const std::lock_guard<std::mutex> lock(guard);
  const Clock::time_point now = Clock::now();
  if (when == Clock::time_point{} || now - when > std::chrono::seconds(1)) last = read_available_memory(), when = now;
  return last;
}

}  // namespace cmc
