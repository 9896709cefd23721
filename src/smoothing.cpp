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

}  // namespace

Smoothing::Smoothing(double h, int dim) : h_(h), dim_(dim) {
    if (dim < 1 || dim > 3) detail::fail_dimension(dim);
    if (!(h > 0) || !std::isfinite(h)) detail::fail_smoothing_length(h);
    inv_h_ = 1 / h;
    for (int q = 0; q < table::quantity_count; ++q) {
        const int n = detail::scale_power(static_cast<QuantityId>(q), dim);
        // Within 2^+-900 (smoothing.hpp: scale_range) or refused: the
        // accurate precision's last product is by h^p + its low part, or by
        // a term's content (2^-11 .. 2^9 in the catalogue, within 2^+-60 in
        // any table) times them, and both must stay normal doubles: beyond,
        // h^p's low part (2^-53 h^p) loses bits to underflow, or content
        // h^p overflows, and the results are wrong by an ulp or +-inf.
        const detail::DoubleDouble p = power(h, n);
        if (!(p.hi >= 1 / scale_range && p.hi <= scale_range)) detail::fail_smoothing_range(h, dim, n, q);
        scale_[q] = p.hi;
        scale_lo_[q] = p.lo;
    }
    log_h_ = std::log(h);
}

}  // namespace mollify
