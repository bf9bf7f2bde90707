// Where a solve's fields live and its passes run: "cpu" (FFTW and OpenMP, every
// build) or "cuda" (cuFFT and kernels on one GPU, builds configured with -DCMC_CUDA=ON).
//
// One source for both: a solver's per-point work is written once, as bodies f(i) or
// f(i, acc) over point (or mode) indices, and a backend runs them over a range: the CPU's
// with Grid::parallel_for / parallel_reduce (OpenMP chunks merged in a fixed order), the
// GPU's as kernels whose reductions are fixed-order trees (grid/CudaDevice.cuh). CMC_HD
// marks such a body, and the small reduction records they fill, as callable on both.
#pragma once

#include <cstddef>
#include <string>

#if defined(__CUDACC__)
#define CMC_HD __host__ __device__
#else
#define CMC_HD
#endif

namespace cmc {

enum class Backend { Cpu, Cuda };

inline const char* backend_name(Backend b) { return b == Backend::Cuda ? "cuda" : "cpu"; }

namespace cuda {
// Whether this build has the CUDA backend (-DCMC_CUDA=ON).
bool built();
// Whether a CUDA device can be used now; if not, `why` says what is missing (no driver,
// no device, a CPU-only build).
bool available(std::string* why = nullptr);
// "NVIDIA H100 80GB HBM3, 79.1 GiB, CUDA runtime 13.0" (throws where none is available).
std::string device_description();
// Seconds of one r2c + c2r pair of an nx x ny transform on the device (cuFFT, double): the
// unit the GPU runs' cost is reported in,
// timed like HalfSpace::time_fft_pair (fastest of at least min_repeats pairs taking
// min_seconds, after one untimed pair). Throws where no device is available.
double time_fft_pair(int nx, int ny, double min_seconds = 0.25, int min_repeats = 5);
// Bytes of the work area cuFFT needs for the two transforms of an nx x ny grid, as the
// device reports it; where there is none (or in a CPU build), one real field is assumed.
std::size_t fft_work_bytes(int nx, int ny);
// Bytes of device memory a Polonsky-Keer solve holds on an nx x ny periodic grid: the count
// of contact/polonsky_keer/CudaBackend.cuh (5 real fields, 1 more with the preconditioner,
// a byte mask, a spectrum, the compliance), cuFFT's work area, the reductions' scratch.
inline std::size_t polonsky_keer_bytes(int nx, int ny, bool precondition) {
  const std::size_t n = std::size_t(nx) * std::size_t(ny), ns = std::size_t(ny) * std::size_t(nx / 2 + 1);
  const std::size_t doubles = n * (precondition ? 6 : 5) + ns * 3;
  return doubles * sizeof(double) + n + fft_work_bytes(nx, ny) + (std::size_t(1) << 16);
}
// Bytes of device memory the quasi-static solver holds with its outer step on the device
// (contact/quasi_static/CudaBackend.cuh): Polonsky-Keer's, the heights, the tension and
// the cascade's passed-on gaps (3 real fields). The outer step's other fields (the gap, the
// predicted gaps and the cascade's flags) use Polonsky-Keer's direction, G t, contact mask
// and spectrum between solves.
inline std::size_t quasi_static_bytes(int nx, int ny, bool precondition) {
  const std::size_t n = std::size_t(nx) * std::size_t(ny);
  return polonsky_keer_bytes(nx, ny, precondition) + 3 * n * sizeof(double);
}
}  // namespace cuda

}  // namespace cmc
