#pragma once
// gonio.measure (measure_binding.cpp): defined when the module is built with the renderer's
// libraries (GONIO_PYTHON_RENDER), as the virtual gonioreflectometer traces with Embree.

#include <pybind11/pybind11.h>

namespace gonio::python {

void register_measure(pybind11::module_& mod);

}  // namespace gonio::python
