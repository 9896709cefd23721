// How far two evaluations of one table may differ: not at all where they
// perform the same operations (same_bits: runtime_forms_test on generic
// x86-64, batch_loops_test's batches against single points, table_file_test),
// and fused_bound where they round differently (one contracts a product into
// an FMA the other does not: runtime_forms_test's FMA copies against generic
// StaticKernel, batch_loops_test's x86-64-v3 StaticKernel against the
// run-time form's x86-64-v3 copy).
#pragma once

#include <mollify/kernel.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>

namespace mollify::testing {

// Where two evaluations must agree exactly (the same operations in the same
// order): the same bits, signed zeros and NaN payloads included.
inline bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// |a - b| in ulps of max(|a|, |b|, floor).
inline double ulps(double a, double b, double floor) {
    if (!std::isfinite(a) || !std::isfinite(b)) return a == b || (std::isnan(a) && std::isnan(b)) ? 0 : INFINITY;
    const double m = std::max({std::abs(a), std::abs(b), floor});
    if (m == 0) return 0;
    return std::abs(a - b) / (std::ldexp(1.0, std::ilogb(m) - 52));
}

// Each rounds differently (fused products), so they agree to the sum of
// their errors against the exact value. The accuracy suite bounds
// Precision::accurate by 4 ulp (values) and 8 (potentials); the difference
// then stays within 16, in ulps of the value (values tinier than 2^-40 of
// the largest |f_h| of the sample in ulps of that floor). Precision::fast
// rounds every term and multiplies the half-ulp rounding of q and 1 - q by
// the edge powers (up to ~25 ulp each, precision.hpp); near a root of f the
// terms cancel, so its error is ulps of the terms, not of f: measured in
// ulps of the sample's max |f_h|, 64. Near a breakpoint the rounded q may
// choose the neighbouring piece (both exact there) and the second
// derivatives of combinations jump by up to ~125 ulp (accuracy_test's kink
// bound of 256): 512 for those.
inline double fused_bound(const table::Kernel& k, QuantityId q, Precision pr) {
    const bool kink = q == QuantityId::d2r || q == QuantityId::laplacian || q == QuantityId::hess_radial ||
                      q == QuantityId::potential_hess_radial;
    if (kink && std::string(k.spec).rfind("combo", 0) == 0) return 512;
    return pr == Precision::accurate ? 16 : 64;
}

// The floor of ulps() for a sample: its largest finite |f_h|, times 2^-40
// for Precision::accurate (see fused_bound).
inline double ulp_floor(const double* f, std::size_t n, Precision pr) {
    double floor = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (std::isfinite(f[i])) floor = std::max(floor, std::abs(f[i]));
    return pr == Precision::accurate ? floor * 0x1p-40 : floor;
}

}  // namespace mollify::testing
