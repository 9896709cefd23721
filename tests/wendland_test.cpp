// Wendland functions (seed 003, T. Franz, PhD thesis, §4.3): the extended
// original psi_{d,k,l} = I^k f_{mu+l}, mu = floor(d/2) + k + 1 (Lemma 4.36),
// and the extended missing psi_{d,k+1/2,l} = I^(1/2) I^k f_{mu'+l},
// mu' = floor((d+1)/2) + k + 1 (§4.3.3), with f_n(r) = (1-r)_+^n and
// I f(r) = int_r^1 s f(s) ds (Def. 4.28).
//
// References are computed in this file: the operator I on plain coefficient
// vectors, Chernih's closed form (Franz Thm. 4.38 / Cor. 4.39) with its own
// generalised binomial, Beta-type integrals by term-wise integration, and the
// missing Wendland functions by Gauss-Legendre quadrature in MPFR.
#include "error.hpp"
#include "kernel.hpp"
#include "spec.hpp"
#include "wendland.hpp"
#include "reference_poly.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mollify::gen {
namespace {

using namespace reference;

Z choose(int n, int k) {
    if (k < 0 || k > n) return 0;
    return fact(n) / (fact(k) * fact(n - k));
}

// (a choose k) for rational a (Franz Thm. 4.38): a (a-1) ... (a-k+1) / k!.
Q general_binomial(const Q& a, int k) {
    if (k < 0) return 0;
    Q b = 1;
    for (int i = 0; i < k; ++i) b *= (a - i) / Q(i + 1);
    return b;
}

Poly one_minus_r_power(int n) {
    Poly p{Q(1)};
    for (int i = 0; i < n; ++i) p = mul(p, Poly{Q(1), Q(-1)});
    return p;
}

// I f(r) = int_r^1 s f(s) ds = F(1) - F(r) with F' = s f(s).
Poly I(const Poly& f) {
    Poly F(f.size() + 2, Q(0));
    for (std::size_t i = 0; i < f.size(); ++i) F[i + 2] = f[i] / (static_cast<int>(i) + 2);
    Poly g(F.size(), Q(0));
    for (std::size_t i = 0; i < F.size(); ++i) g[i] = -F[i];
    g[0] += at(F, Q(1));
    return g;
}

Poly I_power(Poly f, int k) {
    for (int i = 0; i < k; ++i) f = I(f);
    return f;
}

// psi_{d,k,l} = I^k f_{floor(d/2)+k+l+1}, computed here.
Poly own_wendland(int d, int k, int l) { return I_power(one_minus_r_power(d / 2 + k + 1 + l), k); }

// g = I^k f_{floor((d+1)/2)+k+l+1}: psi_{d,k+1/2,l} = I^(1/2) g.
Poly own_missing_inner(int d, int k, int l) { return I_power(one_minus_r_power((d + 1) / 2 + k + 1 + l), k); }

Poly coefficients(const Laurent& l) {
    EXPECT_TRUE(l.is_polynomial());
    Poly p;
    for (int i = 0; i <= l.high() && !l.is_zero(); ++i) p.push_back(l.coefficient(i));
    return p;
}

// Chernih's closed form (Franz Cor. 4.39): psi_{d,k,l} = C sum_{j=0}^{mu+2k+l} a_j r^j,
//   a_j = (-1)^(k+j) binom(mu+2k+l, j) binom((j-1)/2, k),  C = 2^k k! (mu+l)! / (mu+2k+l)!.
// `halve` = false gives the variant printed in Franz Thm. 4.38, binom(j-1, k).
Poly chernih_sum(int d, int k, int l, bool halve = true) {
    const int mu = d / 2 + k + 1;
    const int n = mu + 2 * k + l;
    Poly p;
    for (int j = 0; j <= n; ++j) {
        const Q sign = (k + j) % 2 == 0 ? Q(1) : Q(-1);
        p.push_back(sign * Q(choose(n, j)) * general_binomial(halve ? Q(j - 1, 2) : Q(j - 1), k));
    }
    return p;
}

Q chernih_constant(int d, int k, int l) {
    const int mu = d / 2 + k + 1;
    Z two_k = 1;
    for (int i = 0; i < k; ++i) two_k *= 2;
    return Q(two_k * fact(k) * fact(mu + l), fact(mu + 2 * k + l));
}

// a = c b for some rational c (b not identically zero).
bool proportional(const Poly& a, const Poly& b) {
    const std::size_t n = std::max(a.size(), b.size());
    Q ratio = 0;
    bool have = false;
    for (std::size_t i = 0; i < n; ++i) {
        const Q x = i < a.size() ? a[i] : Q(0), y = i < b.size() ? b[i] : Q(0);
        if (y == 0) {
            if (x != 0) return false;
            continue;
        }
        if (!have) {
            ratio = x / y;
            have = true;
        } else if (x != ratio * y) {
            return false;
        }
    }
    return have && ratio != 0;
}

// (a) Unit-mass W(0) with r = support radius. Literature: Dehnen & Aly 2012
// (MNRAS 425, 1068), Table 1 (C2, C4, C6 Wendland functions). The shapes in
// D = 2, 3 are psi_{3,k} = (1-r)^4 (1+4r), (1-r)^6 (1+6r+35/3 r^2),
// (1-r)^8 (1+8r+25r^2+32r^3), in D = 1 psi_{1,k} = (1-r)^3 (1+3r),
// (1-r)^5 (1+5r+8r^2), (1-r)^7 (1+7r+19r^2+21r^3) (up to constants). By hand:
//   3D k=1: int r^2 (1-r)^4 (1+4r) = B(3,5) + 4 B(4,5) = 1/105 + 4/280 = 1/42, x 4 pi -> 21/(2 pi);
//   2D k=1: int r (1-r)^4 (1+4r)   = B(2,5) + 4 B(3,5) = 1/30 + 4/105  = 1/14, x 2 pi -> 7/pi;
//   1D k=1: int (1-r)^3 (1+3r)     = B(1,4) + 3 B(2,4) = 1/4 + 3/20    = 2/5,  x 2    -> 5/4.
// The others are recomputed below by exact integration of the shape built
// here (own_wendland), before the generator is asked.
struct Literature {
    int D, k;
    Q value;  // W(0) = value * pi^-omega_pi(D)
};
const Literature literature[] = {
    {3, 1, Q(21, 2)}, {3, 2, Q(495, 32)}, {3, 3, Q(1365, 64)},  // Dehnen & Aly 2012
    {2, 1, Q(7)},     {2, 2, Q(9)},       {2, 3, Q(78, 7)},     // Dehnen & Aly 2012
    {1, 1, Q(5, 4)},  {1, 2, Q(3, 2)},    {1, 3, Q(55, 32)},    // derived here
};

TEST(Wendland, UnitMassValueAtZeroMatchesLiterature) {
    for (const auto& [D, k, value] : literature) {
        const Exact want = Exact::pi_power(value, -omega_pi(D));
        // Own derivation: W(0) = psi(0) / (omega_D int_0^1 r^(D-1) psi).
        const Poly psi = own_wendland(D, k, 0);
        EXPECT_EQ(Exact::pi_power(at(psi, Q(0)) / (omega_rational(D) * integral01(psi, D - 1)), -omega_pi(D)), want)
            << "own integration, D = " << D << ", k = " << k;
        const ExactKernel K = kernel("wendland:k=" + std::to_string(k), D);
        EXPECT_EQ(K.W.at(Q(0)), want) << "D = " << D << ", k = " << k << ": " << K.W.at(Q(0)).to_string();
        EXPECT_EQ(radial_moment(K, 0), Exact(Q(1)));
    }
    // Perturbed references are rejected: a transposed digit, the 3D value in 2D.
    EXPECT_NE(kernel("wendland:k=3", 3).W.at(Q(0)), Exact::pi_power(Q(1365, 46), -1));
    EXPECT_NE(kernel("wendland:k=1", 2).W.at(Q(0)), Exact::pi_power(Q(21, 2), -1));
    EXPECT_NE(kernel("wendland:k=2", 1).W.at(Q(0)), Exact(Q(3, 2) + pow(Q(10), -30)));
}

// (b) Chernih's closed form against the generator, exactly (the shape is I^k f
// itself, so the constant C of Cor. 4.39 appears exactly); and the operator I
// implemented here gives the same polynomial.
TEST(Wendland, ChernihClosedForm) {
    for (int d = 1; d <= 3; ++d)
        for (int k = 0; k <= 5; ++k)
            for (int l = 0; l <= 5; ++l) {
                const Poly shape = coefficients(wendland_shape(d, k, l));
                const Poly sum = chernih_sum(d, k, l);
                EXPECT_TRUE(proportional(shape, sum)) << "d = " << d << ", k = " << k << ", l = " << l;
                Poly scaled = sum;
                for (Q& c : scaled) c *= chernih_constant(d, k, l);
                EXPECT_EQ(shape, scaled) << "d = " << d << ", k = " << k << ", l = " << l;
                EXPECT_EQ(shape, own_wendland(d, k, l)) << "d = " << d << ", k = " << k << ", l = " << l;
            }
    // The largest parameters.
    const int K = max_wendland_k, L = max_wendland_l;
    for (int d = 1; d <= 3; ++d) EXPECT_TRUE(proportional(coefficients(wendland_shape(d, K, L)), chernih_sum(d, K, L)));
    // The generalised binomial of number.hpp agrees with the one here.
    for (int j = -3; j <= 12; ++j)
        for (int k = 0; k <= 6; ++k) EXPECT_EQ(binomial(Q(j, 2), k), general_binomial(Q(j, 2), k));
}

// The check can fail: Thm. 4.38 as printed, binom(j-1, k) instead of
// binom((j-1)/2, k), is proportional for k = 1 (factor 2) but not for k >= 2.
TEST(Wendland, ChernihMisprintIsDetected) {
    for (int d = 1; d <= 3; ++d)
        for (int k = 2; k <= 5; ++k)
            EXPECT_FALSE(proportional(coefficients(wendland_shape(d, k, 0)), chernih_sum(d, k, 0, false)))
                << "d = " << d << ", k = " << k;
    EXPECT_TRUE(proportional(coefficients(wendland_shape(3, 1, 0)), chernih_sum(3, 1, 0, false)));
    // And a shape with the wrong exponent is not proportional.
    EXPECT_FALSE(proportional(coefficients(wendland_shape(3, 2, 1)), chernih_sum(3, 2, 0)));
}

// (c) l acts as a dimension increment (Franz after Lemma 4.36): psi_{d,k,l} = psi_{d+2l,k},
// since floor((d+2l)/2) = floor(d/2) + l.
TEST(Wendland, ExtensionIsDimensionIncrement) {
    for (int d = 1; d <= 3; ++d)
        for (int k = 0; k <= 5; ++k)
            for (int l = 0; l <= 5; ++l)
                EXPECT_EQ(wendland_shape(d, k, l), wendland_shape(d + 2 * l, k, 0))
                    << "d = " << d << ", k = " << k << ", l = " << l;
    EXPECT_FALSE(wendland_shape(1, 2, 1) == wendland_shape(1, 2, 0));  // l does change the shape
}

// (d) d/dr I f = -r f, so d/dr I^k f_n = -r I^(k-1) f_n. For (d, k-1, l+1) the
// exponent floor(d/2) + (k-1) + 1 + (l+1) equals that of (d, k, l): hence
//   wendland_shape(d,k,l)' = -r wendland_shape(d,k-1,l+1)
// exactly (no constants are dropped by I). The same holds for the missing
// functions, I^(1/2) commuting with I (Franz Lemma 4.30) and mu' shifting the
// same way: missing(d,k,l)' = -r missing(d,k-1,l+1).
TEST(Wendland, DerivativeIdentityOfI) {
    const Laurent minus_r = Laurent::monomial(Q(-1), 1);
    for (int d = 1; d <= 3; ++d)
        for (int k = 1; k <= 5; ++k)
            for (int l = 0; l <= 4; ++l) {
                EXPECT_EQ(wendland_shape(d, k, l).derivative(), wendland_shape(d, k - 1, l + 1) * minus_r)
                    << "d = " << d << ", k = " << k << ", l = " << l;
                if (k <= 3) {
                    EXPECT_TRUE(missing_wendland_shape(d, k, l).derivative() ==
                                missing_wendland_shape(d, k - 1, l + 1) * minus_r)
                        << "missing, d = " << d << ", k = " << k << ", l = " << l;
                }
            }
    // The identity is sharp: with l instead of l+1 it fails.
    EXPECT_FALSE(wendland_shape(3, 2, 0).derivative() == wendland_shape(3, 1, 0) * minus_r);
    EXPECT_FALSE(missing_wendland_shape(3, 2, 0).derivative() == missing_wendland_shape(3, 1, 0) * minus_r);
}

// (f) Franz Cor. 4.37: psi_{d,k,l}^(n)(1) = 0 for 0 <= n <= floor(d/2) + 2k + l, and
// psi = (1-r)^(floor(d/2)+2k+l+1) p(r) with p(1) != 0 (Lemma 4.36: p(1) is the
// j = 0 term, 2^k / binom(mu+l+k, k) > 0), so the next derivative does not vanish.
TEST(Wendland, SmoothnessAtTheEdge) {
    for (int d = 1; d <= 3; ++d)
        for (int k = 0; k <= 5; ++k)
            for (int l = 0; l <= 5; ++l) {
                const int s = d / 2 + 2 * k + l;
                Poly p = coefficients(wendland_shape(d, k, l));
                for (int n = 0; n <= s; ++n) {
                    EXPECT_EQ(at(p, Q(1)), 0) << "d = " << d << ", k = " << k << ", l = " << l << ", n = " << n;
                    p = deriv(p);
                }
                EXPECT_NE(at(p, Q(1)), 0) << "d = " << d << ", k = " << k << ", l = " << l << ", n = " << s + 1;
                EXPECT_EQ(wendland_edge_power(d, k, l), s + 1);
                EXPECT_EQ(kernel("wendland:k=" + std::to_string(k) + ",l=" + std::to_string(l), d).claims.smoothness, s);
            }
}

// ---- Missing Wendland functions ----------------------------------------------

// (e) By quadrature. The generator's convention (wendland.cpp) drops the
// constant of I^(1/2): psi_{d,k+1/2,l}(r) = int_r^1 s g(s) / sqrt(s^2 - r^2) ds with
// g = I^k f_{floor((d+1)/2)+k+l+1}. Substituting s = sqrt(r^2 + u^2) (s ds = u du,
// sqrt(s^2 - r^2) = u) gives the integral of an analytic function,
//   psi(r) = int_0^{sqrt(1-r^2)} g(sqrt(r^2 + u^2)) du,
// whose only singularities are the branch points u = +-i r. Gauss-Legendre on
// panels [0, r], [r, 2r], [2r, 4r], ... keeps them well away: in the
// coordinates of a panel they sit at -1 + 2i (first panel) or beyond -3 (the
// others), i.e. Bernstein ellipses rho >= 4.6, so for moderate degrees of g
// n = 96 nodes err by about rho^(-2n), far below 10^-80. The rule is also
// compared with 64 nodes to check convergence.
using boost::multiprecision::mpfr_float;
constexpr unsigned digits = 80;  // ~266 bits
constexpr unsigned bits = 256;

mpfr_float real(const Q& q) {
    mpfr_float x(0, digits);
    mpfr_set_q(x.backend().data(), q.backend().data(), MPFR_RNDN);
    return x;
}

struct Rule {
    std::vector<mpfr_float> x, w;  // on [-1, 1]
};

Rule gauss_legendre(int n) {
    Rule rule;
    const mpfr_float pi = boost::multiprecision::acos(mpfr_float(-1, digits));
    for (int i = 1; i <= n; ++i) {
        mpfr_float x = boost::multiprecision::cos(pi * (mpfr_float(i, digits) - mpfr_float(0.25, digits)) /
                                                  (mpfr_float(n, digits) + mpfr_float(0.5, digits)));
        mpfr_float dp(0, digits);
        for (int it = 0; it < 100; ++it) {
            mpfr_float p0(1, digits), p1 = x;  // P_0, P_1
            for (int m = 2; m <= n; ++m) {
                mpfr_float p2 = ((2 * m - 1) * x * p1 - (m - 1) * p0) / m;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (x * p1 - p0) / (x * x - 1);
            const mpfr_float dx = p1 / dp;
            x -= dx;
            if (boost::multiprecision::abs(dx) < mpfr_float("1e-75", digits)) break;
        }
        rule.x.push_back(x);
        rule.w.push_back(2 / ((1 - x * x) * dp * dp));
    }
    return rule;
}

// g(s) = (1-s)^m h(s) with h(1) != 0, split exactly here so that g is evaluated
// without the cancellation of its expanded coefficients near s = 1 (g ~ 10^-50
// there for the largest k, l while its coefficients are large).
struct Factored {
    int m = 0;
    Poly h;
};

Factored factor_edge(Poly g) {
    Factored f;
    while (g.size() > 1) {
        Poly q(g.size() - 1, Q(0));  // g / (s - 1) by synthetic division
        Q carry = 0;
        for (std::size_t i = g.size(); i-- > 1;) {
            carry = g[i] + carry;
            q[i - 1] = carry;
        }
        if (g[0] + carry != 0) break;
        for (Q& c : q) c = -c;  // g / (1 - s)
        g = q;
        ++f.m;
    }
    f.h = g;
    return f;
}

mpfr_float eval(const Factored& g, const mpfr_float& s) {
    mpfr_float v(0, digits);
    for (std::size_t i = g.h.size(); i-- > 0;) v = v * s + real(g.h[i]);
    return v * boost::multiprecision::pow(1 - s, g.m);
}

mpfr_float missing_by_quadrature(const Poly& inner, const Q& r, const Rule& rule) {
    const Factored g = factor_edge(inner);
    const mpfr_float rr = real(r), r2 = rr * rr;
    const mpfr_float L = boost::multiprecision::sqrt(1 - r2);
    std::vector<mpfr_float> edges{mpfr_float(0, digits)};
    for (mpfr_float e = rr; e < L; e *= 2) edges.push_back(e);
    edges.push_back(L);
    mpfr_float total(0, digits);
    for (std::size_t p = 0; p + 1 < edges.size(); ++p) {
        const mpfr_float half = (edges[p + 1] - edges[p]) / 2, mid = (edges[p + 1] + edges[p]) / 2;
        for (std::size_t i = 0; i < rule.x.size(); ++i) {
            const mpfr_float u = mid + half * rule.x[i];
            total += half * rule.w[i] * eval(g, boost::multiprecision::sqrt(r2 + u * u));
        }
    }
    return total;
}

// Compares the closed form with the quadrature at r = 1/4, 1/2, 3/4, 9/10.
void expect_matches_quadrature(int d, int k, int l, const Rule& fine, const Rule& coarse, const char* tol,
                               unsigned closed_form_bits) {
    const mpfr_float tolerance(tol, digits);
    const ClosedForm psi = missing_wendland_shape(d, k, l);
    const Poly g = own_missing_inner(d, k, l);
    for (const Q& r : {Q(1, 4), Q(1, 2), Q(3, 4), Q(9, 10)}) {
        const std::string what = "d = " + std::to_string(d) + ", k = " + std::to_string(k) +
                                 ", l = " + std::to_string(l) + ", r = " + short_string(r);
        const mpfr_float want = missing_by_quadrature(g, r, fine);
        const mpfr_float check = missing_by_quadrature(g, r, coarse);
        ASSERT_LT(boost::multiprecision::abs(want - check), tolerance * boost::multiprecision::abs(want))
            << "quadrature not converged, " << what;
        const auto [got, magnitude] = psi.evaluate(real(r), closed_form_bits);
        EXPECT_LT(boost::multiprecision::abs(got - want), tolerance * boost::multiprecision::abs(want))
            << what << ": " << got.str(40) << " vs " << want.str(40) << " (magnitude " << magnitude.str(5) << ")";
    }
}

// Sets MPFR's default precision for the test's temporaries, restoring it after.
struct DefaultPrecision {
    unsigned saved = mpfr_float::default_precision();
    explicit DefaultPrecision(unsigned d) { mpfr_float::default_precision(d); }
    ~DefaultPrecision() { mpfr_float::default_precision(saved); }
};

TEST(WendlandMissing, ClosedFormMatchesQuadrature) {
    const DefaultPrecision precision(digits);
    const Rule fine = gauss_legendre(96), coarse = gauss_legendre(64);
    // Small parameters, closed form at 256 bits: observed agreement 5 10^-67 or
    // better (the two rules agree to 10^-75), so 10^-55 leaves ample room.
    for (int d = 1; d <= 3; ++d)
        for (int k = 0; k <= 3; ++k)
            for (int l = 0; l <= 2; ++l) expect_matches_quadrature(d, k, l, fine, coarse, "1e-55", bits);
    // The largest parameters. Near r = 1 psi is tiny (~10^-58 at r = 9/10 for
    // k = l = 12) while the closed form's S and arcsech terms are not: it loses
    // log10(magnitude/|value|) (up to 48) digits to cancellation, so it is
    // evaluated at 640 bits (~190 digits) here. Observed agreement 2 10^-76
    // (the 80-digit quadrature's own level); 10^-60 leaves room.
    for (int d = 1; d <= 3; ++d) {
        expect_matches_quadrature(d, 6, 12, fine, coarse, "1e-60", 640);
        expect_matches_quadrature(d, max_wendland_k, max_wendland_l, fine, coarse, "1e-60", 640);
    }
    // The comparison can fail: a closed form for the wrong l differs.
    const mpfr_float want = missing_by_quadrature(own_missing_inner(3, 1, 1), Q(1, 2), fine);
    const mpfr_float wrong = missing_wendland_shape(3, 1, 0).evaluate(real(Q(1, 2)), bits).first;
    EXPECT_GT(boost::multiprecision::abs(wrong - want), mpfr_float("1e-50", digits) * boost::multiprecision::abs(want));
}

// Exact unit mass, derived independently of the Wallis integrals used by the
// generator: by Fubini on 0 < r < s < 1 and r = s t,
//   int_0^1 r^(D-1) psi(r) dr = int_0^1 s g(s) int_0^s r^(D-1)/sqrt(s^2-r^2) dr ds
//                             = c_D int_0^1 s^D g(s) ds,
// c_D = int_0^1 t^(D-1)/sqrt(1-t^2) dt = pi/2, 1, pi/4 for D = 1, 2, 3. So the
// normalisation is 1/(omega_D c_D int s^D g) = 1/(pi G), 1/(2 pi G), 1/(pi^2 G).
TEST(WendlandMissing, NormalisationByFubini) {
    for (int D = 1; D <= 3; ++D)
        for (int k : {0, 1, 2, 3, max_wendland_k})
            for (int l : {0, 1, 2, max_wendland_l}) {
                const Q G = integral01(own_missing_inner(D, k, l), D);
                const Exact want = D == 1 ? Exact::pi_power(Q(1) / G, -1)
                                 : D == 2 ? Exact::pi_power(Q(1) / (2 * G), -1)
                                          : Exact::pi_power(Q(1) / G, -2);
                const ExactKernel K = kernel("wendland-missing:k=" + std::to_string(k) + ",l=" + std::to_string(l), D);
                EXPECT_EQ(K.normalisation, want) << "D = " << D << ", k = " << k << ", l = " << l << ": "
                                                 << K.normalisation.to_string() << " vs " << want.to_string();
                EXPECT_EQ(radial_moment(K, 0), Exact(Q(1)));
            }
    // Detects a perturbed reference (c_3 taken as pi/2 instead of pi/4).
    const Q G = integral01(own_missing_inner(3, 1, 1), 3);
    EXPECT_NE(kernel("wendland-missing:k=1,l=1", 3).normalisation, Exact::pi_power(Q(1) / (2 * G), -2));
}

}  // namespace
}  // namespace mollify::gen
