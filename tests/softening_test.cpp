// Softening to order 6 (softening.hpp, softening_certificate.hpp, query.hpp):
// the exact derivatives of phi, their certificate at the breakpoints and the
// support edge, SWIFT's D_soft_n and GADGET-4's g-factors, bad orders.
//
// Independent references: (1) derivatives at rational points by synthetic
// division (p(r) - p(a) = (r - a) q(r), p'(a) = q(a)), not Laurent::derivative;
// (2) the Green's function's derivatives at r = 1 from their closed formulas,
// and the jump of phi^(n+2) equal to the jump of W^(n) (Delta phi = W);
// (3) MPFR (256 bits) values from Gauss's law phi' = M(r) r^(1-D),
// M(r) = int_0^r t^(D-1) W(t) dt by Romberg quadrature, and Leibniz's rule,
// never the generator's antiderivatives; (4) the peers' facts (SWIFT's W(0) =
// -3 for Wendland C2, GADGET-4's h = 2.8 eps for the cubic spline), the
// tensor recursion T_(n+1) = T_n'/r and GADGET-4's expanded g-factors.
#include "error.hpp"
#include "kernel.hpp"
#include "potential.hpp"
#include "query.hpp"
#include "softening.hpp"
#include "softening_certificate.hpp"
#include "spec.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace mollify::gen {
namespace {

struct Case {
    std::string spec;
    int dim;
};

// Polynomial kernels (exact values at every rational r): Wendland C2/C4/C6
// (k = 1, 2, 3) and the cubic spline in 3D, a mollifier of order 2 and 4, a
// combination, and 2D and 1D cases (2D potentials have log r pieces).
const std::vector<Case>& polynomial_cases() {
    static const std::vector<Case> cases{
        {"wendland:k=1", 3},  {"wendland:k=2", 3},          {"wendland:k=3", 3},
        {"cubic-spline", 3},  {"mollifier:M=4", 3},         {"mollifier:M=3,order=4", 3},
        {"combo:m=2,base=wendland:k=2", 3},                 {"box", 3},
        {"wendland:k=1", 2},  {"cubic-spline", 2},          {"mollifier:M=4", 2},
        {"combo:m=3,base=wendland:k=1", 2},                 {"wendland:k=1", 1},
        {"cubic-spline", 1},  {"mollifier:M=3", 1},
    };
    return cases;
}

ExactKernel kernel(const Case& c) { return make_kernel(parse_spec(c.spec), c.dim); }

std::string name(const Case& c) { return c.spec + " D=" + std::to_string(c.dim); }

// Two rational points inside each piece and one outside the support.
std::vector<Q> sample_points(const Radial& f) {
    std::vector<Q> r;
    for (std::size_t i = 0; i + 1 < f.breaks.size(); ++i) {
        const Q a = f.breaks[i], w = f.breaks[i + 1] - a;
        r.push_back(a + w / 3);
        r.push_back(a + w * Q(5, 7));
    }
    r.push_back(Q(3, 2));
    return r;
}

// p'(a) by synthetic division: p(r) - p(a) = (a - r) q(r), so p'(a) = -q(a).
Q slope(const Laurent& p, const Q& a) {
    const auto q = (p - Laurent(p(a))).divided_by_linear_power(a, 1);
    if (!q) ADD_FAILURE() << "p(r) - p(a) is not divisible by (a - r)";
    return q ? -(*q)(a) : Q(0);
}

// d/dr of a closed form of basis 1 and log r at rational a > 0.
Exact derivative_at(const ClosedForm& f, const Q& a) {
    Exact d;
    for (const auto& [key, p] : f.terms()) {
        const Exact c = Exact::of(key.factor);
        if (key.basis == Basis::one) d += c * Exact(slope(p, a));
        else if (key.basis == Basis::log) d += c * (Exact::log_of(a) * slope(p, a) + Exact(p(a) / a));
        else ADD_FAILURE() << "unexpected basis in a polynomial kernel's potential";
    }
    return d;
}

TEST(Softening, EachDerivativeIsTheSlopeOfThePreviousOne) {
    for (const Case& c : polynomial_cases()) {
        SCOPED_TRACE(name(c));
        const std::vector<Radial> d = softening_derivatives(kernel(c));
        ASSERT_EQ(d.size(), 7u);
        for (int n = 0; n < 6; ++n)
            for (const Q& r : sample_points(d[n])) {
                SCOPED_TRACE("n = " + std::to_string(n) + ", r = " + short_string(r));
                EXPECT_EQ(derivative_at(d[n].form_at(r), r), d[n + 1].at(r));
            }
    }
}

TEST(Softening, ZerothDerivativeIsThePotential) {
    for (const Case& c : polynomial_cases()) {
        const ExactKernel k = kernel(c);
        EXPECT_TRUE(softening_derivatives(k, 0).front() == potential(k.W, k.dim)) << name(c);
    }
}

// G^(n)(1): 3D G = -1/(4 pi r), G^(n) = -(-1)^n n! / (4 pi r^(n+1));
// 2D G = log(r)/(2 pi), G^(n) = (-1)^(n-1) (n-1)! / (2 pi r^n), n >= 1;
// 1D G = r/2 (r > 0).
Exact green_derivative_at_one(int dim, int n) {
    const Q sign = n % 2 ? Q(-1) : Q(1);
    switch (dim) {
        case 3: return Exact::pi_power(-sign * Q(factorial(n)) / 4, -1);
        case 2: return n == 0 ? Exact() : Exact::pi_power(-sign * Q(factorial(n - 1)) / 2, -1);
        default: return Exact(n == 0 ? Q(1, 2) : n == 1 ? Q(1, 2) : Q(0));
    }
}

std::vector<Case> certificate_cases() {
    std::vector<Case> cases = polynomial_cases();
    for (int dim = 1; dim <= 3; ++dim) {
        cases.push_back({"wendland-missing:k=1,l=1", dim});  // S, arcsech, arcsin
        cases.push_back({"wendland-missing:k=0", dim});      // W^(s+1) infinite at the edge
    }
    cases.push_back({"wendland:k=0", 3});
    cases.push_back({"poly6", 3});
    return cases;
}

TEST(Softening, CertificateAtTheEdgeAgainstTheGreensFunction) {
    for (const Case& c : certificate_cases()) {
        SCOPED_TRACE(name(c));
        const ExactKernel k = kernel(c);
        const std::vector<Certificate> certs = softening_certificates(k);
        ASSERT_FALSE(certs.empty());
        for (const Certificate& cert : certs) EXPECT_TRUE(cert.passed) << cert.what << " [" << cert.detail << "]";
        const SofteningSmoothness s = softening_smoothness(k, softening_derivatives(k));
        EXPECT_EQ(s.guaranteed, std::min(k.claims.smoothness + 2, 6));
        EXPECT_GE(s.continuous_at_edge, s.guaranteed);
        for (const Join& j : s.joins) {
            if (!j.edge) continue;
            // Outside the support phi is the Green's function, at every order.
            ASSERT_TRUE(j.right.has_value()) << join_name(j);
            EXPECT_EQ(*j.right, green_derivative_at_one(c.dim, j.order)) << join_name(j);
            if (j.order <= s.guaranteed) {
                ASSERT_TRUE(j.left.has_value()) << join_name(j);
                EXPECT_EQ(*j.left, green_derivative_at_one(c.dim, j.order)) << join_name(j);
            }
        }
    }
}

// The one-sided limit, nullopt where infinite (a negative power of S at r = 1).
std::optional<Exact> limit(const ClosedForm& f, const Q& r) {
    try {
        return value_at(f, r);
    } catch (const Error&) {
        return std::nullopt;
    }
}

// Delta phi = W: phi'' = W - (D-1) phi'/r, so where phi^(0..n+1) are
// continuous, the jump of phi^(n+2) is the jump of W^(n) (infinite where
// W^(n) is). The first jump of phi at each breakpoint is therefore two
// orders above W's, by the same amount.
TEST(Softening, FirstJumpOfPhiIsTwoOrdersAboveTheKernels) {
    int jumps_seen = 0, infinite_seen = 0;
    for (const Case& c : certificate_cases()) {
        SCOPED_TRACE(name(c));
        const ExactKernel k = kernel(c);
        const SofteningSmoothness s = softening_smoothness(k, softening_derivatives(k));
        Radial w = k.W;
        for (int n = 0; n + 2 <= 6; ++n, w = w.derivative())
            for (std::size_t i = 1; i < w.breaks.size(); ++i) {
                const Q& b = w.breaks[i];
                const auto w_left = limit(w.pieces[i - 1], b);
                const auto w_right = limit(i + 1 < w.breaks.size() ? w.pieces[i] : w.outside, b);
                auto join = [&](int order) {
                    for (const Join& j : s.joins)
                        if (j.order == order && j.at == b) return j;
                    ADD_FAILURE() << "no join of order " << order << " at " << short_string(b);
                    return Join{};
                };
                bool lower_continuous = true;
                for (int m = 0; m <= n + 1; ++m) lower_continuous = lower_continuous && join(m).continuous();
                if (!lower_continuous) continue;
                const Join j = join(n + 2);
                if (!w_left || !w_right) {
                    EXPECT_FALSE(j.left && j.right) << join_name(j) << " is finite where W^(" << n << ") is not";
                    ++infinite_seen;
                    continue;
                }
                ASSERT_TRUE(j.left && j.right) << join_name(j);
                const Exact w_jump = *w_right - *w_left;
                EXPECT_EQ(*j.right - *j.left, w_jump) << join_name(j);
                jumps_seen += !w_jump.is_zero();
            }
    }
    EXPECT_GT(jumps_seen, 5);  // the test saw real jumps, not only continuity
    EXPECT_GE(infinite_seen, 3);  // and wendland-missing:k=0's infinite ones, in each dimension
}

TEST(Softening, StatedSmoothnessOfWendlandC2AndTheCubicSpline) {
    // Wendland C2 = (1-r)^4 (4r+1) at the edge: C^3, phi C^5, phi^(6) jumps.
    // Cubic spline: C^2, phi C^4, phi^(5) jumps at r = 1/2 and 1.
    const SofteningSmoothness w = softening_smoothness(kernel({"wendland:k=1", 3}),
                                                       softening_derivatives(kernel({"wendland:k=1", 3})));
    EXPECT_EQ(w.continuous_at_edge, 5);
    const SofteningSmoothness cs = softening_smoothness(kernel({"cubic-spline", 3}),
                                                        softening_derivatives(kernel({"cubic-spline", 3})));
    EXPECT_EQ(cs.continuous_at_edge, 4);
    int jumps = 0;
    for (const Join& j : cs.joins) jumps += j.order == 5 && !j.continuous();
    EXPECT_EQ(jumps, 2);
    // wendland-missing:k=0 in 3D, (1-r)^(7/2) at the edge: phi C^5, phi^(6) infinite there.
    const SofteningSmoothness m = softening_smoothness(kernel({"wendland-missing:k=0", 3}),
                                                       softening_derivatives(kernel({"wendland-missing:k=0", 3})));
    EXPECT_EQ(m.guaranteed, 5);
    EXPECT_EQ(m.continuous_at_edge, 5);
    ASSERT_EQ(m.joins.back().order, 6);
    EXPECT_FALSE(m.joins.back().left.has_value());
    EXPECT_TRUE(m.joins.back().right.has_value());
}

// ---------------------------------------------------------------- (3) MPFR
constexpr unsigned bits = 256;
constexpr unsigned digits10 = bits * 30103 / 100000 + 2;

Real real(const Q& q) {
    Real x(0, digits10);
    mpfr_set_q(x.backend().data(), q.backend().data(), MPFR_RNDN);
    return x;
}

Real real(const Exact& e) { return e.evaluate(bits).first; }

// a (a-1) ... (a-j+1)
Real falling(int a, int j) {
    Real p(1, digits10);
    for (int i = 0; i < j; ++i) p *= a - i;
    return p;
}

Real choose(int n, int k) { return falling(n, k) / falling(k, k); }

// The kernel's pieces as MPFR polynomials W(t) = sum_m c_m t^m.
struct Piece {
    Q a, b;
    std::vector<std::pair<int, Real>> terms;
};

std::vector<Piece> mpfr_pieces(const Radial& W) {
    std::vector<Piece> out;
    for (std::size_t i = 0; i < W.pieces.size(); ++i) {
        Laurent p;
        Atom factor;
        EXPECT_TRUE(W.pieces[i].single_polynomial(&p, &factor)) << "kernel piece is not one polynomial";
        const Real f = real(Exact::of(factor));
        Piece piece{W.breaks[i], W.breaks[i + 1], {}};
        for (int m = p.low(); m <= p.high() && !p.is_zero(); ++m)
            if (p.coefficient(m) != 0) piece.terms.emplace_back(m, real(p.coefficient(m)) * f);
        out.push_back(piece);
    }
    return out;
}

// W^(i)(t) on one piece (its polynomial, also at the piece's right end).
Real w_derivative(const Piece& p, int i, const Real& t) {
    Real s(0, digits10);
    for (const auto& [m, c] : p.terms)
        if (m >= i) s += c * falling(m, i) * boost::multiprecision::pow(t, m - i);
    return s;
}

// W^(i)(t) at an interior point t (0 outside the support).
Real w_derivative(const std::vector<Piece>& W, int i, const Real& t) {
    for (const Piece& p : W)
        if (t >= real(p.a) && t < real(p.b)) return w_derivative(p, i, t);
    return Real(0, digits10);
}

using Integrand = std::function<Real(const Piece&, const Real&)>;

// Romberg quadrature: with L levels the last column is exact for polynomials
// of degree <= 2L - 1 (polynomial_levels: degree <= 17, asserted per kernel
// below), and for the 2D phi(r) integrand t W(t) log t converges like h^(2L).
constexpr int polynomial_levels = 9;
constexpr int log_levels = 13;
constexpr int max_exact_degree = 2 * polynomial_levels - 1;

Real romberg(const Integrand& f, const Piece& p, const Real& a, const Real& b, int levels) {
    std::vector<std::vector<Real>> R(levels, std::vector<Real>(levels, Real(0, digits10)));
    Real h = b - a;
    R[0][0] = h * (f(p, a) + f(p, b)) / 2;
    for (int i = 1; i < levels; ++i) {
        h /= 2;
        Real sum(0, digits10);
        for (long k = 1; k < (1L << i); k += 2) sum += f(p, a + h * k);
        R[i][0] = R[i - 1][0] / 2 + h * sum;
        Real four(1, digits10);
        for (int j = 1; j <= i; ++j) {
            four *= 4;
            R[i][j] = R[i][j - 1] + (R[i][j - 1] - R[i - 1][j - 1]) / (four - 1);
        }
    }
    return R[levels - 1][levels - 1];
}

// int over [lo, hi] of f, split at the kernel's breakpoints.
Real integral(const std::vector<Piece>& W, const Integrand& f, const Real& lo, const Real& hi,
              int levels = polynomial_levels) {
    Real s(0, digits10);
    for (const Piece& p : W) {
        const Real a = std::max(real(p.a), lo), b = std::min(real(p.b), hi);
        if (a < b) s += romberg(f, p, a, b, levels);
    }
    return s;
}

Real density(int dim, const Piece& p, const Real& t) { return boost::multiprecision::pow(t, dim - 1) * w_derivative(p, 0, t); }

// M(r) = int_0^min(r, 1) t^(D-1) W(t) dt (omega_D M(r) is the mass inside r).
Real enclosed(const std::vector<Piece>& W, int dim, const Q& r) {
    return integral(W, [&](const Piece& p, const Real& t) { return density(dim, p, t); }, Real(0, digits10),
                    real(r < 1 ? r : Q(1)));
}

// phi^(n)(r) from Gauss's law, independently of potential.cpp; M = enclosed(W, dim, r).
Real reference(const std::vector<Piece>& W, int dim, int n, const Q& rq, const Real& M) {
    const Real r = real(rq);
    const Real one(1, digits10);
    if (n == 0) {
        if (rq >= 1) {  // the Green's function
            if (dim == 3) return -one / (4 * pi_at(bits) * r);
            if (dim == 2) return boost::multiprecision::log(r) / (2 * pi_at(bits));
            return r / 2;
        }
        // phi(r) = G(1) - int_r^1 M(s) s^(1-D) ds = G(1) - int_0^1 t^(D-1) W(t) kappa(max(r, t)) dt,
        // kappa(s) = int_s^1 x^(1-D) dx.
        auto kappa = [&](const Real& s) -> Real {
            if (dim == 3) return one / s - 1;
            if (dim == 2) return -boost::multiprecision::log(s);
            return one - s;
        };
        const Real inner = M * kappa(r);
        const Real outer = integral(
            W, [&](const Piece& p, const Real& t) { return density(dim, p, t) * kappa(t); }, r, one,
            dim == 2 ? log_levels : polynomial_levels);
        const Real g1 = dim == 3 ? -one / (4 * pi_at(bits)) : dim == 2 ? Real(0, digits10) : one / 2;
        return g1 - inner - outer;
    }
    // phi^(n) = (M r^(1-D))^(n-1) = sum_k C(n-1, k) M^(k) (r^(1-D))^(n-1-k), M^(k) = (t^(D-1) W)^(k-1).
    auto m_derivative = [&](int k) -> Real {
        if (k == 0) return M;
        Real s(0, digits10);
        for (int j = 0; j <= k - 1; ++j)
            if (j <= dim - 1)
                s += choose(k - 1, j) * falling(dim - 1, j) * boost::multiprecision::pow(r, dim - 1 - j) *
                     w_derivative(W, k - 1 - j, r);
        return s;
    };
    Real s(0, digits10);
    for (int k = 0; k <= n - 1; ++k)
        s += choose(n - 1, k) * m_derivative(k) * falling(1 - dim, n - 1 - k) *
             boost::multiprecision::pow(r, 1 - dim - (n - 1 - k));
    return s;
}

TEST(Softening, DerivativesAgainstMpfrFromGausssLaw) {
    for (const Case& c : polynomial_cases()) {
        SCOPED_TRACE(name(c));
        const ExactKernel k = kernel(c);
        const std::vector<Radial> d = softening_derivatives(k);
        const std::vector<Piece> W = mpfr_pieces(k.W);
        // Romberg is exact for t^(D-1) W(t) and for t^(D-1) W(t) kappa(t) in 1D and 3D (kappa
        // of degree 1 and -1/0): degree <= m + D.
        for (const Piece& p : W)
            for (const auto& [m, coefficient] : p.terms) ASSERT_LE(m + c.dim, max_exact_degree);
        for (const Q& r : sample_points(d[0])) {
            const Real M = enclosed(W, c.dim, r);
            for (int n = 0; n <= 6; ++n) {
                const Real got = real(d[n].at(r)), want = reference(W, c.dim, n, r, M);
                // Polynomial integrands (Romberg exact): 256-bit rounding of ~10^4 terms, measured <= 3e-73
                // relative. The 2D phi integrand t W(t) log t: Romberg's truncation, measured <= 8e-43.
                const bool log_integrand = c.dim == 2 && n == 0 && r < 1;
                const Real tolerance = Real(log_integrand ? "1e-38" : "1e-68", digits10) * (1 + abs(want));
                EXPECT_LE(abs(got - want), tolerance)
                    << "n = " << n << ", r = " << short_string(r) << ": " << got.str(30) << " vs " << want.str(30);
            }
        }
    }
}

// ------------------------------------------------------ (4) SWIFT, GADGET-4
const std::vector<std::string> three_d_kernels{"wendland:k=1", "wendland:k=2",  "wendland:k=3",
                                               "cubic-spline", "mollifier:M=4", "combo:m=2,base=wendland:k=2"};

TEST(Softening, SwiftPlummerEquivalentWendlandC2) {
    // peers.md (SWIFT kernel_gravity.h): phi = m W(u)/H, H = 3 eps, W(0) = -3, so D_soft_1(0) = -W(0) = 3.
    const ExactKernel k = kernel({"wendland:k=1", 3});
    EXPECT_EQ(value_at(swift_d_soft(k).front().pieces.front(), Q(0)), Exact(Q(3)));
    // The same through the query grammar.
    EXPECT_EQ(value_at(query(k, "d_soft:1").pieces.front(), Q(0)), Exact(Q(3)));
}

TEST(Softening, GadgetPlummerEquivalentCubicSpline) {
    // peers.md (GADGET-4 gravtree_build.cc): h = 2.8 eps, the potential at 0 that of a Plummer sphere,
    // -m/eps: g(0) = 1/eps = 2.8/h, so fac0(0) = 14/5 with h = 1.
    const ExactKernel k = kernel({"cubic-spline", 3});
    EXPECT_EQ(value_at(gadget_gfactors(k).front().pieces.front(), Q(0)), Exact(Q(14, 5)));
}

Radial over_r(const Radial& f, int times = 1) { return f.times(Laurent::monomial(Q(1), -times)); }

TEST(Softening, SwiftRecursionAndTensorFactors) {
    for (const std::string& spec : three_d_kernels) {
        SCOPED_TRACE(spec);
        const ExactKernel k = kernel({spec, 3});
        const std::vector<Radial> D = swift_d_soft(k);
        ASSERT_EQ(D.size(), 6u);
        // D_soft_1 = -W, W = 4 pi phi.
        EXPECT_TRUE(D[0] == potential(k.W, 3) * Exact::pi_power(Q(-4), 1));
        // peers.md: D_soft_{n+1} = D_soft_n' - (n-1) D_soft_n / u (index i = n - 1).
        for (int n = 1; n < 6; ++n)
            EXPECT_TRUE(D[n] == D[n - 1].derivative() - over_r(D[n - 1]) * Exact(Q(n - 1))) << "n = " << n;
        // The tensor factors T_0 = g, T_(n+1) = T_n'/r: D_soft_(n+1) = r^n T_n.
        Radial T = D[0];
        for (int n = 0; n < 6; ++n) {
            EXPECT_TRUE(D[n] == T.times(Laurent::monomial(Q(1), n))) << "n = " << n;
            T = over_r(T.derivative());
        }
        // Outside: the Newtonian (-1)^n (2n-1)!! / r^(n+1) (SWIFT's Dt_n, GADGET-4's r >= h branch).
        Q double_factorial = 1;
        for (int n = 0; n < 6; ++n) {
            if (n > 0) double_factorial *= 2 * n - 1;
            const Q sign = n % 2 ? Q(-1) : Q(1);
            EXPECT_TRUE(D[n].outside == ClosedForm(Laurent::monomial(sign * double_factorial, -(n + 1)))) << "n = " << n;
        }
    }
}

TEST(Softening, GadgetFactorsAreTheExpandedDerivativeForms) {
    // gravtree.h (struct gfactors): fac_n = sum_k c_(n,k) g^(k) / r^(n-k) with g', g'' - g'/r,
    // g''' - 3g''/r + 3g'/r^2, ... The c_(n,k) of E_n = r^n ((1/r) d/dr)^n are the reverse Bessel
    // polynomial coefficients (-1)^(n-k) (2n-k-1)! / (2^(n-k) (k-1)! (n-k)!), 1 <= k <= n
    // (n = 5: 105, -105, 45, -10, 1 as GADGET-4 prints).
    for (const std::string& spec : three_d_kernels) {
        SCOPED_TRACE(spec);
        const ExactKernel k = kernel({spec, 3});
        const std::vector<Radial> fac = gadget_gfactors(k);
        ASSERT_EQ(fac.size(), 6u);
        std::vector<Radial> g{softened_inverse_distance(k)};
        for (int n = 1; n <= 5; ++n) g.push_back(g.back().derivative());
        EXPECT_TRUE(fac[0] == g[0]);
        for (int n = 1; n <= 5; ++n) {
            Radial want = g[n] * Exact(Q(0));
            for (int j = 1; j <= n; ++j) {
                const Q sign = (n - j) % 2 ? Q(-1) : Q(1);
                const Q c = sign * Q(factorial(2 * n - j - 1)) /
                            (pow(Q(2), n - j) * Q(factorial(j - 1)) * Q(factorial(n - j)));
                want = want + over_r(g[j], n - j) * Exact(c);
            }
            EXPECT_TRUE(fac[n] == want) << "n = " << n;
        }
        const std::vector<Radial> D = swift_d_soft(k);
        for (int n = 0; n <= 5; ++n) EXPECT_TRUE(fac[n] == D[n]) << "fac" << n << " = D_soft_" << n + 1;
    }
}

TEST(Softening, CertifiedBundleForTheWriters) {
    for (const Case& c : polynomial_cases()) {
        SCOPED_TRACE(name(c));
        const ExactKernel k = kernel(c);
        const Softening s = certified_softening(k);
        ASSERT_EQ(s.derivatives.size(), 7u);
        EXPECT_TRUE(s.derivatives[6] == softening_derivatives(k)[6]);
        if (c.dim == 3) {
            ASSERT_EQ(s.multipole.size(), 6u);
            for (int n = 0; n < 6; ++n) EXPECT_TRUE(s.multipole[n] == swift_d_soft(k)[n]);
        } else {
            EXPECT_TRUE(s.multipole.empty());
        }
        EXPECT_EQ(s.smoothness.guaranteed, std::min(k.claims.smoothness + 2, 6));
    }
}

// Phantom's dphidh (peers.md: -phi - q dphi/dq) is d/dh of phi_h = phi(r/h)/h
// at h = 1. Independent check: Delta phi_h = W_h = W(r/h)/h^3, so
// Delta (d phi_h/dh) = d W_h/dh = -(3 W + r W') at h = 1; with the exterior 0
// (the Green's function does not depend on h) that determines it. Phantom's own
// relation dphidh0 = dphidh(0) = -phi(0) too.
TEST(Softening, PhantomDphidh) {
    for (const std::string& spec : three_d_kernels) {
        SCOPED_TRACE(spec);
        const ExactKernel k = kernel({spec, 3});
        const Radial d = softening_h_derivative(k);
        EXPECT_TRUE(d.outside.is_zero());
        const Radial dW_dh = (k.W * Exact(Q(3)) + k.W.derivative().times(Laurent::monomial(Q(1), 1))) * Exact(Q(-1));
        EXPECT_TRUE(radial_laplacian(d, 3) == dW_dh);
        const Radial phi = potential(k.W, 3);
        EXPECT_EQ(value_at(d.pieces.front(), Q(0)), -value_at(phi.pieces.front(), Q(0)));
        EXPECT_TRUE(query(k, "dphidh") == d);
    }
}

// ------------------------------------------------------------- (5) errors
std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(Softening, BadOrdersAreNamed) {
    const ExactKernel k = kernel({"wendland:k=2", 3});
    EXPECT_NE(error_of([&] { softening_derivatives(k, 7); }).find("softening order 7 is outside 0..6"), std::string::npos);
    EXPECT_NE(error_of([&] { softening_derivatives(k, -1); }).find("softening order -1 is outside 0..6"), std::string::npos);
    EXPECT_NE(error_of([&] { swift_d_soft(k, 7); }).find("D_soft order 7 is outside 1..6"), std::string::npos);
    EXPECT_NE(error_of([&] { swift_d_soft(k, 0); }).find("D_soft order 0 is outside 1..6"), std::string::npos);
    EXPECT_NE(error_of([&] { gadget_gfactors(k, 6); }).find("g-factor order 6 is outside 0..5"), std::string::npos);
    EXPECT_NE(error_of([&] { query(k, "softening:7"); }).find("softening order 7"), std::string::npos);
    EXPECT_NE(error_of([&] { query(k, "softening:-1"); }).find("softening order -1"), std::string::npos);
    EXPECT_NE(error_of([&] { query(k, "softening:2x"); }).find("order '2x' is not an integer"), std::string::npos);
    EXPECT_NE(error_of([&] { query(k, "softening:"); }).find("order '' is not an integer"), std::string::npos);
    EXPECT_NE(error_of([&] { query(k, "smoothing:2"); }).find("unknown quantity 'smoothing:2'"), std::string::npos);
    EXPECT_NE(error_of([&] { swift_d_soft(kernel({"wendland:k=2", 2})); }).find("D = 2"), std::string::npos);
    EXPECT_NE(error_of([&] { softening_h_derivative(kernel({"wendland:k=2", 2})); }).find("D = 2"), std::string::npos);
    EXPECT_NE(error_of([&] { softening_derivatives(kernel({"box-d1", 1})); }).find("no Poisson potential"),
              std::string::npos);
}

TEST(Softening, QueryNamesListEveryFamilyOnce) {
    const std::string names = query_names();
    for (const auto& f : ordered_families())
        EXPECT_NE(names.find(f.name + ":" + std::to_string(f.low) + ".." + std::to_string(f.high)), std::string::npos);
    // The tabulated names still resolve through the one entry point.
    const ExactKernel k = kernel({"wendland:k=2", 3});
    EXPECT_TRUE(query(k, "potential") == query(k, "softening:0"));
    EXPECT_TRUE(query(k, "dpotential") == query(k, "softening:1"));
}

}  // namespace
}  // namespace mollify::gen
