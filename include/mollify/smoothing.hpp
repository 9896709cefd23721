// Everything a kernel evaluation needs from the smoothing length h, computed
// once per h (and checked once): W_h(r) = h^-D W(r/h), so each quantity
// carries a power of h (its dimension), and a 2D potential the constant
// log h that keeps it equal to the Green's function outside the support.
#pragma once

#include <mollify/error.hpp>
#include <mollify/table.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <charconv>
#include <string>

namespace mollify {

using QuantityId = table::QuantityId;

using table::quantity_names;

namespace detail {

// The shortest decimal that reads back as x (0.6, not 0.59999999999999998).
inline std::string show(double x) {
    char buf[32];
    return {buf, std::to_chars(buf, buf + sizeof buf, x).ptr};
}

// f_h(r) = h^(scale_power) f(r/h): W_h = h^-D W(r/h) and every r-derivative
// adds a power of 1/h; the potential solves Delta phi_h = W_h, two powers up.
constexpr int scale_power(QuantityId q, int dim) {
    constexpr int shift[table::quantity_count] = {0, -1, -2, -2, -2, -4, 2, 1, 0, -2};
    return shift[static_cast<int>(q)] - dim;
}

}  // namespace detail

class Smoothing {
public:
    Smoothing(double h, int dim) : h_(h), dim_(dim) {
        if (dim < 1 || dim > 3) fail("dimension " + std::to_string(dim) + " is not 1, 2 or 3");
        if (!(h > 0) || !std::isfinite(h)) fail("smoothing length h = " + detail::show(h) + " is not a positive finite number");
        inv_h_ = 1 / h;
        for (int q = 0; q < table::quantity_count; ++q) {
            // h^n in long double, then one rounding: the scale is (all but
            // always) the correctly rounded power; its rounding error, to the
            // 11 further bits of long double, is kept for Precision::accurate.
            const int n = detail::scale_power(static_cast<QuantityId>(q), dim);
            const long double p = std::pow(static_cast<long double>(h), n);
            scale_[q] = static_cast<double>(p);
            scale_lo_[q] = static_cast<double>(p - static_cast<long double>(scale_[q]));
            if (!std::isnormal(scale_[q]))
                fail("smoothing length h = " + detail::show(h) + " is out of range in D = " + std::to_string(dim) +
                     ": h^" + std::to_string(n) + " (for " + quantity_names[q] + ") is not a normal double");
        }
        log_h_ = std::log(h);
    }

    double h() const { return h_; }
    double inverse() const { return inv_h_; }
    int dim() const { return dim_; }
    double scale(QuantityId q) const { return scale_[static_cast<int>(q)]; }
    double scale_lo(QuantityId q) const { return scale_lo_[static_cast<int>(q)]; }  // h^p - scale(q)
    double log_h() const { return log_h_; }

private:
    double h_;
    int dim_;
    double inv_h_ = 0;
    double log_h_ = 0;
    std::array<double, table::quantity_count> scale_{}, scale_lo_{};
};

namespace detail {

// A radius must be a finite r >= 0: a NaN would otherwise fail every
// comparison and come out as an exterior 0.
inline void check_radius(double r) {
    if (!(r >= 0) || !std::isfinite(r)) fail("radius r = " + show(r) + " is not a finite number >= 0");
}

inline void check_coordinate(double x, int component) {
    if (!std::isfinite(x)) fail("coordinate x[" + std::to_string(component) + "] = " + show(x) + " is not finite");
}

}  // namespace detail
}  // namespace mollify
