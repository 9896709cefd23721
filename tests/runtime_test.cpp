// The runtime's contract apart from accuracy (tests/accuracy_test.cpp):
// both forms agree bit for bit, the support is exact, gradients are finite
// at r = 0, the vector forms are the radial ones times x, and bad input is
// an Error naming the value, never a NaN. No GMP here: this is what users link.
#include <mollify/kernel.hpp>
#include <mollify/tables/catalogue.hpp>
#include <mollify/tables/combo/m_3_base_wendland_k_2_D3.hpp>
#include <mollify/tables/classic/box_d1_D1.hpp>
#include <mollify/tables/combo/m_3_base_wendland_k_3_l_1_D1.hpp>
#include <mollify/tables/mollifier/M_4_order_4_D3.hpp>
#include <mollify/tables/wendland/k_0_D1.hpp>
#include <mollify/tables/wendland/k_1_D2.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>
#include <mollify/tables/wendland/k_2_l_1_D3.hpp>
#include <mollify/tables/wendland/k_4_l_4_D3.hpp>
#include <mollify/tables/wendland_missing/k_1_l_1_D2.hpp>

#include "fused_bound.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

namespace {

using mollify::Error;
using mollify::QuantityId;
namespace tables = mollify::tables;

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();

// Runs f and expects an Error whose message contains `needle`.
template <class F>
void expect_error(F f, const std::string& needle) {
    try {
        f();
        ADD_FAILURE() << "no error; expected one naming '" << needle << "'";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

// The run-time form's instruction set forced for one test, the one before
// restored at its end (InstructionSetIsChosenAndCanBeForced reads the choice
// made at load time, whatever ran before it in this process).
class ForcedIsa {
public:
    explicit ForcedIsa(std::string_view name) : previous_(mollify::isa()) { mollify::use_isa(name); }
    ~ForcedIsa() { mollify::use_isa(previous_); }
    ForcedIsa(const ForcedIsa&) = delete;
    ForcedIsa& operator=(const ForcedIsa&) = delete;

private:
    std::string previous_;
};

std::vector<double> radii(std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1.25);
    std::vector<double> r(n);
    for (double& x : r) x = u(rng);
    r[0] = 0;
    r[1] = 1;
    r[2] = std::nextafter(1.0, 2.0);
    r[3] = std::nextafter(1.0, 0.0);
    return r;
}

// Mueller's viscosity kernel has h/(2r) in W itself: infinite at 0 by design.
bool value_is_singular_at_origin(const mollify::table::Kernel& k) {
    const auto& first = k.quantities[0].pieces[0];
    for (int t = 0; t < first.nterms; ++t)
        if (first.terms[t].low < 0) return true;
    return false;
}

}  // namespace

// Both precisions run from one plan: kernel(spec, dim, fast) is
// StaticKernel<table, fast> bit for bit on the instruction set this test is
// compiled for, and with() switches the precision of the same kernel.
// (Every path against StaticKernel: runtime_forms_test.)
TEST(Runtime, RunTimeFastIsCompileTimeFast) {
    const ForcedIsa generic("generic");
    using F = mollify::StaticKernel<tables::combo_m_3_base_wendland_k_3_l_1_D1, mollify::Precision::fast>;
    using A = mollify::StaticKernel<tables::combo_m_3_base_wendland_k_3_l_1_D1>;
    const mollify::Kernel fast = mollify::kernel("combo:m=3,base=wendland:k=3,l=1", 1, mollify::Precision::fast);
    EXPECT_EQ(fast.precision(), mollify::Precision::fast);
    EXPECT_EQ(fast.with(mollify::Precision::accurate).precision(), mollify::Precision::accurate);
    const auto r = radii(1000, 3);
    std::vector<double> a(r.size()), b(r.size()), c(r.size());
    bool differ = false;
    for (const double h : {1.0, 0.37, 3e-7, 2.5e6}) {
        std::vector<double> rh(r);
        for (double& x : rh) x *= h;
        F::evaluate<QuantityId::value>(rh, F::smoothing(h), a);
        fast.evaluate(QuantityId::value, rh, h, b);
        for (std::size_t i = 0; i < r.size(); ++i) ASSERT_EQ(a[i], b[i]) << "r = " << rh[i] << ", h = " << h;
        A::evaluate<QuantityId::value>(rh, A::smoothing(h), a);
        fast.with(mollify::Precision::accurate).evaluate(QuantityId::value, rh, h, c);
        for (std::size_t i = 0; i < r.size(); ++i) {
            ASSERT_EQ(a[i], c[i]) << "r = " << rh[i] << ", h = " << h;
            differ = differ || b[i] != c[i];
        }
    }
    EXPECT_TRUE(differ) << "fast and accurate gave the same bits everywhere: with() did not switch";
    // The pair batch (the SPH path) of both precisions, against the scalar forms.
    std::vector<double> x(r), w(r.size()), g(r.size());
    const std::span<const double> in[] = {x};
    const std::span<double> out[] = {g};
    fast.pairs(in, fast.smoothing(0.5), w, out);
    for (std::size_t i = 0; i < r.size(); ++i) {
        const auto p = F::pair(mollify::Vector<1>{x[i]}, F::smoothing(0.5));
        ASSERT_EQ(w[i], p.value) << "x = " << x[i];
        ASSERT_EQ(g[i], p.gradient[0]) << "x = " << x[i];
    }
    expect_error([] { mollify::kernel("wendland:k=2", 3, static_cast<mollify::Precision>(7)); }, "precision 7");
    expect_error([] { mollify::precision("exact"); }, "'exact'");
    expect_error([] { mollify::use_isa("sse9"); }, "'sse9'");
    EXPECT_EQ(mollify::precision("fast"), mollify::Precision::fast);
    EXPECT_EQ(mollify::name(mollify::Precision::accurate), "accurate");
}

namespace {

// What a solver sees of a kernel through mollify::RadialKernel alone: the
// same code for either form, so that the forms can be compared bit for bit.
struct Seen {
    int dim;
    std::string spec;
    bool has_potential;
    std::string table_spec;
    std::vector<double> batches, pairs;
    double scalar, value;
};

template <mollify::RadialKernel K>
Seen through_the_concept(const K& k, const std::vector<double>& r) {
    Seen seen{k.dim(), std::string(k.spec()), k.has_potential(), k.table().spec, {}, {}, 0, 0};
    std::vector<double> out(r.size());
    for (const double h : {1.0, 0.37, 2.5e6})
        for (const QuantityId q : {QuantityId::value, QuantityId::dr, QuantityId::d2r}) {
            std::vector<double> rh(r);
            for (double& x : rh) x *= h;
            k.evaluate(q, rh, k.smoothing(h), out);
            seen.batches.insert(seen.batches.end(), out.begin(), out.end());
        }
    std::vector<double> w(r.size()), g(r.size());
    const std::span<const double> x[] = {r};
    const std::span<double> grad[] = {g};
    k.pairs(x, k.smoothing(0.5), w, grad);
    seen.pairs = w;
    seen.pairs.insert(seen.pairs.end(), g.begin(), g.end());
    seen.scalar = k(QuantityId::dr, 0.3, 0.9);
    seen.value = k.value(0.3, 0.9);
    return seen;
}

}  // namespace

// StaticKernel and the run-time Kernel have one member API (issue 18): a
// function template written against the concept takes either and, on the
// instruction set this test is compiled for, gets the same bits; the
// quantity chosen at run time is the compile-time one.
TEST(Runtime, StaticAndRunTimeKernelsShareOneApi) {
    const ForcedIsa generic("generic");
    using W = mollify::StaticKernel<tables::combo_m_3_base_wendland_k_3_l_1_D1, mollify::Precision::fast>;
    static_assert(mollify::RadialKernel<W>);
    static_assert(mollify::RadialKernel<mollify::StaticKernel<tables::wendland_k_2_D3>>);
    static_assert(W::dim() == W::dimension && W::dim() == 1);
    const mollify::Kernel k = mollify::kernel("combo:m=3,base=wendland:k=3,l=1", 1, mollify::Precision::fast);
    const auto r = radii(500, 5);
    const Seen a = through_the_concept(W{}, r), b = through_the_concept(k, r);
    EXPECT_EQ(a.dim, 1);
    EXPECT_EQ(a.dim, b.dim);
    EXPECT_EQ(a.spec, "combo:m=3,base=wendland:k=3,l=1");
    EXPECT_EQ(a.spec, b.spec);
    EXPECT_EQ(a.table_spec, a.spec);
    EXPECT_EQ(a.has_potential, b.has_potential);
    ASSERT_EQ(a.batches.size(), b.batches.size());
    for (std::size_t i = 0; i < a.batches.size(); ++i) ASSERT_EQ(a.batches[i], b.batches[i]) << "entry " << i;
    ASSERT_EQ(a.pairs.size(), b.pairs.size());
    for (std::size_t i = 0; i < a.pairs.size(); ++i) ASSERT_EQ(a.pairs[i], b.pairs[i]) << "entry " << i;
    EXPECT_EQ(a.scalar, b.scalar);
    EXPECT_EQ(a.value, b.value);
    // The run-time choice of quantity is the template's, bit for bit.
    std::vector<double> fixed(r.size()), chosen(r.size());
    W::evaluate<QuantityId::d2r>(r, W::smoothing(0.7), fixed);
    W::evaluate(QuantityId::d2r, r, W::smoothing(0.7), chosen);
    for (std::size_t i = 0; i < r.size(); ++i) ASSERT_EQ(fixed[i], chosen[i]) << "r = " << r[i];
    EXPECT_EQ(W{}(QuantityId::value, 0.3, 0.9), W::value(0.3, 0.9));
    expect_error([&] { W::evaluate(static_cast<QuantityId>(12), r, W::smoothing(1), chosen); }, "quantity number 12");
    const std::span<const double> two[] = {r, r};
    expect_error([&] { W::pairs(two, W::smoothing(1), fixed, {}); }, "2 inputs");
}

TEST(Runtime, EveryEmittedKernelIsReachableByItsSpec) {
    for (const mollify::table::Kernel* t : tables::all_kernels) {
        const mollify::Kernel k = mollify::kernel(t->spec, t->dim);
        EXPECT_EQ(&k.table(), t) << t->spec;
    }
}

// W and every derivative are exactly 0 outside the closed support r <= h;
// the potential is the Green's function there, continuous with the inside.
TEST(Runtime, SupportIsExact) {
    for (const mollify::table::Kernel* t : tables::all_kernels) {
        const mollify::Kernel k = mollify::kernel(t->spec, t->dim);
        for (const double h : {1.0, 0.1, 7e-8, 3e7}) {
            const double beyond[] = {std::nextafter(h, inf), 1.5 * h, 1e3 * h, 1e300};
            for (int q = 0; q < 6; ++q)
                for (const double r : beyond) ASSERT_EQ(k(static_cast<QuantityId>(q), r, h), 0.0) << t->spec << " D" << t->dim << " q" << q << " r " << r;
            if (t->smoothness >= 0 && t->dim == 3 && t->has_potential) {
                // -1/(4 pi r) on both sides of the edge, to a few ulps.
                const double in = k.potential(h, h), out = k.potential(std::nextafter(h, inf), h);
                EXPECT_NEAR(in, out, 8 * std::abs(in) * 0x1p-52) << t->spec << " h " << h;
            }
        }
    }
}

// grad W = (W'/r) x from the emitted W'/r: finite at r = 0 (no 0 * inf,
// SPlisHSPlasH's bug); kernels with a cusp at 0 (spiky, viscosity, Wendland
// k = 0) use W'(r) x/r, and 0 at x = 0. Checked through the pair batch, the
// SPH path, for every kernel at tiny displacements and at 0.
TEST(Runtime, GradientIsFiniteAtTheOrigin) {
    for (const mollify::table::Kernel* t : tables::all_kernels) {
        if (value_is_singular_at_origin(*t)) continue;
        const mollify::Kernel k = mollify::kernel(t->spec, t->dim);
        for (const double x0 : {0.0, 1e-320, 1e-300, 1e-160, 1e-20}) {
            std::vector<double> x(1, x0), zero(1, 0.0), w(1), g0(1), g1(1), g2(1);
            const std::span<const double> in[] = {x, zero, zero};
            const std::span<double> out[] = {g0, g1, g2};
            k.pairs(std::span(in, static_cast<std::size_t>(t->dim)), k.smoothing(1.0), w,
                    std::span(out, static_cast<std::size_t>(t->dim)));
            EXPECT_TRUE(std::isfinite(w[0]) && std::isfinite(g0[0]) && std::isfinite(g1[0]) && std::isfinite(g2[0]))
                << t->spec << " D" << t->dim << " x " << x0 << ": W " << w[0] << " grad " << g0[0];
            if (x0 == 0) {
                EXPECT_EQ(g0[0], 0.0) << t->spec << " D" << t->dim;
            }
        }
    }
}

// The vector forms are the radial quantities times x: grad = (W'/r) x,
// Hessian = (W'/r) I + hess_radial x x^T, Laplacian = trace of the Hessian.
TEST(Runtime, VectorFormsAreTheRadialOnes) {
    using W = mollify::StaticKernel<tables::mollifier_M_4_order_4_D3>;
    const double h = 0.75;
    const mollify::Vector<3> x{0.1, -0.2, 0.3};
    const double r = std::sqrt(0.01 + 0.04 + 0.09);
    const auto s = W::smoothing(h);
    const auto p = W::pair(x, s);
    EXPECT_DOUBLE_EQ(p.value, W::value(r, h));
    const double g = W::radial<QuantityId::grad_over_r>(r, s);
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(p.gradient[c], g * x[c]);
    const auto hess = W::hessian(x, s);
    EXPECT_NEAR(hess[0][0] + hess[1][1] + hess[2][2], W::radial<QuantityId::laplacian>(r, s), 1e-12 * std::abs(hess[0][0]));
    EXPECT_DOUBLE_EQ(hess[0][1], hess[1][0]);
    const auto e = W::potential_gradient(x, s);
    EXPECT_DOUBLE_EQ(e[2], W::radial<QuantityId::dpotential_over_r>(r, s) * x[2]);
}

// Belley's first-derivative kernel is odd in 1D: W(-x) = -W(x), W'(x) even.
TEST(Runtime, OddKernelIn1D) {
    using W = mollify::StaticKernel<tables::box_d1_D1>;
    static_assert(W::odd);
    const auto s = W::smoothing(1.0);
    EXPECT_EQ(W::value(mollify::Vector<1>{-0.3}, s), -W::value(mollify::Vector<1>{0.3}, s));
    EXPECT_EQ(W::gradient({-0.3}, s)[0], W::gradient({0.3}, s)[0]);
}

// The 2D potential includes log(h)/(2 pi): phi_h(r) = phi(r/h) + log(h)/(2 pi),
// the Green's function log(r)/(2 pi) outside at every h.
TEST(Runtime, TwoDimensionalPotentialCarriesLogH) {
    using W = mollify::StaticKernel<tables::wendland_k_1_D2>;
    for (const double h : {1e-8, 0.5, 1.0, 3.0, 1e8}) {
        const double edge = W::potential(h, h), green = std::log(h) / (2 * std::acos(-1.0));
        EXPECT_NEAR(edge, green, 4e-16 * std::max(1.0, std::abs(green))) << h;
        EXPECT_NEAR(W::potential(0.5 * h, h) - W::potential(0.5, 1.0), green, 1e-15 * std::max(1.0, std::abs(green))) << h;
    }
}

TEST(Runtime, BatchPairsMatchTheScalarPair) {
    const ForcedIsa generic("generic");  // the instruction set of the static form here
    const mollify::Kernel k = mollify::kernel("wendland:k=2", 3);
    using W = mollify::StaticKernel<tables::wendland_k_2_D3>;
    const std::size_t n = 257;
    std::vector<double> x(n), y(n), z(n), w(n), gx(n), gy(n), gz(n);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-0.8, 0.8);
    for (std::size_t i = 0; i < n; ++i) x[i] = u(rng), y[i] = u(rng), z[i] = u(rng);
    const auto s = k.smoothing(0.9);
    const std::span<const double> in[] = {x, y, z};
    const std::span<double> out[] = {gx, gy, gz};
    k.pairs(in, s, w, out);
    for (std::size_t i = 0; i < n; ++i) {
        const auto p = W::pair({x[i], y[i], z[i]}, s);
        ASSERT_EQ(w[i], p.value);
        ASSERT_EQ(gx[i], p.gradient[0]);
        ASSERT_EQ(gz[i], p.gradient[2]);
    }
}

TEST(Runtime, BadInputNamesTheValue) {
    using W = mollify::StaticKernel<tables::wendland_k_2_D3>;
    expect_error([] { W::value(0.5, 0.0); }, "h = 0");
    expect_error([] { W::value(0.5, -2.0); }, "h = -2");
    expect_error([] { W::value(0.5, not_a_number); }, "h = nan");
    expect_error([] { W::value(0.5, inf); }, "h = inf");
    expect_error([] { W::value(0.5, 1e-300); }, "out of range");
    expect_error([] { W::value(not_a_number, 1.0); }, "r = nan");
    expect_error([] { W::value(-0.25, 1.0); }, "r = -0.25");
    expect_error([] { W::value(inf, 1.0); }, "r = inf");
    expect_error([] { W::gradient({0.1, not_a_number, 0.0}, 1.0); }, "x[1] = nan");
    expect_error([] { mollify::kernel("wendland:k=2", 4); }, "dimension 4");
    expect_error([] { mollify::kernel("wendland:k=2", 0); }, "dimension 0");
    expect_error([] { mollify::kernel("nonsense", 3); }, "nonsense");
    expect_error([] { mollify::kernel("wendland:k=9", 3); }, "mollify::exact::kernel");
    expect_error([] { mollify::kernel("wendland:k=9", 3); }, "mollify-gen emit --format data --only 'wendland:k=9'");
    expect_error([] { mollify::kernel("viscosity", 1); }, "not defined in D = 1");
    expect_error([] { mollify::quantity("gradient"); }, "'gradient'");
    const mollify::Kernel k = mollify::kernel("poly6", 2);
    std::vector<double> r{0.1, 0.2, not_a_number, 0.3}, out(4);
    expect_error([&] { k.evaluate(QuantityId::value, r, 1.0, out); }, "r = nan");
    std::vector<double> short_out(3);
    expect_error([&] { k.evaluate(QuantityId::value, std::span<const double>(r.data(), 2), 1.0, short_out); }, "2 inputs");
    expect_error([&] { k.evaluate(QuantityId::value, std::span<const double>(r.data(), 2), mollify::Smoothing(1.0, 3), std::span<double>(out.data(), 2)); },
                 "made for D = 3");
    const mollify::Kernel box = mollify::kernel("box-d2", 1);
    if (!box.has_potential()) expect_error([&] { box.potential(0.5, 1.0); }, "no potential");
}

// The batch forms check their inputs in the pass that evaluates (the static
// form: each r's bits as it is computed; the run-time form: per chunk before
// it): a bad value anywhere - first, past the run-time form's first chunk,
// last - is named with its component, in every dimension and pair loop (3D
// and 2D whole loops, the 1D and cusped ones), both precisions. Huge finite
// coordinates overflow r to inf and are not refused: W and grad W are 0.
template <const mollify::table::Kernel& K, mollify::Precision Pr>
void expect_batches_name_bad_input() {
    using W = mollify::StaticKernel<K, Pr>;
    constexpr int D = W::dimension;
    const mollify::Kernel runtime = mollify::kernel(K, Pr);
    const std::string where = std::string(K.spec) + " D" + std::to_string(D);
    constexpr std::size_t n = 4500;  // past one run-time chunk (2048, 4096 points sorted by piece)
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    std::vector<std::vector<double>> x(D, std::vector<double>(n)), grad(D, std::vector<double>(n));
    for (auto& c : x)
        for (double& v : c) v = u(rng);
    std::vector<double> w(n);
    auto run = [&](bool static_form) {
        mollify::Points<D> in;
        mollify::PointsOut<D> out;
        std::vector<std::span<const double>> rin;
        std::vector<std::span<double>> rout;
        for (int c = 0; c < D; ++c) {
            in[static_cast<std::size_t>(c)] = x[static_cast<std::size_t>(c)];
            out[static_cast<std::size_t>(c)] = grad[static_cast<std::size_t>(c)];
            rin.emplace_back(x[static_cast<std::size_t>(c)]);
            rout.emplace_back(grad[static_cast<std::size_t>(c)]);
        }
        if (static_form) W::pairs(in, W::smoothing(0.5), w, out);
        else runtime.pairs(rin, runtime.smoothing(0.5), w, rout);
    };
    for (const bool static_form : {true, false}) {
        SCOPED_TRACE(where + (static_form ? " static" : " run-time"));
        for (const std::size_t i : {std::size_t{0}, std::size_t{4200}, n - 1})
            for (int c = 0; c < D; ++c)
                for (const double bad : {not_a_number, inf, -inf}) {
                    double& v = x[static_cast<std::size_t>(c)][i];
                    const double kept = v;
                    v = bad;
                    expect_error([&] { run(static_form); },
                                 "coordinate x[" + std::to_string(c) + "] = " + (bad != bad ? "nan" : bad > 0 ? "inf" : "-inf"));
                    v = kept;
                }
        for (const double huge : {1e200, -1e300, 0x1p600}) {
            for (int c = 0; c < D; ++c) x[static_cast<std::size_t>(c)][n / 2] = huge;
            run(static_form);
            EXPECT_EQ(w[n / 2], 0.0) << huge;
            for (int c = 0; c < D; ++c) EXPECT_EQ(grad[static_cast<std::size_t>(c)][n / 2], 0.0) << huge;
        }
        for (int c = 0; c < D; ++c) x[static_cast<std::size_t>(c)][n / 2] = 0.1;
    }
    // Radii: NaN, infinite or negative refused (-0 is a radius).
    std::vector<double> r(n);
    for (double& v : r) v = std::abs(u(rng));
    std::vector<double> out(n);
    for (const std::size_t i : {std::size_t{0}, std::size_t{4200}, n - 1})
        for (const double bad : {not_a_number, inf, -0.25, -0x1p-1074}) {
            const double kept = r[i];
            r[i] = bad;
            const std::string named = "r = " + (bad != bad ? std::string("nan") : bad == inf ? "inf" : bad == -0.25 ? "-0.25" : "-5e-324");
            expect_error([&] { W::template evaluate<QuantityId::value>(r, W::smoothing(0.5), out); }, named);
            expect_error([&] { runtime.evaluate(QuantityId::value, r, runtime.smoothing(0.5), out); }, named);
            r[i] = kept;
        }
    r[5] = -0.0;
    W::template evaluate<QuantityId::value>(r, W::smoothing(0.5), out);
    EXPECT_EQ(out[5], W::value(0.0, 0.5)) << where;
}

// Smoothing::reused, which the checked scalar forms call per call: every
// field bit for bit Smoothing(h, dim)'s, through repeats, h one ulp apart,
// alternating dimensions and refused lengths (which keep nothing); and the
// checked forms of both kernels equal to the form with a Smoothing made for
// that h, also with h changing between calls and on two threads at once.
bool same_smoothing(const mollify::Smoothing& a, const mollify::Smoothing& b) {
    auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
    bool same = bits(a.h()) == bits(b.h()) && bits(a.inverse()) == bits(b.inverse()) && a.dim() == b.dim() &&
                bits(a.log_h()) == bits(b.log_h());
    for (int q = 0; q < mollify::table::quantity_count; ++q) {
        const auto id = static_cast<QuantityId>(q);
        same = same && bits(a.scale(id)) == bits(b.scale(id)) && bits(a.scale_lo(id)) == bits(b.scale_lo(id));
    }
    return same;
}

TEST(Smoothing, ReusedIsTheSmoothingOfThisH) {
    const double up = std::nextafter(1.0, 2.0), third = 1.0 / 3;
    const std::pair<double, int> calls[] = {{1.0, 3}, {1.0, 3}, {up, 3}, {1.0, 3}, {1.0, 2}, {up, 3}, {third, 1},
                                            {1.0, 2}, {third, 3}, {2.5e-30, 3}, {2.5e-30, 2}, {1.0, 3}, {1.0, 1}};
    for (const auto& [h, dim] : calls)
        EXPECT_TRUE(same_smoothing(mollify::Smoothing::reused(h, dim), mollify::Smoothing(h, dim))) << "h " << h << " D" << dim;
    // A refused length names itself and leaves nothing behind.
    for (const double bad : {0.0, -1.0, not_a_number, inf, 1e300}) {
        mollify::Smoothing::reused(0.5, 3);
        expect_error([&] { mollify::Smoothing::reused(bad, 3); }, "smoothing length h = ");
        EXPECT_TRUE(same_smoothing(mollify::Smoothing::reused(0.5, 3), mollify::Smoothing(0.5, 3))) << "after h " << bad;
    }
    expect_error([] { mollify::Smoothing::reused(1.0, 4); }, "dimension 4");
    expect_error([] { mollify::Smoothing::reused(1.0, 0); }, "dimension 0");

    using W = mollify::StaticKernel<tables::wendland_k_2_D3>;
    const mollify::Kernel runtime(tables::wendland_k_2_D3);
    const double r = 0.4;
    for (const double h : {1.0, up, 1.0, 0.5, 0.5, std::nextafter(0.5, 0.0), 1.0}) {
        const mollify::Smoothing s(h, 3);
        EXPECT_EQ(W::value(r, h), W::radial<QuantityId::value>(r, s)) << "h " << h;
        EXPECT_EQ(W::potential(r, h), W::radial<QuantityId::potential>(r, s)) << "h " << h;
        EXPECT_EQ(W::value(mollify::Vector<3>{r, 0, 0}, h), W::value(mollify::Vector<3>{r, 0, 0}, s)) << "h " << h;
        EXPECT_EQ(runtime.value(r, h), W::radial<QuantityId::value>(r, s)) << "h " << h;
    }
    // Two threads, each its own h: a memo shared between them would race.
    auto worker = [&](double h, int& wrong) {
        const double expected = W::radial<QuantityId::value>(r, mollify::Smoothing(h, 3));
        for (int k = 0; k < 20000; ++k) wrong += W::value(r, h) != expected;
    };
    int wrong_a = 0, wrong_b = 0;
    std::thread a(worker, 0.5, std::ref(wrong_a)), b(worker, 0.75, std::ref(wrong_b));
    a.join();
    b.join();
    EXPECT_EQ(wrong_a + wrong_b, 0);
}

// Smoothing::reused(h, dim, q), the radial scalar forms' Smoothing, makes
// q's scale alone for a new h (and reused(h, dim, {q, q'}) those two): q's scale, low part, h, 1/h and (for the 2D
// potential) log h bit for bit Smoothing(h, dim)'s, every other scale NaN
// (Smoothing(h, dim)'s where |log2 h| > 120: there the whole Smoothing is
// made, with its checks), every scale made once the full form is asked for;
// and the same h refused with the same message, also where q's own power is
// in range but another quantity's is not (3D h = 1e-39: h^-3 ~ 2^388, the
// Hessian part's h^-7 ~ 2^907 > scale_range), at the ends of the range it
// takes without the others' checks (|log2 h| <= 120) and beyond.
TEST(Smoothing, OneQuantityIsTheSmoothingsScale) {
    auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
    const double lengths[] = {1.0, std::nextafter(1.0, 2.0), 1.0 / 3, 0.37, 2.5e-30, 2.5e30, 0x1p-120, 0x1.fffffffffffffp+120,
                              0x1p+121, std::nextafter(0x1p-120, 0.0), 1e-38, 5e38, 1e-39, 1e39, 6.6e-55, 1.4e54, 1e-300,
                              1e300, 0x1p-1074, 0.0, -1.0, not_a_number, inf};
    int made = 0, made_alone = 0, refused = 0;
    for (const double h : lengths)
        for (int dim = 1; dim <= 3; ++dim) {
            std::string full_error;
            std::optional<mollify::Smoothing> full;
            try {
                full.emplace(h, dim);
            } catch (const Error& e) {
                full_error = e.what();
            }
            for (int q = 0; q < mollify::table::quantity_count; ++q) {
                const auto id = static_cast<QuantityId>(q);
                const std::string where = "h " + std::to_string(h) + " D" + std::to_string(dim) + " q" + std::to_string(q);
                mollify::Smoothing::reused(0.5, dim);  // a kept Smoothing for another h
                if (!full) {
                    std::string one_error;
                    try {
                        mollify::Smoothing::reused(h, dim, id);
                    } catch (const Error& e) {
                        one_error = e.what();
                    }
                    EXPECT_EQ(one_error, full_error) << where;
                    ++refused;
                    continue;
                }
                const mollify::Smoothing& one = mollify::Smoothing::reused(h, dim, id);
                EXPECT_EQ(bits(one.scale(id)), bits(full->scale(id))) << where;
                EXPECT_EQ(bits(one.scale_lo(id)), bits(full->scale_lo(id))) << where;
                EXPECT_EQ(bits(one.h()), bits(full->h())) << where;
                EXPECT_EQ(bits(one.inverse()), bits(full->inverse())) << where;
                if (dim != 2 || id == QuantityId::potential) {
                    EXPECT_EQ(bits(one.log_h()), bits(full->log_h())) << where;
                }
                // Within |log2 h| <= 120 the others are not made (NaN), beyond it all are.
                const bool alone = std::abs(std::ilogb(h)) <= 120;
                for (int o = 0; o < mollify::table::quantity_count; ++o) {
                    const auto other = static_cast<QuantityId>(o);
                    if (o == q) continue;
                    if (alone) {
                        EXPECT_TRUE(std::isnan(one.scale(other))) << where << " other q" << o;
                    } else {
                        EXPECT_EQ(bits(one.scale(other)), bits(full->scale(other))) << where << " other q" << o;
                    }
                }
                made_alone += alone;
                // Another quantity of the same h, then the whole Smoothing.
                const auto next = static_cast<QuantityId>((q + 3) % mollify::table::quantity_count);
                {  // a set of two for a new h: both made, the rest as above
                    mollify::Smoothing::reused(0.5, dim);
                    const mollify::Smoothing& two = mollify::Smoothing::reused(h, dim, {id, next});
                    EXPECT_EQ(bits(two.scale(id)), bits(full->scale(id))) << where;
                    EXPECT_EQ(bits(two.scale_lo(next)), bits(full->scale_lo(next))) << where;
                    const auto third = static_cast<QuantityId>((q + 6) % mollify::table::quantity_count);
                    EXPECT_EQ(std::isnan(two.scale(third)), alone) << where;
                }
                EXPECT_EQ(bits(mollify::Smoothing::reused(h, dim, next).scale_lo(next)), bits(full->scale_lo(next))) << where;
                EXPECT_EQ(bits(mollify::Smoothing::reused(h, dim, id).scale(id)), bits(full->scale(id))) << where;
                EXPECT_TRUE(same_smoothing(mollify::Smoothing::reused(h, dim), *full)) << where;
                ++made;
            }
        }
    EXPECT_GE(made, 400);
    EXPECT_EQ(made_alone, 8 * 3 * 10);  // the first eight lengths, every D and quantity
    EXPECT_GE(refused, 150);
    expect_error([] { mollify::Smoothing::reused(1.0, 4, QuantityId::value); }, "dimension 4");
    // Not a quantity: the whole Smoothing, for the caller's check to name q.
    EXPECT_TRUE(same_smoothing(mollify::Smoothing::reused(0.25, 3, static_cast<QuantityId>(12)), mollify::Smoothing(0.25, 3)));
}

// The checked vector forms with h (W::value(x, h), gradient, pair, hessian,
// potential, potential_gradient) and the scalar W(q, r, h), which make only
// the scales of the quantities they name for a new h: each bit for bit the same form with
// Smoothing(h, D), with h new at every call (the kept Smoothing has only
// what the call named), at x = 0, inside, near the edge and beyond; kernels
// with a cusp (W'/r singular at 0: the gradient by W'), odd ones (1D), a 2D
// potential (log h), a combination. A quantity a form reads and does not
// name is NaN there and fails this.
template <const mollify::table::Kernel& K>
void check_vector_forms_with_h() {
    using W = mollify::StaticKernel<K>;
    constexpr int d = W::dimension;
    auto same = [](double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); };
    const double lengths[] = {0.37, 1.0, 2.5e6, 3e-30, std::nextafter(0.37, 1.0)};
    const double at[] = {0.0, 1e-9, 0.2, 0.55, 0.999, 1.0, 1.5};
    int compared = 0;
    for (const double h : lengths)
        for (const double t : at)
            for (const double sign : {1.0, -1.0}) {
                mollify::Vector<d> x{};
                for (int c = 0; c < d; ++c) x[c] = sign * t * h * (c == 0 ? 0.8 : 0.6 / std::sqrt(double(d - 1)));
                const mollify::Smoothing s(h, d);
                const std::string where = std::string(K.spec) + " D" + std::to_string(d) + " h " + std::to_string(h) +
                                          " |x|/h " + std::to_string(t) + " sign " + std::to_string(sign);
                auto fresh = [] { mollify::Smoothing::reused(0.125, d); };  // the next call's h is new
                fresh();
                EXPECT_TRUE(same(W::value(x, h), W::value(x, s))) << where;
                fresh();
                const auto g = W::gradient(x, h), gs = W::gradient(x, s);
                fresh();
                const auto p = W::pair(x, h), ps = W::pair(x, s);
                fresh();
                const auto m = W::hessian(x, h), ms = W::hessian(x, s);
                EXPECT_TRUE(same(p.value, ps.value)) << where;
                for (int i = 0; i < d; ++i) {
                    EXPECT_TRUE(same(g[i], gs[i])) << where << " gradient " << i;
                    EXPECT_TRUE(same(p.gradient[i], ps.gradient[i])) << where << " pair " << i;
                    for (int j = 0; j < d; ++j) EXPECT_TRUE(same(m[i][j], ms[i][j])) << where << " hessian " << i << j;
                }
                // The radial scalar forms, every quantity the kernel has: W(q, r, h).
                const double r = t * h;
                for (int q = 0; q < mollify::table::quantity_count; ++q) {
                    if (K.quantities[q].npieces == 0) continue;  // not in this table
                    const auto id = static_cast<QuantityId>(q);
                    double batch = 0;
                    W::evaluate(id, std::span<const double>(&r, 1), s, std::span<double>(&batch, 1));
                    fresh();
                    EXPECT_TRUE(same(W{}(id, r, h), batch)) << where << " q" << q;
                }
                if constexpr (K.has_potential) {
                    fresh();
                    EXPECT_TRUE(same(W::potential(x, h), W::potential(x, s))) << where;
                    fresh();
                    const auto e = W::potential_gradient(x, h), es = W::potential_gradient(x, s);
                    for (int i = 0; i < d; ++i) EXPECT_TRUE(same(e[i], es[i])) << where << " potential gradient " << i;
                }
                ++compared;
            }
    EXPECT_EQ(compared, 5 * 7 * 2) << K.spec;
}

TEST(Smoothing, VectorFormsWithHAreTheSmoothingsForms) {
    check_vector_forms_with_h<tables::wendland_k_2_D3>();
    check_vector_forms_with_h<tables::wendland_k_0_D1>();  // a cusp, W'/r singular at 0
    check_vector_forms_with_h<tables::wendland_k_1_D2>();  // the 2D potential's log h
    check_vector_forms_with_h<tables::wendland_missing_k_1_l_1_D2>();
    check_vector_forms_with_h<tables::mollifier_M_4_order_4_D3>();
    check_vector_forms_with_h<tables::combo_m_3_base_wendland_k_2_D3>();
    check_vector_forms_with_h<tables::combo_m_3_base_wendland_k_3_l_1_D1>();
    check_vector_forms_with_h<tables::box_d1_D1>();  // odd in 1D
}

// Smoothing's powers of h by the CPU's fused multiply-add and by Dekker's
// products (what a CPU without FMA runs): the same bits, for every quantity
// alone, all at once and random sets, in every D, at 200,000 random h across the range
// and beyond it (the same refusals). Its FMA copy compiled with contraction
// (without -ffp-contract=off for src/smoothing.cpp) differs in most low parts.
TEST(Smoothing, ScalesTheSameWithoutFma) {
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> mantissa(1.0, 2.0);
    std::uniform_int_distribution<int> exponent(-140, 140);
    std::array<double, mollify::table::quantity_count> a, a_lo, b, b_lo;
    int compared = 0, refused = 0;
    for (int k = 0; k < 200000; ++k) {
        const double h = std::ldexp(mantissa(rng), exponent(rng));
        const int dim = 1 + k % 3;
        // Every quantity, one alone, or any set of them.
        const unsigned needed = k % 3 == 0   ? mollify::detail::every_quantity
                                : k % 3 == 1 ? 1u << (k / 3 % mollify::table::quantity_count)
                                             : static_cast<unsigned>(rng() % (mollify::detail::every_quantity + 1));
        a.fill(0.0), a_lo.fill(0.0), b.fill(0.0), b_lo.fill(0.0);
        bool a_refused = false, b_refused = false;
        try {
            mollify::detail::smoothing_scales(h, 1 / h, dim, needed, true, a, a_lo);
        } catch (const Error&) {
            a_refused = true;
        }
        try {
            mollify::detail::smoothing_scales(h, 1 / h, dim, needed, false, b, b_lo);
        } catch (const Error&) {
            b_refused = true;
        }
        ASSERT_EQ(a_refused, b_refused) << "h " << h << " D" << dim << " needed " << needed;
        refused += a_refused;
        if (a_refused) continue;
        for (int q = 0; q < mollify::table::quantity_count; ++q) {
            const auto i = static_cast<std::size_t>(q);
            EXPECT_EQ(std::bit_cast<std::uint64_t>(a[i]), std::bit_cast<std::uint64_t>(b[i])) << "h " << h << " D" << dim << " q" << q;
            EXPECT_EQ(std::bit_cast<std::uint64_t>(a_lo[i]), std::bit_cast<std::uint64_t>(b_lo[i]))
                << "h " << h << " D" << dim << " q" << q;
        }
        ++compared;
    }
    EXPECT_GE(compared, 150000);
    EXPECT_GE(refused, 900);
#if defined(__x86_64__)
    // On a CPU without FMA both are Dekker's: then this test compares nothing new.
    if (!__builtin_cpu_supports("fma")) std::cout << "no FMA on this CPU: both sides are Dekker's products\n";
#endif
}

// The checked scalar call k(q, r, h) (k.value, k.potential) takes its own
// way into the evaluator (one radius, without a batch's chunks): for every
// catalogue kernel, both precisions and every quantity it has, at the hard
// radii (0, the smallest subnormal, each piece's ends and the doubles beside
// them, the support's edge, beyond it) and tiny to huge h, it is the value
// the batch gives the same radius among 200 or more others (past the blocks
// of 64 and the one-pass loops' vector body): bit for bit on generic x86-64
// (the same operations), and on the instruction set chosen here within
// fused_bound (a block loop may contract a product into an FMA where the
// one-point path does not: measured, the fast precision's second
// derivatives and potentials).
TEST(Runtime, ScalarCallIsTheBatchsValue) {
#if defined(MOLLIFY_SANITIZED_BUILD)
    // Under the sanitizers (its memory, not its numbers; 31 s with all four)
    const std::vector<double> lengths{0.37, 3e-30};
#else
    const std::vector<double> lengths{1.0, 0.37, 2.5e6, 3e-30};
#endif
    const std::string chosen(mollify::isa());
    for (const std::string& isa : {std::string("generic"), chosen}) {
        const ForcedIsa forced(isa);
        const bool same_operations = isa == "generic";
        int compared = 0;
        for (const mollify::table::Kernel* table : tables::all_kernels)
            for (const mollify::Precision pr : {mollify::Precision::accurate, mollify::Precision::fast}) {
                const mollify::Kernel k(*table, pr);
                std::vector<double> hard{0.0, 0x1p-1074, 1e-300, 1e-8, 0.25, 1.0, 1.5, 3.0};
                for (int q = 0; q < mollify::table::quantity_count; ++q)
                    for (int p = 0; p < table->quantities[q].npieces; ++p) {
                        const double lo = table->quantities[q].pieces[p].lo;
                        if (lo > 0 && lo < 8) hard.insert(hard.end(), {std::nextafter(lo, 0.0), lo, std::nextafter(lo, 8.0)});
                    }
                std::sort(hard.begin(), hard.end());
                hard.erase(std::unique(hard.begin(), hard.end()), hard.end());
                const std::vector<double> base = radii(std::max<std::size_t>(200, 140 + 3 * hard.size()), 11);
                std::vector<std::size_t> at;  // the hard radii's places, then every 37th
                for (std::size_t i = 0; i < hard.size(); ++i) at.push_back(100 + 3 * i);
                for (std::size_t i = 0; i < base.size(); i += 37) at.push_back(i);
                for (const double h : lengths) {
                    std::vector<double> r(base);
                    for (double& x : r) x *= h;
                    for (std::size_t i = 0; i < hard.size(); ++i) r[at[i]] = hard[i] * h;
                    std::vector<double> out(r.size());
                    for (int q = 0; q < mollify::table::quantity_count; ++q) {
                        if (!table->quantities[q].npieces) continue;
                        if (q >= static_cast<int>(QuantityId::potential) && !k.has_potential()) continue;
                        const auto id = static_cast<QuantityId>(q);
                        k.evaluate(id, r, h, out);
                        const double floor = mollify::testing::ulp_floor(out.data(), out.size(), pr);
                        const double bound = mollify::testing::fused_bound(*table, id, pr);
                        for (const std::size_t i : at) {
                            const double scalar = k(id, r[i], h);
                            ++compared;
                            const bool agree = same_operations ? mollify::testing::same_bits(scalar, out[i])
                                                               : mollify::testing::ulps(scalar, out[i], floor) <= bound;
                            if (!agree)
                                ADD_FAILURE() << table->spec << " D" << table->dim << " " << mollify::quantity_names[q]
                                              << " " << (pr == mollify::Precision::fast ? "fast" : "accurate") << " on "
                                              << isa << ": k(q, r, h) = " << scalar << ", the batch " << out[i]
                                              << " at r = " << r[i] << ", h = " << h;
                        }
                    }
                }
            }
        EXPECT_GT(compared, 100000) << isa;
    }
    // A bad radius or length is named as the batch names it.
    const mollify::Kernel k = mollify::kernel("wendland:k=2", 3);
    for (const mollify::Kernel& each : {k, k.with(mollify::Precision::fast)}) {
        expect_error([&] { each.value(not_a_number, 1.0); }, "r = nan");
        expect_error([&] { each.value(-0.25, 1.0); }, "r = -0.25");
        expect_error([&] { each.value(inf, 1.0); }, "r = inf");
        expect_error([&] { each(QuantityId::dr, 0.5, 0.0); }, "h = 0");
    }
}

TEST(Runtime, BatchesNameTheBadInput) {
    using mollify::Precision;
    expect_batches_name_bad_input<tables::wendland_k_2_D3, Precision::accurate>();
    expect_batches_name_bad_input<tables::wendland_k_2_D3, Precision::fast>();
    expect_batches_name_bad_input<tables::combo_m_3_base_wendland_k_2_D3, Precision::accurate>();
    expect_batches_name_bad_input<tables::wendland_k_1_D2, Precision::fast>();
    expect_batches_name_bad_input<tables::wendland_k_0_D1, Precision::accurate>();  // cusp: the point-by-point loop
    expect_batches_name_bad_input<tables::combo_m_3_base_wendland_k_3_l_1_D1, Precision::fast>();
}

// Precision::accurate (double-double edge factors) against Precision::fast:
// the same function, so within the fast form's own error (tests/accuracy_test
// measures both against the exact values); and the double-double arithmetic
// keeps the runtime's promises where its parts meet 0, infinity or huge
// scales: S = sqrt(1 - q^2) = 0 exactly at the edge of a missing Wendland
// function, q^-3 near a cusp, h^p near the end of the double range.
TEST(Runtime, AccurateAndFastPrecisionsAgreeAndStayFinite) {
    using A = mollify::StaticKernel<tables::wendland_missing_k_1_l_1_D2>;
    using F = mollify::StaticKernel<tables::wendland_missing_k_1_l_1_D2, mollify::Precision::fast>;
    static_assert(A::precision == mollify::Precision::accurate, "accurate is the default");
    for (const double h : {1.0, 1e-8, 3e7}) {
        const mollify::Smoothing s(h, 2);
        EXPECT_EQ(A::radial<QuantityId::value>(h, s), 0.0) << "h = " << h;
        EXPECT_TRUE(std::isfinite(A::radial<QuantityId::potential>(h, s))) << "h = " << h;
        for (const double r : radii(200, 7)) {
            const double a = A::radial<QuantityId::value>(r * h, s), f = F::radial<QuantityId::value>(r * h, s);
            EXPECT_NEAR(a, f, 64 * std::numeric_limits<double>::epsilon() * std::abs(a)) << "r/h = " << r << " h = " << h;
        }
    }
    // Wendland k = 0 has a cusp: its Hessian part ~ q^-3 is finite down to
    // q ~ 1e-102 and +-inf (never NaN) below.
    using C = mollify::StaticKernel<tables::wendland_k_0_D1>;
    const mollify::Smoothing one(1.0, 1);
    for (const double r : {1e-10, 1e-101, 1e-110, 1e-300}) {
        const double x = C::radial<QuantityId::hess_radial>(r, one);
        EXPECT_FALSE(std::isnan(x)) << "r = " << r;
        if (r > 1e-102) {
            EXPECT_TRUE(std::isfinite(x)) << "r = " << r;
        }
    }
    // Scales near the end of the accepted range (h^-7 ~ 5.5e270 ~ 2^899 for
    // the 3D Hessian part at h = 2.1e-39, mollify::scale_range): no NaN
    // from splitting huge factors.
    using W = mollify::StaticKernel<tables::wendland_k_4_l_4_D3>;
    const mollify::Smoothing tiny(2.1e-39, 3);
    for (const double r : radii(200, 8)) {
        EXPECT_TRUE(std::isfinite(W::radial<QuantityId::hess_radial>(r * 2.1e-39, tiny))) << "r/h = " << r;
        EXPECT_TRUE(std::isfinite(W::radial<QuantityId::value>(r * 2.1e-39, tiny))) << "r/h = " << r;
    }
}

// The accurate precision's last product (value times h^p) leaves out its
// overflow guard only for polynomial terms bounded on the support
// (table::bounded_term: the fused loops, StaticKernel's bounded pieces);
// elsewhere the guard stays, and a value that overflows is +-inf of its sign.
TEST(Runtime, UnboundedTermsKeepTheOverflowGuard) {
    using mollify::table::Term;
    const double c[] = {3, 18, 35}, huge[] = {3, 18, 0x1p400}, nan[] = {3, std::nan(""), 35};
    Term t{};
    t.basis = mollify::table::Basis::one, t.var = mollify::table::Var::r, t.edge = 1.0, t.edge_power = 6, t.c = c, t.n = 3;
    EXPECT_EQ(mollify::table::term_bound(t), 56 * 64);  // (3 + 18 + 35) (1 + 1)^6
    EXPECT_TRUE(mollify::table::bounded_term(t));
    Term low = t, log = t, big = t, bad = t;
    low.low = -1, log.basis = mollify::table::Basis::log, big.c = huge, bad.c = nan;
    for (const Term& u : {low, log, big, bad}) EXPECT_FALSE(mollify::table::bounded_term(u));
    // Every polynomial term of the catalogue is bounded (so the fused loops take them all).
    int polynomial = 0;
    for (const mollify::table::Kernel* k : tables::all_kernels)
        for (const mollify::table::Quantity& q : k->quantities)
            for (int p = 0; p < q.npieces; ++p)
                for (int j = 0; j < q.pieces[p].nterms; ++j) {
                    const Term& u = q.pieces[p].terms[j];
                    if (u.basis != mollify::table::Basis::one || u.low < 0 || u.var == mollify::table::Var::shifted) continue;
                    ++polynomial;
                    EXPECT_TRUE(mollify::table::bounded_term(u)) << k->spec << " D" << k->dim;
                }
    EXPECT_GT(polynomial, 1000);
    // Wendland C4's W times 2^700 (unsplit), at h = 2^-128 (h^-3 = 2^384): the
    // values up to ~2^1090 overflow, where the product's cross terms overflow
    // too, to either sign; the guarded product gives +inf, else 2^700 W_h.
    const mollify::table::Kernel& base = tables::wendland_k_2_D3;
    mollify::table::Kernel scaled = base;
    const mollify::table::Quantity& value = base.quantities[static_cast<int>(QuantityId::value)];
    std::vector<mollify::table::Piece> pieces(value.pieces, value.pieces + value.npieces);
    std::vector<std::vector<Term>> terms(pieces.size());
    std::vector<std::vector<double>> coefficients, low_parts;
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        for (int j = 0; j < pieces[p].nterms; ++j) {
            Term u = pieces[p].terms[j];
            coefficients.emplace_back(u.c, u.c + u.n);
            low_parts.emplace_back(u.c_lo, u.c_lo + u.n);
            for (double& x : coefficients.back()) x = std::ldexp(x, 700);
            for (double& x : low_parts.back()) x = std::ldexp(x, 700);
            u.c = coefficients.back().data(), u.c_lo = low_parts.back().data();
            u.split = 0, u.m = nullptr, u.content = u.content_lo = 0;
            terms[p].push_back(u);
        }
        pieces[p].terms = terms[p].empty() ? nullptr : terms[p].data();
    }
    scaled.quantities[static_cast<int>(QuantityId::value)] = {pieces.data(), value.npieces};
    const mollify::Kernel big_kernel(scaled), kernel(base);
    const double h = 0x1p-128;
    std::vector<double> r;
    for (int i = 0; i <= 2000; ++i) r.push_back(h * i / 2000.0);
    std::vector<double> got(r.size()), w(r.size());
    big_kernel.evaluate(QuantityId::value, r, h, got);
    kernel.evaluate(QuantityId::value, r, h, w);
    int overflowed = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
        const double expected = std::ldexp(w[i], 700);
        overflowed += std::isinf(expected);
        ASSERT_EQ(got[i], expected) << "r/h = " << r[i] / h;
    }
    EXPECT_GT(overflowed, 100);
}

// A combination whose W'/r has its first radius moved (a table made at run
// time; not a kernel's derivative, only a plumbing check): the pair loop
// takes each radius's distance once for W and W'/r where their radii are
// the same (Plan::shared_pair), so here it must not: its grad W is then
// (W'/r)(|x|) x with W'/r's own radius, as the one-quantity evaluation
// gives it (with the plan's same_radii check dropped, the pair loop took
// W's radius 1/3 for W'/r's term too, and this failed at the first q > 0).
TEST(Runtime, PairsOfACombinationTakeEachQuantitysOwnRadii) {
    using mollify::table::Term;
    const mollify::table::Kernel& base = tables::combo_m_3_base_wendland_k_2_D3;
    mollify::table::Kernel moved = base;
    const mollify::table::Quantity& over_r = base.quantities[static_cast<int>(QuantityId::grad_over_r)];
    std::vector<mollify::table::Piece> pieces(over_r.pieces, over_r.pieces + over_r.npieces);
    std::vector<Term> first(pieces[0].terms, pieces[0].terms + pieces[0].nterms);
    ASSERT_GT(first.size(), 1u);
    ASSERT_NE(first[0].edge, 1.0);
    first[0].edge = 0.3, first[0].edge_lo = 0;
    pieces[0].terms = first.data();
    moved.quantities[static_cast<int>(QuantityId::grad_over_r)] = {pieces.data(), over_r.npieces};
    for (const mollify::Precision p : {mollify::Precision::accurate, mollify::Precision::fast}) {
        const mollify::Kernel kernel(moved, p);
        const std::size_t n = 1000;
        const double h = 0.9;
        std::vector<double> x(n), y(n), z(n), w(n), gx(n), gy(n), gz(n), r(n), g(n);
        for (std::size_t i = 0; i < n; ++i) {  // |x| from 0 to 0.4 h, across both radii
            r[i] = 0.4 * h * static_cast<double>(i) / n;
            x[i] = r[i], y[i] = 0, z[i] = 0;
        }
        const std::span<const double> in[] = {x, y, z};
        const std::span<double> out[] = {gx, gy, gz};
        kernel.pairs(in, kernel.smoothing(h), w, out);
        kernel.evaluate(QuantityId::grad_over_r, r, h, g);
        // The two paths round differently (the fast precision's sum cancels:
        // ~10^3 ulp); the wrong radius changes the value by ~1 of its size.
        double size = 0;
        for (std::size_t i = 0; i < n; ++i) size = std::max(size, std::abs(g[i] * x[i]));
        for (std::size_t i = 0; i < n; ++i)
            ASSERT_NEAR(gx[i], g[i] * x[i], 1e-9 * size)
                << "q = " << r[i] / h << (p == mollify::Precision::accurate ? ", accurate" : ", fast");
    }
}

// At h = 2^k, f_h(q h) = 2^(k p) f_1(q) exactly: q = r/h is the same double
// and h^p a power of two, so the value differs from h = 1's only in its
// last product, exact wherever the result is a normal double. Every
// catalogue kernel and quantity (not the 2D potential, whose log h term is
// not a power), both precisions, at the smallest and largest accepted h
// (values above 2^-968, where the last rounding's error is a normal double):
// where h^p's low part or a split term's content times h^p (content_in_scale)
// left the normal range, the accurate precision was an ulp off or +-inf
// where the value is finite (stop 44's kernels at h = 2^146 and 2^-146 in
// 3D: 2^-1018 values an ulp off, hess_radial inf for 2^934). And h just
// beyond the range is refused, naming it.
TEST(Runtime, PowerOfTwoSmoothingLengthsScaleExactly) {
    const std::vector<double> q = {1e-300, 1e-3, 0.1, 0.5, 0.77, 0.9, 0.999, 0.99999, 1 - 0x1p-40, 1.3, 1.9, 2.7};
    int compared = 0;
    for (const mollify::table::Kernel* t : tables::all_kernels) {
        const int D = t->dim;
        // The accepted powers of two: h^p within 2^+-900 for the extreme p = -(D + 4).
        const int k_max = 900 / (D + 4);
        for (const mollify::Precision pr : {mollify::Precision::accurate, mollify::Precision::fast}) {
            const mollify::Kernel kernel(*t, pr);
            const mollify::Smoothing unit(1.0, D);
            for (const int k : {-k_max, 1 - k_max, -64, 64, k_max - 1, k_max}) {
                const mollify::Smoothing s(std::ldexp(1.0, k), D);
                for (int qi = 0; qi < mollify::table::quantity_count; ++qi) {
                    const auto Q = static_cast<QuantityId>(qi);
                    if (qi >= static_cast<int>(QuantityId::potential) && !kernel.has_potential()) continue;
                    if (D == 2 && Q == QuantityId::potential) continue;
                    std::vector<double> r(q.size()), at_h(q.size()), at_1(q.size());
                    for (std::size_t i = 0; i < q.size(); ++i) r[i] = std::ldexp(q[i], k);
                    kernel.evaluate(Q, r, s, at_h);
                    kernel.evaluate(Q, q, unit, at_1);
                    const int p = mollify::detail::scale_power(Q, D);
                    for (std::size_t i = 0; i < q.size(); ++i) {
                        const double expected = std::ldexp(at_1[i], k * p);
                        // r = q 2^k itself exact; the result's rounding error
                        // 2^-53 |result| normal (below 2^-968 the double-double
                        // low parts are subnormal: the accuracy suite's tiny values)
                        if (std::ldexp(r[i], -k) != q[i] || !(std::abs(expected) >= 0x1p-968)) continue;
                        ++compared;
                        ASSERT_EQ(at_h[i], expected) << t->spec << " D" << D << " " << mollify::quantity_names[qi]
                                                     << " h = 2^" << k << " q = " << q[i]
                                                     << (pr == mollify::Precision::fast ? " fast" : " accurate");
                    }
                }
            }
            expect_error([&] { mollify::Smoothing(std::ldexp(1.0, k_max + 1), D); }, "is outside [2^-900, 2^900]");
            expect_error([&] { mollify::Smoothing(std::ldexp(1.0, -k_max - 1), D); }, "is outside [2^-900, 2^900]");
        }
    }
    EXPECT_GT(compared, 100000);
}

// A table given at run time (here a copy of a catalogue table, owned by the
// kernel) is evaluated like the catalogue's own: the same plan, the same
// bits; a null table is an error.
TEST(Runtime, KernelOfATableLoadedAtRunTime) {
    const auto owned = std::make_shared<const mollify::table::Kernel>(tables::combo_m_3_base_wendland_k_2_D3);
    const mollify::Kernel loaded = mollify::kernel(owned);
    const mollify::Kernel named = mollify::kernel("combo:m=3,base=wendland:k=2", 3);
    EXPECT_EQ(&loaded.table(), owned.get());
    EXPECT_EQ(loaded.spec(), named.spec());
    const auto r = radii(500, 11);
    for (const QuantityId q : {QuantityId::value, QuantityId::grad_over_r, QuantityId::potential}) {
        std::vector<double> a(r.size()), b(r.size());
        loaded.evaluate(q, r, 0.7, a);
        named.evaluate(q, r, 0.7, b);
        for (std::size_t i = 0; i < r.size(); ++i) ASSERT_EQ(a[i], b[i]) << "r = " << r[i];
    }
    expect_error([] { mollify::kernel(std::shared_ptr<const mollify::table::Kernel>{}); }, "null table");
}

// The instruction set in use is the best of the three compiled in that
// this CPU runs (the sanitizer build has no x86-64-v4 copy: CMakeLists.txt),
// and can be switched back and forth.
TEST(Runtime, InstructionSetIsChosenAndCanBeForced) {
    const std::string chosen(mollify::isa());
    EXPECT_TRUE(chosen == "generic" || chosen == "x86-64-v3" || chosen == "x86-64-v4") << chosen;
#if defined(__x86_64__)
    __builtin_cpu_init();
    const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                    __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
#if defined(MOLLIFY_SANITIZED_BUILD)
    const bool with_v4 = false;
#else
    const bool with_v4 = true;
#endif
    const char* forced = std::getenv("MOLLIFY_ISA");
    if (!forced || !*forced) {
        EXPECT_EQ(chosen, v4 && with_v4 ? "x86-64-v4" : v3 ? "x86-64-v3" : "generic");
    }
#endif
    mollify::use_isa("generic");
    EXPECT_EQ(mollify::isa(), "generic");
    mollify::use_isa(chosen);
    EXPECT_EQ(mollify::isa(), chosen);
}
