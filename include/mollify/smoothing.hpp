// Everything a kernel evaluation needs from the smoothing length h, computed
// once per h (and checked once): W_h(r) = h^-D W(r/h), so each quantity
// carries a power of h (its dimension), and a 2D potential the constant
// log h that keeps it equal to the Green's function outside the support.
#pragma once

#include <mollify/detail/failures.hpp>
#include <mollify/table.hpp>

#include <array>
#include <cmath>
#include <initializer_list>

namespace mollify {

using QuantityId = table::QuantityId;

using table::quantity_names;

namespace detail {

// f_h(r) = h^(scale_power) f(r/h): W_h = h^-D W(r/h) and every r-derivative
// adds a power of 1/h; the potential solves Delta phi_h = W_h, two powers up.
constexpr int scale_power(QuantityId q, int dim) {
    constexpr int shift[table::quantity_count] = {0, -1, -2, -2, -2, -4, 2, 1, 0, -2};
    return shift[static_cast<int>(q)] - dim;
}

// Every quantity as a bit (1 << QuantityId): Smoothing's sets of scales.
inline constexpr unsigned every_quantity = (1u << table::quantity_count) - 1;

}  // namespace detail

// Every h^p a Smoothing accepts lies in [1/scale_range, scale_range]
// (src/smoothing.cpp: why): h in ~[2.0e-39, 5.1e38] in 3D, where the
// Hessian part's h^-7 is the extreme, ~[7.0e-46, 1.4e45] in 2D, ~[6.5e-55,
// 1.5e54] in 1D.
inline constexpr double scale_range = 0x1p+900;

class Smoothing {
    // The tag of a Smoothing with some quantities' scales (reused(h, dim, q)):
    // explicit, so that no caller outside can pass {} for it.
    struct Some {
        explicit Some() = default;
    };

public:
    // Checks h and D (mollify::Error naming them); out of line, in
    // src/smoothing.cpp: made once per h, never in a hot loop.
    Smoothing(double h, int dim);

    // Smoothing(h, dim), bit for bit, kept from this thread's last call for
    // this dim where h is the same (its bits): the checked scalar forms
    // (W::value(r, h), k(q, r, h)) take h per call, and making a Smoothing
    // costs ~4 evaluations (35-55 against ~10 ns on Zen 4). Valid until this
    // thread's next call for the same dim.
    static const Smoothing& reused(double h, int dim);
    // The same for a call that needs only quantity q, or only these
    // quantities (the checked scalar and vector forms): where h is new,
    // only their scales are made (and log h for the 2D potential), their
    // bits those of Smoothing(h, dim); the other scales are NaN until a call
    // needs them. The same h accepted and refused; a q that is no quantity
    // (the caller names it) as reused(h, dim).
    static const Smoothing& reused(double h, int dim, QuantityId q);
    static const Smoothing& reused(double h, int dim, std::initializer_list<QuantityId> quantities) {
        return reused_for(h, dim, bits_of(quantities));  // inline: the set's bits folded where it is a constant
    }

    double h() const { return h_; }
    double inverse() const { return inv_h_; }
    int dim() const { return dim_; }
    double scale(QuantityId q) const { return scale_[static_cast<int>(q)]; }
    double scale_lo(QuantityId q) const { return scale_lo_[static_cast<int>(q)]; }  // h^p - scale(q)
    double log_h() const { return dim_ == 2 ? log_h_ : std::log(h_); }  // kept for the 2D potential only
    // h = m 2^e with m in [1/2, 1): m, 2^-e (exact) and 1/m as a double-double
    // (hi + lo). Precision::accurate takes a whole Wendland-like quantity's
    // edge factor (1 - q)^P as (m - r 2^-e)^P m^-P, whose base is exact in
    // three operations (detail::unit_distance), where (h - r)/h needs seven.
    double significand() const { return significand_; }
    double binary_unit() const { return binary_unit_; }
    double inverse_significand() const { return inverse_significand_; }
    double inverse_significand_lo() const { return inverse_significand_lo_; }

    Smoothing(double h, int dim, unsigned needed, Some);  // for std::optional::emplace in kept

private:
    // The quantities as bits (a q that is no quantity: all of them, for the
    // caller's check to name q).
    static constexpr unsigned bits_of(std::initializer_list<QuantityId> quantities) {
        unsigned bits = 0;
        for (const QuantityId q : quantities) {
            const auto b = static_cast<unsigned>(q);
            bits |= b < static_cast<unsigned>(table::quantity_count) ? 1u << b : detail::every_quantity;
        }
        return bits;
    }
    static const Smoothing& reused_for(double h, int dim, unsigned needed);
    static Smoothing& kept(double h, int dim, unsigned needed);
    void make(unsigned needed);

    double h_;
    int dim_;
    double inv_h_ = 0;
    double log_h_ = 0;
    double significand_ = 0, binary_unit_ = 0, inverse_significand_ = 0, inverse_significand_lo_ = 0;
    void make_significand();
    std::array<double, table::quantity_count> scale_{}, scale_lo_{};
    unsigned made_ = 0;  // the quantities whose scale is made, a bit each
};

namespace detail {

// The needed quantities' h^p (a bit each, 1 << QuantityId; Smoothing::scale,
// scale_lo) in D = dim, by the CPU's fused multiply-add where it has one and
// use_fma, else by Dekker's exact products: the same bits either way
// (Smoothing.ScalesTheSameWithoutFma). Refuses an h^p beyond scale_range.
// inverse is 1/h (Smoothing::inverse(), divided once).
void smoothing_scales(double h, double inverse, int dim, unsigned needed, bool use_fma, std::array<double, table::quantity_count>& scale,
                      std::array<double, table::quantity_count>& scale_lo);

// A radius must be a finite r >= 0: a NaN would otherwise fail every
// comparison and come out as an exterior 0.
inline void check_radius(double r) {
    if (!(r >= 0) || !std::isfinite(r)) fail_radius(r);
}

inline void check_coordinate(double x, int component) {
    if (!std::isfinite(x)) fail_coordinate(x, component);
}

}  // namespace detail
}  // namespace mollify
