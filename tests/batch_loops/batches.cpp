// StaticKernel's batch loops in a unit built -march=x86-64-v3 -mtune=znver1
// (tests/CMakeLists.txt): GCC's Zen 1 tuning prefers 128-bit vectors, which
// MOLLIFY_BATCH_LOOP overrides with 256 (include/mollify/detail/isa.hpp);
// and built -march=x86-64-v4 -mtune=sapphirerapids (batch_loops_v4_test),
// whose 256-bit preference it overrides with 512. A batch runs its points
// through the wide lanes, a shorter vector remainder and scalar code; a
// single point only through the scalar code. They must agree bit for bit: a
// value may not depend on the batch it was computed in (nor on the vector
// width, which then changes no rounding). And the batch against the run-time
// form's copy for the same instruction set (libmollify's evaluator for it,
// chosen by the caller): within runtime_forms_test's bounds (fused_bound.hpp),
// since the static form's unrolled expressions are contracted into FMAs where
// the data-driven loops have their own; bit for bit where both sum a
// combination's distinct terms (shared_sums below). And the pair loops'
// W and grad W, and the batch forms of W and W'/r, against the scalar forms
// at the same |x|: the loops leave out a combination's terms that no point
// of a register reaches (detail::levels, quantity_levels), the scalar forms
// never do; registers with one point below a level's radius test that
// choice (levels_against_radial, evaluate_levels_against_radial).
#include "batch_loops/batches.hpp"
#include "fused_bound.hpp"
#include "hard_points.hpp"

#include <mollify/kernel.hpp>
#include <mollify/static_kernel.hpp>
#include <mollify/tables/combo/m_2_base_wendland_k_1_D2.hpp>
#include <mollify/tables/combo/m_3_base_wendland_k_2_D3.hpp>
#include <mollify/tables/wendland/k_1_D1.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace batch_loops {

namespace {

namespace table = mollify::table;
using mollify::Precision;
using mollify::QuantityId;
using mollify::Smoothing;
using mollify::testing::same_bits;

// Does the static form sum the quantity's distinct terms (a combination's,
// Precision::accurate where the target fuses multiply-add)? For W and W'/r
// the run-time form's fused loop (the generator lists their shapes) does the
// same operations in the same order, so there the two agree bit for bit.
template <const table::Kernel& K, std::size_t... Q>
constexpr std::array<bool, table::quantity_count> shared_sums(std::index_sequence<Q...>) {
    return {mollify::detail::shared_accurate<K, static_cast<int>(Q)>...};
}

// Every digit: the values differ in the last place.
std::string bits(double x) {
    char text[64];
    std::snprintf(text, sizeof text, "%.17g (%a)", x, x);
    return std::string(text);
}

// The pair loops' W and grad W = (W'/r) x against the scalar forms of W
// and W'/r at the same radius |x| (detail::radius, as the loops take it):
// those take every term at every point, the pair loops leave out a
// combination's terms that no point of a register reaches (levels), so this
// is what tells a wrongly chosen level.
template <class S, class Mismatch>
void expect_pair_as_radial(const std::array<double, S::dimension>& x, double w, const auto& grad, std::size_t i,
                           const Smoothing& s, Mismatch mismatch) {
    constexpr int D = S::dimension;
    double r = std::abs(x[0]);
    if constexpr (D == 2) r = mollify::detail::radius(x[0], x[1]);
    if constexpr (D == 3) r = mollify::detail::radius(x[0], x[1], x[2]);
    // the scalar forms: every term at every point (a batch of one point
    // takes the levels of its own radius)
    const double value = S::template radial<QuantityId::value>(r, s);
    const double over_r = S::template radial<QuantityId::grad_over_r>(r, s);
    if (!same_bits(w, value)) mismatch("pairs W against W at |x|", w, value);
    for (int c = 0; c < D; ++c)
        if (!same_bits(grad[c][i], over_r * x[c]))
            mismatch("pairs grad W_" + std::to_string(c) + " against (W'/r)(|x|) x", grad[c][i], over_r * x[c]);
}

// S::pairs over whole arrays of displacements, into w and grad (sized as x).
template <class S>
void pairs_of(const std::array<std::vector<double>, S::dimension>& x, const Smoothing& s, std::vector<double>& w,
              std::array<std::vector<double>, S::dimension>& grad) {
    mollify::Points<S::dimension> xs;
    mollify::PointsOut<S::dimension> gs;
    for (int c = 0; c < S::dimension; ++c) {
        xs[c] = x[c];
        gs[c] = grad[c];
    }
    S::pairs(xs, s, w, gs);
}

// Registers of points all at or beyond a level's radius a_L h but one, at
// (1 - 2^-4) a_L h (where the left-out term is far from 0) or one double
// below a_L h: the one point's term must be taken, in every place of the
// batch, batches of 8, 16 and 24 along x (|x| = r exactly).
template <class S>
void levels_against_radial(const Smoothing& s, Comparison& out) {
    constexpr int D = S::dimension;
    constexpr const table::Kernel& K = S::table();
    for (int l = 0; l + 1 < mollify::detail::levels<K>; ++l) {
        const double a = mollify::detail::level_bound<K>(l) * s.h();
        for (const double below : {a * (1 - 0x1p-4), std::nextafter(a, 0.0)})
            for (const std::size_t m : {8, 16, 24})
                for (std::size_t at = 0; at < m; ++at) {
                    std::array<std::vector<double>, D> x, grad;
                    for (int c = 0; c < D; ++c) {
                        x[c].assign(m, 0.0);
                        grad[c].assign(m, 0.0);
                    }
                    for (std::size_t k = 0; k < m; ++k) x[0][k] = k == at ? below : a * (1 + 0x1p-10 * static_cast<double>(k));
                    std::vector<double> w(m);
                    pairs_of<S>(x, s, w, grad);
                    for (std::size_t k = 0; k < m; ++k) {
                        std::array<double, D> xk{};
                        xk[0] = x[0][k];
                        expect_pair_as_radial<S>(xk, w[k], grad, k, s, [&](const std::string& what, double batch, double other) {
                            if (out.mismatches.size() < 20)
                                out.mismatches.push_back(std::string(K.spec) + " level " + std::to_string(l + 1) + ", h = " +
                                                         bits(s.h()) + ", " + std::to_string(m) + " points, point " +
                                                         std::to_string(k) + " at r = " + bits(x[0][k]) + " (below a_L h: " +
                                                         std::to_string(at) + "): " + what + ": batch " + bits(batch) +
                                                         ", other " + bits(other));
                        });
                    }
                    out.compared += m * (D + 1);
                }
    }
}

// The same registers for the batch evaluation of one quantity whose terms
// are radii in order (detail::quantity_levels: W and W'/r of a
// combination), StaticKernel's and the run-time form's, against the scalar
// form at each point, bit for bit (both forms sum the distinct terms
// alike); batches of 5 and 11 take the last, shorter register.
template <class S, int Q>
void evaluate_levels_against_radial(const mollify::Kernel& runtime, const Smoothing& s, Comparison& out) {
    constexpr const table::Kernel& K = S::table();
    constexpr QuantityId quantity = static_cast<QuantityId>(Q);
    for (int l = 0; l + 1 < mollify::detail::quantity_levels<K, Q>; ++l) {
        const double a = mollify::detail::level_bound<K, Q>(l) * s.h();
        for (const double below : {a * (1 - 0x1p-4), std::nextafter(a, 0.0)})
            for (const std::size_t m : {5, 8, 11, 16, 24})
                for (std::size_t at = 0; at < m; ++at) {
                    std::vector<double> r(m), batch(m), other(m);
                    for (std::size_t k = 0; k < m; ++k) r[k] = k == at ? below : a * (1 + 0x1p-10 * static_cast<double>(k));
                    S::template evaluate<quantity>(r, s, batch);
                    runtime.evaluate(quantity, r, s, other);
                    for (std::size_t k = 0; k < m; ++k) {
                        const double alone = S::template radial<quantity>(r[k], s);
                        for (const auto& [form, x] : {std::pair{"StaticKernel", batch[k]}, std::pair{"run-time", other[k]}})
                            if (!same_bits(x, alone) && out.mismatches.size() < 20)
                                out.mismatches.push_back(std::string(K.spec) + " " + table::quantity_names[Q] + " level " +
                                                         std::to_string(l + 1) + ", h = " + bits(s.h()) + ", " + form +
                                                         " batch of " + std::to_string(m) + ", point " + std::to_string(k) +
                                                         " at r = " + bits(r[k]) + " (below a_L h: " + std::to_string(at) +
                                                         "): batch " + bits(x) + ", alone " + bits(alone));
                    }
                    out.compared += 2 * m;
                }
    }
}

template <const table::Kernel& K, Precision Pr>
void compare(Comparison& out) {
    using S = mollify::StaticKernel<K, Pr>;
    const mollify::Kernel runtime = mollify::kernel(K, Pr);
    constexpr int D = S::dimension;
    const std::vector<double> q = mollify::testing::hard_q(K);
    const std::size_t n = q.size();
    const std::string kernel = std::string(K.spec) + " D" + std::to_string(D) + (Pr == Precision::fast ? " fast" : " accurate");
    auto mismatch = [&](const std::string& what, std::size_t i, double batch, double other) {
        if (out.mismatches.size() < 20)
            out.mismatches.push_back(kernel + " " + what + " at r/h = " + bits(q[i]) + ": batch " + bits(batch) +
                                     ", other " + bits(other));
        else if (out.mismatches.size() == 20)
            out.mismatches.push_back("...");
    };
    for (const double h : {1.0, 0.37, 3e-7, 2.5e6}) {
        const Smoothing s(h, D);
        std::vector<double> r(n), batch(n), reference(n);
        for (std::size_t i = 0; i < n; ++i) r[i] = q[i] * h;
        for (int qi = 0; qi < table::quantity_count; ++qi) {
            if (K.quantities[qi].npieces == 0) continue;
            const auto quantity = static_cast<QuantityId>(qi);
            S::evaluate(quantity, r, s, batch);
            runtime.evaluate(quantity, r, s, reference);
            const double floor = mollify::testing::ulp_floor(batch.data(), n, Pr);
            const double bound = mollify::testing::fused_bound(K, quantity, Pr);
            const bool lockstep =
                Pr == Precision::accurate && (quantity == QuantityId::value || quantity == QuantityId::grad_over_r) &&
                shared_sums<K>(std::make_index_sequence<table::quantity_count>{})[static_cast<std::size_t>(qi)];
            for (std::size_t i = 0; i < n; ++i) {
                double alone = 0;
                S::evaluate(quantity, std::span<const double>(&r[i], 1), s, std::span<double>(&alone, 1));
                if (!same_bits(batch[i], alone)) mismatch(std::string(table::quantity_names[qi]), i, batch[i], alone);
                const double e = mollify::testing::ulps(batch[i], reference[i], floor);
                out.worst_against_runtime = std::max(out.worst_against_runtime, e);
                if (e > bound)
                    mismatch(std::string(table::quantity_names[qi]) + " against the run-time form (" + std::to_string(e) +
                                 " ulp)", i, batch[i], reference[i]);
                else if (lockstep && !same_bits(batch[i], reference[i]))
                    mismatch(std::string(table::quantity_names[qi]) + " against the run-time form's shared terms, bit for bit",
                             i, batch[i], reference[i]);
            }
            out.compared += n;
        }
        // W + grad W at displacements of length r along a direction that
        // changes with the point (every component non-zero).
        std::array<std::vector<double>, D> x, grad;
        for (int c = 0; c < D; ++c) {
            x[c].resize(n);
            grad[c].resize(n);
        }
        std::vector<double> w(n);
        for (std::size_t i = 0; i < n; ++i)
            for (int c = 0; c < D; ++c) x[c][i] = r[i] * (c == 0 ? 0.6 : c == 1 ? -0.64 : 0.48) * (1 + 1e-3 * (i % 7));
        pairs_of<S>(x, s, w, grad);
        std::vector<double> w_alone(n);
        std::array<std::vector<double>, D> g_alone;
        for (int c = 0; c < D; ++c) g_alone[c].resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            std::array<double, D> xi, gi;
            double wi = 0;
            mollify::Points<D> one;
            mollify::PointsOut<D> one_out;
            for (int c = 0; c < D; ++c) {
                xi[c] = x[c][i];
                one[c] = std::span<const double>(&xi[c], 1);
                one_out[c] = std::span<double>(&gi[c], 1);
            }
            S::pairs(one, s, std::span<double>(&wi, 1), one_out);
            w_alone[i] = wi;
            for (int c = 0; c < D; ++c) g_alone[c][i] = gi[c];
            if (!same_bits(w[i], wi)) mismatch("pairs W", i, w[i], wi);
            for (int c = 0; c < D; ++c)
                if (!same_bits(grad[c][i], gi[c])) mismatch("pairs grad W_" + std::to_string(c), i, grad[c][i], gi[c]);
            expect_pair_as_radial<S>(xi, w[i], grad, i, s, [&](const std::string& what, double batch, double other) {
                mismatch(what, i, batch, other);
            });
        }
        out.compared += n * (D + 1);
        if constexpr (mollify::detail::levels<K> > 1 && Pr == Precision::accurate) {
            levels_against_radial<S>(s, out);
            evaluate_levels_against_radial<S, static_cast<int>(QuantityId::value)>(runtime, s, out);
            evaluate_levels_against_radial<S, static_cast<int>(QuantityId::grad_over_r)>(runtime, s, out);
        }
        // Batches of every length around the pair loops' blocks of 16
        // (detail/roots_ahead.hpp: the roots a block ahead, a last block
        // that overlaps the one before, fewer than 16 points plainly), from
        // an odd offset: each point's values as it gives them alone.
        for (const std::size_t m : {1, 15, 16, 17, 24, 31, 32, 33, 47, 48, 49, 100, 129}) {
            const std::size_t from = 3;
            if (from + m > n) {  // the sample shrank: this test would no longer cover its blocks
                out.mismatches.push_back(kernel + ": " + std::to_string(n) + " hard points, too few for a batch of " +
                                         std::to_string(m));
                continue;
            }
            std::vector<double> wm(m);
            std::array<std::vector<double>, D> gm;
            mollify::Points<D> part;
            mollify::PointsOut<D> part_out;
            for (int c = 0; c < D; ++c) {
                gm[c].resize(m);
                part[c] = std::span<const double>(x[c]).subspan(from, m);
                part_out[c] = gm[c];
            }
            S::pairs(part, s, wm, part_out);
            for (std::size_t i = 0; i < m; ++i) {
                const std::string batch = "pairs of " + std::to_string(m) + " points, point " + std::to_string(i) + ": ";
                if (!same_bits(wm[i], w_alone[from + i])) mismatch(batch + "W", from + i, wm[i], w_alone[from + i]);
                for (int c = 0; c < D; ++c)
                    if (!same_bits(gm[c][i], g_alone[c][from + i]))
                        mismatch(batch + "grad W_" + std::to_string(c), from + i, gm[c][i], g_alone[c][from + i]);
            }
            out.compared += m * (D + 1);
        }
    }
}

template <const table::Kernel& K>
void both(Comparison& out) {
    compare<K, Precision::accurate>(out);
    compare<K, Precision::fast>(out);
}

// Does run() raise an Error whose message names `needle`?
template <class Run>
bool error_names(Run run, const std::string& needle) {
    try {
        run();
    } catch (const mollify::Error& e) {
        return std::string(e.what()).find(needle) != std::string::npos;
    }
    return false;
}

// pairs(x, n) for x with a NaN, +inf or -inf in each coordinate at points
// where blocks of roots begin, lie and end, in batches of 4500 (281 blocks
// of 16 and a last one overlapping the one before) and 7 (no whole block);
// `missed` gets the cases that gave no Error naming the coordinate.
template <int D, class Pairs>
void expect_flagged(const std::string& who, Pairs pairs, std::vector<std::string>& missed) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-0.25, 0.25);  // inside h = 0.5, every level of a combination
    for (const std::size_t n : {std::size_t{4500}, std::size_t{7}}) {
        std::array<std::vector<double>, D> x;
        for (auto& c : x) {
            c.resize(n);
            for (double& v : c) v = u(rng);
        }
        const std::vector<std::size_t> places = n > 16 ? std::vector<std::size_t>{0, 17, 4200, n - 1} : std::vector<std::size_t>{3};
        for (const std::size_t i : places)
            for (int c = 0; c < D; ++c)
                for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                                         -std::numeric_limits<double>::infinity()}) {
                    double& v = x[static_cast<std::size_t>(c)][i];
                    const double kept = v;
                    v = bad;
                    const std::string needle = "coordinate x[" + std::to_string(c) + "]";
                    if (!error_names([&] { pairs(x, n); }, needle))
                        missed.push_back(who + ": " + std::to_string(bad) + " in " + needle + " of point " + std::to_string(i) +
                                         " of " + std::to_string(n) + " not named");
                    v = kept;
                }
    }
}

// StaticKernel's pairs and the run-time form's for table K, precision Pr.
template <const table::Kernel& K, Precision Pr>
void expect_pairs_flagged(std::vector<std::string>& missed) {
    using W = mollify::StaticKernel<K, Pr>;
    constexpr int D = W::dimension;
    const std::string who = std::string(K.spec) + " D" + std::to_string(D) + (Pr == Precision::fast ? " fast" : " accurate");
    expect_flagged<D>(who + " StaticKernel", [](std::array<std::vector<double>, D>& x, std::size_t n) {
        std::vector<double> w(n);
        std::array<std::vector<double>, D> g;
        mollify::Points<D> in;
        mollify::PointsOut<D> out;
        for (std::size_t c = 0; c < D; ++c) {
            g[c].resize(n);
            in[c] = x[c];
            out[c] = g[c];
        }
        W::pairs(in, W::smoothing(0.5), w, out);
    }, missed);
    const mollify::Kernel k = mollify::kernel(K, Pr);
    expect_flagged<D>(who + " run-time form", [&k](std::array<std::vector<double>, D>& x, std::size_t n) {
        std::vector<double> w(n);
        std::array<std::vector<double>, D> g;
        std::vector<std::span<const double>> in;
        std::vector<std::span<double>> out;
        for (std::size_t c = 0; c < D; ++c) {
            g[c].resize(n);
            in.emplace_back(x[c]);
            out.emplace_back(g[c]);
        }
        k.pairs(in, k.smoothing(0.5), w, out);
    }, missed);
}

// W and W'/r of table K (precision accurate: by levels where K is a
// combination) in batches of 4500 and 7 radii in [0, 0.5), with a bad radius
// at places of the first, second, a middle and the last register, and -0
// (a radius) everywhere else once: StaticKernel's and the run-time form's.
template <const table::Kernel& K>
void expect_radii_flagged(std::vector<std::string>& missed) {
    using W = mollify::StaticKernel<K>;
    const mollify::Kernel k = mollify::kernel(K);
    const std::string who = std::string(K.spec) + " D" + std::to_string(W::dimension);
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> u(0.0, 0.5);
    for (const std::size_t n : {std::size_t{4500}, std::size_t{7}}) {
        std::vector<double> r(n), out(n);
        for (double& v : r) v = u(rng);
        for (const bool static_form : {true, false})
            for (const QuantityId q : {QuantityId::value, QuantityId::grad_over_r}) {
                auto run = [&] {
                    if (static_form) W::evaluate(q, r, W::smoothing(0.5), out);
                    else k.evaluate(q, r, k.smoothing(0.5), out);
                };
                const std::string form = who + (static_form ? " StaticKernel " : " run-time form ") +
                                         mollify::quantity_names[static_cast<int>(q)];
                const std::vector<std::size_t> places =
                    n > 16 ? std::vector<std::size_t>{0, 9, 2000, n - 1} : std::vector<std::size_t>{3};
                for (const std::size_t i : places)
                    for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                                             -std::numeric_limits<double>::infinity(), -0.25, -0x1p-1074}) {
                        const double kept = r[i];
                        r[i] = bad;
                        if (!error_names(run, "radius r = "))
                            missed.push_back(form + ": radius " + std::to_string(bad) + " at " + std::to_string(i) + " of " +
                                             std::to_string(n) + " not named");
                        r[i] = kept;
                    }
                const double kept = r[n / 2];
                r[n / 2] = -0.0;
                try {
                    run();
                } catch (const mollify::Error& e) {
                    missed.push_back(form + ": -0 refused: " + e.what());
                }
                r[n / 2] = kept;
            }
    }
}

}  // namespace

std::vector<std::string> unflagged_bad_radii() {
    std::vector<std::string> missed;
    expect_radii_flagged<mollify::tables::combo_m_3_base_wendland_k_2_D3>(missed);
    expect_radii_flagged<mollify::tables::wendland_k_2_D3>(missed);
    return missed;
}

std::vector<std::string> unflagged_bad_inputs() {
    namespace tables = mollify::tables;
    std::vector<std::string> missed;
    expect_pairs_flagged<tables::wendland_k_2_D3, Precision::accurate>(missed);
    expect_pairs_flagged<tables::wendland_k_2_D3, Precision::fast>(missed);
    expect_pairs_flagged<tables::combo_m_3_base_wendland_k_2_D3, Precision::accurate>(missed);
    expect_pairs_flagged<tables::combo_m_2_base_wendland_k_1_D2, Precision::accurate>(missed);
    return missed;
}

// The vectorised paths of the batch loops: one whole term (Wendland C4,
// pairs_3d), pieces of several terms (the combinations, in 3D and in 2D:
// pairs_2d), and the 1D loop of pairs_unchecked itself. (Pieces chosen by
// branches, sqrt/log ones, do not vectorise: no vector width to test; a
// missing Wendland function here would triple this unit's 15 s compile.)
Comparison batches_against_points() {
    namespace tables = mollify::tables;
    Comparison out;
    both<tables::wendland_k_2_D3>(out);
    // The units fuse multiply-add: the combinations' pair loops take their
    // levels (else levels_against_radial would test nothing).
    static_assert(mollify::detail::levels<tables::combo_m_3_base_wendland_k_2_D3> == 3);
    static_assert(mollify::detail::levels<tables::combo_m_2_base_wendland_k_1_D2> == 2);
    static_assert(mollify::detail::quantity_levels<tables::combo_m_3_base_wendland_k_2_D3, 0> == 3);
    both<tables::combo_m_3_base_wendland_k_2_D3>(out);
    both<tables::combo_m_2_base_wendland_k_1_D2>(out);
    both<tables::wendland_k_1_D1>(out);
    return out;
}

}  // namespace batch_loops
