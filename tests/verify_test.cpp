// Verification must be able to fail (issue 20): kernels built wrong in each
// way a published code got them wrong are caught with the right diagnosis,
// and mollify's own run-time kernels pass at <= 1 ulp (they are within 0.51
// ulp of the exact values, README "Runtime accuracy"; 1 leaves room for the
// one rounding of the scale h^p). The wrong kernels are built from the
// generator's exact polynomials (never typed coefficients) or from the
// runtime's values.
#include <mollify/exact.hpp>
#include <mollify/testing.hpp>
#include <mollify/verify.hpp>

#include "closed_form.hpp"
#include "sanitized.hpp"
#include "conventions.hpp"
#include "verify/reference.hpp"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <string>
#include <vector>

namespace {

namespace v = mollify::verify;
using mollify::verify::DiagnosisKind;
using mollify::verify::Quantity;

mollify::Kernel runtime(const std::string& spec, int dim) { return mollify::exact::kernel(spec, dim); }

// The runtime's quantity as a callable.
std::function<double(double, double)> quantity_of(const mollify::Kernel& k, Quantity q) {
    const mollify::QuantityId id = q == Quantity::value         ? mollify::QuantityId::value
                                   : q == Quantity::dr          ? mollify::QuantityId::dr
                                   : q == Quantity::potential   ? mollify::QuantityId::potential
                                   : q == Quantity::grad_over_r ? mollify::QuantityId::grad_over_r
                                                                : mollify::QuantityId::dpotential;
    return [k, id](double r, double h) { return k(id, r, h); };
}

void expect_kind(const v::Report& r, DiagnosisKind kind, const std::string& text = "") {
    EXPECT_FALSE(r.passed()) << r.to_string();
    ASSERT_TRUE(r.diagnosis.has_value()) << r.to_string();
    EXPECT_EQ(v::name(r.diagnosis->kind), v::name(kind)) << r.to_string();
    if (!text.empty()) {
        EXPECT_NE(r.diagnosis->text.find(text), std::string::npos) << "wanted '" << text << "' in\n" << r.to_string();
    }
}

// W of a one-piece polynomial kernel as expanded monomials sum c_k q^k
// (SWIFT's and many codes' form), coefficients the exact ones rounded.
std::vector<double> expanded_coefficients(const std::string& spec, int dim) {
    const mollify::accuracy::Reference ref(spec, dim);
    mollify::gen::Laurent p;
    mollify::gen::Atom factor;
    EXPECT_EQ(ref.kernel().W.pieces.size(), 1u);
    EXPECT_TRUE(ref.kernel().W.pieces.front().single_polynomial(&p, &factor));
    std::vector<double> c;
    for (int k = 0; k <= p.high(); ++k)
        c.push_back(static_cast<double>(
            (mollify::gen::Exact(p.coefficient(k)) * mollify::gen::Exact::of(factor)).evaluate(200).first));
    return c;
}

template <class T>
T expanded(const std::vector<double>& c, T r, T h, int dim) {
    const T q = r / h;
    if (q >= 1) return 0;
    T s = 0;
    for (std::size_t k = c.size(); k-- > 0;) s = s * q + static_cast<T>(c[k]);
    T scale = 1;
    for (int d = 0; d < dim; ++d) scale *= h;
    return s / scale;
}

TEST(Verify, OwnRuntimeKernelsPassWithinOneUlp) {
    const std::pair<const char*, int> kernels[] = {
        {"wendland:k=1", 3}, {"wendland:k=2", 3}, {"cubic-spline", 3}, {"combo:m=2,base=wendland:k=1", 3},
        {"mollifier:M=4", 3}, {"wendland:k=1", 2}, {"mollifier:M=4", 2}, {"cubic-spline", 1}};
#ifdef MOLLIFY_SANITIZED_BUILD  // the memory of verify is the same for every kernel: two (18 s for all eight)
    const std::span<const std::pair<const char*, int>> checked(kernels, 2);
#else
    const std::span<const std::pair<const char*, int>> checked(kernels);
#endif
    for (const auto& [spec, dim] : checked) {
        const mollify::Kernel k = runtime(spec, dim);
        for (Quantity q : {Quantity::value, Quantity::dr, Quantity::potential, Quantity::force, Quantity::grad_over_r}) {
            if (!k.has_potential() && (q == Quantity::potential || q == Quantity::force)) continue;
            // Potentials: 4 ulps (the runtime's potentials are within 3.39 raw
            // ulps, README "Runtime accuracy"; its bound there is 8).
            v::Options o;
            o.ulps = q == Quantity::value || q == Quantity::dr || q == Quantity::grad_over_r ? 1 : 4;
            const v::Report r = v::verify(quantity_of(k, q), spec, dim, q, o);
            EXPECT_TRUE(r.passed()) << r.to_string();
            EXPECT_GT(r.points, 10000u);
        }
    }
}

TEST(Verify, ConstantOffByOneInAMillionIsAConstantFactor) {
    const mollify::Kernel k = runtime("wendland:k=1", 3);
    const v::Report r = v::verify([&](double x, double h) { return k.value(x, h) * (1 + 1e-6); }, "wendland:k=1", 3,
                                  Quantity::value);
    expect_kind(r, DiagnosisKind::constant_factor, "normalisation off by the factor");
}

// PySPH's 3D quintic spline normalisation 3/(359 pi) instead of 1/(120 pi)
// (pypr/pysph, fixed in 4f733660; ../shared/peers.md). The exact constant
// from the quintic spline's definition (Schoenberg's M6 as PySPH and Morris
// 1996 write it: w(q) = (3 - q)^5 - 6 (2 - q)^5 + 15 (1 - q)^5, each term
// where positive, support 3h): sigma = 1 / (4 pi int_0^3 q^2 w(q) dq).
mollify::gen::Q quintic_spline_mass_over_4pi() {
    using mollify::gen::Laurent;
    using mollify::gen::Q;
    const std::pair<int, int> terms[] = {{3, 1}, {2, -6}, {1, 15}};  // (a, c): c (a - q)^5 on [0, a)
    Q integral = 0;
    for (const auto& [a, c] : terms) {
        const Laurent f = Laurent::binomial_power(Q(a), Q(-1), 5) * Laurent::monomial(Q(c), 2);
        Q log_coefficient = 0;
        const Laurent F = f.antiderivative(&log_coefficient);
        integral += F(Q(a)) - F(Q(0));
    }
    return integral;
}

// The published ratio, computed exactly here, applied to mollify's quintic
// spline (PySPH's 3D constant before 4f733660, pysph/base/kernels.py @
// dfd2d52e), must be recognised and named.
TEST(Verify, PySphQuinticNormalisationIsRecognisedAsRational) {
    using mollify::gen::Q;
    const Q exact_sigma_times_pi = 1 / (4 * quintic_spline_mass_over_4pi());
    EXPECT_EQ(exact_sigma_times_pi, Q(1, 120));  // the corrected constant 1/(120 pi)
    const Q ratio = Q(3, 359) / exact_sigma_times_pi;  // PySPH's 3/(359 pi) over the exact one
    EXPECT_EQ(ratio, Q(360, 359));
    const mollify::Kernel k = runtime("quintic-spline", 3);
    const double factor = static_cast<double>(ratio);
    const v::Report r = v::verify([&](double x, double h) { return k.value(x, h) * factor; }, "quintic-spline", 3,
                                  Quantity::value);
    expect_kind(r, DiagnosisKind::constant_factor, "360/359");
    // W(0) = 66/(120 pi) (3/H)^3 = 297/(20 pi) H^-3 on mollify's support H = 3h
    EXPECT_NE(r.diagnosis->text.find("297"), std::string::npos) << r.to_string();
}

// Phantom's convention takes Phantom's own radkern per kernel: 3 for its
// stock quintic spline (kernel_quintic.f90), so the kernel on support 3h
// shows no systematic error (only the rounding of 3h, which grows towards the
// edge: 344 ulps measured, 2.9 for r < H/2); on support 2h (radkern 2,
// Phantom's other kernels) it is a support convention 2/3.
TEST(Verify, PhantomsQuinticHasRadkern3) {
    const mollify::Kernel k = runtime("quintic-spline", 3);
    v::Options o;
    o.convention = "phantom";
    o.ulps = 1;
    const v::Report ok = v::verify([&](double x, double h) { return k.value(x, 3 * h); }, "quintic-spline", 3,
                                   Quantity::value, o);
    EXPECT_TRUE(!ok.diagnosis || ok.diagnosis->kind == DiagnosisKind::edge_cancellation) << ok.to_string();
    EXPECT_LT(ok.max_ulps, 1e4) << ok.to_string();
    const v::Report two = v::verify([&](double x, double h) { return k.value(x, 2 * h) * 8.0 / 27.0; }, "quintic-spline", 3,
                                    Quantity::value, o);
    expect_kind(two, DiagnosisKind::support_convention, "2/3 x H");
}

TEST(Verify, PiMultipleIsRecognised) {
    // mollify's phi against Phantom's convention (phi = -1/r outside): 1/(4 pi).
    const mollify::Kernel k = runtime("wendland:k=1", 3);
    v::Options o;
    o.convention = "phantom";
    const v::Report r = v::verify([&](double x, double h) { return k.potential(x, 2 * h); }, "wendland:k=1", 3,
                                  Quantity::potential, o);
    expect_kind(r, DiagnosisKind::constant_factor, "1/(4 pi)");
}

TEST(Verify, WrongSign) {
    const mollify::Kernel k = runtime("cubic-spline", 2);
    const v::Report r = v::verify([&](double x, double h) { return -k(mollify::QuantityId::dr, x, h); }, "cubic-spline",
                                  2, Quantity::dr);
    expect_kind(r, DiagnosisKind::wrong_sign);
}

// A kernel that returns 0: the factor 0 said as such (it had read "normalisation off by the factor 0").
TEST(Verify, ZeroEverywhere) {
    const v::Report r = v::verify([](double, double) { return 0.0; }, "wendland:k=2", 3, Quantity::value);
    expect_kind(r, DiagnosisKind::constant_factor, "constant factor 0: got = 0 where the exact value is not");
}

TEST(Verify, FactorTwoSupport) {
    // q = r/h on [0, 2) (Phantom's radkern 2) handed to a check of h = support.
    const mollify::Kernel k = runtime("wendland:k=1", 3);
    const v::Report r = v::verify([&](double x, double h) { return k.value(x, 2 * h); }, "wendland:k=1", 3,
                                  Quantity::value);
    expect_kind(r, DiagnosisKind::support_convention, "support 2 x H");
    v::Options phantom;
    phantom.convention = "phantom";
    const v::Report ok = v::verify([&](double x, double h) { return k.value(x, 2 * h); }, "wendland:k=1", 3,
                                   Quantity::value, phantom);
    EXPECT_TRUE(ok.passed()) << ok.to_string();
}

TEST(Verify, SwiftGammaSupport) {
    // h = 2 sigma, H = gamma h (SWIFT) checked as h = H: support gamma.
    const mollify::Kernel k = runtime("cubic-spline", 3);
    const mollify::accuracy::Reference ref("cubic-spline", 3);
    const double gamma = mollify::gen::swift_gamma(ref.kernel()).value;
    auto swift = [&](double x, double h) { return k.value(x, gamma * h); };
    expect_kind(v::verify(swift, "cubic-spline", 3, Quantity::value), DiagnosisKind::support_convention, "kernel_gamma");
    v::Options o;
    o.convention = "swift";
    const v::Report ok = v::verify(swift, "cubic-spline", 3, Quantity::value, o);
    EXPECT_TRUE(ok.passed()) << ok.to_string();
    EXPECT_TRUE(ok.float_ulps);
}

TEST(Verify, GradientMissingAFactorQ) {
    // SPlisHSPlasH PR #347: the Wendland gradient missing a factor q.
    const mollify::Kernel k = runtime("wendland:k=1", 3);
    const v::Report r = v::verify([&](double x, double h) { return x == 0 ? 0.0 : k(mollify::QuantityId::dr, x, h) / (x / h); },
                                  "wendland:k=1", 3, Quantity::dr);
    expect_kind(r, DiagnosisKind::gradient_factor, "factor q missing");
}

TEST(Verify, GradientInQNotR) {
    // Phantom's grkern is dW/dq: handed over as dW/dr it lacks 1/h.
    const mollify::Kernel k = runtime("cubic-spline", 3);
    const v::Report r = v::verify([&](double x, double h) { return k(mollify::QuantityId::dr, x, h) * h; }, "cubic-spline",
                                  3, Quantity::dr);
    expect_kind(r, DiagnosisKind::gradient_factor, "1/h missing");
}

// W'/r, the factor of grad W = (W'/r) x: W' handed over instead is
// diagnosed; the textbook W'(r)/r is NaN at r = 0 (an SPH self-pair's 0 x
// NaN), where W'/r has its finite limit; a cusp's W'/r (spiky's) is -inf
// there, and the runtime's passes.
TEST(Verify, GradOverR) {
    const mollify::Kernel k = runtime("wendland:k=2", 3);
    const v::Report ok = v::verify([&](double x, double h) { return k(mollify::QuantityId::grad_over_r, x, h); },
                                   "wendland:k=2", 3, Quantity::grad_over_r);
    EXPECT_TRUE(ok.passed()) << ok.to_string();
    EXPECT_EQ(v::parse_quantity("grad_over_r"), Quantity::grad_over_r);
    EXPECT_EQ(v::name(Quantity::grad_over_r), "grad_over_r");
    expect_kind(v::verify([&](double x, double h) { return k(mollify::QuantityId::dr, x, h); }, "wendland:k=2", 3,
                          Quantity::grad_over_r),
                DiagnosisKind::gradient_factor, "division by r missing");
    expect_kind(v::verify([&](double x, double h) { return k(mollify::QuantityId::dr, x, h) / x; }, "wendland:k=2", 3,
                          Quantity::grad_over_r),
                DiagnosisKind::not_finite, "NaN at r = 0");
    const mollify::Kernel spiky = runtime("spiky", 3);
    const v::Report cusp = v::verify([&](double x, double h) { return spiky(mollify::QuantityId::grad_over_r, x, h); },
                                     "spiky", 3, Quantity::grad_over_r);
    EXPECT_TRUE(cusp.passed()) << cusp.to_string();
}

TEST(Verify, KernelOfAnotherDimension) {
    const mollify::Kernel k2 = runtime("wendland:k=1", 2);
    const v::Report r = v::verify([&](double x, double h) { return k2.value(x, h); }, "wendland:k=1", 3, Quantity::value);
    expect_kind(r, DiagnosisKind::other_dimension, "D = 2");
}

TEST(Verify, ExpandedMonomialsCancelNearTheEdge) {
    const std::vector<double> c = expanded_coefficients("wendland:k=2", 3);
    const v::Report r = v::verify([&](double x, double h) { return expanded<double>(c, x, h, 3); }, "wendland:k=2", 3,
                                  Quantity::value);
    expect_kind(r, DiagnosisKind::edge_cancellation, "towards the support edge");
}

// The textbook factored form (q = r/h rounded, then pow(1 - q, 6)): 1 - q
// carries ulp(q)/(1 - q); the user's constant W(0) is mollify's, the shape
// (1 - q)^6 (1 + 6q + 35q^2/3) Wendland's C4 as printed (Dehnen & Aly 2012).
TEST(Verify, TextbookEdgeFactorLosesAccuracyNearTheEdge) {
    const mollify::Kernel k = runtime("wendland:k=2", 3);
    const double w0 = k.value(0, 1);
    const v::Report r = v::verify(
        [&](double x, double h) {
            const double q = x / h;
            return q >= 1 ? 0.0 : w0 * std::pow(1 - q, 6) * (1 + 6 * q + 35.0 / 3 * q * q) / (h * h * h);
        },
        "wendland:k=2", 3, Quantity::value);
    expect_kind(r, DiagnosisKind::edge_cancellation, "or 1 - q is formed from a rounded q");
}

TEST(Verify, SinglePrecision) {
    const std::vector<double> c = expanded_coefficients("wendland:k=1", 3);
    auto f = [&](double x, double h) {
        return static_cast<double>(expanded<float>(c, static_cast<float>(x), static_cast<float>(h), 3));
    };
    const v::Report r = v::verify(f, "wendland:k=1", 3, Quantity::value);
    expect_kind(r, DiagnosisKind::single_precision, "exactly floats");
}

TEST(Verify, SinglePrecisionInside) {
    // w(q) in float, the scale h^-3 in double: the values are not floats.
    const std::vector<double> c = expanded_coefficients("wendland:k=1", 3);
    auto f = [&](double x, double h) {
        return static_cast<double>(expanded<float>(c, static_cast<float>(x / h), 1.0f, 3)) / (h * h * h);
    };
    const v::Report r = v::verify(f, "wendland:k=1", 3, Quantity::value);
    expect_kind(r, DiagnosisKind::single_precision, "part of the evaluation is in float");
}

TEST(Verify, NotFinite) {
    const mollify::Kernel k = runtime("wendland:k=1", 3);
    const v::Report r = v::verify([&](double x, double h) { return x == 0 ? std::nan("") : k.value(x, h); },
                                  "wendland:k=1", 3, Quantity::value);
    expect_kind(r, DiagnosisKind::not_finite, "NaN at r = 0");
}

TEST(Verify, SamplesCoverTheHardPoints) {
    const std::vector<v::Sample> s = v::samples("cubic-spline", 3, Quantity::value);
    bool zero = false, edge = false, outside = false, breakpoint = false, tiny_h = false, huge_h = false;
    for (const v::Sample& p : s) {
        zero = zero || p.r == 0;
        edge = edge || (p.h == 1 && p.r == std::nextafter(1.0, 0.0));
        outside = outside || (p.h == 1 && p.r == std::nextafter(1.0, 2.0));
        breakpoint = breakpoint || (p.h == 1 && p.r == 0.5);  // Monaghan's q = 1 at half the support
        tiny_h = tiny_h || p.h <= 1e-30;
        huge_h = huge_h || p.h >= 1e30;
    }
    EXPECT_TRUE(zero && edge && outside && breakpoint && tiny_h && huge_h);
    EXPECT_EQ(s.size(), v::samples("cubic-spline", 3, Quantity::value).size());
    EXPECT_EQ(s.back().r, v::samples("cubic-spline", 3, Quantity::value).back().r);  // seeded: reproducible
}

// compare() counts the hard points among any samples it is given, so a
// verdict on samples of one's own says it holds for those only: a kernel
// right at its own radii may be wrong at r = 0 or next to the edge.
TEST(Verify, ReportCountsTheHardPointsAmongTheSamples) {
    const mollify::Kernel k = runtime("wendland:k=2", 3);
    v::Options o;
    o.uniform = 200;
    const std::vector<v::Sample> all = v::samples("wendland:k=2", 3, Quantity::value, o);
    auto values_at = [&](const std::vector<v::Sample>& at) {
        std::vector<double> w;
        for (const v::Sample& a : at) w.push_back(k.value(a.r, a.h));
        return w;
    };
    const v::Report whole = v::compare("wendland:k=2", 3, Quantity::value, all, values_at(all), o);
    EXPECT_TRUE(whole.passed() && whole.complete()) << whole.to_string();
    EXPECT_GT(whole.hard_points, 100u);
    EXPECT_LT(whole.hard_points, all.size());  // the uniform ones are not hard points
    EXPECT_EQ(whole.hard_points_compared, whole.hard_points);
    EXPECT_EQ(whole.to_string().find("given samples only"), std::string::npos) << whole.to_string();

    // The uniform points alone (the last 200), twice over: none of the hard points.
    std::vector<v::Sample> own(all.end() - 200, all.end());
    own.insert(own.end(), all.end() - 200, all.end());
    const v::Report mine = v::compare("wendland:k=2", 3, Quantity::value, own, values_at(own), o);
    EXPECT_TRUE(mine.passed()) << mine.to_string();
    EXPECT_FALSE(mine.complete());
    EXPECT_EQ(mine.hard_points, whole.hard_points);
    EXPECT_EQ(mine.hard_points_compared, 0u);
    EXPECT_NE(mine.to_string().find("PASSED on the given samples only (0 of " + std::to_string(whole.hard_points) +
                                    " hard points)"),
              std::string::npos)
        << mine.to_string();

    // r = 0 and the first hard points, each twice: counted once each.
    std::vector<v::Sample> some(all.begin(), all.begin() + 10);
    some.insert(some.end(), all.begin(), all.begin() + 10);
    const v::Report few = v::compare("wendland:k=2", 3, Quantity::value, some, values_at(some), o);
    EXPECT_EQ(few.hard_points_compared, 10u) << few.to_string();
    EXPECT_NE(few.to_string().find("hard points: 10 of "), std::string::npos) << few.to_string();

    // a failing verdict is not qualified: it fails on the samples it has
    std::vector<double> off = values_at(own);
    for (double& w : off) w *= 1 + 1e-9;
    const v::Report wrong = v::compare("wendland:k=2", 3, Quantity::value, own, off, o);
    EXPECT_FALSE(wrong.passed());
    EXPECT_EQ(wrong.to_string().find("given samples only"), std::string::npos) << wrong.to_string();
}

TEST(Verify, BadInputNamesTheValue) {
    auto message = [](auto&& f) {
        try {
            f();
        } catch (const mollify::Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    v::Options o;
    o.convention = "sphynx";
    EXPECT_NE(message([&] { v::samples("cubic-spline", 3, Quantity::value, o); }).find("sphynx"), std::string::npos);
    o.convention = "mollify";
    EXPECT_EQ(v::samples("cubic-spline", 3, Quantity::value, o).size(), v::samples("cubic-spline", 3, Quantity::value).size());
    EXPECT_NE(message([] { v::parse_quantity("hessian"); }).find("hessian"), std::string::npos);
    EXPECT_NE(message([] { v::samples("box-d1", 1, Quantity::potential); }).find("no potential"), std::string::npos);
    EXPECT_NE(message([] { v::samples("wendlnd:k=1", 3, Quantity::value); }).find("wendlnd"), std::string::npos);
    const std::vector<v::Sample> s{{1, 1}};
    const std::vector<double> two{1, 2};
    EXPECT_NE(message([&] { v::compare("cubic-spline", 3, Quantity::value, s, two); }).find("2 values for 1 samples"),
              std::string::npos);
    const std::vector<v::Sample> negative{{1, 1}, {-1, 1}};
    EXPECT_NE(message([&] { v::compare("cubic-spline", 3, Quantity::value, negative, two); }).find("sample 1 (r = -1"),
              std::string::npos);
    o.convention = "phantom";
    EXPECT_NE(message([&] { v::samples("cubic-spline", 2, Quantity::value, o); }).find("D = 2"), std::string::npos);
    o.convention = "cpp";
    o.ulps = -1;
    EXPECT_NE(message([&] { v::samples("cubic-spline", 3, Quantity::value, o); }).find("-1"), std::string::npos);
    // more uniform points than a verification takes: named, not std::bad_alloc from the allocation
    o.ulps = 4;
    o.uniform = std::size_t{100'000'000'000};
    EXPECT_NE(message([&] { v::samples("cubic-spline", 3, Quantity::value, o); })
                  .find("100000000000 uniform points: at most 100000000"),
              std::string::npos);
    EXPECT_NE(message([&] { v::compare("cubic-spline", 3, Quantity::value, s, std::vector<double>{1}, o); })
                  .find("100000000000 uniform points"),
              std::string::npos);
}

// The matcher, as a user writes it.
double user_wendland_c2(double r, double h) { return runtime("wendland:k=1", 3).value(r, h); }
double user_wrong_wendland_c2(double r, double h) { return 2 * runtime("wendland:k=1", 3).value(r, h); }

// The matchers' uniform points: the default 10,000, and 1,000 under the
// sanitizers (sanitized.hpp: the same code paths, a tenth of the MPFR
// reference's work at -O0 + ASan, where FailureMessageIsTheDiagnosis took 15 s).
mollify::testing::KernelMatcher matches(const char* spec, int dim) {
    return mollify::testing::MatchesKernel(spec, dim).UniformPoints(mollify::testing::sanitized_build ? 1000 : 10000);
}

TEST(VerifyMatcher, PassesForTheExactKernel) {
    EXPECT_THAT(user_wendland_c2, matches("wendland:k=1", 3).WithinUlps(1));
    const mollify::Kernel k = runtime("wendland:k=1", 3);
    EXPECT_THAT([&](double r, double h) { return k(mollify::QuantityId::dr, r, h); },
                matches("wendland:k=1", 3).Quantity("dr").Convention("gadget4"));
}

TEST(VerifyMatcher, FailureMessageIsTheDiagnosis) {
    ::testing::StringMatchResultListener listener;
    EXPECT_FALSE(::testing::ExplainMatchResult(matches("wendland:k=1", 3), user_wrong_wendland_c2,
                                               &listener));
    EXPECT_NE(listener.str().find("diagnosis (constant factor): normalisation off by the factor 2"), std::string::npos)
        << listener.str();
    EXPECT_NE(listener.str().find("worst:"), std::string::npos) << listener.str();
    EXPECT_NONFATAL_FAILURE(EXPECT_THAT(user_wrong_wendland_c2, matches("wendland:k=1", 3)),
                            "normalisation off by the factor 2");
}

}  // namespace
