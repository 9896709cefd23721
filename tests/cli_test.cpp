// mollify-gen as a user runs it: output formats, exit status 2 with a message
// naming the bad value (and nothing written), and the checked-in generated/
// reproduced byte for byte (CPython-style freshness check).
#include "command.hpp"
#include "sanitized.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

using mollify::testing::Outcome;
using mollify::testing::slurp;

fs::path scratch(const std::string& name) {
    const fs::path p = fs::temp_directory_path() / ("mollify-cli-test-" + std::to_string(::getpid()) + "-" + name);
    fs::remove_all(p);
    return p;
}

Outcome run(const std::string& args) { return mollify::testing::run_command(std::string(MOLLIFY_GEN) + " " + args, scratch("run")); }

std::vector<std::string> lines(const std::string& s) {
    std::vector<std::string> v;
    std::istringstream in(s);
    for (std::string l; std::getline(in, l);) v.push_back(l);
    return v;
}

std::vector<std::string> lines_matching(const std::string& text, const std::regex& re) {
    std::vector<std::string> out;
    for (const std::string& l : lines(text))
        if (std::regex_match(l, re)) out.push_back(l);
    return out;
}

std::vector<fs::path> tree(const fs::path& root) {
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(root))
        if (e.is_regular_file()) files.push_back(fs::relative(e.path(), root));
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace

TEST(Cli, ValueWithExactForm) {
    const Outcome r = run("value mollifier:M=4 --dim 3 --r 0 --exact");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto l = lines(r.out);
    ASSERT_EQ(l.size(), 2u);
    EXPECT_EQ(l[1], "3465/512 * pi^-1");  // sigma_{4(3)}/(4 pi): 1/sigma = int_0^1 r^2 (1-r^2)^4 dr = 128/3465
    EXPECT_EQ(l[0].size(), std::string("2.154241757548453925530262745233211013680e+00").size());  // 40 digits
    EXPECT_NEAR(std::stod(l[0]), 3465.0 / 512.0 / M_PI, 1e-15);
}

TEST(Cli, DecimalAndRationalRadiiAgree) {
    const Outcome a = run("value wendland:k=2,l=1 --dim 2 --r 0.25 --digits 30");
    const Outcome b = run("value wendland:k=2,l=1 --dim 2 --r 1/4 --digits 30");
    ASSERT_EQ(a.status, 0) << a.err;
    EXPECT_EQ(a.out, b.out);
    EXPECT_EQ(lines(a.out)[0].size(), std::string("1.23456789012345678901234567890e+00").size());
}

// Every --digits the command accepts (1..100000) is delivered: the Ziv loop
// had stopped at 2^16 bits, so past ~16,000 digits an irrational value (here
// with 1/pi, and a missing Wendland function's square root and logarithm)
// failed as "internal". The long decimal starts with the 40-digit one's first
// 39 digits (its 40th is rounded; no carry runs back here: checked by hand).
TEST(Cli, ValueDeliversEveryDigitsItAccepts) {
    for (const std::string query : {"value wendland:k=2 --dim 3 --r 1/2 --quantity potential",
                                    "value wendland-missing:k=1,l=1 --dim 2 --r 1/2"}) {
        const Outcome short_one = run(query + " --digits 40");
        const Outcome long_one = run(query + " --digits 100000");
        ASSERT_EQ(long_one.status, 0) << query << ": " << long_one.err;
        const std::string s = lines(short_one.out)[0], l = lines(long_one.out)[0];
        const std::size_t mantissa = l.find('e');
        ASSERT_NE(mantissa, std::string::npos) << query;
        EXPECT_EQ(mantissa, 100000u + 1 + (l[0] == '-')) << query;  // the digits and the point
        EXPECT_EQ(l.substr(mantissa), s.substr(s.find('e'))) << query;
        EXPECT_EQ(l.substr(0, s.find('e') - 1), s.substr(0, s.find('e') - 1)) << query;  // all but the 40th digit
    }
}

TEST(Cli, PotentialOutsideTheSupportIsTheGreensFunction) {
    const Outcome r = run("value mollifier:M=4 --dim 2 --r 2 --quantity potential --exact");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(lines(r.out)[1], "1/2 * pi^-1 * log(2)");
    const Outcome r3 = run("value wendland:k=2 --dim 3 --r 4 --quantity potential --exact");
    EXPECT_EQ(lines(r3.out)[1], "-1/16 * pi^-1");  // -1/(4 pi r) at r = 4
}

TEST(Cli, MissingWendlandValueHasAClosedForm) {
    const Outcome r = run("value wendland-missing:k=1,l=1 --dim 2 --r 1/2 --digits 25 --exact");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto l = lines(r.out);
    ASSERT_EQ(l.size(), 2u);
    EXPECT_NE(l[1].find("sqrt(3/4)"), std::string::npos) << l[1];
    EXPECT_NE(l[1].find("log((1 + sqrt(3/4)) / (1/2))"), std::string::npos) << l[1];
}

TEST(Cli, Weights) {
    const Outcome r = run("weights --radii 1/3,2/3,1");
    ASSERT_EQ(r.status, 0) << r.err;
    // Franz Prop. 4.24: w_1 = (4/9)/(4/9-1/9) * 1/(1-1/9) = 3/2, w_2 = -3/5, w_3 = 1/10.
    EXPECT_EQ(r.out, "3/2\n-3/5\n1/10\n");
}

TEST(Cli, Errata) {
    const Outcome r = run("errata");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto l = lines(r.out);
    ASSERT_FALSE(l.empty());
    EXPECT_TRUE(std::regex_match(l.back(), std::regex("checked [0-9]+ entries, [0-9]+ discrepancies"))) << l.back();
    for (std::size_t i = 0; i + 1 < l.size(); ++i)
        EXPECT_TRUE(std::regex_search(l[i], std::regex("^[^|]+ \\| [^|]+ \\| [^|]+ \\| printed: .* \\| exact: .*")))
            << l[i];
}

TEST(Cli, ErrataOfCodes) {
    const Outcome r = run("errata --codes");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto l = lines(r.out);
    ASSERT_FALSE(l.empty());
    EXPECT_TRUE(std::regex_match(l.back(), std::regex("checked [0-9]+ published constants of codes, [0-9]+ wrong"))) << l.back();
    for (std::size_t i = 0; i + 1 < l.size(); ++i)
        EXPECT_TRUE(std::regex_search(
            l[i], std::regex("^[^|]+ \\| [^|]+ \\| [^|]+ \\| published: .* \\| exact: .* \\| published/exact: .* \\| .+$")))
            << l[i];
    // A malformed transcription: exit 2, the file, entry and field named.
    const fs::path dir = scratch("codes");
    fs::create_directories(dir / "codes");
    std::ofstream(dir / "codes" / "bad.json")
        << R"({"code": "X", "repository": "x/x", "entries": [{"entry": "e1", "quantity": "code.normalisation",)"
           R"( "file": "k.c", "seen": true, "expression": "e", "says": "s", "params": {"spec": "poly6", "dim": 3}}]})";
    const Outcome bad = run("errata --codes --transcriptions " + dir.string());
    EXPECT_EQ(bad.status, 2);
    EXPECT_TRUE(bad.err.find("bad.json, entry 'e1' (k.c): missing field 'params.support'") != std::string::npos) << bad.err;
    fs::remove_all(dir);
}

TEST(Cli, BadArgumentsExitWithStatus2NamingTheValue) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"value gaussian --dim 3 --r 0", "gaussian"},
        {"value wendland:k=2 --dim 4 --r 0", "dimension 4"},
        {"value wendland:k=2 --dim 3 --r -1", "-1"},
        {"value wendland:k=2 --dim 3 --r abc", "abc"},
        {"value wendland:k=2 --dim 3 --r 0 --quantity hessian", "hessian"},
        {"value wendland:k=2 --dim 3 --r 0 --digits 0", "--digits 0"},
        {"value spiky --dim 3 --r 0 --quantity grad_over_r", "singular at r = 0"},
        {"value box-d1 --dim 1 --r 0 --quantity potential", "no Poisson potential"},
        {"value viscosity --dim 1 --r 1/2", "dimension 1"},
        {"weights --radii 1/2,1/2", "1/2"},
        {"weights --radii 0,1", "radius 0"},
        {"value wendland:k=2 --r 0", "--dim"},
        {"frobnicate", "frobnicate"},
        {"emit --format xml --out /nonexistent/mollify-cli-test", "--format xml"},
    };
    for (const auto& [args, named] : cases) {
        const Outcome r = run(args);
        EXPECT_EQ(r.status, 2) << args;
        EXPECT_NE(r.err.find(named), std::string::npos) << args << " -> " << r.err;
        EXPECT_TRUE(r.out.empty()) << args;
    }
}

TEST(Cli, BadEmitWritesNothing) {
    const fs::path out = scratch("bad-emit");
    const Outcome r = run("emit --out " + out.string() + " --only wendland:k=2 --only wendland:k=99");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("k=99"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    // A kernel that no dimension left takes (these had written no kernel and exited 0), and a step
    // kernel for Phantom (0/0 in its av_factor had been named as "a zero denominator" alone).
    const std::vector<std::pair<std::string, std::string>> cases = {
        {" --only viscosity --dim 1", "--only viscosity exists in D = 2, 3, but --dim asks for D = 1: nothing to emit"},
        {" --only wendland:k=2 --target phantom --dim 2",
         "--only wendland:k=2 exists in D = 1, 2, 3, but --dim asks for D = 2 and --target phantom takes D = 3: nothing to emit"},
        {" --only box --target phantom", "box has w' = 0 inside its support (a step kernel)"},
    };
    for (const auto& [args, named] : cases) {
        const Outcome bad = run("emit --out " + out.string() + args);
        EXPECT_EQ(bad.status, 2) << args;
        EXPECT_NE(bad.err.find(named), std::string::npos) << args << " -> " << bad.err;
        EXPECT_FALSE(fs::exists(out)) << args;
    }
}

TEST(Cli, EmitOnlyNamesItsCommandInTheBanner) {
    const fs::path out = scratch("only");
    const Outcome r = run("emit --out " + out.string() + " --only wendland:l=1,k=2");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string h = slurp(out / "mollify/tables/wendland/k_2_l_1_D3.hpp");
    EXPECT_NE(h.find("with: mollify-gen emit --only wendland:k=2,l=1\n"), std::string::npos);
    EXPECT_NE(h.find("wendland_k_2_l_1_D3"), std::string::npos);
    EXPECT_EQ(h.find(out.string()), std::string::npos);  // no paths in generated files
    fs::remove_all(out);
}

// One header per kernel and dimension, named by the rule of emit.cpp's
// kernel_header, each including only table.hpp; the list of all kernels
// declared in catalogue.hpp (no table) and defined in src/catalogue.cpp.
TEST(Cli, EmitWritesOneHeaderPerKernelAndDimension) {
    const fs::path out = scratch("per-kernel");
    // Under the sanitizers without the missing Wendland function (28 s at -O0 +
    // ASan; EveryFamilyEmitsAsCheckedInUnderSanitizers emits one).
    const std::string missing = mollify::testing::sanitized_build ? "" : " --only wendland-missing:k=1";
    const Outcome r = run("emit --out " + out.string() + " --only wendland:k=2" + missing +
                          " --only combo:m=3,base=wendland:k=2 --only mollifier:M=4,order=4 --only box-d1");
    ASSERT_EQ(r.status, 0) << r.err;
    std::vector<fs::path> want = {
        "catalogue.json",
        "mollify/constants/cot_series.hpp",
        "mollify/constants/log_two.hpp",
        "mollify/tables/catalogue.hpp",
        "mollify/tables/classic/box_d1_D1.hpp",
        "mollify/tables/combo/m_3_base_wendland_k_2_D1.hpp",
        "mollify/tables/combo/m_3_base_wendland_k_2_D2.hpp",
        "mollify/tables/combo/m_3_base_wendland_k_2_D3.hpp",
        "mollify/tables/mollifier/M_4_order_4_D1.hpp",
        "mollify/tables/mollifier/M_4_order_4_D2.hpp",
        "mollify/tables/mollifier/M_4_order_4_D3.hpp",
        "mollify/tables/wendland/k_2_D1.hpp",
        "mollify/tables/wendland/k_2_D2.hpp",
        "mollify/tables/wendland/k_2_D3.hpp",
        "mollify/tables/wendland_missing/k_1_D1.hpp",
        "mollify/tables/wendland_missing/k_1_D2.hpp",
        "mollify/tables/wendland_missing/k_1_D3.hpp",
        "src/catalogue.cpp",
        "src/term_shapes.def",
    };
    if (mollify::testing::sanitized_build)
        std::erase_if(want, [](const fs::path& p) { return p.string().find("wendland_missing") != std::string::npos; });
    EXPECT_EQ(tree(out), want);
    // The fused loops' shapes of these kernels: W of Wendland C4 (with low
    // parts: h^-3 scaled) is one term (1 - q)^6 p(q), p of degree 2, a whole
    // quantity; the combination's W has terms at the interior edges a_j.
    // Both split (table::Term::split: integer coefficients, exact Horner).
    const std::string shapes = slurp(out / "src/term_shapes.def");
    EXPECT_NE(shapes.find("MOLLIFY_WHOLE_SHAPE(true, true, false, 3, 6, 1, 0)\n"), std::string::npos) << shapes;
    EXPECT_NE(shapes.find("MOLLIFY_TERM_SHAPE(true, false, false, 3, 6, 1, 0)\n"), std::string::npos) << shapes;
    // Its distinct terms keep their grids (the table's split: 24, 23, 23
    // bits), so that the run-time form's loop computes the grid of 2^-23 once.
    EXPECT_NE(shapes.find("MOLLIFY_SHARED_TERMS(3, {true, false, false, 3, 6, 24, 0}, {true, false, false, 3, 6, 23, 0}, "
                          "{true, true, false, 3, 6, 23, 0})\n"),
              std::string::npos)
        << shapes;
    // No kernel here has pieces of one term each (the cubic spline's: below).
    EXPECT_TRUE(lines_matching(shapes, std::regex("^MOLLIFY_PIECES.*")).empty()) << shapes;
    const std::string h = slurp(out / "mollify/tables/combo/m_3_base_wendland_k_2_D3.hpp");
    EXPECT_NE(h.find("inline constexpr table::Kernel combo_m_3_base_wendland_k_2_D3 = {"), std::string::npos);
    EXPECT_EQ(lines_matching(h, std::regex("^#include .*")), std::vector<std::string>{"#include <mollify/table.hpp>"});
    const std::string index = slurp(out / "mollify/tables/catalogue.hpp");
    EXPECT_EQ(lines_matching(index, std::regex("^#include <mollify/.*")),
              std::vector<std::string>{"#include <mollify/table.hpp>"});
    EXPECT_NE(index.find("extern const std::span<const table::Kernel* const> all_kernels;"), std::string::npos);
    const std::string source = slurp(out / "src/catalogue.cpp");
    // Every kernel's header: not catalogue.json, cot_series.hpp, log_two.hpp, catalogue.hpp, term_shapes.def.
    EXPECT_EQ(lines_matching(source, std::regex("^#include <mollify/tables/.*")).size(), want.size() - 5);
    // Catalogue order: the --only order, dimensions 1..3.
    const auto first = source.find("&wendland_k_2_D1,"), last = source.find("&box_d1_D1,");
    EXPECT_NE(first, std::string::npos);
    EXPECT_NE(last, std::string::npos);
    EXPECT_LT(first, last);
    fs::remove_all(out);
}

// Regenerating leaves unchanged files alone (their timestamps too, so that
// a build after `mollify-gen emit` rebuilds nothing) and rewrites a changed
// or missing one.
// The cubic spline's W and W'/r are two pieces of one term each, at the
// same breakpoint 1/2: listed as pieces (the run-time form's one-pass pair
// loop), W'/r's outer term (1 - q)^2 q^-1 with its power of q (low -1,
// fusable since its piece starts at 1/2); in 1D no pair of them (the 1D
// pair loop takes the sign of x).
TEST(Cli, EmitListsTheCubicSplinesPieces) {
    const fs::path out = scratch("pieces");
    const Outcome r = run("emit --out " + out.string() + " --only cubic-spline");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string shapes = slurp(out / "src/term_shapes.def");
    EXPECT_NE(shapes.find("MOLLIFY_TERM_SHAPE(true, true, false, 1, 2, 0, -1)\n"), std::string::npos) << shapes;
    EXPECT_NE(shapes.find("MOLLIFY_PIECES(2, {true, false, false, 4, 0, 0, 0}, {true, true, false, 1, 3, 0, 0})\n"),
              std::string::npos)
        << shapes;
    EXPECT_NE(shapes.find("MOLLIFY_PIECES(2, {true, false, false, 2, 0, 0, 0}, {true, true, false, 1, 2, 0, -1})\n"),
              std::string::npos)
        << shapes;
    EXPECT_EQ(lines_matching(shapes, std::regex("^MOLLIFY_PIECES_PAIR.*")).size(), 1u) << shapes;
    fs::remove_all(out);
}

TEST(Cli, EmitRewritesOnlyChangedFiles) {
    const fs::path out = scratch("unchanged");
    const std::string emit = "emit --out " + out.string() + " --only wendland:k=1";
    ASSERT_EQ(run(emit).status, 0);
    const auto files = tree(out);
    ASSERT_FALSE(files.empty());
    // An old timestamp, far from any the emit could write (file systems
    // with coarse timestamps could not tell two close ones apart).
    const auto old = fs::file_time_type::clock::now() - std::chrono::hours(24 * 365);
    for (const auto& f : files) fs::last_write_time(out / f, old);
    const fs::path changed = out / "mollify/tables/wendland/k_1_D2.hpp", removed = out / "src/catalogue.cpp";
    const std::string want_changed = slurp(changed), want_removed = slurp(removed);
    { std::ofstream(changed, std::ios::app) << "// edited\n"; }
    fs::last_write_time(changed, old);
    fs::remove(removed);
    ASSERT_EQ(run(emit).status, 0);
    EXPECT_EQ(tree(out), files);  // no temporary files left behind
    for (const auto& f : files) {
        if (out / f == changed || out / f == removed) continue;
        EXPECT_TRUE(fs::last_write_time(out / f) == old) << f << " was rewritten with the same content";
    }
    EXPECT_EQ(slurp(changed), want_changed);
    EXPECT_TRUE(fs::last_write_time(changed) != old);
    EXPECT_EQ(slurp(removed), want_removed);
    fs::remove_all(out);
}

// CPython-style: regenerate, then fail on any difference from the checked-in tables.
#ifdef MOLLIFY_SANITIZED_BUILD
// Under ASan + UBSan the whole catalogue takes ~2.5 minutes at -O0 (a tenth
// of CI): one kernel of every family instead, through every stage of the
// generator (closed forms, missing Wendland series, Vandermonde weights,
// potentials, every certificate, emission), byte for byte the checked-in
// headers (written by an earlier, unsanitized run: so also deterministic).
// Freshness of the whole catalogue is the optimised build's test below.
TEST(Cli, EveryFamilyEmitsAsCheckedInUnderSanitizers) {
    const fs::path a = scratch("families");
    const std::string only =
        " --only mollifier:M=4 --only mollifier:M=4,order=4 --only wendland:k=2,l=1 --only wendland-missing:k=1,l=1"
        " --only combo:m=3,base=wendland:k=2 --only poly6 --only spiky --only viscosity --only cubic-spline"
        " --only box --only box-d1 --only box-d2";
    // --search-choices: the series pieces searched, not taken from their
    // compiled-in choices (search_choices.hpp), so the searches run instrumented.
    const fs::path choices = scratch("families-choices.def");
    const Outcome r = run("emit --out " + a.string() + only + " --search-choices " + choices.string());
    ASSERT_EQ(r.status, 0) << r.err;
    fs::remove(choices);
    const auto files = tree(a);
    // 31 kernel headers (viscosity: D = 2, 3; box-d1, box-d2: D = 1), the two catalogue files, catalogue.json,
    // term_shapes.def, constants/cot_series.hpp and log_two.hpp
    EXPECT_EQ(files.size(), 37u);
    const fs::path checked_in = MOLLIFY_GENERATED_DIR;
    int headers = 0;
    for (const auto& f : files) {
        if (f.extension() != ".hpp" || f.filename() == "catalogue.hpp") continue;  // the catalogue lists only these kernels
        headers += f.string().starts_with("mollify/tables/") ? 1 : 0;
        // All but the banner's first line, which names the command (here with --only).
        auto body = [](const std::string& text) { return text.substr(std::min(text.find('\n'), text.size())); };
        EXPECT_TRUE(body(slurp(a / f)) == body(slurp(checked_in / f))) << f << " differs from generated/" << f.string();
    }
    EXPECT_EQ(headers, 31);
    fs::remove_all(a);
}
#else
// One emit, compared byte for byte with generated/: the checked-in files
// were written by an earlier run of the same generator, so equality also
// shows the output does not depend on the run (thread scheduling, addresses);
// a second emit here would cost a whole catalogue (~50 s in CI) to show it
// again.
TEST(Cli, GeneratedTablesAreFreshAndDeterministic) {
    const fs::path a = scratch("fresh");
    ASSERT_EQ(run("emit --out " + a.string()).status, 0);
    const fs::path checked_in = MOLLIFY_GENERATED_DIR;
    const auto files = tree(a);
    EXPECT_EQ(files, tree(checked_in)) << "generated/ holds files mollify-gen emit does not write, or misses some";
    for (const auto& f : files)
        EXPECT_TRUE(slurp(a / f) == slurp(checked_in / f))
            << "generated/" << f.string() << " is stale (or the emit is not deterministic): run `mollify-gen emit --out "
               "generated` twice, compare, and commit";
    fs::remove_all(a);
}

// The series pieces' choices compiled into mollify-gen (search_choices.hpp)
// are the searches': searched afresh, every search chooses as the checked-in
// file says, and the tables are the checked-in ones (the test above emits
// them from the compiled-in choices).
TEST(Cli, SearchChoicesAreTheSearches) {
    const fs::path a = scratch("choices");
    const fs::path choices = a / "search_choices.def";
    ASSERT_EQ(run("emit --out " + a.string() + " --search-choices " + choices.string()).status, 0);
    EXPECT_TRUE(slurp(choices) == slurp(MOLLIFY_SEARCH_CHOICES))
        << "generator/search_choices.def is stale: run `mollify-gen emit --search-choices "
           "generator/search_choices.def`, rebuild mollify-gen, emit, and commit";
    fs::remove(choices);
    const fs::path checked_in = MOLLIFY_GENERATED_DIR;
    for (const auto& f : tree(a))
        EXPECT_TRUE(slurp(a / f) == slurp(checked_in / f)) << "searched afresh, generated/" << f.string() << " differs";
    fs::remove_all(a);
}
#endif
