// The kernel-spec grammar: canonical spellings, and every malformed or
// out-of-range spec rejected with a message naming the bad part.
#include "error.hpp"
#include "kernel.hpp"
#include "spec.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace mollify::gen;

namespace {

std::string canonical(const std::string& text) { return spec_string(parse_spec(text)); }

std::string error_of(const std::string& text) {
    try {
        parse_spec(text);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(Spec, CanonicalSpellings) {
    EXPECT_EQ(canonical("mollifier:M=4"), "mollifier:M=4");
    EXPECT_EQ(canonical("mollifier:order=2,M=4"), "mollifier:M=4");
    EXPECT_EQ(canonical("mollifier:order=4,M=4"), "mollifier:M=4,order=4");
    EXPECT_EQ(canonical("wendland:k=2"), "wendland:k=2");
    EXPECT_EQ(canonical("wendland:l=0,k=2"), "wendland:k=2");
    EXPECT_EQ(canonical("wendland:k=2,l=1"), "wendland:k=2,l=1");
    EXPECT_EQ(canonical("wendland-missing:k=1,l=1"), "wendland-missing:k=1,l=1");
    EXPECT_EQ(canonical("combo:m=3,base=wendland:k=2,l=1"), "combo:m=3,base=wendland:k=2,l=1");
    // Radii that are equidistant j/m are the m form; order of radii is irrelevant.
    EXPECT_EQ(canonical("combo:radii=1/3;2/3;1,base=mollifier:M=4"), "combo:m=3,base=mollifier:M=4");
    EXPECT_EQ(canonical("combo:radii=1;0.5,base=poly6"), "combo:m=2,base=poly6");
    EXPECT_EQ(canonical("combo:radii=1/7;3/10;1,base=poly6"), "combo:radii=1/7;3/10;1,base=poly6");
    for (const char* c :
         {"poly6", "spiky", "viscosity", "cubic-spline", "quartic-spline", "quintic-spline", "box", "box-d1", "box-d2"})
        EXPECT_EQ(canonical(c), c);
}

TEST(Spec, BadSpecsAreRejectedNamingTheValue) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"gaussian", "unknown kernel 'gaussian'"},
        {"", "malformed"},
        {"mollifier", "needs M="},
        {"mollifier:M=0", "M=0 is out of range"},
        {"mollifier:M=65", "M=65 is out of range"},
        {"mollifier:M=2.5", "M=2.5 is out of range"},
        {"mollifier:M=x", "'x' is not a number"},
        {"mollifier:M=4,order=3", "order=3 must be even"},
        {"mollifier:M=4,order=0", "order=0 is out of range"},
        {"mollifier:M=4,M=5", "parameter M given twice"},
        {"mollifier:M=4,k=2", "unknown parameter 'k'"},
        {"wendland:k=-1", "k=-1 is out of range"},
        {"wendland:k=2,l=13", "l=13 is out of range"},
        {"wendland", "needs k="},
        {"poly6:M=3", "unknown parameter 'M'"},
        {"combo:m=3", "needs base="},
        {"combo:base=poly6", "needs m=... or radii="},
        {"combo:m=2,radii=1/2;1,base=poly6", "either m= or radii="},
        {"combo:m=0,base=poly6", "m=0 is out of range"},
        {"combo:radii=1/2;1/2;1,base=poly6", "distinct"},
        {"combo:radii=1/2;3/4,base=poly6", "largest radius must be 1"},
        {"combo:radii=0;1,base=poly6", "radius 0 is outside (0, 1]"},
        {"combo:radii=1/2;3/2,base=poly6", "radius 3/2 is outside (0, 1]"},
        {"combo:radii=1/0;1,base=poly6", "zero denominator"},
        {"combo:m=2,base=combo:m=2,base=poly6", "cannot be a combo"},
        {"combo:m=2,base=wendland-missing:k=1", "not supported in combinations"},
        {"combo:m=2,base=box-d1", "not supported in combinations"},
        {"combo:m=2,base=nothing", "unknown kernel 'nothing'"},
        {"wendland:k=2,base=poly6", "takes no base="},
        {"wendland:k=2,", "malformed"},
        {"wendland k=2", "malformed"},
    };
    for (const auto& [spec, expected] : cases) {
        const std::string message = error_of(spec);
        EXPECT_NE(message.find(expected), std::string::npos) << "spec '" << spec << "' gave: '" << message << "'";
    }
}

TEST(Spec, DimensionsOutsideTheKernelsDomainAreErrors) {
    EXPECT_THROW(make_kernel(parse_spec("wendland:k=2"), 0), Error);
    EXPECT_THROW(make_kernel(parse_spec("wendland:k=2"), 4), Error);
    EXPECT_THROW(make_kernel(parse_spec("viscosity"), 1), Error);
    EXPECT_THROW(make_kernel(parse_spec("box-d1"), 2), Error);
    EXPECT_THROW(make_kernel(parse_spec("box-d2"), 3), Error);
    EXPECT_NO_THROW(make_kernel(parse_spec("box-d2"), 1));
}

TEST(Numbers, RationalAndDecimalInputs) {
    EXPECT_EQ(parse_rational("3/4", "x"), Q(3, 4));
    EXPECT_EQ(parse_rational("-6/8", "x"), Q(-3, 4));
    EXPECT_EQ(parse_rational("0.125", "x"), Q(1, 8));
    EXPECT_EQ(parse_rational(".5", "x"), Q(1, 2));
    EXPECT_EQ(parse_rational("1e-3", "x"), Q(1, 1000));
    EXPECT_EQ(parse_rational("2.5E+2", "x"), Q(250));
    EXPECT_EQ(parse_rational("7", "x"), Q(7));
    // Leading zeros are decimal, never octal.
    EXPECT_EQ(parse_rational("010", "x"), Q(10));
    EXPECT_EQ(parse_rational("08/010", "x"), Q(4, 5));
    EXPECT_EQ(parse_rational("-007.50", "x"), Q(-15, 2));
    for (const char* bad : {"", "1/", "/2", "1.2.3", "e5", "1e", "--1", "0x10", "1 /2", "nan", "inf"})
        EXPECT_THROW(parse_rational(bad, "x"), Error) << bad;
    // mollify-gen value --r: a double exactly, where its shortest decimal is another rational
    EXPECT_EQ(parse_rational_or_hex_float("0x1.8p-2", "x"), Q(3, 8));
    EXPECT_EQ(parse_rational_or_hex_float("-0x1p+0", "x"), Q(-1));
    EXPECT_EQ(parse_rational_or_hex_float("0x1p-1074", "x"), mollify::gen::pow(Q(2), -1074));
    EXPECT_EQ(parse_rational_or_hex_float("0x1.4cccccccccccdp-2", "x"),
              Q(Z("5854679515581645"), Z("18014398509481984")));  // the double 0.325, not 13/40
    EXPECT_NE(parse_rational_or_hex_float("0x1.4cccccccccccdp-2", "x"), parse_rational_or_hex_float("0.325", "x"));
    EXPECT_EQ(parse_rational_or_hex_float("3/4", "x"), Q(3, 4));
    for (const char* bad : {"0x", "0x1.8", "0x1p", "0xzz", "0x1p99999", "0x1p-2junk", "-0x", "0x-1p3", "0x1p-99999"})
        EXPECT_THROW(parse_rational_or_hex_float(bad, "x"), Error) << bad;
    // The grammar's hex-floats (mollify::hex_float, which mollify verify --samples reads too):
    // no prefix, not meant as one; malformed, NaN; beyond the doubles, inf.
    EXPECT_FALSE(mollify::hex_float("0.5").has_value());
    EXPECT_FALSE(mollify::hex_float("x1p0").has_value());
    EXPECT_EQ(*mollify::hex_float("+0X1.8P+1"), 3.0);
    EXPECT_EQ(*mollify::hex_float("-0x.8p0"), -0.5);
    EXPECT_EQ(*mollify::hex_float("0x1p-1074"), 0x1p-1074);
    for (const char* bad : {"0x", "0x1.8", "0x1p", "0x-1p3", "0x+1p3", "0x1p3 ", "-0x"})
        EXPECT_TRUE(std::isnan(*mollify::hex_float(bad))) << bad;
    EXPECT_EQ(*mollify::hex_float("-0x1p99999"), -std::numeric_limits<double>::infinity());
}

// Random junk built from the grammar's own characters: every input either
// parses to a spec whose canonical spelling parses back to itself, or is
// rejected with mollify's Error — never another exception or a crash.
TEST(Spec, RandomInputsParseOrFailCleanly) {
    const std::string alphabet = "mollifierwendlandcombospikypolyboxdM=kl,;:/.-0123456789e+ ";
    const std::vector<std::string> seeds = {"mollifier:M=", "wendland:k=", "combo:m=", "combo:radii=", ",base=",
                                            ",order=", ",l=", "wendland-missing:k="};
    std::mt19937 rng(20261121);  // fixed seed: reproducible
    int parsed = 0;
    for (int i = 0; i < 20000; ++i) {
        std::string text;
        const int pieces = 1 + static_cast<int>(rng() % 5);
        for (int p = 0; p < pieces; ++p) {
            if (rng() % 2) text += seeds[rng() % seeds.size()];
            const int n = static_cast<int>(rng() % 4);
            for (int c = 0; c < n; ++c) text += alphabet[rng() % alphabet.size()];
        }
        try {
            const Spec s = parse_spec(text);
            EXPECT_EQ(spec_string(parse_spec(spec_string(s))), spec_string(s)) << text;
            ++parsed;
        } catch (const Error&) {
        } catch (const std::exception& e) {
            ADD_FAILURE() << "'" << text << "' threw a non-mollify exception: " << e.what();
        }
    }
    EXPECT_GT(parsed, 10);  // the generator does reach valid specs
}
