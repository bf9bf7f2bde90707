// grid/Backend.hpp in a build without the CUDA backend (the default): there is no device,
// and the case parser refuses backend = "cuda" with the key named (Case.cpp).
#ifndef CMC_CUDA
#include "cmc/grid/Backend.hpp"

#include <stdexcept>

namespace cmc::cuda {

namespace {
const char* kNotBuilt = "this build of cmc has no CUDA backend (configure a build folder with -DCMC_CUDA=ON; docs/user-guide/gpu.md)";
}

bool built() { return false; }
bool available(std::string* why) {
  if (why) *why = kNotBuilt;
  return false;
}
std::string device_description() { throw std::runtime_error(kNotBuilt); }
double time_fft_pair(int, int, double, int) { throw std::runtime_error(kNotBuilt); }
std::size_t fft_work_bytes(int nx, int ny) { return std::size_t(nx) * std::size_t(ny) * sizeof(double); }

}  // namespace cmc::cuda
#endif
