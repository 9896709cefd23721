#include "emit.hpp"

#include "emit_metadata.hpp"
#include "error.hpp"
#include "emit_round.hpp"
#include "write_cpp.hpp"
#include "write_data.hpp"
#include "write_json.hpp"

#include <boost/multiprecision/mpfr.hpp>

#include <algorithm>
#include <thread>

namespace mollify::gen {

namespace {

// What one kernel contributes to the output.
struct KernelOutput {
    std::string path, id, text;  // the kernel's file: C++ header or data file
    nlohmann::ordered_json json;
    std::vector<std::string> failures;  // failed certificates
    int certificates = 0;
};

KernelOutput render_kernel(const CatalogueEntry& e, EmitFormat format) {
    const KernelFacts f = kernel_facts(e);
    std::vector<std::optional<std::vector<RoundedPiece>>> tables;
    for (int i = 0; i < table::quantity_count; ++i)
        tables.push_back(rounded_quantity(quantity_of(f, i), table::is_potential(static_cast<table::QuantityId>(i)),
                                          parts_of(f, i)));
    KernelOutput out = format == EmitFormat::cpp
                           ? KernelOutput{kernel_header(f.spec, e.dim), f.id, kernel_cpp(f, tables), kernel_json(f), {}, 0}
                           : KernelOutput{kernel_data_path(f.spec, e.dim), f.id, kernel_data(f, tables), {}, {}, 0};
    for (const Certificate& c : f.certificates) {
        ++out.certificates;
        if (!c.passed) out.failures.push_back(f.spec + " D=" + std::to_string(e.dim) + ": " + c.what + " (" + c.detail + ")");
    }
    return out;
}

}  // namespace

EmitResult render_catalogue(const std::vector<CatalogueEntry>& entries, const std::string& command, EmitFormat format) {
    // Kernels are independent: render them on every core, then assemble in
    // catalogue order so the output does not depend on scheduling.
    std::vector<KernelOutput> outputs(entries.size());
    std::vector<std::string> errors(entries.size());
    const unsigned workers = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (unsigned w = 0; w < workers; ++w)
        pool.emplace_back([&, w] {
            for (std::size_t i = w; i < entries.size(); i += workers) {
                try {
                    outputs[i] = render_kernel(entries[i], format);
                } catch (const std::exception& ex) {
                    errors[i] = spec_string(entries[i].spec) + " D=" + std::to_string(entries[i].dim) + ": " + ex.what();
                }
            }
            mpfr_free_cache();  // MPFR keeps per-thread constant caches (pi)
        });
    for (auto& t : pool) t.join();
    for (const auto& e : errors)
        if (!e.empty()) fail(e);

    EmitResult result;
    std::vector<std::string> headers, ids;  // catalogue order
    std::vector<nlohmann::ordered_json> kernels;
    for (KernelOutput& k : outputs) {
        if (result.files.count(k.path)) fail("internal: two kernels emitted to " + k.path + " (" + k.id + ")");
        result.files[k.path] = format == EmitFormat::cpp ? kernel_file(command, k.text) : k.text;
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
    result.files["catalogue.json"] = catalogue_json(command, kernels);
    return result;
}

}  // namespace mollify::gen
