// The memory Polonsky-Keer holds, counted from its code (contact/Memory.hpp says what the
// numbers mean and who asks).
#pragma once

#include "cmc/contact/Memory.hpp"

#include <cstddef>

namespace cmc::pk {

// On the host. CPU backend, within a solve: the search direction (and the preconditioned
// gap, on a periodic grid), the contact set (bytes); no spectrum of the pressure or the
// heights (CpuBackend.hpp; the direction's is the half-space's spectrum, which the input
// layer counts with the half-space). A periodic grid held by one process runs the fused
// sweeps (grid/RowColumnFourier.hpp): the compliance once more, in the transform's layout
// (its row buffers are a few rows); that layout leaves kColumnPad = 8 modes unused after
// each column of my, so its spectra (the compliance, and the half-space's scratch, which
// keeps its longer buffer for the rest of the run) are 8/my longer, and the least w of
// each block of eight points, an eighth of a field. Otherwise (a free boundary, a
// distributed grid) G t for the linear steps, a field of the grid. The CUDA backend holds
// its work arrays on the device (device_bytes), none on the host.
inline FieldCount host_memory(const MemoryShape& s, bool precondition) {
  FieldCount f;
  if (s.cuda) return f;
  const bool fused = s.periodic && s.ranks == 1;
  const double pad = 8.0 / s.my(), sp = s.sp(), m = s.m();
  f.solve_grid += 1.0 + (s.periodic && precondition ? 1.0 : 0.0) + 1.0 / 8.0 + (fused ? 1.0 / 8.0 : 1.0);
  f.solve_transform += fused ? sp / 2.0 / m + 0.5 * pad * sp / m : 0.0;
  if (fused) f.run_transform += pad * sp / m;
  return f;
}

// Bytes of device memory a solve holds on an nx x ny periodic grid (CudaBackend.cuh): 5
// real fields, 1 more with the preconditioner, a byte mask, a spectrum, the compliance,
// cuFFT's work area (`fft_work`, cuda::fft_work_bytes) and the reductions' scratch.
inline std::size_t device_bytes(int nx, int ny, bool precondition, std::size_t fft_work) {
  const std::size_t n = std::size_t(nx) * std::size_t(ny), ns = std::size_t(ny) * std::size_t(nx / 2 + 1);
  const std::size_t doubles = n * (precondition ? 6 : 5) + ns * 3;
  return doubles * sizeof(double) + n + fft_work + (std::size_t(1) << 16);
}

}  // namespace cmc::pk
