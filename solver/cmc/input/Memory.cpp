// The memory a run holds (estimate_memory) and the memory this machine has
// (available_memory): declared in input/Case.hpp, which the parser's check of a case's
// grid uses (check_memory in input/Case.cpp).
#include "cmc/input/Case.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
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

void count_adhesive_cg(const Case& c, const FieldSizes& z, FieldCounts& f) {
  const bool periodic = z.periodic;
  const bool load_control = c.loading.control == LoadControl::Force || c.loading.control == LoadControl::MeanPressure;
  // AdhesiveSolver::Work (a member of the solver, kept for the whole run): heights, x,
  // Ku, d, Kd, r, c, trial, Ktrial on the transform grid, K h when periodic, the bound
  // flags (bytes); the stiffness when periodic.
  f.run_transform += 9.0 + (periodic ? 1.0 : 0.0) + 1.0 / 8.0;
  if (periodic) f.run_transform += z.sp / 2.0 / z.m;
  // The load path's trial copy of the state; the pull-off search's best state and its
  // copy; load control: the three points of the bracketing search, each a state. The
  // walk holds them while a step is measured and written (its callbacks run inside it).
  f.run_grid += 3.0;
  if (c.loading.refine_pulloff > 0) f.run_grid += 6.0;
  if (load_control) f.run_grid += 9.0;
}

void count_polonsky_keer_host(const Case& c, const FieldSizes& z, FieldCounts& f) {
  const bool periodic = z.periodic;
  const double sp = z.sp, m = z.m, my = z.my;
  // Polonsky-Keer, within a solve: the search direction (and the preconditioned gap, on
  // a periodic grid), the contact set (bytes); no spectrum of the pressure or the heights
  // (contact/PolonskyKeerHost.hpp; the direction's is the half-space's
  // spectrum, counted above). A periodic grid held by one process runs the fused sweeps
  // (grid/RowColumnFourier.hpp): the compliance once more, in the transform's layout (its
  // row buffers are a few rows); that layout leaves kColumnPad = 8 modes unused after
  // each column of my, so its spectra (the compliance, and the half-space's scratch,
  // which keeps its longer buffer for the rest of the run) are 8/my longer, and the
  // least w of each block of eight points, an eighth of a field. Otherwise (a free
  // boundary, a distributed grid) G t for the linear steps, a field of the grid.
  const bool fused = periodic && memory_split().ranks == 1;
  const double pad = 8.0 / my;
  f.solve_grid += 1.0 + (periodic && c.solver.precondition ? 1.0 : 0.0) + 1.0 / 8.0 + (fused ? 1.0 / 8.0 : 1.0);
  f.solve_transform += fused ? sp / 2.0 / m + 0.5 * pad * sp / m : 0.0;
  if (fused) f.run_transform += pad * sp / m;
}

void count_quasi_static(const Case& c, const FieldSizes& z, FieldCounts& f) {
  // QuasiStaticAdhesion: K's unit response and its set-up impulse on the transform grid
  // in its constructor (freed once the cascade's nine entries are read off), and the
  // stiffness when periodic, for the whole run; within a solve, around its
  // Polonsky-Keer (counted above): the shifted heights, the tension, G t and the
  // predicted gaps, the cascade's pull, applied and decay fields and flags. The inner
  // state is the driver's (counted above), moved in and back; the next tension is
  // computed where it is used, and a checkpoint inside a step is written a block of rows
  // at a time (no copy).
  // On the GPU the outer step's fields are the device's (grid/Backend.hpp
  // quasi_static_bytes); the host makes the first tension of a warm start and the
  // tension it subtracts at the end (one field).
  f.setup_transform = 2.0;
  f.run_transform += z.periodic ? z.sp / 2.0 / z.m : 0.0;
  f.solve_grid += c.grid.backend == "cuda" ? 1.0 : 4.0 + 3.0 + 1.0 / 8.0;
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
  const bool adhesive = c.solver.kind == SolverKind::AdhesiveCg;
  FieldCounts f;
  count_every_run(z, f);
  if (adhesive) {
    count_adhesive_cg(c, z, f);
  } else if (c.grid.backend == "cuda") {
    // Polonsky-Keer on the GPU holds its work arrays on the device (printed separately,
    // grid/Backend.hpp polonsky_keer_bytes; its stiffness is taken from the compliance
    // there, the host makes none), and no FFT pair is timed on the host (its two fields,
    // counted above, are not made). Counted from the code; the host's peak of a GPU run
    // has not been measured.
    f.run_transform -= 2.0;
  } else {
    count_polonsky_keer_host(c, z, f);
  }
  // Fields a solver makes in its constructor and frees there, before any state or solve
  // field exists: a phase of their own (the larger grids' blocks go back to the system;
  // a smaller grid's stay in glibc's heap, where the state's fields and the solve's are
  // then allocated).
  if (c.solver.kind == SolverKind::QuasiStatic) count_quasi_static(c, z, f);
  // A solved step: the observables (the contact mask (bytes), patch labels (ints) and their
  // union-find parents, a Fourier transform of the pressure (its spectrum and scratch), the
  // distributions' per-thread counts). The writer scales and writes a field a block of
  // rows at a time (8 MB), so it holds no copy of a field.
  f.step_grid = 0.0;
  if (c.observables.enabled) f.step_grid = 1.0 / 8.0 + 1.0 + 2.0 + 1.0;
  // The adhesive CG measures and writes inside its load path, beside its work arrays.
  if (adhesive) f.run_grid += f.step_grid, f.step_grid = 0.0;
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
}  // namespace

std::optional<double> available_memory() {
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

}  // namespace cmc
