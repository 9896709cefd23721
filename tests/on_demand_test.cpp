// Any kernel at run time (include/mollify/exact.hpp): a kernel outside the
// compiled catalogue is generated exactly, certified, cached and evaluated
// without recompiling; its values are the exact ones (MPFR at >= 200 bits,
// correctly rounded) to the runtime's bounds; the cache is keyed by spec,
// dimension and generator version, and a damaged cache file is regenerated,
// never trusted; bad specs fail naming the value before any work.
#include <mollify/exact.hpp>
#include <mollify/table_file.hpp>
#include <mollify/tables/catalogue.hpp>

#include "emit_metadata.hpp"
#include "kernel.hpp"
#include "quantities.hpp"
#include "rounding.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace mollify::gen;

namespace {

// A fresh cache folder per test.
struct Cache {
    fs::path dir;
    explicit Cache(const std::string& name)
        : dir(fs::temp_directory_path() / ("mollify-on-demand-" + name + "-" + std::to_string(::getpid()))) {
        fs::remove_all(dir);
    }
    ~Cache() { fs::remove_all(dir); }
    mollify::exact::Options options() const { return {dir, true}; }
};

std::size_t files_below(const fs::path& dir) {
    std::size_t n = 0;
    if (fs::exists(dir))
        for (const auto& e : fs::recursive_directory_iterator(dir)) n += e.is_regular_file();
    return n;
}

// The exact value at a double r, correctly rounded.
double exact_at(const Radial& f, double r) {
    return round_to_double([&](unsigned bits) {
        Real rr(0, bits * 30103 / 100000 + 2);
        mpfr_set_d(rr.backend().data(), r, MPFR_RNDN);
        return f.evaluate(rr, bits);
    });
}

double ulps(double got, double exact) {
    if (got == exact) return 0;
    return std::abs(got - exact) / std::ldexp(1.0, std::ilogb(exact) - 52);
}

// W and W' of a generated kernel at h = 1 against the exact values: within
// 4 ulp (the accuracy suite's bound for Precision::accurate, tests/accuracy_test.cpp),
// at the hard points (near 0, the breakpoints, near the edge) and between.
void expect_exact_values(const std::string& spec, int dim) {
    Cache cache("values");
    const mollify::Kernel k = mollify::exact::kernel(spec, dim, mollify::Precision::accurate, cache.options());
    const ExactKernel exact = make_kernel(parse_spec(spec), dim);
    const Quantities q = derive_quantities(exact);
    for (const char* name : {"value", "dr"}) {
        const Radial& f = quantity(exact, q, name);
        for (double r : {1e-3, 0.1, 0.25, 0.25 + 0x1p-50, 1.0 / 3, 0.5, 0.5 - 0x1p-50, 0.7, 0.9, 0.99, 1 - 0x1p-20, 1 - 0x1p-40}) {
            const double e = exact_at(f, r);
            if (e == 0) continue;
            const double got = k(mollify::quantity(name), r, 1.0);
            EXPECT_LE(ulps(got, e), 4.0) << spec << " D=" << dim << " " << name << " at r = " << r << ": " << got
                                         << " against " << e;
        }
    }
}

}  // namespace

TEST(OnDemand, KernelsOutsideTheCatalogueAreExact) {
    for (const char* spec : {"wendland:k=6,l=3", "combo:radii=1/4;1/2;1,base=mollifier:M=5"}) {
        for (const mollify::table::Kernel* t : mollify::tables::all_kernels)
            ASSERT_NE(std::string(t->spec), spec) << "not a test of generation: " << spec << " is compiled in";
        expect_exact_values(spec, 3);
    }
    expect_exact_values("mollifier:M=11,order=4", 2);
}

TEST(OnDemand, CatalogueKernelsAreTheCompiledTables) {
    Cache cache("catalogue");
    const auto t = mollify::exact::table("wendland:l=0,k=2", 3, cache.options());  // any spelling
    bool found = false;
    for (const mollify::table::Kernel* c : mollify::tables::all_kernels) found = found || c == t.get();
    EXPECT_TRUE(found);
    EXPECT_EQ(files_below(cache.dir), 0u);  // nothing generated, nothing cached
}

TEST(OnDemand, GeneratedTablesAreCachedByVersionSpecAndDimension) {
    Cache cache("cache");
    const std::string spec = "wendland:k=5,l=2";
    const fs::path file = mollify::exact::cache_file(cache.dir, spec, 2);
    EXPECT_NE(file.string().find(generator_version()), std::string::npos) << file;
    const double first = mollify::exact::kernel(spec, 2, mollify::Precision::accurate, cache.options()).value(0.3, 1.0);
    ASSERT_TRUE(fs::is_regular_file(file)) << file;
    EXPECT_EQ(files_below(cache.dir), 1u);

    // Read back from the cache: the same table, bit for bit the same value.
    const auto stamp = fs::last_write_time(file);
    EXPECT_EQ(mollify::exact::kernel(spec, 2, mollify::Precision::accurate, cache.options()).value(0.3, 1.0), first);
    EXPECT_EQ(fs::last_write_time(file), stamp);

    // A damaged file (truncated) is regenerated, not trusted or fatal.
    fs::resize_file(file, fs::file_size(file) / 2);
    EXPECT_EQ(mollify::exact::kernel(spec, 2, mollify::Precision::accurate, cache.options()).value(0.3, 1.0), first);
    EXPECT_GT(fs::file_size(file), 0u);
    EXPECT_NO_THROW(mollify::TableFile::load(file));

    // A file changed where every field stays well formed (the first coefficient of W's first term
    // one ulp up, so the values move) fails its checksum and is regenerated; so is a file of
    // format 3 (no checksum): a cache trusts only what it can check.
    auto text_of = [&] {
        std::ifstream in(file);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    auto write = [&](const std::string& text) { std::ofstream(file, std::ios::trunc) << text; };
    const std::string good = text_of();
    const std::size_t term = good.find("\nterm ");
    ASSERT_NE(term, std::string::npos);
    const std::size_t digit = good.find(" 0x1.", good.find(" 0x", good.find(" 0x", good.find(" 0x", term) + 1) + 1) + 1);
    ASSERT_NE(digit, std::string::npos);
    std::string changed = good;
    const std::size_t last = changed.find('p', digit) - 1;  // the mantissa's last hex digit
    changed[last] = changed[last] == 'f' ? 'e' : static_cast<char>(changed[last] + 1);
    ASSERT_NE(changed, good);
    auto as_v3 = [](std::string text) {  // without the checksum line, as format 3
        text = text.substr(0, text.find("checksum"));
        return text.replace(0, std::string("mollify-table 4").size(), "mollify-table 3");
    };
    EXPECT_NO_THROW(mollify::TableFile::parse(as_v3(changed), "v3"));  // well formed: only the checksum tells
    write(changed);
    EXPECT_THROW(mollify::TableFile::load(file), mollify::Error);
    EXPECT_EQ(mollify::exact::kernel(spec, 2, mollify::Precision::accurate, cache.options()).value(0.3, 1.0), first);
    EXPECT_EQ(text_of(), good);
    write(as_v3(good));
    EXPECT_EQ(mollify::TableFile::load(file).version(), 3);
    EXPECT_EQ(mollify::exact::kernel(spec, 2, mollify::Precision::accurate, cache.options()).value(0.3, 1.0), first);
    EXPECT_EQ(text_of(), good);

    // A file holding another kernel under this name is not used either.
    const fs::path other = mollify::exact::cache_file(cache.dir, "wendland:k=5,l=1", 2);
    mollify::exact::table("wendland:k=5,l=1", 2, cache.options());
    fs::copy_file(other, file, fs::copy_options::overwrite_existing);
    EXPECT_EQ(mollify::exact::table(spec, 2, cache.options())->spec, spec);

    // use_cache = false: generated, nothing written.
    Cache none("none");
    mollify::exact::table(spec, 2, {none.dir, false});
    EXPECT_EQ(files_below(none.dir), 0u);

    // A cache that cannot be written (here a file where the folder would be) names the folder and
    // the ways on: MOLLIFY_CACHE_DIR, use_cache = false (which then works).
    Cache blocked("blocked");
    fs::create_directories(blocked.dir);
    std::ofstream(blocked.dir / generator_version()) << "a file, not a folder\n";
    try {
        mollify::exact::table(spec, 2, blocked.options());
        ADD_FAILURE() << "no error for an unwritable cache";
    } catch (const mollify::Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(blocked.dir.string()), std::string::npos) << m;
        EXPECT_NE(m.find("set MOLLIFY_CACHE_DIR to a writable folder"), std::string::npos) << m;
        EXPECT_NE(m.find("use_cache = false"), std::string::npos) << m;
    }
    EXPECT_EQ(mollify::exact::table(spec, 2, {blocked.dir, false})->spec, spec);
}

TEST(OnDemand, BadSpecsFailNamingTheValueBeforeAnyWork) {
    Cache cache("bad");
    auto message = [&](const std::string& spec, int dim) -> std::string {
        try {
            mollify::exact::table(spec, dim, cache.options());
        } catch (const mollify::Error& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_NE(message("wendland:k=99", 3).find("k=99"), std::string::npos);
    EXPECT_NE(message("wendlnd:k=2", 3).find("wendlnd"), std::string::npos);
    EXPECT_NE(message("viscosity", 1).find("not defined in D = 1"), std::string::npos);
    EXPECT_NE(message("wendland:k=6", 4).find("dimension 4"), std::string::npos);
    EXPECT_EQ(files_below(cache.dir), 0u);
}

TEST(OnDemand, DefaultCacheFolderFollowsTheEnvironment) {
    ::setenv("MOLLIFY_CACHE_DIR", "/some/where", 1);
    EXPECT_EQ(mollify::exact::default_cache_dir(), fs::path("/some/where"));
    ::unsetenv("MOLLIFY_CACHE_DIR");
    ::setenv("XDG_CACHE_HOME", "/x", 1);
    EXPECT_EQ(mollify::exact::default_cache_dir(), fs::path("/x/mollify"));
    ::unsetenv("XDG_CACHE_HOME");
}
