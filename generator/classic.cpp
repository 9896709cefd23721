#include "classic.hpp"

#include "anderson.hpp"
#include "error.hpp"
#include "schoenberg.hpp"

namespace mollify::gen {

namespace {

Laurent poly(std::initializer_list<std::pair<int, Q>> terms) {
    Laurent p;
    for (const auto& [n, c] : terms) p += Laurent::monomial(c, n);
    return p;
}

Radial two_pieces(const Laurent& inner, const Laurent& outer, int parity = 1) {
    Radial r;
    r.breaks = {Q(0), Q(1, 2), Q(1)};
    r.pieces = {ClosedForm(inner), ClosedForm(outer)};
    r.parity = parity;
    return r;
}

}  // namespace

Radial classic_shape(Family f) {
    switch (f) {
        case Family::poly6: return Radial::single(one_minus_r2_power(3));
        case Family::spiky: return Radial::single(Laurent::binomial_power(Q(1), Q(-1), 3));
        case Family::viscosity:  // -r^3/2 + r^2 + 1/(2r) - 1 (Mueller et al. 2003)
            return Radial::single(poly({{3, Q(-1, 2)}, {2, Q(1)}, {-1, Q(1, 2)}, {0, Q(-1)}}));
        case Family::cubic_spline:  // 1 - 6q^2 + 6q^3 on [0,1/2), 2(1-q)^3 on [1/2,1]
            return two_pieces(poly({{0, Q(1)}, {2, Q(-6)}, {3, Q(6)}}), Laurent::binomial_power(Q(1), Q(-1), 3) * Q(2));
        case Family::quartic_spline: return schoenberg_shape(5);  // M5: knots 1/5, 3/5, 1
        case Family::quintic_spline: return schoenberg_shape(6);  // M6: knots 1/3, 2/3, 1
        case Family::box: return Radial::single(Laurent(Q(1)));
        case Family::box_d1: {  // -sign(x): odd
            Radial r = Radial::single(Laurent(Q(-1)));
            r.parity = -1;
            return r;
        }
        case Family::box_d2: return two_pieces(Laurent(Q(-1)), Laurent(Q(1)));
        default: fail("internal: not a classic kernel");
    }
}

}  // namespace mollify::gen
