// Anderson's compact polynomial mollifiers (seed 000, C. R. Anderson,
// "Compact Polynomial Mollifiers for Poisson's Equation", UCLA CAM 14-43).
//
// Reference values are derived here, never copied from Anderson's tables
// (Tables 1-8 contain sign misprints; see ExponentMethodOrderFourClosedForm).
// The polynomial arithmetic used for the references (integration over
// [0, 1], derivatives at r = 1, division by (1 - r^2)) is written in this
// file on plain coefficient vectors, independently of Laurent.
//
// Conventions (README): support radius 1, unit mass over R^D, sphere measure
// omega_1 = 2, omega_2 = 2 pi, omega_3 = 4 pi. Note that Anderson's §2 says
// omega_1 = 1, which conflicts with his Theorem 1 (1/sigma = int_0^1 r^(N-1)
// (1-r^2)^M dr, i.e. omega_1 = 2); we follow Theorem 1.
#include "anderson.hpp"
#include "kernel.hpp"
#include "linear_solve.hpp"
#include "spec.hpp"
#include "reference_poly.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mollify::gen {
namespace {

using namespace reference;

std::string mollifier(int M, int order = 2) {
    return "mollifier:M=" + std::to_string(M) + (order == 2 ? "" : ",order=" + std::to_string(order));
}

Exact omega(int D) { return Exact::pi_power(omega_rational(D), omega_pi(D)); }

Z pow2(int n) {
    Z p = 1;
    for (int i = 0; i < n; ++i) p *= 2;
    return p;
}

Laurent to_laurent(const Poly& p) {
    Laurent l;
    for (std::size_t i = 0; i < p.size(); ++i) l += Laurent::monomial(p[i], static_cast<int>(i));
    return l;
}

Poly add(Poly a, const Poly& b, const Q& s = Q(1)) {
    if (a.size() < b.size()) a.resize(b.size(), Q(0));
    for (std::size_t i = 0; i < b.size(); ++i) a[i] += s * b[i];
    return a;
}

Poly t_power(int n) {  // (1 - r^2)^n
    Poly p{Q(1)};
    for (int i = 0; i < n; ++i) p = mul(p, Poly{Q(1), Q(0), Q(-1)});
    return p;
}

// p / (r - root) by synthetic division; false when the remainder is not 0.
bool divide_by_linear(Poly& p, const Q& root) {
    if (p.empty()) return true;
    Poly q(p.size() - 1, Q(0));
    Q carry = 0;
    for (std::size_t i = p.size(); i-- > 1;) {
        carry = p[i] + carry * root;
        q[i - 1] = carry;
    }
    if (p[0] + carry * root != 0) return false;
    p = q;
    return true;
}

// The kernel's single polynomial piece on [0, 1] as pi^pi_power * p(r); the
// kernel must vanish outside.
Poly polynomial_of(const Radial& W, int* pi_power) {
    EXPECT_EQ(W.breaks, (std::vector<Q>{Q(0), Q(1)}));
    EXPECT_TRUE(W.outside.is_zero());
    Laurent l;
    Atom a;
    EXPECT_TRUE(W.pieces.at(0).single_polynomial(&l, &a)) << "W is not q pi^e p(r)";
    EXPECT_EQ(a.log_of, 1);
    *pi_power = a.pi_power;
    Poly p;
    EXPECT_TRUE(l.is_polynomial());
    for (int i = 0; i <= l.high() && !l.is_zero(); ++i) p.push_back(l.coefficient(i));
    return p;
}

// 1/sigma_{M(D)} = int_0^1 r^(D-1) (1-r^2)^M dr = B(D/2, M+1)/2 (t = r^2). In
// closed form with factorials (Gamma(M + 1 + D/2) expanded for half-integers):
//   D = 1: B(1/2, M+1)/2 = 2^(2M) (M!)^2 / (2M+1)!
//   D = 2: B(1, M+1)/2   = 1/(2(M+1))
//   D = 3: B(3/2, M+1)/2 = 2^(2M+1) M! (M+1)! / (2M+3)!
// (M = 1: 2/3, 1/4, 2/15, matching int (1-r^2), int r(1-r^2), int r^2(1-r^2)).
Q sigma(int M, int D) {
    switch (D) {
        case 1: return Q(fact(2 * M + 1), pow2(2 * M) * fact(M) * fact(M));
        case 2: return Q(2 * (M + 1));
        default: return Q(fact(2 * M + 3), pow2(2 * M + 1) * fact(M) * fact(M + 1));
    }
}

// (a) Anderson's Theorem 1, eqs. (15)-(17): p(r) = sum_{k=0}^M c_k r^(2k) with
//   int_{unit ball} p = omega_D sum_k c_k / (D + 2k) = 1                   (16)
//   d^q p/dr^q (1) = sum_k (2k)(2k-1)...(2k-q+1) c_k = 0, q = 0..M-1      (17)
// Unknowns c'_k = omega_D c_k keep the system rational. Returns c' as a
// polynomial in r. The tests break the system through `dim_row` (the
// dimension used in (16)) and `last_q` (the highest derivative condition:
// M-1 is Anderson's; M replaces q = M-1 by q = M).
Poly theorem_one(int M, int dim_row, int last_q) {
    const std::size_t n = static_cast<std::size_t>(M) + 1;
    Matrix A(n, std::vector<Q>(n, Q(0)));
    std::vector<Q> b(n, Q(0));
    for (int k = 0; k <= M; ++k) A[0][static_cast<std::size_t>(k)] = Q(1, dim_row + 2 * k);
    b[0] = 1;
    std::vector<int> qs;
    for (int q = 0; q + 1 < M; ++q) qs.push_back(q);
    qs.push_back(last_q);
    for (std::size_t row = 1; row < n; ++row) {
        const int q = qs[row - 1];
        for (int k = 0; k <= M; ++k) {
            Q falling = 1;  // d^q/dr^q r^(2k) at r = 1
            for (int s = 0; s < q; ++s) falling *= 2 * k - s;
            A[row][static_cast<std::size_t>(k)] = falling;
        }
    }
    const std::vector<Q> c = solve(A, b);
    Poly p(2 * n - 1, Q(0));
    for (std::size_t k = 0; k < n; ++k) p[2 * k] = c[k];
    return p;
}

TEST(Anderson, TheoremOneDeterminesTheMollifier) {
    for (int D = 1; D <= 3; ++D)
        for (int M = 1; M <= 9; ++M) {
            const Poly c = theorem_one(M, D, M - 1);
            const ExactKernel k = kernel(mollifier(M), D);
            // W = omega_D^-1 sum_k c'_k r^(2k), as an exact radial function.
            const Radial expected = Radial::single(ClosedForm(to_laurent(c))) * omega(D).inverse();
            EXPECT_TRUE(k.W == expected) << "D = " << D << ", M = " << M;
            int e = 0;
            const Poly w = polynomial_of(k.W, &e);
            EXPECT_EQ(e, -omega_pi(D));
            Poly scaled;
            for (const Q& x : w) scaled.push_back(x * omega_rational(D));
            EXPECT_EQ(scaled, c) << "D = " << D << ", M = " << M;
            // Theorem 1, (18): the solution is sigma_{M(D)}/omega_D (1-r^2)^M.
            Poly t = t_power(M);
            for (Q& x : t) x *= sigma(M, D);
            EXPECT_EQ(c, t) << "D = " << D << ", M = " << M;
        }
}

// The comparison above can fail: the system set up for another dimension,
// or with the last derivative condition (q = M-1) replaced by q = M, has a
// different solution (Lemma 1: conditions (17) are what force (1-r^2)^M).
TEST(Anderson, TheoremOneDetectsAWrongSystem) {
    for (int M = 2; M <= 9; ++M) {
        const ExactKernel k = kernel(mollifier(M), 3);
        const Radial wrong_dim = Radial::single(ClosedForm(to_laurent(theorem_one(M, 2, M - 1)))) * omega(3).inverse();
        EXPECT_FALSE(k.W == wrong_dim) << "M = " << M;
        const Radial wrong_q = Radial::single(ClosedForm(to_laurent(theorem_one(M, 3, M)))) * omega(3).inverse();
        EXPECT_FALSE(k.W == wrong_q) << "M = " << M;
    }
}

// (b) W(0) omega_D = sigma_{M(D)}: 2(M+1) in 2D, 1/int_0^1 r^2 (1-r^2)^M dr in 3D
// (see sigma() for the Beta-function derivation), and 1/int_0^1 (1-r^2)^M dr in 1D.
TEST(Anderson, NormalisationSigma) {
    for (int M = 1; M <= 9; ++M) {
        for (int D = 1; D <= 3; ++D) {
            const ExactKernel k = kernel(mollifier(M), D);
            EXPECT_EQ(k.W.at(Q(0)) * omega(D), Exact(sigma(M, D))) << "D = " << D << ", M = " << M;
            EXPECT_EQ(k.normalisation, Exact::pi_power(sigma(M, D) / omega_rational(D), -omega_pi(D)));
            // Cross-check of the Beta closed form by direct integration here.
            EXPECT_EQ(sigma(M, D), Q(1) / integral01(t_power(M), D - 1)) << "D = " << D << ", M = " << M;
        }
        EXPECT_EQ(sigma(M, 2), Q(2 * (M + 1)));
    }
    // A perturbed reference is rejected (e.g. a 1D value computed with
    // Anderson's omega_1 = 1 instead of 2).
    EXPECT_NE(kernel(mollifier(3), 1).W.at(Q(0)), Exact(sigma(3, 1)));
    EXPECT_NE(kernel(mollifier(3), 3).W.at(Q(0)) * omega(3), Exact(sigma(3, 3) + pow(Q(10), -30)));
}

// (c) Anderson §2 second moments. Radial symmetry gives int x_i^2 B = (1/D) int |x|^2 B,
// and with t = r^2, int_0^1 r^a (1-r^2)^M dr = B((a+1)/2, M+1)/2, so
//   int x_i^2 B = (1/D) B(D/2 + 1, M+1) / B(D/2, M+1) = (1/D) (D/2)/(M + 1 + D/2) = 1/(2M + 2 + D):
//   D = 2: 1/(2(M+2)),   D = 3: 1/(2M+5) (Anderson prints 1/(2(M+2)+1)),   D = 1: 1/(2M+3).
TEST(Anderson, SecondMoments) {
    for (int M = 1; M <= 9; ++M) {
        const Exact m2 = radial_moment(kernel(mollifier(M), 2), 2) * Q(1, 2);
        const Exact m3 = radial_moment(kernel(mollifier(M), 3), 2) * Q(1, 3);
        const Exact m1 = radial_moment(kernel(mollifier(M), 1), 2) * Q(1, 1);
        EXPECT_EQ(m2, Exact(Q(1, 2 * (M + 2)))) << "M = " << M;
        EXPECT_EQ(m3, Exact(Q(1, 2 * M + 5))) << "M = " << M;
        EXPECT_EQ(m1, Exact(Q(1, 2 * M + 3))) << "M = " << M;
        for (int D = 1; D <= 3; ++D)  // the same by integration here
            EXPECT_EQ(integral01(t_power(M), D + 1) / integral01(t_power(M), D - 1) / D, Q(1, 2 * M + 2 + D));
        // Detects a wrong reference: the 2D value in 3D.
        EXPECT_NE(m3, Exact(Q(1, 2 * (M + 2))));
    }
}

// (d) The exponent method (Anderson (11)-(12)): B = sum_{j<K} beta_j (1-r^2)^(M+j),
// order 2K. Checked directly: unit mass, radial moments |x|^2 .. |x|^(2K-2) zero
// and |x|^(2K) non-zero (integrated here), the factor (1-r^2)^M with a cofactor
// that is a polynomial of degree < K in (1-r^2) and does not vanish at r = 1,
// so derivatives 0..M-1 vanish at r = 1 and the M-th does not. These conditions
// determine the beta_j (K unknowns, K independent linear conditions), so they
// pin the kernel down completely.
void check_exponent_method(int M, int order, int D) {
    const std::string what = mollifier(M, order) + " in D = " + std::to_string(D);
    SCOPED_TRACE(what);
    const ExactKernel k = kernel(mollifier(M, order), D);
    const int K = order / 2;
    int e = 0;
    const Poly w = polynomial_of(k.W, &e);
    ASSERT_EQ(e, -omega_pi(D));
    for (std::size_t i = 1; i < w.size(); i += 2) EXPECT_EQ(w[i], 0) << "odd power r^" << i;
    // Moments, with omega_D = omega_rational * pi^omega_pi cancelling pi^e.
    EXPECT_EQ(omega_rational(D) * integral01(w, D - 1), Q(1));
    EXPECT_EQ(radial_moment(k, 0), Exact(Q(1)));
    for (int j = 1; j < K; ++j) {
        EXPECT_EQ(integral01(w, D - 1 + 2 * j), Q(0)) << "moment |x|^" << 2 * j;
        EXPECT_TRUE(radial_moment(k, 2 * j).is_zero()) << "moment |x|^" << 2 * j;
    }
    EXPECT_NE(integral01(w, D - 1 + 2 * K), Q(0)) << "moment |x|^" << 2 * K;
    EXPECT_FALSE(radial_moment(k, 2 * K).is_zero());
    // Factor (1-r^2)^M = (1-r)^M (1+r)^M.
    Poly cofactor = w;
    for (int i = 0; i < M; ++i) {
        ASSERT_TRUE(divide_by_linear(cofactor, Q(1))) << "no factor (1-r)^" << i + 1;
        ASSERT_TRUE(divide_by_linear(cofactor, Q(-1))) << "no factor (1+r)^" << i + 1;
    }
    EXPECT_NE(at(cofactor, Q(1)), 0) << "cofactor vanishes at r = 1: smoother than claimed";
    EXPECT_LE(static_cast<int>(cofactor.size()), 2 * K - 1) << "cofactor of degree >= K in (1-r^2)";
    Poly d = w;
    for (int q = 0; q < M; ++q) {
        EXPECT_EQ(at(d, Q(1)), 0) << "derivative " << q << " at r = 1";
        d = deriv(d);
    }
    EXPECT_NE(at(d, Q(1)), 0) << "derivative " << M << " at r = 1";
    EXPECT_EQ(k.claims.order, order);
    EXPECT_EQ(k.claims.smoothness, M - 1);
    // exponent_method() itself: alpha_0 = 1 and W = normalisation * sum alpha_j (1-r^2)^(M+j).
    const ExponentMethod em = exponent_method(M, order, D);
    ASSERT_EQ(static_cast<int>(em.alpha.size()), K);
    EXPECT_EQ(em.alpha[0], Q(1));
    Poly sum;
    for (int j = 0; j < K; ++j) sum = add(sum, t_power(M + j), em.alpha[static_cast<std::size_t>(j)]);
    EXPECT_TRUE(k.W == Radial::single(ClosedForm(to_laurent(sum))) * em.normalisation);
}

TEST(Anderson, ExponentMethodOrdersFourAndSix) {
    for (int order : {4, 6})
        for (int D = 1; D <= 3; ++D)
            for (int M = 1; M <= 9; ++M) check_exponent_method(M, order, D);
}

// Hard cases: M = 9 with orders up to the largest allowed (large alternating
// coefficients), and the largest M. (M = 64 with order 20 works too but takes
// about a second; it adds nothing the cases here do not exercise.)
TEST(Anderson, ExponentMethodHighOrders) {
    for (int D = 1; D <= 3; ++D) {
        for (int order : {8, 12, 16, max_mollifier_order}) check_exponent_method(9, order, D);
        check_exponent_method(max_mollifier_M, 6, D);
    }
}

// Order 4 in closed form. With J(n) = int_0^1 r^(D-1) (1-r^2)^n dr and r^2 = 1 - t,
// int_0^1 r^(D+1) t^n dr = J(n) - J(n+1), and J(n+1)/J(n) = (n+1)/(n+1+D/2)
// (Beta recursion). The |x|^2 condition beta_0 (J(M) - J(M+1)) + beta_1 (J(M+1) - J(M+2)) = 0
// gives alpha_1 = beta_1/beta_0 = -(M + 2 + D/2)/(M + 1) = -(2M + 4 + D)/(2M + 2), and unit
// mass gamma (J(M) + alpha_1 J(M+1)) = 1 gives gamma = -(M + 1 + D/2) sigma_{M(D)}, where
// B = gamma/omega_D (1-r^2)^M (1 + alpha_1 (1-r^2)).
TEST(Anderson, ExponentMethodOrderFourClosedForm) {
    for (int D = 1; D <= 3; ++D)
        for (int M = 1; M <= 9; ++M) {
            const ExponentMethod em = exponent_method(M, 4, D);
            const Q alpha1(-(2 * M + 4 + D), 2 * M + 2);
            const Q gamma = -(Q(M + 1) + Q(D, 2)) * sigma(M, D);
            ASSERT_EQ(em.alpha.size(), 2u);
            EXPECT_EQ(em.alpha[1], alpha1) << "D = " << D << ", M = " << M;
            EXPECT_EQ(em.normalisation, Exact::pi_power(gamma / omega_rational(D), -omega_pi(D)))
                << "D = " << D << ", M = " << M;
        }
    // Deliberately wrong inputs are rejected: sign-flipped alpha_1 (which is what
    // Anderson's Tables 5, 7 and 3 print for 2D M = 1, 3D M = 7 and 1D M = 9).
    EXPECT_NE(exponent_method(1, 4, 2).alpha[1], Q(2));
    EXPECT_EQ(exponent_method(1, 4, 2).alpha[1], Q(-2));
    EXPECT_NE(exponent_method(7, 4, 3).alpha[1], Q(21, 16));
    EXPECT_EQ(exponent_method(7, 4, 3).alpha[1], Q(-21, 16));
    EXPECT_NE(exponent_method(9, 4, 1).alpha[1], Q(23, 20));
    EXPECT_EQ(exponent_method(9, 4, 1).alpha[1], Q(-23, 20));
}

// (e) Anderson App. B, fourth order, M = 4:
//   2D: B = -60/(2 pi) (1-r^2)^4 (1 - 7/5 (1-r^2))
//   3D: B = -45045/256 / (4 pi) (1-r^2)^4 (1 - 3/2 (1-r^2))
// Verified: the closed form above gives alpha_1 = -(8+4+2)/10 = -7/5 and
// gamma = -(5+1) * 10 = -60 in 2D; alpha_1 = -(8+4+3)/10 = -3/2 and
// gamma = -(5 + 3/2) * 3465/128 = -45045/256 in 3D (sigma_{4(3)} = 9!/(2^9 4! 5!) = 3465/128).
// Directly in 2D: int_0^1 r t^n dr = 1/(2(n+1)), int_0^1 r^3 t^n dr = 1/(2(n+1)(n+2));
// the r^2 condition beta_0/60 + beta_1/84 = 0 gives beta_1 = -7/5 beta_0, and
// unit mass beta_0 (1/10 - 7/60) = -beta_0/60 = 1 gives beta_0 = -60.
Radial appendix_b(const Q& gamma, int D, const Q& alpha1) {
    const Poly p = add(t_power(4), t_power(5), alpha1);  // t^4 (1 + alpha1 t)
    return Radial::single(ClosedForm(to_laurent(p))) * Exact::pi_power(gamma / omega_rational(D), -1);
}

TEST(Anderson, AppendixBFourthOrderM4) {
    const ExactKernel k2 = kernel("mollifier:M=4,order=4", 2);
    const ExactKernel k3 = kernel("mollifier:M=4,order=4", 3);
    EXPECT_TRUE(k2.W == appendix_b(Q(-60), 2, Q(-7, 5)));
    EXPECT_TRUE(k3.W == appendix_b(Q(-45045, 256), 3, Q(-3, 2)));
    // Perturbed prefactor or coefficient: must not match.
    EXPECT_FALSE(k2.W == appendix_b(Q(-50), 2, Q(-7, 5)));
    EXPECT_FALSE(k2.W == appendix_b(Q(-60), 2, Q(-3, 2)));
    EXPECT_FALSE(k3.W == appendix_b(Q(-45045, 256), 3, Q(-7, 5)));
    // App. B, second order M = 4: 10/(2 pi) (1-r^2)^4 in 2D (sigma_{4(2)} = 10).
    EXPECT_TRUE(kernel("mollifier:M=4", 2).W ==
                Radial::single(ClosedForm(to_laurent(t_power(4)))) * Exact::pi_power(Q(10, 2), -1));
}

}  // namespace
}  // namespace mollify::gen
