// What the solvers' passes share, written once for every solver and backend: the small
// reduction records their bodies fill (CMC_HD: callable on the GPU too), and the CPU's way
// of running a body over a range of points (the GPU's is grid/CudaDevice.cuh's).
#pragma once

#include "cmc/grid/Backend.hpp"
#include "cmc/grid/Grid.hpp"

#include <cstddef>

namespace cmc {

// A sum.
struct Sum {
  double v = 0.0;
  CMC_HD void merge(const Sum& o) { v += o.v; }
};
// A count, as a double (the GPU's reductions merge doubles).
struct Count {
  double n = 0.0;
  CMC_HD void merge(const Count& o) { n += o.n; }
};
// The largest rise and the largest fall of a quantity over the points (both >= 0).
struct RiseFall {
  double rise = 0.0, fall = 0.0;
  CMC_HD void merge(const RiseFall& o) {
    rise = rise < o.rise ? o.rise : rise;  // std::max, which device code lacks
    fall = fall < o.fall ? o.fall : fall;
  }
};

// Bodies of the shapes a solver hands its backend's passes, for the backend concepts
// (polonsky_keer/Contract.hpp, quasi_static/Contract.hpp), which only ask whether a call
// compiles; nothing calls these.
namespace archetype {
struct PointBody {
  CMC_HD void operator()(std::size_t) const {}
};
struct SumBody {
  CMC_HD void operator()(std::size_t, Sum&) const {}
};
}  // namespace archetype

// The CPU's passes, for a backend to derive from: f(i) for i in [0, k), and the sums of
// f(i, acc), OpenMP chunks merged in a fixed order (Grid::parallel_for, parallel_reduce).
struct HostPasses {
  template <class F>
  static void all(std::size_t k, F f) {
    Grid::parallel_for(k, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) f(i);
    });
  }
  template <class Acc, class F>
  static Acc reduce(std::size_t k, F f) {
    return Grid::parallel_reduce<Acc>(k, [&](std::size_t b, std::size_t e, Acc& acc) {
      for (std::size_t i = b; i < e; ++i) f(i, acc);
    });
  }
};

}  // namespace cmc
