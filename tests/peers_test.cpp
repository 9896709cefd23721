// `mollify-gen emit --target phantom` (issue 19, item 1): Phantom's
// `module kernel` compiles with gfortran as Phantom builds it
// (-fdefault-real-8, after a stub `physcon`), and a driver written here
// evaluates every public procedure at the hard points (0, near 0, the
// breakpoints and their neighbours, near radkern on both sides, outside)
// and writes the bits; this test compares them with the exact values
// (MPFR, 256 bits, from mollify's certified quantities of the unit-support
// kernel: W = cnormk w(q)/h^3 = W_1(q/2)/(2h)^3, phi = 4 pi phi_1(q/2)/2) and
// checks Phantom's own consistency rules (test_kernel.f90's and more: wab0 =
// w(0), gradh0 = -3 w(0), get_kernel = wkern/grkern bitwise, dphidh = -phi -
// q dphi/dq, finite differences) and the normalisation 4 pi cnormk int w q^2
// = 1 exactly, which Phantom's own test does not check. (Finite differences
// of w and phi are subsumed: grkern and fsoft are compared with the exact
// derivatives.) A missing gfortran
// fails. Also: D != 3 and a kernel without a potential give clear errors.
#include "command.hpp"
#include "sanitized.hpp"

#include <catalogue.hpp>
#include <conventions.hpp>
#include <emit_metadata.hpp>
#include <radial.hpp>
#include <error.hpp>
#include <rounding.hpp>
#include <softening.hpp>
#include <softening_certificate.hpp>
#include <target.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
namespace gen = mollify::gen;
using mollify::testing::run_command;
using mollify::testing::slurp;

// Wendland C2, C4, C6, the cubic and quintic splines (inner breakpoints), a
// kernel Phantom does not have, and a missing Wendland function (sqrt,
// arcsech and Taylor pieces in its potential).
const char* const specs[] = {"wendland:k=1",     "wendland:k=2",         "wendland:k=3",
                             "cubic-spline",     "quintic-spline",       "wendland:k=2,l=1",
                             "wendland-missing:k=1"};

// The procedures' error bound, in ulps of max(|exact|, |q f'(q)|) (the error
// an exact evaluator makes from the rounding of q): the tables are the
// runtime's Precision::fast form, whose Horner and edge powers reach 24.9 ulp
// (README, "Runtime accuracy"); the exact power-of-two scalings add nothing.
// A wrong coefficient, scale or piece is off by far more.
constexpr double bound_ulps = 32;

fs::path work_dir() { return fs::path(MOLLIFY_PEERS_WORK_DIR); }

void run_in(const fs::path& dir, const std::string& what, const std::string& command) {
    const auto r = run_command("cd '" + dir.string() + "' && " + command, dir / "capture");
    ASSERT_EQ(r.status, 0) << what << " failed (a missing tool fails this test): " << command << "\n" << r.out << r.err;
}

std::vector<double> read_doubles(const fs::path& file) {
    const std::string bytes = slurp(file);
    std::vector<double> out(bytes.size() / sizeof(double));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(double));
    return out;
}

// The q at which the driver evaluates (Phantom's scaling: support radkern,
// 2 but for the quartic 2.5 and the quintic 3): near 0, fractions of
// radkern, every breakpoint and radkern with three neighbours each side, a
// grid, outside.
std::vector<double> points(double radkern, const std::vector<gen::Q>& unit_breaks) {
    std::vector<double> q = {0.0, 1e-300, 1e-12, 1e-6, 1e-3, 10.0, 1e6};
    for (double f : {0.05, 0.25, 0.5, 0.75, 0.95, 0.9995, 1.0, 1.25}) q.push_back(f * radkern);
    for (const gen::Q& b : unit_breaks) {
        if (b == 0) continue;
        double lo = static_cast<double>(b) * radkern, hi = lo;
        q.push_back(lo);
        for (int i = 0; i < 3; ++i) q.push_back(lo = std::nextafter(lo, 0.0)), q.push_back(hi = std::nextafter(hi, 4.0));
    }
    for (int i = 1; i < 64; ++i) q.push_back(radkern * i / 64 + 1e-3);
    return q;
}

// What the driver writes per point.
constexpr const char* columns[] = {"wkern", "grkern", "potensoft", "fsoft", "dphidh", "gsoft", "wkern_drag"};
constexpr int ncol = 7;

std::string driver(std::size_t n) {
    std::ostringstream s;
    s << "program driver\n use kernel\n implicit none\n integer, parameter :: n = " << n << "\n"
      << " real :: p(n), w, g, w1, g1, d, phi, f, gs\n integer :: i, u, v\n"
      << " open(newunit=u, file='points.bin', access='stream', form='unformatted', status='old')\n read(u) p\n close(u)\n"
      << " open(newunit=v, file='phantom.bin', access='stream', form='unformatted', status='replace')\n"
      << " write(v) radkern, radkern2, cnormk, wab0, gradh0, dphidh0, cnormk_drag, hfact_default, av_factor\n"
      << " do i = 1, n\n  call get_kernel(p(i)**2, p(i), w, g)\n  call get_kernel_grav1(p(i)**2, p(i), w1, g1, d)\n"
      << "  call kernel_softening(p(i)**2, p(i), phi, f)\n  call kernel_grad_soft(p(i)**2, p(i), gs)\n"
      << "  ! Phantom's test_kernel: the subroutines and functions agree exactly\n"
      << "  if (w /= wkern(p(i)**2, p(i)) .or. g /= grkern(p(i)**2, p(i)) .or. w1 /= w .or. g1 /= g) stop 3\n"
      << "  write(v) w, g, phi, f, d, gs, wkern_drag(p(i)**2, p(i))\n end do\n close(v)\n"
      << " write(*,'(a)') kernelname\nend program driver\n";
    return s.str();
}

// The exact value of a unit-support quantity at x, times c: MPFR at 2048 (8192 below 1e-3)
// bits (the pieces are evaluated expanded, and W's root of order up to 9 at
// the edge cancels ~9 x 53 bits at x = 1 - 2^-53).
// f(q/radkern) c, q/radkern in MPFR (not rounded to a double).
double exact_at(const gen::Radial& f, double q, double radkern, const gen::Exact& c) {
    const unsigned bits = q < 1e-3 ? 8192 : 2048;  // tiny q: E_n's r^-n terms cancel (2^-600: ~3000 bits)
    // q = 0: the limit (S, arcsech, log are 0 * inf there), from 2^-600 (x^2 log x far below a double's ulp)
    const bool limit = q == 0 && !f.form_at(gen::Q(0)).is_elementary();
    const gen::Real xr = gen::Real(limit ? std::ldexp(1.0, -600) : q, bits) / gen::Real(limit ? 1.0 : radkern, bits);
    return static_cast<double>(f.evaluate(xr, bits).first * c.evaluate(bits).first);
}
double exact_at(const gen::Radial& f, double x, const gen::Exact& c) { return exact_at(f, x, 1.0, c); }

double ulps_off(double y, double exact, double scale) {
    const double s = std::max(std::fabs(exact), scale);
    if (s == 0) return y == 0 ? 0 : INFINITY;
    return std::fabs(y - exact) / (std::nextafter(s, INFINITY) - s);
}

// Emitted in the test itself: a failure in SetUpTestSuite reads as "skipped"
// in ctest, not "failed".
void emit_phantom_modules() {
    fs::remove_all(work_dir());
    fs::create_directories(work_dir());
    std::string only;
    for (const char* s : specs) only += std::string(" --only '") + s + "'";
    const auto r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target phantom" + only + " --out '" +
                                   work_dir().string() + "'",
                               work_dir() / "capture");
    ASSERT_EQ(r.status, 0) << r.out << r.err;
}

// -fdefault-real-8 as Phantom's build; a physcon providing pi as the stock files' `use physcon, only:pi`.
void compile_and_run(const fs::path& dir, const fs::path& module, std::size_t n) {
    std::ofstream(dir / "physcon.f90") << "module physcon\n implicit none\n real, parameter :: pi = 4.*atan(1.)\nend module physcon\n";
    std::ofstream(dir / "driver.f90") << driver(n);
    const std::string fc = "gfortran -std=f2008 -fdefault-real-8 -fdefault-double-8 -Wall -Wextra -Werror -Wno-unused-dummy-argument -O2";
    ASSERT_NO_FATAL_FAILURE(run_in(dir, "gfortran", fc + " -c physcon.f90 -o physcon.o"));
    ASSERT_NO_FATAL_FAILURE(run_in(dir, "gfortran", fc + " -c '" + module.string() + "' -o kernel.o"));
    ASSERT_NO_FATAL_FAILURE(run_in(dir, "gfortran", fc + " -Wno-compare-reals driver.f90 kernel.o physcon.o -o driver"));
    ASSERT_NO_FATAL_FAILURE(run_in(dir, "driver", "./driver"));
}

TEST(Phantom, EveryProcedureMatchesTheExactKernelAndPhantomsRules) {
    ASSERT_NO_FATAL_FAILURE(emit_phantom_modules());
    for (const char* spec : specs) {
        SCOPED_TRACE(spec);
        const gen::KernelFacts facts = gen::kernel_facts({mollify::parse_spec(spec), 3});
        // Phantom's radkern: 2, but its stock quartic 2.5 and quintic 3 (peers.md; conventions' support_multiple)
        const gen::Q R = gen::support_multiple(gen::convention("phantom"), facts.kernel);
        const double Rd = static_cast<double>(R);
        if (std::string(spec) == "quintic-spline") {
            EXPECT_EQ(R, gen::Q(3));
        }
        const std::vector<double> q = points(Rd, facts.quantities.value.breaks);
        const fs::path dir = work_dir() / facts.id;
        fs::create_directories(dir);
        {
            std::ofstream f(dir / "points.bin", std::ios::binary);
            f.write(reinterpret_cast<const char*>(q.data()), static_cast<std::streamsize>(q.size() * sizeof(double)));
        }
        const fs::path module = work_dir() / "phantom" / ("kernel_" + facts.id + ".f90");
        ASSERT_TRUE(fs::exists(module)) << module;
        ASSERT_NO_FATAL_FAILURE(compile_and_run(dir, module, q.size()));
        const std::vector<double> d = read_doubles(dir / "phantom.bin");
        ASSERT_EQ(d.size(), 9 + q.size() * ncol);

        // Constants, against their exact values (0.5 ulp: correctly rounded).
        const gen::ExactKernel& k = facts.kernel;
        const gen::Radial& W1 = facts.quantities.value;
        const double radkern = d[0], cnormk = d[2], wab0 = d[3], gradh0 = d[4], dphidh0 = d[5];
        EXPECT_EQ(radkern, Rd);
        EXPECT_EQ(d[1], Rd * Rd);
        // cnormk w(q) = W_1(q/R)/R^3; Phantom's split w(0) = 1 where W_1(0) = N s(0) is a rational multiple of N:
        // cnormk = W_1(0)/R^3 then, w = W_1/W_1(0); else cnormk = N/R^3, w = s. And 4 pi cnormk int_0^R w q^2 dq = 1.
        const bool unit_w0 = k.shape.form_at(gen::Q(0)).is_elementary() && k.shape.at(gen::Q(0)).is_rational() &&
                             k.shape.at(gen::Q(0)).rational() != 0;
        const gen::Exact s0 = unit_w0 ? k.shape.at(gen::Q(0)) : gen::Exact(gen::Q(1));
        const gen::Exact cnormk_exact = k.normalisation * s0 * (gen::Q(1) / (R * R * R));
        EXPECT_EQ(cnormk, gen::round_to_double(cnormk_exact));
        // int_0^R w q^2 dq = R^3 int_0^1 (s/s(0)) x^2 dx
        const gen::Exact mass = gen::sphere_measure(3) * cnormk_exact * gen::Exact(R * R * R) *
                                gen::radial_integral(k.shape, 2) * s0.inverse();
        EXPECT_TRUE(mass == gen::Exact(gen::Q(1))) << mass.to_string();
        if (unit_w0) {
            EXPECT_EQ(wab0, 1.0);
            EXPECT_EQ(gradh0, -3.0);
        }
        // hfact_default: conventions' phantom_hfact (its rule tested in targets_test); cubic: exactly 1.2's double.
        EXPECT_EQ(d[7], gen::phantom_hfact(k).value);
        if (std::string(spec) == "cubic-spline") {
            EXPECT_EQ(d[7], 1.2);
            // Phantom's stock values (its expressions round twice: within 1 ulp)
            EXPECT_LE(ulps_off(cnormk, 1 / M_PI, 0), 1);
            EXPECT_EQ(d[8], 124.0 / 105.0);
        }
        if (std::string(spec) == "wendland:k=1") {
            EXPECT_LE(ulps_off(cnormk, 1.3125 / M_PI, 0), 1);  // stock C2: 1.3125/pi = 21/(16 pi)
            EXPECT_LE(ulps_off(d[6], 105.0 / (64.0 * M_PI), 0), 1);
            EXPECT_EQ(d[8], 10.0 / 9.0);
            EXPECT_EQ(dphidh0, 1.5);
        }
        if (std::string(spec) == "quintic-spline") {  // Phantom's stock kernel_quintic.f90 (f68ddd74), w(0) = 66 there
            EXPECT_LE(ulps_off(cnormk, 66.0 / (120.0 * M_PI), 0), 1);
            EXPECT_LE(ulps_off(d[6], 66.0 / (168.0 * M_PI), 0), 1);  // cnormk_drag
            EXPECT_EQ(dphidh0, 239.0 / 210.0);
            EXPECT_EQ(d[8], 2771.0 / 1890.0);  // av_factor
        }

        // Exact references (unit support, x = q/R).
        const gen::Radial& phi1 = *facts.quantities.potential;
        const gen::Radial dphi1 = phi1.derivative(), d2phi1 = dphi1.derivative(), d3phi1 = d2phi1.derivative();
        const gen::Radial dW1 = W1.derivative();
        const gen::Exact invN = (k.normalisation * s0).inverse(), pi4 = gen::sphere_measure(3);
        double worst = 0;
        std::string worst_at;
        for (std::size_t i = 0; i < q.size(); ++i) {
            const double* y = &d[9 + i * ncol];
            const gen::Q r1 = gen::Q(1) / R, r2 = r1 * r1;
            const double w = exact_at(W1, q[i], Rd, invN), dw = exact_at(dW1, q[i], Rd, invN * r1);
            const double phi = exact_at(phi1, q[i], Rd, pi4 * r1), f = exact_at(dphi1, q[i], Rd, pi4 * r2);
            const double f2 = exact_at(d2phi1, q[i], Rd, pi4 * r2 * r1);
            // gsoft' = q phi''': the scale of the rounding of x = q/R where R is not a power of two
            const double f3 = Rd == 2 ? 0.0 : exact_at(d3phi1, q[i], Rd, pi4 * r2 * r2);
            double exact[ncol] = {w, dw, phi, f, -phi - q[i] * f, q[i] * f2 - f, q[i] * q[i] * w};
            if (q[i] == 0)  // the limits seen from 2^-600 (exact_at): below 1e-150 they are the odd functions' 0
                for (double& e : exact) e = std::fabs(e) < 1e-150 ? 0.0 : e;
            const double scale[ncol] = {std::fabs(q[i] * dw), std::fabs(q[i] * f2 * q[i]) + std::fabs(dw), std::fabs(q[i] * f),
                                        std::fabs(q[i] * f2), std::fabs(phi) + std::fabs(q[i] * f),
                                        std::fabs(f) + std::fabs(q[i] * f2) + std::fabs(q[i] * q[i] * f3),
                                        std::fabs(q[i] * q[i] * dw) + std::fabs(q[i] * w)};
            for (int c = 0; c < ncol; ++c) {
                if (q[i] == 0 && (c == 5)) continue;  // gsoft's reference q phi'' - phi' is exact at 0 below
                const double u = ulps_off(y[c], exact[c], scale[c]);
                if (u > worst) worst = u, worst_at = std::string(columns[c]) + " at q = " + std::to_string(q[i]);
                EXPECT_LE(u, bound_ulps) << columns[c] << " at q = " << q[i] << ": " << y[c] << " vs " << exact[c];
            }
            // Outside the support: W = 0 and Phantom's exterior forms.
            if (q[i] > Rd) {
                EXPECT_EQ(y[0], 0.0);
                EXPECT_EQ(y[1], 0.0);
                EXPECT_LE(ulps_off(y[2], -1 / q[i], 0), 2);
                EXPECT_LE(ulps_off(y[3], 1 / (q[i] * q[i]), 0), 2);
                EXPECT_EQ(y[4], 0.0);
            }
            // Phantom's rule dphidh = -phi - q dphi/dq from the module's own values (their rounding: 4 ulp of the scale).
            EXPECT_LE(ulps_off(y[4], -y[2] - q[i] * y[3], std::fabs(y[2]) + std::fabs(q[i] * y[3])), 2 * bound_ulps);
        }
        std::printf("%s: worst %.2f ulp (%s)\n", spec, worst, worst_at.c_str());
        // wab0 = w(0), gradh0 = -3 w(0), dphidh0 = -phi(0): the exact values (limits at 0 for the
        // missing Wendland function's S and arcsech r) correctly rounded, bit for bit.
        const gen::Exact w0 = gen::value_at(W1.form_at(gen::Q(0)), gen::Q(0)) * invN;
        EXPECT_EQ(wab0, gen::round_to_double(w0)) << w0.to_string();
        EXPECT_EQ(gradh0, gen::round_to_double(w0 * gen::Q(-3)));
        EXPECT_EQ(dphidh0, gen::round_to_double(gen::value_at(phi1.form_at(gen::Q(0)), gen::Q(0)) * pi4 * (gen::Q(-1) / R)));
        // wab0 = w(0) exactly (the function at 0 is the constant term), dphidh0 = dphidh(0).
        EXPECT_EQ(d[9 + 0], wab0);
        EXPECT_EQ(d[9 + 4], dphidh0);
    }
}

TEST(PhantomErrors, PhantomIsThreeDimensional) {
    const gen::KernelFacts f = gen::kernel_facts({mollify::parse_spec("cubic-spline"), 2});
    const gen::Tables tables = gen::rounded_tables(f);
    try {
        gen::write_phantom({f, tables, gen::convention("phantom")}, "test");
        FAIL() << "a 2D kernel was written for Phantom";
    } catch (const gen::Error& e) {
        EXPECT_NE(std::string(e.what()).find("3D only"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("D = 2"), std::string::npos) << e.what();
    }
}

// --target gadget4: each header compiles with g++ -std=c++11 -Wall -Wextra -Werror in
// its dimension (ONEDIMS, TWODIMS, 3D); a driver evaluates kernel_main
// (modes -1, 0, 1) with hinv3 = hinv4 = 1 at the hard points and, in 3D, the
// g-factors at h = 1 and h = 1e-3 (fac_n = h^-(n+1) E_n(r/h)); compared with
// MPFR: wk = W, dwk = W' (mollify's certified quantities), fac0 = -4 pi phi,
// fac1 = -4 pi phi', fac2 = -4 pi r^2 (phi'' - phi'/r)/r^2 (the potential's
// own quantities), fac3..5 = softening.hpp's E_n (tested there against the
// recursion and GADGET-4's expanded forms). Bound: 32 ulp of max(|exact|,
// |u f'(u)|) as for Phantom (the Precision::fast form), plus pow(h, -(n+1)).
TEST(Gadget4, KernelMainAndGfactorsMatchTheExactValues) {
    const fs::path dir = work_dir().string() + "_gadget4";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // Under the sanitizers without the missing Wendland function (sanitized.hpp):
    // the Phantom test above takes it through the same shared C/Fortran pieces.
    // A sixth-order combination: its fac_n term by term (multipole_factor_parts); planned as one merged
    // sum they were up to ~1.7e4 ulp off (stop 90, a by-hand run of this test).
    std::vector<const char*> g4specs = {"cubic-spline", "quartic-spline", "wendland:k=1", "combo:m=2,base=wendland:k=1",
                                        "combo:m=3,base=wendland:k=3,l=2"};
    if (!mollify::testing::sanitized_build) g4specs.push_back("wendland-missing:k=1");
    std::string only;
    for (const char* sp : g4specs) only += std::string(" --only '") + sp + "'";
    const auto r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target gadget4" + only + " --out '" + dir.string() + "'",
                               dir / "capture");
    ASSERT_EQ(r.status, 0) << r.err;
    std::vector<double> u = {0.0, 1e-300, 1e-12, 1e-6, 1e-3, 0.1, 0.25, 0.5, 0.75, 0.9, 0.999, 1.0, 1.5, 10.0};
    for (double b : {0.2, 0.5, 0.6, 1.0}) {  // the breakpoints (the quartic spline's at 1/5 and 3/5), three ulps either side
        double lo = b, hi = b;
        for (int i = 0; i < 3; ++i) u.push_back(lo = std::nextafter(lo, 0.0)), u.push_back(hi = std::nextafter(hi, 4.0));
    }
    for (int i = 1; i < 40; ++i) u.push_back(i / 40.0 + 1e-4);
    for (const char* spec : g4specs)
        for (int dim = 1; dim <= 3; ++dim) {
            SCOPED_TRACE(std::string(spec) + " D=" + std::to_string(dim));
            const gen::KernelFacts facts = gen::kernel_facts({mollify::parse_spec(spec), dim});
            const bool gravity = dim == 3 && facts.quantities.potential.has_value();
            std::ostringstream d;
            d << "#include <cstdio>\n#include \"gadget4/" << facts.id << ".h\"\nint main() {\n  const double u[] = {";
            for (double x : u) d << gen::exact_decimal_literal(x) << ", ";
            d << "};\n  for (double x : u) {\n    double w = -1, dw = -1, w1 = -1, dw1 = -1;\n"
              << "    kernel_main(x, 1, 1, &w, &dw, COMPUTE_WK_AND_DWK);\n    kernel_main(x, 1, 1, &w1, &dw, COMPUTE_DWK);\n"
              << "    kernel_main(x, 1, 1, &w, &dw1, COMPUTE_WK);\n    if (w1 != -1 || dw1 != -1) return 3;\n"
              << "    std::fwrite(&w, 8, 1, stdout);\n    std::fwrite(&dw, 8, 1, stdout);\n";
            if (gravity)
                d << "    double fac[6];\n    mollify_g4_" << facts.id << "_gfactors(x, 1.0, fac);\n    std::fwrite(fac, 8, 6, stdout);\n"
                  << "    mollify_g4_" << facts.id << "_gfactors(x * 1e-3, 1e-3, fac);\n    std::fwrite(fac, 8, 6, stdout);\n";
            d << "  }\n}\n";
            std::ofstream(dir / (facts.id + ".cpp")) << d.str();
            const std::string flags = dim == 1 ? " -DONEDIMS" : dim == 2 ? " -DTWODIMS" : "";
            // GADGET-4's own -std=c++11 (its buildsystem/Makefile.comp.gcc), where hex floats are errors
            ASSERT_NO_FATAL_FAILURE(run_in(dir, "g++", "g++ -std=c++11 -O2 -Wall -Wextra -Werror" + flags + " " + facts.id +
                                                           ".cpp -o " + facts.id));
            ASSERT_NO_FATAL_FAILURE(run_in(dir, facts.id, "(./" + facts.id + " > " + facts.id + ".bin)"));
            const std::vector<double> y = read_doubles(dir / (facts.id + ".bin"));
            const std::size_t per = gravity ? 14 : 2;
            ASSERT_EQ(y.size(), u.size() * per);
            const gen::Exact one(gen::Q(1));
            const gen::Radial& W = facts.quantities.value;
            const gen::Radial dW = W.derivative(), d2W = dW.derivative();
            std::vector<gen::Radial> fac;
            int finite = -1;
            if (gravity) fac = gen::gadget_gfactors(facts.kernel, gen::max_gfactor), finite = gen::finite_at_origin(fac);
            double worst = 0;
            for (std::size_t i = 0; i < u.size(); ++i) {
                const double* v = &y[i * per];
                const double x = u[i];
                auto check = [&](double got, double exact, double scale, const std::string& what, double bound) {
                    if (x == 0 && std::fabs(exact) < 1e-150) exact = 0;
                    const double e = ulps_off(got, exact, scale);
                    worst = std::max(worst, e);
                    EXPECT_LE(e, bound) << what << " at u = " << x << ": " << got << " vs " << exact;
                };
                check(v[0], exact_at(W, x, one), std::fabs(x * exact_at(dW, x, one)), "wk", bound_ulps);
                check(v[1], exact_at(dW, x, one), std::fabs(x * exact_at(d2W, x, one)), "dwk", bound_ulps);
                if (!gravity) continue;
                const gen::Exact m4pi = gen::sphere_measure(3) * gen::Q(-1);
                const gen::Radial& phi = *facts.quantities.potential;
                const gen::Radial& dphi = *facts.quantities.dpotential;
                const double refs[3] = {exact_at(phi, x, m4pi), exact_at(dphi, x, m4pi),
                                        x * x * exact_at(*facts.quantities.potential_hess_radial, x, m4pi)};
                for (int n = 0; n <= finite; ++n) {
                    const double exact = n < 3 && x > 1e-100 ? refs[n] : exact_at(fac[n], x, one);
                    const double scale = std::fabs(x * exact_at(fac[n].derivative(), x, one));
                    check(v[2 + n], exact, scale, "fac" + std::to_string(n), bound_ulps);
                    // h = 1e-3: h^-(n+1) times the same E_n, r/h rounded once, pow: 2 more ulp
                    const double hp = std::pow(1e3, n + 1);
                    check(v[8 + n], exact * hp, scale * hp, "fac" + std::to_string(n) + " at h = 1e-3", bound_ulps + 2);
                }
            }
            std::printf("%s D=%d: worst %.2f ulp\n", spec, dim, worst);
        }
}

// GADGET-4's gravity tree softens with its cubic spline whatever the SPH
// kernel: one unit takes a header whole (NORM, kernel_main) and another
// kernel's with MOLLIFY_G4_SOFTENING_ONLY (its prefixed functions only), in
// either order, under GADGET-4's -std=c++11 -Wall -Wextra -Werror. Without the
// macro the two headers' NORM and kernel_main clash, which must not compile.
// The values: kernel_main the SPH kernel's, the g-factors the other's (32 ulp
// as above), the Plummer factors E_0(0) = 14/5 (GADGET-4's 2.8) and 3.
TEST(Gadget4, SofteningOfOneKernelBesideTheSphKernelOfAnother) {
    const fs::path dir = work_dir().string() + "_gadget4_softening";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target gadget4 --only cubic-spline --only wendland:k=1 --dim 3 --out '" +
                                   dir.string() + "'",
                               dir / "capture");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string body =
        "#include <cstdio>\nint main() {\n  double w = 0, dw = 0, fac[6];\n  kernel_main(0.3, 1, 1, &w, &dw, COMPUTE_WK_AND_DWK);\n"
        "  mollify_g4_cubic_spline_D3_gfactors(0.3, 1.0, fac);\n  const double p[2] = {MOLLIFY_G4_cubic_spline_D3_PLUMMER, "
        "MOLLIFY_G4_wendland_k_1_D3_PLUMMER};\n  std::fwrite(&w, 8, 1, stdout);\n  std::fwrite(&dw, 8, 1, stdout);\n"
        "  std::fwrite(fac, 8, 6, stdout);\n  std::fwrite(p, 8, 2, stdout);\n}\n";
    const std::string sph = "#include \"gadget4/wendland_k_1_D3.h\"\n";
    const std::string soft = "#define MOLLIFY_G4_SOFTENING_ONLY\n#include \"gadget4/cubic_spline_D3.h\"\n#undef MOLLIFY_G4_SOFTENING_ONLY\n";
    const std::string cc = "g++ -std=c++11 -O2 -Wall -Wextra -Werror ";
    std::ofstream(dir / "sph_first.cpp") << sph + soft + body;
    std::ofstream(dir / "softening_first.cpp") << soft + sph + body;
    std::ofstream(dir / "clash.cpp") << sph + "#include \"gadget4/cubic_spline_D3.h\"\n" + body;
    const gen::KernelFacts c2 = gen::kernel_facts({mollify::parse_spec("wendland:k=1"), 3});
    const gen::KernelFacts cubic = gen::kernel_facts({mollify::parse_spec("cubic-spline"), 3});
    const std::vector<gen::Radial> fac = gen::gadget_gfactors(cubic.kernel, gen::max_gfactor);
    const gen::Exact one(gen::Q(1));
    for (const char* unit : {"sph_first", "softening_first"}) {
        SCOPED_TRACE(unit);
        ASSERT_NO_FATAL_FAILURE(run_in(dir, "g++", cc + unit + ".cpp -o " + unit));
        ASSERT_NO_FATAL_FAILURE(run_in(dir, unit, std::string("(./") + unit + " > " + unit + ".bin)"));
        const std::vector<double> y = read_doubles(dir / (std::string(unit) + ".bin"));
        ASSERT_EQ(y.size(), 10u);
        const double x = 0.3;
        const gen::Radial& W = c2.quantities.value;
        const gen::Radial dW = W.derivative();
        // kernel_main is NORM w(u): W itself on support 1 (GADGET-4's hinv3 = hinv4 = 1)
        EXPECT_LE(ulps_off(y[0], exact_at(W, x, one), std::fabs(x * exact_at(dW, x, one))), bound_ulps);
        EXPECT_LE(ulps_off(y[1], exact_at(dW, x, one), std::fabs(x * exact_at(dW.derivative(), x, one))), bound_ulps);
        for (int n = 0; n < 6; ++n)
            EXPECT_LE(ulps_off(y[2 + n], exact_at(fac[n], x, one), std::fabs(x * exact_at(fac[n].derivative(), x, one))), bound_ulps)
                << "the cubic spline's fac" << n;
        EXPECT_EQ(y[8], 2.8);
        EXPECT_EQ(y[9], 3.0);
    }
    const auto clash = run_command("cd '" + dir.string() + "' && " + cc + "clash.cpp -o clash", dir / "capture");
    EXPECT_NE(clash.status, 0) << "two whole headers in one unit compiled";
}

// GADGET-4's EXPLICIT_VECTORIZATION calls kernel_main_vector(u, hinv3, hinv4,
// &wk, &dwk) on four neighbours at once in its vectorclass Vec4d, NORM
// already in the hinv3 and hinv4 its loops pass (src/sph/density.cc,
// hydra.cc). Here a stand-in Vec4d with what the headers use (lane-wise
// + - * /, < and >, select, store and load; GADGET-4's vectorclass is not in
// CI: checked by hand with it, README "Integration with GADGET-4"), under
// GADGET-4's -std=c++11 -Wall -Wextra -Werror, in every dimension, at the
// breakpoints, their neighbours and beyond the support edge:
// - the form: four-lane functions for kernels of few polynomial pieces, each
//   lane by the scalar functions for the others (the missing Wendland
//   function's sqrt and arcsech);
// - with x86-64's baseline flags (no FMA, so nothing fused), each lane is
//   kernel_main's value bit for bit (hinv3 = 2, hinv4 = 4): the same
//   arithmetic, the pieces chosen as the scalar chain chooses them (a piece
//   selected on the wrong side of a breakpoint, NORM applied twice, or hinv3
//   and hinv4 swapped, differs);
// - each lane within 32 ulp of the exact W and W' (as kernel_main above),
//   also built with FMA where this machine has it (the compiler may then fuse
//   a combination's sum of terms differently on four lanes than on one).
TEST(Gadget4, FourLaneFormIsTheScalarFormLaneByLane) {
    const fs::path dir = work_dir().string() + "_gadget4_vector";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::vector<std::string> vspecs = {"cubic-spline", "wendland:k=2", "combo:m=2,base=wendland:k=1", "wendland-missing:k=1"};
    std::string only;
    for (const std::string& sp : vspecs) only += " --only '" + sp + "'";
    const auto r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target gadget4" + only + " --out '" + dir.string() + "'",
                               dir / "capture");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string vec4d =
        "struct Vec4db {\n  bool b[4];\n};\nstruct Vec4d {\n  double v[4];\n  Vec4d() { for (int i = 0; i < 4; ++i) v[i] = 0; }\n"
        "  Vec4d(double x) { for (int i = 0; i < 4; ++i) v[i] = x; }\n"
        "  void store(double *p) const { for (int i = 0; i < 4; ++i) p[i] = v[i]; }\n"
        "  Vec4d &load(const double *p) { for (int i = 0; i < 4; ++i) v[i] = p[i]; return *this; }\n};\n"
        "#define LANEWISE(R, op, f) inline R operator op(Vec4d a, Vec4d b) { R r; for (int i = 0; i < 4; ++i) r.f[i] = a.v[i] op b.v[i]; return r; }\n"
        "LANEWISE(Vec4d, +, v) LANEWISE(Vec4d, -, v) LANEWISE(Vec4d, *, v) LANEWISE(Vec4d, /, v) LANEWISE(Vec4db, <, b) LANEWISE(Vec4db, >, b)\n"
        "inline Vec4d select(Vec4db s, Vec4d a, Vec4d b) { Vec4d r; for (int i = 0; i < 4; ++i) r.v[i] = s.b[i] ? a.v[i] : b.v[i]; return r; }\n";
    std::vector<double> u = {0.0, 1e-300, 1e-9, 0.1, 0.2, 0.37, 0.6, 0.75, 0.9, 0.999, 1.5, 10.0};
    for (double b : {0.5, 1.0}) {  // the breakpoints (the cubic spline's and the combination's at 1/2), three ulps either side
        double lo = b, hi = b;
        u.push_back(b);
        for (int i = 0; i < 3; ++i) u.push_back(lo = std::nextafter(lo, 0.0)), u.push_back(hi = std::nextafter(hi, 4.0));
    }
    while (u.size() % 4 != 0) u.push_back(0.5);
    const bool fma = __builtin_cpu_supports("fma") && __builtin_cpu_supports("avx2");
    for (const std::string& spec : vspecs)
        for (int dim = 1; dim <= 3; ++dim) {
            const gen::KernelFacts facts = gen::kernel_facts({mollify::parse_spec(spec), dim});
            const std::string unit = facts.id;
            SCOPED_TRACE(unit);
            const std::string header = slurp(dir / "gadget4" / (unit + ".h"));
            const bool four_lanes = header.find("_w_v4(u)") != std::string::npos;
            EXPECT_EQ(four_lanes, spec != "wendland-missing:k=1") << "kernel_main_vector's form";
            std::ostringstream d;
            d << "#include <cstdio>\n" << vec4d << "#define EXPLICIT_VECTORIZATION\n#include \"gadget4/" << unit << ".h\"\n"
              << "int main() {\n  const double u[] = {";
            for (double x : u) d << gen::exact_decimal_literal(x) << ", ";
            d << "};\n  for (unsigned b = 0; b < sizeof u / sizeof *u; b += 4) {\n    Vec4d x, w(-1), dw(-1);\n    x.load(u + b);\n"
              << "    kernel_main_vector(x, Vec4d(NORM * 2.0), Vec4d(NORM * 4.0), &w, &dw);\n    for (int i = 0; i < 4; ++i) {\n"
              << "      double sw = -2, sd = -2;\n      kernel_main(u[b + i], 2.0, 4.0, &sw, &sd, COMPUTE_WK_AND_DWK);\n"
              << "      const double out[4] = {w.v[i], dw.v[i], sw, sd};\n      std::fwrite(out, 8, 4, stdout);\n    }\n  }\n}\n";
            std::ofstream(dir / (unit + ".cpp")) << d.str();
            const gen::Exact one(gen::Q(1));
            const gen::Radial& W = facts.quantities.value;
            const gen::Radial dW = W.derivative(), d2W = dW.derivative();
            const std::string flags = dim == 1 ? " -DONEDIMS" : dim == 2 ? " -DTWODIMS" : "";
            for (const std::string& isa : fma ? std::vector<std::string>{"", " -mavx2 -mfma"} : std::vector<std::string>{""}) {
                SCOPED_TRACE(isa.empty() ? "baseline" : isa);
                const std::string bin = unit + (isa.empty() ? "" : "_fma");
                ASSERT_NO_FATAL_FAILURE(
                    run_in(dir, "g++", "g++ -std=c++11 -O2 -Wall -Wextra -Werror" + flags + isa + " " + unit + ".cpp -o " + bin));
                ASSERT_NO_FATAL_FAILURE(run_in(dir, bin, "(./" + bin + " > " + bin + ".bin)"));
                const std::vector<double> y = read_doubles(dir / (bin + ".bin"));
                ASSERT_EQ(y.size(), 4 * u.size());
                for (std::size_t i = 0; i < u.size(); ++i) {
                    const double* v = &y[4 * i];
                    const double x = u[i];
                    if (isa.empty()) {
                        EXPECT_EQ(v[0], v[2]) << "wk at u = " << x << ": four lanes against kernel_main";
                        EXPECT_EQ(v[1], v[3]) << "dwk at u = " << x << ": four lanes against kernel_main";
                    }
                    double w = exact_at(W, x, one), dw = exact_at(dW, x, one);
                    if (x == 0 && std::fabs(dw) < 1e-150) dw = 0;  // the limit from 2^-600 (exact_at), as above
                    // hinv3 = 2, hinv4 = 4: exact scalings, and a form that swaps them differs
                    EXPECT_LE(ulps_off(v[0] / 2, w, std::fabs(x * dw)), bound_ulps) << "wk at u = " << x << ": " << v[0] << " vs 2 x " << w;
                    EXPECT_LE(ulps_off(v[1] / 4, dw, std::fabs(x * exact_at(d2W, x, one))), bound_ulps)
                        << "dwk at u = " << x << ": " << v[1] << " vs 4 x " << dw;
                }
            }
        }
}

TEST(PhantomErrors, HigherOrderKernelsNameTheirSecondMoment) {
    const fs::path out = work_dir().string() + "_combo";
    const auto r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target phantom --only combo:m=2,base=wendland:k=1 --out '" +
                                   out.string() + "'",
                               work_dir().string() + "_combo_capture");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("combo:m=2,base=wendland:k=1"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("second moment"), std::string::npos) << r.err;
}

// The files of tests/golden/peers, regenerated: any change of the writer's
// output shows here (regenerate with the command in their banners,
// --out tests/golden/peers, after checking the change).
TEST(PeersGolden, RegeneratedFilesEqualTheGoldenOnes) {
    const fs::path golden = MOLLIFY_PEERS_GOLDEN_DIR, out = work_dir().string() + "_golden";
    fs::remove_all(out);
    fs::create_directories(out);
    int files = 0;
    const auto r = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target phantom --only cubic-spline --only wendland:k=1 --out '" +
                                   out.string() + "'",
                               out / "capture");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto g = run_command(std::string("'") + MOLLIFY_GEN + "' emit --target gadget4 --only cubic-spline --only wendland:k=1 --out '" +
                                   out.string() + "'",
                               out / "capture");
    ASSERT_EQ(g.status, 0) << g.err;
    for (const char* target : {"phantom", "gadget4"})
        for (const auto& f : fs::recursive_directory_iterator(golden / target)) {
            if (!f.is_regular_file()) continue;
            ++files;
            EXPECT_EQ(slurp(out / fs::relative(f.path(), golden)), slurp(f.path())) << f.path();
        }
    EXPECT_EQ(files, 2 + 6);
}

}  // namespace
