// The CUDA backend's grid layer (grid/Backend.hpp): device buffers, cuFFT
// transforms, and the per-point passes and reductions that run a solver's bodies (written
// once, CMC_HD) as kernels. Included by .cu files only; built with -DCMC_CUDA=ON.
//
// Reductions are deterministic: a pass over n indices runs on a number of blocks that
// depends on n alone (at most kMaxBlocks of kThreads threads, grid-stride), each thread
// accumulates its indices in a fixed order, each block merges its threads' partials in a
// fixed tree in shared memory, and one block merges the blocks' partials in a fixed tree.
// No atomics: the same input gives the same bits on every run on the same device model.
#pragma once

#include "cmc/grid/Backend.hpp"

#ifdef CMC_CUDA_EMULATION
#include "cmc/grid/CudaEmulation.hpp"  // the device code's logic on the host (tests/emulation)
#else

#include <cuda_runtime.h>
#include <cufft.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace cmc::cuda {

// Throws std::runtime_error naming what failed and CUDA's reason.
void check(cudaError_t e, const char* what);
void check(cufftResult r, const char* what);

// Where a GPU solve's time goes, for tuning: with $CMC_CUDA_PROFILE set, every pass,
// reduction, copy and set-up below is bracketed by device synchronisations and its wall
// time added here (which slows the solve a little; off, nothing is synchronised for it).
struct Profile {
  bool on = false;
  double pass_s = 0.0, reduce_s = 0.0, upload_s = 0.0, download_s = 0.0, setup_s = 0.0;
  long passes = 0, reductions = 0;
  double upload_bytes = 0.0, download_bytes = 0.0;
  double cascade_s = 0.0;  // the quasi-static cascade's rounds (their passes and reductions counted above too)
  long cascades = 0, rounds = 0;
};
Profile& profile();
class ProfileScope {
 public:
  explicit ProfileScope(double& slot) : slot_(&slot) {
    if (profile().on) {
      cudaDeviceSynchronize();
      t0_ = std::chrono::steady_clock::now();
    }
  }
  ~ProfileScope() {
    if (!profile().on) return;
    cudaDeviceSynchronize();
    *slot_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }
  ProfileScope(const ProfileScope&) = delete;
  ProfileScope& operator=(const ProfileScope&) = delete;

 private:
  double* slot_;
  std::chrono::steady_clock::time_point t0_{};
};

// A device array of n T (cudaMalloc; never managed memory), zeroed: a pass that reads an
// entry before any writes it (the first direction of Polonsky-Keer, t = g + 0 (t − t̄))
// reads 0, not whatever bits the memory held (which may be a NaN).
template <class T>
class Buffer {
 public:
  Buffer() = default;
  explicit Buffer(std::size_t n, const char* what = "a device field") : n_(n) {
    if (!n) return;
    check(cudaMalloc(reinterpret_cast<void**>(&p_), n * sizeof(T)), what);
    check(cudaMemset(p_, 0, n * sizeof(T)), what);
  }
  ~Buffer() {
    if (p_) cudaFree(p_);
  }
  Buffer(Buffer&& o) noexcept : p_(std::exchange(o.p_, nullptr)), n_(std::exchange(o.n_, 0)) {}
  Buffer& operator=(Buffer&& o) noexcept {
    std::swap(p_, o.p_);
    std::swap(n_, o.n_);
    return *this;
  }
  T* data() const { return p_; }
  std::size_t size() const { return n_; }
  void upload(const T* host, std::size_t n) {
    ProfileScope ps(profile().upload_s);
    profile().upload_bytes += double(n * sizeof(T));
    check(cudaMemcpy(p_, host, n * sizeof(T), cudaMemcpyHostToDevice), "copy to the device");
  }
  void download(T* host, std::size_t n) const {
    ProfileScope ps(profile().download_s);
    profile().download_bytes += double(n * sizeof(T));
    check(cudaMemcpy(host, p_, n * sizeof(T), cudaMemcpyDeviceToHost), "copy from the device");
  }

 private:
  T* p_ = nullptr;
  std::size_t n_ = 0;
};

constexpr int kThreads = 256;
constexpr int kMaxBlocks = 1024;
inline int blocks_for(std::size_t n) {
  return int(std::max<std::size_t>(1, std::min<std::size_t>(kMaxBlocks, (n + kThreads - 1) / kThreads)));
}

template <class F>
__global__ void all_kernel(std::size_t n, F f) {
  for (std::size_t i = blockIdx.x * std::size_t(kThreads) + threadIdx.x; i < n; i += std::size_t(gridDim.x) * kThreads) f(i);
}
// f(i) for every i of [0, n).
template <class F>
void all(std::size_t n, F f) {
  if (!n) return;
  ProfileScope ps(profile().pass_s);
  ++profile().passes;
  all_kernel<<<blocks_for(n), kThreads>>>(n, f);
  check(cudaGetLastError(), "a per-point pass");
}

// Which indices of a reduction call the body.
struct Everywhere {
  __device__ bool operator()(std::size_t) const { return true; }
};
struct InMask {
  const std::uint8_t* m;
  __device__ bool operator()(std::size_t i) const { return m[i] != 0; }
};
struct InMaskOrBelow {
  const std::uint8_t* m;
  const double* w;
  double level;
  __device__ bool operator()(std::size_t i) const { return m[i] != 0 || w[i] < level; }
};

// Merges kThreads partials held in shared memory into sh[0], in a fixed tree.
template <class Acc>
__device__ void merge_block(Acc* sh) {
  __syncthreads();
  for (int s = kThreads / 2; s > 0; s >>= 1) {
    if (int(threadIdx.x) < s) sh[threadIdx.x].merge(sh[threadIdx.x + s]);
    __syncthreads();
  }
}
template <class Acc, class Sel, class F>
__global__ void reduce_kernel(std::size_t n, Sel sel, F f, Acc* partial) {
  __shared__ alignas(16) unsigned char raw[kThreads * sizeof(Acc)];
  Acc* sh = reinterpret_cast<Acc*>(raw);
  Acc a{};
  for (std::size_t i = blockIdx.x * std::size_t(kThreads) + threadIdx.x; i < n; i += std::size_t(gridDim.x) * kThreads)
    if (sel(i)) f(i, a);
  sh[threadIdx.x] = a;
  merge_block(sh);
  if (threadIdx.x == 0) partial[blockIdx.x] = sh[0];
}
template <class Acc>
__global__ void merge_kernel(const Acc* partial, int m, Acc* out) {
  __shared__ alignas(16) unsigned char raw[kThreads * sizeof(Acc)];
  Acc* sh = reinterpret_cast<Acc*>(raw);
  Acc a{};
  for (int i = int(threadIdx.x); i < m; i += kThreads) a.merge(partial[i]);
  sh[threadIdx.x] = a;
  merge_block(sh);
  if (threadIdx.x == 0) out[0] = sh[0];
}

// Reductions with a small device scratch of their own (the blocks' partials).
class Reducer {
 public:
  static constexpr std::size_t kMaxAcc = 56;  // bytes of the largest partial record (1025 fit in 64 KiB)
  Reducer() : scratch_((kMaxBlocks + 1) * kMaxAcc, "the reductions' scratch") {}
  // f(i, acc) for every i of [0, n) that sel accepts; the merged record, on the host.
  template <class Acc, class Sel, class F>
  Acc run(std::size_t n, Sel sel, F f) {
    static_assert(sizeof(Acc) <= kMaxAcc, "a reduction record larger than the scratch holds");
    ProfileScope ps(profile().reduce_s);
    ++profile().reductions;
    Acc* part = reinterpret_cast<Acc*>(scratch_.data());
    const int nb = blocks_for(n);
    reduce_kernel<Acc><<<nb, kThreads>>>(n, sel, f, part);
    check(cudaGetLastError(), "a reduction pass");
    merge_kernel<Acc><<<1, kThreads>>>(part, nb, part + kMaxBlocks);
    check(cudaGetLastError(), "a reduction's merge");
    Acc out{};
    check(cudaMemcpy(&out, part + kMaxBlocks, sizeof(Acc), cudaMemcpyDeviceToHost), "a reduction's result");
    return out;
  }

 private:
  Buffer<unsigned char> scratch_;
};

// Real-to-complex and complex-to-real transforms of an nx x ny grid (x fastest; the
// spectrum is ny rows of nx/2 + 1 modes, FFTW's r2c layout), in double precision, the two
// plans sharing one work area. Unnormalised, like Fourier. Counts its transforms and
// the seconds inside them (CUDA events around each).
class Fft {
 public:
  Fft(int nx, int ny);
  ~Fft();
  Fft(const Fft&) = delete;
  Fft& operator=(const Fft&) = delete;
  // in (nx ny reals) -> out (spectrum, interleaved re/im); in preserved.
  void forward(const double* in, double* out);
  // in (spectrum; destroyed) -> out (nx ny reals).
  void inverse(double* in, double* out);
  std::size_t work_bytes() const { return work_.size(); }
  long forwards = 0, inverses = 0;
  double seconds = 0.0;

 private:
  void timed(cufftResult r, const char* what);
  void release() noexcept;
  cufftHandle f_ = 0, i_ = 0;
  Buffer<unsigned char> work_;
  cudaEvent_t e0_ = nullptr, e1_ = nullptr;
};

}  // namespace cmc::cuda

#endif  // CMC_CUDA_EMULATION
