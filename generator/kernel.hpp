// A kernel of the catalogue in dimension D, exactly: its shape as the family
// defines it, the normalisation constant (rational x pi^e), the normalised
// W = normalisation * shape, and the claims its certificates must prove.
#pragma once

#include "radial.hpp"
#include "spec.hpp"

#include <memory>
#include <string>
#include <vector>

namespace mollify::gen {

enum class Normalisation {
    unit_mass,          // int W = 1
    first_derivative,   // 1D, odd: int x W(x) dx = -1, so f * W ~ f' (Belley (17))
    second_derivative,  // 1D, even, zero mass: int x^2 W(x) dx = 2 (Belley)
};

struct Claims {
    int smoothness = 0;  // C^s across every breakpoint and at the support edge; -1: discontinuous
    int order = 2;       // radial moments r^2 .. r^(order-2) vanish
    std::string no_potential;  // why there is no Poisson potential; empty if there is one
};

struct ExactKernel {
    Spec spec;
    int dim = 3;
    Radial shape;
    Exact normalisation;
    Radial W;
    Normalisation normalised_by = Normalisation::unit_mass;
    Claims claims;
    std::string source;  // where the definition comes from
    // Computed once here, read by combo_terms and the writers:
    std::vector<Q> alpha;    // a mollifier's alpha_j, B = normalisation * sum_j alpha_j (1-r^2)^(M+j) (Anderson (12))
    std::vector<Q> weights;  // a combination's w_j of W = sum_j w_j psi_{a_j} (Franz (4.17), Prop. 4.24)
    std::shared_ptr<const ExactKernel> base;  // a combination's psi, unit mass, support 1
};

// Throws Error for a dimension outside 1..3 or a kernel not defined in it.
ExactKernel make_kernel(const Spec& spec, int dim);

// The terms of a combination W = sum_j w_j psi_{a_j} (Franz (4.17)):
// psi_{a_j} = a_j^-D psi(r/a_j), the base kernel (unit mass) scaled to
// support a_j, with its weight w_j (Prop. 4.24). Empty for other families.
struct ComboTerm {
    Q weight;
    ExactKernel kernel;
};
std::vector<ComboTerm> combo_terms(const ExactKernel& k);

// int_{R^D} |x|^p W dx (radial moment), exactly; p = 0 is the mass.
Exact radial_moment(const ExactKernel& k, int p);

}  // namespace mollify::gen
