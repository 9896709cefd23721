// The samples CSV reader (tools/mollify/samples_csv.hpp): what any language
// writes is read exactly; every malformed row is an Error naming the file,
// the line, the column and the bad text.
#include "samples_csv.hpp"

#include <mollify/error.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>

using mollify::app::parse_samples_csv;
using mollify::app::read_samples_csv;

namespace {

std::string error_of(std::string_view text) {
    try {
        parse_samples_csv(text, "s.csv");
    } catch (const mollify::Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return "";
}

TEST(SamplesCsv, ReadsNumbersExactly) {
    // Python's repr, C's %.17g, Fortran's ES25.17E3.
    const auto t = parse_samples_csv("r,h,value\n0.1,1,0.30000000000000004\n"
                                     "5.0000000000000000E-001, 2.5E+000 ,4.9406564584124654e-324\n"
                                     "0,1e-300,1.7976931348623157e308\n",
                                     "s.csv");
    ASSERT_EQ(t.r.size(), 3u);
    EXPECT_EQ(t.r[0], 0.1);
    EXPECT_EQ(t.value[0], 0.1 + 0.2);
    EXPECT_EQ(t.r[1], 0.5);
    EXPECT_EQ(t.h[1], 2.5);
    EXPECT_EQ(t.value[1], std::bit_cast<double>(std::uint64_t{1}));  // the smallest subnormal
    EXPECT_EQ(t.h[2], 1e-300);
    EXPECT_EQ(t.value[2], 1.7976931348623157e308);
}

// Hex-floats, a double's exact value (C's %a, Python's float.hex, Fortran's EX editing), as
// mollify-gen value --r reads them; a sign only in front of the prefix.
TEST(SamplesCsv, ReadsHexFloats) {
    const auto t = parse_samples_csv("r,h,value\n0x1.999999999999ap-4,0X1P+0,-0x1.8p+1\n0x0p+0,+0x1p-1074,0x1.fffffffffffffp+1023\n",
                                     "s.csv");
    ASSERT_EQ(t.r.size(), 2u);
    EXPECT_EQ(t.r[0], 0.1);
    EXPECT_EQ(t.h[0], 1.0);
    EXPECT_EQ(t.value[0], -3.0);
    EXPECT_EQ(t.r[1], 0.0);
    EXPECT_EQ(t.h[1], std::bit_cast<double>(std::uint64_t{1}));
    EXPECT_EQ(t.value[1], 1.7976931348623157e308);
    EXPECT_EQ(error_of("r,h,value\n0x-1p3,1,2\n"), "s.csv:2: column 1 (r): \"0x-1p3\" is not a number");
    EXPECT_EQ(error_of("r,h,value\n0x,1,2\n"), "s.csv:2: column 1 (r): \"0x\" is not a number");
    EXPECT_EQ(error_of("r,h,value\n0x1p99999,1,2\n"), "s.csv:2: column 1 (r): \"0x1p99999\" is out of the range of a double");
    EXPECT_EQ(error_of("r,h,value\n-0x1p-1,1,2\n"), "s.csv:2: column 1 (r): r = \"-0x1p-1\" is negative (r >= 0 needed)");
}

TEST(SamplesCsv, ColumnsInAnyOrderQuotedHeadersCrlfBlankLines) {
    const auto t = parse_samples_csv("\"value\",\"r\",\"h\"\r\n\r\n2.5,0.25,+1\r\n\n-3,0,2\r\n", "s.csv");
    ASSERT_EQ(t.r.size(), 2u);
    EXPECT_EQ(t.value[0], 2.5);
    EXPECT_EQ(t.r[0], 0.25);
    EXPECT_EQ(t.h[0], 1);
    EXPECT_EQ(t.value[1], -3);  // a kernel value may be negative (a gradient, a potential)
    EXPECT_EQ(t.h[1], 2);
}

TEST(SamplesCsv, MalformedRowsNameFileLineColumnAndText) {
    EXPECT_EQ(error_of("r,h,value\n0.1,1,2\n0.2,abc,3\n"), "s.csv:3: column 2 (h): \"abc\" is not a number");
    EXPECT_EQ(error_of("r,h,value\n0.1,1,2\n0.2,1,3x\n"), "s.csv:3: column 3 (value): \"3x\" is not a number");
    EXPECT_EQ(error_of("r,h,value\n0.1,1\n"), "s.csv:2: this row has 2 fields, 3 expected (r, h, value): \"0.1,1\"");
    EXPECT_EQ(error_of("r,h,value\n0.1,1,2,4\n"),
              "s.csv:2: this row has 4 fields, 3 expected (r, h, value): \"0.1,1,2,4\"");
    EXPECT_EQ(error_of("r,h,value\n\n0.1,,2\n"), "s.csv:3: column 2 (h): empty field, a number expected");
    EXPECT_EQ(error_of("r,h,value\n0.1;1;2\n"),
              "s.csv:2: this row has 1 field, 3 expected (r, h, value): \"0.1;1;2\"");
    EXPECT_EQ(error_of("r,h,value\n1e999,1,2\n"), "s.csv:2: column 1 (r): \"1e999\" is out of the range of a double");
    EXPECT_EQ(error_of("r,h,value\n0.1,1,\x01\n"), "s.csv:2: column 3 (value): \"\\x01\" is not a number");
}

TEST(SamplesCsv, OutOfDomainAndNonFiniteNamed) {
    EXPECT_EQ(error_of("r,h,value\n-0.5,1,2\n"), "s.csv:2: column 1 (r): r = \"-0.5\" is negative (r >= 0 needed)");
    EXPECT_EQ(error_of("r,h,value\n0.5,0,2\n"), "s.csv:2: column 2 (h): h = \"0\" is not positive (h > 0 needed)");
    EXPECT_EQ(error_of("r,h,value\n0.5,-1,2\n"), "s.csv:2: column 2 (h): h = \"-1\" is not positive (h > 0 needed)");
    EXPECT_EQ(error_of("r,h,value\n0.5,1,nan\n"), "s.csv:2: column 3 (value): \"nan\" is not finite");
    EXPECT_EQ(error_of("r,h,value\n0.5,1,-inf\n"), "s.csv:2: column 3 (value): \"-inf\" is not finite");
    EXPECT_EQ(error_of("r,h,value\ninf,1,2\n"), "s.csv:2: column 1 (r): \"inf\" is not finite");
}

TEST(SamplesCsv, HeaderErrors) {
    EXPECT_EQ(error_of(""), "s.csv: empty: a header line r,h,value and one row per sample expected");
    EXPECT_EQ(error_of("r,h,value\n"), "s.csv: a header and no rows: one row per sample expected");
    EXPECT_EQ(error_of("0.1,1,2\n"), "s.csv:1: column 1: \"0.1\" is not a column name (the header names the columns "
                                     "r, h, value, e.g. \"r,h,value\")");
    EXPECT_EQ(error_of("r,r,value\n"), "s.csv:1: column 2: \"r\" appears twice (the header names the columns "
                                       "r, h, value, e.g. \"r,h,value\")");
    EXPECT_EQ(error_of("r,h\n"), "s.csv:1: the header has 2 columns, 3 expected (the header names the columns "
                                 "r, h, value, e.g. \"r,h,value\")");
}

TEST(SamplesCsv, FileNamedWhenMissingOrInErrors) {
    const auto dir = std::filesystem::temp_directory_path() / "mollify_samples_csv_test";
    std::filesystem::create_directories(dir);
    EXPECT_THROW(
        {
            try {
                read_samples_csv(dir / "absent.csv");
            } catch (const mollify::Error& e) {
                EXPECT_NE(std::string(e.what()).find("absent.csv"), std::string::npos) << e.what();
                throw;
            }
        },
        mollify::Error);
    std::ofstream(dir / "bad.csv") << "r,h,value\n0.1,1,x\n";
    try {
        read_samples_csv(dir / "bad.csv");
        ADD_FAILURE();
    } catch (const mollify::Error& e) {
        EXPECT_EQ(std::string(e.what()), (dir / "bad.csv").string() + ":2: column 3 (value): \"x\" is not a number");
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
