#include "arrays.hpp"

#include <mollify/error.hpp>

#include <string>

namespace mollify::python {

namespace {

py::module_ numpy() { return py::module_::import("numpy"); }

Doubles contiguous(const py::object& a) {
    return Doubles::ensure(numpy().attr("ascontiguousarray")(a, py::arg("dtype") = "float64"));
}

std::vector<py::ssize_t> shape_of(const py::array& a) { return {a.shape(), a.shape() + a.ndim()}; }

}  // namespace

Broadcast broadcast(const py::object& a, const py::object& b) {
    const py::module_ np = numpy();
    const py::tuple both =
        np.attr("broadcast_arrays")(np.attr("asarray")(a, "float64"), np.attr("asarray")(b, "float64"));
    Broadcast out{contiguous(both[0]), contiguous(both[1]), {}};
    out.shape = shape_of(both[0].cast<py::array>());  // ascontiguousarray makes 0-d arrays 1-d
    return out;
}

Displacements displacements(const py::object& x, const py::object& h, int dim) {
    const py::module_ np = numpy();
    py::array xs = np.attr("asarray")(x, "float64");
    if (dim == 1 && (xs.ndim() == 0 || xs.shape(xs.ndim() - 1) != 1)) xs = np.attr("expand_dims")(xs, -1);  // 1D: x itself
    if (xs.ndim() == 0 || xs.shape(xs.ndim() - 1) != dim)
        fail("displacements must have shape (..., " + std::to_string(dim) + ") for a kernel in D = " +
             std::to_string(dim) + ", not " + py::str(py::tuple(py::cast(shape_of(xs)))).cast<std::string>());
    const std::vector<py::ssize_t> lead(xs.shape(), xs.shape() + xs.ndim() - 1);
    // h against the points' shape: broadcast with x[..., 0].
    const py::tuple both = np.attr("broadcast_arrays")(xs[py::make_tuple(py::ellipsis(), 0)], np.attr("asarray")(h, "float64"));
    Displacements out;
    out.h = contiguous(both[1]);
    out.shape = shape_of(both[1].cast<py::array>());
    // x broadcast to the joint shape too (h may have more points than x).
    std::vector<py::ssize_t> full = out.shape;
    full.push_back(dim);
    const Doubles xb = contiguous(np.attr("broadcast_to")(xs, py::tuple(py::cast(full))));
    const std::size_t n = out.size();
    out.components.assign(static_cast<std::size_t>(dim), std::vector<double>(n));
    const double* p = xb.data();
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < dim; ++c) out.components[c][i] = p[i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(c)];
    return out;
}

py::array_t<double> empty(const std::vector<py::ssize_t>& shape, const std::vector<py::ssize_t>& trailing) {
    std::vector<py::ssize_t> full = shape;
    full.insert(full.end(), trailing.begin(), trailing.end());
    return py::array_t<double>(full);
}

py::object finish(py::array_t<double> a) {
    if (a.ndim() == 0) return py::float_(*a.data());
    return a;
}

}  // namespace mollify::python
