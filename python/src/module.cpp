// mollify._core: the compiled half of the Python package (python/mollify/).
// Every mollify::Error (a bad spec, r < 0, h <= 0, NaN, ...) reaches Python
// as mollify.Error, a ValueError carrying the library's message.
#include "bindings.hpp"

#include <mollify/error.hpp>

PYBIND11_MODULE(_core, m) {
    m.doc() = "mollify's compiled runtime and exact generator (use the package mollify)";
    pybind11::register_exception<mollify::Error>(m, "Error", PyExc_ValueError);
    mollify::python::bind_kernel(m);
    mollify::python::bind_exact(m);
    mollify::python::bind_verify(m);
}
