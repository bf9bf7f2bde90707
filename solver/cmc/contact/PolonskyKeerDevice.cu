// Polonsky-Keer on one GPU (issue 16): the device backend of PolonskyKeerRun.hpp. The
// iteration is PolonskyKeerRun.hpp's, body for body; here are only where its fields live
// (device buffers for the whole solve) and how its passes and transforms run (kernels
// with fixed-order reductions and cuFFT, grid/CudaDevice.cuh). Periodic boundary, one
// process: the case parser refuses other combinations with backend = "cuda".
// Its fields and their count: PolonskyKeerDevice.cuh.
#include "cmc/contact/PolonskyKeerDevice.cuh"

#include <cstdio>
#include <sstream>

namespace cmc {

void PolonskyKeer::DeviceDelete::operator()(Device* d) const noexcept { delete d; }

void pk::report_profile(const PolonskyKeer::Device& d) {
  if (!cuda::profile().on) return;
  const cuda::Profile& pr = cuda::profile();
  std::fprintf(stderr,
               "cuda profile, so far: transforms %.3f s (%ld + %ld), passes %.3f s (%ld), reductions %.3f s (%ld), "
               "uploads %.3f s (%.2f GB), downloads %.3f s (%.2f GB), set-up %.3f s\n",
               d.fft.seconds, d.fft.forwards, d.fft.inverses, pr.pass_s, pr.passes, pr.reduce_s, pr.reductions,
               pr.upload_s, 1e-9 * pr.upload_bytes, pr.download_s, 1e-9 * pr.download_bytes, pr.setup_s);
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
    pk::check_device_memory("Polonsky-Keer", nx, ny, cuda::polonsky_keer_bytes(nx, ny, start.precondition));
    cuda::ProfileScope ps(cuda::profile().setup_s);
    dev.reset(new PolonskyKeer::Device(hs, start.precondition));
  }
  PolonskyKeer::Device& d = *dev;
  const long f0 = d.fft.forwards, i0 = d.fft.inverses;
  const double s0 = d.fft.seconds;
  d.H.upload(heights.data(), d.n);
  if (start.warm) d.P.upload(st.pressure.data(), d.n);
  End end;
  {
    Run<PolonskyKeer::Device> run(d, o, h_scale, target, start);
    run.run(res);
    end = {run.sigma(), run.delta(), run.failure};
  }
  st.pressure.resize(d.n);
  st.displacement.resize(d.n);
  d.P.download(st.pressure.data(), d.n);
  d.W.download(st.displacement.data(), d.n);
  hs.count_transforms(d.fft.forwards - f0, d.fft.inverses - i0, d.fft.seconds - s0);
  pk::report_profile(d);
  if (!o.keep_work) dev.reset();
  return end;
}

}  // namespace cmc
