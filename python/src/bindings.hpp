// The parts of the Python module cmc._core, one file each (python/src/).
#pragma once

#include <pybind11/pybind11.h>

namespace cmcpy {

void bind_run(pybind11::module_& m);       // run.cpp: cases and runs
void bind_surface(pybind11::module_& m);   // surface.cpp: generated surfaces and height files
void bind_analytic(pybind11::module_& m);  // analytic.cpp: the analytic references
void bind_check(pybind11::module_& m);     // check.cpp: predictions scored against references

}  // namespace cmcpy
