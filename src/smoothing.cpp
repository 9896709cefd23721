// Smoothing's constructor, out of line: it runs once per h, and its checks'
// messages need <string> (include/mollify/detail/failures.hpp).
#include <mollify/smoothing.hpp>

#include <cmath>

namespace mollify {

Smoothing::Smoothing(double h, int dim) : h_(h), dim_(dim) {
    if (dim < 1 || dim > 3) detail::fail_dimension(dim);
    if (!(h > 0) || !std::isfinite(h)) detail::fail_smoothing_length(h);
    inv_h_ = 1 / h;
    for (int q = 0; q < table::quantity_count; ++q) {
        // h^n in long double, then one rounding: the scale is (all but
        // always) the correctly rounded power; its rounding error, to the
        // 11 further bits of long double, is kept for Precision::accurate.
        const int n = detail::scale_power(static_cast<QuantityId>(q), dim);
        const long double p = std::pow(static_cast<long double>(h), n);
        scale_[q] = static_cast<double>(p);
        scale_lo_[q] = static_cast<double>(p - static_cast<long double>(scale_[q]));
        if (!std::isnormal(scale_[q])) detail::fail_smoothing_range(h, dim, n, q);
    }
    log_h_ = std::log(h);
}

}  // namespace mollify
