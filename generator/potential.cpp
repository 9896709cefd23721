#include "potential.hpp"

#include "error.hpp"

namespace mollify::gen {

ClosedForm green_function(int dim) {
    switch (dim) {
        case 1: return ClosedForm(Laurent::monomial(Q(1, 2), 1));
        case 2: return ClosedForm(Laurent(Q(1, 2)), TermKey{Basis::log, 0, Atom{-1, 1}});
        case 3: return ClosedForm(Laurent::monomial(Q(-1, 4), -1)) * Exact::pi_power(Q(1), -1);
    }
    fail("dimension " + std::to_string(dim) + " is outside 1..3");
}

Radial potential(const Radial& W, int dim) {
    const std::size_t n = W.pieces.size();
    // Gauss: omega_D r^(D-1) phi'(r) = mass inside r, so phi' = m(r) / r^(D-1)
    // with m(r) = int_0^r s^(D-1) W(s) ds.
    std::vector<ClosedForm> flux(n);
    Exact m_at_break;
    for (std::size_t i = 0; i < n; ++i) {
        const ClosedForm F = (W.pieces[i] * Laurent::monomial(Q(1), dim - 1)).antiderivative();
        const Q& a = W.breaks[i];
        Exact F_at_a;
        try {
            F_at_a = value_at(F, a);
        } catch (const Error&) {
            fail("kernel is not integrable at r = 0 in dimension " + std::to_string(dim));
        }
        flux[i] = F - ClosedForm::constant(F_at_a) + ClosedForm::constant(m_at_break);
        m_at_break = value_at(flux[i], W.breaks[i + 1]);
    }
    Radial phi = W;
    phi.outside = green_function(dim);
    Exact value = value_at(phi.outside, W.support());
    for (std::size_t i = n; i-- > 0;) {
        const ClosedForm dphi = flux[i] * Laurent::monomial(Q(1), 1 - dim);
        const ClosedForm P = dphi.antiderivative();
        phi.pieces[i] = P - ClosedForm::constant(value_at(P, W.breaks[i + 1])) + ClosedForm::constant(value);
        if (i > 0) value = value_at(phi.pieces[i], W.breaks[i]);
    }
    phi.parity = 1;
    return phi;
}

Radial radial_laplacian(const Radial& f, int dim) {
    const Radial d1 = f.derivative();
    const Radial d2 = d1.derivative();
    Radial lap = d2 + d1.times(Laurent::monomial(Q(dim - 1), -1));
    lap.parity = f.parity;
    return lap;
}

}  // namespace mollify::gen
