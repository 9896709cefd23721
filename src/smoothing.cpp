// Smoothing's constructor, out of line: it runs once per h, and its checks'
// messages need <string> (include/mollify/detail/failures.hpp).
#include <mollify/detail/double_double.hpp>
#include <mollify/smoothing.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>

namespace mollify {

namespace {

using detail::DoubleDouble;

// The exact error of a product: by a fused multiply-add where the CPU has
// one, else by Dekker's split (detail::two_product of the generic build this
// file is compiled for: ~17 operations, two thirds of a Smoothing's time).
// Both are the exact a b - p, so the same bits (Smoothing.ScalesTheSameWithoutFma).
template <bool Fma>
[[gnu::always_inline]] inline DoubleDouble exact_product(double a, double b) {
    if constexpr (Fma) {
        const double p = a * b;
        return {p, __builtin_fma(a, b, -p)};
    } else {
        return detail::two_product(a, b);
    }
}

// detail::DoubleDouble's product and reciprocal as the generic build forms
// them (each multiply-add two roundings: this file is compiled with
// -ffp-contract=off, CMakeLists.txt), their exact products by
// exact_product<Fma>.
template <bool Fma>
[[gnu::always_inline]] inline DoubleDouble times(const DoubleDouble& a, const DoubleDouble& b) {
    const DoubleDouble p = exact_product<Fma>(a.hi, b.hi);
    return {p.hi, a.hi * b.lo + (a.lo * b.hi + p.lo)};
}
template <bool Fma>
[[gnu::always_inline]] inline DoubleDouble reciprocal_of(double x, double y) {  // y = 1/x, the Smoothing's inverse()
    const DoubleDouble yx = exact_product<Fma>(y, x);
    return {y, ((1 - yx.hi) - yx.lo) * y};  // detail::reciprocal of {x, 0}
}

// The powers every quantity needs: h^-7 (the 3D Hessian part) .. h^1 (the
// 1D potential).
constexpr int lowest_power = -7, highest_power = 1;
static_assert([] {
    for (int dim = 1; dim <= 3; ++dim)
        for (int q = 0; q < table::quantity_count; ++q) {
            const int n = detail::scale_power(static_cast<QuantityId>(q), dim);
            if (n < lowest_power || n > highest_power) return false;
        }
    return true;
}());

using Scales = std::array<double, table::quantity_count>;

using detail::every_quantity;

// Quantity q's h^p into scale[q], scale_lo[q], or refused.
[[gnu::always_inline]] inline void store_scale(double h, int dim, int q, int n, const DoubleDouble& x, Scales& scale,
                                               Scales& scale_lo) {
    // Within 2^+-900 (smoothing.hpp: scale_range) or refused: the
    // accurate precision's last product is by h^p + its low part, or by
    // a term's content (2^-11 .. 2^9 in the catalogue, within 2^+-60 in
    // any table) times them, and both must stay normal doubles: beyond,
    // h^p's low part (2^-53 h^p) loses bits to underflow, or content
    // h^p overflows, and the results are wrong by an ulp or +-inf.
    const DoubleDouble p = detail::fast_two_sum(x.hi, x.lo);
    if (!(p.hi >= 1 / scale_range && p.hi <= scale_range)) detail::fail_smoothing_range(h, dim, n, q);
    scale[static_cast<std::size_t>(q)] = p.hi;
    scale_lo[static_cast<std::size_t>(q)] = p.lo;
}

// x^0 .. x^(N-1) in double-double by repeated products: h^n (|n| <= 7)
// from h or from its double-double reciprocal, ~|n| 2^-104 relative error,
// so the rounded sum is h^n correctly rounded but for values that close to
// a rounding boundary, and the low part is the rounding error
// Precision::accurate carries. Once for all quantities: one reciprocal and
// eight products (3D: ten reciprocals and forty products when each quantity
// made its own power; the same products in the same order, so the same
// bits, at ~2.5x less time a Smoothing, which the checked scalar forms make
// per call). std::pow(long double, int) went through powl and cost a fifth
// of a batch of the accuracy suite, whose points each have their own h (as
// an SPH code's particles do).
template <bool Fma, std::size_t N>
[[gnu::always_inline]] inline std::array<DoubleDouble, N> powers(const DoubleDouble& x) {
    std::array<DoubleDouble, N> p;
    p[0] = {1.0, 0.0};
    for (std::size_t k = 1; k < N; ++k) p[k] = times<Fma>(p[k - 1], x);
    return p;
}

// The needed quantities' h^p (a bit each): every quantity's from the whole
// table of powers (unrolled), some quantities' from powers only as deep as
// theirs go (W alone in 3D: a reciprocal and three products), by the same
// products in the same order, so a power's bits are the same whichever
// others are needed.
template <bool Fma>
[[gnu::always_inline]] inline void make_scales(double h, double inverse, int dim, unsigned needed, Scales& scale, Scales& scale_lo) {
    if (needed == every_quantity) {
        const auto down = powers<Fma, 1 - lowest_power>(reciprocal_of<Fma>(h, inverse));
        const auto up = powers<Fma, 1 + highest_power>({h, 0.0});
        for (int q = 0; q < table::quantity_count; ++q) {
            const int n = detail::scale_power(static_cast<QuantityId>(q), dim);
            store_scale(h, dim, q, n, n < 0 ? down[static_cast<std::size_t>(-n)] : up[static_cast<std::size_t>(n)], scale,
                        scale_lo);
        }
        return;
    }
    int deepest_down = 0, deepest_up = 0;
    for (unsigned rest = needed; rest != 0; rest &= rest - 1) {
        const int n = detail::scale_power(static_cast<QuantityId>(std::countr_zero(rest)), dim);
        deepest_down = std::max(deepest_down, -n);
        deepest_up = std::max(deepest_up, n);
    }
    std::array<DoubleDouble, 1 - lowest_power> down;
    std::array<DoubleDouble, 1 + highest_power> up;
    down[0] = up[0] = {1.0, 0.0};
    if (deepest_down > 0) {
        const DoubleDouble reciprocal = reciprocal_of<Fma>(h, inverse);
        for (int k = 1; k <= deepest_down; ++k)
            down[static_cast<std::size_t>(k)] = times<Fma>(down[static_cast<std::size_t>(k - 1)], reciprocal);
    }
    for (int k = 1; k <= deepest_up; ++k) up[static_cast<std::size_t>(k)] = times<Fma>(up[static_cast<std::size_t>(k - 1)], {h, 0.0});
    for (unsigned rest = needed; rest != 0; rest &= rest - 1) {
        const int q = std::countr_zero(rest), n = detail::scale_power(static_cast<QuantityId>(q), dim);
        store_scale(h, dim, q, n, n < 0 ? down[static_cast<std::size_t>(-n)] : up[static_cast<std::size_t>(n)], scale,
                    scale_lo);
    }
}

#if defined(__x86_64__) && !defined(__FMA__)
[[gnu::target("fma")]] void make_scales_fma(double h, double inverse, int dim, unsigned needed, Scales& scale, Scales& scale_lo) {
    make_scales<true>(h, inverse, dim, needed, scale, scale_lo);
}
void make_scales_split(double h, double inverse, int dim, unsigned needed, Scales& scale, Scales& scale_lo) {
    make_scales<false>(h, inverse, dim, needed, scale, scale_lo);
}
#endif

// Whether every h^p of every quantity in every D lies well within
// scale_range: |log2 h| <= 120 gives |log2 h^p| <= 7 * 121 < 900 for the
// powers -7 .. 1 (lowest_power, highest_power). There one quantity's scale
// is made without the others' checks, which all pass.
// (The exponent from h's bits: a subnormal, infinite or NaN h is outside.)
bool every_scale_within_range(double h) {
    const int e = static_cast<int>((std::bit_cast<std::uint64_t>(h) >> 52) & 0x7ff) - 1023;
    return e >= -120 && e <= 120;
}
static_assert(-lowest_power * 121 < 900 && highest_power * 121 < 900);

}  // namespace

namespace detail {
void smoothing_scales(double h, double inverse, int dim, unsigned needed, bool use_fma, std::array<double, table::quantity_count>& scale,
                      std::array<double, table::quantity_count>& scale_lo) {
    needed &= every_quantity;
#if defined(__x86_64__) && !defined(__FMA__)
    if (use_fma && __builtin_cpu_supports("fma"))
        make_scales_fma(h, inverse, dim, needed, scale, scale_lo);
    else
        make_scales_split(h, inverse, dim, needed, scale, scale_lo);
#else
    (void)use_fma;
    make_scales<MOLLIFY_HAS_FMA != 0>(h, inverse, dim, needed, scale, scale_lo);
#endif
}
}  // namespace detail

Smoothing::Smoothing(double h, int dim) : h_(h), dim_(dim) {
    if (dim < 1 || dim > 3) detail::fail_dimension(dim);
    if (!(h > 0) || !std::isfinite(h)) detail::fail_smoothing_length(h);
    inv_h_ = 1 / h;
    make(every_quantity);  // checks h's range first
    make_significand();
}

Smoothing::Smoothing(double h, int dim, unsigned needed, Some) : h_(h), dim_(dim), inv_h_(1 / h) {
    scale_.fill(std::numeric_limits<double>::quiet_NaN());
    scale_lo_.fill(std::numeric_limits<double>::quiet_NaN());
    log_h_ = std::numeric_limits<double>::quiet_NaN();
    make(needed);
    make_significand();
}

// h = m 2^e, m in [1/2, 1) (h is normal: every_scale_within_range, or its
// scales' check).
void Smoothing::make_significand() {
    int e = 0;
    significand_ = std::frexp(h_, &e);
    binary_unit_ = std::ldexp(1.0, -e);
    const double y = 1 / significand_;
    const DoubleDouble inverse = reciprocal_of<false>(significand_, y);  // detail::two_product: exact either way
    inverse_significand_ = inverse.hi;
    inverse_significand_lo_ = inverse.lo;
}

// The needed quantities' scales and, with the 2D potential, log h.
void Smoothing::make(unsigned needed) {
    detail::smoothing_scales(h_, inv_h_, dim_, needed, true, scale_, scale_lo_);
    made_ |= needed;
    // The 2D potential's; log_h() forms it for the others.
    if (dim_ == 2 && (needed >> static_cast<int>(QuantityId::potential) & 1u)) log_h_ = std::log(h_);
}

namespace {
// This thread's Smoothings, one per dimension, so that kernels of several D
// in one loop each keep theirs.
thread_local std::array<std::optional<Smoothing>, 3> kept_smoothings;
}  // namespace

// This thread's Smoothing for h in D = dim with the needed quantities'
// scales made; a new h's made afresh, checked as Smoothing(h, dim) checks
// it: some quantities' alone only where every quantity's passes.
Smoothing& Smoothing::kept(double h, int dim, unsigned needed) {
    if (dim < 1 || dim > 3) detail::fail_dimension(dim);
    std::optional<Smoothing>& kept = kept_smoothings[static_cast<std::size_t>(dim - 1)];
    // emplace destroys the old one first: a refused h throws and leaves nothing kept.
    if (!kept || std::bit_cast<std::uint64_t>(kept->h_) != std::bit_cast<std::uint64_t>(h)) {
        if (needed != every_quantity && h > 0 && every_scale_within_range(h))
            kept.emplace(h, dim, needed, Some{});
        else
            kept.emplace(h, dim);
    } else if ((kept->made_ & needed) != needed) {
        kept->make(needed & ~kept->made_);  // within range: the same h made a Smoothing before
    }
    return *kept;
}

// The kept Smoothing where it is for h and has what is needed, first
// (a call with the same h as the last: ~4 ns), else kept().
const Smoothing& Smoothing::reused_for(double h, int dim, unsigned needed) {
    const auto d = static_cast<unsigned>(dim - 1);
    if (d < 3) {
        const std::optional<Smoothing>& k = kept_smoothings[d];
        if (k && std::bit_cast<std::uint64_t>(k->h_) == std::bit_cast<std::uint64_t>(h) && (k->made_ & needed) == needed)
            return *k;
    }
    return kept(h, dim, needed);
}

const Smoothing& Smoothing::reused(double h, int dim) { return reused_for(h, dim, every_quantity); }

const Smoothing& Smoothing::reused(double h, int dim, QuantityId q) { return reused_for(h, dim, bits_of({q})); }

}  // namespace mollify
