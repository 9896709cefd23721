// What the free-space Poisson solvers take and give: smoothed sources and
// the potential and field they make at target points.
//
// Convention (the runtime's, include/mollify/static_kernel.hpp): the
// potential of a unit source smoothed by W_delta solves
//     Delta phi_delta = W_delta,
// so outside the support phi_delta(r) IS the Green's function
//     G(r) = -1/(4 pi r)   (3D),     G(r) = log(r)/(2 pi)   (2D),
// and inside it is finite (at r = 0 too: the self term is exact). The solvers
// return, at each target x,
//     phi(x) = sum_j q_j phi_delta_j(|x - x_j|),     E(x) = -grad phi(x).
// phi is therefore MINUS the physicist's electrostatic potential of charges
// q_j/(4 pi) (3D): with q_j = 4 pi G m_j it is the Newtonian gravitational
// potential (Delta phi = 4 pi G rho) and E the gravitational acceleration,
// pointing TOWARDS a positive q_j. The notes' stream function of vortices
// Gamma_j (notes 001, "vortex blobs": -Delta g = delta, psi = g * omega) is
// psi = -phi with q_j = Gamma_j; see biot_savart().
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>
#include <mollify/static_kernel.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

// Sources as views of the caller's arrays (structure of arrays): positions
// x[c][j], charges q[j], and the smoothing length delta (the kernel's support
// radius): one value for every source, or one per source.
template <int D>
struct Sources {
    Points<D> x;
    std::span<const double> q;
    std::span<const double> delta;

    std::size_t size() const { return q.size(); }
    bool global_delta() const { return delta.size() == 1; }
    double delta_of(std::size_t j) const { return global_delta() ? delta[0] : delta[j]; }
};

// Potential phi and field E = -grad phi at each target.
template <int D>
struct Field {
    std::vector<double> potential;
    std::array<std::vector<double>, D> field;

    explicit Field(std::size_t n = 0) : potential(n, 0.0) {
        for (auto& c : field) c.assign(n, 0.0);
    }
    std::size_t size() const { return potential.size(); }
};

// The 2D Biot-Savart velocity of vortex blobs of circulation q_j: the notes
// (001, "vortex blobs") take psi = g * omega with -Delta g = delta and
// (u, v) = (psi_y, -psi_x). Here psi = -phi, so
//     u = -phi_y = E_y,     v = phi_x = -E_x.
// (A single blob of circulation Gamma > 0 turns counter-clockwise: at
// (r, 0) outside the support, u = 0, v = Gamma/(2 pi r).)
inline std::array<std::vector<double>, 2> biot_savart(const Field<2>& f) {
    std::array<std::vector<double>, 2> u{f.field[1], f.field[0]};
    for (double& v : u[1]) v = -v;
    return u;
}

namespace detail {

inline void check_points(std::span<const double> x, int component, const char* what) {
    for (std::size_t j = 0; j < x.size(); ++j)
        if (!std::isfinite(x[j]))
            fail(std::string(what) + " " + std::to_string(j) + ": coordinate x[" + std::to_string(component) +
                 "] = " + mollify::detail::show(x[j]) + " is not finite");
}

// Every check the solvers make before they compute: a non-empty source set,
// matching sizes, finite coordinates and charges, delta > 0 finite.
template <int D>
void check_sources(const Sources<D>& s) {
    const std::size_t n = s.q.size();
    if (n == 0) fail("the source set is empty (no charges q_j)");
    for (int c = 0; c < D; ++c) {
        if (s.x[c].size() != n)
            fail("sources: " + std::to_string(n) + " charges but " + std::to_string(s.x[c].size()) +
                 " coordinates x[" + std::to_string(c) + "]");
        check_points(s.x[c], c, "source");
    }
    if (s.delta.size() != 1 && s.delta.size() != n)
        fail("sources: " + std::to_string(s.delta.size()) + " smoothing lengths delta for " + std::to_string(n) +
             " sources (give one for all, or one per source)");
    for (std::size_t j = 0; j < s.delta.size(); ++j)
        if (!(s.delta[j] > 0) || !std::isfinite(s.delta[j]))
            fail("smoothing length delta[" + std::to_string(j) + "] = " + mollify::detail::show(s.delta[j]) +
                 " is not a positive finite number");
    for (std::size_t j = 0; j < n; ++j)
        if (!std::isfinite(s.q[j]))
            fail("charge q[" + std::to_string(j) + "] = " + mollify::detail::show(s.q[j]) + " is not finite");
}

template <int D>
std::size_t check_targets(const Points<D>& x) {
    for (int c = 0; c < D; ++c) {
        if (x[c].size() != x[0].size())
            fail("targets: " + std::to_string(x[0].size()) + " coordinates x[0] but " + std::to_string(x[c].size()) +
                 " coordinates x[" + std::to_string(c) + "]");
        check_points(x[c], c, "target");
    }
    return x[0].size();
}

}  // namespace detail
}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
