// Kernel values: any kernel of the grammar tabulated at given radii and one
// smoothing length, for every quantity asked for, as a user checks a kernel
// (or compares mollify with another code) without writing a program. A
// kernel outside the compiled catalogue is generated exactly, certified and
// cached on the first run (mollify::exact), then evaluated by libmollify's
// run-time form: nothing is recompiled. Output: values.csv (spec, dim,
// quantity, h, r, value with 17 significant digits: the double itself),
// summary.md.
#include "experiment.hpp"

#include <mollify/dynamic_kernel.hpp>
#include <mollify/exact.hpp>
#include <mollify/smoothing.hpp>
#include <mollify/tables/catalogue.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mollify::app {

namespace {

// %.17g: enough digits that the text reads back as the same double.
std::string exact_digits(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

std::string origin_of(const Kernel& k) {
    for (const table::Kernel* t : tables::all_kernels)
        if (t == &k.table()) return "compiled in";
    return "generated (mollify::exact), cached";
}

}  // namespace

void run_kernel_values(const Scene& scene, Output& out) {
    scene.only("kernel_values", {"kernels", "dim", "quantities", "radii", "h", "precision"});
    const long dim = scene.integer("kernel_values.dim");
    if (dim < 1 || dim > 3) scene.reject("kernel_values.dim", std::to_string(dim) + " is not 1, 2 or 3");
    const double h = scene.positive("kernel_values.h");
    checked(scene, "kernel_values.h", [&] { (void)Smoothing(h, static_cast<int>(dim)); });
    const std::vector<double> radii = scene.numbers("kernel_values.radii");
    if (radii.empty()) scene.reject("kernel_values.radii", "no radius");
    for (double r : radii)
        if (!(r >= 0) || !std::isfinite(r)) scene.reject("kernel_values.radii", format(r) + " is not a finite radius >= 0");
    std::vector<QuantityId> quantities;
    for (const std::string& name : scene.has("kernel_values.quantities") ? scene.strings("kernel_values.quantities")
                                                                            : std::vector<std::string>{"value"}) {
        quantities.push_back(checked(scene, "kernel_values.quantities", [&] { return quantity(name); }));
    }
    if (quantities.empty()) scene.reject("kernel_values.quantities", "no quantity");
    const Precision precision = scene_precision(scene, "kernel_values.precision");
    // Every kernel resolved (and generated where needed) before any value:
    // a bad spec fails the scene with its name and nothing written.
    std::vector<Kernel> kernels;
    const std::vector<std::string> specs = scene.strings("kernel_values.kernels");
    if (specs.empty()) scene.reject("kernel_values.kernels", "no kernel");
    for (const std::string& spec : specs) {
        kernels.push_back(checked(scene, "kernel_values.kernels", [&] { return exact::kernel(spec, static_cast<int>(dim), precision); }));
        for (QuantityId q : quantities)
            if (table::is_potential(q) && !kernels.back().has_potential())
                scene.reject("kernel_values.quantities", "kernel " + spec + " has no " + quantity_names[static_cast<int>(q)]);
    }

    Table values{{"spec", "dim", "quantity", "h", "r", "value"}, {}};
    Table origins{{"kernel", "table"}, {}};
    for (const Kernel& k : kernels) {
        origins.add({std::string(k.spec()), origin_of(k)});
        for (QuantityId q : quantities) {
            std::vector<double> v(radii.size());
            k.evaluate(q, radii, h, v);
            for (std::size_t i = 0; i < radii.size(); ++i)
                values.add({std::string(k.spec()), std::to_string(dim), quantity_names[static_cast<int>(q)],
                            exact_digits(h), exact_digits(radii[i]), exact_digits(v[i])});
        }
    }
    out.csv("values.csv", values);
    std::string& md = out.summary();
    md += "# " + scene.title() + "\n\n";
    md += "Every value is the double mollify's run-time form returns (Precision::" + std::string(name(precision)) +
          ", within 4 ulp of the exact value: tests/accuracy_test.cpp), h = " + exact_digits(h) + ", D = " +
          std::to_string(dim) + "; check any of them with `mollify-gen value SPEC --dim D --r R` (h = 1).\n\n";
    md += origins.markdown() + "\n" + values.markdown();
}

}  // namespace mollify::app
