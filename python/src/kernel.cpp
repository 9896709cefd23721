// mollify.Kernel: the run-time form (mollify::Kernel) over NumPy arrays. Every
// radial quantity by its table name (value, dr, ..., potential_hess_radial;
// force = dpotential, dphi/dr, as mollify.verify names it) at broadcast (r, h),
// and the vector forms of StaticKernel (gradient, pair, hessian,
// potential_gradient, potential_hessian) at displacements of shape (..., D).
// Each is one batch call per run of equal h, outside the GIL.
#include "arrays.hpp"
#include "bindings.hpp"

#include <mollify/exact.hpp>

#include <cmath>
#include <string>

namespace mollify::python {

namespace {

py::object radial(const Kernel& k, QuantityId q, const py::object& r, const py::object& h) {
    const Broadcast b = broadcast(r, h);
    py::array_t<double> out = empty(b.shape);
    double* o = out.mutable_data();
    {
        py::gil_scoped_release unlocked;
        const std::span<const double> rs = b.first(), hs = b.second();
        for_each_run(hs, [&](std::size_t first, std::size_t last) {
            k.evaluate(q, rs.subspan(first, last - first), hs[first], std::span<double>(o + first, last - first));
        });
    }
    return finish(std::move(out));
}

std::vector<std::span<const double>> const_spans(const Displacements& x, std::size_t first, std::size_t last) {
    std::vector<std::span<const double>> s;
    for (const auto& c : x.components) s.emplace_back(c.data() + first, last - first);
    return s;
}

// W_h and grad W_h at displacements (mollify::Kernel::pairs: the cusp
// kernels' and the odd 1D kernel's gradients as StaticKernel forms them).
py::tuple pair(const Kernel& k, const py::object& x, const py::object& h) {
    const int dim = k.dim();
    const Displacements d = displacements(x, h, dim);
    py::array_t<double> w = empty(d.shape), grad = empty(d.shape, {dim});
    std::vector<std::vector<double>> g(static_cast<std::size_t>(dim), std::vector<double>(d.size()));
    {
        py::gil_scoped_release unlocked;
        double* wo = w.mutable_data();
        const std::span<const double> hs(d.h.data(), d.size());
        for_each_run(hs, [&](std::size_t first, std::size_t last) {
            const std::vector<std::span<const double>> xs = const_spans(d, first, last);
            std::vector<std::span<double>> gs;
            for (auto& c : g) gs.emplace_back(c.data() + first, last - first);
            k.pairs(xs, k.smoothing(hs[first]), std::span<double>(wo + first, last - first), gs);
        });
        double* go = grad.mutable_data();
        for (std::size_t i = 0; i < d.size(); ++i)
            for (int c = 0; c < dim; ++c) go[i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(c)] = g[c][i];
    }
    return py::make_tuple(finish(std::move(w)), finish(std::move(grad)));
}

// |x| as StaticKernel::norm forms it; coordinates checked as the runtime
// checks them (its message).
std::vector<double> norms(const Displacements& d) {
    std::vector<double> r(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
        double s = 0;
        for (std::size_t c = 0; c < d.components.size(); ++c) {
            const double v = d.components[c][i];
            detail::check_coordinate(v, static_cast<int>(c));
            s = c == 0 ? v * v : std::fma(v, v, s);
        }
        r[i] = d.components.size() == 1 ? std::abs(d.components[0][i]) : std::sqrt(s);
    }
    return r;
}

std::vector<double> at(const Kernel& k, QuantityId q, const std::vector<double>& r, const Doubles& h) {
    std::vector<double> out(r.size());
    const std::span<const double> hs(h.data(), r.size());
    for_each_run(hs, [&](std::size_t first, std::size_t last) {
        k.evaluate(q, std::span<const double>(r).subspan(first, last - first), hs[first],
                   std::span<double>(out).subspan(first, last - first));
    });
    return out;
}

// grad phi_h = (phi_h'/r) x.
py::object potential_gradient(const Kernel& k, const py::object& x, const py::object& h) {
    const int dim = k.dim();
    const Displacements d = displacements(x, h, dim);
    py::array_t<double> out = empty(d.shape, {dim});
    {
        py::gil_scoped_release unlocked;
        const std::vector<double> r = norms(d);
        const std::vector<double> over_r = at(k, QuantityId::dpotential_over_r, r, d.h);
        double* o = out.mutable_data();
        for (std::size_t i = 0; i < d.size(); ++i)
            for (int c = 0; c < dim; ++c) o[i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(c)] = over_r[i] * d.components[c][i];
    }
    return finish(std::move(out));
}

// Hessian = (f'/r) I + ((f'' - f'/r)/r^2) x x^T, both parts emitted exactly;
// in 1D W'' itself (sign(x) W'' for the odd kernel), as StaticKernel::hessian.
py::object hessian(const Kernel& k, const py::object& x, const py::object& h, bool of_potential) {
    const int dim = k.dim();
    const Displacements d = displacements(x, h, dim);
    py::array_t<double> out = empty(d.shape, {dim, dim});
    {
        py::gil_scoped_release unlocked;
        const std::vector<double> r = norms(d);
        double* o = out.mutable_data();
        const std::size_t n = d.size(), dd = static_cast<std::size_t>(dim) * static_cast<std::size_t>(dim);
        if (dim == 1 && !of_potential) {
            const std::vector<double> d2 = at(k, QuantityId::d2r, r, d.h);
            const bool odd = k.table().parity < 0;
            for (std::size_t i = 0; i < n; ++i) o[i] = odd && d.components[0][i] < 0 ? -d2[i] : d2[i];
        } else {
            const std::vector<double> over_r =
                at(k, of_potential ? QuantityId::dpotential_over_r : QuantityId::grad_over_r, r, d.h);
            const std::vector<double> rad =
                at(k, of_potential ? QuantityId::potential_hess_radial : QuantityId::hess_radial, r, d.h);
            // The upper triangle as StaticKernel forms it, mirrored: symmetric
            // to the bit ((rad x_i) x_j and (rad x_j) x_i may round apart).
            for (std::size_t p = 0; p < n; ++p)
                for (int i = 0; i < dim; ++i)
                    for (int j = i; j < dim; ++j) {
                        const double v = rad[p] * d.components[i][p] * d.components[j][p] + (i == j ? over_r[p] : 0.0);
                        o[p * dd + static_cast<std::size_t>(i * dim + j)] = v;
                        o[p * dd + static_cast<std::size_t>(j * dim + i)] = v;
                    }
        }
    }
    return finish(std::move(out));
}

std::string repr(const Kernel& k) {
    return "mollify.kernel('" + std::string(k.spec()) + "', " + std::to_string(k.dim()) + ", precision='" +
           std::string(name(k.precision())) + "')";
}

}  // namespace

void bind_kernel(py::module_& m) {
    py::class_<Kernel> cls(m, "Kernel",
                           "A kernel W_h in D dimensions, evaluated by libmollify's run-time form (mollify::Kernel).");
    cls.def_property_readonly("spec", [](const Kernel& k) { return std::string(k.spec()); }, "canonical kernel spec")
        .def_property_readonly("dim", &Kernel::dim)
        .def_property_readonly("has_potential", &Kernel::has_potential)
        .def_property_readonly("precision", [](const Kernel& k) { return std::string(name(k.precision())); })
        .def_property_readonly("support", [](const Kernel& k) { return k.table().support; },
                               "support radius in units of h (1)")
        .def_property_readonly("smoothness", [](const Kernel& k) { return k.table().smoothness; })
        .def_property_readonly("order", [](const Kernel& k) { return k.table().order; })
        .def("with_precision", [](const Kernel& k, const std::string& p) { return k.with(precision(p)); },
             py::arg("precision"), "the same kernel at another precision ('accurate' or 'fast')")
        .def("evaluate", [](const Kernel& k, const std::string& q, const py::object& r, const py::object& h) {
                 return radial(k, quantity(q), r, h);
             }, py::arg("quantity"), py::arg("r"), py::arg("h"),
             "the named radial quantity at r and h (broadcast), as float64")
        .def("__call__", [](const Kernel& k, const std::string& q, const py::object& r, const py::object& h) {
                 return radial(k, quantity(q), r, h);
             }, py::arg("quantity"), py::arg("r"), py::arg("h"))
        .def("gradient", [](const Kernel& k, const py::object& x, const py::object& h) -> py::object {
                 const py::tuple wg = pair(k, x, h);
                 return wg[1];
             },
             py::arg("x"), py::arg("h"), "grad W_h at displacements x of shape (..., D)")
        .def("pair", &pair, py::arg("x"), py::arg("h"), "(W_h, grad W_h) at displacements x of shape (..., D)")
        .def("hessian", [](const Kernel& k, const py::object& x, const py::object& h) { return hessian(k, x, h, false); },
             py::arg("x"), py::arg("h"), "the Hessian of W_h at displacements x, shape (..., D, D)")
        .def("potential_gradient", &potential_gradient, py::arg("x"), py::arg("h"),
             "grad phi_h at displacements x (the field of a unit charge is its negative)")
        .def("potential_hessian", [](const Kernel& k, const py::object& x, const py::object& h) { return hessian(k, x, h, true); },
             py::arg("x"), py::arg("h"))
        .def("__repr__", &repr);
    for (int i = 0; i < table::quantity_count; ++i) {
        const auto q = static_cast<QuantityId>(i);
        cls.def(quantity_names[i], [q](const Kernel& k, const py::object& r, const py::object& h) { return radial(k, q, r, h); },
                py::arg("r"), py::arg("h"),
                (std::string("the quantity '") + quantity_names[i] + "' at r and h (broadcast)").c_str());
    }
    cls.def("force", [](const Kernel& k, const py::object& r, const py::object& h) {
        return radial(k, QuantityId::dpotential, r, h);
    }, py::arg("r"), py::arg("h"), "dphi_h/dr (= dpotential; mollify.verify's quantity 'force')");

    m.def("kernel", [](const std::string& spec, int dim, const std::string& p) {
              return exact::kernel(spec, dim, precision(p));
          }, py::arg("spec"), py::arg("dim"), py::arg("precision") = "accurate",
          "the kernel of a spec in dim: the compiled catalogue's, else generated exactly and cached (mollify::exact::kernel)");
    m.def("isa", [] { return std::string(isa()); }, "the instruction set of the runtime's loops");
}

}  // namespace mollify::python
