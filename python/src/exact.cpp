// mollify.exact: exact values (the generator's query code, as `mollify-gen
// value`: generator/query.*) and any kernel of the grammar at run time
// (mollify::exact::kernel). Numbers cross as "p/q" strings, which Python
// turns into fractions.Fraction (python/mollify/exact.py).
#include "bindings.hpp"

#include <mollify/exact.hpp>

#include "number.hpp"
#include "query.hpp"
#include "rounding.hpp"
#include "spec.hpp"

#include <map>
#include <memory>
#include <string>
#include <tuple>

namespace mollify::python {

namespace py = pybind11;

namespace {

// The exact quantities asked for so far: making a kernel exactly and deriving
// its quantities takes milliseconds to seconds, a value at one r microseconds.
const gen::Radial& quantity_of(const std::string& canonical, int dim, const std::string& name) {
    static std::map<std::tuple<std::string, int, std::string>, std::shared_ptr<const gen::Radial>> known;
    auto& f = known[{canonical, dim, name}];
    if (!f) f = std::make_shared<const gen::Radial>(gen::query(gen::make_kernel(gen::parse_spec(canonical), dim), name));
    return *f;
}

gen::ExactValue value(const std::string& spec, int dim, const std::string& r, const std::string& name,
                      const std::string& h) {
    const std::string canonical = spec_string(parse_spec(spec));
    // The numbers `mollify-gen value --r` reads: rationals, decimals and hex-floats (a double's exact value).
    const gen::Q rq = gen::parse_rational_or_hex_float(r, "r"), hq = gen::parse_rational_or_hex_float(h, "h");
    const gen::Scaling s = hq == 1 ? gen::Scaling{} : gen::scaling(name, dim);
    const std::string where = name + " of " + canonical + " in D = " + std::to_string(dim);
    return gen::exact_value(quantity_of(canonical, dim, name), rq, hq, s, where);
}

}  // namespace

void bind_exact(py::module_& m) {
    py::class_<gen::ExactValue>(m, "ExactValue", "an exact value: its closed form, and correct rounding")
        .def_property_readonly("closed_form", [](const gen::ExactValue& v) { return v.closed_form; })
        .def_property_readonly("rational", [](const gen::ExactValue& v) -> py::object {
            if (v.exact && v.exact->is_rational()) return py::str(gen::pq(v.exact->rational()));
            return py::none();
        }, "'p/q' where the value is rational, else None")
        .def_property_readonly("is_exact", [](const gen::ExactValue& v) { return v.exact.has_value(); },
                               "a finite sum q pi^e log(p) (True), or a closed form at r (False)")
        .def("__float__", [](const gen::ExactValue& v) {
            return v.exact ? gen::round_to_double(*v.exact) : gen::round_to_double(v.evaluate);
        }, "the value correctly rounded to double")
        .def("decimal", [](const gen::ExactValue& v, int digits) {
            if (digits < 1 || digits > gen::max_decimal_digits)
                fail("digits " + std::to_string(digits) + " is outside 1.." + std::to_string(gen::max_decimal_digits));
            return v.exact ? gen::decimal(*v.exact, digits) : gen::decimal(v.evaluate, digits);
        }, py::arg("digits"), "the value to that many significant digits, correctly rounded")
        .def("__repr__", [](const gen::ExactValue& v) {
            return "<exact " + v.closed_form + " = " + (v.exact ? gen::decimal(*v.exact, 17) : gen::decimal(v.evaluate, 17)) +
                   "...>";
        });
    m.def("exact_value", &value, py::arg("spec"), py::arg("dim"), py::arg("r"), py::arg("quantity"), py::arg("h"));
    m.def("quantity_names", &gen::query_names);
    m.def("exact_kernel", [](const std::string& spec, int dim, const std::string& p, const std::string& cache_dir,
                             bool use_cache) {
        exact::Options o;
        o.cache_dir = cache_dir;
        o.use_cache = use_cache;
        return exact::kernel(spec, dim, precision(p), o);
    }, py::arg("spec"), py::arg("dim"), py::arg("precision"), py::arg("cache_dir"), py::arg("use_cache"));
    m.def("default_cache_dir", [] { return exact::default_cache_dir().string(); });
}

}  // namespace mollify::python
