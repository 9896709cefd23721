// `mollify verify` as a user runs it (issue 20, item 4), through shared
// libraries compiled here with Debian's g++, gcc and gfortran and CSV files:
//   - mollify's own Wendland k=2 (3D) as a C-ABI function (extern "C" around
//     StaticKernel, Precision::accurate) passes at <= 1 ulp (the issue's bound
//     for mollify's own kernels) through --library and through a CSV of its
//     values;
//   - the same kernel emitted by `mollify-gen emit --target c|fortran|python`
//     (the Fortran through its bind(C) functions, the Python module through
//     a CSV written by Debian's python3) passes at 32 ulps: those files
//     evaluate as Precision::fast, whose bound is tests/targets_test.cpp's
//     function_bound (measured: W at most 10.2 ulps from C, 10.5 from Fortran,
//     9.5 from Python; dW/dr 9.0 from C, 8.0 from Fortran);
//   - wrong libraries (1e-6 relative off, support 2h) fail, exit 1, diagnosed;
//   - crashing, NaN-returning functions, a missing symbol, a bad path, a
//     malformed CSV, bad options: exit 2 with their message, no report.
#include "command.hpp"

#include <gtest/gtest.h>

#include <dlfcn.h>
#include <unistd.h>

#include <charconv>
#include <tuple>

#include <filesystem>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;
using mollify::testing::Outcome;
using mollify::testing::run_command;

namespace {

// ctest runs each test in its own process, two at a time: the libraries are
// built once into a folder named by the test's and mollify-gen's build times
// (built under a temporary name, renamed when complete: the first process to
// finish wins), and every process works in a folder of its own.
const fs::path root = MOLLIFY_VERIFY_WORK_DIR;
fs::path work;  // root/run-<pid>, with copies of the libraries
const std::string kernel = "wendland:k=2";
const std::string prefix = "mollify_wendland_k_2_D3";

Outcome run(const std::string& arguments) {
    return run_command("cd '" + work.string() + "' && '" MOLLIFY "' verify " + arguments, work / "out");
}

void shell(const std::string& what, const std::string& command) {
    const auto r = run_command("cd '" + work.string() + "' && " + command, work / "sh");
    ASSERT_EQ(r.status, 0) << what << " failed (installed? tools/install-deps.sh):\n" << command << "\n" << r.err;
}

// C wrappers around the emitted header: right, and wrong in the ways the
// issue lists (a constant 1e-6 relative too large, support 2h: W_2h(r) =
// W_h(r/2)/8 in 3D), and foreign code misbehaving at r > h/2.
const std::string wrappers = R"(#include <math.h>
#include "c/mollify_wendland_k_2_D3.h"
double my_w(double r, double h) { return mollify_wendland_k_2_D3_value_h(r, h); }
double my_dr(double r, double h) { return mollify_wendland_k_2_D3_dr_h(r, h); }
double my_w_off(double r, double h) { return mollify_wendland_k_2_D3_value_h(r, h) * (1 + 1e-6); }
double my_w_2h(double r, double h) { return mollify_wendland_k_2_D3_value_h(0.5 * r, h) * 0.125; }
double my_w_crash(double r, double h) { if (r > 0.5 * h) { volatile int* p = 0; *p = 1; } return my_w(r, h); }
double my_w_nan(double r, double h) { return r > 0.5 * h ? NAN : my_w(r, h); }
)";

// mollify's own kernel as a C-ABI function: the compile-time form,
// Precision::accurate (README, "Runtime").
const std::string own_kernel = R"(#include <mollify/static_kernel.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>
using W = mollify::StaticKernel<mollify::tables::wendland_k_2_D3>;
extern "C" double mollify_w(double r, double h) { return W::radial<mollify::QuantityId::value>(r, W::smoothing(h)); }
extern "C" double mollify_dr(double r, double h) { return W::radial<mollify::QuantityId::dr>(r, W::smoothing(h)); }
)";

// The libraries, built once; in SetUp, not SetUpTestSuite, so that a missing
// compiler fails every test (a failing SetUpTestSuite reads as skipped in ctest).
// Builds the libraries in `work` (a temporary folder).
void build_libraries() {
    for (const char* target : {"c", "fortran", "python"})
        ASSERT_NO_FATAL_FAILURE(shell("mollify-gen emit", "'" MOLLIFY_GEN "' emit --target " + std::string(target) +
                                                              " --only " + kernel + " --dim 3 --out . > /dev/null"));
    std::ofstream(work / "mine.c") << wrappers;
    ASSERT_NO_FATAL_FAILURE(
        shell("gcc", "gcc -std=c99 -O2 -shared -fPIC -Wall -Wextra -Werror -I. mine.c -o libmine.so -lm"));
    std::ofstream(work / "own.cpp") << own_kernel;
    const std::string src = MOLLIFY_SOURCE_DIR;
    ASSERT_NO_FATAL_FAILURE(shell("g++", "g++ -std=c++20 -O2 -shared -fPIC -Wall -Wextra -Werror -Wl,--no-undefined -I'" +
                                             src + "/include' -I'" + src + "/generated' own.cpp '" + src +
                                             "/src/failures.cpp' '" + src + "/src/smoothing.cpp' '" + src +
                                             "/src/precision.cpp' -o libown.so"));
    ASSERT_NO_FATAL_FAILURE(shell("gfortran", "gfortran -std=f2008 -O2 -shared -fPIC -Wall -Werror fortran/" + prefix +
                                                  ".f90 -o libmine_fortran.so"));
}

long long build_time(const fs::path& file) {
    return static_cast<long long>(fs::last_write_time(file).time_since_epoch().count());
}

// The shared library folder, built if absent; then this process's folder with copies.
bool prepare() {
    const fs::path libs = root / ("libs-" + std::to_string(build_time("/proc/self/exe")) + "-" +
                                  std::to_string(build_time(MOLLIFY_GEN)));
    work = root / ("run-" + std::to_string(::getpid()));
    fs::remove_all(work);
    fs::create_directories(work);
    if (!fs::exists(libs)) {
        build_libraries();
        if (::testing::Test::HasFatalFailure()) return false;
        std::error_code ec;
        fs::rename(work, libs, ec);  // fails if another process was first: its folder is as good
        if (ec) fs::remove_all(work);
        fs::create_directories(work);
    }
    for (const char* f : {"libmine.so", "libmine_fortran.so", "libown.so"}) fs::copy_file(libs / f, work / f);
    fs::copy(libs / "python", work / "python", fs::copy_options::recursive);
    return true;
}

// The emitted files' bound (Precision::fast): tests/targets_test.cpp's function_bound.
const std::string emitted_bound = "32";

class VerifyCli : public ::testing::Test {
protected:
    static void TearDownTestSuite() { fs::remove_all(work); }  // this process's folder
    void SetUp() override {
        static const bool built = prepare();
        ASSERT_TRUE(built) << "building the test libraries failed (see the first test's output)";
    }
};

TEST_F(VerifyCli, OwnKernelPassesWithinOneUlp) {
    for (const auto& [symbol, quantity] : {std::pair{"mollify_w", "value"}, std::pair{"mollify_dr", "dr"}}) {
        const auto r = run(kernel + " --dim 3 --library ./libown.so --symbol " + symbol + " --quantity " + quantity +
                           " --ulps 1");
        EXPECT_EQ(r.status, 0) << symbol << "\n" << r.out << r.err;
        EXPECT_NE(r.out.find("verdict: " + std::string(symbol) + " (./libown.so) PASSES"), std::string::npos) << r.out;
        EXPECT_EQ(r.err, "");
    }
}

TEST_F(VerifyCli, EmittedCAndFortranBindCPassAtTheirBound) {
    for (const auto& [lib, symbol, quantity] :
         {std::tuple{"./libmine.so", std::string("my_w"), "value"}, std::tuple{"./libmine.so", std::string("my_dr"), "dr"},
          std::tuple{"libmine_fortran.so", prefix + "_f90_value_h", "value"},
          std::tuple{"libmine_fortran.so", prefix + "_f90_dr_h", "dr"}}) {
        const auto r = run(kernel + " --dim 3 --library " + lib + " --symbol " + symbol + " --quantity " + quantity +
                           " --ulps " + emitted_bound);
        EXPECT_EQ(r.status, 0) << symbol << "\n" << r.out << r.err;
        EXPECT_NE(r.out.find("PASSES"), std::string::npos) << r.out;
    }
}

// The arguments from --write-arguments, the values from the C library
// (dlopen here, as any other language would compute them), as CSV.
TEST_F(VerifyCli, OwnKernelThroughCsvPassesWithinOneUlp) {
    auto r = run(kernel + " --dim 3 --write-arguments args.csv");
    ASSERT_EQ(r.status, 0) << r.err;
    void* lib = ::dlopen((work / "libown.so").c_str(), RTLD_NOW);
    ASSERT_NE(lib, nullptr) << ::dlerror();
    const auto w = reinterpret_cast<double (*)(double, double)>(::dlsym(lib, "mollify_w"));
    ASSERT_NE(w, nullptr);
    std::ifstream in(work / "args.csv");
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(line, "r,h");
    std::ostringstream csv;
    csv.precision(17);
    csv << "r,h,value\n";
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        const auto comma = line.find(',');
        double rr = 0, h = 0;  // from_chars: stod rejects subnormals (ERANGE), which the hard points have
        std::from_chars(line.data(), line.data() + comma, rr);
        std::from_chars(line.data() + comma + 1, line.data() + line.size(), h);
        csv << line << "," << w(rr, h) << "\n";
        ++rows;
    }
    EXPECT_GT(rows, 10000u);  // the hard points and 10^4 uniform ones
    std::ofstream(work / "samples.csv") << csv.str();
    r = run(kernel + " --dim 3 --samples samples.csv --ulps 1");
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("verdict: samples.csv PASSES"), std::string::npos) << r.out;
    // every hard point among the rows: said so, and the verdict unqualified
    EXPECT_EQ(r.out.find("--write-arguments writes every hard point"), std::string::npos) << r.out;
    const auto at = r.out.find("  hard points: ");
    ASSERT_NE(at, std::string::npos) << r.out;
    std::size_t found = 0, all = 0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + at, "  hard points: %zu of %zu among the samples", &found, &all), 2) << r.out;
    EXPECT_EQ(found, all);
    EXPECT_GT(all, 100u);
    EXPECT_EQ(r.out.find("the given rows only"), std::string::npos) << r.out;

    // Rows of the same right kernel at radii of one's own (h = 1, r/h =
    // 0.005 .. 0.985): it passes, but only on those rows, and the output says
    // how few of the hard points (r = 0, the edge, tiny and huge h) were
    // among them.
    std::ostringstream own;
    own.precision(17);
    own << "r,h,value\n";
    for (int i = 0; i < 99; ++i) own << (i + 0.5) / 100 << ",1," << w((i + 0.5) / 100, 1.0) << "\n";
    std::ofstream(work / "own_rows.csv") << own.str();
    r = run(kernel + " --dim 3 --samples own_rows.csv --ulps 1");
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    const auto own_at = r.out.find("  hard points: ");
    ASSERT_NE(own_at, std::string::npos) << r.out;
    std::size_t own_found = 0, own_all = 0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + own_at, "  hard points: %zu of %zu among the samples", &own_found, &own_all), 2) << r.out;
    EXPECT_EQ(own_all, all);
    EXPECT_LT(own_found, all / 10) << r.out;
    EXPECT_NE(r.out.find("among the samples (the verification's samples hold them all; the others were not checked)"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("\n  (mollify verify --write-arguments writes every hard point)\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("verdict: own_rows.csv PASSES: max"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("over 99 points, the given rows only (" + std::to_string(own_found) + " of " + std::to_string(all) +
                         " hard points)"),
              std::string::npos)
        << r.out;
}

// The README's Python example: Debian's python3 evaluates the arguments with
// the emitted module (mollify-gen emit --target python) and writes repr()s.
TEST_F(VerifyCli, EmittedPythonThroughCsvPassesAtItsBound) {
    auto r = run(kernel + " --dim 3 --write-arguments py_args.csv");
    ASSERT_EQ(r.status, 0) << r.err;
    std::ofstream(work / "write_samples.py") << R"(import csv, sys
sys.path.insert(0, "python")
import mollify_wendland_k_2_D3 as w
with open("py_args.csv") as f, open("py_samples.csv", "w", newline="") as out:
    rows = csv.writer(out)
    rows.writerow(["r", "h", "value"])
    for row in csv.DictReader(f):
        r, h = float(row["r"]), float(row["h"])
        rows.writerow([repr(r), repr(h), repr(float(w.value_h(r, h)))])
)";
    ASSERT_NO_FATAL_FAILURE(shell("python3", "/usr/bin/python3 write_samples.py"));
    r = run(kernel + " --dim 3 --samples py_samples.csv --ulps " + emitted_bound);
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("verdict: py_samples.csv PASSES"), std::string::npos) << r.out;
}

TEST_F(VerifyCli, WrongKernelsFailWithADiagnosis) {
    auto r = run(kernel + " --dim 3 --library ./libmine.so --symbol my_w_off");
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("FAILS"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("diagnosis (constant factor)"), std::string::npos) << r.out;
    r = run(kernel + " --dim 3 --library ./libmine.so --symbol my_w_2h");
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("diagnosis (support convention)"), std::string::npos) << r.out;
    // ... and is right in Phantom's convention (support 2h), as the diagnosis says.
    r = run(kernel + " --dim 3 --library ./libmine.so --symbol my_w_2h --convention phantom --ulps " + emitted_bound);
    EXPECT_EQ(r.status, 0) << r.out << r.err;
}

TEST_F(VerifyCli, ForeignFailuresExitTwoNamingTheArgument) {
    auto r = run(kernel + " --dim 3 --library ./libmine.so --symbol my_w_crash");
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_EQ(r.out, "");  // nothing half-written
    EXPECT_NE(r.err.find("mollify verify: error: my_w_crash crashed with SIGSEGV at r="), std::string::npos) << r.err;

    r = run(kernel + " --dim 3 --library ./libmine.so --symbol my_w_nan");
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find("my_w_nan returned nan at r="), std::string::npos) << r.err;

    r = run(kernel + " --dim 3 --library ./libmine.so --symbol my_kernel");
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("no symbol my_kernel in ./libmine.so: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("undefined symbol: my_kernel"), std::string::npos) << r.err;

    r = run(kernel + " --dim 3 --library ./libabsent.so --symbol my_w");
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("cannot open library ./libabsent.so: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("No such file or directory"), std::string::npos) << r.err;
}

TEST_F(VerifyCli, BadInputExitsTwo) {
    std::ofstream(work / "bad.csv") << "r,h,value\n0.1,0.5,3\n0.2,0.5,x3\n";
    auto r = run(kernel + " --dim 3 --samples bad.csv");
    EXPECT_EQ(r.status, 2) << r.out << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find("bad.csv:3: column 3 (value): \"x3\" is not a number"), std::string::npos) << r.err;

    r = run(kernel + " --dim 3 --library ./libmine.so --symbol my_w --quantity hessian");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("hessian"), std::string::npos) << r.err;

    r = run(kernel + " --dim 3 --library ./libmine.so --symbol my_w --convention nonsense");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("nonsense"), std::string::npos) << r.err;

    r = run("wendland:k=99 --dim 3 --library ./libmine.so --symbol my_w");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("99"), std::string::npos) << r.err;

    r = run(kernel + " --dim 3 --library ./libmine.so");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--library needs --symbol"), std::string::npos) << r.err;

    r = run(kernel + " --dim 3 --samples bad.csv --library ./libmine.so --symbol my_w");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("exactly one of"), std::string::npos) << r.err;

    for (const char* points : {"100000000000", "-5"}) {  // std::bad_alloc; -5 had wrapped to 2^64 - 5
        r = run(kernel + " --dim 3 --write-arguments huge.csv --points " + points);
        EXPECT_EQ(r.status, 2) << r.err;
        EXPECT_NE(r.err.find(std::string("--points: Value ") + points + " not in range 0 to 100000000"), std::string::npos)
            << r.err;
        EXPECT_FALSE(std::filesystem::exists(work / "huge.csv"));
    }

    r = run(kernel + " --library ./libmine.so --symbol my_w");  // --dim missing: CLI11's error
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--dim"), std::string::npos) << r.err;
}

TEST_F(VerifyCli, WriteArgumentsIsAtomicAndNamesBadPaths) {
    const auto r = run(kernel + " --dim 3 --write-arguments no_such_dir/args.csv");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("no_such_dir/args.csv"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(work / "no_such_dir"));
}

}  // namespace
