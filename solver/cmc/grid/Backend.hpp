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
}  // namespace cuda

}  // namespace cmc
