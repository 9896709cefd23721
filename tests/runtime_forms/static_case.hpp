// The compile-time form of a table behind two function pointers, so that
// runtime_forms_test compares it with the run-time form; the instantiations
// are spread over four units (cases_*.cpp: 361 s CPU in one unit under
// ASan, the sanitizer build's critical path; in four, both cores share it).
#pragma once

#include <mollify/static_kernel.hpp>

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace mollify::testing {

namespace table = mollify::table;
using mollify::Precision;
using mollify::QuantityId;
using mollify::Smoothing;

using StaticBatch = void (*)(Precision, QuantityId, const double*, double*, std::size_t, const Smoothing&);
using StaticPairs = void (*)(Precision, const std::span<const double>*, const Smoothing&, double*,
                             const std::span<double>*, std::size_t);

struct Case {
    const table::Kernel* table;
    StaticBatch batch;
    StaticPairs pairs;
};

template <const table::Kernel& K, Precision Pr, std::size_t... Q>
void batch_of(QuantityId q, const double* r, double* out, std::size_t n, const Smoothing& s, std::index_sequence<Q...>) {
    auto one = [&]<std::size_t I>(std::integral_constant<std::size_t, I>) {
        if constexpr (K.quantities[I].npieces > 0)
            if (static_cast<std::size_t>(q) == I)
                mollify::StaticKernel<K, Pr>::template evaluate_unchecked<static_cast<QuantityId>(I)>(r, out, n, s);
    };
    (one(std::integral_constant<std::size_t, Q>{}), ...);
}

template <const table::Kernel& K>
void batch(Precision pr, QuantityId q, const double* r, double* out, std::size_t n, const Smoothing& s) {
    constexpr auto all = std::make_index_sequence<table::quantity_count>{};
    if (pr == Precision::accurate) batch_of<K, Precision::accurate>(q, r, out, n, s, all);
    else batch_of<K, Precision::fast>(q, r, out, n, s, all);
}

template <const table::Kernel& K, Precision Pr>
void pairs_of(const std::span<const double>* x, const Smoothing& s, double* w, const std::span<double>* g, std::size_t n) {
    constexpr int D = K.dim;
    mollify::Points<D> in;
    mollify::PointsOut<D> out;
    for (int c = 0; c < D; ++c) {
        in[static_cast<std::size_t>(c)] = x[c];
        out[static_cast<std::size_t>(c)] = g[c];
    }
    mollify::StaticKernel<K, Pr>::pairs_unchecked(in, s, w, out, n);
}

template <const table::Kernel& K>
void pairs(Precision pr, const std::span<const double>* x, const Smoothing& s, double* w, const std::span<double>* g,
           std::size_t n) {
    if (pr == Precision::accurate) pairs_of<K, Precision::accurate>(x, s, w, g, n);
    else pairs_of<K, Precision::fast>(x, s, w, g, n);
}

template <const table::Kernel& K>
Case case_of() {
    return {&K, &batch<K>, &pairs<K>};
}

// The greedy cover printed by the features of every catalogue table, in four parts.
std::vector<Case> cases_1();
std::vector<Case> cases_2();
std::vector<Case> cases_3();
std::vector<Case> cases_4();

}  // namespace mollify::testing
