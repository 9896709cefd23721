// How the runtime evaluates the factored kernel forms: a choice of speed
// against error, made per kernel type (StaticKernel<table, Precision>).
#pragma once

#include <string_view>

namespace mollify {

enum class Precision {
    // The default. Everything the error comes from in double-double
    // (detail/double_double.hpp): r/h, 1 - r/h, the edge factors
    // (1 - q)^n, (1 - q^2)^M, S^m, the coefficients (table::Term::c_lo) and
    // the polynomial, by the compensated Horner scheme (detail/evaluate.hpp);
    // one rounding at the end. Values and derivatives of every catalogue
    // kernel within 4 ulp (measured <= 0.51 but for the missing Wendland
    // functions, <= 2.96), potentials within 8 (tests/accuracy_test.cpp).
    accurate,
    // Plain double: the same factored forms with rounded q and 1 - q, whose
    // half-ulp the power n multiplies; 2.8-3.8x the speed
    // (bench/results/kernel_bench.md). Every catalogue kernel within 32 ulps
    // of max(|f|, |r f'|) (measured <= 21.8), the mollifiers of order 4 and 6
    // and the combinations within 64 (their polynomials' terms cancel:
    // measured <= 49.7) (tests/accuracy_test.cpp, fast_bound).
    fast,
};

// Names as in scene files and on command lines: "accurate", "fast"
// (src/precision.cpp; an unknown name fails naming it).
std::string_view name(Precision p);
Precision precision(std::string_view name);

}  // namespace mollify
