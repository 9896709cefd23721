// Smoothing's constructor, out of line: it runs once per h, and its checks'
// messages need <string> (include/mollify/detail/failures.hpp).
#include <mollify/detail/double_double.hpp>
#include <mollify/smoothing.hpp>

#include <cmath>
#include <cstdlib>

namespace mollify {

namespace {

// h^n (|n| <= 7) in double-double by repeated products of h or of its
// double-double reciprocal: ~|n| 2^-104 relative error, so the rounded sum
// is h^n correctly rounded but for values that close to a rounding boundary,
// and the low part is the rounding error Precision::accurate carries. Ten
// products and a reciprocal per quantity; std::pow(long double, int) went
// through powl and cost a fifth of a batch of the accuracy suite, whose
// points each have their own h (as an SPH code's particles do).
detail::DoubleDouble power(double h, int n) {
    const detail::DoubleDouble x = n < 0 ? detail::reciprocal({h, 0.0}) : detail::DoubleDouble{h, 0.0};
    detail::DoubleDouble p{1.0, 0.0};
    for (int i = 0; i < std::abs(n); ++i) p = p * x;
    return detail::fast_two_sum(p.hi, p.lo);
}

// Where the low part of h^n would underflow (or h^n overflow) the 64-bit
// significand and 15-bit exponent of long double keep 11 bits beyond the
// double; one rounding of its power then gives the scale.
detail::DoubleDouble extended_power(double h, int n) {
    const long double p = std::pow(static_cast<long double>(h), n);
    const double hi = static_cast<double>(p);
    return {hi, static_cast<double>(p - static_cast<long double>(hi))};
}

}  // namespace

Smoothing::Smoothing(double h, int dim) : h_(h), dim_(dim) {
    if (dim < 1 || dim > 3) detail::fail_dimension(dim);
    if (!(h > 0) || !std::isfinite(h)) detail::fail_smoothing_length(h);
    inv_h_ = 1 / h;
    for (int q = 0; q < table::quantity_count; ++q) {
        const int n = detail::scale_power(static_cast<QuantityId>(q), dim);
        detail::DoubleDouble p = power(h, n);
        if (!(std::abs(p.hi) >= 0x1p-960 && std::abs(p.hi) <= 0x1p+1000)) p = extended_power(h, n);
        scale_[q] = p.hi;
        scale_lo_[q] = p.lo;
        if (!std::isnormal(scale_[q])) detail::fail_smoothing_range(h, dim, n, q);
    }
    log_h_ = std::log(h);
}

}  // namespace mollify
