// The run-time form (mollify::kernel: a plan of the table evaluated by
// libmollify's data-driven loops) against the compile-time form
// (StaticKernel: the table a template argument, unrolled) on the tables
// of runtime_forms/cases_*.cpp, every quantity, both precisions, the batch
// and the pair loop, at the hard points: near 0 (down to subnormal r/h), at
// and within ulps of the support edge, within ulps of every breakpoint and
// combination radius, beyond the support, at h from 1e-30 to 1e30.
//
// On the instruction set this test is compiled for (generic x86-64) the two
// must agree bit for bit: the evaluator performs the same operations in the
// same order. The x86-64-v3 and x86-64-v4 copies (FMA) round differently;
// they are held to the accuracy suite's reasoning instead (see fused_bound).
//
// Instantiating StaticKernel for all 256 catalogue tables is the deleted
// registry's cost (22 minutes of compile); the tables compared are a cover of
// every evaluation path the catalogue takes (tests/shape_features.hpp,
// chosen greedily), and CoverEveryPathOfTheCatalogue fails if a table of the
// catalogue takes a path none of them takes.
#include "runtime_forms/static_case.hpp"
#include "fused_bound.hpp"
#include "hard_points.hpp"
#include "shape_features.hpp"

#include <mollify/kernel.hpp>
#include <mollify/tables/catalogue.hpp>
#include <mollify/detail/show.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace tables = mollify::tables;
namespace table = mollify::table;
using mollify::Precision;
using mollify::QuantityId;
using mollify::Smoothing;

using mollify::testing::Case;
using mollify::testing::fused_bound;
using mollify::testing::hard_q;
using mollify::testing::same_bits;
using mollify::testing::ulp_floor;
using mollify::testing::ulps;

// The greedy cover printed by the features of every catalogue table; the
// issue's benchmark kernels (Wendland C4 and combo:m=3,base=wendland:k=2 in
// 3D) among them.
const std::vector<Case>& cases() {
    static const std::vector<Case> all = [] {
        std::vector<Case> out;
        for (auto part : {mollify::testing::cases_1, mollify::testing::cases_2, mollify::testing::cases_3,
                          mollify::testing::cases_4})
            for (const Case& c : part()) out.push_back(c);
        return out;
    }();
    return all;
}

constexpr double smoothing_lengths[] = {1.0, 0.37, 3e-7, 2.5e6, 1e-30, 1e30};

struct Isa {
    const char* name;
    bool bit_for_bit;
};

std::vector<Isa> isas() {
    std::vector<Isa> out = {{"generic", true}};
    for (const char* fused : {"x86-64-v3", "x86-64-v4"}) {
        try {
            mollify::use_isa(fused);
            out.push_back({fused, false});
        } catch (const mollify::Error&) {
            // This CPU lacks AVX2 + FMA (v3) or AVX-512 (v4): that copy cannot run here.
        }
    }
    return out;
}

// Where no static form of the same ISA compares (x86-64-v3, -v4: the static
// units are generic), the pair loop against the same kernel's batches on
// the same ISA, bit for bit: W(r) and (W'/r)(r) x at r = |x| as the pair
// loop computes it (multiply-adds: fused there). Its own loops (one pass
// for whole quantities, blocks sharing q and e) against evaluate's. Not
// for odd kernels or where W'/r is singular at 0 (W' x/r there).
void expect_pairs_as_batches(const mollify::Kernel& k, const std::span<const double>* x, const Smoothing& s,
                             const std::vector<double>& w, const std::span<double>* grad, const char* isa) {
    const table::Kernel& t = k.table();
    if (t.parity < 0) return;  // odd 1D kernels: point by point, sign(x) f(|x|)
    const std::size_t n = w.size();
    std::vector<double> r(n), value(n), over_r(n), at_zero(1);
    k.evaluate(QuantityId::grad_over_r, std::vector<double>{0.0}, s, at_zero);
    if (!std::isfinite(at_zero[0])) return;
    for (std::size_t i = 0; i < n; ++i) {
        if (t.dim == 1) {  // |x_0|, not the root of its square (which underflows below 2^-511)
            r[i] = std::abs(x[0][i]);
            continue;
        }
        double sq = std::fma(x[1][i], x[1][i], x[0][i] * x[0][i]);
        if (t.dim == 3) sq = std::fma(x[2][i], x[2][i], sq);
        r[i] = std::sqrt(sq);
    }
    k.evaluate(QuantityId::value, r, s, value);
    k.evaluate(QuantityId::grad_over_r, r, s, over_r);
    for (std::size_t i = 0; i < n; ++i) {
        const std::string where = std::string(isa) + " pairs " + t.spec + " D" + std::to_string(t.dim) + " " +
                                  std::string(mollify::name(k.precision())) + " point " + std::to_string(i);
        ASSERT_TRUE(same_bits(w[i], value[i])) << where << ": W " << w[i] << " against the batch's " << value[i];
        for (std::size_t d = 0; d < static_cast<std::size_t>(t.dim); ++d)
            ASSERT_TRUE(same_bits(grad[d][i], over_r[i] * x[d][i]))
                << where << ": grad " << grad[d][i] << " against " << over_r[i] * x[d][i];
    }
}

}  // namespace

TEST(Runtime, CoverEveryPathOfTheCatalogue) {
    std::set<std::string> covered;
    for (const Case& c : cases())
        for (const std::string& f : mollify::testing::features(*c.table)) covered.insert(f);
    for (const table::Kernel* k : tables::all_kernels)
        for (const std::string& f : mollify::testing::features(*k))
            EXPECT_TRUE(covered.count(f)) << k->spec << " D" << k->dim << " takes a path no compared table takes: " << f;
}

TEST(Runtime, CompileTimeAndRunTimeFormsAgreeBitForBit) {
    for (const Isa& isa : isas()) {
        mollify::use_isa(isa.name);
        ASSERT_EQ(mollify::isa(), isa.name);
        double worst = 0;
        for (const Case& c : cases()) {
            const table::Kernel& k = *c.table;
            const std::vector<double> q = hard_q(k);
            for (const Precision pr : {Precision::accurate, Precision::fast}) {
                const mollify::Kernel runtime = mollify::kernel(k, pr);
                ASSERT_EQ(&runtime.table(), &k);
                for (const double h : smoothing_lengths) {
                    const Smoothing s(h, k.dim);
                    std::vector<double> r(q.size()), a(q.size()), b(q.size());
                    for (std::size_t i = 0; i < q.size(); ++i) r[i] = q[i] * h;
                    for (int qi = 0; qi < table::quantity_count; ++qi) {
                        if (k.quantities[qi].npieces == 0) continue;
                        const auto id = static_cast<QuantityId>(qi);
                        c.batch(pr, id, r.data(), a.data(), r.size(), s);
                        runtime.evaluate(id, r, s, b);
                        const double floor = ulp_floor(a.data(), a.size(), pr);
                        for (std::size_t i = 0; i < r.size(); ++i) {
                            const std::string where = std::string(isa.name) + " " + k.spec + " D" + std::to_string(k.dim) +
                                                      " " + mollify::quantity_names[qi] + " " +
                                                      std::string(mollify::name(pr)) + " r/h = " +
                                                      mollify::detail::show(q[i]) + " h = " + mollify::detail::show(h);
                            if (isa.bit_for_bit) {
                                ASSERT_TRUE(same_bits(a[i], b[i])) << where << ": static " << a[i] << " run-time " << b[i];
                            } else {
                                const double e = ulps(a[i], b[i], floor);
                                worst = std::max(worst, e);
                                ASSERT_LE(e, fused_bound(k, id, pr)) << where << ": static " << a[i] << " run-time " << b[i];
                            }
                        }
                    }
                    // The pair loop at displacements along a diagonal and at random.
                    const std::size_t n = q.size();
                    std::vector<std::vector<double>> x(3, std::vector<double>(n)), ga(3, std::vector<double>(n)),
                        gb(3, std::vector<double>(n));
                    std::vector<double> wa(n), wb(n);
                    std::mt19937_64 rng(7);
                    std::uniform_real_distribution<double> u(-1, 1);
                    for (std::size_t i = 0; i < n; ++i)
                        for (int d = 0; d < k.dim; ++d)
                            x[static_cast<std::size_t>(d)][i] =
                                (i % 2 ? q[i] / std::sqrt(static_cast<double>(k.dim)) * (d == 0 ? -1 : 1) : 1.25 * u(rng)) * h;
                    const std::span<const double> in[] = {x[0], x[1], x[2]};
                    const std::span<double> out_a[] = {ga[0], ga[1], ga[2]}, out_b[] = {gb[0], gb[1], gb[2]};
                    const auto dim = static_cast<std::size_t>(k.dim);
                    c.pairs(pr, in, s, wa.data(), out_a, n);
                    runtime.pairs(std::span(in, dim), s, wb, std::span(out_b, dim));
                    for (std::size_t i = 0; i < n; ++i) {
                        const std::string where = std::string(isa.name) + " pairs " + k.spec + " D" + std::to_string(k.dim) +
                                                  " " + std::string(mollify::name(pr)) + " h = " + mollify::detail::show(h) +
                                                  " point " + std::to_string(i);
                        if (isa.bit_for_bit) {
                            ASSERT_TRUE(same_bits(wa[i], wb[i])) << where << ": W " << wa[i] << " against " << wb[i];
                            for (std::size_t d = 0; d < dim; ++d)
                                ASSERT_TRUE(same_bits(ga[d][i], gb[d][i])) << where << ": grad " << ga[d][i] << " against " << gb[d][i];
                        }
                    }
                    if (!isa.bit_for_bit) expect_pairs_as_batches(runtime, in, s, wb, out_b, isa.name);
                }
            }
        }
        if (!isa.bit_for_bit) std::printf("[forms] %s against generic StaticKernel: max %.3g ulp\n", isa.name, worst);
    }
    mollify::use_isa("generic");
}
