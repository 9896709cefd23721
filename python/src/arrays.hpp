// NumPy arrays in and out of the extension: arguments broadcast against each
// other (NumPy's rules, by NumPy itself) into contiguous float64 arrays the
// runtime's batch calls take, and results shaped like them.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstddef>
#include <span>
#include <vector>

namespace mollify::python {

namespace py = pybind11;

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

// a and b as float64, broadcast to one shape (np.broadcast_arrays), each made
// contiguous; the error NumPy raises for shapes that do not broadcast.
struct Broadcast {
    Doubles a, b;
    std::vector<py::ssize_t> shape;
    std::size_t size() const { return static_cast<std::size_t>(a.size()); }
    std::span<const double> first() const { return {a.data(), size()}; }
    std::span<const double> second() const { return {b.data(), size()}; }
};
Broadcast broadcast(const py::object& a, const py::object& b);

// Displacements x of shape (..., dim) (a scalar or a 1-D array of dim numbers
// for one point) and h broadcast against x's leading shape, copied into one
// contiguous array per component (the runtime's pairs take spans of spans).
struct Displacements {
    std::vector<std::vector<double>> components;  // dim arrays of n numbers
    Doubles h;                                    // n numbers
    std::vector<py::ssize_t> shape;               // the points' shape (x.shape[:-1])
    std::size_t size() const { return static_cast<std::size_t>(h.size()); }
};
Displacements displacements(const py::object& x, const py::object& h, int dim);

// An array of the given shape followed by `trailing` (empty: the shape);
// a 0-d result is returned as a Python float by finish().
py::array_t<double> empty(const std::vector<py::ssize_t>& shape, const std::vector<py::ssize_t>& trailing = {});
py::object finish(py::array_t<double> a);

// Calls f(first, last) on the maximal runs [first, last) of equal h (one
// Smoothing, one batch call, per run: a scalar h is one call).
template <class F>
void for_each_run(std::span<const double> h, F&& f) {
    std::size_t first = 0;
    while (first < h.size()) {
        std::size_t last = first + 1;
        while (last < h.size() && h[last] == h[first]) ++last;
        f(first, last);
        first = last;
    }
}

}  // namespace mollify::python
