#include "softening.hpp"

#include "error.hpp"
#include "potential.hpp"

namespace mollify::gen {

namespace {

std::string where(const ExactKernel& k) { return "kernel " + spec_string(k.spec) + " in D = " + std::to_string(k.dim); }

void check_order(const std::string& what, int order, int low, int high) {
    if (order < low || order > high)
        fail(what + " order " + std::to_string(order) + " is outside " + std::to_string(low) + ".." +
             std::to_string(high));
}

Radial poisson_potential(const ExactKernel& k) {
    if (!k.claims.no_potential.empty()) fail(where(k) + ": " + k.claims.no_potential);
    return potential(k.W, k.dim);
}

}  // namespace

std::vector<Radial> softening_derivatives(const ExactKernel& k, int max_order) {
    check_order("softening", max_order, 0, max_softening_order);
    std::vector<Radial> d{poisson_potential(k)};
    for (int n = 1; n <= max_order; ++n) d.push_back(d.back().derivative());
    return d;
}

Radial softened_inverse_distance(const ExactKernel& k) {
    if (k.dim != 3)
        fail(where(k) + ": the softened 1/r (SWIFT's D_soft, GADGET-4's g-factors) is 3D gravity; D = " +
             std::to_string(k.dim) + " has no 1/r Green's function");
    // 3D Green's function -1/(omega_3 r): g = -omega_3 phi is 1/r outside.
    return poisson_potential(k) * (-sphere_measure(3));
}

Exact plummer_equivalent(const Radial& g, const std::string& kernel) {
    Exact g0;
    try {
        g0 = value_at(g.pieces.front(), Q(0));
    } catch (const Error& e) {
        fail("kernel " + kernel + ": the softened 1/r is infinite at r = 0 (" + e.what() + "), no Plummer-equivalent softening");
    }
    if (!(g0.evaluate(64).first > 0))
        fail("kernel " + kernel + ": the softened 1/r at r = 0 is " + g0.to_string() + " <= 0, no Plummer-equivalent softening");
    return g0;
}

std::vector<Radial> multipole_factors(const ExactKernel& k, int max_order) {
    check_order("multipole factor", max_order, 0, max_softening_order - 1);
    std::vector<Radial> e{softened_inverse_distance(k)};
    for (int n = 0; n < max_order; ++n) {
        // E_{n+1} = E_n' - n E_n / r (derivation in softening.hpp).
        Radial next = e[n].derivative() - e[n].times(Laurent::monomial(Q(n), -1));
        next.parity = n % 2 ? 1 : -1;
        e.push_back(next);
    }
    return e;
}

Radial softening_h_derivative(const ExactKernel& k) {
    if (k.dim != 3)
        fail(where(k) + ": dphidh is defined for 3D gravity (phi_h = phi(r/h)/h); D = " + std::to_string(k.dim));
    const Radial phi = poisson_potential(k);
    Radial d = (phi + phi.derivative().times(Laurent::monomial(Q(1), 1))) * Exact(Q(-1));
    d.parity = 1;
    return d;
}

std::vector<Radial> swift_d_soft(const ExactKernel& k, int max_order) {
    check_order("D_soft", max_order, 1, max_d_soft);
    return multipole_factors(k, max_order - 1);
}

std::vector<Radial> gadget_gfactors(const ExactKernel& k, int max_order) {
    check_order("g-factor", max_order, 0, max_gfactor);
    return multipole_factors(k, max_order);
}

}  // namespace mollify::gen
