// One unit of isa_units_test, compiled twice into the same program: for
// generic x86-64 (MOLLIFY_UNIT = generic: generic_code, generic_values) and
// for x86-64-v3 (AVX2, FMA: v3_code, v3_values). The solvers' headers are inline code, and their hot loops
// differ by instruction set (sph/pair_batch.hpp's AVX2 gathers; what the
// compiler vectorises): a linker that kept one copy of each would run the
// AVX2 code from the generic unit too. mollify/detail/isa.hpp's inline
// namespace keeps the copies apart.
#include "unit.hpp"

#include "../sanitized.hpp"

#include <mollify/kernel.hpp>
#include <mollify/poisson.hpp>
#include <mollify/sph.hpp>
#include <mollify/vortex.hpp>

#include <cmath>
#include <cstdint>

#define MOLLIFY_UNIT_STRING(x) #x
#define MOLLIFY_UNIT_NAME(x) MOLLIFY_UNIT_STRING(x)
#define MOLLIFY_UNIT_JOIN(a, b) a##_##b
#define MOLLIFY_UNIT_FUNCTION(a, b) MOLLIFY_UNIT_JOIN(a, b)

namespace isa_units {

namespace {

template <class F>
std::uintptr_t address(F* f) {
    return reinterpret_cast<std::uintptr_t>(f);
}

// 6^3 particles on a jittered lattice in the unit periodic cube, eps = 0.3:
// the 3D cell sweep (its AVX2 sums and gathers in the v3 unit).
std::vector<double> sph_density() {
    constexpr int n = 6;
    mollify::sph::Field<3> x;
    for (int i = 0; i < n * n * n; ++i) {
        const int a = i % n, b = i / n % n, c = i / (n * n);
        x[0].push_back((a + 0.5 + 0.1 * std::sin(i)) / n);
        x[1].push_back((b + 0.5 + 0.1 * std::cos(3 * i)) / n);
        x[2].push_back((c + 0.5 + 0.1 * std::sin(7 * i)) / n);
    }
    mollify::sph::BarotropicEuler<3, mollify::Kernel> euler(mollify::kernel("wendland:k=2", 3), 0.3,
                                                            mollify::sph::Domain<3>::periodic(1.0),
                                                            std::vector<double>(x[0].size(), 1.0 / (n * n * n)));
    std::vector<double> rho;
    euler.density(x, rho);
    return rho;
}

// 50 charges, direct summation in 3D with the mollified kernel.
std::vector<double> poisson_potential() {
    std::array<std::vector<double>, 3> x;
    std::vector<double> q, delta{0.2};
    for (int j = 0; j < 50; ++j) {
        for (int c = 0; c < 3; ++c) x[c].push_back(std::fmod(0.618034 * (j + 1) * (c + 1), 1.0));
        q.push_back(j % 2 ? 0.5 : -0.25);
    }
    const mollify::poisson::Sources<3> s{{x[0], x[1], x[2]}, q, delta};
    return mollify::poisson::direct<3>(mollify::kernel("mollifier:M=4", 3), s).potential;
}

// The 3D treecode's field at 3000 sources (1000 under the sanitizers),
// leaves of 32 and p = 10 (many translations, whose inner loops,
// Multipole<3>::tile_dot and local_sums, take a register's worth of lanes at
// a time: 2 in the generic unit, 4 in the v3 unit), and direct summation's.
// The sources are the same doubles in both units: frac(0.7548776662 (j + 1)
// (c + 1) + 0.1 c) in integers, then one division (as a double expression,
// the v3 unit contracted it into an FMA, and the units' sources differed by
// an ulp: fields 1.8e-10 apart at close pairs, hiding the sums' rounding).
std::pair<std::vector<double>, std::vector<double>> tree_and_direct_field() {
    std::array<std::vector<double>, 3> x;
    std::vector<double> q, delta{0.02};
    const int n = mollify::testing::sanitized_build ? 1000 : 3000;
    for (std::uint64_t j = 0; j < static_cast<std::uint64_t>(n); ++j) {
        for (std::uint64_t c = 0; c < 3; ++c)
            x[c].push_back(static_cast<double>(((j + 1) * (c + 1) * 7548776662 + c * 1000000000) % 10000000000) / 1e10);
        q.push_back(std::sin(static_cast<double>(j)) - 0.1);
    }
    const mollify::poisson::Sources<3> s{{x[0], x[1], x[2]}, q, delta};
    const mollify::Kernel k = mollify::kernel("mollifier:M=4", 3);
    const auto tree = mollify::poisson::Treecode<3, mollify::Kernel>(k, s, {.theta = 0.5, .order = 10, .leaf_size = 32});
    std::pair<std::vector<double>, std::vector<double>> e;
    for (const auto& c : tree.evaluate().field) e.first.insert(e.first.end(), c.begin(), c.end());
    for (const auto& c : mollify::poisson::direct<3>(k, s).field) e.second.insert(e.second.end(), c.begin(), c.end());
    return e;
}

// Krasny's sheet of 64 compact blobs: the velocities.
std::vector<double> vortex_velocity() {
    const mollify::vortex::CompactBlob blob(mollify::kernel("wendland:k=2", 2), 0.1);
    const mollify::vortex::Sheet sheet = mollify::vortex::krasny_sheet(64, 0.01);
    std::vector<double> u, v;
    mollify::vortex::velocity(blob, sheet, u, v);
    return u;
}

}  // namespace

UnitCode MOLLIFY_UNIT_FUNCTION(MOLLIFY_UNIT, code)() {
    return {MOLLIFY_UNIT_NAME(MOLLIFY_ISA), address(&mollify::sph::detail::near_pairs<3, true>),
            address(static_cast<mollify::poisson::Field<3> (*)(const mollify::Kernel&, const mollify::poisson::Sources<3>&)>(
                &mollify::poisson::direct<3, mollify::Kernel>)),
            address(static_cast<void (*)(const mollify::vortex::CompactBlob&, const mollify::vortex::Sheet&,
                                         std::vector<double>&, std::vector<double>&)>(
                &mollify::vortex::velocity<mollify::vortex::CompactBlob>))};
}

UnitValues MOLLIFY_UNIT_FUNCTION(MOLLIFY_UNIT, values)() {
    auto [tree, direct] = tree_and_direct_field();
    return {sph_density(), poisson_potential(), vortex_velocity(), std::move(tree), std::move(direct)};
}

}  // namespace isa_units
