// The compile-time form of a kernel: the emitted table is a template
// argument, so evaluation is straight-line code with every coefficient a
// constant (fully inlinable; batch loops vectorise).
//
//   using W = mollify::StaticKernel<mollify::tables::wendland_k_2_D3>;
//   const mollify::Smoothing s(h, W::dimension);  // checks h once
//   double w = W::radial<mollify::QuantityId::value>(r, s);
//   auto [w, grad] = W::pair({dx, dy, dz}, s);  // W_h and grad W_h at x_i - x_j
//
// Conventions: W_h(x) = h^-D W(|x|/h) with support |x| <= h; every radial
// quantity f_h(r) = h^p f(r/h) (p from detail::scale_power); the potential
// phi_h solves Delta phi_h = W_h and equals the Green's function outside
// the support (2D: phi(r/h) + log(h)/(2 pi) inside). Outside the support W
// and its derivatives are exactly 0.
#pragma once

#include <mollify/detail/evaluate.hpp>
#include <mollify/detail/lanes.hpp>
#include <mollify/detail/near_origin.hpp>
#include <mollify/detail/roots_ahead.hpp>
#include <mollify/precision.hpp>
#include <mollify/smoothing.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string_view>
#include <type_traits>
#include <utility>

namespace mollify {

template <int D>
using Vector = std::array<double, D>;

template <int D>
using Matrix = std::array<std::array<double, D>, D>;

// W_h and grad W_h at one displacement, as an SPH pair loop needs them.
template <int D>
struct Pair {
    double value;
    Vector<D> gradient;
};

// D spans of equal length: the components of n points (structure of arrays).
template <int D>
using Points = std::array<std::span<const double>, D>;
template <int D>
using PointsOut = std::array<std::span<double>, D>;

namespace detail {
inline namespace MOLLIFY_ISA {

// e = (h - r)/h to within about half an ulp: where the target fuses
// multiply-add, one correction step with the exact residual (h - r) - e h
// replaces the division; otherwise the division is correctly rounded.
MOLLIFY_INLINE double edge_distance(double h_minus_r, const Smoothing& s) {
#if defined(__FMA__) || defined(__FP_FAST_FMA)
    const double e = h_minus_r * s.inverse();
    return mul_add(std::fma(-e, s.h(), h_minus_r), s.inverse(), e);
#else
    return h_minus_r / s.h();
#endif
}

inline void check_sizes(std::size_t in, std::size_t out, const char* what) {
    if (in != out) fail_sizes(in, out, what);
}

template <int D>
inline std::size_t check_points(const Points<D>& x) {
    for (int c = 1; c < D; ++c) check_sizes(x[0].size(), x[c].size(), "point components");
    return x[0].size();
}

// Tests on the bits (integer compares vectorise; a floating-point reduction
// would not), or-ed over a batch: is a value NaN or infinite (exponent all
// ones), or, for radii, negative (sign bit set, not -0)? Only when some
// value is flagged is the bad one looked for, to name it.
inline constexpr std::uint64_t exponent_bits = 0x7ff0000000000000;
inline constexpr std::uint64_t sign_bit = 0x8000000000000000;

MOLLIFY_INLINE std::uint64_t not_finite(double x) {
    return static_cast<std::uint64_t>((std::bit_cast<std::uint64_t>(x) & exponent_bits) == exponent_bits);
}

MOLLIFY_INLINE std::uint64_t not_a_radius(double r) {
    return not_finite(r) | static_cast<std::uint64_t>(std::bit_cast<std::uint64_t>(r) > sign_bit);
}

inline void check_radii(std::span<const double> r) {
    std::uint64_t bad = 0;
    for (const double x : r) bad |= not_a_radius(x);
    if (bad)
        for (const double x : r) check_radius(x);
}

inline void check_coordinates(std::span<const double> x, int component) {
    std::uint64_t bad = 0;
    for (const double v : x) bad |= not_finite(v);
    if (bad)
        for (const double v : x) check_coordinate(v, component);
}

// The batch loops' input check, kept out of their bodies: each block of
// roots as it is taken (for_each_block_of_roots, the pair loops) or each
// register of radii before its body (for_each_register_at_levels, the batch
// evaluation by levels). Tested in the body, the flag was reduced across the
// register after every register of a combination's levels, 13 of the 106
// instructions of its outermost term's body (stop 71: combo:m=3,base=
// wendland:k=2's accurate W + grad W per 4096 points 15.8 -> 15.3 us, its
// fast 7.3 -> 7.0; its W by levels 9.9-10.0 -> 9.0 us). Per lane the
// largest exponent field seen (VPMAXSQ with AVX-512; the fields are below
// 2^63, so signed): an r not finite (an input inf or NaN, or its square
// overflowed); for Radii also the least of the bits less 1, wrapping (a
// negative r but -0 gives at most -2, -0 the largest number): not_a_radius.
// Reduced once, by any(). Integer operations: -ffast-math does not fold
// them. Fewer than a whole count, and without lanes of four or more, the
// scalar tests.
template <bool Radii>
class BadInputLanes {
public:
    MOLLIFY_INLINE void operator()(const double* __restrict r, std::size_t count) {
        for (std::size_t j = 0; j < count; ++j) flagged_ |= Radii ? not_a_radius(r[j]) : not_finite(r[j]);
    }
    template <std::size_t B>
    MOLLIFY_INLINE void operator()(const double* __restrict r, std::integral_constant<std::size_t, B> count) {
#if defined(MOLLIFY_LANES)
        if constexpr (register_doubles >= 4 && B % register_doubles == 0) {
            for (std::size_t k = 0; k < B; k += register_doubles) {
                const Bits b = std::bit_cast<Bits>(load_lanes(r + k));
                const Fields f = std::bit_cast<Fields>(b & exponent_bits);
                largest_ = largest_ > f ? largest_ : f;
                if constexpr (Radii) {
                    const Fields less = std::bit_cast<Fields>(b - 1);
                    least_ = least_ < less ? least_ : less;
                }
            }
            return;
        }
#endif
        (*this)(r, std::size_t{count});
    }
    bool any() const {
        std::uint64_t flagged = flagged_;
#if defined(MOLLIFY_LANES)
        for (int l = 0; l < register_doubles; ++l)
            flagged |= static_cast<std::uint64_t>((largest_[l] == static_cast<std::int64_t>(exponent_bits)) |
                                                  (Radii && least_[l] < -1));
#endif
        return flagged != 0;
    }

private:
#if defined(MOLLIFY_LANES)
    typedef std::uint64_t Bits __attribute__((vector_size(register_doubles * sizeof(double))));
    typedef std::int64_t Fields __attribute__((vector_size(register_doubles * sizeof(double))));
    Fields largest_{}, least_ = Fields{} + std::numeric_limits<std::int64_t>::max();
#endif
    std::uint64_t flagged_ = 0;
};
using NonFiniteRoots = BadInputLanes<false>;
using NotRadii = BadInputLanes<true>;

// W and grad W = (W'/r) x at n displacements x in 3D, from wg(r, level) =
// {W, W'/r} (inlined: MOLLIFY_INLINE_LAMBDA), the level (a std::
// integral_constant below Levels) chosen per block by level(roots, count):
// the 3D pair loop of both forms, the roots a block ahead
// (for_each_root_ahead_at_levels). Restrict pointers: the outputs alias
// nothing read, which the vectoriser must know. Checked: whether some r is
// not finite (NonFiniteRoots).
template <bool Checked, int Levels, class WG, class Level>
MOLLIFY_INLINE bool pairs_at_radii_at_levels(std::size_t n, const double* __restrict x0, const double* __restrict x1,
                                             const double* __restrict x2, double* __restrict w, double* __restrict g0,
                                             double* __restrict g1, double* __restrict g2, WG wg, Level level) {
    std::conditional_t<Checked, NonFiniteRoots, NoRootCheck> check;
    for_each_root_ahead_at_levels<Levels>(
        n, [x0, x1, x2](std::size_t i) MOLLIFY_INLINE_LAMBDA { return radius(x0[i], x1[i], x2[i]); }, level,
        [x0, x1, x2, w, g0, g1, g2, &wg](std::size_t i, double r, auto at) MOLLIFY_INLINE_LAMBDA {
            const auto [wi, gi] = wg(r, at);
            w[i] = wi;
            g0[i] = gi * x0[i];
            g1[i] = gi * x1[i];
            g2[i] = gi * x2[i];
        },
        check, w, g0, g1, g2);
    if constexpr (Checked) return check.any();
    else return false;
}

// One level: wg(r) alone.
template <bool Checked, class WG>
MOLLIFY_INLINE bool pairs_at_radii(std::size_t n, const double* __restrict x0, const double* __restrict x1,
                                   const double* __restrict x2, double* __restrict w, double* __restrict g0,
                                   double* __restrict g1, double* __restrict g2, WG wg) {
    return pairs_at_radii_at_levels<Checked, 1>(
        n, x0, x1, x2, w, g0, g1, g2, [&wg](double r, auto) MOLLIFY_INLINE_LAMBDA { return wg(r); },
        [](const double*, std::size_t) MOLLIFY_INLINE_LAMBDA { return 0; });
}

}  // namespace MOLLIFY_ISA
}  // namespace detail

MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN
inline namespace MOLLIFY_ISA {

template <const table::Kernel& K, Precision Pr = Precision::accurate>
class StaticKernel {
    static_assert(K.support == 1.0, "tables are emitted with support 1; h scales them");
    static_assert(K.dim >= 1 && K.dim <= 3);
#if defined(__FAST_MATH__)
    // -ffast-math lets the compiler reassociate: two_sum's error term and
    // the split's (q + C) - C fold away, and the "accurate" values would be
    // silently a few ulp off.
    static_assert(Pr != Precision::accurate,
                  "mollify: Precision::accurate needs IEEE arithmetic, and this unit is compiled with -ffast-math "
                  "(__FAST_MATH__): compile it without, or use Precision::fast");
#endif

public:
    static constexpr int dimension = K.dim;
    static constexpr bool odd = K.parity < 0;  // Belley's first-derivative kernel in 1D
    static constexpr Precision precision = Pr;

    // The member API both kernel forms share (mollify::RadialKernel,
    // kernel_concept.hpp): static here, callable on an object as on the type.
    static constexpr int dim() { return K.dim; }
    static constexpr std::string_view spec() { return K.spec; }
    static constexpr const table::Kernel& table() { return K; }
    static constexpr bool has_potential() { return K.has_potential; }
    static Smoothing smoothing(double h) { return Smoothing(h, dimension); }

    // f_h(r) for a radius r >= 0, unchecked (the hot path): r finite >= 0 and s made for this dimension.
    // A quantity singular at 0 takes its leading order there below r/h = 2^-150
    // (detail/near_origin.hpp): one branch, in its loops only.
    template <QuantityId Q>
    MOLLIFY_INLINE static double radial(double r, const Smoothing& s) {
        if constexpr (mends<Q>)
            if (detail::near_origin(r, s.h())) [[unlikely]]
                return at_origin<Q>(r, s);
        return radial_unmended<Q>(r, s);
    }

private:
    // radial without the branch: the batch loops flag the radii near the
    // origin as they go (branch-free, so they vectorise) and mend those
    // after (mend_near_origin).
    template <QuantityId Q>
    MOLLIFY_INLINE static double radial_unmended(double r, const Smoothing& s) {
        constexpr int q = static_cast<int>(Q);
        if constexpr (K.quantities[q].npieces == 0) detail::fail_missing_quantity(K.spec, q, dimension);
        else return emitted<Q>(r, s);
    }

    template <QuantityId Q>
    static constexpr bool mends = [] {
        if constexpr (K.quantities[static_cast<int>(Q)].npieces == 0) return false;
        else return detail::singular_at_origin<K, static_cast<int>(Q)>;
    }();

    template <QuantityId Q>
    static detail::origin::Leading leading() {
        return detail::origin::leading(detail::piece_table<K, static_cast<int>(Q), 0>);
    }

    template <QuantityId Q>
    static double at_origin(double r, const Smoothing& s, const detail::origin::Leading& f = leading<Q>()) {
        constexpr int q = static_cast<int>(Q);
        const double in = detail::near_origin_value(f, r, s.h(), s.scale(Q), s.scale_lo(Q), K.spec, quantity_names[q]);
        if constexpr (Q == QuantityId::potential && dimension == 2) return detail::mul_add(detail::log_coefficient<K, q>, s.log_h(), in);
        else return in;
    }

    // The radii of a batch near the origin, after its loop flagged some.
    template <QuantityId Q>
    static void mend_near_origin(const double* in, double* out, std::size_t n, const Smoothing& s) {
        const detail::origin::Leading f = leading<Q>();
        for (std::size_t i = 0; i < n; ++i)
            if (detail::near_origin(in[i], s.h())) out[i] = at_origin<Q>(in[i], s, f);
    }

    // Level: the pair loop's level of r's register (detail::levels; W and
    // W'/r only): the first Level terms of a combination, which no point of
    // the register reaches, are left out.
    template <QuantityId Q, int Level = 0>
    MOLLIFY_INLINE static double emitted(double r, const Smoothing& s) {
        constexpr int q = static_cast<int>(Q);
        detail::Scaled a = scaled(r, s);
        double in;
        if constexpr (Pr == Precision::accurate) {
            a.scale = {s.scale(Q), s.scale_lo(Q)};
            if constexpr (constexpr int unit = detail::unit_edge_power(K.quantities[q]); unit > 0) {
                a.eu = detail::unit_distance(r, s.binary_unit(), s.significand());
                a.scale = detail::unit_edge_scale<unit>(a.scale, {s.inverse_significand(), s.inverse_significand_lo()});
            }
            in = detail::inside<K, q, Pr, detail::inner_pieces<K, q> - 1, Level>(a);
        } else {
            in = detail::inside<K, q, Pr>(a) * s.scale(Q);
        }
        if constexpr (Q == QuantityId::potential && dimension == 2) in = detail::mul_add(detail::log_coefficient<K, q>, s.log_h(), in);
        // A quantity singular at 0 is its limit where its terms give NaN
        // (inf - inf, 0 * inf: at q = 0 and where q^low overflows).
        if constexpr (detail::singular_at_origin<K, q>) in = detail::select(std::isnan(in), detail::limit_at_origin_of<K, q>, in);
        if constexpr (detail::zero_outside<K, q>) {
            return detail::select(r <= s.h(), in, 0.0);
        } else if constexpr (detail::log_coefficient<K, q> == 0) {
            // Both sides, then a select: a branch here kept every batch of a
            // potential quantity from vectorising (mollifier:M=4 3D,
            // Precision::fast: 8 ns per value). The 2D exterior's log(r)
            // would not vectorise and costs more than the branch.
            return detail::select(r <= s.h(), in, detail::outside<K, q>(r));
        } else {
            return r <= s.h() ? in : detail::outside<K, q>(r);
        }
    }

    MOLLIFY_INLINE static detail::Scaled scaled(double r, const Smoothing& s) {
        if constexpr (Pr == Precision::accurate) return detail::scaled_accurate(r, s.h(), s.inverse());
        else return {r * s.inverse(), detail::edge_distance(s.h() - r, s), r, s.h(), s.inverse()};
    }

public:
    // Checked scalar forms (for a new h only Q's scale made: Smoothing::reused(h, D, Q)).
    template <QuantityId Q>
    static double radial(double r, double h) {
        require_potential<Q>();
        detail::check_radius(r);
        return radial<Q>(r, Smoothing::reused(h, dimension, Q));
    }
    static double value(double r, double h) { return radial<QuantityId::value>(r, h); }
    static double dr(double r, double h) { return radial<QuantityId::dr>(r, h); }
    static double laplacian(double r, double h) { return radial<QuantityId::laplacian>(r, h); }
    static double potential(double r, double h) { return radial<QuantityId::potential>(r, h); }

    // Vector forms at a displacement x (unchecked with a Smoothing, checked with h).
    MOLLIFY_INLINE static double value(const Vector<dimension>& x, const Smoothing& s) {
        const double w = radial<QuantityId::value>(norm(x), s);
        if constexpr (odd) return x[0] < 0 ? -w : w;
        return w;
    }

    // grad W_h = (W_h'/r) x, from the emitted W'/r: finite at r = 0, where
    // W'(r)/r -> W''(0), never 0 * inf.
    MOLLIFY_INLINE static Vector<dimension> gradient(const Vector<dimension>& x, const Smoothing& s) {
        return gradient_at(x, norm(x), s);
    }

    MOLLIFY_INLINE static Pair<dimension> pair(const Vector<dimension>& x, const Smoothing& s) {
        const double r = norm(x);
        double w = radial<QuantityId::value>(r, s);
        if constexpr (odd) w = x[0] < 0 ? -w : w;
        return {w, gradient_at(x, r, s)};
    }

    // Hessian = (W'/r) I + ((W'' - W'/r)/r^2) x x^T, both parts emitted exactly.
    static Matrix<dimension> hessian(const Vector<dimension>& x, const Smoothing& s) {
        return hessian_of<QuantityId::grad_over_r, QuantityId::hess_radial, QuantityId::d2r>(x, s);
    }

    MOLLIFY_INLINE static double laplacian(const Vector<dimension>& x, const Smoothing& s) {
        const double l = radial<QuantityId::laplacian>(norm(x), s);
        if constexpr (odd) return x[0] < 0 ? -l : l;
        return l;
    }

    MOLLIFY_INLINE static double potential(const Vector<dimension>& x, const Smoothing& s) {
        require_potential<QuantityId::potential>();
        return radial<QuantityId::potential>(norm(x), s);
    }

    // grad phi_h = (phi_h'/r) x; the field of a unit charge is its negative.
    MOLLIFY_INLINE static Vector<dimension> potential_gradient(const Vector<dimension>& x, const Smoothing& s) {
        require_potential<QuantityId::dpotential_over_r>();
        return times(radial<QuantityId::dpotential_over_r>(norm(x), s), x);
    }

    static Matrix<dimension> potential_hessian(const Vector<dimension>& x, const Smoothing& s) {
        require_potential<QuantityId::dpotential_over_r>();
        return hessian_of<QuantityId::dpotential_over_r, QuantityId::potential_hess_radial, QuantityId::potential_hess_radial>(x, s);
    }

    // Checked vector forms (for a new h only the scales of the quantities
    // each reads: a scale it reads and did not name is NaN, and fails the
    // vector forms' tests).
    static double value(const Vector<dimension>& x, double h) {
        return value(checked(x), Smoothing::reused(h, dimension, QuantityId::value));
    }
    static Vector<dimension> gradient(const Vector<dimension>& x, double h) {
        return gradient(checked(x), Smoothing::reused(h, dimension, {QuantityId::grad_over_r, QuantityId::dr}));
    }
    static Pair<dimension> pair(const Vector<dimension>& x, double h) {
        return pair(checked(x), Smoothing::reused(h, dimension, {QuantityId::value, QuantityId::grad_over_r, QuantityId::dr}));
    }
    static Matrix<dimension> hessian(const Vector<dimension>& x, double h) {
        return hessian(checked(x), Smoothing::reused(h, dimension, {QuantityId::grad_over_r, QuantityId::hess_radial, QuantityId::d2r}));
    }
    static double potential(const Vector<dimension>& x, double h) {
        return potential(checked(x), Smoothing::reused(h, dimension, QuantityId::potential));
    }
    static Vector<dimension> potential_gradient(const Vector<dimension>& x, double h) {
        return potential_gradient(checked(x), Smoothing::reused(h, dimension, QuantityId::dpotential_over_r));
    }

    // Batch forms over contiguous arrays, checked in the pass that
    // evaluates: each input's bits tested as it is read (a separate pass
    // read the inputs twice, from memory at 10^6 points), the bad input
    // named only after the pass where one was flagged; the outputs are then
    // unspecified, as the Error says.
    template <QuantityId Q>
    static void evaluate(std::span<const double> r, const Smoothing& s, std::span<double> out) {
        require_potential<Q>();
        require_dim(s);
        detail::check_sizes(r.size(), out.size(), "evaluate");
        if (evaluate_loop<Q, true>(r.data(), out.data(), r.size(), s)) detail::check_radii(r);
    }

    // The quantity chosen at run time (the shared API): one branch per
    // batch, then the loop of evaluate<Q>.
    static void evaluate(QuantityId q, std::span<const double> r, const Smoothing& s, std::span<double> out) {
        evaluate_indexed<0>(q, r, s, out);
    }

    // f_h at one radius, checked, as mollify::Kernel's operator().
    double operator()(QuantityId q, double r, double h) const {
        double out = 0;
        evaluate(q, std::span<const double>(&r, 1), Smoothing::reused(h, dimension, q), std::span<double>(&out, 1));
        return out;
    }

    // The batch loop without checks, for callers that checked their radii.
    template <QuantityId Q>
    static void evaluate_unchecked(const double* __restrict in, double* __restrict out, std::size_t n,
                                   const Smoothing& smoothing) {
        evaluate_loop<Q, false>(in, out, n, smoothing);
    }

    // W_h and grad W_h at n displacements x_i - x_j (structure of arrays).
    static void pairs(const Points<dimension>& x, const Smoothing& s, std::span<double> w, const PointsOut<dimension>& grad) {
        require_dim(s);
        const std::size_t n = detail::check_points<dimension>(x);
        detail::check_sizes(n, w.size(), "pairs (values)");
        for (int c = 0; c < dimension; ++c) detail::check_sizes(n, grad[c].size(), "pairs (gradient)");
        // A NaN or infinite coordinate makes r = |x| NaN or infinite (a sum
        // of squares: no inf - inf), so the loop tests r; where some r was
        // flagged the coordinates are checked, to name the bad one (huge
        // finite ones overflow r too, and are fine: W = 0 beyond h).
        if (pair_loop<true>(x, s, w.data(), grad, n))
            for (int c = 0; c < dimension; ++c) detail::check_coordinates(x[c], c);
    }

    // The shared API's form: x and grad hold dim() spans.
    static void pairs(std::span<const std::span<const double>> x, const Smoothing& s, std::span<double> w,
                      std::span<const std::span<double>> grad) {
        detail::check_sizes(x.size(), static_cast<std::size_t>(dimension), "pairs (components of x)");
        detail::check_sizes(grad.size(), static_cast<std::size_t>(dimension), "pairs (components of grad)");
        Points<dimension> xs;
        PointsOut<dimension> gs;
        for (int c = 0; c < dimension; ++c) {
            xs[c] = x[c];
            gs[c] = grad[c];
        }
        pairs(xs, s, w, gs);
    }

    static void require_dim(const Smoothing& s) {
        if (s.dim() != dimension) detail::fail_smoothing_dimension(s.dim(), K.spec, dimension);
    }

private:
    template <int I>
    static void evaluate_indexed(QuantityId q, std::span<const double> r, const Smoothing& s, std::span<double> out) {
        if constexpr (I == table::quantity_count) {
            detail::fail_quantity(static_cast<int>(q));
        } else if (static_cast<int>(q) == I) {
            evaluate<static_cast<QuantityId>(I)>(r, s, out);
        } else {
            evaluate_indexed<I + 1>(q, r, s, out);
        }
    }

    template <QuantityId Q>
    static void require_potential() {
        constexpr bool needs = static_cast<int>(Q) >= static_cast<int>(QuantityId::potential);
        if constexpr (needs && !K.has_potential) detail::fail_no_potential(K.spec, dimension);
    }

    MOLLIFY_INLINE static double norm(const Vector<dimension>& x) {
        if constexpr (dimension == 1) {
            return std::abs(x[0]);
        } else {
            double s = x[0] * x[0];
            for (int c = 1; c < dimension; ++c) s = detail::mul_add(x[c], x[c], s);
            const double r = std::sqrt(s);
            if constexpr (mends<QuantityId::grad_over_r>)  // a cusp: r itself near 0
                if (r < detail::radius_underflow) [[unlikely]]
                    return unscaled_norm(x);
            return r;
        }
    }

    // |x| where its square underflows (detail::unscaled_radius; D >= 2).
    static double unscaled_norm(const Vector<dimension>& x) {
        if constexpr (dimension == 2) return detail::unscaled_radius(x[0], x[1]);
        else return detail::unscaled_radius(x[0], x[1], x[2]);
    }

    // The 1D odd kernel W(x) = sign(x) f(|x|) has W'(x) = f'(|x|): its
    // gradient is (f'/r)|x|.
    MOLLIFY_INLINE static Vector<dimension> oriented(const Vector<dimension>& x) {
        if constexpr (odd) return {std::abs(x[0])};
        return x;
    }

    // A kernel with a cusp at 0 (W'(0) != 0) has W'/r ~ W'(0)/r: its gradient
    // is W'(r) x/r, and 0 at x = 0, the symmetric value an SPH self-term needs
    // (inf * 0 there was SPlisHSPlasH's NaN).
    MOLLIFY_INLINE static Vector<dimension> gradient_at(const Vector<dimension>& x, double r, const Smoothing& s) {
        constexpr int g = static_cast<int>(QuantityId::grad_over_r);
        if constexpr (detail::singular_at_origin<K, g>) {
            if (!(r > 0)) return Vector<dimension>{};
            Vector<dimension> unit = oriented(x);
            for (double& c : unit) c /= r;
            return times(radial<QuantityId::dr>(r, s), unit);
        } else {
            return times(radial<QuantityId::grad_over_r>(r, s), oriented(x));
        }
    }

    MOLLIFY_INLINE static Vector<dimension> times(double a, const Vector<dimension>& x) {
        Vector<dimension> y;
        for (int c = 0; c < dimension; ++c) y[c] = a * x[c];
        return y;
    }

    // Hessian = (f'/r) I + rad x x^T, rad = (f'' - f'/r)/r^2 emitted exactly
    // (no cancellation where f'' ~ f'/r near 0). Where rad is singular at 0
    // (~1/r for Wendland C2, 1/r^3 for spiky) its product with x x^T is not:
    // below r/h = 2^-150 R u u^T, u = x/r, R = r^2 rad from its leading
    // order (detail::near_origin_value with r^2), at x = 0 (f'/r)(0) I (rad
    // x x^T was inf 0 = NaN there, inf below r/h ~ 1e-100). A cusp (f'/r
    // ~ f'(0)/r) takes f'' u u^T + (f'/r)(I - u u^T) on the diagonal, f''
    // from its own table: f'/r + R cancelled there to f'' (spiky's H_00 at
    // r/h = 1e-3 lost 9 bits, and everything below).
    template <QuantityId OverR, QuantityId Radial, QuantityId Second>
    static Matrix<dimension> hessian_of(const Vector<dimension>& x, const Smoothing& s) {
        Matrix<dimension> m{};
        if constexpr (dimension == 1 && Second != Radial) {
            const double d2 = radial<Second>(std::abs(x[0]), s);  // f'' itself: no r^2 (f''-f'/r)/r^2 + f'/r detour
            m[0][0] = odd && x[0] < 0 ? -d2 : d2;
            return m;
        }
        constexpr bool cusp = Second != Radial && mends<OverR>;
        double r = norm(x);
        if constexpr (mends<Radial> || cusp) {
            if (r < detail::radius_underflow) r = unscaled_norm(x);  // (norm does so only for a cusp)
            if (!(r > 0)) {  // x = 0
                const double over_r = radial<OverR>(0.0, s);
                for (int i = 0; i < dimension; ++i) m[i][i] = over_r;
                return m;
            }
        }
        const double over_r = radial<OverR>(r, s);
        // rad x_i x_j, or R u_i u_j near 0
        bool near = false;
        double big_r = 0;
        if constexpr (mends<Radial>) {
            if (r < detail::near_origin_bound * s.h()) {
                constexpr int q = static_cast<int>(Radial);
                near = true;
                big_r = detail::near_origin_value(leading<Radial>(), r, s.h(), s.scale(Radial), s.scale_lo(Radial), K.spec,
                                                  quantity_names[q], 2);
            }
        }
        double rad = near ? 0.0 : radial<Radial>(r, s);
        // rad beyond the doubles where rad x_i x_j is not (h below ~1e-30, r/h
        // above the bound: spiky's rad at h = 1e-38, r/h = 1e-20 is 1e325,
        // rad x_0 x_1 1e210): the same products of x and h scaled by 2^-e
        // (h = m 2^e: exact), rad' = 2^-ep rad finite there, the power of two
        // 2^e(p+2) put back after them.
        int e = 0;  // h's exponent where rad is taken at h 2^-e
        if constexpr (mends<Radial>) {
            if (!near && !std::isfinite(rad)) [[unlikely]] {
                const double m = std::frexp(s.h(), &e);
                rad = radial<Radial>(std::ldexp(r, -e), Smoothing(m, dimension));
            }
        }
        // (a component 0 makes its terms 0, also where the factor beside it
        // is beyond the doubles: never inf 0)
        auto outer = [&](int i, int j) {
            if (x[i] == 0 || x[j] == 0) return 0.0;
            if (near) return big_r * (x[i] / r) * (x[j] / r);
            if (e == 0) return rad * x[i] * x[j];
            return std::ldexp(rad * std::ldexp(x[i], -e) * std::ldexp(x[j], -e), e * (detail::scale_power(Radial, dimension) + 2));
        };
        for (int i = 0; i < dimension; ++i)
            for (int j = 0; j < dimension; ++j) m[i][j] = outer(i, j) + (i == j ? over_r : 0.0);
        if constexpr (cusp) {
            const double second = radial<Second>(r, s);
            for (int i = 0; i < dimension; ++i) {
                double across = 0;  // 1 - u_i^2 without the cancellation
                for (int j = 0; j < dimension; ++j)
                    if (j != i) across = detail::mul_add(x[j] / r, x[j] / r, across);
                const double along = (x[i] / r) * (x[i] / r);
                m[i][i] = (along == 0 ? 0.0 : second * along) + (across == 0 ? 0.0 : over_r * across);
                if (std::isnan(m[i][i])) [[unlikely]]  // +-inf of both signs: f''(r) and f'/r beyond the doubles
                    m[i][i] = cusp_diagonal_beyond<OverR, Second>(r, along, across, s);
            }
        }
        return m;
    }

    // A cusp's f'' u_i^2 + (f'/r)(1 - u_i^2) where both terms are beyond
    // the doubles (viscosity near 0): each times r^k from its leading order
    // (k the larger of their singular orders), summed, then r^-k, so the
    // sum's sign and size come out, +-inf where it is beyond the doubles too.
    template <QuantityId OverR, QuantityId Second>
    static double cusp_diagonal_beyond(double r, double along, double across, const Smoothing& s) {
        constexpr int second = static_cast<int>(Second), over_r = static_cast<int>(OverR);
        const detail::origin::Leading f2 = leading<Second>(), f1 = leading<OverR>();
        const int k = -std::min(f2.low, f1.low);
        const double a = detail::near_origin_value(f2, r, s.h(), s.scale(Second), s.scale_lo(Second), K.spec,
                                                   quantity_names[second], k);
        const double b = detail::near_origin_value(f1, r, s.h(), s.scale(OverR), s.scale_lo(OverR), K.spec,
                                                   quantity_names[over_r], k);
        const double t = (along == 0 ? 0.0 : a * along) + (across == 0 ? 0.0 : b * across);
        int e = 0;
        const double mr = std::frexp(r, &e);
        return std::ldexp(t * std::pow(mr, -k), -k * e);
    }

    static const Vector<dimension>& checked(const Vector<dimension>& x) {
        for (int c = 0; c < dimension; ++c) detail::check_coordinate(x[c], c);
        return x;
    }

public:
    // The pair loop without checks, for solvers that checked their state.
    // Written on scalars with restrict pointers and a local smoothing, so the
    // compiler sees no aliasing and no aggregates, and vectorises it.
    static void pairs_unchecked(const Points<dimension>& x, const Smoothing& smoothing, double* __restrict w,
                                const PointsOut<dimension>& grad, std::size_t n) {
        pair_loop<false>(x, smoothing, w, grad, n);
    }

private:
    // The batch loops: restrict pointers and a local copy of the smoothing,
    // so the compiler knows the output aliases nothing it reads (else no
    // SIMD). Checked: is some input flagged (detail::not_a_radius), tested
    // as it is read, or by levels each register before its body (NotRadii).
    template <QuantityId Q, bool Checked>
    MOLLIFY_BATCH_LOOP static bool evaluate_loop(const double* __restrict in, double* __restrict out, std::size_t n,
                                                 const Smoothing& smoothing) {
        const Smoothing s = smoothing;
        std::uint64_t flagged = 0;
        constexpr int q = static_cast<int>(Q);
        if constexpr (Pr == Precision::accurate && detail::quantity_levels<K, q> > 1) {
            // A combination's terms by levels, as the pair loops (pair_levels),
            // from the radii as given.
            const detail::RadiusLevel<detail::quantity_levels<K, q>> level(
                [](int l) { return detail::level_bound<K, q>(l); }, s.h());
            std::conditional_t<Checked, detail::NotRadii, detail::NoRootCheck> check;
            detail::for_each_register_at_levels<detail::quantity_levels<K, q>>(
                n, in, level,
                [in, out, &s]<int L>(std::size_t i, std::integral_constant<int, L>) MOLLIFY_INLINE_LAMBDA {
                    out[i] = emitted<Q, L>(in[i], s);
                },
                check);
            if constexpr (Checked) flagged = check.any();
            if constexpr (mends<Q>) {
                std::uint64_t near = 0;
                for (std::size_t i = 0; i < n; ++i) near |= detail::near_origin(in[i], s.h());
                if (near) mend_near_origin<Q>(in, out, n, s);
            }
        } else {
            std::uint64_t near = 0;
            MOLLIFY_VECTOR_LOOP
            for (std::size_t i = 0; i < n; ++i) {
                if constexpr (Checked) flagged |= detail::not_a_radius(in[i]);
                if constexpr (mends<Q>) near |= detail::near_origin(in[i], s.h());
                out[i] = radial_unmended<Q>(in[i], s);
            }
            if constexpr (mends<Q>)
                if (near) mend_near_origin<Q>(in, out, n, s);
        }
        return flagged != 0;
    }

    template <bool Checked>
    MOLLIFY_BATCH_LOOP static bool pair_loop(const Points<dimension>& x, const Smoothing& smoothing, double* __restrict w,
                                             const PointsOut<dimension>& grad, std::size_t n) {
        constexpr bool cusp = detail::singular_at_origin<K, static_cast<int>(QuantityId::grad_over_r)>;
        static_assert(cusp || !mends<QuantityId::value>, "a W singular at 0 has a singular W'/r: the cusp's loop, through radial");
        if constexpr (dimension == 1 || odd || cusp) {
            const Smoothing s = smoothing;
            std::uint64_t flagged = 0;
            MOLLIFY_VECTOR_LOOP
            for (std::size_t i = 0; i < n; ++i) {
                Vector<dimension> xi;
                for (int c = 0; c < dimension; ++c) xi[c] = x[c][i];
                if constexpr (Checked) flagged |= detail::not_finite(norm(xi));
                const Pair<dimension> p = pair(xi, s);
                w[i] = p.value;
                for (int c = 0; c < dimension; ++c) grad[c][i] = p.gradient[c];
            }
            return flagged != 0;
        } else if constexpr (dimension == 2) {
            return pairs_2d<Checked>(x[0].data(), x[1].data(), w, grad[0].data(), grad[1].data(), n, smoothing);
        } else {
            return pairs_3d<Checked>(x[0].data(), x[1].data(), x[2].data(), w, grad[0].data(), grad[1].data(),
                                     grad[2].data(), n, smoothing);
        }
    }

    // The pair loops' levels (detail::levels, for_each_root_ahead_at_levels):
    // where every r of a register of points is at least the L-th radius
    // a_L h of a combination (with 2^-48 to spare over q's rounding), the
    // terms of the radii below it are 0 at each of them and are not
    // evaluated (their masked sum was (+0, +0): the same bits). Uniform
    // displacements in [-h, h]^3 (kernel_bench): of registers of 8, 14 %
    // reach q < 1/3 for combo:m=3, 74 % q < 2/3. One level elsewhere.
    static constexpr int pair_levels = Pr == Precision::accurate ? detail::levels<K> : 1;
    static detail::RadiusLevel<pair_levels> level_of_register(const Smoothing& s) {
        return {[](int l) { return detail::level_bound<K>(l); }, s.h()};
    }

    // Raw restrict pointers as parameters: with them GCC proves the loop free
    // of aliasing and vectorises it (pointers taken from spans it does not);
    // the lambdas capture them by value, which keeps that. The roots a block
    // ahead of their use (detail/roots_ahead.hpp).
    template <bool Checked>
    MOLLIFY_BATCH_LOOP static bool pairs_2d(const double* __restrict x0, const double* __restrict x1, double* __restrict w,
                                            double* __restrict g0, double* __restrict g1, std::size_t n, const Smoothing& smoothing) {
        const Smoothing s = smoothing;
        std::conditional_t<Checked, detail::NonFiniteRoots, detail::NoRootCheck> check;
        detail::for_each_root_ahead_at_levels<pair_levels>(
            n, [x0, x1](std::size_t i) MOLLIFY_INLINE_LAMBDA { return detail::radius(x0[i], x1[i]); }, level_of_register(s),
            [x0, x1, w, g0, g1, &s]<int L>(std::size_t i, double r, std::integral_constant<int, L>) MOLLIFY_INLINE_LAMBDA {
                w[i] = emitted<QuantityId::value, L>(r, s);
                const double g = emitted<QuantityId::grad_over_r, L>(r, s);
                g0[i] = g * x0[i];
                g1[i] = g * x1[i];
            },
            check, w, g0, g1);
        if constexpr (Checked) return check.any();
        else return false;
    }

    template <bool Checked>
    MOLLIFY_BATCH_LOOP static bool pairs_3d(const double* __restrict x0, const double* __restrict x1,
                                            const double* __restrict x2, double* __restrict w, double* __restrict g0,
                                            double* __restrict g1, double* __restrict g2, std::size_t n,
                                            const Smoothing& smoothing) {
        const Smoothing s = smoothing;
        return detail::pairs_at_radii_at_levels<Checked, pair_levels>(
            n, x0, x1, x2, w, g0, g1, g2,
            [&s]<int L>(double r, std::integral_constant<int, L>) MOLLIFY_INLINE_LAMBDA {
                return std::pair{emitted<QuantityId::value, L>(r, s), emitted<QuantityId::grad_over_r, L>(r, s)};
            },
            level_of_register(s));
    }
};

}  // namespace MOLLIFY_ISA
MOLLIFY_VECTOR_MISSES_ALLOWED_END
}  // namespace mollify
