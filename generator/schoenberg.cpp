#include "schoenberg.hpp"

#include "error.hpp"

#include <algorithm>

namespace mollify::gen {

Radial schoenberg_shape(int n) {
    if (n < 2 || n > 12) fail("B-spline order n = " + std::to_string(n) + " outside 2..12");
    const Q half = Q(n, 2);
    // Knots n/2 - j > 0 of the truncated powers, in units of the support n/2.
    std::vector<int> js;
    for (int j = 0; half - j > 0; ++j) js.push_back(j);
    Radial r;
    r.breaks = {Q(0)};
    for (auto it = js.rbegin(); it != js.rend(); ++it) r.breaks.push_back((half - *it) / half);
    r.pieces.clear();
    // Piece [b_i, b_{i+1}) carries every truncated power whose knot lies above it.
    for (std::size_t i = 0; i + 1 < r.breaks.size(); ++i) {
        Laurent p;
        for (int j : js) {
            const Q knot = (half - j) / half;
            if (knot < r.breaks[i + 1]) continue;
            const Q sign = j % 2 == 0 ? Q(1) : Q(-1);
            p += Laurent::binomial_power(half - j, -half, n - 1) * (sign * Q(binomial(static_cast<unsigned>(n),
                                                                                        static_cast<unsigned>(j))));
        }
        r.pieces.push_back(ClosedForm(p * (Q(1) / Q(factorial(static_cast<unsigned>(n - 1))))));
    }
    return r;
}

}  // namespace mollify::gen
