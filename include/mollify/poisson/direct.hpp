// Direct summation: phi(x_i) = sum_j q_j phi_delta_j(|x_i - x_j|) over every
// source (notes 001, "direct summation: particle-particle interactions",
// O(N M) operations), with the exact mollified kernel for every pair, so the
// self term (target = source, r = 0) is the kernel's finite value. OpenMP
// over targets; the inner loop is the blocked, vectorised pair sum.
//
//   const auto k = mollify::kernel("mollifier:M=4", 3);
//   auto f = mollify::poisson::direct<3>(k, {{x, y, z}, q, delta}, {{tx, ty, tz}});
//   f.potential[i], f.field[c][i]
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/parallel.hpp>
#include <mollify/poisson/pair_sum.hpp>
#include <mollify/poisson/sources.hpp>

#include <numeric>
#include <vector>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

// phi and E = -grad phi at the targets (any points: sources or others).
template <int D, RadialKernel K>
Field<D> direct(const K& kernel, const Sources<D>& sources, const Points<D>& targets) {
    detail::check_kernel(kernel, D);
    detail::check_sources(sources);
    const std::size_t m = detail::check_targets<D>(targets);
    std::vector<std::size_t> order(sources.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    const detail::SourceArrays<D> s(sources, order);
    Field<D> out(m);
    const auto count = static_cast<long>(m);
    MOLLIFY_PARALLEL_FOR(schedule(dynamic, 16))
    for (long i = 0; i < count; ++i) {
        std::array<double, D> xt, e{};
        for (int c = 0; c < D; ++c) xt[c] = targets[c][static_cast<std::size_t>(i)];
        double phi = 0;
        detail::add_exact<D>(kernel, s, xt, 0, s.size(), phi, e);
        out.potential[static_cast<std::size_t>(i)] = phi;
        for (int c = 0; c < D; ++c) out.field[c][static_cast<std::size_t>(i)] = e[c];
    }
    return out;
}

// Targets = sources (each source feels its own smoothed charge exactly).
template <int D, RadialKernel K>
Field<D> direct(const K& kernel, const Sources<D>& sources) {
    return direct<D>(kernel, sources, sources.x);
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
