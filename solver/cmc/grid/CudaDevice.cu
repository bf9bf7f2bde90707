#include "cmc/grid/CudaDevice.cuh"

#include <cstdlib>
#include <sstream>
#include <vector>

namespace cmc::cuda {

Profile& profile() {
  static Profile p = [] {
    Profile q;
    const char* e = std::getenv("CMC_CUDA_PROFILE");
    q.on = e && *e && std::string(e) != "0";
    return q;
  }();
  return p;
}

void check(cudaError_t e, const char* what) {
  if (e == cudaSuccess) return;
  std::ostringstream s;
  s << "CUDA: " << what << " failed: " << cudaGetErrorString(e);
  if (e == cudaErrorMemoryAllocation) s << " (the grid does not fit this GPU's memory: use a smaller grid or the CPU backend)";
  throw std::runtime_error(s.str());
}

void check(cufftResult r, const char* what) {
  if (r == CUFFT_SUCCESS) return;
  std::ostringstream s;
  s << "cuFFT: " << what << " failed (cufftResult " << int(r) << ")";
  if (r == CUFFT_ALLOC_FAILED) s << ": out of device memory";
  throw std::runtime_error(s.str());
}

namespace {
// Two plans of one shape without a work area of their own; returns the larger need.
std::size_t make_plans(int nx, int ny, cufftHandle& f, cufftHandle& i) {
  std::size_t wf = 0, wi = 0;
  check(cufftCreate(&f), "creating a plan");
  check(cufftCreate(&i), "creating a plan");
  check(cufftSetAutoAllocation(f, 0), "planning");
  check(cufftSetAutoAllocation(i, 0), "planning");
  if (ny == 1) {  // a line (plane strain): the same layout, one row
    check(cufftMakePlan1d(f, nx, CUFFT_D2Z, 1, &wf), "planning the forward transform");
    check(cufftMakePlan1d(i, nx, CUFFT_Z2D, 1, &wi), "planning the inverse transform");
  } else {
    check(cufftMakePlan2d(f, ny, nx, CUFFT_D2Z, &wf), "planning the forward transform");
    check(cufftMakePlan2d(i, ny, nx, CUFFT_Z2D, &wi), "planning the inverse transform");
  }
  return std::max(wf, wi);
}
}  // namespace

Fft::Fft(int nx, int ny) {
  try {
    const std::size_t ws = make_plans(nx, ny, f_, i_);
    work_ = Buffer<unsigned char>(std::max<std::size_t>(ws, 1), "cuFFT's work area");
    check(cufftSetWorkArea(f_, work_.data()), "setting the work area");
    check(cufftSetWorkArea(i_, work_.data()), "setting the work area");
    check(cudaEventCreate(&e0_), "creating an event");
    check(cudaEventCreate(&e1_), "creating an event");
  } catch (...) {
    release();  // a constructor that throws runs no destructor: the plans would leak
    throw;
  }
}

Fft::~Fft() { release(); }

void Fft::release() noexcept {
  if (f_) cufftDestroy(f_);
  if (i_) cufftDestroy(i_);
  if (e0_) cudaEventDestroy(e0_);
  if (e1_) cudaEventDestroy(e1_);
  f_ = i_ = 0;
  e0_ = e1_ = nullptr;
}

void Fft::timed(cufftResult r, const char* what) {
  check(r, what);
  check(cudaEventRecord(e1_), "timing a transform");
  check(cudaEventSynchronize(e1_), "a transform");
  float ms = 0.0f;
  check(cudaEventElapsedTime(&ms, e0_, e1_), "timing a transform");
  seconds += 1e-3 * double(ms);
}

void Fft::forward(const double* in, double* out) {
  check(cudaEventRecord(e0_), "timing a transform");
  timed(cufftExecD2Z(f_, const_cast<double*>(in), reinterpret_cast<cufftDoubleComplex*>(out)), "a forward transform");
  ++forwards;
}

void Fft::inverse(double* in, double* out) {
  check(cudaEventRecord(e0_), "timing a transform");
  timed(cufftExecZ2D(i_, reinterpret_cast<cufftDoubleComplex*>(in), out), "an inverse transform");
  ++inverses;
}

std::size_t fft_work_bytes(int nx, int ny) {
  if (!available()) return std::size_t(nx) * std::size_t(ny) * sizeof(double);
  cufftHandle f = 0, i = 0;
  std::size_t ws = 0;
  try {
    ws = make_plans(nx, ny, f, i);
  } catch (...) {
    if (f) cufftDestroy(f);
    if (i) cufftDestroy(i);
    throw;
  }
  cufftDestroy(f);
  cufftDestroy(i);
  return ws;
}

// ---------------------------------------------------------------- Backend.hpp

bool built() { return true; }

bool available(std::string* why) {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess || count == 0) {
    if (why)
      *why = std::string("grid.backend = \"cuda\": ") +
             (e != cudaSuccess ? std::string("no usable CUDA device (") + cudaGetErrorString(e) + ")" : "no CUDA device") +
             " on this machine: run on a machine with an NVIDIA GPU, or with backend = \"cpu\"";
    cudaGetLastError();  // clear it
    return false;
  }
  return true;
}

std::string device_description() {
  std::string why;
  if (!available(&why)) throw std::runtime_error(why);
  int dev = 0, rt = 0;
  check(cudaGetDevice(&dev), "finding the device");
  cudaDeviceProp prop{};
  check(cudaGetDeviceProperties(&prop, dev), "reading the device's properties");
  check(cudaRuntimeGetVersion(&rt), "reading the runtime version");
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << prop.name << ", " << double(prop.totalGlobalMem) / double(1u << 30) << " GiB, CUDA runtime " << rt / 1000 << "."
    << (rt % 1000) / 10;
  return s.str();
}

double time_fft_pair(int nx, int ny, double min_seconds, int min_repeats) {
  std::string why;
  if (!available(&why)) throw std::runtime_error(why);
  const std::size_t n = std::size_t(nx) * std::size_t(ny), ns = std::size_t(ny) * std::size_t(nx / 2 + 1);
  Buffer<double> in(n), out(n), spec(2 * ns);
  check(cudaMemset(in.data(), 0, n * sizeof(double)), "clearing a field");
  Fft fft(nx, ny);
  auto pair = [&] {
    check(cudaDeviceSynchronize(), "a transform");
    const auto t0 = std::chrono::steady_clock::now();
    fft.forward(in.data(), spec.data());
    fft.inverse(spec.data(), out.data());
    check(cudaDeviceSynchronize(), "a transform");
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  pair();  // plans' first use, not timed
  std::vector<double> t;
  double total = 0.0;
  while (int(t.size()) < min_repeats || total < min_seconds) total += t.emplace_back(pair());
  return *std::min_element(t.begin(), t.end());
}

}  // namespace cmc::cuda
