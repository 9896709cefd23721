// The error terms Franz tracks (§6.2), between an SPH state and a reference
// solution (u~, rho~), weighted by the particle masses h^d rho_0(h j):
//   Q_kin = h^d sum_j rho_0(h j) |u_j - u~(x_j, t)|^2,
//   Q_pot = h^d sum_j rho_0(h j) |rho^{eps,h}(x_j) - rho~(x_j, t)|,
// Q_pot standing in for the potential part of Q (3.27), which needs the
// root kernel.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/sph/euler.hpp>

#include <cstddef>
#include <vector>

namespace mollify::sph {
inline namespace MOLLIFY_ISA {

struct EnergyError {
    double kinetic = 0;
    double potential = 0;
};

template <int D, class Velocity, class Density>
EnergyError energy_error(const State<D>& y, const std::vector<double>& rho, const std::vector<double>& mass,
                         Velocity&& exact_u, Density&& exact_rho) {
    EnergyError q;
    for (std::size_t j = 0; j < y.size(); ++j) {
        const auto u = exact_u(j);
        double e2 = 0;
        for (int c = 0; c < D; ++c) e2 += (y.u[c][j] - u[c]) * (y.u[c][j] - u[c]);
        q.kinetic += mass[j] * e2;
        q.potential += mass[j] * std::abs(rho[j] - exact_rho(j));
    }
    return q;
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph
