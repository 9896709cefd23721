// `mollify-gen emit --target c|fortran|python` (issue 19, item 4): the files
// compile with Debian's toolchains (gcc -std=c99 -pedantic, gfortran
// -std=f2008, /usr/bin/python3 with NumPy), and a driver per language,
// written here, evaluates every emitted function at the hard points (near 0,
// near the support edge on both sides, the kernel's own breakpoints and their
// neighbouring doubles, h from 1e-8 to 1e8, r/h up to 1e6; around r/h =
// 2^-150 with h from 1e-30 to 1e30, where a quantity singular at 0 takes its
// leading order) and dumps the results and the constants as raw doubles;
// this test compares them with the exact values (tools/accuracy's MPFR
// reference, >= 200 bits).
// A missing tool fails the test (never a skip). Also: conventions as data
// (SWIFT's gamma, Phantom's hfact), bad --target arguments, and the golden
// files of tests/golden/targets (a writer change that alters output is seen).
#include "accuracy/accuracy.hpp"
#include "command.hpp"

#include <catalogue.hpp>
#include <conventions.hpp>
#include <emit_metadata.hpp>
#include <rounding.hpp>
#include <target.hpp>
#include <target_code.hpp>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace acc = mollify::accuracy;
namespace gen = mollify::gen;
using mollify::QuantityId;
using mollify::testing::run_command;
using mollify::testing::slurp;
using Real = acc::Real;

// The kernels the drivers evaluate: every piece shape of the tables
// (Wendland's (1 - q)^n p(q), a 2D potential with log r, the missing
// Wendland functions' S, arcsech, arcsin and Taylor pieces, a mollifier's
// (1 - q^2)^M, a combination's inner edges a_j, the cubic spline's inner
// breakpoint, a 1D kernel).
struct Case {
    const char* spec;
    int dim;
};
#ifndef MOLLIFY_SANITIZED_BUILD
constexpr Case cases[] = {
    {"wendland:k=2", 3},         {"wendland:k=4,l=4", 2},           {"wendland-missing:k=1", 3},
    {"mollifier:M=4", 2},        {"combo:m=3,base=wendland:k=2", 3}, {"cubic-spline", 1},
    {"cubic-spline", 2},         {"combo:m=2,base=wendland:k=1", 2},  // its hess_radial: +inf at r = 0, not inf - inf
    {"viscosity", 3},  // every quantity singular at 0 (q^-1 .. q^-5): the leading order below r/h = 2^-150
};
constexpr int uniform_points = 200;
#else  // -O0 + ASan (CI time): the polynomial shapes, the hard points only.
constexpr Case cases[] = {{"wendland:k=2", 3}, {"combo:m=3,base=wendland:k=2", 3}, {"cubic-spline", 1}};
constexpr int uniform_points = 0;
#endif

// Error bounds for the functions, in intrinsic ulps: |y - f_h(r)| in ulps of
// max(|f_h(r)|, |r f_h'(r)|) (+ |c log h| inside for a 2D potential), the
// error an exact evaluator makes when handed r/h with one ulp of relative
// error (tests/accuracy_test.cpp, "intrinsic"). The files evaluate as the
// runtime's Precision::fast does, whose plain-double Horner and edge powers
// reach 24.9 ulp for values and gradients of the polynomial families
// (README, "Runtime accuracy", history), plus the rounding of pow(h, p)
// (< 1 ulp) and, in Fortran and NumPy, no FMA in (a h - r)/h and (r - c h)/h.
// Measured here: <= 21.2 (C, wendland:k=4,l=4 D2 W at r/h = 0.1), Fortran
// 17.2, Python 17.2; missing Wendland <= 4.4. A wrong coefficient, piece or
// scale is off by far more (a wrong sign near the edge: ~1e15 ulp).
constexpr double function_bound = 32;
// Tiny values (|exact| < 1e-10 of max |f_h|, where the intrinsic scale may
// itself be tiny: W's root at the edge) pass within 1 ulp of max |f_h| or
// within the function bound in intrinsic ulps; else they count as others.
constexpr double tiny_fraction = 1e-10;
constexpr double tiny_bound = 1;

fs::path work_dir() { return fs::path(MOLLIFY_TARGETS_WORK_DIR); }

std::string specs_arguments() {
    std::set<std::string> specs;
    for (const Case& c : cases) specs.insert(c.spec);
    std::string out;
    for (const std::string& s : specs) out += " --only '" + s + "'";
    return out;
}

// The kernel as the writers see it.
struct Emitted {
    std::string spec;
    int dim;
    std::unique_ptr<gen::KernelFacts> facts;
    gen::Tables tables;
    std::unique_ptr<gen::CodeKernel> code;
};

std::vector<Emitted> emitted_kernels() {
    std::vector<Emitted> out;
    for (const Case& c : cases) {
        Emitted e{c.spec, c.dim, std::make_unique<gen::KernelFacts>(gen::kernel_facts({mollify::parse_spec(c.spec), c.dim})),
                  {}, {}};
        e.tables = gen::rounded_tables(*e.facts);
        e.code = std::make_unique<gen::CodeKernel>(gen::code_kernel({*e.facts, e.tables, gen::convention("c")}));
        out.push_back(std::move(e));
    }
    return out;
}

// The hard points, and each kernel's own piece bounds with their
// neighbouring doubles at h = 1 and h = 3.
std::vector<acc::Point> points(const std::vector<Emitted>& kernels) {
    std::vector<acc::Point> out = acc::hard_points(uniform_points, 19);
    std::set<double> bounds;
    for (const Emitted& k : kernels)
        for (const gen::CodeQuantity& q : k.code->quantities)
            for (const gen::CodePiece& p : q.inside) bounds.insert(p.lo);
    for (double b : bounds)
        for (double r : {std::nextafter(b, 0.0), b, std::nextafter(b, 2.0)})
            for (double h : {1.0, 3.0}) out.push_back({r * h, h, "piece bound"});
    // Just above and below r/h = 2^-150, where the files take a singular
    // quantity's leading order (target_code.hpp, CodeQuantity::near_origin),
    // down to r's least subnormal, h from 1e-30 to 1e30: evaluated f(r/h)
    // first, viscosity's W'/r overflowed below r/h ~ 1e-100 and its W at a
    // subnormal r/h, where h^p f(r/h) is finite for a large h.
    for (double h : {1e-30, 1e-8, 1.0, 3.0, 1e8, 1e30}) {
        for (double q : {0x1p-149, 0x1p-150, 0x1p-151, 1e-50, 1e-100, 1e-150, 1e-200, 1e-250, 1e-300, 1e-310})
            if (q * h > 0) out.push_back({q * h, h, "near origin"});
        out.push_back({0x1p-1074, h, "near origin"});
    }
    return out;
}

void write_points(const fs::path& file, const std::vector<acc::Point>& pts) {
    std::ofstream f(file, std::ios::binary);
    for (const acc::Point& p : pts) {
        f.write(reinterpret_cast<const char*>(&p.r), sizeof p.r);
        f.write(reinterpret_cast<const char*>(&p.h), sizeof p.h);
    }
}

std::vector<double> read_doubles(const fs::path& file) {
    const std::string bytes = slurp(file);
    std::vector<double> out(bytes.size() / sizeof(double));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(double));
    return out;
}

// ---------------------------------------------------------------------------
// The drivers: for each kernel, its normalisation, its constants, then for
// each quantity and point f_h(r, h) and (h = 1 ? f(r) : f_h(r, h)).

std::string c_driver(const std::vector<Emitted>& kernels, std::size_t n) {
    std::string s = "#include <stdio.h>\n";
    for (const Emitted& k : kernels) s += "#include \"c/" + k.code->prefix + ".h\"\n";
    s += "enum { n = " + std::to_string(n) + " };\nstatic double p[2 * n];\n";
    s += "static void put(FILE *f, double x) { fwrite(&x, sizeof x, 1, f); }\n";
    s += "int main(void) {\n    FILE *in = fopen(\"points.bin\", \"rb\"), *out = fopen(\"c.bin\", \"wb\");\n    int i;\n";
    s += "    if (!in || !out || fread(p, sizeof(double), 2 * n, in) != (size_t)(2 * n)) return 1;\n";
    for (const Emitted& k : kernels) {
        const std::string& P = k.code->prefix;
        s += "    put(out, " + P + "_normalisation);\n";
        s += "    fwrite(" + P + "_c, sizeof(double), sizeof " + P + "_c / sizeof " + P + "_c[0], out);\n";
        for (const gen::CodeQuantity& q : k.code->quantities) {
            const std::string f = P + "_" + q.name;
            s += "    for (i = 0; i < n; ++i) {\n        put(out, " + f + "_h(p[2 * i], p[2 * i + 1]));\n";
            s += "        put(out, p[2 * i + 1] == 1.0 ? " + f + "(p[2 * i]) : " + f + "_h(p[2 * i], p[2 * i + 1]));\n    }\n";
        }
    }
    s += "    fclose(out);\n    fclose(in);\n    return 0;\n}\n";
    return s;
}

std::string fortran_driver(const std::vector<Emitted>& kernels, std::size_t n) {
    std::string s = "program driver\n  use, intrinsic :: iso_c_binding, only: c_double\n";
    for (std::size_t j = 0; j < kernels.size(); ++j) {
        std::string module = kernels[j].code->prefix;
        for (char& c : module) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        const std::string k = "k" + std::to_string(j) + "_";
        s += "  use " + module + ", only: " + k + "normalisation => normalisation\n";
        s += "  use " + module + ", only: " + k + "c => c\n";
        for (const gen::CodeQuantity& q : kernels[j].code->quantities) {
            s += "  use " + module + ", only: " + k + q.name + " => kernel_" + q.name + "\n";
            s += "  use " + module + ", only: " + k + q.name + "_h => kernel_" + q.name + "_h\n";
        }
    }
    s += "  implicit none\n  integer, parameter :: n = " + std::to_string(n) + "\n";
    s += "  real(c_double) :: p(2, n)\n  integer :: i, u, v\n";
    s += "  open(newunit=u, file='points.bin', access='stream', form='unformatted', status='old')\n  read(u) p\n  close(u)\n";
    s += "  open(newunit=v, file='fortran.bin', access='stream', form='unformatted', status='replace')\n";
    for (std::size_t j = 0; j < kernels.size(); ++j) {
        const std::string k = "k" + std::to_string(j) + "_";
        s += "  write(v) " + k + "normalisation\n  write(v) " + k + "c\n";
        for (const gen::CodeQuantity& q : kernels[j].code->quantities) {
            const std::string f = k + q.name;
            s += "  do i = 1, n\n    write(v) " + f + "_h(p(1, i), p(2, i))\n";
            s += "    if (p(2, i) == 1.0_c_double) then\n      write(v) " + f + "(p(1, i))\n    else\n      write(v) " + f +
                 "_h(p(1, i), p(2, i))\n    end if\n  end do\n";
        }
    }
    s += "  close(v)\nend program driver\n";
    return s;
}

std::string python_driver(const std::vector<Emitted>& kernels) {
    std::string s = "import sys\nfrom fractions import Fraction\n\nimport numpy as np\n\nsys.path.insert(0, 'python')\n";
    for (std::size_t j = 0; j < kernels.size(); ++j) s += "import " + kernels[j].code->prefix + " as k" + std::to_string(j) + "\n";
    s += R"(
p = np.fromfile('points.bin', dtype='<f8').reshape(-1, 2)
r, h = p[:, 0].copy(), p[:, 1].copy()
chunks = []


def check(m, quantities):
    # the exact rational constants: float(Fraction) is correctly rounded
    for i, (c, x) in enumerate(zip(m.C, m.C_EXACT)):
        if isinstance(x, Fraction) and float(x) != c:
            sys.exit(f'{m.SPEC} D{m.DIM}: C[{i}] = {c!r} is not float({x})')
    if len(m.C) != len(m.C_EXACT):
        sys.exit(f'{m.SPEC}: {len(m.C)} constants, {len(m.C_EXACT)} exact values')
    if tuple(m.QUANTITIES) != tuple(quantities):
        sys.exit(f'{m.SPEC}: quantities {m.QUANTITIES}')
    for bad in ((-1.0, 1.0), (float('nan'), 1.0), (0.5, 0.0), (0.5, float('inf'))):
        try:
            m.value_h(*bad)
            sys.exit(f'{m.SPEC}: value_h{bad} raised nothing')
        except ValueError as e:
            if repr(bad[0] if bad[0] != 0.5 else bad[1]) not in str(e):
                sys.exit(f'{m.SPEC}: value_h{bad}: the message {e} does not name the value')
    if not isinstance(m.value(0.5), np.floating):
        sys.exit(f'{m.SPEC}: value(0.5) is not a scalar')
    chunks.append(np.array([m.NORMALISATION]))
    chunks.append(m.C)
    for name in quantities:
        y = getattr(m, name + '_h')(r, h)
        y1 = np.where(h == 1.0, getattr(m, name)(r), y)
        chunks.append(np.column_stack([y, y1]).ravel())


)";
    for (std::size_t j = 0; j < kernels.size(); ++j) {
        s += "check(k" + std::to_string(j) + ", (";
        for (const gen::CodeQuantity& q : kernels[j].code->quantities) s += "'" + q.name + "', ";
        s += "))\n";
    }
    s += "np.concatenate(chunks).astype('<f8').tofile('python.bin')\n";
    return s;
}

void write_text(const fs::path& file, const std::string& text) {
    std::ofstream f(file, std::ios::binary);
    f << text;
}

// Each language's test works in a folder of its own (ctest runs them in parallel).
fs::path language_dir;

// Runs a shell command in the language's folder; its output on failure.
void run_in_work_dir(const std::string& what, const std::string& command) {
    const auto r = run_command("cd '" + language_dir.string() + "' && " + command, language_dir / "capture");
    ASSERT_EQ(r.status, 0) << what << ": " << command << "\n" << r.out << r.err;
}

// ---------------------------------------------------------------------------
// The comparison with the exact values.

// |y - x| in ulps of the scale s >= |x| (ulp as in accuracy::ulp_error).
double error_in_ulps_of(double y, const Real& x, const Real& s) {
    if (!std::isfinite(y)) return acc::ulp_error(y, x);
    Real m = boost::multiprecision::abs(x) > s ? Real(boost::multiprecision::abs(x)) : s;
    if (m == 0) return acc::ulp_error(y, x);
    const Real d = boost::multiprecision::abs(Real(y, 1200) - x);
    const long e = std::max(static_cast<long>(mpfr_get_exp(m.backend().data())) - 53, -1074L);
    Real u(0, 64);
    mpfr_set_ui_2exp(u.backend().data(), 1, e, MPFR_RNDN);
    return static_cast<double>(d / u);
}

struct Worst {
    double ulps = 0;
    acc::Point at{0, 0, ""};
};

// The constants a language dumped against the generator's: bitwise the
// correctly rounded ones, and within half an ulp of their exact values.
void check_constants(const std::string& language, const Emitted& k, const std::vector<double>& got, std::size_t& at) {
    ASSERT_LE(at + 1 + k.code->constants.size(), got.size()) << language << ": output too short";
    EXPECT_EQ(got[at], gen::round_to_double(k.facts->kernel.normalisation)) << language << " " << k.spec << " normalisation";
    EXPECT_LE(acc::ulp_error(got[at], k.facts->kernel.normalisation.evaluate(300).first), 0.5);
    ++at;
    for (std::size_t i = 0; i < k.code->constants.size(); ++i, ++at) {
        const gen::CodeConstant& c = k.code->constants[i];
        ASSERT_EQ(std::bit_cast<std::uint64_t>(got[at]), std::bit_cast<std::uint64_t>(c.value))
            << language << " " << k.spec << " D" << k.dim << " constant " << i << " (" << c.exact << ")";
        if (c.exact_value) {
            EXPECT_LE(acc::ulp_error(got[at], c.exact_value->evaluate(300).first), 0.5) << c.exact;
        }
    }
}

class Targets : public ::testing::Test {
protected:
    // Nothing here may throw: gtest reports a failed SetUpTestSuite as a
    // skipped test, which ctest counts as passed.
    static void SetUpTestSuite() {
        kernels_ = new std::vector<Emitted>(emitted_kernels());
        points_ = new std::vector<acc::Point>(points(*kernels_));
    }

    // The language's folder, emptied, with the points.
    static void prepare(const std::string& language) {
        language_dir = work_dir() / language;
        std::error_code ec;
        fs::remove_all(language_dir, ec);
        ASSERT_FALSE(ec) << language_dir << ": " << ec.message();
        fs::create_directories(language_dir, ec);
        ASSERT_FALSE(ec) << language_dir << ": " << ec.message();
        write_points(language_dir / "points.bin", *points_);
    }
    static void TearDownTestSuite() {
        delete kernels_;
        delete points_;
    }

    static void emit(const std::string& target) {
        run_in_work_dir("emit", std::string("'") + MOLLIFY_GEN + "' emit --target " + target + specs_arguments() + " --out .");
    }

    // The exact values of kernel k's quantity q at every point, computed
    // once for all three languages (MPFR: most of this test's time); all of
    // the kernel's quantities at once, point by point (the reference shares
    // each point's bases among them).
    static const std::vector<Real>& exact_values(std::size_t k, const acc::Reference& ref, QuantityId q) {
        static std::map<std::pair<std::size_t, int>, std::vector<Real>> cache;
        if (!cache.count({k, static_cast<int>(q)})) {
            std::vector<QuantityId> ids{q};
            for (const gen::CodeQuantity& c : (*kernels_)[k].code->quantities)
                if (c.id != q && !cache.count({k, static_cast<int>(c.id)})) ids.push_back(c.id);
            std::vector<std::vector<Real>> values(ids.size());
            for (const acc::Point& pt : *points_)
                for (std::size_t j = 0; j < ids.size(); ++j) values[j].push_back(ref.value(ids[j], pt.r, pt.h));
            for (std::size_t j = 0; j < ids.size(); ++j) cache[{k, static_cast<int>(ids[j])}] = std::move(values[j]);
        }
        return cache[{k, static_cast<int>(q)}];
    }
    static const acc::Reference& reference(std::size_t k) {
        static std::map<std::size_t, std::unique_ptr<acc::Reference>> cache;
        auto& r = cache[k];
        if (!r) {
            r = std::make_unique<acc::Reference>((*kernels_)[k].spec, (*kernels_)[k].dim);
            r->find_all_maxima();
        }
        return *r;
    }

    // Every function at every point against the exact value.
    static void check_functions(const std::string& language, const std::vector<double>& got) {
        std::size_t at = 0;
        const std::size_t n = points_->size();
        for (std::size_t ki = 0; ki < kernels_->size(); ++ki) {
            const Emitted& k = (*kernels_)[ki];
            check_constants(language, k, got, at);
            const acc::Reference& ref = reference(ki);
            for (const gen::CodeQuantity& q : k.code->quantities) {
                const std::vector<Real>& exact = exact_values(ki, ref, q.id);
                ASSERT_LE(at + 2 * n, got.size()) << language << ": output too short";
                const int p = mollify::detail::scale_power(q.id, k.dim);
                const double log_coefficient = q.log_h_coefficient ? k.code->constants[*q.log_h_coefficient].value : 0;
                Worst worst, tiny;
                for (std::size_t i = 0; i < n; ++i, at += 2) {
                    const acc::Point& pt = (*points_)[i];
                    const double y = got[at], y1 = got[at + 1];
                    EXPECT_EQ(std::bit_cast<std::uint64_t>(y), std::bit_cast<std::uint64_t>(y1))
                        << language << " " << k.spec << " " << q.name << "(r) is not " << q.name << "_h(r, 1) at r = " << pt.r;
                    const Real& x = exact[i];
                    // Singular at r = 0 (hess_radial of a 2D combination): the exact
                    // value is +-inf there, and so must the file's be.
                    if (boost::multiprecision::isinf(x)) {
                        EXPECT_EQ(y, static_cast<double>(x))
                            << language << " " << k.spec << " " << q.name << " at r = " << pt.r << ", h = " << pt.h;
                        continue;
                    }
                    // max |f_h| over the support, for the tiny values
                    const double max = ref.max_abs(q.id) * std::pow(pt.h, p) + std::abs(log_coefficient * std::log(pt.h));
                    auto intrinsic = [&] {
                        double e = acc::ulp_error(y, x);
                        if (e > 1 || !std::isfinite(y)) {
                            Real s = boost::multiprecision::abs(ref.slope(q.id, pt.r, pt.h));
                            if (pt.r <= pt.h) s += Real(std::abs(log_coefficient * std::log(pt.h)), 30);
                            e = std::min(e, error_in_ulps_of(y, x, s));
                        }
                        return e;
                    };
                    if (boost::multiprecision::abs(x) < tiny_fraction * max) {
                        // A tiny value near a root of f (W'' of the cubic at q = 1/3) passes by either metric.
                        const double e = acc::scaled_error(y, x, max);
                        if (e <= tiny_bound || intrinsic() <= function_bound) {
                            if (!(e <= tiny.ulps)) tiny = {e, pt};
                            continue;
                        }
                    }
                    const double e = intrinsic();
                    if (!(e <= worst.ulps)) worst = {e, pt};
                }
                std::printf("%-8s %-30s D%d %-22s max %8.3g intrinsic ulp at r=%.17g h=%.3g (%s); tiny %.3g ulp of max\n",
                            language.c_str(), k.spec.c_str(), k.dim, q.name.c_str(), worst.ulps, worst.at.r, worst.at.h,
                            worst.at.why, tiny.ulps);
                EXPECT_LE(worst.ulps, function_bound) << language << " " << k.spec << " D" << k.dim << " " << q.name
                                                      << " at r = " << worst.at.r << ", h = " << worst.at.h;
            }
        }
        EXPECT_EQ(at, got.size()) << language << ": output of unexpected length";
    }

    static std::vector<Emitted>* kernels_;
    static std::vector<acc::Point>* points_;
};

std::vector<Emitted>* Targets::kernels_ = nullptr;
std::vector<acc::Point>* Targets::points_ = nullptr;

// The three languages in one test: their files are checked against the
// same exact values, computed once (three tests would be three processes,
// each computing them again: 2/3 of this test's CI time).
void check_c();
void check_fortran();
void check_python();

TEST_F(Targets, CFortranAndPythonFilesCompileAndAgreeWithTheExactValues) {
    {
        SCOPED_TRACE("C");
        check_c();
    }
    {
        SCOPED_TRACE("Fortran");
        check_fortran();
    }
    {
        SCOPED_TRACE("Python");
        check_python();
    }
}

class TargetsC : public Targets {
public:
    static void run();
};
void check_c() { TargetsC::run(); }

void TargetsC::run() {
    ASSERT_NO_FATAL_FAILURE(prepare("c"));
    ASSERT_NO_FATAL_FAILURE(emit("c"));
    // Every emitted header alone, then the driver with all of them. Also clang's every warning
    // (-Weverything: a user's strictest flags, -Wdouble-promotion and -Wfloat-equal among them,
    // which C's float NAN and INFINITY and q == 0 had tripped in every file).
    for (const auto& f : fs::directory_iterator(language_dir / "c")) {
        const std::string include = "echo '#include \"" + f.path().string() + "\"' | ";
        ASSERT_NO_FATAL_FAILURE(run_in_work_dir("gcc", include + "gcc -std=c99 -Wall -Wextra -Werror -pedantic -x c -fsyntax-only -"));
        ASSERT_NO_FATAL_FAILURE(run_in_work_dir("clang", include + "clang -std=c99 -Weverything -Werror -x c -fsyntax-only -"));
    }
    write_text(language_dir / "driver.c", c_driver(*kernels_, points_->size()));
    // -O1: the optimiser's flow warnings (-Wmaybe-uninitialized ...) as at
    // -O2, for 60 % of its compile time (the driver with every kernel: 4.2
    // against 6.9 s; the same values, C99 contracts no multiply-add).
    ASSERT_NO_FATAL_FAILURE(run_in_work_dir("gcc", "gcc -std=c99 -O1 -Wall -Wextra -Werror -pedantic -I. driver.c -o c_driver -lm"));
    ASSERT_NO_FATAL_FAILURE(run_in_work_dir("C driver", "./c_driver"));
    static std::vector<double> got;  // static: EXPECT_NONFATAL_FAILURE's statement sees no locals
    got = read_doubles(language_dir / "c.bin");
    check_functions("c", got);
    // The comparison can fail: W of the first kernel at one point inside the
    // support, 1e-12 too large (~4500 ulp), is caught.
    std::size_t i = 0;
    while (i < points_->size() && !((*points_)[i].h == 1 && (*points_)[i].r > 0.1 && (*points_)[i].r < 0.5)) ++i;
    ASSERT_LT(i, points_->size());
    const std::size_t at = 1 + kernels_->front().code->constants.size() + 2 * i;
    got[at] *= 1 + 1e-12;
    got[at + 1] = got[at];
    EXPECT_NONFATAL_FAILURE(check_functions("c", got), "function_bound");
}

class TargetsFortran : public Targets {
public:
    static void run();
};
void check_fortran() { TargetsFortran::run(); }

void TargetsFortran::run() {
    ASSERT_NO_FATAL_FAILURE(prepare("fortran"));
    ASSERT_NO_FATAL_FAILURE(emit("fortran"));
    // Every emitted module checked; those the driver uses compiled (with the
    // same flags, so that compile is their check: gfortran's front end on the
    // missing Wendland modules, ~0.5 MB each, is seconds). -O1, as for C:
    // the flow warnings of an optimised build (the missing Wendland modules
    // 24.5 s at -O2, 20 s at -O1).
    // -Wextra -pedantic: a user's strict flags (-Wextra's -Wcompare-reals had flagged the
    // near-origin helper's real comparison in every module with a singular quantity).
    constexpr const char* fortran_flags = "gfortran -std=f2008 -pedantic -Wall -Wextra -Werror";
    std::set<std::string> compiled;
    for (const Emitted& k : *kernels_) compiled.insert(k.code->prefix + ".f90");
    for (const auto& f : fs::directory_iterator(language_dir / "fortran")) {
        if (compiled.count(f.path().filename().string())) continue;
        ASSERT_NO_FATAL_FAILURE(run_in_work_dir("gfortran", std::string(fortran_flags) + " -fsyntax-only '" + f.path().string() + "'"));
    }
    std::string objects;
    for (const Emitted& k : *kernels_) {
        ASSERT_NO_FATAL_FAILURE(run_in_work_dir("gfortran", std::string(fortran_flags) + " -O1 -c fortran/" +
                                                                k.code->prefix + ".f90 -o " + k.code->prefix + ".o"));
        objects += " " + k.code->prefix + ".o";
    }
    write_text(language_dir / "driver.f90", fortran_driver(*kernels_, points_->size()));
    ASSERT_NO_FATAL_FAILURE(
        run_in_work_dir("gfortran", "gfortran -std=f2008 -Wall -Werror -O1 driver.f90" + objects + " -o fortran_driver"));
    ASSERT_NO_FATAL_FAILURE(run_in_work_dir("Fortran driver", "./fortran_driver"));
    check_functions("fortran", read_doubles(language_dir / "fortran.bin"));
}

class TargetsPython : public Targets {
public:
    static void run();
};
void check_python() { TargetsPython::run(); }

void TargetsPython::run() {
    ASSERT_NO_FATAL_FAILURE(prepare("python"));
    ASSERT_NO_FATAL_FAILURE(emit("python"));
    write_text(language_dir / "driver.py", python_driver(*kernels_));
    // Debian's python3 (with python3-numpy), not whatever python3 is first on PATH.
    ASSERT_NO_FATAL_FAILURE(run_in_work_dir("python", "/usr/bin/python3 driver.py"));
    check_functions("python", read_doubles(language_dir / "python.bin"));
}

// The files of tests/golden/targets, regenerated: any change of a writer's
// output shows here (regenerate them with the command in their banners,
// --out tests/golden/targets, after checking the change).
TEST(TargetsGolden, RegeneratedFilesEqualTheGoldenOnes) {
    const fs::path golden = MOLLIFY_TARGETS_GOLDEN_DIR, out = work_dir().string() + "_golden";
    fs::remove_all(out);
    fs::create_directories(out);
    int files = 0;
    for (const char* target : {"c", "fortran", "python"}) {
        const auto r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target " + target +
                                       " --only cubic-spline --only combo:m=2,base=wendland:k=1 --out '" + out.string() + "'",
                                   out / "capture");
        ASSERT_EQ(r.status, 0) << r.err;
        for (const auto& f : fs::recursive_directory_iterator(golden / target)) {
            if (!f.is_regular_file()) continue;
            ++files;
            EXPECT_EQ(slurp(out / fs::relative(f.path(), golden)), slurp(f.path())) << f.path();
        }
    }
    EXPECT_EQ(files, 3 * 6);
}

TEST(TargetsCommandLine, BadTargetsAreErrorsNamingTheValue) {
    const fs::path out = work_dir().string() + "_bad";
    auto r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target cobol --only cubic-spline --out '" + out.string() + "'",
                         work_dir().string() + "_capture");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--target cobol is not a target (cpp, c, fortran, python"), std::string::npos) << r.err;
    r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target c --format data --only cubic-spline --out '" +
                        out.string() + "'",
                    work_dir().string() + "_capture");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--format data is for --target cpp only"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

// ---------------------------------------------------------------------------
// Conventions as data.

TEST(TargetsConventions, EveryTargetIsDescribedOnce) {
    std::set<std::string> names;
    for (const gen::Convention& c : gen::conventions()) EXPECT_TRUE(names.insert(c.target).second) << c.target;
    for (const char* t : {"cpp", "c", "fortran", "python", "phantom", "swift", "gadget4"}) EXPECT_TRUE(names.count(t)) << t;
    EXPECT_THROW(gen::convention("cobol"), mollify::Error);
    // Phantom's potential is -1/q outside: 4 pi times mollify's -1/(4 pi r).
    EXPECT_EQ(gen::potential_scale(gen::convention("phantom")).to_string(), "4 * pi^1");
    EXPECT_EQ(gen::potential_scale(gen::convention("c")).to_string(), "1");
}

// The separate normalisation constants are the codes' own (../shared/peers.md:
// Phantom's cubic cnormk = 1/pi, its Wendland C2 21/(16 pi); GADGET-4's 3D
// cubic NORM 8/pi with H the support).
TEST(TargetsConventions, SeparateNormalisationsAreTheCodesOwn) {
    auto norm = [](const char* target, const char* spec) {
        return gen::separate_normalisation(gen::convention(target), gen::make_kernel(mollify::parse_spec(spec), 3)).to_string();
    };
    EXPECT_EQ(norm("phantom", "cubic-spline"), "1 * pi^-1");
    EXPECT_EQ(norm("phantom", "wendland:k=1"), "21/16 * pi^-1");
    EXPECT_EQ(norm("gadget4", "cubic-spline"), "8 * pi^-1");
    EXPECT_THROW(norm("c", "cubic-spline"), mollify::Error);
}

// Correctly rounded square roots, decided exactly: against MPFR at 300 bits.
TEST(TargetsConventions, SquareRootsAreCorrectlyRounded) {
    for (const gen::Q& x : {gen::Q(2), gen::Q(3) / gen::Q(7), gen::Q(1) / gen::Q(1000003), gen::Q(4), gen::Q(9) / gen::Q(16),
                            gen::Q(123456789) / gen::Q(1000)}) {
        Real y(0, 300);
        mpfr_set_q(y.backend().data(), x.backend().data(), MPFR_RNDN);
        y = sqrt(y);
        EXPECT_LE(acc::ulp_error(gen::sqrt_to_double(x), y), 0.5) << x;
        EXPECT_EQ(gen::sqrt_to_float(x), static_cast<float>(static_cast<double>(y))) << x;  // double rounding is exact here
    }
    EXPECT_THROW(gen::sqrt_to_double(gen::Q(-1)), mollify::Error);
}

// SWIFT's gamma = H/(2 sigma) (Dehnen & Aly 2012, table 1; SWIFT's
// kernel_hydro.h prints 6 digits: ../shared/peers.md), and Phantom's hfact
// rule reproducing its stock C2, C4, C6 defaults to the digit they give.
TEST(TargetsConventions, SwiftGammaAndPhantomHfactFromTheExactSecondMoment) {
    auto gamma = [](const char* spec, int dim) {
        return gen::swift_gamma(gen::make_kernel(mollify::parse_spec(spec), dim)).value;
    };
    EXPECT_NEAR(gamma("cubic-spline", 3), 1.825742, 5e-7);
    EXPECT_NEAR(gamma("cubic-spline", 2), 1.778002, 5e-7);
    EXPECT_NEAR(gamma("cubic-spline", 1), 1.732051, 5e-7);
    EXPECT_NEAR(gamma("wendland:k=1", 3), 1.936492, 5e-7);
    EXPECT_NEAR(gamma("wendland:k=2", 3), 2.207940, 5e-7);
    EXPECT_NEAR(gamma("wendland:k=3", 3), 2.449490, 5e-7);
    const auto cubic = gen::make_kernel(mollify::parse_spec("cubic-spline"), 3);
    EXPECT_EQ(gen::swift_gamma(cubic).square, gen::Q(10) / gen::Q(3));  // gamma^2 = 1/(4 sigma^2), sigma^2 = 3/40
    auto hfact = [](const char* spec) { return gen::phantom_hfact(gen::make_kernel(mollify::parse_spec(spec), 3)); };
    // Phantom's six stock kernels keep its own hfact_default (peers.md)
    EXPECT_EQ(hfact("cubic-spline").value, 1.2);
    EXPECT_EQ(hfact("quartic-spline").value, 1.1);
    EXPECT_EQ(hfact("quintic-spline").value, 1.0);  // the equal-sigma rule: sqrt(162/175) = 0.96, which Phantom refuses
    EXPECT_EQ(hfact("wendland:k=1").square, gen::Q(169, 100));
    EXPECT_EQ(hfact("wendland:k=2").value, 1.5);
    EXPECT_EQ(hfact("wendland:k=3").value, 1.6);
    // The others: equal standard deviation with the cubic at 1.2 on radkern 2 (Dehnen & Aly), reproducing
    // Phantom's rounded C2, C4, C6 defaults to the digit they give ...
    auto sigma_rule = [](const char* spec) {
        const auto k = gen::make_kernel(mollify::parse_spec(spec), 3);
        const auto cubic = gen::make_kernel(mollify::parse_spec("cubic-spline"), 3);
        return gen::Q(36, 25) * gen::variance(cubic) / gen::variance(k);  // hfact^2, radkern 2 both
    };
    EXPECT_NEAR(gen::sqrt_to_double(sigma_rule("wendland:k=1")), 1.3, 0.05);
    EXPECT_NEAR(gen::sqrt_to_double(sigma_rule("wendland:k=2")), 1.5, 0.05);
    EXPECT_NEAR(gen::sqrt_to_double(sigma_rule("wendland:k=3")), 1.6, 0.05);
    EXPECT_EQ(hfact("wendland:k=2,l=1").square, sigma_rule("wendland:k=2,l=1"));
    // ... and at least 1, Phantom's checksetup's floor (mollifier:M=1 by the rule: sqrt(189/250) = 0.87)
    EXPECT_EQ(sigma_rule("mollifier:M=1"), gen::Q(189, 250));
    EXPECT_EQ(hfact("mollifier:M=1").value, 1.0);
    EXPECT_NE(hfact("mollifier:M=1").rule.find("Phantom's floor"), std::string::npos);
}

}  // namespace
