// kernel_bench: evaluations per second of W and of W + grad W (the pair API,
// 3D) for one representative kernel per family, mollify's compile-time
// (StaticKernel) and run-time (Kernel) batches against the naive forms
// (expanded monomials, textbook pow), each next to the error it achieves,
// measured in the same run and the same build (same flags, FMA or not)
// against the exact values: speed against error. For two kernels also the
// potential phi and phi'/r (the Poisson and vortex solvers' pairs within a
// support), both precisions and forms.
//
// Counters: tsc_cyc = time stamp counter ticks per evaluation (constant rate,
// the nominal clock; a core boosting above it does more work per tick),
// bound = the FMA-pipe lower bound of mollify's factored form (multiplies and
// FMAs / (vector lanes x 2 FMA pipes); the lanes are the build's: 8 doubles
// with AVX-512, 4 with AVX, 2 otherwise), ulp_W and ulp_G = max ulp
// error of W and W'/r over the sample (hard points + uniform).
//
//   kernel_bench [benchmark flags] [--md=FILE]   (cmake --build build --target bench-kernels)
#include "accuracy/measure.hpp"

#include <mollify/kernel.hpp>
#include <mollify/tables/classic/cubic_spline_D3.hpp>
#include <mollify/tables/classic/poly6_D3.hpp>
#include <mollify/tables/classic/quintic_spline_D3.hpp>
#include <mollify/tables/combo/m_3_base_wendland_k_2_D3.hpp>
#include <mollify/tables/mollifier/M_4_D3.hpp>
#include <mollify/tables/mollifier/M_9_order_6_D3.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>
#include <mollify/tables/wendland/k_4_l_4_D3.hpp>
#include <mollify/tables/wendland_missing/k_1_D3.hpp>

#include "report.hpp"

#include <benchmark/benchmark.h>
#include <x86intrin.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace acc = mollify::accuracy;
namespace tables = mollify::tables;
using mollify::QuantityId;
using mollify::Smoothing;
using mollify::table::Kernel;

namespace {

constexpr double h = 1.3;  // not 1, so the scaling by h is real work
constexpr std::size_t sizes[] = {1'000'000, 4096};  // DRAM-bound batch, cache-resident batch
constexpr int error_uniform = 20'000;                // uniform points of the error sample (plus the hard ones)

// ---- capacities of the naive forms, from the emitted table at compile time ----

constexpr int inner_pieces(const Kernel& k, QuantityId q) { return k.quantities[static_cast<int>(q)].npieces - 1; }

// Coefficients of the expanded Horner form (n + edge_power, plus zero low
// coefficients) and of the pow form's cofactor (n, factored pieces only),
// max over the pieces.
constexpr int naive_size(const Kernel& k, QuantityId q, bool expanded) {
    int most = 1;
    const auto& quantity = k.quantities[static_cast<int>(q)];
    for (int p = 0; p < inner_pieces(k, q); ++p)
        for (int t = 0; t < quantity.pieces[p].nterms; ++t) {
            const auto& term = quantity.pieces[p].terms[t];
            const int low_v = term.var == mollify::table::Var::r ? term.low : term.low / 2;  // odd pieces: q v^k
            if (!expanded && term.edge_power == 0) continue;  // no factorisation: the pow form uses the monomials
            most = std::max(most, std::max(low_v, 0) + term.n + (expanded ? term.edge_power : 0));
        }
    return most;
}

template <const Kernel& K, QuantityId Q>
using NaiveOf = acc::Naive<naive_size(K, Q, true), naive_size(K, Q, false), inner_pieces(K, Q)>;

// ---- the FMA-pipe bound of mollify's factored form ----

constexpr int ipow_products(int n) { return n <= 1 ? 0 : ipow_products(n / 2) + 1 + n % 2; }

// Multiplies and FMAs of one quantity inside the support (every polynomial
// piece is evaluated, then one is selected), without the shared q, 1 - q, q^2.
constexpr int quantity_products(const Kernel& k, QuantityId q) {
    int ops = 1;  // the scale h^p
    const auto& quantity = k.quantities[static_cast<int>(q)];
    for (int p = 0; p < inner_pieces(k, q); ++p)
        for (int t = 0; t < quantity.pieces[p].nterms; ++t) {
            const auto& term = quantity.pieces[p].terms[t];
            ops += term.n - 1;                                                          // Horner FMAs
            if (term.low != 0) ops += ipow_products(std::abs(term.low)) + 1;           // q^low and the product
            if (term.edge_power != 0) ops += ipow_products(term.edge_power) + 1;       // (1 - v)^n and the product
            if (term.edge_power != 0 && term.var == mollify::table::Var::r2) ops += 1;  // (1 - q)(1 + q)
        }
    return ops;
}

constexpr bool uses_square(const Kernel& k, QuantityId q) {
    const auto& quantity = k.quantities[static_cast<int>(q)];
    for (int p = 0; p < inner_pieces(k, q); ++p)
        for (int t = 0; t < quantity.pieces[p].nterms; ++t)
            if (quantity.pieces[p].terms[t].var == mollify::table::Var::r2) return true;
    return false;
}

// W + grad W at one displacement: |x|^2 (1 mul + 2 FMA), q = r/h (1),
// 1 - q from h - r (1 mul + 2 FMA), v = q^2 if used (1), W, W'/r, grad = (W'/r) x (3).
constexpr int pair_products(const Kernel& k) {
    const bool square = uses_square(k, QuantityId::value) || uses_square(k, QuantityId::grad_over_r);
    return 3 + 1 + 3 + (square ? 1 : 0) + quantity_products(k, QuantityId::value) +
           quantity_products(k, QuantityId::grad_over_r) + 3;
}
constexpr int value_products(const Kernel& k) {
    return 1 + 3 + (uses_square(k, QuantityId::value) ? 1 : 0) + quantity_products(k, QuantityId::value);
}
// The build's doubles per vector (detail::register_doubles: MOLLIFY_BATCH_LOOP
// asks for 512-bit vectors where AVX-512 is enabled), two FMA pipes of that
// width: the Intel server cores and Zen 5; Zen 4 splits a 512-bit FMA into
// two 256-bit halves, so its bound is twice the printed one.
constexpr int vector_lanes = mollify::detail::register_doubles;
constexpr double lanes_per_cycle = 2.0 * vector_lanes;

// ---- data ----

// Where the displacements lie: uniform in [-h, h]^3 (about half inside the
// support, as in a neighbour loop with a cell list); `ball`, uniform in the
// support's ball (a neighbour list already filtered to r < h, as the SPH
// sweeps' pair loops get it: a combination's inner terms then reach more
// registers of points, goal 3's harder case); or a shell lo <= r/h < hi,
// uniform in its volume (a combination's band between two of its radii:
// every register of points at one level).
struct Region {
    double lo = 0, hi = 0;  // a shell where hi > 0
    bool ball = false;
    auto operator<=>(const Region&) const = default;
};
constexpr Region cube{}, ball{0, 0, true};

struct Data {
    std::vector<double> x[3], r, w, g[3];
    Data(std::size_t n, Region where) {
        std::mt19937_64 rng(42);
        std::uniform_real_distribution<double> u(-h, h);
        for (auto& c : x) c.resize(n);
        if (where.hi > 0) {
            // a direction uniform on the sphere, r^3 uniform in [lo^3, hi^3)
            std::normal_distribution<double> normal;
            std::uniform_real_distribution<double> cube_of_r(std::pow(where.lo, 3), std::pow(where.hi, 3));
            for (std::size_t i = 0; i < n; ++i) {
                double v[3], norm = 0;
                for (double& c : v) {
                    c = normal(rng);
                    norm += c * c;
                }
                const double radius = h * std::cbrt(cube_of_r(rng)) / std::sqrt(norm);
                for (int c = 0; c < 3; ++c) x[c][i] = v[c] * radius;
            }
        } else {
            for (std::size_t i = 0; i < n;) {
                for (auto& c : x) c[i] = u(rng);
                if (!where.ball || x[0][i] * x[0][i] + x[1][i] * x[1][i] + x[2][i] * x[2][i] < h * h) ++i;
            }
        }
        r.resize(n);
        for (std::size_t i = 0; i < n; ++i) r[i] = std::sqrt(x[0][i] * x[0][i] + x[1][i] * x[1][i] + x[2][i] * x[2][i]);
        w.resize(n);
        for (auto& c : g) c.resize(n);
    }
    mollify::Points<3> points() const { return {x[0], x[1], x[2]}; }
    mollify::PointsOut<3> grad() { return {g[0], g[1], g[2]}; }
};

Data& data(std::size_t n, Region where = cube) {
    static std::map<std::pair<std::size_t, Region>, Data> cache;
    return cache.try_emplace({n, where}, n, where).first->second;
}

// ---- errors, measured once per (kernel, form) ----

struct Errors {
    double value = 0, grad = 0;
};

struct Sample {
    std::vector<acc::Point> points = acc::hard_points(error_uniform, 7);
};
const Sample& sample() {
    static const Sample s;
    return s;
}

Errors errors_of(const acc::ExactValues& w, const acc::ExactValues& g, const acc::Evaluation& value,
                 const acc::Evaluation& grad) {
    return {acc::measure(w, value, sample().points).max_ulp, acc::measure(g, grad, sample().points).max_ulp};
}

// ---- timing ----

// Runs `batch` in the benchmark loop, TSC ticks around it, and the counters.
template <class Batch>
void timed(benchmark::State& state, std::size_t n, double bound, const Errors& e, Batch&& batch) {
    const unsigned long long start = __rdtsc();
    for (auto _ : state) {
        batch();
        benchmark::ClobberMemory();
    }
    const unsigned long long ticks = __rdtsc() - start;
    const double evals = static_cast<double>(state.iterations()) * static_cast<double>(n);
    state.SetItemsProcessed(static_cast<std::int64_t>(evals));
    state.counters["tsc_cyc"] = static_cast<double>(ticks) / evals;
    state.counters["bound"] = bound;
    state.counters["ulp_W"] = e.value;
    if (e.grad >= 0) state.counters["ulp_G"] = e.grad;
}

// Naive W + grad W: r = |x|, both polynomials in the same q.
template <acc::Form F, class NW, class NG>
void naive_pairs(const NW& fw, const NG& fg, const double* x0, const double* x1, const double* x2, double* w,
                 double* g0, double* g1, double* g2, std::size_t n) {
    const acc::NaiveScale sw(h, fw.scale_power), sg(h, fg.scale_power);
    for (std::size_t i = 0; i < n; ++i) {
        const double r = std::sqrt(x0[i] * x0[i] + x1[i] * x1[i] + x2[i] * x2[i]);
        w[i] = acc::naive_at<F>(fw, r, sw);
        const double over_r = acc::naive_at<F>(fg, r, sg);
        g0[i] = over_r * x0[i];
        g1[i] = over_r * x1[i];
        g2[i] = over_r * x2[i];
    }
}

template <acc::Form F, class NW>
void naive_values(const NW& fw, const double* r, double* w, std::size_t n) {
    const acc::NaiveScale sw(h, fw.scale_power);
    for (std::size_t i = 0; i < n; ++i) w[i] = acc::naive_at<F>(fw, r[i], sw);
}

// ---- one family ----

// A naive form whose arrays are exactly as long as the generator's
// polynomials: no padding Horner steps, so the naive loops are not slowed.
template <class Naive>
Naive tight(const std::string& spec, QuantityId q) {
    const acc::NaivePolynomial p = acc::naive_polynomial(spec, 3, q);
    if (p.max_expanded() != Naive::capacity || p.max_cofactor() != Naive::cofactor_capacity ||
        static_cast<int>(p.pieces.size()) != Naive::piece_capacity)
        mollify::fail("kernel_bench: naive capacities of " + spec + " (" + mollify::quantity_names[static_cast<int>(q)] +
                      ") are " + std::to_string(Naive::capacity) + "/" + std::to_string(Naive::cofactor_capacity) + "/" +
                      std::to_string(Naive::piece_capacity) + ", the generator needs " + std::to_string(p.max_expanded()) +
                      "/" + std::to_string(p.max_cofactor()) + "/" + std::to_string(p.pieces.size()));
    return Naive(p);
}

// "/n", a benchmark name's batch size (appended: `"/" + std::to_string(n)`
// trips GCC 12's -Wrestrict).
std::string batch_suffix(std::size_t n) { return std::string("/").append(std::to_string(n)); }

// inside: also W + grad W at points inside the support only
// (W+gradW-inside/...: both precisions, both forms; goal 3's kernels).
template <const Kernel& K>
void register_kernel(const char* label, bool inside = false) {
    using W = mollify::StaticKernel<K>;  // Precision::accurate, the default
    using F = mollify::StaticKernel<K, mollify::Precision::fast>;
    static_assert(W::dimension == 3);
    const mollify::Kernel runtime(K);  // what mollify::kernel(K.spec, 3) returns: the data-driven form
    const std::string spec = K.spec;
    const NaiveOf<K, QuantityId::value> nw = tight<NaiveOf<K, QuantityId::value>>(spec, QuantityId::value);
    const NaiveOf<K, QuantityId::grad_over_r> ng = tight<NaiveOf<K, QuantityId::grad_over_r>>(spec, QuantityId::grad_over_r);

    const acc::Reference ref(spec, 3);
    const auto& pts = sample().points;
    const acc::ExactValues ew = acc::exact_values(ref, QuantityId::value, pts);
    const acc::ExactValues eg = acc::exact_values(ref, QuantityId::grad_over_r, pts);
    const Errors e_static = errors_of(
        ew, eg, [](double r, double hh) { return W::template radial<QuantityId::value>(r, hh); },
        [](double r, double hh) { return W::template radial<QuantityId::grad_over_r>(r, hh); });
    const Errors e_fast = errors_of(
        ew, eg, [](double r, double hh) { return F::template radial<QuantityId::value>(r, hh); },
        [](double r, double hh) { return F::template radial<QuantityId::grad_over_r>(r, hh); });
    const Errors e_runtime = errors_of(
        ew, eg, [runtime](double r, double hh) { return runtime(QuantityId::value, r, hh); },
        [runtime](double r, double hh) { return runtime(QuantityId::grad_over_r, r, hh); });
    const Errors e_expanded = errors_of(
        ew, eg, [nw](double r, double hh) { return acc::naive_at<acc::Form::expanded>(nw, r, acc::NaiveScale(hh, nw.scale_power)); },
        [ng](double r, double hh) { return acc::naive_at<acc::Form::expanded>(ng, r, acc::NaiveScale(hh, ng.scale_power)); });
    const Errors e_pow = errors_of(
        ew, eg, [nw](double r, double hh) { return acc::naive_at<acc::Form::pow>(nw, r, acc::NaiveScale(hh, nw.scale_power)); },
        [ng](double r, double hh) { return acc::naive_at<acc::Form::pow>(ng, r, acc::NaiveScale(hh, ng.scale_power)); });
    const Errors value_only[] = {{e_static.value, -1}, {e_runtime.value, -1}, {e_expanded.value, -1}, {e_pow.value, -1},
                                 {e_fast.value, -1}};

    const double vb = value_products(K) / lanes_per_cycle, pb = pair_products(K) / lanes_per_cycle;
    const std::string base = std::string(label) + "/";
    for (const std::size_t n : sizes) {
        const std::string suffix = batch_suffix(n);
        auto reg = [&](const std::string& name, auto fn) { benchmark::RegisterBenchmark(name.c_str(), fn)->Unit(benchmark::kMicrosecond); };
        reg("W/" + base + "static" + suffix, [n, vb, e = value_only[0]](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = W::smoothing(h);
            timed(st, n, vb, e, [&] { W::template evaluate<QuantityId::value>(d.r, s, d.w); });
        });
        reg("W/" + base + "static-fast" + suffix, [n, vb, e = value_only[4]](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = F::smoothing(h);
            timed(st, n, vb, e, [&] { F::template evaluate<QuantityId::value>(d.r, s, d.w); });
        });
        reg("W/" + base + "runtime" + suffix, [n, vb, runtime, e = value_only[1]](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = runtime.smoothing(h);
            timed(st, n, vb, e, [&] { runtime.evaluate(QuantityId::value, d.r, s, d.w); });
        });
        reg("W/" + base + "runtime-fast" + suffix, [n, vb, fast = runtime.with(mollify::Precision::fast),
                                                 e = value_only[4]](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = fast.smoothing(h);
            timed(st, n, vb, e, [&] { fast.evaluate(QuantityId::value, d.r, s, d.w); });
        });
        reg("W/" + base + "expanded" + suffix, [n, vb, nw, e = value_only[2]](benchmark::State& st) {
            Data& d = data(n);
            timed(st, n, vb, e, [&] { naive_values<acc::Form::expanded>(nw, d.r.data(), d.w.data(), n); });
        });
        reg("W/" + base + "pow" + suffix, [n, vb, nw, e = value_only[3]](benchmark::State& st) {
            Data& d = data(n);
            timed(st, n, vb, e, [&] { naive_values<acc::Form::pow>(nw, d.r.data(), d.w.data(), n); });
        });
        // W + grad W through the checked API, both forms and precisions, at
        // the displacements of data(n, where)
        auto checked_pairs = [&](const std::string& quantity, Region where) {
            reg(quantity + base + "static" + suffix, [n, pb, e_static, where](benchmark::State& st) {
                Data& d = data(n, where);
                const Smoothing s = W::smoothing(h);
                timed(st, n, pb, e_static, [&] { W::pairs(d.points(), s, d.w, d.grad()); });
            });
            reg(quantity + base + "static-fast" + suffix, [n, pb, e_fast, where](benchmark::State& st) {
                Data& d = data(n, where);
                const Smoothing s = F::smoothing(h);
                timed(st, n, pb, e_fast, [&] { F::pairs(d.points(), s, d.w, d.grad()); });
            });
            for (const mollify::Precision pr : {mollify::Precision::accurate, mollify::Precision::fast}) {
                const bool is_fast = pr == mollify::Precision::fast;
                reg(quantity + base + (is_fast ? "runtime-fast" : "runtime") + suffix,
                    [n, pb, where, k = runtime.with(pr), e = is_fast ? e_fast : e_runtime](benchmark::State& st) {
                        Data& d = data(n, where);
                        const Smoothing s = k.smoothing(h);
                        const std::span<const double> x[3] = {d.x[0], d.x[1], d.x[2]};
                        const std::span<double> g[3] = {d.g[0], d.g[1], d.g[2]};
                        timed(st, n, pb, e, [&] { k.pairs(x, s, d.w, g); });
                    });
            }
        };
        checked_pairs("W+gradW/", cube);
        reg("W+gradW/" + base + "static-unchecked" + suffix, [n, pb, e_static](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = W::smoothing(h);
            timed(st, n, pb, e_static, [&] { W::pairs_unchecked(d.points(), s, d.w.data(), d.grad(), n); });
        });
        reg("W+gradW/" + base + "static-fast-unchecked" + suffix, [n, pb, e_fast](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = F::smoothing(h);
            timed(st, n, pb, e_fast, [&] { F::pairs_unchecked(d.points(), s, d.w.data(), d.grad(), n); });
        });
        if (inside) checked_pairs("W+gradW-inside/", ball);
        // A combination's levels one at a time, in cache: every point's r/h
        // in [a_L, a_L+1) (its radii, a_0 = 0, the last 1), so that every
        // register of points sums the terms of the radii from a_L on
        // (StaticKernel's pair_levels): what each level costs, the outermost
        // (its term alone) the least.
        constexpr int levels = mollify::detail::levels<K>;
        if (levels > 1 && n <= 4096)
            for (int l = 0; l < levels; ++l) {
                // (1 + 2^-40: clear of the 2^-48 a level leaves for the rounding of q)
                const double lo = l == 0 ? 0 : mollify::detail::level_bound<K>(l - 1) * (1 + 0x1p-40);
                const double hi = l + 1 == levels ? 1 : mollify::detail::level_bound<K>(l);
                checked_pairs("W+gradW-level" + std::to_string(l) + "/", Region{lo, hi});
            }
        reg("W+gradW/" + base + "expanded" + suffix, [n, pb, nw, ng, e_expanded](benchmark::State& st) {
            Data& d = data(n);
            timed(st, n, pb, e_expanded, [&] {
                naive_pairs<acc::Form::expanded>(nw, ng, d.x[0].data(), d.x[1].data(), d.x[2].data(), d.w.data(),
                                                 d.g[0].data(), d.g[1].data(), d.g[2].data(), n);
            });
        });
        reg("W+gradW/" + base + "pow" + suffix, [n, pb, nw, ng, e_pow](benchmark::State& st) {
            Data& d = data(n);
            timed(st, n, pb, e_pow, [&] {
                naive_pairs<acc::Form::pow>(nw, ng, d.x[0].data(), d.x[1].data(), d.x[2].data(), d.w.data(),
                                            d.g[0].data(), d.g[1].data(), d.g[2].data(), n);
            });
        });
    }
    std::cerr << label << ": mollify's factored form, W + grad W in 3D: " << pair_products(K)
              << " multiplies/FMAs per evaluation (bound " << pb << " cycles), W alone " << value_products(K) << "\n";
}

// The compile-time and run-time forms only, both precisions (kernels with
// no naive polynomial form: the missing Wendland functions' sqrt pieces).
template <const Kernel& K>
void register_forms(const char* label) {
    using W = mollify::StaticKernel<K>;
    using F = mollify::StaticKernel<K, mollify::Precision::fast>;
    const mollify::Kernel runtime(K);
    const std::string base = std::string(label) + "/";
    const Errors none{-1, -1};
    for (const std::size_t n : sizes) {
        const std::string suffix = batch_suffix(n);
        auto reg = [&](const std::string& name, auto fn) { benchmark::RegisterBenchmark(name.c_str(), fn)->Unit(benchmark::kMicrosecond); };
        reg("W/" + base + "static" + suffix, [n, none](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = W::smoothing(h);
            timed(st, n, 0, none, [&] { W::template evaluate<QuantityId::value>(d.r, s, d.w); });
        });
        reg("W/" + base + "static-fast" + suffix, [n, none](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = F::smoothing(h);
            timed(st, n, 0, none, [&] { F::template evaluate<QuantityId::value>(d.r, s, d.w); });
        });
        for (const mollify::Precision pr : {mollify::Precision::accurate, mollify::Precision::fast}) {
            const std::string form = pr == mollify::Precision::fast ? "runtime-fast" : "runtime";
            reg("W/" + base + form + suffix, [n, none, k = runtime.with(pr)](benchmark::State& st) {
                Data& d = data(n);
                const Smoothing s = k.smoothing(h);
                timed(st, n, 0, none, [&] { k.evaluate(QuantityId::value, d.r, s, d.w); });
            });
            reg("W+gradW/" + base + form + suffix, [n, none, k = runtime.with(pr)](benchmark::State& st) {
                Data& d = data(n);
                const std::span<const double> x[3] = {d.x[0], d.x[1], d.x[2]};
                const std::span<double> g[3] = {d.g[0], d.g[1], d.g[2]};
                const Smoothing s = k.smoothing(h);
                timed(st, n, 0, none, [&] { k.pairs(x, s, d.w, g); });
            });
        }
        // Checked, as the run-time form's pairs are.
        reg("W+gradW/" + base + "static" + suffix, [n, none](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = W::smoothing(h);
            timed(st, n, 0, none, [&] { W::pairs(d.points(), s, d.w, d.grad()); });
        });
        reg("W+gradW/" + base + "static-fast" + suffix, [n, none](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = F::smoothing(h);
            timed(st, n, 0, none, [&] { F::pairs(d.points(), s, d.w, d.grad()); });
        });
        reg("W+gradW/" + base + "static-unchecked" + suffix, [n, none](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = W::smoothing(h);
            timed(st, n, 0, none, [&] { W::pairs_unchecked(d.points(), s, d.w.data(), d.grad(), n); });
        });
        reg("W+gradW/" + base + "static-fast-unchecked" + suffix, [n, none](benchmark::State& st) {
            Data& d = data(n);
            const Smoothing s = F::smoothing(h);
            timed(st, n, 0, none, [&] { F::pairs_unchecked(d.points(), s, d.w.data(), d.grad(), n); });
        });
    }
}

// The potential phi and phi'/r (the Poisson and vortex solvers' pairs within
// a support), both precisions, both forms; ulp_W and ulp_G are then the
// errors of phi and phi'/r. Until stop 37 no row measured them, and a branch
// between the support and the Green's function kept every such batch from
// vectorising (mollifier:M=4: 8.4 against 1.6 ns per value, fast).
template <const Kernel& K>
void register_potentials(const char* label) {
    using W = mollify::StaticKernel<K>;
    using F = mollify::StaticKernel<K, mollify::Precision::fast>;
    const mollify::Kernel runtime(K);
    const acc::Reference ref(K.spec, 3);
    const auto& pts = sample().points;
    const acc::ExactValues ep = acc::exact_values(ref, QuantityId::potential, pts);
    const acc::ExactValues eg = acc::exact_values(ref, QuantityId::dpotential_over_r, pts);
    // Measured on the run-time form: StaticKernel's values are the same bit
    // for bit (runtime_forms_test), so its rows carry these errors too.
    const auto errors_in = [&](mollify::Precision pr) {
        const mollify::Kernel k = runtime.with(pr);
        return errors_of(ep, eg, [k](double r, double hh) { return k(QuantityId::potential, r, hh); },
                         [k](double r, double hh) { return k(QuantityId::dpotential_over_r, r, hh); });
    };
    const Errors accurate = errors_in(mollify::Precision::accurate), fast = errors_in(mollify::Precision::fast);
    for (const std::size_t n : sizes) {
        const std::string suffix = batch_suffix(n);
        auto reg = [&](const std::string& name, auto fn) { benchmark::RegisterBenchmark(name.c_str(), fn)->Unit(benchmark::kMicrosecond); };
        const auto both = [&]<QuantityId Q>(const std::string& quantity) {
            const std::string base = quantity + "/" + label + "/";
            reg(base + "static" + suffix, [n, accurate](benchmark::State& st) {
                Data& d = data(n);
                const Smoothing s = W::smoothing(h);
                timed(st, n, 0, accurate, [&] { W::template evaluate<Q>(d.r, s, d.w); });
            });
            reg(base + "static-fast" + suffix, [n, fast](benchmark::State& st) {
                Data& d = data(n);
                const Smoothing s = F::smoothing(h);
                timed(st, n, 0, fast, [&] { F::template evaluate<Q>(d.r, s, d.w); });
            });
            for (const mollify::Precision pr : {mollify::Precision::accurate, mollify::Precision::fast}) {
                const bool is_fast = pr == mollify::Precision::fast;
                reg(base + (is_fast ? "runtime-fast" : "runtime") + suffix,
                    [n, e = is_fast ? fast : accurate, k = runtime.with(pr)](benchmark::State& st) {
                        Data& d = data(n);
                        const Smoothing s = k.smoothing(h);
                        timed(st, n, 0, e, [&] { k.evaluate(Q, d.r, s, d.w); });
                    });
            }
        };
        both.template operator()<QuantityId::potential>("phi");
        both.template operator()<QuantityId::dpotential_over_r>("phi'/r");
    }
}

// The checked scalar forms, one call per radius, as code that has no batch
// at hand calls them, both precisions: W::value(r, h) and the run-time
// form's k.value(r, h) (one radius into the evaluator: Evaluator::at_radius)
// take h per call (Smoothing::reused keeps this thread's last Smoothing per
// D), against radial(r, s) with the caller's own Smoothing, and with h
// alternating between two lengths (each call then makes its Smoothing: since
// stop 59 with the one quantity's scale, Smoothing::reused(h, D, q); a whole
// Smoothing made by the caller per call beside it).
template <const Kernel& K>
void register_scalar(const char* label) {
    using W = mollify::StaticKernel<K>;
    using F = mollify::StaticKernel<K, mollify::Precision::fast>;
    const mollify::Kernel runtime(K);
    const acc::Reference ref(K.spec, 3);
    const acc::ExactValues ew = acc::exact_values(ref, QuantityId::value, sample().points);
    const double e = acc::measure(ew, [](double r, double hh) { return W::value(r, hh); }, sample().points).max_ulp;
    const double e_fast = acc::measure(ew, [](double r, double hh) { return F::value(r, hh); }, sample().points).max_ulp;
    const Errors value_only{e, -1}, fast_value_only{e_fast, -1};
    constexpr std::size_t n = 4096;
    const std::string base = std::string("W-scalar/") + label + "/";
    auto reg = [&](const std::string& name, auto fn) {
        benchmark::RegisterBenchmark((base + name + batch_suffix(n)).c_str(), fn)->Unit(benchmark::kMicrosecond);
    };
    reg("static-checked", [value_only](benchmark::State& st) {
        Data& d = data(n);
        timed(st, n, 0, value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) d.w[i] = W::value(d.r[i], h);
        });
    });
    reg("static-smoothing", [value_only](benchmark::State& st) {
        Data& d = data(n);
        const Smoothing s = W::smoothing(h);
        timed(st, n, 0, value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) d.w[i] = W::template radial<QuantityId::value>(d.r[i], s);
        });
    });
    reg("static-checked-two-h", [value_only](benchmark::State& st) {
        Data& d = data(n);
        const double lengths[2] = {h, std::nextafter(h, 2 * h)};
        timed(st, n, 0, value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) d.w[i] = W::value(d.r[i], lengths[i & 1]);
        });
    });
    reg("static-smoothing-per-h", [value_only](benchmark::State& st) {  // the caller's own Smoothing for each h
        Data& d = data(n);
        const double lengths[2] = {h, std::nextafter(h, 2 * h)};
        timed(st, n, 0, value_only, [&] {
            for (std::size_t i = 0; i < n; ++i)
                d.w[i] = W::template radial<QuantityId::value>(d.r[i], W::smoothing(lengths[i & 1]));
        });
    });
    // W_h and grad W_h by W::pair(x, h), the same h and h alternating (an
    // SPH code with a smoothing length per particle); errors of W only.
    reg("static-pair-checked", [value_only](benchmark::State& st) {
        Data& d = data(n);
        timed(st, n, 0, value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) {
                const auto p = W::pair({d.x[0][i], d.x[1][i], d.x[2][i]}, h);
                d.w[i] = p.value, d.g[0][i] = p.gradient[0], d.g[1][i] = p.gradient[1], d.g[2][i] = p.gradient[2];
            }
        });
    });
    reg("static-pair-checked-two-h", [value_only](benchmark::State& st) {
        Data& d = data(n);
        const double lengths[2] = {h, std::nextafter(h, 2 * h)};
        timed(st, n, 0, value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) {
                const auto p = W::pair({d.x[0][i], d.x[1][i], d.x[2][i]}, lengths[i & 1]);
                d.w[i] = p.value, d.g[0][i] = p.gradient[0], d.g[1][i] = p.gradient[1], d.g[2][i] = p.gradient[2];
            }
        });
    });
    reg("runtime-checked", [value_only, runtime](benchmark::State& st) {
        Data& d = data(n);
        timed(st, n, 0, value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) d.w[i] = runtime.value(d.r[i], h);
        });
    });
    reg("runtime-checked-two-h", [value_only, runtime](benchmark::State& st) {
        Data& d = data(n);
        const double lengths[2] = {h, std::nextafter(h, 2 * h)};
        timed(st, n, 0, value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) d.w[i] = runtime.value(d.r[i], lengths[i & 1]);
        });
    });
    reg("static-fast-checked", [fast_value_only](benchmark::State& st) {
        Data& d = data(n);
        timed(st, n, 0, fast_value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) d.w[i] = F::value(d.r[i], h);
        });
    });
    reg("runtime-fast-checked", [fast_value_only, fast = runtime.with(mollify::Precision::fast)](benchmark::State& st) {
        Data& d = data(n);
        timed(st, n, 0, fast_value_only, [&] {
            for (std::size_t i = 0; i < n; ++i) d.w[i] = fast.value(d.r[i], h);
        });
    });
}

// ---- Markdown ----

using mollify::bench::Collector;
using mollify::bench::number;

std::string counter(const benchmark::BenchmarkReporter::Run& r, const char* name, const char* f) {
    const auto it = r.counters.find(name);
    return it == r.counters.end() ? "–" : number(f, it->second.value);
}

// The flags that decide vectorisation (bench/CMakeLists.txt; the mollify
// target adds -fno-math-errno).
const char* build_flags() { return "-O3 -march=native -fno-math-errno"; }
std::string compiler() {
#if defined(__clang__)
    std::string v = "clang " __clang_version__;
#else
    std::string v = "GCC " __VERSION__;
#endif
    while (!v.empty() && v.back() == ' ') v.pop_back();  // clang's ends in a space
    return v;
}

std::string load() {
    double l[3] = {0, 0, 0};
    if (getloadavg(l, 3) != 3) return "unknown";
    return number("%.2f", l[0]) + ", " + number("%.2f", l[1]) + ", " + number("%.2f", l[2]);
}
std::string load_before;

// A repetitions' spread (Google Benchmark's _stddev and _cv rows) is not a
// time to divide.
bool spread(const std::string& name) {
    auto ends = [&](const std::string& tail) {
        return name.size() >= tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
    };
    return ends("_stddev") || ends("_cv");
}

// The runs' CPU times per iteration by name, and the names' quantity/kernel
// keys and batch sizes in run order (name: quantity/kernel/form/batch).
struct Timings {
    std::map<std::string, double> cpu;
    std::vector<std::string> keys, sizes;
    explicit Timings(const std::vector<benchmark::BenchmarkReporter::Run>& runs) {
        for (const auto& r : runs) {
            const std::string name = r.benchmark_name();
            if (spread(name)) continue;
            cpu[name] = r.GetAdjustedCPUTime();
            const auto a = name.find('/'), b = name.find('/', a + 1), c = name.rfind('/');
            const std::string key = name.substr(0, b), size = name.substr(c + 1);
            if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
            if (std::find(sizes.begin(), sizes.end(), size) == sizes.end()) sizes.push_back(size);
        }
    }
    bool has(const std::string& key, const std::string& form, const std::string& size) const {
        return cpu.count(key + "/" + form + "/" + size) != 0;
    }
    // form's time over base's, "–" where either did not run
    std::string ratio(const std::string& key, const std::string& form, const std::string& base, const std::string& size) const {
        const auto x = cpu.find(key + "/" + form + "/" + size), y = cpu.find(key + "/" + base + "/" + size);
        return x == cpu.end() || y == cpu.end() ? std::string("–") : number("%.2f", x->second / y->second);
    }
};

// The run-time form's CPU time over StaticKernel's in this run (issue 18's
// goal: <= 1.25): accurate against the checked static form (both API calls
// check their inputs), fast against static-fast, and for the pairs also
// against the unchecked static pair loop.
void write_form_ratios(std::ofstream& out, const Timings& t) {
    out << "\n## The run-time form against StaticKernel\n\n"
        << "CPU time of `mollify::Kernel` (libmollify's data-driven loops) over `StaticKernel`'s, the same batch, "
           "this run (the goal of issue 18: <= 1.25).\n\n"
        << "| quantity/kernel | batch | accurate | fast | fast, against the unchecked static pair loop |\n"
           "|---|--:|--:|--:|--:|\n";
    for (const std::string& key : t.keys)
        for (const std::string& size : t.sizes) {
            if (!t.has(key, "runtime", size)) continue;
            const bool pairs = key.rfind("W+gradW", 0) == 0;
            out << "| " << key << " | " << size << " | " << t.ratio(key, "runtime", "static", size) << " | "
                << t.ratio(key, "runtime-fast", "static-fast", size) << " | "
                << (pairs ? t.ratio(key, "runtime-fast", "static-fast-unchecked", size) : std::string("–")) << " |\n";
        }
}

// Precision::accurate's CPU time over Precision::fast's in this run, each
// form against itself, the same batch (issue 21's goal 3: <= 1.5 for
// W + grad W of Wendland C4 and combo:m=3,base=wendland:k=2).
void write_precision_ratios(std::ofstream& out, const Timings& t) {
    out << "\n## Precision::accurate against Precision::fast\n\n"
        << "CPU time of the accurate precision (<= 0.51 ulp) over the fast one, the same form and batch, this run "
           "(issue 21's goal 3: <= 1.5 for W+gradW of wendland:k=2 and combo:m=3,base=wendland:k=2; the -inside "
           "rows: every point inside the support; the -levelL rows: every point's r/h between a combination's "
           "L-th radius and the next, so every register sums the terms from the L-th radius on).\n\n"
        << "| quantity/kernel | batch | StaticKernel | run-time form |\n|---|--:|--:|--:|\n";
    for (const std::string& key : t.keys)
        for (const std::string& size : t.sizes)
            if (t.has(key, "static-fast", size))
                out << "| " << key << " | " << size << " | " << t.ratio(key, "static", "static-fast", size) << " | "
                    << t.ratio(key, "runtime", "runtime-fast", size) << " |\n";
}

void write_markdown(const std::string& path, const std::vector<benchmark::BenchmarkReporter::Run>& runs) {
    std::ofstream out(path + ".tmp");
    out << "# kernel_bench results\n\nGenerated by `cmake --build build --target bench-kernels` (bench/kernel_bench.cpp), "
        << "built by " << compiler() << " with " << build_flags() << ".\n"
        << "Name: quantity/kernel/form/batch size. ns/eval from wall time; tsc_cyc = time-stamp-counter ticks per\n"
        << "evaluation; bound = multiplies+FMAs of mollify's factored form / " << lanes_per_cycle << " (" << vector_lanes
        << " doubles a vector x 2 FMA pipes); ulp_W, ulp_G =\n"
        << "max ulp error of W and W'/r (rows phi and phi'/r: of the potential and phi'/r) measured in the same run ("
        << error_uniform << " uniform + hard points). The repetitions' spread: _stddev rows in Meval/s, _cv rows\n"
        << "in percent of the mean rate.\n\n"
        << "| benchmark | ns/eval | Meval/s | tsc_cyc/eval | bound | ulp_W | ulp_G |\n|---|--:|--:|--:|--:|--:|--:|\n";
    for (const auto& r : runs) {
        const double evals = r.counters.count("items_per_second") ? r.counters.at("items_per_second").value : 0;
        const std::string name = r.benchmark_name();
        // (a spread is no rate to invert: a _cv row's rate is already the ratio)
        const std::string ns = spread(name) ? std::string("–") : number("%.3f", 1e9 / evals);
        const std::string rate = name.ends_with("_cv") ? number("%.1f %%", 100 * evals) : number("%.1f", evals / 1e6);
        out << "| " << name << " | " << ns << " | " << rate
            << " | " << counter(r, "tsc_cyc", "%.2f") << " | " << counter(r, "bound", "%.2f") << " | "
            << counter(r, "ulp_W", "%.3g") << " | " << counter(r, "ulp_G", "%.3g") << " |\n";
    }
    const Timings timings(runs);
    write_form_ratios(out, timings);
    write_precision_ratios(out, timings);
    out << "\nLoad average (1, 5, 15 min) before: " << load_before << "; after: " << load() << ".\n";
    out.close();
    std::rename((path + ".tmp").c_str(), path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    const std::string md = mollify::bench::initialize(argc, argv);
    load_before = load();
    register_kernel<tables::wendland_k_2_D3>("wendland:k=2", true);
    register_kernel<tables::wendland_k_4_l_4_D3>("wendland:k=4,l=4");
    register_kernel<tables::mollifier_M_4_D3>("mollifier:M=4");
    register_kernel<tables::mollifier_M_9_order_6_D3>("mollifier:M=9,order=6");
    register_kernel<tables::combo_m_3_base_wendland_k_2_D3>("combo:m=3,base=wendland:k=2", true);
    register_kernel<tables::cubic_spline_D3>("cubic-spline");
    register_kernel<tables::poly6_D3>("poly6");
    register_forms<tables::wendland_missing_k_1_D3>("wendland-missing:k=1");
    register_forms<tables::quintic_spline_D3>("quintic-spline");
    register_potentials<tables::mollifier_M_4_D3>("mollifier:M=4");
    register_potentials<tables::wendland_k_2_D3>("wendland:k=2");
    register_scalar<tables::wendland_k_2_D3>("wendland:k=2");
    Collector collector;
    benchmark::RunSpecifiedBenchmarks(&collector);
    if (!md.empty()) write_markdown(md, collector.runs());
    benchmark::Shutdown();
    return 0;
}
