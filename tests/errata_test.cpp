// The errata engine against the transcriptions of the three source
// documents: it must find the known printing errors, leave the correct
// tables alone, and reject malformed transcriptions with a useful message.
#include "errata.hpp"
#include "error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace {

using mollify::gen::check_errata;
using mollify::gen::Discrepancy;
using mollify::gen::ErrataReport;
using mollify::gen::format_line;

const ErrataReport& report() {
    static const ErrataReport r = check_errata(MOLLIFY_TRANSCRIPTIONS_DIR);
    return r;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Discrepancies whose `where` equals `where` (empty: any) and whose entry
// contains every one of `parts`.
std::vector<Discrepancy> found(const std::string& where, const std::vector<std::string>& parts) {
    std::vector<Discrepancy> out;
    for (const auto& d : report().discrepancies) {
        if (!where.empty() && d.where != where) continue;
        if (std::all_of(parts.begin(), parts.end(), [&](const std::string& p) { return contains(d.entry, p); }))
            out.push_back(d);
    }
    return out;
}

std::size_t count_where(const std::string& where) { return found(where, {}).size(); }

// --- the totals are pinned: any change in the engine or the core shows here

TEST(Errata, TotalsArePinned) {
    EXPECT_EQ(report().checked, 1443);
    EXPECT_EQ(report().discrepancies.size(), 314u);
}

TEST(Errata, DocumentLabels) {
    std::vector<std::string> docs;
    for (const auto& d : report().discrepancies)
        if (std::find(docs.begin(), docs.end(), d.document) == docs.end()) docs.push_back(d.document);
    EXPECT_EQ(docs, (std::vector<std::string>{"Anderson 2014 (seed 000)", "Belley 2007 (seed 002)", "Franz 2019 (seed 003)"}));
}

// --- Anderson (seed 000)

TEST(Errata, AndersonAlphaMisprints) {
    struct Case {
        const char* where;
        const char* entry;
        const char* printed;
        const char* exact;
    };
    for (const Case& c : {Case{"Table 3", "alpha_{0(1)}, order 4, M = 9", "23/20", "-23/20"},
                          Case{"Table 5", "alpha_{0(2)}, order 4, M = 1", "2", "-2"},
                          Case{"Table 6", "alpha_{1(2)}, order 6, M = 3", "4/5", "14/5"},
                          Case{"Table 7", "alpha_{0(3)}, order 4, M = 7", "21/16", "-21/16"}}) {
        const auto d = found(c.where, {c.entry});
        ASSERT_EQ(d.size(), 1u) << c.where << " " << c.entry;
        EXPECT_EQ(d[0].printed, c.printed);
        EXPECT_EQ(d[0].exact, c.exact);
    }
    EXPECT_EQ(found("Table 3", {}).size(), 1u);
    EXPECT_EQ(found("Table 5", {}).size(), 1u);
    EXPECT_EQ(found("Table 6", {}).size(), 1u);
    EXPECT_EQ(found("Table 7", {}).size(), 1u);
    EXPECT_EQ(found("Table 7", {})[0].remark, "sign differs");
}

TEST(Errata, AndersonCorrectTablesAreNotFlagged) {
    EXPECT_EQ(count_where("Table 1"), 0u);  // all 27 sigma
    EXPECT_EQ(count_where("Table 2"), 0u);  // all 18 c0, including -3/16 (D = 2, M = 1)
    EXPECT_EQ(count_where("Table 4"), 0u);
    EXPECT_EQ(count_where("Table 8"), 0u);
    EXPECT_EQ(count_where("§2"), 0u);                    // second moments
    EXPECT_EQ(count_where("§4, eqs. (13)/(14)"), 0u);    // the potentials themselves
    EXPECT_TRUE(found("Appendix B", {"B_delta"}).empty());  // the kernels
    EXPECT_TRUE(found("Appendix B", {"phi_delta, D = 2"}).empty());
    EXPECT_TRUE(found("Appendix B", {"phi_delta, D = 3", "coefficient"}).empty());
}

TEST(Errata, AndersonTheorem1FactorTwoIn1D) {
    const auto d = found("Theorem 1", {});
    ASSERT_EQ(d.size(), 9u);
    for (const auto& x : d) {
        EXPECT_TRUE(contains(x.entry, "sigma_{M(1)}")) << x.entry;
        EXPECT_TRUE(contains(x.remark, "omega_1 = 2")) << x.remark;
    }
    EXPECT_EQ(found("Theorem 1", {"M = 1"})[0].printed, "3/2");
    EXPECT_EQ(found("Theorem 1", {"M = 1"})[0].exact, "3/4");
}

TEST(Errata, AndersonRadiiCombinationArgumentConvention) {
    const auto eq9 = found("eq. (9)", {});
    ASSERT_EQ(eq9.size(), 1u);
    EXPECT_TRUE(contains(eq9[0].entry, "4/3 * B(1/2 r)"));
    EXPECT_TRUE(contains(eq9[0].remark, "B_{1/2}(r) = 2^N B(2 r)"));
    const auto eq10 = found("eq. (10)", {});
    ASSERT_EQ(eq10.size(), 2u);
    EXPECT_TRUE(found("eq. (10)", {"weight"}).empty());  // the weights themselves are right
}

TEST(Errata, AndersonGradientsOnePowerOfDeltaShort) {
    const auto d = found("", {"d phi_delta / d x_i", "power of delta"});
    EXPECT_EQ(d.size(), 22u);  // 18 in §4, 4 in Appendix B: every gradient formula
    for (const auto& x : d) EXPECT_TRUE(contains(x.remark, "printed delta^")) << x.remark;
    EXPECT_EQ(found("§4", {"d phi_delta / d x_i, D = 3, M = 1,", "power of delta"})[0].exact, "delta^-3");
}

TEST(Errata, AndersonAppendixBGradientCoefficient) {
    const auto d = found("Appendix B", {"D = 2, M = 4, fourth order", "coefficient of (r/delta)^6"});
    ASSERT_EQ(d.size(), 1u);
    EXPECT_TRUE(contains(d[0].remark, "bracket coefficient printed 5/8, exact 5/4")) << d[0].remark;
    // The other bracket coefficients of that formula are right.
    EXPECT_EQ(found("Appendix B", {"d phi_delta / d x_i", "coefficient"}).size(), 1u);
}

TEST(Errata, AndersonAppendixB3DAdditiveSign) {
    const auto d = found("Appendix B", {"additive term"});
    ASSERT_EQ(d.size(), 2u);  // second and fourth order, both D = 3
    for (const auto& x : d) {
        EXPECT_TRUE(contains(x.entry, "D = 3"));
        EXPECT_EQ(x.printed, "1/4 * pi^-1 * delta^-1");
        EXPECT_EQ(x.exact, "-1/4 * pi^-1 * delta^-1");
    }
}

TEST(Errata, AndersonHessians) {
    // x_i x_j part: delta^-2 short in both dimensions, all 18 formulas.
    const auto xx = found("§4", {"d^2 phi_delta", "x_i x_j term, power of delta"});
    EXPECT_EQ(xx.size(), 18u);
    EXPECT_TRUE(found("§4", {"d^2 phi_delta", "x_i x_j coefficient"}).empty());
    // 2D epsilon_ij sums: the printed (2 sigma k) divides each of the M + 1
    // coefficients by sigma = 2 (M + 1).
    const auto eps = found("§4", {"d^2 phi_delta / dx_j dx_i, D = 2", "epsilon_ij coefficient"});
    EXPECT_EQ(eps.size(), 54u);
    const auto m1 = found("§4", {"D = 2, M = 1,", "epsilon_ij coefficient of (r/delta)^0"});
    ASSERT_EQ(m1.size(), 1u);
    EXPECT_TRUE(contains(m1[0].remark, "printed/exact = 1/4"));
    EXPECT_TRUE(found("§4", {"d^2 phi_delta / dx_j dx_i, D = 3", "epsilon_ij"}).empty());
}

// --- Franz (seed 003)

TEST(Errata, FranzCorrectTablesAreNotFlagged) {
    EXPECT_EQ(count_where("Table 4.1"), 0u);
    EXPECT_EQ(count_where("Table 4.3"), 0u);
    EXPECT_EQ(count_where("Prop. 4.24 (equidistant closed form after Lemma 4.25)"), 0u);
    EXPECT_TRUE(found("Table 4.2", {"m = 4"}).empty());
    EXPECT_TRUE(found("Table 4.4", {"k = 1, l = 1, m = 4"}).empty());
    EXPECT_TRUE(found("Table 4.4", {"k = 3, l = 1, m = 4"}).empty());
}

// Thm. 4.38 prints binom(j-1, k) where Cor. 4.39 has binom((j-1)/2, k): the
// two agree for k = 1 only.
TEST(Errata, FranzTheorem438BinomialArgument) {
    for (int d = 1; d <= 3; ++d) {
        EXPECT_TRUE(found("Thm. 4.38", {"d = " + std::to_string(d) + ", k = 1,"}).empty()) << d;
        EXPECT_FALSE(found("Thm. 4.38", {"d = " + std::to_string(d) + ", k = 2,"}).empty()) << d;
        EXPECT_FALSE(found("Thm. 4.38", {"d = " + std::to_string(d) + ", k = 3,"}).empty()) << d;
    }
}

TEST(Errata, FranzMissingTermInTable44) {
    const auto d = found("Table 4.4", {"k = 2, l = 1, m = 4"});
    ASSERT_FALSE(d.empty());
    for (const auto& x : d) EXPECT_TRUE(contains(x.remark, "term -psi(r) = -(1 - r)_+^7 (16 r^2 + 7 r + 1) missing")) << x.remark;
}

TEST(Errata, FranzMissingWendlandCoefficients) {
    const auto t45 = found("Table 4.5", {});
    ASSERT_EQ(t45.size(), 1u);
    EXPECT_TRUE(contains(t45[0].entry, "psi_{2,2,1}") && contains(t45[0].entry, "S coefficient of r^2"));
    EXPECT_EQ(t45[0].printed, "-6888");
    EXPECT_EQ(t45[0].exact, "-688");
    const auto t46 = found("Table 4.6", {});
    ASSERT_EQ(t46.size(), 1u);
    EXPECT_TRUE(contains(t46[0].entry, "psi_{3,2,3}") && contains(t46[0].entry, "L coefficient of r^12"));
    EXPECT_EQ(t46[0].exact, "-315315");  // -45045 * 7: the bracket's r^12 coefficient is 7, not 1
}

TEST(Errata, FranzSixthOrderMiddleArgument) {
    // Phi = 1620 psi(3r) - 81 psi(2r) + 4 psi(r): the weights are those of the
    // radii 1/3, 2/3, 1, whose middle member is psi(3r/2), not psi(2r).
    for (const char* table : {"Table 4.2", "Table 4.4"}) {
        const auto w = found(table, {"Phi weights", "m = 6", "argument scale"});
        ASSERT_EQ(w.size(), 1u) << table;
        EXPECT_EQ(w[0].printed, "psi(2 r)");
        EXPECT_EQ(w[0].exact, "psi(3/2 r)");
        EXPECT_TRUE(found(table, {"Phi weights", "), weight"}).empty()) << table;  // weights are right
        for (const char* k : {"k = 1,", "k = 2,", "k = 3,"}) {
            const auto rows = found(table, {"Phi,", k, "m = 6"});
            ASSERT_FALSE(rows.empty()) << table << " " << k;
            EXPECT_TRUE(contains(rows[0].remark, "should be the radius-2/3 member")) << rows[0].remark;
        }
    }
}

// --- Belley (seed 002)

TEST(Errata, BelleyViscosity) {
    const auto d = found("Chapitre 1, §1.1 (unnumbered display)", {"viscosit"});
    ASSERT_EQ(d.size(), 3u);
    const auto form = found("", {"viscosit", "formula"});
    ASSERT_EQ(form.size(), 1u);
    EXPECT_TRUE(contains(form[0].remark, "differs in form"));
    EXPECT_TRUE(contains(form[0].remark, "-1/2 r h^-3"));
    EXPECT_TRUE(contains(form[0].exact, "-1/2 r^3 h^-3"));
    EXPECT_EQ(found("", {"viscosit", "absolute value"}).size(), 1u);
    const auto support = found("", {"viscosit", "support"});
    ASSERT_EQ(support.size(), 1u);
    EXPECT_EQ(support[0].printed, "-1 <= r <= 1");
}

TEST(Errata, BelleyEverythingElseIsRight) {
    std::size_t belley = 0;
    for (const auto& d : report().discrepancies)
        if (contains(d.document, "Belley")) ++belley;
    EXPECT_EQ(belley, 3u);  // poly6, spiky, moments (13)/(17)/(21), kernel values: all right
}

// --- format

TEST(Errata, FormatLine) {
    Discrepancy d{"Anderson 2014 (seed 000)", "Table 3", "alpha_{0(1)}, order 4, M = 9", "23/20", "-23/20", ""};
    EXPECT_EQ(format_line(d), "Anderson 2014 (seed 000) | Table 3 | alpha_{0(1)}, order 4, M = 9 | printed: 23/20 | exact: -23/20");
    d.remark = "sign differs";
    EXPECT_EQ(format_line(d),
              "Anderson 2014 (seed 000) | Table 3 | alpha_{0(1)}, order 4, M = 9 | printed: 23/20 | exact: -23/20 | sign differs");
}

// --- malformed transcriptions

class ScratchDir : public ::testing::Test {
protected:
    void SetUp() override {
        std::random_device rd;
        dir_ = std::filesystem::temp_directory_path() / ("mollify_errata_" + std::to_string(rd()) + std::to_string(rd()));
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
    // The message of the Error check_errata throws ("" if none).
    std::string error_message() {
        try {
            check_errata(dir_);
        } catch (const mollify::gen::Error& e) {
            return e.what();
        }
        return "";
    }
    static std::string file_with(const std::string& entry) {
        return R"({"document": "A. N. Author, Some Paper, 2001", "seed": "009_x.txt", "entries": [)" + entry + "]}";
    }
    std::filesystem::path dir_;
};

TEST_F(ScratchDir, EmptyDirectoryChecksNothing) {
    const ErrataReport r = check_errata(dir_);
    EXPECT_EQ(r.checked, 0);
    EXPECT_TRUE(r.discrepancies.empty());
}

TEST_F(ScratchDir, MissingDirectoryThrows) {
    EXPECT_THROW(check_errata(dir_ / "nope"), mollify::gen::Error);
}

TEST_F(ScratchDir, UnknownQuantityNamesFileAndEntry) {
    write("broken.json", file_with(R"({"where": "Table 9", "entry": "mystery value", "quantity": "anderson.mystery",
                                       "params": {}, "printed": "1"})"));
    const std::string m = error_message();
    EXPECT_TRUE(contains(m, "broken.json")) << m;
    EXPECT_TRUE(contains(m, "mystery value")) << m;
    EXPECT_TRUE(contains(m, "anderson.mystery")) << m;
}

TEST_F(ScratchDir, MissingFieldNamesFileAndEntry) {
    write("missing.json", file_with(R"({"where": "Table 1", "entry": "sigma without M", "quantity": "anderson.sigma",
                                        "params": {"D": 2}, "printed": "4"})"));
    const std::string m = error_message();
    EXPECT_TRUE(contains(m, "missing.json")) << m;
    EXPECT_TRUE(contains(m, "sigma without M")) << m;
    EXPECT_TRUE(contains(m, "params.M")) << m;
}

// Out-of-table parameters are a clear error, not a crash (order 0 used to
// build an empty system) nor a minutes-long computation (order 250).
TEST_F(ScratchDir, OutOfTableOrderIsAnError) {
    for (const char* order : {"0", "3", "250"}) {
        write("order.json", file_with(std::string(R"({"where": "Table 3", "entry": "gamma of order )") + order +
                                      R"(", "quantity": "anderson.gamma", "params": {"D": 1, "M": 2, "order": )" +
                                      order + R"(}, "printed": "1"})"));
        const std::string m = error_message();
        EXPECT_TRUE(contains(m, "order.json")) << m;
        EXPECT_TRUE(contains(m, std::string("order = ") + order)) << m;
    }
}

TEST_F(ScratchDir, BadNumberNamesFileAndEntry) {
    write("badnumber.json", file_with(R"({"where": "Table 1", "entry": "sigma typo", "quantity": "anderson.sigma",
                                          "params": {"D": 2, "M": 1}, "printed": "4//3"})"));
    const std::string m = error_message();
    EXPECT_TRUE(contains(m, "badnumber.json")) << m;
    EXPECT_TRUE(contains(m, "sigma typo")) << m;
    EXPECT_TRUE(contains(m, "4//3")) << m;
}

TEST_F(ScratchDir, SmallFileIsCheckedAndLabelled) {
    write("a.json", file_with(R"({"where": "Table 1", "entry": "sigma right", "quantity": "anderson.sigma",
                                  "params": {"D": 2, "M": 1}, "printed": "4"},
                                 {"where": "Table 1", "entry": "sigma wrong", "quantity": "anderson.sigma",
                                  "params": {"D": 3, "M": 1}, "printed": "15/4"})"));
    const ErrataReport r = check_errata(dir_);
    EXPECT_EQ(r.checked, 2);
    ASSERT_EQ(r.discrepancies.size(), 1u);
    EXPECT_EQ(format_line(r.discrepancies[0]),
              "Author 2001 (seed 009) | Table 1 | sigma wrong | printed: 15/4 | exact: 15/2 | printed/exact = 1/2");
}

}  // namespace
