// Tables loaded at run time (include/mollify/table_file.hpp): kernels that
// take every evaluation path of the catalogue (shape_features.hpp), written
// by `mollify-gen emit --format data` and loaded, are the compiled tables
// bit for bit, every field; bad files fail naming the file, the line and
// the bad value.
#include "command.hpp"
#include "fused_bound.hpp"
#include "sanitized.hpp"
#include "shape_features.hpp"

#include <mollify/error.hpp>
#include <mollify/table_file.hpp>
#include <mollify/tables/catalogue.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <set>
#include <unistd.h>

namespace fs = std::filesystem;
namespace table = mollify::table;
using mollify::TableFile;
using mollify::testing::same_bits;

namespace {

fs::path scratch(const std::string& name) {
    const fs::path p = fs::temp_directory_path() / ("mollify-table-file-test-" + std::to_string(::getpid()) + "-" + name);
    fs::remove_all(p);
    return p;
}

// Every field of two tables equal, doubles bit for bit (so -0.0 != 0.0 and
// inf == inf), absent arrays absent in both; the first difference, or "".
std::string difference(const table::Kernel& a, const table::Kernel& b) {
    if (std::strcmp(a.spec, b.spec) || a.dim != b.dim) return "spec/dim";
    if (!same_bits(a.support, b.support)) return "support";
    if (a.smoothness != b.smoothness || a.order != b.order || a.parity != b.parity) return "smoothness/order/parity";
    if (!same_bits(a.normalisation, b.normalisation)) return "normalisation";
    if (std::strcmp(a.normalisation_exact, b.normalisation_exact)) return "normalisation_exact";
    if (a.has_potential != b.has_potential) return "has_potential";
    for (int q = 0; q < table::quantity_count; ++q) {
        const table::Quantity &qa = a.quantities[q], &qb = b.quantities[q];
        const std::string where = table::quantity_names[q];
        if (qa.npieces != qb.npieces || (qa.pieces == nullptr) != (qb.pieces == nullptr)) return where + " pieces";
        for (int p = 0; p < qa.npieces; ++p) {
            const table::Piece &pa = qa.pieces[p], &pb = qb.pieces[p];
            const std::string at = where + " piece " + std::to_string(p);
            if (!same_bits(pa.lo, pb.lo) || !same_bits(pa.hi, pb.hi)) return at + " bounds";
            if (pa.nterms != pb.nterms || (pa.terms == nullptr) != (pb.terms == nullptr)) return at + " terms";
            for (int t = 0; t < pa.nterms; ++t) {
                const table::Term &x = pa.terms[t], &y = pb.terms[t];
                const std::string term = at + " term " + std::to_string(t);
                if (x.basis != y.basis || x.s_power != y.s_power || x.var != y.var || x.edge_power != y.edge_power ||
                    x.low != y.low || x.n != y.n)
                    return term + " shape";
                if (!same_bits(x.edge, y.edge) || !same_bits(x.edge_lo, y.edge_lo)) return term + " edge";
                if (!same_bits(x.centre, y.centre) || !same_bits(x.centre_lo, y.centre_lo)) return term + " centre";
                if ((x.c_lo == nullptr) != (y.c_lo == nullptr)) return term + " c_lo presence";
                if (x.plain != y.plain) return term + " plain";
                if (x.split != y.split || (x.m == nullptr) != (y.m == nullptr) || !same_bits(x.content, y.content) ||
                    !same_bits(x.content_lo, y.content_lo))
                    return term + " split";
                for (int k = 0; x.m && k < x.n; ++k)
                    if (!same_bits(x.m[k], y.m[k])) return term + " m[" + std::to_string(k) + "]";
                for (int k = 0; k < x.n; ++k) {
                    if (!same_bits(x.c[k], y.c[k])) return term + " c[" + std::to_string(k) + "]";
                    if (x.c_lo && !same_bits(x.c_lo[k], y.c_lo[k])) return term + " c_lo[" + std::to_string(k) + "]";
                }
            }
        }
    }
    return "";
}

std::string error_of(const std::string& text) {
    try {
        TableFile::parse(text, "bad.table");
    } catch (const mollify::Error& e) {
        return e.what();
    }
    return "(no error)";
}

// One kernel's file as mollify-gen writes it.
std::string kernel_text(const std::string& spec, const std::string& file) {
    const fs::path out = scratch("one");
    const auto r = mollify::testing::run_command(std::string(MOLLIFY_GEN) + " emit --format data --only " + spec + " --out " +
                                                     out.string(),
                                                 out.string() + "-log");
    EXPECT_EQ(r.status, 0) << r.err;
    const std::string text = mollify::testing::slurp(out / "mollify/tables" / file);
    fs::remove_all(out);
    return text;
}

// A small valid file: box-d1 in 1D (no potential).
std::string box_d1_text() { return kernel_text("box-d1", "classic/box_d1_D1.table"); }

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace

// Specs whose tables, together, take every path (term shape, piece kind,
// quantity kind) any catalogue table takes: the writer and the reader have
// one branch per such feature, so these exercise all of both. Chosen
// greedily (most new features first); a third of the catalogue's emit time
// is then spent, not all of it (under ASan: ~40 s instead of 277 s). Under
// the sanitizers, of the missing Wendland functions only one (sanitized.hpp).
std::vector<std::string> specs_covering_the_catalogue() {
    std::map<std::string, std::set<std::string>> by_spec;
    std::set<std::string> wanted;
    for (const table::Kernel* k : mollify::tables::all_kernels) {
        if (mollify::testing::left_to_optimised_build(k->spec)) continue;
        const std::set<std::string> f = mollify::testing::features(*k);
        by_spec[k->spec].insert(f.begin(), f.end());
        wanted.insert(f.begin(), f.end());
    }
    std::vector<std::string> chosen;
    while (!wanted.empty()) {
        std::string best;
        std::size_t gain = 0;
        for (const auto& [spec, f] : by_spec) {
            std::size_t n = 0;
            for (const std::string& x : f) n += wanted.count(x);
            if (n > gain) gain = n, best = spec;
        }
        if (gain == 0) break;
        chosen.push_back(best);
        for (const std::string& x : by_spec[best]) wanted.erase(x);
    }
    return chosen;
}

TEST(TableFile, KernelsOfEveryCataloguePathLoadBitForBitAsCompiled) {
    const std::vector<std::string> specs = specs_covering_the_catalogue();
    ASSERT_GE(specs.size(), 5u);  // families: wendland, missing, mollifier, combo, classic at least
    std::string only;
    for (const std::string& s : specs) only += " --only '" + s + "'";
    const fs::path out = scratch("catalogue");
    const auto r = mollify::testing::run_command(
        std::string(MOLLIFY_GEN) + " emit --format data" + only + " --out " + out.string(), out.string() + "-log");
    ASSERT_EQ(r.status, 0) << r.err;
    std::map<std::pair<std::string, int>, const table::Kernel*> compiled;
    for (const table::Kernel* k : mollify::tables::all_kernels) compiled[{k->spec, k->dim}] = k;
    std::set<std::string> loaded_specs;
    std::set<std::string> covered;
    for (const auto& e : fs::recursive_directory_iterator(out)) {
        if (!e.is_regular_file()) continue;
        ASSERT_EQ(e.path().extension(), ".table") << e.path();
        const TableFile file = TableFile::load(e.path());
        const table::Kernel& k = file.kernel();
        const auto it = compiled.find({k.spec, k.dim});
        ASSERT_NE(it, compiled.end()) << k.spec << " D=" << k.dim << " is not in the compiled catalogue";
        EXPECT_EQ(difference(k, *it->second), "") << k.spec << " D=" << k.dim;
        loaded_specs.insert(k.spec);
        for (const std::string& f : mollify::testing::features(k)) covered.insert(f);
        // The loaded table evaluates as the compiled one (table::evaluate, the reference).
        for (double x : {0.0, 0.25, 0.5, 0.999, 1.0, 2.0})
            EXPECT_TRUE(same_bits(table::evaluate(k.quantities[0], x), table::evaluate(it->second->quantities[0], x)));
    }
    EXPECT_EQ(loaded_specs, std::set<std::string>(specs.begin(), specs.end()));
    // The loaded files themselves (not only the compiled tables chosen) take every path of the catalogue.
    for (const table::Kernel* k : mollify::tables::all_kernels)
        for (const std::string& f : mollify::testing::features(*k))
            if (!mollify::testing::left_to_optimised_build(k->spec)) {
                EXPECT_TRUE(covered.count(f)) << "no loaded table takes the path of " << k->spec << " D" << k->dim << ": " << f;
            }
    fs::remove_all(out);
}

TEST(TableFile, MovingKeepsTheTableValid) {
    TableFile a = TableFile::parse(box_d1_text(), "box_d1_D1.table");
    const table::Kernel* before = &a.kernel();
    const TableFile b = std::move(a);
    EXPECT_EQ(&b.kernel(), before);
    EXPECT_STREQ(b.kernel().spec, "box-d1");
    EXPECT_FALSE(b.kernel().has_potential);
    EXPECT_EQ(b.kernel().quantities[static_cast<int>(table::QuantityId::potential)].npieces, 0);
}

TEST(TableFile, BadFilesFailNamingFileLineAndValue) {
    const std::string good = box_d1_text();
    ASSERT_NO_THROW(TableFile::parse(good, "good.table"));
    // Versions 1 (before table::Term::plain), 2 (before split) and 3 (before the checksum) are read
    // as well, without a checksum line.
    ASSERT_EQ(good.rfind("mollify-table 4\n", 0), 0u);
    const std::string unsummed = good.substr(0, good.find("checksum crc32 "));
    for (const char* v : {"1", "2", "3"}) {
        const TableFile f = TableFile::parse(replaced(unsummed, "mollify-table 4", std::string("mollify-table ") + v), "old.table");
        EXPECT_EQ(f.version(), v[0] - '0');
    }
    EXPECT_EQ(TableFile::parse(good, "good.table").version(), 4);
    // Wendland C4's W: c = 165/(32 pi) (3, 18, 35), exact at the grid 2^-23.
    const std::string c4 = kernel_text("wendland:k=2", "wendland/k_2_D3.table");
    ASSERT_NO_THROW(TableFile::parse(c4, "c4.table"));
    const std::string split = " split 23 0x1.a42b46d861c78p+0 0x1.a40f855b9a531p-54 0x1.8p+1 0x1.2p+4 0x1.18p+5\n";
    ASSERT_NE(c4.find(split), std::string::npos);
    const std::vector<std::pair<std::string, std::string>> cases = {
        {replaced(good, "mollify-table 4", "mollify-table 7"), "format version '7'"},
        // Version 4's checksum: a well-formed change (W's first coefficient one ulp up, which the
        // split's check, within 2^-51 of content m_0, lets through), a changed or missing checksum
        // line, a checksum of another kind.
        {replaced(c4, " 0x1.3b2075224955ap+2 ", " 0x1.3b2075224955bp+2 "), "is not the file's"},
        {replaced(c4, "checksum crc32 ", "checksum crc32 0"), "is not the file's"},
        {c4.substr(0, c4.find("checksum")), "the file ends where 'checksum' was expected"},
        {replaced(c4, "checksum crc32 ", "checksum md5 "), "checksum kind is not crc32"},
        // A split that would leave Horner's rule inexact: 3 + 18 q + 35 q^2 at the grid 2^-24 needs 54 bits.
        {replaced(c4, " split 23 ", " split 24 "), "split = 24 leaves Horner's rule inexact"},
        {replaced(c4, " split 23 ", " split 27 "), "split = 27 is outside 1..26"},
        {replaced(c4, " 0x1.8p+1 0x1.2p+4", " 0x1.9p+1 0x1.2p+4"), "m_k = 3.125"},
        {replaced(c4, " split 23 0x1.a42b46d861c78p+0", " split 23 0x1.a42b46d861d78p+0"), "is not c_k"},
        // A content that would leave content h^p subnormal at the smallest accepted scale.
        {replaced(c4, " split 23 0x1.a42b46d861c78p+0", " split 23 0x1.a42b46d861c78p-70"), "is outside [2^-60, 2^60]"},
        {replaced(good, " -\n", " - plain 5\n"), "plain = 5 is outside 0..n - 2"},
        {replaced(good, "dim 1", "dim 4"), "bad.table:4: dimension 4"},
        {replaced(good, "dim 1", "dim one"), "'one' is not an integer"},
        {replaced(good, "quantity dr", "quantity d2r"), "quantity 'd2r' where 'dr' was expected"},
        {replaced(good, "term one", "term cosh"), "basis 'cosh'"},
        {replaced(good, "piece 0x0p+0", "piece 0.5"), "'0.5' is not a hex-float"},
        // strtod reads "nan(0x1)" (it has an x): a NaN field is refused, not evaluated.
        {replaced(c4, "\nnormalisation 0x", "\nnormalisation nan(0x1) 0x"), "normalisation 'nan(0x1)' is NaN"},
        {replaced(c4, " split 23 0x1.a42b46d861c78p+0", " split 23 nan(0x1)"), "content 'nan(0x1)' is NaN"},
        // pieces that do not tile [0, inf): a gap, an overlap, an empty piece, an open end
        {replaced(c4, "piece 0x0p+0 0x1p+0 1", "piece 0x1p-1 0x1p+0 1"), "piece [0.5, 1) does not follow 0"},
        {replaced(c4, "piece 0x1p+0 inf 0", "piece 0x1.1p+0 inf 0"), "which ends at 1"},
        {replaced(c4, "piece 0x0p+0 0x1p+0 1", "piece 0x0p+0 0x0p+0 1"), "piece [0, 0) does not follow 0"},
        {replaced(c4, "piece 0x1p+0 inf 0", "piece 0x1p+0 0x1p+1 0"), "the last piece ends at 2, not inf"},
        {replaced(good, "has_potential 0", "has_potential 2"), "has_potential 2"},
        {good.substr(0, good.rfind('\n', good.size() / 2) + 1), "the file ends"},  // after a whole line
        {good + "junk\n", "text after the checksum"},
        {unsummed + "junk\n", "'junk' is not a 'checksum' line"},
        {replaced(unsummed, "mollify-table 4", "mollify-table 3") + "junk\n", "text after 'end'"},
    };
    for (const auto& [text, named] : cases) {
        const std::string e = error_of(text);
        EXPECT_NE(e.find(named), std::string::npos) << named << " -> " << e;
        EXPECT_EQ(e.rfind("bad.table:", 0), 0u) << e;
    }
    try {
        TableFile::load("/nonexistent/k_2_D3.table");
        ADD_FAILURE() << "no error";
    } catch (const mollify::Error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/k_2_D3.table"), std::string::npos) << e.what();
    }
}
