// The SPH benchmarks' particles: the lattice of spacing 1/side in the
// periodic unit box, each coordinate jittered by +-0.1 of the spacing
// (seeded), so neighbour counts are those of a settled SPH fluid.
#pragma once

#include <mollify/sph/domain.hpp>
#include <mollify/sph/euler.hpp>  // sph::Field

#include <cstddef>
#include <random>

namespace mollify::bench {

inline constexpr double lattice_jitter = 0.1;  // of the spacing, each coordinate

template <int D>
sph::Field<D> lattice(long side) {
    const double dx = 1.0 / static_cast<double>(side);
    const sph::Domain<D> box = sph::Domain<D>::periodic(1.0);
    std::mt19937_64 rng(20240604);
    std::uniform_real_distribution<double> u(-lattice_jitter * dx, lattice_jitter * dx);
    std::size_t n = 1;
    for (int c = 0; c < D; ++c) n *= static_cast<std::size_t>(side);
    sph::Field<D> x;
    for (auto& c : x) c.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t k = i;
        for (int c = 0; c < D; ++c) {
            x[c][i] = box.wrap(static_cast<double>(k % static_cast<std::size_t>(side)) * dx + u(rng));
            k /= static_cast<std::size_t>(side);
        }
    }
    return x;
}

}  // namespace mollify::bench
