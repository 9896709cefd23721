// Evaluation of one emitted quantity (include/mollify/table.hpp) at a
// scaled radius, unrolled at compile time: the table is a template
// argument, so every coefficient, power and piece boundary is a constant
// and a batch loop over points is straight-line code the compiler can
// vectorise.
#pragma once

#include <mollify/detail/double_double.hpp>
#include <mollify/detail/isa.hpp>
#include <mollify/precision.hpp>
#include <mollify/table.hpp>

#include <bit>
#include <cmath>
#include <limits>
#include <cstddef>
#include <cstdint>
#include <utility>

namespace mollify::detail {
inline namespace MOLLIFY_ISA {

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
// Precision::accurate also keeps both as double-doubles (qq, ee): their
// low parts are what the edge factors need to be right to the last bit.
struct Scaled {
    double q;
    double e;
    double r, h, inv_h;  // Precision::fast: the distance (a h - r)/h to an interior edge a; Taylor pieces: (r - c h)/h
    DoubleDouble qq{}, ee{};
    DoubleDouble scale{1.0, 0.0};  // Precision::accurate: h^p, multiplied into a piece before its rounding
    // Precision::accurate: q^2 - rounded(qq.hi^2), for the first-order
    // correction p(v) + p'(v) dv of a polynomial in v = q^2 (in v = q: v =
    // qq.hi, dv = qq.lo).
    double dq2 = 0;
    // Precision::accurate, a quantity of one edge-factor term (unit_edge_power):
    // m - r 2^-e for h = m 2^e (unit_distance), its edge distance.
    DoubleDouble eu{};
};

// x/h to double-double accuracy, for x = x.hi + x.lo near a multiple of h:
// the residual x.hi - (x.hi/h) h is exact with a fused multiply-add
// (Markstein), and two_product's error term where there is none.
inline DoubleDouble over_h(const DoubleDouble& x, double h, double inv_h) {
    const double y = x.hi * inv_h;
#if MOLLIFY_HAS_FMA
    const double residual = std::fma(-y, h, x.hi);
#else
    const DoubleDouble yh = two_product(y, h);
    const double residual = (x.hi - yh.hi) - yh.lo;
#endif
    return {y, (residual + x.lo) * inv_h};
}

// q = r/h and e = (h - r)/h in double-double, for r <= h: h - r is exact as
// a fast two-sum (|h| >= |r|), then divided by h with its residual. Outside
// the support (r > h) the numbers are meaningless and are never selected.
// The polynomials take q as it comes, qq_hi = r (1/h) rounded and its
// residual qq_lo (|qq_lo| <= ~2 ulp(qq_hi): unnormalised, which the split's
// bound allows, generator/emit_round.cpp); q = qq_hi + qq_lo rounded, r/h
// to ~half an ulp, chooses the pieces and feeds the transcendental bases.
// (AccurateRadius: the numbers alone, which a batch loop keeps in registers;
// GCC does not scalarise the whole Scaled there.)
struct AccurateRadius {
    double qq_hi, qq_lo, ee_hi, ee_lo, q, dq2;
};

// r/h for a double r (over_h without a low part to add).
inline DoubleDouble over_h(double x, double h, double inv_h) {
    const double y = x * inv_h;
#if MOLLIFY_HAS_FMA
    return {y, std::fma(-y, h, x) * inv_h};
#else
    const DoubleDouble yh = two_product(y, h);
    return {y, ((x - yh.hi) - yh.lo) * inv_h};
#endif
}

inline AccurateRadius accurate_radius(double r, double h, double inv_h) {
    const DoubleDouble q = over_h(r, h, inv_h);
    const DoubleDouble e = over_h(fast_two_sum(h, -r), h, inv_h);
    const DoubleDouble square = two_product(q.hi, q.hi);
    return {q.hi, q.lo, e.hi, e.lo, q.hi + q.lo, mul_add(2 * q.hi, q.lo, square.lo)};
}

// m - r 2^-e exactly (h = m 2^e, m in [1/2, 1): Smoothing::significand,
// binary_unit), for r <= h: r 2^-e is exact (barring underflow, below 2^-1000
// of m), and m - r 2^-e a fast two-sum (m >= r 2^-e), three operations
// where (h - r)/h in double-double takes seven (accurate_radius: a two-sum,
// then a division's residual). It is h (1 - q) 2^-e = m (1 - q), so a
// quantity's edge factor (1 - q)^P is (m - r 2^-e)^P m^-P, and m^-P joins
// its scale once per batch (unit_edge_scale). Beyond h, where the quantity
// is 0 and this is not read, some finite number.
inline DoubleDouble unit_distance(double r, double binary_unit, double significand) {
    const double d = mul_add(-r, binary_unit, significand);
    return {d, mul_add(-r, binary_unit, significand - d)};
}

// The largest edge power taken so, and why: (m - r 2^-e)^P <= (1 - q)^P, so
// table::term_bound still bounds the term, while the scale grows by m^-P <=
// 2^P; rounded_product_bounded needs |x| |y| < ~2^1076, so the term's bound
// keeps 2^P more room below 2^100 than bounded_term asks.
inline constexpr int max_unit_edge_power = 16;

// A quantity whose edge factor is taken in units of 2^e: one inner piece of
// one term (1 - q)^P p(q) (edge 1, v = q, no power of q, Basis::one), 1 <= P
// <= max_unit_edge_power, 0 outside: Wendland's W, W'/r, W'' and their
// like. Its P, else 0. Both forms (src/plan.cpp: QuantityPlan::unit_edge)
// take it from here, so the same quantities the same way.
constexpr int unit_edge_power(const table::Quantity& q) {
    if (q.npieces != 2 || q.pieces[0].nterms != 1 || q.pieces[1].nterms != 0) return 0;
    const table::Term& t = q.pieces[0].terms[0];
    if (t.edge != 1.0 || t.edge_lo != 0.0 || t.var != table::Var::r || t.basis != table::Basis::one || t.low != 0 ||
        t.edge_power < 1 || t.edge_power > max_unit_edge_power)
        return 0;
    double room = 0x1p100;
    for (int k = 0; k < t.edge_power; ++k) room /= 2;
    return table::term_bound(t) < room ? t.edge_power : 0;
}

// h^p m^-P in double-double, the scale of such a quantity (P its
// unit_edge_power): once per batch.
template <int P>
MOLLIFY_INLINE DoubleDouble unit_edge_scale(const DoubleDouble& scale, const DoubleDouble& inverse_significand) {
    return scale * ipow<P>(inverse_significand);
}

inline Scaled scaled_accurate(double r, double h, double inv_h) {
    const AccurateRadius x = accurate_radius(r, h, inv_h);
    return {x.q, x.ee_hi + x.ee_lo, r, h, inv_h, {x.qq_hi, x.qq_lo}, {x.ee_hi, x.ee_lo}, {1.0, 0.0}, x.dq2};
}

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

// The coefficients of a term, and those of an edge series (one per term,
// accurate_series), as arrays of double-doubles {c, c_lo}: the operands of
// compensated_horner.
struct Coefficients {
    static constexpr std::size_t capacity = 128;
    double c[capacity]{}, lo[capacity]{};
    std::size_t n = 0;
    bool exact = true;  // every lo is 0
    int plain = 0;      // table::Term::plain
    constexpr void push(double hi, double low) {
        c[n] = hi;
        lo[n] = low;
        exact = exact && low == 0;
        ++n;
    }
};

// The k-th low part of a coefficient array Lo (table::Term::c_lo), which is
// nullptr where every low part is 0. A template argument, not a test
// `Lo == nullptr`: under -fsanitize GCC no longer folds the comparison of a
// table's address with null, and the constexpr tables below would not compile.
template <const double* Lo>
constexpr double low_at(int k) {
    return Lo[k];
}
template <>
constexpr double low_at<nullptr>(int) {
    return 0.0;
}

template <const table::Kernel& K, int Q, int P, int T>
inline constexpr Coefficients term_coefficients = [] {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    static_assert(t.n <= static_cast<int>(Coefficients::capacity));
    Coefficients out;
    for (int k = 0; k < t.n; ++k) out.push(t.c[k], low_at<t.c_lo>(k));
    out.plain = t.plain;
    return out;
}();

template <const table::Kernel& K, int Q, int P>
inline constexpr Coefficients series_coefficients = []<std::size_t... T>(std::index_sequence<T...>) {
    static_assert(sizeof...(T) <= Coefficients::capacity);
    Coefficients out;
    (out.push(term_table<K, Q, P, static_cast<int>(T)>.c[0], low_at<term_table<K, Q, P, static_cast<int>(T)>.c_lo>(0)),
     ...);
    return out;
}(std::make_index_sequence<static_cast<std::size_t>(piece_table<K, Q, P>.nterms)>{});

struct HornerSums {
    double sum, error, slope;
};

// One step of the scheme. A function forced inline, not a lambda: in a
// large unit (the treecode's) GCC left the lambda a call, and a call in
// the batch loop kept it from vectorising (mollifier:M=4's potential and
// phi'/r together, Precision::accurate: 24 against 100 ns per pair).
template <bool Exact, bool Plain = false>
MOLLIFY_INLINE void compensated_step(HornerSums& h, double v, double c, double c_lo) {
    h.slope = mul_add(h.slope, v, h.sum);
    if constexpr (Plain) {  // a leading step of table::Term::plain
        h.sum = mul_add(h.sum, v, c);
        return;
    }
    const DoubleDouble product = two_product(h.sum, v);
    const DoubleDouble s = two_sum(product.hi, c);
    h.sum = s.hi;
    if constexpr (Exact) h.error = mul_add(h.error, v, product.lo + s.lo);
    else h.error = mul_add(h.error, v, (product.lo + s.lo) + c_lo);
}

// sum_k C[k] (v + dv)^k as a double-double, for Precision::accurate: the
// compensated Horner scheme (Graillat, Langlois & Louvet, "Compensated
// Horner scheme", 2005): each step's product and sum errors, exact by
// two_product and two_sum, are summed by a second Horner recurrence, so the
// result is as if Horner's rule ran in twice the precision (relative error
// ~ u + cond(p, v) u^2; plain Horner is ~ 2 n cond(p, v) u, up to 4 ulp for
// the Wendland polynomials of degree 8 and unbounded near a root of p).
// The coefficients' own low parts (table::Term::c_lo) enter the second
// recurrence, and the derivative p'(v) dv, by a plain Horner recurrence,
// removes the rounding dv of v itself. The first C.plain steps (a Taylor
// piece's highest coefficients, where the generator proves it harmless)
// are plain Horner steps.
template <const Coefficients& C, std::size_t... I>
MOLLIFY_INLINE DoubleDouble compensated_horner(double v, double dv, std::index_sequence<I...>) {
    constexpr std::size_t n = C.n;
    HornerSums h{C.c[n - 1], C.plain > 0 ? 0.0 : C.lo[n - 1], 0.0};
    (compensated_step<C.exact, (static_cast<int>(I) < C.plain)>(h, v, C.c[n - 2 - I], C.lo[n - 2 - I]), ...);
    return {h.sum, mul_add(h.slope, dv, h.error)};
}

// Forced inline like the step: GCC left this a call for the 11-term
// pieces of Wendland C4's potential (a scalar batch, 87 ns per value).
template <const Coefficients& C>
MOLLIFY_INLINE DoubleDouble compensated_horner(double v, double dv) {
    if constexpr (C.n == 1) return {C.c[0], C.lo[0]};
    else return compensated_horner<C>(v, dv, std::make_index_sequence<C.n - 1>{});
}

// 1.5 * 2^(52 - split): (q + C) - C is q rounded to a multiple of 2^-split
// (for 0 <= q < 2^(51 - split); beyond, where a piece's value is not
// selected, some other number).
constexpr double split_constant(int split) {
    double c = 1.5;
    for (int k = 0; k < 52 - split; ++k) c *= 2;
    return c;
}

// table::Term::split: content * p_m(q + dq) as a double-double, p_m's
// Horner rule exact at qa (q rounded to the grid 2^-split; the generator
// proves every partial product and sum a double) and the remainder
// d = p_m(q) - p_m(qa) by d_k = d_{k+1} q + a_{k+1} (q - qa), each term of
// the sign of q - qa (generator/emit_round.cpp: split_of bounds its
// error). {a, d} is left unnormalised: |d| <~ 2^-split |p_m'|, and the
// product keeps d to first order. Bit for bit the same in both evaluators.
// split_sum is {p_m(qa), d}, split_horner content times it.
MOLLIFY_INLINE DoubleDouble split_sum(const double* m, int n, double c, double q, double dq) {
    const double qa = (q + c) - c, qb = (q - qa) + dq;
    if (n == 1) return {m[0], 0.0};
    // the first step apart: d_{n-1} = 0 (an FMA with a zero operand is not
    // folded away: 0 * q may be NaN)
    double d = m[n - 1] * qb, a = mul_add(m[n - 1], qa, m[n - 2]);
    // unrolled where n is a constant (GCC 12 kept such loops rolled inside
    // a batch loop, which then did not vectorise)
#pragma GCC unroll 32
    for (int k = n - 3; k >= 0; --k) {
        d = mul_add(d, q, a * qb);
        a = mul_add(a, qa, m[k]);
    }
    return {a, d};
}

MOLLIFY_INLINE DoubleDouble split_horner(const double* m, int n, double c, double content, double content_lo, double q,
                                         double dq) {
    return DoubleDouble{content, content_lo} * split_sum(m, n, c, q, dq);
}

// A piece of one split term whose value is its factor times p (Basis::one,
// sqrt_power): its content joins the scale h^p, one double-double product
// per batch instead of one per point: rounded_product(factor p_m, content h^p).
constexpr bool content_in_scale(int split, table::Basis basis) {
    return split > 0 && (basis == table::Basis::one || basis == table::Basis::sqrt_power);
}

// log r for 0 < r <= 1 without losing the digits of a value near 0.
inline double log_near_one(const Scaled& a) { return a.q < 0.5 ? std::log(a.q) : std::log1p(-a.e); }

// The transcendental factor of a term (table::Basis), from q and e:
// S = sqrt(1 - q^2) = sqrt(e (1 + q)), arcsech q = log((1 + S)/q).
// (The algebraic S^m is part of a term's factor: fast_term, factor_dd.)
template <table::Basis B>
inline double basis(const Scaled& a) {
    if constexpr (B == table::Basis::arcsech) {
        // Near 0 the sum of two positive logs (no cancellation, and finite
        // down to subnormal q); near 1 log1p of the small (1 + S - q)/q.
        const double S = std::sqrt(a.e * (1 + a.q));
        return a.q < 0.5 ? std::log1p(S) - std::log(a.q) : std::log1p((a.e + S) / a.q);
    } else if constexpr (B == table::Basis::log) {
        return log_near_one(a);
    } else {
        static_assert(B == table::Basis::arcsin);
        // atan2(q, S) rather than asin q: near q = 1 asin magnifies the
        // rounding of q by 1/S, while S comes from the accurate e.
        return std::atan2(a.q, std::sqrt(a.e * (1 + a.q)));
    }
}

// The distance to a term's edge, (edge - q) for Var::r and (edge^2 - q^2)
// for Var::r2 (Var::shifted pieces carry no edge factor): at the support
// edge from e, elsewhere (a combination's radius a_j) as (a h - r)/h with
// one rounding of a h - r, not a - q from the rounded q, which loses
// ulp(a)/(a - q) near the edge.
template <const table::Kernel& K, int Q, int P, int T>
inline double distance_to_edge(const Scaled& a) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    constexpr bool support_edge = t.edge == 1.0;
    const double to_edge = support_edge ? a.e : mul_add(t.edge, a.h, -a.r) * a.inv_h;
    return t.var == table::Var::r ? to_edge : to_edge * (t.edge + a.q);
}

// edge - q for an interior edge (a combination's radius a_j) in
// double-double, from q's: edge - qq.hi is exact where qq.hi >= edge/2
// (Sterbenz), a fast two-sum's error below (|edge| > |qq.hi|); beyond
// 2 edge, where the term is not used, some finite number. Its error is
// qq's, ~2^-104 q absolute: near a_j the term is ~(a_j - q)^n, the other
// terms carry the value, whose own condition a_j/(a_j - q) in q magnifies
// that error alike. (From (a h - r)/h, whose numerator is exact, the
// distance was right to 2^-104 of itself, for a two-sum and a division's
// residual more a term: 11 operations, here 5.)
MOLLIFY_INLINE DoubleDouble interior_distance(double edge, double edge_lo, const DoubleDouble& qq) {
    const DoubleDouble s = fast_two_sum(edge, -qq.hi);
    return {s.hi, s.lo + (edge_lo - qq.lo)};
}

// The same in double-double: at the support edge ee, at an interior edge
// interior_distance; edge + q by a two-sum.
template <const table::Kernel& K, int Q, int P, int T>
inline DoubleDouble distance_to_edge_dd(const Scaled& a) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    if constexpr (unit_edge_power(quantity_table<K, Q>) > 0) return a.eu;  // the scale has m^-P
    DoubleDouble d = a.ee;
    if constexpr (t.edge != 1.0) d = interior_distance(t.edge, t.edge_lo, a.qq);
    if constexpr (t.var == table::Var::r) {
        return d;
    } else {
        const DoubleDouble edge_plus_q = plus(t.edge, a.qq);
        return d * DoubleDouble{edge_plus_q.hi, edge_plus_q.lo + t.edge_lo};
    }
}

// The algebraic factor of a term in double-double (Precision::accurate):
// (edge - v)^edge_power q^low S^s_power. Forced inline: since ipow's
// products are forced inline, GCC left this a call in large units (Wendland
// k = l = 4's (1 - q)^14: a scalar pair loop, 8x slower).
template <const table::Kernel& K, int Q, int P, int T>
MOLLIFY_INLINE DoubleDouble factor_dd(const Scaled& a) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    DoubleDouble f{1.0, 0.0};
    bool one = true;
    auto times_f = [&](const DoubleDouble& g) {
        f = one ? g : f * g;
        one = false;
    };
    if constexpr (t.edge_power != 0) {
        static_assert(t.var != table::Var::shifted, "Taylor pieces carry no edge factor");
        times_f(ipow<t.edge_power>(distance_to_edge_dd<K, Q, P, T>(a)));
    }
    if constexpr (t.low != 0) times_f(ipow<t.low>(a.qq));
    if constexpr (t.basis == table::Basis::sqrt_power) {
        const DoubleDouble s2 = a.ee * plus(1.0, a.qq);  // S^2 = (1 - q)(1 + q)
        if constexpr (t.s_power % 2 == 0) times_f(ipow<t.s_power / 2>(s2));
        else times_f(ipow<t.s_power>(sqrt(s2)));
    }
    return f;
}

template <const table::Kernel& K, int Q, int P, int T>
inline constexpr bool has_factor = term_table<K, Q, P, T>.edge_power != 0 || term_table<K, Q, P, T>.low != 0 ||
                                   term_table<K, Q, P, T>.basis == table::Basis::sqrt_power;

// The distance r/h - centre of a Taylor piece (table::Var::shifted) from r
// and h, not from the rounded q: (r - c h)/h with one rounding of r - c h
// where there is an FMA (then v is within ~1.5 ulp of itself); without one
// c h is rounded first, an absolute error <= c 2^-53, the size of the
// rounding of q itself. The centre's own rounding (centre_lo, ~2^-55) is
// subtracted after.
inline double shifted(const Scaled& a, double centre, double centre_lo) {
    return mul_add(-centre, a.h, a.r) * a.inv_h - centre_lo;
}

// The same in double-double (Precision::accurate): r - c h exactly (a
// two-product and a two-sum), divided by h with its residual, then the
// centre's rounding taken off; rounding v instead would enter p(v)
// multiplied by v p'(v)/p(v), large near the edge where S^m is steep.
inline DoubleDouble shifted_dd(const Scaled& a, double centre, double centre_lo) {
    const DoubleDouble ch = two_product(centre, a.h);
    const DoubleDouble d = two_sum(a.r, -ch.hi);
    const DoubleDouble v = over_h({d.hi, d.lo - ch.lo}, a.h, a.inv_h);
    const DoubleDouble w = two_sum(v.hi, -centre_lo);
    return fast_two_sum(w.hi, w.lo + v.lo);
}

// The polynomial p(v) of a term, v = q, q^2 or q - centre, by Horner's rule.
template <const table::Kernel& K, int Q, int P, int T>
inline double polynomial(const Scaled& a) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    constexpr auto steps = std::make_index_sequence<static_cast<std::size_t>(t.n - 1)>{};
    const double v = t.var == table::Var::r    ? a.q
                     : t.var == table::Var::r2 ? a.q * a.q
                                               : shifted(a, t.centre, t.centre_lo);
    return horner<K, Q, P, T>(v, steps);
}

// The same as a double-double (Precision::accurate): compensated Horner at
// the rounded v, corrected for v's rounding (Scaled::qq, dq2, shifted_dd).
template <const table::Kernel& K, int Q, int P, int T>
inline DoubleDouble accurate_polynomial(const Scaled& a) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    constexpr const Coefficients& c = term_coefficients<K, Q, P, T>;
    if constexpr (t.n == 1) {
        return {c.c[0], c.lo[0]};
    } else if constexpr (t.split > 0) {
        static_assert(t.var == table::Var::r);
        return split_horner(t.m, t.n, split_constant(t.split), t.content, t.content_lo, a.qq.hi, a.qq.lo);
    } else if constexpr (t.var == table::Var::shifted) {
        const DoubleDouble v = shifted_dd(a, t.centre, t.centre_lo);
        return compensated_horner<c>(v.hi, v.lo);
    } else if constexpr (t.var == table::Var::r) {
        return compensated_horner<c>(a.qq.hi, a.qq.lo);
    } else {
        return compensated_horner<c>(a.qq.hi * a.qq.hi, a.dq2);
    }
}

template <const table::Kernel& K, int Q, int P, int T>
inline double with_basis(const Scaled& a, double x) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    if constexpr (t.basis == table::Basis::log || t.basis == table::Basis::arcsech) {
        // r^low log r -> 0 as r -> 0 for low > 0: the limit, not 0 * inf.
        if constexpr (t.low > 0) return a.q == 0 ? 0.0 : x * basis<t.basis>(a);
        return x * basis<t.basis>(a);
    } else if constexpr (t.basis == table::Basis::arcsin) {
        return x * basis<t.basis>(a);
    }
    return x;
}

// One term, (edge - v)^edge_power q^low p(v) basis(q), with its algebraic
// factor (edge - v)^edge_power q^low S^s_power formed in double
// (Precision::fast: the power multiplies the half-ulp rounding of its base).
template <const table::Kernel& K, int Q, int P, int T>
inline double fast_term(const Scaled& a) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    double x = polynomial<K, Q, P, T>(a);
    if constexpr (t.low != 0) x *= ipow<t.low>(a.q);
    if constexpr (t.edge_power != 0) x *= ipow<t.edge_power>(distance_to_edge<K, Q, P, T>(a));
    if constexpr (t.basis == table::Basis::sqrt_power) x *= ipow<t.s_power>(std::sqrt(a.e * (1 + a.q)));
    return with_basis<K, Q, P, T>(a, x);
}

// The same with the factor in double-double (Precision::accurate): p(v)
// times the factor, unrounded, as a double-double; a transcendental basis
// multiplies the rounded product.
template <const table::Kernel& K, int Q, int P, int T>
inline DoubleDouble accurate_term(const Scaled& a, const DoubleDouble& factor) {
    constexpr const table::Term& t = term_table<K, Q, P, T>;
    const DoubleDouble x = accurate_polynomial<K, Q, P, T>(a);
    if constexpr (t.basis == table::Basis::one || t.basis == table::Basis::sqrt_power) {
        return factor * x;
    } else {
        return {with_basis<K, Q, P, T>(a, rounded_product(factor, x)), 0.0};
    }
}

// Does term T continue the series of term T - 1: the same factor but for a
// higher power of the same edge distance? Then its factor is the previous
// one times the distance to the difference of the powers, one or two
// double-double products instead of a new power (the missing Wendland
// functions' edge series run to ~50 terms S (1 - q^2)^j).
constexpr bool continues(const table::Term& s, const table::Term& t) {
    return s.basis == t.basis && s.s_power == t.s_power && s.var == t.var && s.var != table::Var::shifted &&
           s.edge == t.edge && s.low == t.low && s.edge_power > 0 && t.edge_power > s.edge_power;
}

template <const table::Kernel& K, int Q, int P, int T>
constexpr bool continues_series() {
    if constexpr (T == 0) return false;
    else return continues(term_table<K, Q, P, T - 1>, term_table<K, Q, P, T>);
}

// Precision::accurate: the terms from T on, added to `sum` in order (in
// double-double: a potential's terms cancel), each factor from the
// previous one where the terms form a series.
template <const table::Kernel& K, int Q, int P, int T>
MOLLIFY_INLINE DoubleDouble accurate_terms(const Scaled& a, const DoubleDouble& sum,
                                   [[maybe_unused]] const DoubleDouble& previous) {
    if constexpr (T == piece_table<K, Q, P>.nterms) {
        return sum;
    } else {
        constexpr const table::Term& t = term_table<K, Q, P, T>;
        DoubleDouble factor{1.0, 0.0};
        if constexpr (continues_series<K, Q, P, T>()) {
            constexpr int step = t.edge_power - term_table<K, Q, P, T - 1>.edge_power;
            factor = previous * ipow<step>(distance_to_edge_dd<K, Q, P, T>(a));
        } else if constexpr (has_factor<K, Q, P, T>) {
            factor = factor_dd<K, Q, P, T>(a);
        }
        const DoubleDouble x = accurate_term<K, Q, P, T>(a, factor);
        return accurate_terms<K, Q, P, T + 1>(a, sum + x, factor);
    }
}

// Is the piece one series sum_j c_j F w^j in the edge distance w (each term
// a constant times the previous term's factor and one more power of w)?
// Then it is evaluated as F times Horner's rule in w: each term's rounding
// is not left in the sum, and ~50 terms cost ~50 FMAs.
template <const table::Kernel& K, int Q, int P, std::size_t... T>
constexpr bool is_edge_series(std::index_sequence<T...>) {
    return ((term_table<K, Q, P, static_cast<int>(T)>.n == 1 && (T == 0 || continues_series<K, Q, P, static_cast<int>(T)>()) &&
             (T == 0 || term_table<K, Q, P, static_cast<int>(T)>.edge_power ==
                            term_table<K, Q, P, static_cast<int>(T) - (T > 0 ? 1 : 0)>.edge_power + 1)) &&
            ...);
}

template <const table::Kernel& K, int Q, int P>
inline constexpr bool edge_series =
    piece_table<K, Q, P>.nterms > 2 &&
    is_edge_series<K, Q, P>(std::make_index_sequence<static_cast<std::size_t>(piece_table<K, Q, P>.nterms)>{});

template <const table::Kernel& K, int Q, int P>
inline double accurate_series(const Scaled& a) {
    const DoubleDouble w = [&] {
        const DoubleDouble d = distance_to_edge_dd<K, Q, P, 0>(a);
        return fast_two_sum(d.hi, d.lo);
    }();
    const DoubleDouble sum = compensated_horner<series_coefficients<K, Q, P>>(w.hi, w.lo);
    return with_basis<K, Q, P, 0>(a, rounded_product(factor_dd<K, Q, P, 0>(a) * sum, a.scale));
}

template <const table::Kernel& K, int Q, int P, std::size_t... T>
inline double fast_piece(const Scaled& a, std::index_sequence<T...>) {
    return (0.0 + ... + fast_term<K, Q, P, static_cast<int>(T)>(a));
}

// Is every term of the piece a polynomial term bounded on the support
// (table::bounded_term)? Then its value times the scale needs no overflow
// guard (rounded_product_bounded; the piece is evaluated at every q and
// selected, but only its own q's are kept).
template <const table::Kernel& K, int Q, int P>
inline constexpr bool bounded_piece = [] {
    for (int t = 0; t < piece_table<K, Q, P>.nterms; ++t)
        if (!table::bounded_term(piece_table<K, Q, P>.terms[t])) return false;
    return piece_table<K, Q, P>.nterms <= 1024;
}();

// x times the scale, rounded (the guard only where x may be unbounded).
template <const table::Kernel& K, int Q, int P>
MOLLIFY_INLINE double scaled_value(const DoubleDouble& x, const DoubleDouble& scale) {
    if constexpr (bounded_piece<K, Q, P>) return rounded_product_bounded(x, scale);
    else return rounded_product(x, scale);
}

// A piece, times the scale h^p (Scaled::scale) for Precision::accurate:
// a single term is rounded once, after the scale (h^p last: the factor of a
// steep term times h^p alone could underflow where the product with p(v)
// does not); several terms are rounded, added, then scaled.
// (Precision::fast scales the selected piece, StaticKernel::emitted.)
template <const table::Kernel& K, int Q, int P, Precision Pr>
MOLLIFY_INLINE double piece(const Scaled& a) {
    constexpr int n = piece_table<K, Q, P>.nterms;
    if constexpr (Pr == Precision::accurate) {
        if constexpr (edge_series<K, Q, P>) {
            return accurate_series<K, Q, P>(a);
        } else if constexpr (n == 1 && !continues_series<K, Q, P, 0>()) {
            DoubleDouble factor{1.0, 0.0};
            if constexpr (has_factor<K, Q, P, 0>) factor = factor_dd<K, Q, P, 0>(a);
            constexpr const table::Term& t = term_table<K, Q, P, 0>;
            if constexpr (content_in_scale(t.split, t.basis)) {
                const DoubleDouble p = split_sum(t.m, t.n, split_constant(t.split), a.qq.hi, a.qq.lo);
                return scaled_value<K, Q, P>(factor * p, DoubleDouble{t.content, t.content_lo} * a.scale);
            }
            return scaled_value<K, Q, P>(accurate_term<K, Q, P, 0>(a, factor), a.scale);
        } else {
            return scaled_value<K, Q, P>(accurate_terms<K, Q, P, 0>(a, DoubleDouble{0.0, 0.0}, DoubleDouble{1.0, 0.0}), a.scale);
        }
    } else {
        return fast_piece<K, Q, P>(a, std::make_index_sequence<static_cast<std::size_t>(n)>{});
    }
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
// From its first piece; both forms (the run-time plan: src/plan.cpp).
constexpr bool singular_piece(const table::Piece& first) {
    for (int t = 0; t < first.nterms; ++t) {
        const table::Term& term = first.terms[t];
        if (term.low < 0) return true;
        if ((term.basis == table::Basis::log || term.basis == table::Basis::arcsech) && term.low <= 0) return true;
    }
    return false;
}

template <const table::Kernel& K, int Q>
inline constexpr bool singular_at_origin = singular_piece(piece_table<K, Q, 0>);

// Below this r/h a singular quantity is its leading order (near_origin.hpp;
// the files of mollify-gen emit --target c|fortran|python too); above it the
// emitted form neither overflows (q^-5 < 2^750) nor meets a subnormal q.
inline constexpr double near_origin_bound = 0x1p-150;

// The limit at q = 0 of a quantity singular there: the most singular terms
// dominate, those of the lowest power q^low and, at the same power, those
// with a logarithm (log q -> -inf, arcsech q ~ -log q -> +inf); each is then
// c(0) edge^p (the polynomial at v = 0, the edge factor (edge - 0)^p, S = 1)
// times that, so the limit is +-inf by the sign of their sum. Evaluated term
// by term they give inf - inf or 0 * inf = NaN (a combination's per-radius
// terms of W'' in 2D; the missing Wendland functions' log r terms). NaN
// where the quantity is not singular at 0 (singular_at_origin's test) or
// this cannot tell: a Taylor term among them, or a sum of 0.
constexpr double limit_at_origin(const table::Piece& first) {
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    auto logarithm = [](const table::Term& t) {
        return t.basis == table::Basis::log || t.basis == table::Basis::arcsech;
    };
    // The most singular order: (low, with a logarithm), lower low first.
    int low = 1 << 30;
    bool with_log = false;
    for (int t = 0; t < first.nterms; ++t) {
        const table::Term& term = first.terms[t];
        if (term.low < low || (term.low == low && logarithm(term))) low = term.low, with_log = logarithm(term);
    }
    if (low > 0 || (low == 0 && !with_log)) return nan;  // not singular
    double sum = 0;
    for (int t = 0; t < first.nterms; ++t) {
        const table::Term& term = first.terms[t];
        if (term.low != low || logarithm(term) != with_log) continue;
        if ((term.basis != table::Basis::one && term.basis != table::Basis::sqrt_power && !with_log) ||
            term.var == table::Var::shifted)
            return nan;
        double weight = term.c[0];
        for (int k = 0; k < term.edge_power; ++k) weight *= term.edge;
        sum += term.basis == table::Basis::log ? -weight : weight;  // log q -> -inf; arcsech q, q^low -> +inf
    }
    return sum > 0 ? inf : sum < 0 ? -inf : nan;
}

template <const table::Kernel& K, int Q>
inline constexpr double limit_at_origin_of = limit_at_origin(piece_table<K, Q, 0>);

// The quantity inside the support, f(q) for 0 <= q <= 1. Polynomial pieces
// are all evaluated and the right one selected (branch-free, so a batch
// loop vectorises); pieces with sqrt/log are chosen by branches.
//
// In Precision::accurate a piece chosen by a branch is a call (branch_piece):
// such a loop does not vectorise anyway, and inlining would copy every
// piece (the missing Wendland functions' Taylor pieces run to 60 terms) into
// every loop of the run-time registry, whose compile time then triples.
template <const table::Kernel& K, int Q, int P, Precision Pr>
MOLLIFY_NOINLINE double branch_piece(const Scaled& a) {
    return piece<K, Q, P, Pr>(a);
}

template <const table::Kernel& K, int Q, int P, Precision Pr>
MOLLIFY_INLINE double chosen_piece(const Scaled& a) {
    if constexpr (Pr == Precision::accurate && !polynomial_inside<K, Q>) return branch_piece<K, Q, P, Pr>(a);
    else return piece<K, Q, P, Pr>(a);
}

// A combination's pieces share terms: piece p holds the terms of the radii
// beyond it. The distinct terms of the inner pieces, each with the q range
// of the run of pieces that holds it, in an order every piece's terms
// follow (then the sum of the terms each masked to its range adds, at every
// q, the terms of q's piece in their order, plus zeros: the same bits); m = 0
// where a term's pieces are not one run, a piece's terms are out of that
// order, a piece is an edge series or a term continues one, or nothing is
// shared. One rule for both forms (shared_terms_rule): StaticKernel reads
// the table (shared_terms below), the run-time plan its copy of it
// (src/plan.cpp: QuantityPlan::shared_terms). Beyond `capacity` distinct
// terms (a combination of more than 16 radii) both keep the pieces.
struct SharedTermList {
    static constexpr int capacity = 16;
    struct Ref {
        int piece, term;
        double lo, hi;
    };
    Ref t[capacity]{};
    int m = 0;
};

// v: the inner pieces, as v.pieces(), v.lo(p), v.terms(p), v.series(p),
// v.continues(p, t) and v.same(p, t, r, u) (term (p, t) is term (r, u)).
template <class View>
constexpr SharedTermList shared_terms_rule(const View& v) {
    const int inner = v.pieces();
    SharedTermList out;
    int first[SharedTermList::capacity]{}, last[SharedTermList::capacity]{}, terms = 0;
    for (int p = 0; p < inner; ++p) {
        if (v.series(p) || (p > 0 && !(v.lo(p) > v.lo(p - 1)))) return SharedTermList{};
        int previous = 0;  // one past the distinct index of the piece's previous term
        for (int t = 0; t < v.terms(p); ++t, ++terms) {
            if (v.continues(p, t)) return SharedTermList{};
            int d = 0;
            while (d < out.m && !v.same(out.t[d].piece, out.t[d].term, p, t)) ++d;
            if (d == out.m) {
                if (out.m == SharedTermList::capacity) return SharedTermList{};
                out.t[out.m] = {p, t, 0.0, 0.0};
                first[out.m] = last[out.m] = p;
                ++out.m;
            } else {
                if (last[d] + 1 != p) return SharedTermList{};  // its pieces are not one run
                last[d] = p;
            }
            if (d < previous) return SharedTermList{};
            previous = d + 1;
        }
    }
    if (out.m == terms || inner < 2) return SharedTermList{};
    constexpr double inf = std::numeric_limits<double>::infinity();
    for (int d = 0; d < out.m; ++d) {
        out.t[d].lo = first[d] == 0 ? -inf : v.lo(first[d]);
        out.t[d].hi = last[d] + 1 == inner ? inf : v.lo(last[d] + 1);
    }
    return out;
}

// The inner pieces' low parts, lo[p][t][k], read through low_at (a table's
// address is not compared with null: under -fsanitize GCC cannot fold that).
struct InnerLows {
    static constexpr int pieces = 8, terms = 8, coefficients = 16;
    double lo[pieces][terms][coefficients]{};
};

// Where a quantity may share terms at all, from the fields alone: the
// target fuses multiply-add (elsewhere both forms keep the pieces, bit for
// bit), at least two inner pieces of at most InnerLows' polynomial terms
// each, bounded on the support (table::bounded_term: the last product needs
// no guard), at most its coefficients a term, and 0 outside.
template <const table::Kernel& K, int Q>
inline constexpr bool may_share_terms = [] {
    const table::Quantity& quantity = quantity_table<K, Q>;
    const int inner = quantity.npieces - 1;
    if (!MOLLIFY_HAS_FMA || inner < 2 || inner > InnerLows::pieces || quantity.pieces[inner].nterms != 0)
        return false;
    for (int p = 0; p < inner; ++p) {
        if (quantity.pieces[p].nterms > InnerLows::terms) return false;
        for (int t = 0; t < quantity.pieces[p].nterms; ++t) {
            const table::Term& term = quantity.pieces[p].terms[t];
            if (term.basis != table::Basis::one || term.n > InnerLows::coefficients || !table::bounded_term(term)) return false;
        }
    }
    return true;
}();

template <const table::Kernel& K, int Q, int P, std::size_t... T>
constexpr void read_lows(InnerLows& out, std::index_sequence<T...>) {
    auto term = [&]<int J>(std::integral_constant<int, J>) {
        constexpr const table::Term& t = term_table<K, Q, P, J>;
        for (int k = 0; k < t.n; ++k) out.lo[P][J][k] = low_at<t.c_lo>(k);
    };
    (term(std::integral_constant<int, static_cast<int>(T)>{}), ...);
}

template <const table::Kernel& K, int Q, std::size_t... P>
constexpr InnerLows inner_lows(std::index_sequence<P...>) {
    InnerLows out;
    (read_lows<K, Q, static_cast<int>(P)>(
         out, std::make_index_sequence<static_cast<std::size_t>(piece_table<K, Q, static_cast<int>(P)>.nterms)>{}),
     ...);
    return out;
}

constexpr bool same_values(const double* a, const double* b, int n) {
    for (int k = 0; k < n; ++k)
        if (a[k] != b[k]) return false;
    return true;
}

// Two terms alike in every field but their arrays of coefficients, which
// each view compares its own way: table::Term and the run-time plan's
// TermPlan (src/plan.hpp) name these fields alike.
template <class Term>
constexpr bool same_term_fields(const Term& a, const Term& b) {
    return a.basis == b.basis && a.s_power == b.s_power && a.var == b.var && a.edge == b.edge &&
           a.edge_lo == b.edge_lo && a.edge_power == b.edge_power && a.low == b.low && a.n == b.n &&
           a.centre == b.centre && a.centre_lo == b.centre_lo && a.plain == b.plain && a.split == b.split &&
           a.content == b.content && a.content_lo == b.content_lo;
}

// The table's inner pieces as shared_terms_rule reads them: term against
// term field by field and value by value (the generator writes a shared
// term once per piece); an edge series' terms continue one another, which
// the rule refuses.
struct TableTerms {
    const table::Quantity& quantity;
    const InnerLows& lows;
    constexpr int pieces() const { return quantity.npieces - 1; }
    constexpr double lo(int p) const { return quantity.pieces[p].lo; }
    constexpr int terms(int p) const { return quantity.pieces[p].nterms; }
    constexpr bool series(int) const { return false; }
    constexpr bool continues(int p, int t) const {
        return t > 0 && detail::continues(quantity.pieces[p].terms[t - 1], quantity.pieces[p].terms[t]);
    }
    constexpr bool same(int p, int t, int r, int u) const {
        const table::Term &a = quantity.pieces[p].terms[t], &b = quantity.pieces[r].terms[u];
        return same_term_fields(a, b) && same_values(a.c, b.c, a.n) && same_values(lows.lo[p][t], lows.lo[r][u], a.n) &&
               (a.split == 0 || same_values(a.m, b.m, a.n));
    }
};

// StaticKernel's shared terms, where Precision::accurate sums them: also
// every distinct term of one coefficient or with low parts (QuantityPlan::
// shared_accurate: compensated Horner with its low parts, as the run-time
// form's loop).
template <const table::Kernel& K, int Q>
constexpr SharedTermList accurate_shared_terms(const InnerLows& lows) {
    const table::Quantity& quantity = quantity_table<K, Q>;
    const SharedTermList out = shared_terms_rule(TableTerms{quantity, lows});
    for (int d = 0; d < out.m; ++d) {
        const int n = quantity.pieces[out.t[d].piece].terms[out.t[d].term].n;
        bool exact = true;
        for (int k = 0; k < n; ++k) exact = exact && lows.lo[out.t[d].piece][out.t[d].term][k] == 0;
        if (n > 1 && exact) return SharedTermList{};
    }
    return out;
}

template <const table::Kernel& K, int Q>
inline constexpr SharedTermList shared_terms = [] {
    if constexpr (may_share_terms<K, Q>)
        return accurate_shared_terms<K, Q>(
            inner_lows<K, Q>(std::make_index_sequence<static_cast<std::size_t>(quantity_table<K, Q>.npieces - 1)>{}));
    else
        return SharedTermList{};
}();

// Precision::accurate sums a combination's distinct terms once, each where
// its pieces reach and (0, 0) elsewhere, as the run-time form's fused loop
// (src/evaluator.cpp: AccurateSharedTerms), instead of every piece's terms
// (the term of the outermost radius then twice: once alone, its content in
// the scale, once in the sums) and a selection (may_share_terms says where).
template <const table::Kernel& K, int Q>
inline constexpr bool shared_accurate = shared_terms<K, Q>.m > 0;

template <const table::Kernel& K, int Q, int J>
MOLLIFY_INLINE DoubleDouble shared_term(const Scaled& a) {
    constexpr int P = shared_terms<K, Q>.t[J].piece, T = shared_terms<K, Q>.t[J].term;
    DoubleDouble factor{1.0, 0.0};
    if constexpr (has_factor<K, Q, P, T>) factor = factor_dd<K, Q, P, T>(a);
    return accurate_term<K, Q, P, T>(a, factor);
}

// Where a distinct term reaches (shared_terms' lo and hi), as a mask of
// the point: a bound at -inf or +inf is not compared (q is then a number,
// or NaN, which the caller's select of r <= h discards).
template <const table::Kernel& K, int Q, int I>
MOLLIFY_INLINE bool reaches(double q) {
    constexpr double lo = shared_terms<K, Q>.t[I].lo, hi = shared_terms<K, Q>.t[I].hi;
    if constexpr (lo == -table::infinity && hi == table::infinity) return true;
    else if constexpr (lo == -table::infinity) return q < hi;
    else if constexpr (hi == table::infinity) return q >= lo;
    else return (q >= lo) & (q < hi);
}

// The sum of the distinct terms, each where it reaches and (0, 0)
// elsewhere, in order: the first term added to (+0, +0) is itself with
// +0 for -0 (two_sum of 0 and a finite t is exact: (t.hi + 0, t.lo + 0)),
// so the sum starts there, without a two-sum. Skip: the first Skip terms
// are known to be (0, 0) at a (the caller's level: no q of its register
// reaches them); from (+0, +0) their sums were (+0, +0), so leaving them
// out gives the same bits. On the support every term is finite
// (table::bounded_term); elsewhere the caller discards the sum.
template <const table::Kernel& K, int Q, int Skip = 0, std::size_t... J>
MOLLIFY_INLINE double shared_accurate_inside(const Scaled& a, std::index_sequence<J...>) {
    DoubleDouble y{0.0, 0.0};
    auto add = [&]<int I>(std::integral_constant<int, I>) MOLLIFY_INLINE_LAMBDA {
        if constexpr (I >= Skip) {
            DoubleDouble t = shared_term<K, Q, I>(a);
            const bool in = reaches<K, Q, I>(a.q);
            t = {select(in, t.hi, 0.0), select(in, t.lo, 0.0)};
            if constexpr (I == Skip) y = {t.hi + 0.0, t.lo + 0.0};
            else y = y + t;
        }
    };
    (add(std::integral_constant<int, static_cast<int>(J)>{}), ...);
    return rounded_product_bounded(y, a.scale);
}

// The pair loops' levels (RadiusLevel), one rule for both forms: where
// W's and W'/r's distinct terms are a combination's radii in order, each
// from q = 0 up to its radius a_j (the last to the support), the same
// radii for both, a register of points every q of which is at least a_L
// is at level L, and there the first L terms of both are 0. v and g: the
// two quantities' terms (lo, hi), m of each. Elsewhere one level.
template <class Terms>
constexpr bool radii_in_order(const Terms& v, const Terms& g, std::size_t m) {
    bool radii = m > 1;
    for (std::size_t j = 0; radii && j < m; ++j) {
        const bool last = j + 1 == m;
        radii = v[j].lo == -table::infinity && g[j].lo == -table::infinity && v[j].hi == g[j].hi &&
                (last ? v[j].hi == table::infinity : v[j].hi < table::infinity && (j == 0 || v[j].hi > v[j - 1].hi));
    }
    return radii;
}

// StaticKernel's: its number of levels (the m radii, else 1) and the l-th
// radius a_l (l < levels - 1; level_bound below).
template <const table::Kernel& K>
inline constexpr int levels = [] {
    constexpr int v = static_cast<int>(table::QuantityId::value), g = static_cast<int>(table::QuantityId::grad_over_r);
    constexpr int m = shared_terms<K, v>.m;
    if constexpr (shared_accurate<K, v> && shared_terms<K, g>.m == m)
        return radii_in_order(shared_terms<K, v>.t, shared_terms<K, g>.t, static_cast<std::size_t>(m)) ? m : 1;
    else
        return 1;
}();

// The same for W or W'/r alone (their batch evaluation; as in the run-time
// form, whose fused loops take these two: generator/term_shapes.hpp),
// where its distinct terms are radii in order. Other quantities keep one
// level (a unit pays a body per level).
template <const table::Kernel& K, int Q>
inline constexpr int quantity_levels = [] {
    constexpr bool w_or_over_r =
        Q == static_cast<int>(table::QuantityId::value) || Q == static_cast<int>(table::QuantityId::grad_over_r);
    if constexpr (w_or_over_r && shared_accurate<K, Q>) {
        constexpr int m = shared_terms<K, Q>.m;
        return radii_in_order(shared_terms<K, Q>.t, shared_terms<K, Q>.t, static_cast<std::size_t>(m)) ? m : 1;
    } else {
        return 1;
    }
}();

// The l-th radius a_l of Q's levels (of W's, the pair loops' levels).
template <const table::Kernel& K, int Q = static_cast<int>(table::QuantityId::value)>
constexpr double level_bound(int l) {
    return shared_terms<K, Q>.t[l].hi;
}

template <const table::Kernel& K, int Q, Precision Pr, int P = inner_pieces<K, Q> - 1, int Skip = 0>
MOLLIFY_INLINE double inside(const Scaled& a) {
    if constexpr (Pr == Precision::accurate && shared_accurate<K, Q>) {
        return shared_accurate_inside<K, Q, Skip>(a, std::make_index_sequence<static_cast<std::size_t>(shared_terms<K, Q>.m)>{});
    } else if constexpr (P == 0) {
        return chosen_piece<K, Q, 0, Pr>(a);
    } else if constexpr (polynomial_inside<K, Q>) {
        const double here = piece<K, Q, P, Pr>(a);
        const double below = inside<K, Q, Pr, P - 1>(a);
        return select(a.q < piece_table<K, Q, P>.lo, below, here);
    } else {
        if (a.q < piece_table<K, Q, P>.lo) return inside<K, Q, Pr, P - 1>(a);
        return chosen_piece<K, Q, P, Pr>(a);
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
