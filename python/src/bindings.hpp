// The parts of the extension module mollify._core, one per concept.
#pragma once

#include <pybind11/pybind11.h>

namespace mollify::python {

void bind_kernel(pybind11::module_& m);  // mollify.kernel, mollify.Kernel (kernel.cpp)
void bind_exact(pybind11::module_& m);   // exact values (exact.cpp)
void bind_verify(pybind11::module_& m);  // mollify.verify's samples, compare, Report (verify.cpp)

}  // namespace mollify::python
