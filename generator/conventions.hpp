// Conventions as data (issue 19, item 6): one description per output target
// of `mollify-gen emit --target NAME` (support radius in units of the
// target's h, normalisation, quantities, sign and scaling of the potential
// and the force, precision), read by the writers and, later, by
// verification. The facts about other codes come from ../shared/peers.md
// (sources cited there); every kernel-dependent constant a convention
// needs (SWIFT's gamma, Phantom's hfact) is computed here exactly from the
// kernel's exact second moment, never typed into a writer.
#pragma once

#include "exact.hpp"
#include "kernel.hpp"

#include <mollify/table.hpp>

#include <string>
#include <utility>
#include <vector>

namespace mollify::gen {

enum class FloatFormat { binary64, binary32 };

// How the target's smoothing length h relates to the support radius H of
// the kernel (mollify's tables have H = 1, and mollify's runtime h is H).
enum class SupportRule {
    support,         // h = H (mollify; GADGET-4's Hsml)
    fixed_multiple,  // H = support_in_h * h (Phantom's radkern)
    twice_sigma,     // h = 2 sigma, H = gamma h, gamma = H / (2 sigma) (SWIFT; Dehnen & Aly 2012, table 1)
};

// How the target writes the kernel: W = norm * w(x) h^-D with x = r / h
// (the normalisation folded into the tables: mollify), or with the
// normalisation a separate constant in front of an unnormalised w (Phantom's
// cnormk, SWIFT's kernel_constant, GADGET-4's NORM).
enum class NormalisationRule { folded, separate_constant };

// The target's potential phi_t as a multiple of mollify's phi (Delta phi = W,
// the Green's function outside: 3D -1/(4 pi r)): the target fixes its
// Green's function's coefficient in 3D (Phantom: phi = -1/q outside for
// G = m = h = 1, so -1; GADGET-4's g-factor is +1/r outside).
struct PotentialRule {
    bool has_potential = true;
    Exact green_coefficient_3d;  // c of c / r outside the support, 3D
    std::string description;
};

struct Convention {
    std::string target;  // the --target name
    std::string code;    // whom the files are for, and the source of the facts
    std::vector<std::string> files;  // what one kernel's files are
    std::vector<int> dims;           // the dimensions the target takes
    FloatFormat precision;
    SupportRule support;
    Q support_in_h;  // SupportRule::support: 1; fixed_multiple: the multiple; twice_sigma: unused (gamma per kernel)
    NormalisationRule normalisation;
    std::vector<table::QuantityId> quantities;  // what the target's functions give
    PotentialRule potential;
    std::string force;   // sign and scaling of the force / gradient
    bool clamps_sign;    // the target clamps W >= 0 and dW <= 0 (SWIFT): no negative lobes
    std::string notes;
    // fixed_multiple: the kernels the code ships with another H/h than
    // support_in_h (support_multiple)
    std::vector<std::pair<Family, Q>> own_multiples;
};

// Every target's convention, the generic ones (cpp, c, fortran, python)
// first.
const std::vector<Convention>& conventions();
// Error naming the target and the known ones.
const Convention& convention(const std::string& target);

// A real constant a convention derives from a kernel, exactly: the square
// root of a rational where needed (gamma, hfact), its square kept exactly.
struct DerivedConstant {
    std::string name;
    Q square;          // the constant is sqrt(square) (positive)
    double value;      // correctly rounded to double
    float value_float; // correctly rounded to float
    std::string rule;  // how it is derived, for the files' comments
};

// sqrt(x) correctly rounded (round half to even) to double and to float,
// decided exactly on rationals: d is RN(sqrt x) iff x lies between the
// squares of d's neighbouring midpoints.
double sqrt_to_double(const Q& x);
float sqrt_to_float(const Q& x);
// sqrt(x) as text for a comment: the rational root where x is a rational
// square ("13/10" for 169/100), else "sqrt(x)".
std::string sqrt_text(const Q& x);

// sigma^2 = (1/D) int |x|^2 W d^D x: the per-dimension variance of the
// (unit-mass, support 1) kernel, exactly (rational for every kernel of the
// grammar: the normalisation's pi cancels the sphere's).
Q variance(const ExactKernel& k);
// SWIFT's gamma = H / (2 sigma) (H = 1): gamma^2 = 1 / (4 sigma^2).
DerivedConstant swift_gamma(const ExactKernel& k);
// Phantom's hfact_default: for the six kernels Phantom ships (cubic,
// quartic, quintic spline, Wendland C2, C4, C6), its own (1.2, 1.1, 1.0, 1.3,
// 1.5, 1.6: a file that replaces the stock one keeps its h, as radkern);
// for the others the one at which the kernel's standard deviation, in units
// of the mean particle spacing, equals that of Phantom's cubic spline
// (radkern 2) at hfact 1.2 (Dehnen & Aly's equal resolution; it would give
// C2 1.27, C4 1.45, C6 1.61, the quintic 0.96): hfact = 1.2 (radkern_cubic
// sigma_cubic) / (radkern sigma), and at least 1, which Phantom's checksetup
// demands (mollifier:M=1 and M=2: 0.87 and 0.99 by the rule).
DerivedConstant phantom_hfact(const ExactKernel& k);
// H/h of SupportRule::support and fixed_multiple for kernel k: the
// convention's support_in_h, or its own_multiples entry for k's family
// (Phantom's radkern of its stock quartic and quintic splines, so that their
// files are the phantom convention and mollify's replace them with the same h).
Q support_multiple(const Convention& c, const ExactKernel& k);
// NormalisationRule::separate_constant: the constant C of W = C w(x) h^-D
// with w the kernel scaled to w(0) = 1 (the stock forms of Phantom and
// GADGET-4: (1 - q/2)^4 (2q + 1), 1 + 6 (u - 1) u^2, ...), exactly:
// fixed_multiple and support, x = r/H, H = support_multiple h, so C = W(0) /
// support_multiple^D with W mollify's kernel on support 1 (Phantom's cnormk:
// 1/pi for the cubic, 21/(16 pi) for Wendland C2; GADGET-4's NORM 8/pi);
// twice_sigma, W(u) = C gamma^-D w(u/gamma) (SWIFT): C = W(0). Error for a
// kernel with W(0) = 0 or singular there.
Exact separate_normalisation(const Convention& c, const ExactKernel& k);
// The target's potential over mollify's: c_target / c_mollify (3D), exact.
Exact potential_scale(const Convention& c);

}  // namespace mollify::gen
