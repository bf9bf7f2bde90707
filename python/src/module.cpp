// The compiled core of the Python package cmc (python/cmc/): cmc._core. The package's
// modules wrap it with the documented API (docs/user-guide/python.md); this module is
// the library's functions with the GIL released while they compute.
#include "bindings.hpp"

#include "References.hpp"
#include "cmc/input/Case.hpp"
#include "cmc/surface/SurfaceIO.hpp"

PYBIND11_MODULE(_core, m) {
  m.doc() = "cmc's compiled core: use the package cmc (docs/user-guide/python.md).";
  m.attr("__version__") = CMC_VERSION;
  // Bad input, named as the command line names it (file, key or argument, and what was
  // expected): ValueErrors, so that callers may catch either.
  pybind11::register_exception<cmc::CaseError>(m, "CaseError", PyExc_ValueError);
  pybind11::register_exception<cmc::reference::InputError>(m, "InputError", PyExc_ValueError);
  pybind11::register_exception<cmc::SurfaceFileError>(m, "SurfaceFileError", PyExc_ValueError);
  cmcpy::bind_run(m);
  cmcpy::bind_surface(m);
  auto analytic = m.def_submodule("analytic");
  cmcpy::bind_analytic(analytic);
  cmcpy::bind_check(m);
}
