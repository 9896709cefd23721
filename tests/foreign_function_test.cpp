// evaluate_foreign (tools/mollify/foreign_function.hpp): foreign functions
// compiled here with Debian's gcc, g++ and gfortran into shared libraries and
// evaluated in a child process; every way foreign code can fail is an Error
// naming the symbol and the argument, and this process lives on.
#include "command.hpp"
#include "foreign_function.hpp"

#include <mollify/error.hpp>

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <vector>

namespace fs = std::filesystem;
using mollify::app::evaluate_foreign;
using mollify::app::ForeignFunction;
using mollify::testing::run_command;

namespace {

// Each test process (ctest runs two at a time) builds its own libraries in
// its own folder: no process dlopens a file another is writing.
const fs::path work = fs::path(MOLLIFY_FOREIGN_WORK_DIR) / ("run-" + std::to_string(::getpid()));

// Compiles `source` (named by its extension) into work/lib<name>.so.
fs::path build_library(const std::string& name, const std::string& extension, const std::string& source,
                       const std::string& compiler) {
    fs::create_directories(work);
    const fs::path src = work / (name + extension), lib = work / ("lib" + name + ".so");
    std::ofstream(src) << source;
    const auto r = run_command(compiler + " -shared -fPIC -O1 -Wall -Werror '" + src.string() + "' -o '" +
                                   lib.string() + "'",
                               work / ("cc_" + name));
    EXPECT_EQ(r.status, 0) << compiler << " failed (is it installed? tools/install-deps.sh):\n" << r.err;
    return lib;
}

// C functions that misbehave at r > 0.5, and behave (r * h + 1) below.
const std::string c_source = R"(#include <math.h>
#include <stdlib.h>
double good(double r, double h) { return r * h + 1; }
double segv(double r, double h) { if (r > 0.5) { volatile int* p = 0; *p = 1; } return r * h + 1; }
double aborts(double r, double h) { if (r > 0.5) abort(); return r * h + 1; }
double exits(double r, double h) { if (r > 0.5) exit(7); return r * h + 1; }
double hangs(double r, double h) { volatile int spin = 1; if (r > 0.5) while (spin) {} return r * h + 1; }
double nan_at(double r, double h) { return r > 0.5 ? NAN : r * h + 1; }
double inf_at(double r, double h) { return r > 0.5 ? INFINITY : r * h + 1; }
double fpe(double r, double h) { volatile int zero = 0; if (r > 0.5) return (int)h / zero; return r * h + 1; }
)";

const std::string cpp_source = R"(#include <stdexcept>
extern "C" double throws(double r, double h) { if (r > 0.5) throw std::runtime_error("r too large"); return r * h + 1; }
extern "C" double throws_int(double r, double h) { if (r > 0.5) throw 42; return r * h + 1; }
)";

const std::string fortran_source = R"(function fortran_w(r, h) bind(C, name='fortran_w') result(w)
  use, intrinsic :: iso_c_binding, only: c_double
  real(c_double), value :: r, h
  real(c_double) :: w
  w = r * h + 1
end function fortran_w
)";

class ForeignFunctionTest : public ::testing::Test {
protected:
    // In SetUp, not SetUpTestSuite: a missing compiler fails each test
    // (a failing SetUpTestSuite reads as skipped in ctest).
    static void TearDownTestSuite() { fs::remove_all(work); }  // this process's folder
    void SetUp() override {
        static const bool built = [] {
            fs::remove_all(work);
            c_lib = build_library("foreign_c", ".c", c_source, "gcc");
            cpp_lib = build_library("foreign_cpp", ".cpp", cpp_source, "g++");
            fortran_lib = build_library("foreign_f", ".f90", fortran_source, "gfortran");
            return !::testing::Test::HasFailure();
        }();
        ASSERT_TRUE(built) << "building the test libraries failed (see the first test's output)";
    }
    static inline fs::path c_lib, cpp_lib, fortran_lib;

    const std::vector<double> r{0, 0.25, 0.5, 0.75, 1};
    const std::vector<double> h{1, 2, 0.5, 0.125, 3};

    // The Error's message when evaluating `symbol` from `lib`.
    std::string error_of(const fs::path& lib, const std::string& symbol,
                         std::chrono::milliseconds timeout = std::chrono::seconds(10)) const {
        try {
            evaluate_foreign({lib, symbol}, r, h, timeout);
        } catch (const mollify::Error& e) {
            return e.what();
        }
        ADD_FAILURE() << symbol << " did not fail";
        return "";
    }
};

TEST_F(ForeignFunctionTest, EvaluatesCAndFortranInOrder) {
    for (const auto& [lib, symbol] : {std::pair{c_lib, "good"}, std::pair{fortran_lib, "fortran_w"}}) {
        const auto values = evaluate_foreign({lib, symbol}, r, h);
        ASSERT_EQ(values.size(), r.size());
        for (std::size_t i = 0; i < r.size(); ++i) EXPECT_EQ(values[i], r[i] * h[i] + 1) << symbol << " " << i;
    }
}

TEST_F(ForeignFunctionTest, NoArgumentsStillChecksLibraryAndSymbol) {
    EXPECT_TRUE(evaluate_foreign({c_lib, "good"}, {}, {}).empty());
    EXPECT_THROW(evaluate_foreign({c_lib, "absent"}, {}, {}), mollify::Error);
}

TEST_F(ForeignFunctionTest, ManyArgumentsStreamThroughThePipe) {
    std::vector<double> rs(100000), hs(100000, 2.0);  // 900 kB of records: more than a pipe's buffer
    for (std::size_t i = 0; i < rs.size(); ++i) rs[i] = 0.5 * static_cast<double>(i) / rs.size();
    const auto values = evaluate_foreign({c_lib, "good"}, rs, hs);
    ASSERT_EQ(values.size(), rs.size());
    for (std::size_t i = 0; i < rs.size(); ++i) ASSERT_EQ(values[i], rs[i] * 2 + 1) << i;
}

TEST_F(ForeignFunctionTest, CrashesNameTheSignalAndTheArgument) {
    EXPECT_EQ(error_of(c_lib, "segv"), "segv crashed with SIGSEGV at r=0.75, h=0.125");
    EXPECT_EQ(error_of(c_lib, "aborts"), "aborts crashed with SIGABRT at r=0.75, h=0.125");
    EXPECT_EQ(error_of(c_lib, "fpe"), "fpe crashed with SIGFPE at r=0.75, h=0.125");
    EXPECT_EQ(error_of(c_lib, "exits"), "exits exited with status 7 (called exit or stop) at r=0.75, h=0.125");
}

TEST_F(ForeignFunctionTest, EndlessLoopTimesOut) {
    EXPECT_EQ(error_of(c_lib, "hangs", std::chrono::milliseconds(500)),
              "hangs did not return within 0.5 s at r=0.75, h=0.125 (an endless loop? --timeout sets the limit)");
}

TEST_F(ForeignFunctionTest, NonFiniteValuesNameTheArgument) {
    EXPECT_EQ(error_of(c_lib, "nan_at"), "nan_at returned nan at r=0.75, h=0.125 (a kernel value is finite)");
    EXPECT_EQ(error_of(c_lib, "inf_at"), "inf_at returned inf at r=0.75, h=0.125 (a kernel value is finite)");
}

TEST_F(ForeignFunctionTest, EscapingExceptions) {
    EXPECT_EQ(error_of(cpp_lib, "throws"), "throws threw an exception (r too large) at r=0.75, h=0.125");
    EXPECT_EQ(error_of(cpp_lib, "throws_int"), "throws_int threw an exception at r=0.75, h=0.125");
}

TEST_F(ForeignFunctionTest, MissingSymbolAndBadLibrary) {
    const std::string missing = error_of(c_lib, "my_w");
    EXPECT_EQ(missing.rfind("no symbol my_w in " + c_lib.string() + ": ", 0), 0u) << missing;
    EXPECT_NE(missing.find("undefined symbol: my_w"), std::string::npos) << missing;  // dlerror's text

    const std::string absent = error_of(work / "libnothing.so", "good");
    EXPECT_EQ(absent.rfind("cannot open library " + (work / "libnothing.so").string() + ": ", 0), 0u) << absent;
    EXPECT_NE(absent.find("No such file or directory"), std::string::npos) << absent;

    const fs::path not_a_library = work / "not_a_library.so";
    std::ofstream(not_a_library) << "text";
    const std::string bad = error_of(not_a_library, "good");
    EXPECT_NE(bad.find("cannot open library"), std::string::npos) << bad;
    EXPECT_NE(bad.find("file too short"), std::string::npos) << bad;
}

TEST_F(ForeignFunctionTest, LibraryInTheWorkingDirectoryWithoutSlash) {
    const fs::path here = fs::current_path();
    fs::current_path(work);
    std::vector<double> values;
    EXPECT_NO_THROW(values = evaluate_foreign({"libforeign_c.so", "good"}, r, h));
    fs::current_path(here);
    EXPECT_EQ(values.size(), r.size());
}

}  // namespace
