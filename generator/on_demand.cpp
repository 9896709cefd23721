// Any kernel at run time (include/mollify/exact.hpp): the compiled catalogue,
// else the cache, else the exact generator. The cache holds table files
// (`mollify-gen emit --format data`, write_data.cpp) under a folder per
// generator version, so a newer generator never reads an older one's
// tables; files are written atomically (write_files), and one that does not
// read back as the table asked for is generated anew, never trusted.
#include <mollify/exact.hpp>
#include <mollify/spec.hpp>
#include <mollify/table_file.hpp>
#include <mollify/tables/catalogue.hpp>

#include "catalogue.hpp"
#include "emit.hpp"
#include "emit_metadata.hpp"
#include "write_data.hpp"

#include <cstdlib>
#include <string>

namespace mollify::exact {

namespace {

std::filesystem::path from_environment(const char* name, const char* below = nullptr) {
    const char* v = std::getenv(name);
    if (!v || !*v) return {};
    return below ? std::filesystem::path(v) / below : std::filesystem::path(v);
}

// The spec and dimension checked before any work: the grammar (an Error
// naming the bad part) and the dimensions the kernel exists in.
gen::CatalogueEntry entry_of(std::string_view spec, int dim) {
    if (dim < 1 || dim > 3) fail("dimension " + std::to_string(dim) + " is not 1, 2 or 3");
    const Spec s = parse_spec(spec);
    if (!gen::defined_in(s, dim)) fail("kernel " + spec_string(s) + " is not defined in D = " + std::to_string(dim));
    return {s, dim};
}

std::shared_ptr<const table::Kernel> compiled(const std::string& key, int dim) {
    for (const table::Kernel* t : tables::all_kernels)
        if (key == t->spec && t->dim == dim) return {std::shared_ptr<const void>(), t};  // static storage: nothing to own
    return nullptr;
}

std::shared_ptr<const table::Kernel> owned(TableFile file) {
    auto f = std::make_shared<const TableFile>(std::move(file));
    return {f, &f->kernel()};
}

// A cached table, or nullptr where there is none or it is not the one asked
// for (a truncated, changed or foreign file, another spec behind the same
// name, a file without the checksum of format 4: regenerated, never trusted).
std::shared_ptr<const table::Kernel> cached(const std::filesystem::path& file, const std::string& key, int dim) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return nullptr;
    try {
        TableFile f = TableFile::load(file);
        if (f.version() < 4) return nullptr;
        auto t = owned(std::move(f));
        if (key == t->spec && t->dim == dim) return t;
    } catch (const Error&) {
    }
    return nullptr;
}

}  // namespace

std::filesystem::path default_cache_dir() {
    for (const auto& dir : {from_environment("MOLLIFY_CACHE_DIR"), from_environment("XDG_CACHE_HOME", "mollify"),
                            from_environment("HOME", ".cache/mollify")})
        if (!dir.empty()) return dir;
    return std::filesystem::temp_directory_path() / "mollify-cache";
}

std::filesystem::path cache_file(const std::filesystem::path& cache, std::string_view spec, int dim) {
    return cache / gen::generator_version() / gen::kernel_data_path(std::string(spec), dim);
}

std::shared_ptr<const table::Kernel> table(std::string_view spec, int dim, const Options& options) {
    const gen::CatalogueEntry e = entry_of(spec, dim);
    const std::string key = spec_string(e.spec);
    if (auto t = compiled(key, dim)) return t;
    const std::filesystem::path cache = options.cache_dir.empty() ? default_cache_dir() : options.cache_dir;
    const std::filesystem::path file = cache_file(cache, key, dim);
    if (options.use_cache)
        if (auto t = cached(file, key, dim)) return t;
    // Generated exactly and certified; the table evaluated is the text just
    // generated, so the cache and this run agree.
    const gen::EmitResult r = gen::render_catalogue({e}, "mollify-gen emit --format data --only '" + key + "'",
                                                    gen::EmitFormat::data);
    if (!r.failed_certificates.empty()) fail("kernel " + key + " failed its certificate: " + r.failed_certificates.front());
    if (r.files.size() != 1) fail("kernel " + key + ": the generator wrote " + std::to_string(r.files.size()) + " tables, not 1");
    if (options.use_cache) {
        try {
            gen::write_files(cache / gen::generator_version(), r);
        } catch (const Error& e) {  // a read-only home on a cluster's nodes: say how to go on
            fail(std::string(e.what()) + " (the cache of generated kernels, " + cache.string() +
                 ": set MOLLIFY_CACHE_DIR to a writable folder, or generate without caching: "
                 "exact::Options::use_cache = false, Python's use_cache=False)");
        }
    }
    return owned(TableFile::parse(r.files.begin()->second, key));
}

Kernel kernel(std::string_view spec, int dim, Precision precision, const Options& options) {
    return mollify::kernel(table(spec, dim, options), precision);
}

}  // namespace mollify::exact
