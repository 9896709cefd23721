// The one kernel-spec grammar as the runtime uses it: header-only, without
// GMP (this test links neither GMP nor the exact core), finding emitted
// tables by the canonical spelling of whatever spelling a user wrote.
#include <mollify/spec.hpp>
#include <mollify/tables/catalogue.hpp>

#include <gtest/gtest.h>

#include <string>

namespace {

const mollify::table::Kernel* find(const std::string& user_spec, int dim) {
    const std::string key = mollify::spec_string(mollify::parse_spec(user_spec));
    for (const auto* k : mollify::tables::all_kernels)
        if (k->dim == dim && key == k->spec) return k;
    return nullptr;
}

}  // namespace

TEST(SpecRuntime, UserSpellingsFindTheEmittedTables) {
    EXPECT_NE(find("wendland:l=1,k=2", 3), nullptr);
    EXPECT_NE(find("combo:radii=1;1/3;2/3,base=mollifier:M=4", 2), nullptr);  // = combo:m=3
    EXPECT_NE(find("combo:radii=0.5;1,base=wendland:k=1,l=2", 1), nullptr);
    EXPECT_NE(find("mollifier:order=6,M=09", 3), nullptr);  // leading zero is decimal
    EXPECT_EQ(find("viscosity", 1), nullptr);                // not defined in 1D, so not emitted
    EXPECT_EQ(find("wendland:k=7", 3), nullptr);             // valid, not in the default catalogue
}

TEST(SpecRuntime, RatiosAreExact) {
    using mollify::parse_ratio;
    using mollify::Ratio;
    EXPECT_EQ(parse_ratio("0.125", "x"), (Ratio{1, 8}));
    EXPECT_EQ(parse_ratio("-6/8", "x"), (Ratio{-3, 4}));
    EXPECT_EQ(parse_ratio("25e-2", "x"), (Ratio{1, 4}));
    EXPECT_EQ(parse_ratio("1e18", "x"), (Ratio{1000000000000000000, 1}));
    EXPECT_EQ(parse_ratio("007", "x"), (Ratio{7, 1}));
    for (const char* too_big : {"1e19", "99999999999999999999", "1/99999999999999999999", "0.0000000000000000000001"})
        EXPECT_THROW(parse_ratio(too_big, "x"), mollify::Error) << too_big;
    for (const char* bad : {"", "1/", "abc", "1..2"}) EXPECT_THROW(parse_ratio(bad, "x"), mollify::Error) << bad;
}

TEST(SpecRuntime, ErrorsNameTheValue) {
    try {
        mollify::parse_spec("combo:radii=1/2;9/8,base=poly6");
        FAIL() << "accepted a radius above 1";
    } catch (const mollify::Error& e) {
        EXPECT_NE(std::string(e.what()).find("radius 9/8"), std::string::npos) << e.what();
    }
}
