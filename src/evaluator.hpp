// The data-driven evaluator's entry points, compiled once per instruction
// set (src/evaluator.cpp in the inline namespace MOLLIFY_ISA of
// detail/isa.hpp) and chosen at load time by the CPU's features
// (src/dispatch.cpp).
#pragma once

#include "plan.hpp"

#include <mollify/precision.hpp>
#include <mollify/smoothing.hpp>

#include <cstddef>
#include <span>

namespace mollify::detail {

// The batch loops of one instruction set.
struct Evaluator {
    const char* isa;
    // f_h at n radii (unchecked: r finite >= 0, s made for the plan's dimension, q present).
    void (*evaluate)(const Plan& plan, Precision pr, QuantityId q, const double* r, double* out, std::size_t n,
                     const Smoothing& s);
    // W_h and grad W_h at n displacements (x and grad: dim spans of n).
    void (*pairs)(const Plan& plan, Precision pr, const std::span<const double>* x, const Smoothing& s, double* w,
                  const std::span<double>* grad, std::size_t n);
    // The public API's checks of its inputs (fail naming a bad value), in
    // this instruction set's vector loops: at -O2 for generic x86-64 they
    // cost as much as a fast batch.
    void (*check_radii)(std::span<const double> r);
    void (*check_coordinates)(std::span<const double> x, int component);
};

// The evaluator in use: x86-64-v3 (AVX2 + FMA) where the CPU has it, else
// generic x86-64; the environment variable MOLLIFY_ISA=generic (or
// set_isa) forces one.
const Evaluator& evaluator();

}  // namespace mollify::detail
