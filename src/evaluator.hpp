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
    // f_h at n radii (s made for the plan's dimension, q present), and W_h
    // and grad W_h at n displacements (x and grad: dim spans of n). Both
    // check their inputs (fail naming a bad r or coordinate) a chunk at a
    // time, each chunk evaluated while it is still in cache: a separate
    // check pass over a batch larger than the caches read it from memory
    // twice (kernel_bench, 10^6 points). On failure, the outputs of the
    // chunks before the bad value are written, the rest untouched.
    void (*evaluate)(const Plan& plan, Precision pr, QuantityId q, const double* r, double* out, std::size_t n,
                     const Smoothing& s);
    void (*pairs)(const Plan& plan, Precision pr, const std::span<const double>* x, const Smoothing& s, double* w,
                  const std::span<double>* grad, std::size_t n);
    // f_h at one radius, checked (fail naming a bad r): evaluate's
    // operations for one point, so its bits, without its chunks around
    // them (Kernel::operator(), a checked scalar call).
    double (*at_radius)(const Plan& plan, Precision pr, QuantityId q, double r, const Smoothing& s);
};

// The evaluator in use: x86-64-v4 (AVX-512F/BW/DQ/VL) where the CPU has it,
// else x86-64-v3 (AVX2 + FMA) where it has that, else generic x86-64; the environment variable MOLLIFY_ISA=generic (or
// set_isa) forces one.
const Evaluator& evaluator();

}  // namespace mollify::detail
