// Seeded particle positions for the SPH tests (sph_test, sph_cells_test).
#pragma once

#include <mollify/sph/euler.hpp>

#include <cstddef>
#include <random>

namespace mollify::testing {

// n points uniform in [lo, hi)^D from a seeded generator: the tests compare
// two searches or sweeps on the same points.
template <int D>
sph::Field<D> random_points(std::size_t n, double lo, double hi, unsigned seed) {
    std::mt19937_64 g(seed);
    std::uniform_real_distribution<double> u(lo, hi);
    sph::Field<D> x;
    for (int c = 0; c < D; ++c)
        for (std::size_t i = 0; i < n; ++i) x[c].push_back(u(g));
    return x;
}

}  // namespace mollify::testing
