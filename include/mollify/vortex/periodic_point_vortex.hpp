// The velocity induced by a row of point vortices of unit circulation at
// (n, 0), n in Z (period 1 in x): Krasny's periodic kernel, the sum over
// images in closed form. With z = x + i y the conjugate velocity is
//     u - i v = cot(pi z) / (2 i),
// i.e. u = -sinh(2 pi y) / (2 D), v = sin(2 pi x) / (2 D) with
//     D = cosh(2 pi y) - cos(2 pi x) = 2 (sinh^2(pi y) + sin^2(pi x)),
// the second form free of cancellation near z = 0.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/constants/cot_series.hpp>

#include <array>
#include <cmath>
#include <iterator>
#include <numbers>

namespace mollify::vortex {
inline namespace MOLLIFY_ISA {

using Velocity = std::array<double, 2>;

namespace detail {

// x reduced to [-1/2, 1/2]: the kernel has period 1 and the compact
// correction needs the nearest image.
inline double nearest_image(double x) { return x - std::nearbyint(x); }

// cosh(2 pi y) - cos(2 pi x) + delta2, and its two numerators; far from the
// row (|y| > 20, where e^(-2 pi |y|) < 1e-54) the limit +-1/2 without overflow.
// sin 2 pi x = 2 sin cos of pi x: one sincos (the sheet's sums spend their
// time here); sinh 2 pi y itself, since 2 sinh cosh of pi y, or sinh from
// expm1, costs the images' difference form (its error eps / (2 pi |z|))
// an ulp.
inline Velocity krasny(double x, double y, double delta2) {
    constexpr double pi = std::numbers::pi;
    if (std::abs(y) > 20) return {-0.5 * std::copysign(1.0, y), 0.0};
    const double sx = std::sin(pi * x), cx = std::cos(pi * x), sy = std::sinh(pi * y);
    const double d = 2 * (sy * sy + sx * sx) + delta2;
    return {-0.5 * std::sinh(2 * pi * y) / d, sx * cx / d};
}

}  // namespace detail

// The point vortex at 0 alone: (-y, x) / (2 pi r^2).
inline Velocity point_vortex(double x, double y) {
    const double c = 1 / (2 * std::numbers::pi * (x * x + y * y));
    return {-y * c, x * c};
}

// The whole row of point vortices (singular at z = 0).
inline Velocity periodic_point_vortex(double x, double y) { return detail::krasny(detail::nearest_image(x), y, 0.0); }

// The row without its vortex at 0: regular at z = 0. Near 0 from
//     pi z cot(pi z) = 1 - 2 sum_k zeta(2k) z^(2k),
// so cot(pi z)/(2i) - 1/(2 pi i z) = (i/pi) sum_k zeta(2k) z^(2k-1); six
// terms leave |z|^13 < 1e-17 for |z| < 0.05. Elsewhere the difference,
// whose rounding is eps / (2 pi |z|) absolute.
inline Velocity periodic_point_vortex_images(double x, double y) {
    x = detail::nearest_image(x);
    if (x * x + y * y >= 0.05 * 0.05) {
        const Velocity p = detail::krasny(x, y, 0.0), s = point_vortex(x, y);
        return {p[0] - s[0], p[1] - s[1]};
    }
    // zeta(2k)/pi, k = 1..6, from the generator (Euler's values, correctly
    // rounded: generated/mollify/constants/cot_series.hpp).
    const auto& c = constants::zeta_even_over_pi;
    constexpr int terms = static_cast<int>(std::size(c));
    // w = sum_k c_k z^(2k-2) (Horner in z^2), w z, then u - i v = i w z.
    const double z2r = x * x - y * y, z2i = 2 * x * y;
    double wr = 0, wi = 0;
    for (int k = terms - 1; k >= 0; --k) {
        const double p = c[k];
        const double tr = wr * z2r - wi * z2i, ti = wr * z2i + wi * z2r;
        wr = tr + p;
        wi = ti;
    }
    const double fr = wr * x - wi * y, fi = wr * y + wi * x;  // w * z
    // u - i v = i (fr + i fi) = -fi + i fr
    return {-fi, -fr};
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::vortex
