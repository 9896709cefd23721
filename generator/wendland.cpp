#include "wendland.hpp"

#include <vector>

namespace mollify::gen {

namespace {

// I f(r) = int_r^1 s f(s) ds for a polynomial f supported in [0, 1].
Laurent wendland_integral(const Laurent& f) {
    Q unused;
    const Laurent F = (f * Laurent::monomial(Q(1), 1)).antiderivative(&unused);
    return Laurent(F(Q(1))) - F;
}

Laurent apply_k(Laurent f, int k) {
    for (int i = 0; i < k; ++i) f = wendland_integral(f);
    return f;
}

}  // namespace

int wendland_edge_power(int d, int k, int l) { return d / 2 + 2 * k + l + 1; }

Laurent wendland_shape(int d, int k, int l) {
    const int mu = d / 2 + k + 1;
    return apply_k(Laurent::binomial_power(Q(1), Q(-1), mu + l), k);
}

ClosedForm missing_wendland_shape(int d, int k, int l) {
    const int mu = (d + 1) / 2 + k + 1;
    const Laurent g = apply_k(Laurent::binomial_power(Q(1), Q(-1), mu + l), k);
    // I^(1/2) g up to the constant sqrt(2/pi): sum_n g_n J_n(r) with
    // J_n(r) = int_r^1 s^(n+1) (s^2 - r^2)^(-1/2) ds  (Franz Lemma 4.64, k = 0):
    // J_0 = S, J_1 = (S + r^2 L)/2, J_n = S/(n+1) + n/(n+1) r^2 J_{n-2}.
    const TermKey S{Basis::sqrt_power, 1, Atom{}};
    const TermKey L{Basis::arcsech, 0, Atom{}};
    std::vector<ClosedForm> J;
    J.push_back(ClosedForm(Laurent(Q(1)), S));
    J.push_back(ClosedForm(Laurent(Q(1, 2)), S) + ClosedForm(Laurent::monomial(Q(1, 2), 2), L));
    for (int n = 2; n <= g.high(); ++n)
        J.push_back(ClosedForm(Laurent(Q(1, n + 1)), S) + J[static_cast<std::size_t>(n - 2)] *
                                                              Laurent::monomial(Q(n, n + 1), 2));
    ClosedForm psi;
    for (int n = 0; n <= g.high(); ++n) psi += J[static_cast<std::size_t>(n)] * g.coefficient(n);
    return psi;
}

}  // namespace mollify::gen
