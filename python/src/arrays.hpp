// numpy arrays over cmc's own buffers, and the Python side of a solve's progress: the
// pieces every part of the module (cmc._core) shares.
#pragma once

#include "cmc/contact/Solver.hpp"
#include "cmc/grid/Grid.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <span>
#include <utility>
#include <vector>

namespace cmcpy {

namespace py = pybind11;

// A numpy array over a container's memory, which the array then owns: the container is
// moved to the heap (no copy of its values) and freed with the last view of it. Needs the GIL.
template <class Container>
py::array_t<double> adopt(Container&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new Container(std::move(values));
  py::capsule free_it(owned, [](void* p) { delete static_cast<Container*>(p); });
  return py::array_t<double>(std::move(shape), owned->data(), free_it);
}

// A field of an nx x ny grid as a (ny, nx) array: row iy holds y = iy dy, x fastest.
inline py::array_t<double> adopt_field(cmc::Field&& f, int nx, int ny) {
  return adopt(std::move(f), {py::ssize_t(ny), py::ssize_t(nx)});
}

// `f` times `k` (a unit conversion: reduced -> SI), in a new field.
inline cmc::Field scaled(std::span<const double> f, double k) {
  cmc::Field out(f.size());
  cmc::Grid::parallel_for(f.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) out[i] = f[i] * k;
  });
  return out;
}

// `f` times `k`, in place (a unit conversion of a buffer the caller hands on).
inline void scale_in_place(cmc::Field& f, double k) {
  cmc::Grid::parallel_for(f.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) f[i] *= k;
  });
}

// The values of a C-contiguous float64 array, to be read with the GIL released (the
// caller keeps the array alive).
inline std::span<const double> values_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
  return {a.data(), std::size_t(a.size())};
}

// The progress of a solve as Python sees it: Ctrl-C (a pending SIGINT, PyErr_CheckSignals)
// and the user's callback, called with the GIL at every progress point of the solver
// (every 25 iterations, or every outer step). Either one raising stops the solve: the
// exception unwinds the solver (its memory is owned by RAII holders) to the caller.
// Captured by pointer, so that copies of the Progress do not touch Python objects
// without the GIL. `step`: the load step being solved, numbered as in the summary.
struct PythonProgress {
  py::object callback;  // None or a callable taking one dict
  int step = 0;

  cmc::Progress hook() {
    return [this](const cmc::ProgressPoint& p) {
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (callback.is_none()) return;
      py::dict d;
      d["step"] = step;
      d["iteration"] = p.iteration;
      d["residual"] = p.residual;
      d["outer"] = p.outer;
      d["inner"] = p.inner;
      callback(d);
    };
  }
};

}  // namespace cmcpy
