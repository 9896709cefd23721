// Weights of high-order combinations Phi = sum_j w_j psi_{a_j} (Franz 2019,
// Prop. 4.24 and the remark after Lemma 4.25; Anderson 2014 eqs. (9)-(10)).
//
// The defining property is the moment system (Franz (4.19) with
// w_j = lambda_j a_j^d / c_0):
//     sum_j w_j a_j^(2k) = [k = 0],   k = 0 .. m-1.
// Every test below checks that system *directly*, with loops written here,
// so none of the three generator routines (product formula, elimination,
// equidistant closed form) is trusted to check another.
#include "error.hpp"
#include "kernel.hpp"
#include "quantities.hpp"
#include "vandermonde.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mollify::gen {
namespace {

std::vector<Q> radii_of(std::initializer_list<Q> r) { return std::vector<Q>(r); }

std::vector<Q> equidistant(int m) {
    std::vector<Q> a;
    for (int j = 1; j <= m; ++j) a.emplace_back(j, m);
    return a;
}

// sum_j w_j a_j^(2k), computed here by repeated multiplication.
Q moment(const std::vector<Q>& w, const std::vector<Q>& a, int k) {
    Q s = 0;
    for (std::size_t j = 0; j < w.size(); ++j) {
        Q p = 1;
        for (int i = 0; i < 2 * k; ++i) p *= a[j];
        s += w[j] * p;
    }
    return s;
}

// Empty string when the moment equations hold exactly, else the first failure.
std::string moment_equations_failure(const std::vector<Q>& w, const std::vector<Q>& a) {
    if (w.size() != a.size()) return "size mismatch";
    for (int k = 0; k < static_cast<int>(a.size()); ++k) {
        const Q want = k == 0 ? Q(1) : Q(0);
        const Q got = moment(w, a, k);
        if (got != want) return "k = " + std::to_string(k) + ": sum w_j a_j^(2k) = " + short_string(got);
    }
    return "";
}

std::string show(const std::vector<Q>& v) {
    std::string s = "(";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + short_string(v[i]);
    return s + ")";
}

TEST(Vandermonde, ThreeMethodsAgreeForEquidistantRadii) {
    for (int m = 1; m <= 12; ++m) {
        const std::vector<Q> a = equidistant(m);
        const std::vector<Q> product = vandermonde_weights(a);
        const std::vector<Q> elimination = vandermonde_weights_by_solve(a);
        const std::vector<Q> closed = equidistant_weights(m);
        EXPECT_EQ(product, elimination) << "m = " << m << ": " << show(product) << " vs " << show(elimination);
        EXPECT_EQ(product, closed) << "m = " << m << ": " << show(product) << " vs " << show(closed);
        EXPECT_EQ(moment_equations_failure(product, a), "") << "m = " << m;
    }
}

// Franz, after Lemma 4.25: w_j = (-1)^(j-1) 2 (m!)^2 / ((m+j)! (m-j)!), so
// w_{j+1}/w_j = -(m-j)/(m+j+1): the signs alternate and |w_j| strictly
// decreases with j (a_j^0 = 1, so |w_j a_j^0| = |w_j|).
TEST(Vandermonde, EquidistantWeightsAlternateAndDecrease) {
    for (int m = 1; m <= 12; ++m) {
        const std::vector<Q> w = vandermonde_weights(equidistant(m));
        ASSERT_EQ(static_cast<int>(w.size()), m);
        EXPECT_GT(w[0], 0) << "m = " << m;
        for (int j = 0; j + 1 < m; ++j) {
            EXPECT_LT(w[j] * w[j + 1], 0) << "m = " << m << ", j = " << j + 1;
            EXPECT_GT(abs(w[j]), abs(w[j + 1])) << "m = " << m << ", j = " << j + 1;
            EXPECT_EQ(w[j + 1] / w[j], Q(-(m - j - 1), m + j + 2)) << "m = " << m << ", j = " << j + 1;
        }
    }
}

// Anderson (9) and (10). From the product formula w_j = prod_{k != j} a_k^2/(a_k^2 - a_j^2):
//   radii (1/2, 1):      w(1/2) = 1/(1 - 1/4) = 4/3,  w(1) = (1/4)/(1/4 - 1) = -1/3;
//   radii (1/3, 2/3, 1): w(1/3) = (4/9)/(4/9 - 1/9) * 1/(1 - 1/9) = 4/3 * 9/8 = 3/2,
//                        w(2/3) = (1/9)/(1/9 - 4/9) * 1/(1 - 4/9) = -1/3 * 9/5 = -3/5,
//                        w(1)   = (1/9)/(1/9 - 1) * (4/9)/(4/9 - 1) = -1/8 * -4/5 = 1/10.
// So Anderson's printed weights -1/3 B(r) + 4/3 B(r/2) and
// 1/10 B(r) - 3/5 B(2r/3) + 3/2 B(r/3) are right (B(gamma r) denoting the
// member of radius gamma).
TEST(Vandermonde, AndersonFourthAndSixthOrderWeights) {
    const std::vector<Q> a4 = radii_of({Q(1, 2), Q(1)});
    const std::vector<Q> want4 = radii_of({Q(4, 3), Q(-1, 3)});
    EXPECT_EQ(vandermonde_weights(a4), want4);
    EXPECT_EQ(vandermonde_weights_by_solve(a4), want4);
    EXPECT_EQ(moment_equations_failure(want4, a4), "");

    const std::vector<Q> a6 = radii_of({Q(1, 3), Q(2, 3), Q(1)});
    const std::vector<Q> want6 = radii_of({Q(3, 2), Q(-3, 5), Q(1, 10)});
    EXPECT_EQ(vandermonde_weights(a6), want6);
    EXPECT_EQ(vandermonde_weights_by_solve(a6), want6);
    EXPECT_EQ(moment_equations_failure(want6, a6), "");
}

TEST(Vandermonde, IrregularRadii) {
    const std::vector<std::vector<Q>> sets = {
        radii_of({Q(1, 7), Q(3, 10), Q(1)}),
        radii_of({Q(1, 1000), Q(1, 999), Q(1)}),  // nearly repeated: huge, exactly cancelling weights
        radii_of({Q(1, 5), Q(1, 2), Q(3, 4), Q(1)}),
        radii_of({Q(1), Q(1, 3), Q(2, 3)}),  // unsorted: the formulas do not need order
        radii_of({Q(2), Q(3)}),              // radii above 1: still a valid system
    };
    for (const auto& a : sets) {
        const std::vector<Q> product = vandermonde_weights(a);
        EXPECT_EQ(product, vandermonde_weights_by_solve(a)) << show(a);
        EXPECT_EQ(moment_equations_failure(product, a), "") << show(a);
    }
    // (1/7, 3/10, 1) by hand: a^2 = 1/49, 9/100, 1.
    //   w(1/7)  = (9/100)/(9/100 - 1/49) * 1/(1 - 1/49) = (441/341) * (49/48) = 21609/16368 = 7203/5456
    //   w(3/10) = (1/49)/(1/49 - 9/100) * 1/(1 - 9/100) = (-100/341) * (100/91) = -10000/31031
    //   w(1)    = (1/49)/(1/49 - 1) * (9/100)/(9/100 - 1) = (-1/48) * (-9/91) = 3/1456
    EXPECT_EQ(vandermonde_weights(sets[0]), radii_of({Q(7203, 5456), Q(-10000, 31031), Q(3, 1456)}));
    // Permuting the radii permutes the weights.
    const std::vector<Q> sorted = vandermonde_weights(radii_of({Q(1, 3), Q(2, 3), Q(1)}));
    const std::vector<Q> permuted = vandermonde_weights(sets[3]);
    EXPECT_EQ(permuted, radii_of({sorted[2], sorted[0], sorted[1]}));
}

TEST(Vandermonde, MomentMatrixRows) {
    const std::vector<Q> a = radii_of({Q(1, 3), Q(2, 3), Q(1)});
    const Matrix A = moment_matrix(a);
    ASSERT_EQ(A.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_EQ(A[k].size(), 3u);
        for (std::size_t j = 0; j < 3; ++j) {
            Q p = 1;
            for (std::size_t i = 0; i < 2 * k; ++i) p *= a[j];
            EXPECT_EQ(A[k][j], p) << "row " << k << ", column " << j;
        }
    }
}

// The check above can fail: a weight perturbed by 10^-30, or a misprinted
// Anderson weight, violates the moment equations.
TEST(Vandermonde, PerturbedWeightsAreDetected) {
    const std::vector<Q> a = equidistant(6);
    std::vector<Q> w = vandermonde_weights(a);
    ASSERT_EQ(moment_equations_failure(w, a), "");
    w[3] += pow(Q(10), -30);
    EXPECT_NE(moment_equations_failure(w, a), "");

    // Keep the mass (k = 0) but break a higher moment.
    std::vector<Q> v = vandermonde_weights(a);
    v[0] += pow(Q(10), -30);
    v[5] -= pow(Q(10), -30);
    EXPECT_EQ(moment(v, a, 0), Q(1));
    EXPECT_NE(moment_equations_failure(v, a), "");

    const std::vector<Q> a6 = radii_of({Q(1, 3), Q(2, 3), Q(1)});
    EXPECT_NE(moment_equations_failure(radii_of({Q(3, 2), Q(-3, 5), Q(1, 9)}), a6), "");
    EXPECT_NE(vandermonde_weights(a6), radii_of({Q(3, 2), Q(-3, 5), Q(1, 9)}));
}

// Errors name the offending value.
void expect_error_mentioning(const std::vector<Q>& radii, const std::string& needle) {
    for (int method = 0; method < 2; ++method) {
        try {
            if (method == 0) vandermonde_weights(radii);
            else vandermonde_weights_by_solve(radii);
            ADD_FAILURE() << "no error for radii " << show(radii) << " (method " << method << ")";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos)
                << "message '" << e.what() << "' does not mention " << needle;
        }
    }
}

// The terms the emitter factors one by one (combo_terms): w_j psi_{a_j},
// psi_{a_j} of unit mass with support a_j, sum exactly to the combination,
// and so do their potentials (sum_j w_j = 1: the Green's functions add up).
TEST(Vandermonde, ComboTermsSumToTheCombination) {
    for (const char* text : {"combo:m=3,base=wendland:k=2,l=1", "combo:radii=1/4;3/5;1,base=mollifier:M=4",
                             "combo:m=2,base=cubic-spline"})
        for (int dim = 1; dim <= 3; ++dim) {
            const ExactKernel k = make_kernel(parse_spec(text), dim);
            const std::vector<ComboTerm> terms = combo_terms(k);
            ASSERT_EQ(terms.size(), k.spec.radii.size());
            Radial W = k.W * Exact(Q(0)), phi = *derive_quantities(k).potential * Exact(Q(0));
            for (std::size_t j = 0; j < terms.size(); ++j) {
                EXPECT_EQ(terms[j].kernel.W.support(), to_q(k.spec.radii[j])) << text;
                EXPECT_EQ(radial_moment(terms[j].kernel, 0), Exact(Q(1))) << text;
                W = W + terms[j].kernel.W * Exact(terms[j].weight);
                phi = phi + *derive_quantities(terms[j].kernel).potential * Exact(terms[j].weight);
            }
            EXPECT_TRUE(W == k.W) << text << " D=" << dim;
            EXPECT_TRUE(phi == *derive_quantities(k).potential) << text << " D=" << dim;
        }
    EXPECT_TRUE(combo_terms(make_kernel(parse_spec("wendland:k=1"), 3)).empty());
}

TEST(Vandermonde, InvalidRadiiThrowNamingTheValue) {
    expect_error_mentioning(radii_of({Q(1, 3), Q(1, 3), Q(1)}), "1/3");
    expect_error_mentioning(radii_of({Q(2, 7), Q(1), Q(2, 7)}), "2/7");
    expect_error_mentioning(radii_of({Q(0), Q(1)}), "0");
    expect_error_mentioning(radii_of({Q(1, 2), Q(-1, 2), Q(1)}), "-1/2");
    expect_error_mentioning(radii_of({Q(-5, 3), Q(1)}), "-5/3");
    EXPECT_THROW(vandermonde_weights({}), Error);
    EXPECT_THROW(equidistant_weights(0), Error);
    EXPECT_THROW(equidistant_weights(-2), Error);
}

}  // namespace
}  // namespace mollify::gen
