// mollify.verify's compiled half: the samples to evaluate someone's kernel
// at, and the judgement of the values (mollify::verify::samples, compare:
// include/mollify/verify.hpp), over NumPy arrays; the Report as a Python
// object. python/mollify/_verify.py evaluates the callable between the two.
#include "arrays.hpp"
#include "bindings.hpp"

#include <mollify/error.hpp>
#include <mollify/verify.hpp>

#include <string>
#include <vector>

namespace mollify::python {

namespace {

namespace v = mollify::verify;

v::Options options(const std::string& convention, double ulps, std::uint64_t seed, std::size_t uniform) {
    v::Options o;
    o.convention = convention;
    o.ulps = ulps;
    o.seed = seed;
    o.uniform = uniform;
    return o;
}

py::tuple samples(const std::string& spec, int dim, const std::string& quantity, const std::string& convention,
                  double ulps, std::uint64_t seed, std::size_t uniform) {
    const std::vector<v::Sample> s =
        v::samples(spec, dim, v::parse_quantity(quantity), options(convention, ulps, seed, uniform));
    py::array_t<double> r(static_cast<py::ssize_t>(s.size())), h(static_cast<py::ssize_t>(s.size()));
    double* rp = r.mutable_data();
    double* hp = h.mutable_data();
    for (std::size_t i = 0; i < s.size(); ++i) {
        rp[i] = s[i].r;
        hp[i] = s[i].h;
    }
    return py::make_tuple(r, h);
}

v::Report compare(const std::string& spec, int dim, const std::string& quantity, const py::object& r,
                  const py::object& h, const py::object& values, const std::string& convention, double ulps,
                  std::uint64_t seed, std::size_t uniform) {
    const Broadcast at = broadcast(r, h);
    const Doubles got = Doubles::ensure(py::module_::import("numpy").attr("ascontiguousarray")(values, "float64"));
    if (static_cast<std::size_t>(got.size()) != at.size())
        fail(std::to_string(got.size()) + " values for " + std::to_string(at.size()) + " samples");
    std::vector<v::Sample> s(at.size());
    for (std::size_t i = 0; i < s.size(); ++i) s[i] = {at.first()[i], at.second()[i]};
    py::gil_scoped_release unlocked;
    return v::compare(spec, dim, v::parse_quantity(quantity), s, std::span<const double>(got.data(), s.size()),
                      options(convention, ulps, seed, uniform));
}

}  // namespace

void bind_verify(py::module_& m) {
    py::class_<v::Point>(m, "VerifyPoint", "one evaluation: the arguments, the value given, the exact value, the error")
        .def_readonly("r", &v::Point::r)
        .def_readonly("h", &v::Point::h)
        .def_readonly("got", &v::Point::got)
        .def_readonly("exact", &v::Point::exact)
        .def_readonly("ulps", &v::Point::ulps)
        .def("__repr__", [](const v::Point& p) {
            return "VerifyPoint(r=" + py::repr(py::float_(p.r)).cast<std::string>() +
                   ", h=" + py::repr(py::float_(p.h)).cast<std::string>() +
                   ", got=" + py::repr(py::float_(p.got)).cast<std::string>() +
                   ", exact=" + py::repr(py::float_(p.exact)).cast<std::string>() +
                   ", ulps=" + py::repr(py::float_(p.ulps)).cast<std::string>() + ")";
        });
    py::class_<v::Diagnosis>(m, "Diagnosis", "why the error is systematic: kind (e.g. 'constant factor') and text")
        .def_property_readonly("kind", [](const v::Diagnosis& d) { return std::string(v::name(d.kind)); })
        .def_readonly("text", &v::Diagnosis::text)
        .def("__repr__", [](const v::Diagnosis& d) { return "Diagnosis(" + std::string(v::name(d.kind)) + ": " + d.text + ")"; })
        .def("__str__", [](const v::Diagnosis& d) { return d.text; });
    py::class_<v::Report>(m, "Report", "the verdict on someone's kernel (mollify::verify::Report)")
        .def_readonly("spec", &v::Report::spec)
        .def_readonly("dim", &v::Report::dim)
        .def_property_readonly("quantity", [](const v::Report& r) { return std::string(v::name(r.quantity)); })
        .def_readonly("convention", &v::Report::convention)
        .def_readonly("bound", &v::Report::bound, "the bound in ulps (the ulps argument)")
        .def_readonly("float_ulps", &v::Report::float_ulps, "errors in ulps of float (a single-precision convention)")
        .def_readonly("points", &v::Report::points)
        .def_readonly("max_ulps", &v::Report::max_ulps)
        .def_readonly("rms_ulps", &v::Report::rms_ulps)
        .def_readonly("worst", &v::Report::worst, "the largest errors, largest first")
        .def_readonly("diagnosis", &v::Report::diagnosis, "a Diagnosis when the error is systematic, else None")
        .def_readonly("hard_points", &v::Report::hard_points,
                      "the verification's hard points (r = 0, the breakpoints, the support edge, the h sweep)")
        .def_readonly("hard_points_compared", &v::Report::hard_points_compared,
                      "how many of them are among the samples compared, bit for bit")
        .def_property_readonly("complete", &v::Report::complete, "every hard point among the samples compared")
        .def_property_readonly("passed", &v::Report::passed)
        .def("to_string", &v::Report::to_string)
        .def("__str__", &v::Report::to_string)
        .def("__repr__", [](const v::Report& r) {
            return "<mollify.verify report " + r.spec + " D" + std::to_string(r.dim) + " " + std::string(v::name(r.quantity)) +
                   ": " + (r.passed() ? "passed" : "FAILED") + ", max " + py::repr(py::float_(r.max_ulps)).cast<std::string>() +
                   " ulp" + (r.complete() ? "" : ", " + std::to_string(r.hard_points_compared) + " of " +
                                                     std::to_string(r.hard_points) + " hard points") + ">";
        });
    m.def("verify_samples", &samples, py::arg("spec"), py::arg("dim"), py::arg("quantity"), py::arg("convention"),
          py::arg("ulps"), py::arg("seed"), py::arg("uniform"));
    m.def("verify_compare", &compare, py::arg("spec"), py::arg("dim"), py::arg("quantity"), py::arg("r"), py::arg("h"),
          py::arg("values"), py::arg("convention"), py::arg("ulps"), py::arg("seed"), py::arg("uniform"));
}

}  // namespace mollify::python
