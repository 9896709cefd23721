#include "emit.hpp"

#include "emit_metadata.hpp"
#include "error.hpp"
#include "emit_round.hpp"
#include "target.hpp"
#include "term_shapes.hpp"
#include "write_constants.hpp"
#include "write_cpp.hpp"
#include "write_data.hpp"
#include "write_json.hpp"

#include <boost/multiprecision/mpfr.hpp>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <thread>

namespace mollify::gen {

Tables rounded_tables(const KernelFacts& f) {
    Tables tables;
    for (int i = 0; i < table::quantity_count; ++i)
        tables.push_back(rounded_quantity(quantity_of(f, i), table::is_potential(static_cast<table::QuantityId>(i)),
                                          parts_of(f, i)));
    return with_one_split_grid(std::move(tables));
}

namespace {

// What one kernel contributes to the output.
struct KernelOutput {
    std::string path, id, text;  // the kernel's file: C++ header or data file
    std::string json;            // its entry in catalogue.json (C++ only)
    std::vector<std::string> failures;  // failed certificates
    int certificates = 0;
    TermShapes shapes;  // C++ only: its terms' shapes for the evaluator's fused loops
};

void count_certificates(const KernelFacts& f, int dim, int& certificates, std::vector<std::string>& failures) {
    for (const Certificate& c : f.certificates) {
        ++certificates;
        if (!c.passed) failures.push_back(f.spec + " D=" + std::to_string(dim) + ": " + c.what + " (" + c.detail + ")");
    }
}

// The order in which the entries are started: the missing Wendland
// functions first, the larger k + l and D before the smaller (their Taylor
// pieces are most of the catalogue's time), then the rest in catalogue
// order, so that the cores, each taking the next entry when free, finish
// together.
std::vector<std::size_t> schedule(const std::vector<CatalogueEntry>& entries) {
    auto weight = [&](std::size_t i) {
        const CatalogueEntry& e = entries[i];
        return e.spec.family == Family::wendland_missing ? 1 + 4 * (e.spec.k + e.spec.l) + e.dim : 0;
    };
    std::vector<std::size_t> order(entries.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return weight(a) > weight(b); });
    return order;
}

// f(entry i, i) for every entry, on every core; the first error (in
// catalogue order) rethrown naming its kernel.
template <class F>
void for_each_kernel(const std::vector<CatalogueEntry>& entries, F f) {
    std::vector<std::string> errors(entries.size());
    const std::vector<std::size_t> order = schedule(entries);
    std::atomic<std::size_t> next{0};
    const unsigned workers = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned w = 0; w < workers; ++w)
        pool.emplace_back([&] {
            for (std::size_t n; (n = next++) < order.size();) {
                const std::size_t i = order[n];
                try {
                    f(entries[i], i);
                } catch (const std::exception& ex) {
                    errors[i] = spec_string(entries[i].spec) + " D=" + std::to_string(entries[i].dim) + ": " + ex.what();
                }
            }
            mpfr_free_cache();  // MPFR keeps per-thread constant caches (pi)
        });
    for (auto& t : pool) t.join();
    for (const auto& e : errors)
        if (!e.empty()) fail(e);
}

// A kernel's file whole (banner included): made on the worker's core, so
// that the assembly after the workers only moves finished texts.
KernelOutput render_kernel(const CatalogueEntry& e, const std::string& command, EmitFormat format) {
    const KernelFacts f = kernel_facts(e);
    const Tables tables = rounded_tables(f);
    KernelOutput out = format == EmitFormat::cpp
                           ? KernelOutput{kernel_header(f.spec, e.dim), f.id, kernel_file(command, f, tables),
                                          kernel_entry(f), {}, 0, {}}
                           : KernelOutput{kernel_data_path(f.spec, e.dim), f.id, kernel_data(f, tables), {}, {}, 0, {}};
    count_certificates(f, e.dim, out.certificates, out.failures);
    if (format == EmitFormat::cpp) add_term_shapes(tables, e.dim, out.shapes);
    return out;
}

}  // namespace

EmitResult render_catalogue(const std::vector<CatalogueEntry>& entries, const std::string& command, EmitFormat format,
                            const FileReady& ready) {
    // Kernels are independent: render them on every core, then assemble in
    // catalogue order so the output does not depend on scheduling.
    std::vector<KernelOutput> outputs(entries.size());
    for_each_kernel(entries, [&](const CatalogueEntry& e, std::size_t i) {
        outputs[i] = render_kernel(e, command, format);
        if (ready) ready(outputs[i].path, outputs[i].text);
    });

    EmitResult result;
    std::vector<std::string> headers, ids;  // catalogue order
    std::vector<std::string> kernels;
    TermShapes shapes;
    for (KernelOutput& k : outputs) {
        shapes.add(k.shapes);
        if (result.files.count(k.path)) fail("internal: two kernels emitted to " + k.path + " (" + k.id + ")");
        result.files[k.path] = std::move(k.text);
        headers.push_back(k.path);
        ids.push_back(k.id);
        kernels.push_back(std::move(k.json));
        result.certificates += k.certificates;
        for (auto& f : k.failures) result.failed_certificates.push_back(f);
    }
    result.kernels = static_cast<int>(entries.size());
    if (format == EmitFormat::data) return result;
    result.files["mollify/tables/catalogue.hpp"] = catalogue_header(command);
    result.files["src/catalogue.cpp"] = catalogue_source(command, headers, ids);
    result.files["src/term_shapes.def"] = term_shapes_source(command, shapes);
    result.files["mollify/constants/cot_series.hpp"] = cot_series_header(command);
    result.files["mollify/constants/log_two.hpp"] = log_two_header(command);
    result.files["catalogue.json"] = catalogue_json(command, kernels);
    return result;
}

EmitResult render_target(const std::vector<CatalogueEntry>& entries, const std::string& command,
                         const std::string& name, bool allow_negative_lobes) {
    const Target& t = target(name);
    const Convention& c = convention(name);
    for (const CatalogueEntry& e : entries)
        if (std::find(c.dims.begin(), c.dims.end(), e.dim) == c.dims.end())
            fail("--target " + name + " takes no kernel in D = " + std::to_string(e.dim) + " (" + spec_string(e.spec) + ")");
    std::vector<TargetFiles> files(entries.size());
    std::vector<int> certificates(entries.size());
    std::vector<std::vector<std::string>> failures(entries.size());
    for_each_kernel(entries, [&](const CatalogueEntry& e, std::size_t i) {
        const KernelFacts f = kernel_facts(e);
        const Tables tables = rounded_tables(f);
        files[i] = t.write({f, tables, c, allow_negative_lobes}, command);
        count_certificates(f, e.dim, certificates[i], failures[i]);
    });
    EmitResult result;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        for (auto& [path, text] : files[i]) {
            if (result.files.count(path)) fail("internal: two kernels emitted to " + path);
            result.files[path] = std::move(text);
        }
        result.certificates += certificates[i];
        for (auto& f : failures[i]) result.failed_certificates.push_back(f);
    }
    result.kernels = static_cast<int>(entries.size());
    return result;
}

}  // namespace mollify::gen
