// Gravitational softening to order 6: the exact radial derivatives of a
// kernel's Poisson potential phi (potential.hpp; support 1, r = u = distance/h)
// and the two multipole forms the N-body codes build from them:
//
//   d^n phi / dr^n, n = 0..6 (softening_derivatives);
//   E_n = r^n ((1/r) d/dr)^n g, g = -omega_3 phi = -4 pi phi the softened 1/r
//   (1/r outside the support), which are both
//     SWIFT's D_soft_{n+1}(u), n = 0..5 (../shared/peers.md, SWIFT: D_soft_1 =
//       -W with W = 4 pi phi its potential kernel, and D_soft_{n+1} = D_soft_n'
//       - (n-1) D_soft_n / u; SWIFT src/kernel_gravity.h and
//       src/gravity_derivatives.h at 8a8f0d794430), and
//     GADGET-4's g-factors fac_n, n = 0..5 (src/gravtree/gravtree.h, struct
//       gfactors, in weiguangcui/Gadget4: g, g', g'' - g'/r,
//       g''' - 3 g''/r + 3 g'/r^2, ...).
//
// Why one E_n serves both. T_n = ((1/r) d/dr)^n g is the radial factor of the
// n-th Cartesian derivative tensor of g(|x|): d_i g = T_1 x_i, d_i T_n =
// T_n' x_i / r = T_{n+1} x_i (so T_{n+1} = T_n' / r, the recursion of the
// brief). With E_n = r^n T_n: E_n' = n E_n / r + r^n T_n' = n E_n / r +
// E_{n+1}, hence E_{n+1} = E_n' - n E_n / r, which is SWIFT's recursion with
// D_soft_{n+1} = E_n, and E_0 = g, E_1 = g', E_2 = g'' - g'/r,
// E_3 = E_2' - 2 E_2 / r = g''' - 3 g''/r + 3 g'/r^2, ... GADGET-4's fac_n.
//
// Scaling (3D, G = m = 1). mollify's phi has support 1; for a softening
// length H (the support): Phi(r) = 4 pi phi(r/H) / H is the potential of a
// unit mass with Delta Phi = 4 pi W_H. SWIFT: u = r/H with H = 3 eps
// (Plummer-equivalent eps), Dt_n = H^-n D_soft_n(u); GADGET-4: u = r/h with
// h = the support (2.8 eps), fac_n(r) = h^-(n+1) E_n(u). Both codes' functions
// are therefore these E_n with H (or h) = 1.
#pragma once

#include "kernel.hpp"

#include <vector>

namespace mollify::gen {

// The orders the N-body codes need: SWIFT's D_soft_1..D_soft_6 (multipole
// order + 1 <= 6), GADGET-4's fac0..fac5 (MULTIPOLE_ORDER <= 5).
inline constexpr int max_softening_order = 6;
inline constexpr int max_d_soft = 6;
inline constexpr int max_gfactor = 5;

// d^n phi / dr^n for n = 0..max_order, exactly, piecewise, the Green's
// function's derivative outside the support. Error for an order outside
// 0..6 or a kernel without a Poisson potential.
std::vector<Radial> softening_derivatives(const ExactKernel& k, int max_order = max_softening_order);

// g = -4 pi phi, the softened 1/r (D = 3 only: the N-body codes' gravity).
Radial softened_inverse_distance(const ExactKernel& k);

// H / eps of the Plummer-equivalent softening, from g of a kernel on support
// 1: g(0), so that the softened potential at r = 0, -m g(0)/H, is Plummer's
// -m/eps (SWIFT's kernel_gravity_softening_plummer_equivalent, 3 for Wendland
// C2; GADGET-4's hard-coded 2.8 = 14/5 for its cubic spline). Error naming
// `kernel` where g(0) is infinite or not positive.
Exact plummer_equivalent(const Radial& g, const std::string& kernel);

// E_0..E_max_order of g (see above); the exterior is (-1)^n (2n-1)!! / r^(n+1).
std::vector<Radial> multipole_factors(const ExactKernel& k, int max_order);

// d/dh of the softened potential phi_h(r) = phi(r/h)/h at h = 1, as a function
// of q = r/h: -(phi + q phi') (the h^-2 factored out), zero outside the support
// (the Green's function does not depend on h). Phantom's dphidh (peers.md:
// dphidh = -phi - q dphi/dq), in mollify's scaling (support 1); 3D only.
Radial softening_h_derivative(const ExactKernel& k);

// SWIFT: element n-1 is D_soft_n(u), n = 1..max_order (<= 6).
std::vector<Radial> swift_d_soft(const ExactKernel& k, int max_order = max_d_soft);

// GADGET-4: element n is fac_n(u), n = 0..max_order (<= 5).
std::vector<Radial> gadget_gfactors(const ExactKernel& k, int max_order = max_gfactor);

}  // namespace mollify::gen
