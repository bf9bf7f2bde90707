// Polonsky-Keer on one GPU: the device backend of Iteration.hpp. The iteration is
// Iteration.hpp's, body for body; here are only where its fields live (device buffers for
// the whole solve) and how its passes and transforms run (kernels with fixed-order
// reductions and cuFFT, grid/CudaDevice.cuh). Periodic boundary, one process: the case
// parser refuses other combinations with backend = "cuda".
// Its fields and their count: CudaBackend.cuh.
#include "cmc/contact/polonsky_keer/CudaBackend.cuh"
#include "cmc/contact/polonsky_keer/Memory.hpp"

#include <cstdio>
#include <sstream>

namespace cmc {

void PolonskyKeer::DeviceDelete::operator()(Device* d) const noexcept { delete d; }

void pk::report_profile(const PolonskyKeer::Device& d) {
  if (!cuda::profile().on) return;
  const cuda::Profile& pr = cuda::profile();
  std::fprintf(stderr,
               "cuda profile, so far: transforms %.3f s (%ld + %ld), passes %.3f s (%ld), reductions %.3f s (%ld), "
               "uploads %.3f s (%.2f GB), downloads %.3f s (%.2f GB), set-up %.3f s; "
               "quasi-static cascade %.3f s (%ld rounds in %ld cascades, its passes and reductions counted above too)\n",
               d.fft.seconds, d.fft.forwards, d.fft.inverses, pr.pass_s, pr.passes, pr.reduce_s, pr.reductions,
               pr.upload_s, 1e-9 * pr.upload_bytes, pr.download_s, 1e-9 * pr.download_bytes, pr.setup_s,
               pr.cascade_s, pr.rounds, pr.cascades);
}

std::size_t pk::check_device_memory(const char* who, int nx, int ny, std::size_t need) {
  std::size_t free_b = 0, total_b = 0;
  cuda::check(cudaMemGetInfo(&free_b, &total_b), "reading the device's free memory");
  if (need > free_b) {
    std::ostringstream s;
    s << who << " on CUDA: the grid " << nx << " x " << ny << " needs " << double(need) / double(1u << 30)
      << " GiB of device memory, and " << double(free_b) / double(1u << 30) << " GiB of "
      << double(total_b) / double(1u << 30) << " GiB are free: use a smaller grid or the CPU backend";
    throw std::runtime_error(s.str());
  }
  return free_b;
}

// The one translation unit that instantiates pk::Run over the device. nvcc keeps the host
// side of a __host__ __device__ lambda (its copy, call and delete functions) in statics of
// an anonymous namespace, one set per translation unit, while the lambda's wrapper type and
// the templates that copy it are merged across units by the linker. A Run<Device> member
// instantiated in two .cu files could then be copied by one unit's code with the other
// unit's statics, never set: a call through a null pointer (every solve crashed once
// quasi_static/CudaBackend.cu instantiated Run<Device> too).
// scripts/gpu/pack.sh refuses a build whose .cu objects share such a wrapper.
pk::End pk::run_on_device(PolonskyKeer::Device& d, const PolonskyKeer::Options& o, double h_scale,
                          const Target& target, const Start& start, SolveResult& res) {
  return iterate(d, o, h_scale, target, start, res);
}

pk::End pk::solve_on_device(std::unique_ptr<PolonskyKeer::Device, PolonskyKeer::DeviceDelete>& dev, HalfSpace& hs,
                            const Field& heights, const PolonskyKeer::Options& o, double h_scale, const Target& target,
                            ContactState& st, const Start& start, SolveResult& res) {
  if (!hs.periodic() || hs.grid().split())
    throw std::invalid_argument("Polonsky-Keer on CUDA: periodic boundary and one process only (grid.periodic = true, no MPI)");
  std::string why;
  if (!cuda::available(&why)) throw std::runtime_error("Polonsky-Keer on CUDA: " + why);
  if (!dev || dev->precondition != start.precondition) {
    dev.reset();
    const int nx = hs.grid().nx, ny = hs.grid().ny;
    const std::size_t need = pk::device_bytes(nx, ny, start.precondition, cuda::fft_work_bytes(nx, ny));
    pk::check_device_memory("Polonsky-Keer", nx, ny, need);
    cuda::ProfileScope ps(cuda::profile().setup_s);
    dev.reset(new PolonskyKeer::Device(hs, start.precondition));
  }
  PolonskyKeer::Device& d = *dev;
  End end;
  {
    const TransformTally tally(hs, [&d] { return d.transforms(); });
    d.H.upload(heights.data(), d.n);
    if (start.warm) d.P.upload(st.pressure.data(), d.n);
    end = run_on_device(d, o, h_scale, target, start, res);
    st.pressure.resize(d.n);
    st.displacement.resize(d.n);
    d.P.download(st.pressure.data(), d.n);
    d.W.download(st.displacement.data(), d.n);
  }
  pk::report_profile(d);
  if (!o.keep_work) dev.reset();
  return end;
}

}  // namespace cmc
