// Tables as data (include/mollify/table_file.hpp): every catalogue table
// written as text and read back is the same table, field for field and bit
// for bit (hexadecimal floats are exact both ways); malformed text is an
// Error naming the line and the bad field.
#include <mollify/error.hpp>
#include <mollify/table_file.hpp>
#include <mollify/tables/catalogue.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <unistd.h>
#include <string>

namespace table = mollify::table;

namespace {

// Bits, not values: -0 against 0 and the low parts' signs matter.
std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

void expect_same_term(const table::Term& a, const table::Term& b, const std::string& where) {
    EXPECT_EQ(a.basis, b.basis) << where;
    EXPECT_EQ(a.s_power, b.s_power) << where;
    EXPECT_EQ(a.var, b.var) << where;
    EXPECT_EQ(bits(a.edge), bits(b.edge)) << where;
    EXPECT_EQ(bits(a.edge_lo), bits(b.edge_lo)) << where;
    EXPECT_EQ(a.edge_power, b.edge_power) << where;
    EXPECT_EQ(a.low, b.low) << where;
    EXPECT_EQ(bits(a.centre), bits(b.centre)) << where;
    EXPECT_EQ(bits(a.centre_lo), bits(b.centre_lo)) << where;
    ASSERT_EQ(a.n, b.n) << where;
    for (int k = 0; k < a.n; ++k) {
        EXPECT_EQ(bits(a.c[k]), bits(b.c[k])) << where << " c[" << k << "]";
        EXPECT_EQ(bits(a.c_lo ? a.c_lo[k] : 0.0), bits(b.c_lo ? b.c_lo[k] : 0.0)) << where << " c_lo[" << k << "]";
    }
}

void expect_same_table(const table::Kernel& a, const table::Kernel& b) {
    const std::string name = std::string(a.spec) + " D=" + std::to_string(a.dim);
    EXPECT_STREQ(a.spec, b.spec);
    EXPECT_EQ(a.dim, b.dim) << name;
    EXPECT_EQ(bits(a.support), bits(b.support)) << name;
    EXPECT_EQ(a.smoothness, b.smoothness) << name;
    EXPECT_EQ(a.order, b.order) << name;
    EXPECT_EQ(a.parity, b.parity) << name;
    EXPECT_EQ(bits(a.normalisation), bits(b.normalisation)) << name;
    EXPECT_STREQ(a.normalisation_exact, b.normalisation_exact) << name;
    EXPECT_EQ(a.has_potential, b.has_potential) << name;
    for (int q = 0; q < table::quantity_count; ++q) {
        const table::Quantity &qa = a.quantities[q], &qb = b.quantities[q];
        ASSERT_EQ(qa.npieces, qb.npieces) << name << " quantity " << q;
        for (int p = 0; p < qa.npieces; ++p) {
            const table::Piece &pa = qa.pieces[p], &pb = qb.pieces[p];
            const std::string where = name + " quantity " + std::to_string(q) + " piece " + std::to_string(p);
            EXPECT_EQ(bits(pa.lo), bits(pb.lo)) << where;
            EXPECT_EQ(bits(pa.hi), bits(pb.hi)) << where;
            ASSERT_EQ(pa.nterms, pb.nterms) << where;
            for (int t = 0; t < pa.nterms; ++t)
                expect_same_term(pa.terms[t], pb.terms[t], where + " term " + std::to_string(t));
        }
    }
}

// The message of the Error that reading `text` throws ("" if none).
std::string error_of(const std::string& text) {
    try {
        mollify::read_table(text, "t.table");
    } catch (const mollify::Error& e) {
        return e.what();
    }
    return "";
}

const std::string small = [] {
    for (const table::Kernel* t : mollify::tables::all_kernels)
        if (std::string(t->spec) == "poly6" && t->dim == 3) return mollify::write_table(*t);
    return std::string();
}();

}  // namespace

TEST(TableFile, EveryCatalogueTableRoundTripsBitForBit) {
    int tables = 0;
    for (const table::Kernel* t : mollify::tables::all_kernels) {
        const std::string text = mollify::write_table(*t, "test");
        const auto back = mollify::read_table(text, t->spec);
        expect_same_table(*t, *back);
        EXPECT_EQ(mollify::write_table(*back, "test"), text) << t->spec;
        ++tables;
    }
    EXPECT_GT(tables, 200);
}

TEST(TableFile, CommentsAndNotesAreIgnoredOnReading) {
    ASSERT_FALSE(small.empty());
    const table::Kernel* poly6 = nullptr;
    for (const table::Kernel* t : mollify::tables::all_kernels)
        if (std::string(t->spec) == "poly6" && t->dim == 3) poly6 = t;
    const std::string noted = mollify::write_table(*poly6, "line one\nline two",
                                                   [](int q, int p, int t, int k) {
                                                       return std::to_string(q) + "/" + std::to_string(p) + "/" +
                                                              std::to_string(t) + "/" + std::to_string(k);
                                                   });
    EXPECT_NE(noted.find("# line two\n"), std::string::npos);
    EXPECT_NE(noted.find("  # 0/0/0/0\n"), std::string::npos);
    expect_same_table(*poly6, *mollify::read_table(noted));
}

TEST(TableFile, MalformedTextNamesTheLineAndField) {
    ASSERT_FALSE(small.empty());
    EXPECT_NE(error_of("").find("t.table"), std::string::npos);
    EXPECT_NE(error_of("mollify-table 2\n").find("not a mollify table"), std::string::npos);
    // Truncated: every proper prefix ending at a line is an error, never a partial table.
    for (std::size_t end = small.find('\n'); end + 1 < small.size(); end = small.find('\n', end + 1))
        EXPECT_NE(error_of(small.substr(0, end + 1)), "") << "prefix of " << end + 1 << " bytes accepted";
    std::string bad = small;
    const std::size_t c = bad.find("\nc ") + 3;
    bad.replace(c, bad.find(' ', c) - c, "0x1.zzp+0");
    const std::string message = error_of(bad);
    EXPECT_NE(message.find("coefficient '0x1.zzp+0' is not a number"), std::string::npos) << message;
    EXPECT_NE(message.find("t.table:"), std::string::npos) << message;
    std::string basis = small;
    basis.replace(basis.find("term one"), 8, "term oops");
    EXPECT_NE(error_of(basis).find("unknown basis 'oops'"), std::string::npos);
    EXPECT_NE(error_of(small + "quantity value pieces 0\n").find("text after 'end'"), std::string::npos);
    std::string order = small;
    order.replace(order.find("quantity dr"), 11, "quantity d2r");
    EXPECT_NE(error_of(order).find("expected quantity 'dr'"), std::string::npos);
}

TEST(TableFile, FilesAreWrittenAtomicallyAndReadBack) {
    const auto dir = std::filesystem::temp_directory_path() / ("mollify-table-file-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    const auto path = dir / "sub" / "poly6_D3.table";
    mollify::write_file_atomically(path, small);
    mollify::write_file_atomically(path, small);  // replaces, leaves no temporary behind
    int files = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir / "sub")) ++files;
    EXPECT_EQ(files, 1);
    EXPECT_EQ(mollify::write_table(*mollify::read_table_file(path)), small);
    try {
        mollify::read_table_file(dir / "missing.table");
        ADD_FAILURE() << "no error for a missing file";
    } catch (const mollify::Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.table"), std::string::npos);
    }
    std::filesystem::remove_all(dir);
}
