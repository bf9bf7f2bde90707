// The quasi-static solver with its outer step on one GPU: the device backend of
// Iteration.hpp. Every field stays on the device from the first outer step to the last:
// Polonsky-Keer's (polonsky_keer/CudaBackend.cuh), the case's heights, the tension and the
// cascade's passed-on gaps. The outer step's other fields live in Polonsky-Keer's work
// arrays, which hold nothing between its solves: the gap in the direction's, the cascade's
// predicted gaps in G t's, its two flags in the contact mask's and the scratch spectrum's.
// The cascade runs in rounds (Parts.hpp): two kernels a round, over the frontier only,
// with a fixed-order count, so a rerun gives the same bits. The host sees the state at the
// start (a warm start's tension and pressure go up), at a checkpoint (the tension and the
// pressure come down, only when one is written: OuterPoint::fetch), and at the end. With
// the outer step on the host between device solves, a run at 8192² spent 151 s of its
// 227 s on the host.
// Periodic boundary, one process (the case parser refuses the rest with backend = "cuda").
// Device memory: qs::device_bytes, Memory.hpp (93 GiB at 32768² with the
// preconditioner, 85 GiB without: an H200, not an H100).
#include "cmc/contact/quasi_static/CudaBackend.cuh"
#include "cmc/contact/quasi_static/Memory.hpp"

#include <memory>

namespace cmc {

SolveResult qs::solve_on_device(const Problem& p, const Target& target, ContactState& st, OuterPoint* from) {
  HalfSpace& hs = p.hs;
  if (!hs.periodic() || hs.grid().split())
    throw std::invalid_argument("quasi-static adhesion on CUDA: periodic boundary and one process only");
  std::string why;
  if (!cuda::available(&why)) throw std::runtime_error("quasi-static adhesion on CUDA: " + why);
  const int nx = hs.grid().nx, ny = hs.grid().ny;
  const std::size_t need = device_bytes(nx, ny, p.options.precondition, cuda::fft_work_bytes(nx, ny));
  pk::check_device_memory("quasi-static adhesion", nx, ny, need);
  std::unique_ptr<DeviceSteps> b;
  {
    cuda::ProfileScope ps(cuda::profile().setup_s);
    b = std::make_unique<DeviceSteps>(hs, p.heights, p.options, p.k_near);
  }
  return solve(*b, hs, p.adhesion, p.options, JumpPrediction(p.self_stiffness, p.adhesion), p.move_floor, target, st,
               from);
}

}  // namespace cmc
