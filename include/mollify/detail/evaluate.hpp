// Evaluation of one emitted quantity (include/mollify/table.hpp) at a
// scaled radius, unrolled at compile time: the table is a template
// argument, so every coefficient, power and piece boundary is a constant
// and a batch loop over points is straight-line code the compiler can
// vectorise.
#pragma once

#include <mollify/table.hpp>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>

// Code compiled for different instruction sets (a benchmark built with
// -march=native linked with a generic library) must not be merged by the
// linker as one inline function: the ISA names an inline namespace.
#if defined(__AVX512F__)
#define MOLLIFY_ISA isa_avx512
#elif defined(__AVX2__) && defined(__FMA__)
#define MOLLIFY_ISA isa_avx2_fma
#elif defined(__FMA__) || defined(__FP_FAST_FMA)
#define MOLLIFY_ISA isa_fma
#else
#define MOLLIFY_ISA isa_generic
#endif

namespace mollify::detail {
inline namespace MOLLIFY_ISA {

// a*b + c with one rounding where the target has a fused multiply-add;
// without one, std::fma would be a slow library call.
inline double mul_add(double a, double b, double c) {
#if defined(__FMA__) || defined(__FP_FAST_FMA)
    return std::fma(a, b, c);
#else
    return a * b + c;
#endif
}

// c ? a : b on the bits, with both sides already computed: GCC will not
// if-convert a ternary whose arms it sank into branches (floating point may
// trap under the default -ftrapping-math), and a branch stops vectorisation.
inline double select(bool c, double a, double b) {
    const std::uint64_t mask = 0 - static_cast<std::uint64_t>(c);
    return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & mask) | (std::bit_cast<std::uint64_t>(b) & ~mask));
}

// x^N by binary powering, unrolled: ceil(log2 N) + popcount(N) - 1 products.
template <int N>
inline double ipow(double x) {
    if constexpr (N < 0) {
        return 1.0 / ipow<-N>(x);
    } else if constexpr (N == 0) {
        return 1.0;
    } else if constexpr (N == 1) {
        return x;
    } else {
        const double half = ipow<N / 2>(x);
        if constexpr (N % 2 == 0) return half * half;
        else return half * half * x;
    }
}

// A point inside the support, in the kernel's own variable: q = r/h and the
// distance to the support edge e = 1 - q, computed from h - r (exact by
// Sterbenz's lemma for r in [h/2, 2h]) so that it stays accurate to the
// last bit when q is within an ulp of 1, where (1 - q)^n is the whole value.
struct Scaled {
    double q;
    double e;
    double r, h, inv_h;  // for the distance to an interior edge a: (a h - r)/h
};

template <const table::Kernel& K, int Q>
inline constexpr const table::Quantity& quantity_table = K.quantities[Q];

template <const table::Kernel& K, int Q, int P>
inline constexpr const table::Piece& piece_table = quantity_table<K, Q>.pieces[P];

template <const table::Kernel& K, int Q, int P, int T>
inline constexpr const table::Term& term_table = piece_table<K, Q, P>.terms[T];

template <const table::Kernel& K, int Q, int P, int T, int I>
inline constexpr double coefficient = term_table<K, Q, P, T>.c[I];

// sum_k c[k] v^k by Horner's rule, from the highest coefficient down.
template <const table::Kernel& K, int Q, int P, int T, std::size_t... I>
inline double horner([[maybe_unused]] double v, std::index_sequence<I...>) {
    constexpr int n = term_table<K, Q, P, T>.n;
    double sum = coefficient<K, Q, P, T, n - 1>;
    ((sum = mul_add(sum, v, coefficient<K, Q, P, T, n - 2 - static_cast<int>(I)>)), ...);
    return sum;
}

// log r for 0 < r <= 1 without losing the digits of a value near 0.
inline double log_near_one(const Scaled& a) { return a.q < 0.5 ? std::log(a.q) : std::log1p(-a.e); }

// The non-polynomial factor of a term (table::Basis), from q and e:
// S = sqrt(1 - q^2) = sqrt(e (1 + q)), arcsech q = log((1 + S)/q).
template <table::Basis B, int SPower>
inline double basis(const Scaled& a) {
    if constexpr (B == table::Basis::one) {
        return 1.0;
    } else if constexpr (B == table::Basis::sqrt_power) {
        return ipow<SPower>(std::sqrt(a.e * (1 + a.q)));
    } else if constexpr (B == table::Basis::arcsech) {
        // Near 0 the sum of two positive logs (no cancellation, and finite
        // down to subnormal q); near 1 log1p of the small (1 + S - q)/q.
        const double S = std::sqrt(a.e * (1 + a.q));
        return a.q < 0.5 ? std::log1p(S) - std::log(a.q) : std::log1p((a.e + S) / a.q);
    } else if constexpr (B == table::Basis::log) {
        return log_near_one(a);
    } else {
        // atan2(q, S) rather than asin q: near q = 1 asin magnifies the
        // rounding of q by 1/S, while S comes from the accurate e.
        return std::atan2(a.q, std::sqrt(a.e * (1 + a.q)));
    }
}

// One term: (edge - v)^edge_power q^low p(v) basis(q), with the term's own
// edge (table::Term); at the support edge (edge = 1) the distance is a.e,
// accurate to the last bit, elsewhere edge - q (exact by Sterbenz's lemma
// for q in [edge/2, 2 edge], where the factor matters).
// The distance r/h - centre of a Taylor piece (table::Var::shifted) from r
// and h, not from the rounded q: (r - c h)/h with one rounding of r - c h
// where there is an FMA (then v is within ~1.5 ulp of itself); without one
// c h is rounded first, an absolute error <= c 2^-53, the size of the
// rounding of q itself. The centre's own rounding (centre_lo, ~2^-55) is
// subtracted after.
inline double shifted(const Scaled& a, double centre, double centre_lo) {
    return mul_add(-centre, a.h, a.r) * a.inv_h - centre_lo;
}

template <const table::Kernel& K, int Q, int P, int T>
inline double term(const Scaled& a) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    const double v = t.var == table::Var::r    ? a.q
                     : t.var == table::Var::r2 ? a.q * a.q
                                               : shifted(a, t.centre, t.centre_lo);
    double x = horner<K, Q, P, T>(v, std::make_index_sequence<static_cast<std::size_t>(t.n - 1)>{});
    if constexpr (t.low != 0) x *= ipow<t.low>(a.q);
    if constexpr (t.edge_power != 0) {
        constexpr bool support_edge = t.edge == 1.0;
        // At an interior edge (a combination's radius a_j, a breakpoint) the
        // distance is (a h - r)/h with one rounding of a h - r, not a - q
        // from the rounded q, which loses ulp(a)/(a - q) near the edge.
        const double to_edge = support_edge ? a.e : mul_add(t.edge, a.h, -a.r) * a.inv_h;
        const double edge = t.var == table::Var::r ? to_edge : to_edge * (t.edge + a.q);
        x *= ipow<t.edge_power>(edge);
    }
    if constexpr (t.basis == table::Basis::log || t.basis == table::Basis::arcsech) {
        // r^low log r -> 0 as r -> 0 for low > 0: the limit, not 0 * inf.
        if constexpr (t.low > 0) return a.q == 0 ? 0.0 : x * basis<t.basis, t.s_power>(a);
        return x * basis<t.basis, t.s_power>(a);
    } else if constexpr (t.basis != table::Basis::one) {
        return x * basis<t.basis, t.s_power>(a);
    }
    return x;
}

template <const table::Kernel& K, int Q, int P, std::size_t... T>
inline double piece(const Scaled& a, std::index_sequence<T...>) {
    return (0.0 + ... + term<K, Q, P, static_cast<int>(T)>(a));
}

template <const table::Kernel& K, int Q, int P>
inline double piece(const Scaled& a) {
    constexpr int n = piece_table<K, Q, P>.nterms;
    return piece<K, Q, P>(a, std::make_index_sequence<static_cast<std::size_t>(n)>{});
}

template <const table::Kernel& K, int Q, int P>
inline constexpr bool polynomial_piece = [] {
    for (int t = 0; t < piece_table<K, Q, P>.nterms; ++t)
        if (piece_table<K, Q, P>.terms[t].basis != table::Basis::one) return false;
    return true;
}();

template <const table::Kernel& K, int Q>
inline constexpr int inner_pieces = quantity_table<K, Q>.npieces - 1;

template <const table::Kernel& K, int Q>
inline constexpr bool polynomial_inside = [] {
    const table::Quantity& q = quantity_table<K, Q>;
    for (int p = 0; p + 1 < q.npieces; ++p)
        for (int t = 0; t < q.pieces[p].nterms; ++t)
            if (q.pieces[p].terms[t].basis != table::Basis::one) return false;
    return true;
}();

// Does the quantity blow up at r = 0 (a negative power of r or a
// logarithm without a vanishing factor in its first piece)? Then it is a cusp
// of W (spiky, viscosity, Wendland k = 0: W'(0) != 0), and W'/r ~ W'(0)/r.
template <const table::Kernel& K, int Q>
inline constexpr bool singular_at_origin = [] {
    const table::Piece& first = piece_table<K, Q, 0>;
    for (int t = 0; t < first.nterms; ++t) {
        const table::Term& term = first.terms[t];
        if (term.low < 0) return true;
        if ((term.basis == table::Basis::log || term.basis == table::Basis::arcsech) && term.low <= 0) return true;
    }
    return false;
}();

// The quantity inside the support, f(q) for 0 <= q <= 1. Polynomial pieces
// are all evaluated and the right one selected (branch-free, so a batch
// loop vectorises); pieces with sqrt/log are chosen by branches.
template <const table::Kernel& K, int Q, int P = inner_pieces<K, Q> - 1>
inline double inside(const Scaled& a) {
    if constexpr (P == 0) {
        return piece<K, Q, 0>(a);
    } else if constexpr (polynomial_inside<K, Q>) {
        const double here = piece<K, Q, P>(a);
        const double below = inside<K, Q, P - 1>(a);
        return select(a.q < piece_table<K, Q, P>.lo, below, here);
    } else {
        if (a.q < piece_table<K, Q, P>.lo) return inside<K, Q, P - 1>(a);
        return piece<K, Q, P>(a);
    }
}

// Outside the support the potentials are the Green's function G(r), the
// same for every h (1D r/2, 2D log(r)/(2 pi), 3D -1/(4 pi r)); it is
// evaluated at r itself, so no rounding of r/h enters. The kernel and its
// derivatives are exactly 0 there.
template <const table::Kernel& K, int Q>
inline constexpr bool zero_outside = piece_table<K, Q, inner_pieces<K, Q>>.nterms == 0;

template <const table::Kernel& K, int Q, int T>
inline double green_term(double r) {
    constexpr int P = inner_pieces<K, Q>;
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    static_assert(t.edge_power == 0 && (t.basis == table::Basis::one || t.basis == table::Basis::log),
                  "the exterior of a potential is a Green's function");
    static_assert(t.var != table::Var::shifted, "the exterior is a Green's function in r");
    const double v = t.var == table::Var::r ? r : r * r;
    double x = horner<K, Q, P, T>(v, std::make_index_sequence<static_cast<std::size_t>(t.n - 1)>{});
    if constexpr (t.low != 0) x *= ipow<t.low>(r);
    if constexpr (t.basis == table::Basis::log) x *= std::log(r);
    return x;
}

template <const table::Kernel& K, int Q, std::size_t... T>
inline double outside(double r, std::index_sequence<T...>) {
    return (0.0 + ... + green_term<K, Q, static_cast<int>(T)>(r));
}

template <const table::Kernel& K, int Q>
inline double outside(double r) {
    constexpr int n = piece_table<K, Q, inner_pieces<K, Q>>.nterms;
    return outside<K, Q>(r, std::make_index_sequence<static_cast<std::size_t>(n)>{});
}

// The coefficient c of c log r in a 2D potential's Green's function
// (1/(2 pi), from the table like every other number): the constant c log h
// that makes phi_h(r) = phi(r/h) + c log h equal G(r) outside the support.
template <const table::Kernel& K, int Q>
inline constexpr double log_coefficient = [] {
    const table::Piece& ext = piece_table<K, Q, inner_pieces<K, Q>>;
    for (int t = 0; t < ext.nterms; ++t)
        if (ext.terms[t].basis == table::Basis::log) return ext.terms[t].c[0];
    return 0.0;
}();

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail
