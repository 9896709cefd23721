// The certificate of the softening derivatives (softening.hpp): phi^(n),
// n = 0..6, is continuous across every breakpoint and, at the support edge,
// with the n-th derivative of the Green's function, proved exactly (rational
// and pi/log constants, no floating point) for every n the kernel's
// smoothness guarantees: a C^s kernel's potential is C^(s+2) (Gauss:
// phi' = m(r)/r^(D-1) with m' = r^(D-1) W, so phi' is C^(s+1)). Beyond that
// order the joins are measured and reported, jumps included, never hidden.
#pragma once

#include "certificate.hpp"
#include "kernel.hpp"

#include <optional>
#include <vector>

namespace mollify::gen {

// phi^(n) at one breakpoint; at the support edge the right side is the
// Green's function's n-th derivative.
struct Join {
    int order = 0;
    Q at;
    bool edge = false;
    std::optional<Exact> left, right;  // one-sided limits; nullopt where infinite (S^-j at r = 1)
    bool continuous() const { return left && right && *left == *right; }
};

struct SofteningSmoothness {
    int guaranteed = 0;        // min(s + 2, 6) for a C^s kernel (s = -1: discontinuous W)
    int continuous_at_edge = -1;  // highest n with phi^(0..n) all continuous at the edge
    std::vector<Join> joins;   // orders 0..6 by breakpoint, the edge last
};

// The highest i such that f[0..i] all have a finite limit at r = 0, -1 if
// f[0] has none: kernels with odd powers of r at the origin (a cusp, e.g.
// wendland:k=0, spiky) have high derivatives of phi, or SWIFT's D_soft_n,
// that blow up there, which a writer must know.
int finite_at_origin(const std::vector<Radial>& f);

// From softening_derivatives(k) (all seven).
SofteningSmoothness softening_smoothness(const ExactKernel& k, const std::vector<Radial>& derivatives);

// The joins of order <= guaranteed, each a certificate that must pass.
std::vector<Certificate> softening_certificates(const SofteningSmoothness& s);
std::vector<Certificate> softening_certificates(const ExactKernel& k);

// What a target writer (Phantom's kernel_softening, SWIFT's kernel_gravity.h,
// GADGET-4's g-factors) takes: phi^(0..6), in 3D the multipole factors
// E_0..E_5 (= D_soft_1..6 = fac0..5; empty in 1D and 2D), and the measured
// smoothness; Error naming the first failed certificate, never an
// uncertified form.
struct Softening {
    std::vector<Radial> derivatives;
    std::vector<Radial> multipole;
    SofteningSmoothness smoothness;
};
Softening certified_softening(const ExactKernel& k);

// "phi^(3) at r = 1 (edge)": the join's name for people.
std::string join_name(const Join& j);

}  // namespace mollify::gen
