// The memory the quasi-static solver holds, counted from its code (contact/Memory.hpp says
// what the numbers mean and who asks): its Polonsky-Keer solves' and its own.
#pragma once

#include "cmc/contact/Memory.hpp"
#include "cmc/contact/polonsky_keer/Memory.hpp"

#include <cstddef>

namespace cmc::qs {

// On the host. K's unit response and its set-up impulse on the transform grid in the
// constructor (freed once the cascade's nine entries are read off), and the stiffness when
// periodic, for the whole run; within a solve, around its Polonsky-Keer: the shifted
// heights, the tension, G t and the predicted gaps, the cascade's pull, applied and decay
// fields and flags (CpuBackend.cpp). The inner state is the driver's, moved in and back;
// the next tension is computed where it is used, and a checkpoint inside a step is written
// a block of rows at a time (no copy). On the GPU the outer step's fields are the device's
// (device_bytes); the host makes the first tension of a warm start and the tension it
// subtracts at the end (one field).
inline FieldCount host_memory(const MemoryShape& s, bool precondition) {
  FieldCount f = pk::host_memory(s, precondition);
  f.setup_transform = 2.0;
  f.run_transform += s.periodic ? s.sp() / 2.0 / s.m() : 0.0;
  f.solve_grid += s.cuda ? 1.0 : 4.0 + 3.0 + 1.0 / 8.0;
  return f;
}

// Bytes of device memory with the outer step on the device (CudaBackend.cuh):
// Polonsky-Keer's, the heights, the tension and the cascade's passed-on gaps (3 real
// fields). The outer step's other fields (the gap, the predicted gaps and the cascade's
// flags) use Polonsky-Keer's direction, G t, contact mask and spectrum between solves.
inline std::size_t device_bytes(int nx, int ny, bool precondition, std::size_t fft_work) {
  const std::size_t n = std::size_t(nx) * std::size_t(ny);
  return pk::device_bytes(nx, ny, precondition, fft_work) + 3 * n * sizeof(double);
}

}  // namespace cmc::qs
