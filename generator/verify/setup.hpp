// What every step of a verification shares: the exact reference of the
// kernel, and how the convention's (r, h) and values relate to mollify's
// f_H(r) (generator/conventions.hpp): H = s h, value = c f_H(r).
#pragma once

#include "../conventions.hpp"
#include "reference.hpp"

#include <mollify/table.hpp>
#include <mollify/verify.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace mollify::verify::detail {

using Real = accuracy::Real;

struct Setup {
    std::string spec;  // canonical
    int dim = 0;
    Quantity quantity = Quantity::value;
    table::QuantityId id = table::QuantityId::value;
    const gen::Convention* convention = nullptr;
    std::shared_ptr<const accuracy::Reference> reference;
    gen::Q support_square;  // s^2 (s = sqrt of it: SWIFT's gamma is irrational)
    Real support_scale;     // s, >= 300 bits
    gen::Exact value_scale; // c: the convention's potential over mollify's (1 for W, dW/dr)
    Real value_scale_real;
    bool single = false;    // the convention's values are floats: ulps of float
    int power = 0;          // f_H(r) = H^power f(r/H)
};

// Errors naming an unknown spec, convention or quantity, a dimension the
// kernel or the convention lacks, a quantity the kernel lacks.
Setup setup(std::string_view spec, int dim, Quantity quantity, const Options& options);

// The reference of spec in dim, built once per process (kept: 8 at most).
std::shared_ptr<const accuracy::Reference> reference(const std::string& spec, int dim);

// H = s h in MPFR (exact for s = 1, 2).
Real support_of(const Setup& s, double h);
// The exact value in the convention's units at (r, h): c f_H(r).
Real exact(const Setup& s, double r, double h);
// The same for another reference (another dimension) or another support H.
Real exact_with(const Setup& s, const accuracy::Reference& ref, double r, const Real& H);
// max |value| over the support at this h (the scale of tiny values).
double magnitude(const Setup& s, double h);

// The hard points of samples() (generator/verify/samples.cpp), without
// the uniform ones: what compare() counts among the samples it is given.
std::vector<Sample> hard_samples(const Setup& s);

}  // namespace mollify::verify::detail
