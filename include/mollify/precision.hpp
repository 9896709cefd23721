// How the runtime evaluates the factored kernel forms: a choice of speed
// against error, made per kernel type (StaticKernel<table, Precision>).
#pragma once

namespace mollify {

enum class Precision {
    // The default. r/h, 1 - r/h and the edge factors (1 - q)^n, (1 - q^2)^M,
    // S^m in double-double (detail/double_double.hpp): the power no longer
    // multiplies the rounding of its base by n, and values and gradients of
    // the kernels without interior roots are within 4 ulp (tests/accuracy_test.cpp).
    accurate,
    // Plain double: the same factored forms with rounded q and 1 - q, whose
    // half-ulp the power n multiplies (up to ~25 ulp for n = 14); about 2.4x
    // the speed (bench/results/kernel_bench.md).
    fast,
};

}  // namespace mollify
