// The naive evaluation forms common SPH codes use, for comparison with
// mollify's factored tables (tools/stability_report, bench/kernel_bench):
//
//   expanded  sum_k c_k v^k by Horner's rule on the expanded monomials
//             (SWIFT style), v = q^2 for even pieces (Anderson, poly6),
//             v = q otherwise; q = r/h computed as r * (1/h).
//   pow       the textbook factored form with std::pow:
//             sigma h^-D pow(1 - q, n) p(q) (Wendland, spiky),
//             sigma h^-D pow(1 - q^2, M) p(q^2) (Anderson, poly6);
//             a piece without a root at its upper end (the inner pieces of
//             the cubic spline and of combinations) has no such
//             factorisation and is evaluated as sum_k c_k pow(q, k).
//
// Both come from the generator's exact expanded polynomials, rounded to
// double once (naive_polynomial); no coefficient is typed anywhere. They
// exist for value W and gradient W'/r of the polynomial kernels (not for the
// missing Wendland functions, whose S P + L Q has no expanded form).
//
// Naive<N, M, P> stores the coefficients in fixed-size arrays (N expanded,
// M cofactor coefficients, P pieces) so that a benchmark's Horner loop has
// a compile-time trip count the compiler unrolls, as in a hand-written
// kernel; shorter pieces are zero-padded at the top (exact: 0 v + c = c).
#pragma once

#include <mollify/error.hpp>
#include <mollify/detail/evaluate.hpp>
#include <mollify/smoothing.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace mollify::accuracy {

enum class Form { mollify, expanded, pow };
inline constexpr Form all_forms[] = {Form::mollify, Form::expanded, Form::pow};
const char* form_name(Form f);

// One piece of a naive quantity, sizes as the generator gives them.
struct NaivePieceData {
    double lo = 0, hi = 1;  // [lo, hi) in q; the last piece is closed
    bool square = false;    // variable v = q^2 (even or odd piece), else v = q
    int low = 0;            // q^low in front (odd pieces, W'/r of non-smooth kernels, Laurent kernels)
    std::vector<double> expanded;  // c_k of v^k
    int edge_power = 0;            // pow form: (edge - v)^edge_power cofactor(v); 0: no factorisation
    double edge = 1;               // hi, or hi^2 when square
    std::vector<double> cofactor;  // coefficients of the cofactor in v
};

// A quantity (value or grad_over_r) of one kernel in the naive forms:
// f_h(r) = h^scale_power f(r/h). `why_not` is non-empty when the kernel
// has no polynomial form (then `pieces` is empty).
struct NaivePolynomial {
    std::vector<NaivePieceData> pieces;
    int scale_power = 0;
    std::string why_not;
    int max_expanded() const;  // the N and M a Naive<N, M, P> needs
    int max_cofactor() const;
};

// From the generator's exact closed forms (GMP), each coefficient correctly
// rounded. Only QuantityId::value and QuantityId::grad_over_r.
NaivePolynomial naive_polynomial(const std::string& spec, int dim, QuantityId q);

// The scale h^p (p < 0 for W and W'/r) as a naive code forms it: 1/h once,
// then |p| - 1 products, and q = r * (1/h).
struct NaiveScale {
    double inv_h = 1, scale = 1;
    NaiveScale(double h, int power) : inv_h(1 / h), scale(1) {
        for (int i = 0; i < -power; ++i) scale *= inv_h;
        for (int i = 0; i < power; ++i) scale *= h;
    }
};

template <int N, int M = N, int P = 1>
struct Naive {
    static constexpr int capacity = N, cofactor_capacity = M, piece_capacity = P;
    struct Piece {
        double hi = 1;
        bool square = false;
        int low = 0;
        int edge_power = 0;
        double edge = 1;
        int nexpanded = 0;
        std::array<double, N> expanded{};
        std::array<double, M> cofactor{};
    };
    int npieces = 0;
    int scale_power = 0;
    std::array<Piece, P> pieces{};

    // Throws mollify::Error when the polynomial does not fit (or has none).
    explicit Naive(const NaivePolynomial& p) : npieces(static_cast<int>(p.pieces.size())), scale_power(p.scale_power) {
        if (!p.why_not.empty()) fail(p.why_not);
        if (npieces > P || p.max_expanded() > N || p.max_cofactor() > M)
            fail("naive form needs " + std::to_string(p.pieces.size()) + " pieces, " +
                 std::to_string(p.max_expanded()) + " and " + std::to_string(p.max_cofactor()) +
                 " coefficients; room for " + std::to_string(P) + ", " + std::to_string(N) + ", " + std::to_string(M));
        for (int i = 0; i < npieces; ++i) {
            const NaivePieceData& d = p.pieces[static_cast<std::size_t>(i)];
            Piece& t = pieces[static_cast<std::size_t>(i)];
            t = {d.hi, d.square, d.low, d.edge_power, d.edge, static_cast<int>(d.expanded.size()), {}, {}};
            for (std::size_t k = 0; k < d.expanded.size(); ++k) t.expanded[k] = d.expanded[k];
            for (std::size_t k = 0; k < d.cofactor.size(); ++k) t.cofactor[k] = d.cofactor[k];
        }
    }

    // The piece holding q in [0, 1]: branches, as a hand-written kernel has.
    const Piece& piece(double q) const {
        for (int i = 0; i + 1 < npieces; ++i)
            if (q < pieces[static_cast<std::size_t>(i)].hi) return pieces[static_cast<std::size_t>(i)];
        return pieces[static_cast<std::size_t>(npieces - 1)];
    }
};

// Horner's rule with a compile-time trip count (unrolled).
template <std::size_t N>
inline double naive_horner(const std::array<double, N>& c, double v) {
    double sum = c[N - 1];
    for (std::size_t k = N - 1; k-- > 0;) sum = mollify::detail::mul_add(sum, v, c[k]);  // fused where the target has FMA, as -ffp-contract=fast gives naive code
    return sum;
}

// q^low by products (low is small: -3..1).
inline double naive_power(double q, int low) {
    double p = 1;
    for (int i = 0; i < low; ++i) p *= q;
    for (int i = 0; i < -low; ++i) p /= q;
    return p;
}

// f(q), 0 <= q <= 1, from expanded monomials.
template <int N, int M, int P>
inline double expanded_form(const Naive<N, M, P>& f, double q) {
    const auto& t = f.piece(q);
    double x = naive_horner(t.expanded, t.square ? q * q : q);
    if (t.low != 0) x *= naive_power(q, t.low);
    return x;
}

// f(q) in the textbook form: pow(edge - v, n) p(v), or sum c_k pow(q, k).
template <int N, int M, int P>
inline double pow_form(const Naive<N, M, P>& f, double q) {
    const auto& t = f.piece(q);
    const double v = t.square ? q * q : q;
    double x = 0;
    if (t.edge_power > 0) {
        x = std::pow(t.edge - v, t.edge_power) * naive_horner(t.cofactor, v);
        if (t.low != 0) x *= std::pow(q, t.low);
    } else {
        for (int k = 0; k < t.nexpanded; ++k)
            x += t.expanded[static_cast<std::size_t>(k)] * std::pow(q, (t.square ? 2 * k : k) + t.low);
    }
    return x;
}

// f_h(r) in a naive form: q = r/h as r * (1/h), zero outside the support.
template <Form F, int N, int M, int P>
inline double naive_at(const Naive<N, M, P>& f, double r, const NaiveScale& s) {
    const double q = r * s.inv_h;
    const double inside = F == Form::pow ? pow_form(f, q <= 1 ? q : 1) : expanded_form(f, q <= 1 ? q : 1);
    return q <= 1 ? s.scale * inside : 0.0;
}

// The capacities the stability report uses for every kernel of the catalogue.
using NaiveAny = Naive<32, 32, 4>;

}  // namespace mollify::accuracy
