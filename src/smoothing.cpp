// Smoothing's constructor, out of line: it runs once per h, and its checks'
// messages need <string> (include/mollify/detail/failures.hpp).
#include <mollify/detail/double_double.hpp>
#include <mollify/smoothing.hpp>

#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>

namespace mollify {

namespace {

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
template <std::size_t N>
std::array<detail::DoubleDouble, N> powers(const detail::DoubleDouble& x) {
    std::array<detail::DoubleDouble, N> p;
    p[0] = {1.0, 0.0};
    for (std::size_t k = 1; k < N; ++k) p[k] = p[k - 1] * x;
    return p;
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

}  // namespace

Smoothing::Smoothing(double h, int dim) : h_(h), dim_(dim) {
    if (dim < 1 || dim > 3) detail::fail_dimension(dim);
    if (!(h > 0) || !std::isfinite(h)) detail::fail_smoothing_length(h);
    inv_h_ = 1 / h;
    const auto down = powers<1 - lowest_power>(detail::reciprocal({h, 0.0}));
    const auto up = powers<1 + highest_power>({h, 0.0});
    for (int q = 0; q < table::quantity_count; ++q) {
        const int n = detail::scale_power(static_cast<QuantityId>(q), dim);
        // Within 2^+-900 (smoothing.hpp: scale_range) or refused: the
        // accurate precision's last product is by h^p + its low part, or by
        // a term's content (2^-11 .. 2^9 in the catalogue, within 2^+-60 in
        // any table) times them, and both must stay normal doubles: beyond,
        // h^p's low part (2^-53 h^p) loses bits to underflow, or content
        // h^p overflows, and the results are wrong by an ulp or +-inf.
        const detail::DoubleDouble& x = n < 0 ? down[static_cast<std::size_t>(-n)] : up[static_cast<std::size_t>(n)];
        const detail::DoubleDouble p = detail::fast_two_sum(x.hi, x.lo);
        if (!(p.hi >= 1 / scale_range && p.hi <= scale_range)) detail::fail_smoothing_range(h, dim, n, q);
        scale_[q] = p.hi;
        scale_lo_[q] = p.lo;
    }
    if (dim == 2) log_h_ = std::log(h);  // the 2D potential's; log_h() forms it for the others
}

const Smoothing& Smoothing::reused(double h, int dim) {
    if (dim < 1 || dim > 3) detail::fail_dimension(dim);
    // One per dimension, so that kernels of several D in one loop each keep theirs.
    thread_local std::array<std::optional<Smoothing>, 3> last;
    std::optional<Smoothing>& kept = last[static_cast<std::size_t>(dim - 1)];
    // emplace destroys the old one first: a refused h throws and leaves nothing kept.
    if (!kept || std::bit_cast<std::uint64_t>(kept->h_) != std::bit_cast<std::uint64_t>(h)) kept.emplace(h, dim);
    return *kept;
}

}  // namespace mollify
