// A host stand-in for grid/CudaDevice.cuh, under CMC_CUDA_EMULATION: the same names
// (Buffer, all, Reducer, Fft, ...) with plain loops, std::vector memory and FFTW, so that
// the device backends' own code (contact/polonsky_keer/CudaBackend.cuh, contact/quasi_static/CudaBackend.cuh:
// which buffer holds what, the order of their passes, what goes up and comes down) runs
// and is tested on a machine without a GPU (tests/emulation; the CPU build only). It checks
// that code's logic, not CUDA: kernels, cuFFT, device memory and the fixed-order trees of
// the real reductions are the GPU tests' (label gpu). Not a backend: nothing selects it at
// run time, and no library source includes it.
#pragma once

#define __device__
#define __host__

#include <fftw3.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

namespace cmc::cuda {

struct Profile {
  bool on = false;
  double pass_s = 0.0, reduce_s = 0.0, upload_s = 0.0, download_s = 0.0, setup_s = 0.0;
  long passes = 0, reductions = 0;
  double upload_bytes = 0.0, download_bytes = 0.0;
  double cascade_s = 0.0;
  long cascades = 0, rounds = 0;
};
inline Profile& profile() {
  static Profile p;
  return p;
}
struct ProfileScope {
  explicit ProfileScope(double&) {}
};

// Device memory: zeroed, as the real Buffer's; uploads and downloads count their bytes.
template <class T>
class Buffer {
 public:
  Buffer() = default;
  explicit Buffer(std::size_t n, const char* = "a device field") : v_(n, T{}) {}
  T* data() const { return v_.empty() ? nullptr : const_cast<T*>(v_.data()); }
  std::size_t size() const { return v_.size(); }
  void upload(const T* host, std::size_t n) {
    profile().upload_bytes += double(n * sizeof(T));
    std::memcpy(v_.data(), host, n * sizeof(T));
  }
  void download(T* host, std::size_t n) const {
    profile().download_bytes += double(n * sizeof(T));
    std::memcpy(host, v_.data(), n * sizeof(T));
  }

 private:
  std::vector<T> v_;
};

template <class F>
void all(std::size_t n, F f) {
  ++profile().passes;
  for (std::size_t i = 0; i < n; ++i) f(i);
}

struct Everywhere {
  bool operator()(std::size_t) const { return true; }
};
struct InMask {
  const std::uint8_t* m;
  bool operator()(std::size_t i) const { return m[i] != 0; }
};
struct InMaskOrBelow {
  const std::uint8_t* m;
  const double* w;
  double level;
  bool operator()(std::size_t i) const { return m[i] != 0 || w[i] < level; }
};

class Reducer {
 public:
  template <class Acc, class Sel, class F>
  Acc run(std::size_t n, Sel sel, F f) {
    ++profile().reductions;
    Acc a{};
    for (std::size_t i = 0; i < n; ++i)
      if (sel(i)) f(i, a);
    return a;
  }
};

// cuFFT's r2c and c2r of an nx x ny grid (x fastest, the spectrum ny rows of nx/2 + 1
// modes), unnormalised; the inverse destroys its input, as cuFFT's may.
class Fft {
 public:
  Fft(int nx, int ny) {
    std::vector<double> r(std::size_t(nx) * std::size_t(ny));
    std::vector<fftw_complex> c(std::size_t(ny) * std::size_t(nx / 2 + 1));
    f_ = fftw_plan_dft_r2c_2d(ny, nx, r.data(), c.data(), FFTW_ESTIMATE | FFTW_UNALIGNED);
    i_ = fftw_plan_dft_c2r_2d(ny, nx, c.data(), r.data(), FFTW_ESTIMATE | FFTW_UNALIGNED);
    if (!f_ || !i_) throw std::runtime_error("emulated Fft: FFTW made no plan");
  }
  ~Fft() {
    fftw_destroy_plan(f_);
    fftw_destroy_plan(i_);
  }
  Fft(const Fft&) = delete;
  Fft& operator=(const Fft&) = delete;
  void forward(const double* in, double* out) {
    const auto t0 = std::chrono::steady_clock::now();
    fftw_execute_dft_r2c(f_, const_cast<double*>(in), reinterpret_cast<fftw_complex*>(out));
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++forwards;
  }
  void inverse(double* in, double* out) {
    const auto t0 = std::chrono::steady_clock::now();
    fftw_execute_dft_c2r(i_, reinterpret_cast<fftw_complex*>(in), out);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++inverses;
  }
  std::size_t work_bytes() const { return 0; }
  long forwards = 0, inverses = 0;
  double seconds = 0.0;

 private:
  fftw_plan f_ = nullptr, i_ = nullptr;
};

}  // namespace cmc::cuda
