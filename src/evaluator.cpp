// The data-driven evaluator: any table evaluated from its plan (plan.hpp)
// with the operations of detail/evaluate.hpp in the same order (the same
// compensated Horner, double-double factors, edge series, Taylor pieces,
// Green's-function exterior), so that its results are StaticKernel's bit
// for bit on generic x86-64 (runtime_forms_test); with FMA the compiler
// contracts StaticKernel's unrolled expressions its own way, and the two
// agree within the precisions' bounds (batch_loops_test, README
// "Runtime"). Compiled once per instruction set
// (CMake: generic x86-64, x86-64-v3 and x86-64-v4), each copy in its own inline
// namespace (detail/isa.hpp).
#include "evaluator.hpp"
#include "term_shapes.hpp"

#include <mollify/static_kernel.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

// A loop over a template's N coefficients (Horner's rule) unrolled
// completely, so that the loop over a block's points around it vectorises:
// without it GCC 12 kept horner_q_fixed<N> (N >= 4), horner_fixed<N>
// (N >= 18) and compensated_fixed<N> (N >= 12) scalar, a point at a time
// (objdump of the x86-64-v3 copy: the potentials' longer polynomials took
// 7-12x the static form's time, kernel_bench). Unrolling changes no
// operation's order, so no bit.
#if defined(__GNUC__)
#define MOLLIFY_UNROLLED _Pragma("GCC unroll 64")
#else
#define MOLLIFY_UNROLLED
#endif

namespace mollify::detail {
inline namespace MOLLIFY_ISA {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// ipow<N> with N at run time: the same binary-powering tree (x^(2m+b) =
// (x^m)^2 x^b, walked from the top bit down), so the same roundings.
inline double ipow_rt(double x, int n) {
    if (n < 0) return 1.0 / ipow_rt(x, -n);
    if (n == 0) return 1.0;
    double out = x;
    for (int bit = std::bit_width(static_cast<unsigned>(n)) - 2; bit >= 0; --bit) {
        out = out * out;
        if ((n >> bit) & 1) out = out * x;
    }
    return out;
}

// The double-double ipow<N>'s tree: x^n = x^(2^k) x^(n - 2^k), the squares
// by repeated squaring, the product built from the lowest set bit up.
inline DoubleDouble ipow_rt(const DoubleDouble& x, int n) {
    if (n < 0) return ipow_rt(reciprocal(x), -n);
    if (n == 0) return {1.0, 0.0};
    DoubleDouble square = x, out{};
    bool first = true;
    for (unsigned m = static_cast<unsigned>(n);; m >>= 1) {
        if (m & 1) {
            out = first ? square : square * out;
            first = false;
        }
        if (m == 1) break;
        square = detail::square(square);
    }
    return out;
}

double basis_of(table::Basis b, const Scaled& a) {
    switch (b) {
        case table::Basis::arcsech: return basis<table::Basis::arcsech>(a);
        case table::Basis::log: return basis<table::Basis::log>(a);
        case table::Basis::arcsin: return basis<table::Basis::arcsin>(a);
        default: return 1.0;  // never called for one, sqrt_power
    }
}

// with_basis
double with_basis(const TermPlan& t, const Scaled& a, double x) {
    if (t.basis == table::Basis::log || t.basis == table::Basis::arcsech) {
        // r^low log r -> 0 as r -> 0 for low > 0: the limit, not 0 * inf.
        if (t.low > 0) return a.q == 0 ? 0.0 : x * basis_of(t.basis, a);
        return x * basis_of(t.basis, a);
    }
    if (t.basis == table::Basis::arcsin) return x * basis_of(t.basis, a);
    return x;
}

double horner(const double* c, int n, double v) {
    double sum = c[n - 1];
    for (int k = n - 2; k >= 0; --k) sum = mul_add(sum, v, c[k]);
    return sum;
}

// compensated_horner over run-time coefficients, the first `plain` steps
// plain (table::Term::plain).
DoubleDouble compensated_horner(const double* c, const double* lo, int n, bool exact, double v, double dv, int plain = 0) {
    if (n == 1) return {c[0], lo[0]};
    double sum = c[n - 1], error = plain > 0 ? 0.0 : lo[n - 1], slope = 0;
    int k = n - 2;
    for (; k >= n - 1 - plain; --k) {
        slope = mul_add(slope, v, sum);
        sum = mul_add(sum, v, c[k]);
    }
    for (; k >= 0; --k) {
        slope = mul_add(slope, v, sum);
        const DoubleDouble product = two_product(sum, v);
        const DoubleDouble s = two_sum(product.hi, c[k]);
        sum = s.hi;
        if (exact) error = mul_add(error, v, product.lo + s.lo);
        else error = mul_add(error, v, (product.lo + s.lo) + lo[k]);
    }
    return {sum, mul_add(slope, dv, error)};
}

// ---- Precision::fast ----

double distance_to_edge(const TermPlan& t, const Scaled& a) {
    const bool support_edge = t.edge == 1.0;
    const double to_edge = support_edge ? a.e : mul_add(t.edge, a.h, -a.r) * a.inv_h;
    return t.var == table::Var::r ? to_edge : to_edge * (t.edge + a.q);
}

double polynomial(const TermPlan& t, const Scaled& a) {
    const double v = t.var == table::Var::r    ? a.q
                     : t.var == table::Var::r2 ? a.q * a.q
                                               : shifted(a, t.centre, t.centre_lo);
    return horner(t.c, t.n, v);
}

// The powers x^n of one base, each by the tree of ipow<N> (x^n = (x^(n/2))^2
// x^(n mod 2)) with its subtrees remembered: a piece's edge series
// (~50 terms (1 - q^2)^j) then costs ~50 products instead of ~400, as the
// static form's common subexpressions do, with the same bits.
class Powers {
public:
    static constexpr int size = 256;
    void reset(double base) {
        base_ = base;
        ++generation_;
    }
    double operator()(int n) {
        if (n < 0) return 1.0 / (*this)(-n);
        if (n == 0) return 1.0;
        if (n == 1) return base_;
        if (n >= size) return ipow_rt(base_, n);
        if (stamp_[n] == generation_) return value_[n];
        const double half = (*this)(n / 2);
        double out = half * half;
        if (n % 2) out = out * base_;
        stamp_[n] = generation_;
        value_[n] = out;
        return out;
    }

private:
    double base_ = 0;
    std::uint64_t generation_ = 1;  // 64 bits: never wraps, so a stale stamp never matches
    std::uint64_t stamp_[size]{};
    double value_[size];
};

// S = sqrt(1 - q^2) is computed once per point (the same bits for every
// term); the powers of the edge distance and of S are remembered while
// consecutive terms share them.
double fast_piece(const PiecePlan& p, const Scaled& a) {
    thread_local Powers edge_powers, s_powers;
    const double S = std::sqrt(a.e * (1 + a.q));
    s_powers.reset(S);
    const TermPlan* previous = nullptr;
    double sum = 0.0;
    for (const TermPlan& t : p.terms) {
        double x = polynomial(t, a);
        if (t.low != 0) x *= ipow_rt(a.q, t.low);
        if (t.edge_power != 0) {
            if (!previous || previous->edge != t.edge || previous->var != t.var || previous->edge_power == 0)
                edge_powers.reset(distance_to_edge(t, a));
            x *= edge_powers(t.edge_power);
        }
        if (t.basis == table::Basis::sqrt_power) x *= s_powers(t.s_power);
        sum = sum + with_basis(t, a, x);
        previous = &t;
    }
    return sum;
}

// ---- Precision::accurate ----

// Quantity q's scale h^p as a double-double, times m^-P where its edge
// factor is taken in units of 2^e (QuantityPlan::unit_edge: StaticKernel::
// emitted's unit_edge_scale, the same products).
DoubleDouble accurate_scale(const QuantityPlan& qp, QuantityId q, const Smoothing& s) {
    const DoubleDouble scale{s.scale(q), s.scale_lo(q)};
    if (qp.unit_edge == 0) return scale;
    return scale * ipow_rt(DoubleDouble{s.inverse_significand(), s.inverse_significand_lo()}, qp.unit_edge);
}

DoubleDouble distance_to_edge_dd(const TermPlan& t, const Scaled& a) {
    if (t.unit_edge) return a.eu;  // the quantity's scale has m^-P (accurate_scale)
    DoubleDouble d = a.ee;
    if (t.edge != 1.0) d = interior_distance(t.edge, t.edge_lo, a.qq);
    if (t.var == table::Var::r) return d;
    const DoubleDouble edge_plus_q = plus(t.edge, a.qq);
    return d * DoubleDouble{edge_plus_q.hi, edge_plus_q.lo + t.edge_lo};
}

DoubleDouble factor_dd(const TermPlan& t, const Scaled& a) {
    DoubleDouble f{1.0, 0.0};
    bool one = true;
    auto times_f = [&](const DoubleDouble& g) {
        f = one ? g : f * g;
        one = false;
    };
    if (t.edge_power != 0) times_f(ipow_rt(distance_to_edge_dd(t, a), t.edge_power));
    if (t.low != 0) times_f(ipow_rt(a.qq, t.low));
    if (t.basis == table::Basis::sqrt_power) {
        const DoubleDouble s2 = a.ee * plus(1.0, a.qq);  // S^2 = (1 - q)(1 + q)
        if (t.s_power % 2 == 0) times_f(ipow_rt(s2, t.s_power / 2));
        else times_f(ipow_rt(sqrt(s2), t.s_power));
    }
    return f;
}

// detail::content_in_scale of a planned term, and its content times a scale.
bool content_in_scale(const TermPlan& t) { return mollify::detail::content_in_scale(t.split, t.basis); }
DoubleDouble content_times(const TermPlan& t, const DoubleDouble& scale) {
    return DoubleDouble{t.content, t.content_lo} * scale;
}

DoubleDouble accurate_polynomial(const TermPlan& t, const Scaled& a) {
    if (t.n == 1) return {t.c[0], t.c_lo[0]};
    if (t.split > 0) return split_horner(t.m.data(), t.n, t.split_c, t.content, t.content_lo, a.qq.hi, a.qq.lo);
    if (t.var == table::Var::shifted) {
        const DoubleDouble v = shifted_dd(a, t.centre, t.centre_lo);
        return compensated_horner(t.c, t.c_lo.data(), t.n, t.exact, v.hi, v.lo, t.plain);
    }
    if (t.var == table::Var::r) return compensated_horner(t.c, t.c_lo.data(), t.n, t.exact, a.qq.hi, a.qq.lo, t.plain);
    return compensated_horner(t.c, t.c_lo.data(), t.n, t.exact, a.qq.hi * a.qq.hi, a.dq2, t.plain);
}

DoubleDouble accurate_term(const TermPlan& t, const Scaled& a, const DoubleDouble& factor) {
    const DoubleDouble x = accurate_polynomial(t, a);
    if (t.basis == table::Basis::one || t.basis == table::Basis::sqrt_power) return factor * x;
    return {with_basis(t, a, rounded_product(factor, x)), 0.0};
}

double accurate_series(const PiecePlan& p, const Scaled& a) {
    const TermPlan& first = p.terms.front();
    const DoubleDouble d = distance_to_edge_dd(first, a);
    const DoubleDouble w = fast_two_sum(d.hi, d.lo);
    const DoubleDouble sum = compensated_horner(p.series_c.data(), p.series_lo.data(), static_cast<int>(p.series_c.size()),
                                                p.series_exact, w.hi, w.lo);
    return with_basis(first, a, rounded_product(factor_dd(first, a) * sum, a.scale));
}

double accurate_piece(const PiecePlan& p, const Scaled& a) {
    if (p.edge_series) return accurate_series(p, a);
    if (p.terms.size() == 1) {
        const TermPlan& t = p.terms.front();
        DoubleDouble factor{1.0, 0.0};
        if (t.has_factor) factor = factor_dd(t, a);
        if (content_in_scale(t))
            return rounded_product(factor * split_sum(t.m.data(), t.n, t.split_c, a.qq.hi, a.qq.lo), content_times(t, a.scale));
        return rounded_product(accurate_term(t, a, factor), a.scale);
    }
    DoubleDouble sum{0.0, 0.0}, previous{1.0, 0.0};
    for (const TermPlan& t : p.terms) {
        DoubleDouble factor{1.0, 0.0};
        if (t.continues) factor = previous * ipow_rt(distance_to_edge_dd(t, a), t.step);
        else if (t.has_factor) factor = factor_dd(t, a);
        const DoubleDouble x = accurate_term(t, a, factor);
        sum = sum + x;
        previous = factor;
    }
    return rounded_product(sum, a.scale);
}

// ---- a quantity at one radius (StaticKernel::emitted) ----

// The inner piece of q (inside<K, Q, Pr>): the highest whose lower end q
// is not below.
const PiecePlan& inner_piece(const QuantityPlan& qp, double q) {
    std::size_t p = qp.inner.size() - 1;
    while (p > 0 && q < qp.inner[p].lo) --p;
    return qp.inner[p];
}

double green_term(const TermPlan& t, double r) {
    const double v = t.var == table::Var::r ? r : r * r;
    double x = horner(t.c, t.n, v);
    if (t.low != 0) x *= ipow_rt(r, t.low);
    if (t.basis == table::Basis::log) x *= std::log(r);
    return x;
}

double outside(const QuantityPlan& qp, double r) {
    double sum = 0.0;
    for (const TermPlan& t : qp.exterior.terms) sum = sum + green_term(t, r);
    return sum;
}

// A quantity singular at r = 0 is its limit there where its terms give NaN
// (StaticKernel::emitted's limit); any other value as it is.
double limit_where_nan(const QuantityPlan& qp, double x) {
    return qp.singular_at_origin ? select(std::isnan(x), qp.at_origin, x) : x;
}

template <Precision Pr>
double radial(const QuantityPlan& qp, QuantityId q, double r, const Smoothing& s, int dim) {
    double in;
    if constexpr (Pr == Precision::accurate) {
        Scaled a = scaled_accurate(r, s.h(), s.inverse());
        a.scale = accurate_scale(qp, q, s);
        if (qp.unit_edge > 0) a.eu = unit_distance(r, s.binary_unit(), s.significand());
        in = accurate_piece(inner_piece(qp, a.q), a);
    } else {
        const Scaled a{r * s.inverse(), edge_distance(s.h() - r, s), r, s.h(), s.inverse()};
        in = fast_piece(inner_piece(qp, a.q), a) * s.scale(q);
    }
    if (q == QuantityId::potential && dim == 2) in = mul_add(qp.log_coefficient, s.log_h(), in);
    in = limit_where_nan(qp, in);
    if (qp.zero_outside) return select(r <= s.h(), in, 0.0);
    return r <= s.h() ? in : outside(qp, r);
}


// ---- blocks of points: quantities whose inner pieces are all polynomial ----
// (polynomial_inside: the static form evaluates every piece and selects,
// branch-free). Terms and coefficients are looped outside, the B points of
// a block inside, each operation the same as the scalar path's for each
// point (so the results are the same bits), in loops the compiler
// vectorises with the coefficient broadcast.

constexpr std::size_t B = 64;

struct DDs {
    double hi[B], lo[B];
};

// What a sum starts from (fast_piece's fold: 0 + the first term), read
// rather than written: GCC makes a zeroing loop `rep stos`, 70 % of a
// combination's piece loop.
constexpr double zeros[B] = {};
constexpr DDs zero_dds = {};

// Shape-specialised loops: the exponent or the polynomial length a
// template argument (up to these sizes; longer ones take the general loops
// below), the coefficients read from the table and broadcast, the sums in
// registers. detail::ipow<N> is the tree ipow_rt walks, so the results are
// the same bits.
constexpr int fixed_power = 16;
constexpr int fixed_length = 24;

template <int N>
void ipow_fixed(const double* x, double* out) {
    for (std::size_t i = 0; i < B; ++i) out[i] = ipow<N>(x[i]);
}

template <int N>
void ipow_fixed_dd(const DDs& x, DDs& out) {
    for (std::size_t i = 0; i < B; ++i) {
        const DoubleDouble y = ipow<N>(DoubleDouble{x.hi[i], x.lo[i]});
        out.hi[i] = y.hi;
        out.lo[i] = y.lo;
    }
}

template <int N>
void horner_fixed(const double* c, const double* v, double* out) {
    double k[N];
    for (int j = 0; j < N; ++j) k[j] = c[j];
    for (std::size_t i = 0; i < B; ++i) {
        double sum = k[N - 1];
        MOLLIFY_UNROLLED
        for (int j = N - 2; j >= 0; --j) sum = mul_add(sum, v[i], k[j]);
        out[i] = sum;
    }
}

template <int N, bool Exact>
void compensated_fixed(const double* c, const double* lo, const double* v, const double* dv, DDs& out) {
    double k[N], l[N];
    for (int j = 0; j < N; ++j) k[j] = c[j], l[j] = lo[j];
    for (std::size_t i = 0; i < B; ++i) {
        double sum = k[N - 1], error = l[N - 1], slope = 0;
        MOLLIFY_UNROLLED
        for (int j = N - 2; j >= 0; --j) {
            slope = mul_add(slope, v[i], sum);
            const DoubleDouble product = two_product(sum, v[i]);
            const DoubleDouble s = two_sum(product.hi, k[j]);
            sum = s.hi;
            if constexpr (Exact) error = mul_add(error, v[i], product.lo + s.lo);
            else error = mul_add(error, v[i], (product.lo + s.lo) + l[j]);
        }
        out.hi[i] = sum;
        out.lo[i] = mul_add(slope, dv[i], error);
    }
}

// x[i] *= ipow<N>(base[i]), in one pass.
template <int N>
void times_ipow_fixed(const double* base, double* x) {
    for (std::size_t i = 0; i < B; ++i) x[i] *= ipow<N>(base[i]);
}

// x[i] *= ipow<N>(distance to the term's edge), in one pass (fast_term's
// edge factor, distance_to_edge).
template <int N, bool VarR, bool SupportEdge>
void times_edge_fixed(const double* q, const double* e, const double* r, double edge, double h, double inv_h, double* x) {
    for (std::size_t i = 0; i < B; ++i) {
        const double to_edge = SupportEdge ? e[i] : mul_add(edge, h, -r[i]) * inv_h;
        const double d = VarR ? to_edge : to_edge * (edge + q[i]);
        x[i] *= ipow<N>(d);
    }
}

// Horner's rule in v = q or q^2 from q, in one pass.
template <int N, bool VarR>
void horner_q_fixed(const double* c, const double* q, double* out) {
    double k[N];
    for (int j = 0; j < N; ++j) k[j] = c[j];
    for (std::size_t i = 0; i < B; ++i) {
        const double v = VarR ? q[i] : q[i] * q[i];
        double sum = k[N - 1];
        MOLLIFY_UNROLLED
        for (int j = N - 2; j >= 0; --j) sum = mul_add(sum, v, k[j]);
        out[i] = sum;
    }
}

// fast_term for Basis::one at one point: Horner's rule in v = q or q^2,
// times ipow<Low>(q), times ipow<P>(distance to the edge).
template <int N, int P, bool VarR, bool SupportEdge, int Low = 0>
MOLLIFY_INLINE double fast_term_at(const double* k, double q, double e, double r, double edge, double h, double inv_h) {
    const double v = VarR ? q : q * q;
    double x = k[N - 1];
    MOLLIFY_UNROLLED
    for (int j = N - 2; j >= 0; --j) x = mul_add(x, v, k[j]);
    if constexpr (Low != 0) x *= ipow<Low>(q);
    if constexpr (P != 0) {
        const double to_edge = SupportEdge ? e : mul_add(edge, h, -r) * inv_h;
        // (the support edge is 1 as a constant: then W's and W'/r's distances
        // in a pair loop are one common subexpression, as StaticKernel's)
        const double d = VarR ? to_edge : to_edge * ((SupportEdge ? 1.0 : edge) + q);
        x *= ipow<P>(d);
    }
    return x;
}

// One whole polynomial term added to a block's sum in one pass (fast_term
// for Basis::one), the sum in registers: sum = from + term, from
// the sum so far or zeros for the first term (fast_piece's fold 0 + term).
// The same operations in the same order as the scalar path, so the same
// bits. A term shared by several pieces (QuantityPlan::shared_terms) is
// added only where lo <= q < hi, +0 elsewhere, which changes no sum (a sum
// from +0 is never -0 in round-to-nearest).
template <int N, int P, bool VarR, bool SupportEdge, int Low>
void add_term_fixed(const double* c, const double* q, const double* e, const double* r, double edge, double h,
                    double inv_h, double lo, double hi, const double* from, double* sum) {
    double k[N];
    for (int j = 0; j < N; ++j) k[j] = c[j];
    if (lo == -infinity && hi == infinity)
        for (std::size_t i = 0; i < B; ++i)
            sum[i] = from[i] + fast_term_at<N, P, VarR, SupportEdge, Low>(k, q[i], e[i], r[i], edge, h, inv_h);
    else
        for (std::size_t i = 0; i < B; ++i)
            sum[i] = from[i] + select((q[i] >= lo) & (q[i] < hi),
                                      fast_term_at<N, P, VarR, SupportEdge, Low>(k, q[i], e[i], r[i], edge, h, inv_h), 0.0);
}

// A whole quantity that is one term (one piece, 0 outside: Wendland's W
// and W'/r) at one radius, as StaticKernel::emitted's loop: q, e, the
// term, the scale, 0 beyond h.
template <int N, int P, bool VarR, bool SupportEdge>
MOLLIFY_INLINE double fast_whole_at(const double* k, double r, double edge, double h, double inv_h, const Smoothing& s,
                                    double scale) {
    const double q = r * inv_h, e = edge_distance(h - r, s);
    const double x = fast_term_at<N, P, VarR, SupportEdge>(k, q, e, r, edge, h, inv_h);
    return select(r <= h, (0.0 + x) * scale, 0.0);
}

// ... at n radii in one pass from r.
template <int N, int P, bool VarR, bool SupportEdge>
MOLLIFY_FLATTEN bool fast_whole_fixed(const TermPlan& t, const double* __restrict r, double* __restrict out, std::size_t n,
                                      const Smoothing& smoothing, double scale) {
    const Smoothing s = smoothing;
    double k[N];
    for (int j = 0; j < N; ++j) k[j] = t.c[j];
    const double h = s.h(), inv_h = s.inverse(), edge = t.edge;
    std::uint64_t refused = 0;
    for (std::size_t i = 0; i < n; ++i) {
        refused |= not_a_radius(r[i]);
        out[i] = fast_whole_at<N, P, VarR, SupportEdge>(k, r[i], edge, h, inv_h, s, scale);
    }
    return refused != 0;
}

// The fast fused loops: for the catalogue's shapes (term_shapes.hpp) of
// up to fused_length coefficients and edge powers up to fused_power, in
// both instruction sets (longer or other terms take fast_term_block, with
// the same bits). Listed shapes only: the 260 loops of every length and
// power were a third of the evaluator's compile time.
constexpr int fused_length = 5;
constexpr int fused_power = 12;
using AddTerm = void (*)(const double*, const double*, const double*, const double*, double, double, double, double, double,
                         const double*, double*);

template <const TermShape& S>
constexpr AddTerm add_term_loop() {
    if constexpr (S.n <= fused_length && S.edge_power <= fused_power)
        return &add_term_fixed<S.n, S.edge_power, S.var_r, S.support_edge, S.low>;
    else
        return nullptr;
}
template <std::size_t... I>
constexpr std::array<AddTerm, sizeof...(I)> add_term_loops(std::index_sequence<I...>) {
    return {add_term_loop<term_shape<I>>()...};
}
// [TermPlan::fast_shape]
constexpr auto add_term_of = add_term_loops(std::make_index_sequence<term_shape_count>{});

bool fused(const TermPlan& t) {
    return t.fast_shape >= 0 && add_term_of[static_cast<std::size_t>(t.fast_shape)] != nullptr;
}

using TimesIpow = void (*)(const double*, double*);
using TimesEdge = void (*)(const double*, const double*, const double*, double, double, double, double*);
using HornerQ = void (*)(const double*, const double*, double*);

template <int... I>
constexpr std::array<TimesIpow, sizeof...(I)> times_ipow_table(std::integer_sequence<int, I...>) {
    return {&times_ipow_fixed<I - fixed_power>...};
}
template <bool VarR, bool SupportEdge, int... I>
constexpr std::array<TimesEdge, sizeof...(I)> times_edge_table(std::integer_sequence<int, I...>) {
    return {&times_edge_fixed<I - fixed_power, VarR, SupportEdge>...};
}
template <bool VarR, int... I>
constexpr std::array<HornerQ, sizeof...(I)> horner_q_table(std::integer_sequence<int, I...>) {
    return {&horner_q_fixed<I + 1, VarR>...};
}

constexpr auto powers = std::make_integer_sequence<int, 2 * fixed_power + 1>{};
constexpr auto times_ipow_of = times_ipow_table(powers);
// [var == r][edge == 1]
constexpr std::array<std::array<decltype(times_edge_table<true, true>(powers)), 2>, 2> times_edge_of = {{
    {times_edge_table<false, false>(powers), times_edge_table<false, true>(powers)},
    {times_edge_table<true, false>(powers), times_edge_table<true, true>(powers)},
}};
constexpr std::array<decltype(horner_q_table<true>(std::make_integer_sequence<int, fixed_length>{})), 2> horner_q_of = {
    horner_q_table<false>(std::make_integer_sequence<int, fixed_length>{}),
    horner_q_table<true>(std::make_integer_sequence<int, fixed_length>{})};

bool fixed(int n) { return n >= -fixed_power && n <= fixed_power; }
std::size_t power_index(int n) { return static_cast<std::size_t>(n + fixed_power); }

using IpowFixed = void (*)(const double*, double*);
using IpowFixedDD = void (*)(const DDs&, DDs&);
using HornerFixed = void (*)(const double*, const double*, double*);
using CompensatedFixed = void (*)(const double*, const double*, const double*, const double*, DDs&);

template <int... I>
constexpr std::array<IpowFixed, sizeof...(I)> ipow_table(std::integer_sequence<int, I...>) {
    return {&ipow_fixed<I - fixed_power>...};
}
template <int... I>
constexpr std::array<IpowFixedDD, sizeof...(I)> ipow_dd_table(std::integer_sequence<int, I...>) {
    return {&ipow_fixed_dd<I - fixed_power>...};
}
template <int... I>
constexpr std::array<HornerFixed, sizeof...(I)> horner_table(std::integer_sequence<int, I...>) {
    return {&horner_fixed<I + 1>...};
}
template <bool Exact, int... I>
constexpr std::array<CompensatedFixed, sizeof...(I)> compensated_table(std::integer_sequence<int, I...>) {
    return {&compensated_fixed<I + 2, Exact>...};
}

constexpr auto ipow_fixed_of = ipow_table(std::make_integer_sequence<int, 2 * fixed_power + 1>{});
constexpr auto ipow_fixed_dd_of = ipow_dd_table(std::make_integer_sequence<int, 2 * fixed_power + 1>{});
constexpr auto horner_fixed_of = horner_table(std::make_integer_sequence<int, fixed_length>{});
constexpr auto compensated_exact_of = compensated_table<true>(std::make_integer_sequence<int, fixed_length - 1>{});
constexpr auto compensated_inexact_of = compensated_table<false>(std::make_integer_sequence<int, fixed_length - 1>{});

// ipow_rt on a block: the binary-powering tree of ipow<N> walked from the
// top bit down (x^(2m+b) = (x^m)^2 x^b), the same products in the same order.
void ipow_block(const double* x, int n, double* out) {
    if (n >= -fixed_power && n <= fixed_power) {
        ipow_fixed_of[static_cast<std::size_t>(n + fixed_power)](x, out);
        return;
    }
    if (n < 0) {
        ipow_block(x, -n, out);
        for (std::size_t i = 0; i < B; ++i) out[i] = 1.0 / out[i];
        return;
    }
    if (n == 0) {
        for (std::size_t i = 0; i < B; ++i) out[i] = 1.0;
        return;
    }
    for (std::size_t i = 0; i < B; ++i) out[i] = x[i];
    for (int bit = std::bit_width(static_cast<unsigned>(n)) - 2; bit >= 0; --bit) {
        for (std::size_t i = 0; i < B; ++i) out[i] = out[i] * out[i];
        if ((n >> bit) & 1)
            for (std::size_t i = 0; i < B; ++i) out[i] = out[i] * x[i];
    }
}

void ipow_block(const DDs& x, int n, DDs& out) {
    if (n >= -fixed_power && n <= fixed_power) {
        ipow_fixed_dd_of[static_cast<std::size_t>(n + fixed_power)](x, out);
        return;
    }
    if (n < 0) {
        DDs inv;
        for (std::size_t i = 0; i < B; ++i) {
            const DoubleDouble y = reciprocal({x.hi[i], x.lo[i]});
            inv.hi[i] = y.hi;
            inv.lo[i] = y.lo;
        }
        ipow_block(inv, -n, out);
        return;
    }
    if (n == 0) {
        for (std::size_t i = 0; i < B; ++i) out.hi[i] = 1.0, out.lo[i] = 0.0;
        return;
    }
    for (std::size_t i = 0; i < B; ++i) {
        const DoubleDouble y = ipow_rt(DoubleDouble{x.hi[i], x.lo[i]}, n);
        out.hi[i] = y.hi;
        out.lo[i] = y.lo;
    }
}

void horner_block(const double* c, int n, const double* v, double* out) {
    if (n <= fixed_length) {
        horner_fixed_of[static_cast<std::size_t>(n - 1)](c, v, out);
        return;
    }
    for (std::size_t i = 0; i < B; ++i) out[i] = c[n - 1];
    for (int k = n - 2; k >= 0; --k) {
        const double ck = c[k];
        for (std::size_t i = 0; i < B; ++i) out[i] = mul_add(out[i], v[i], ck);
    }
}

struct FastBlock {
    double q[B], e[B], r[B];
    double h, inv_h;
};

// The powers x^n of B bases (BlockPowers), each by the tree of ipow<N>
// with its subtrees remembered, as Powers does for one point: a piece's
// edge series (~50 terms S (1 - q^2)^j) then costs ~50 products per point.
class BlockPowers {
public:
    static constexpr int size = 80;
    void reset(const double* base) {
        for (std::size_t i = 0; i < B; ++i) base_[i] = base[i];
        ++generation_;
    }
    // x^n for 1 <= n < size.
    const double* operator()(int n) {
        if (n == 1) return base_;
        if (stamp_[n] == generation_) return value_[n];
        const double* half = (*this)(n / 2);
        double* out = value_[n];
        if (n % 2)
            for (std::size_t i = 0; i < B; ++i) out[i] = half[i] * half[i] * base_[i];
        else
            for (std::size_t i = 0; i < B; ++i) out[i] = half[i] * half[i];
        stamp_[n] = generation_;
        return out;
    }
    static bool remembers(int n) { return n >= 1 && n < size; }

private:
    double base_[B];
    std::uint64_t generation_ = 1;  // 64 bits: never wraps, so a stale stamp never matches
    std::uint64_t stamp_[size]{};
    double value_[size][B];
};

// The powers a piece's terms share (fast_piece: the edge powers while
// consecutive terms have the same edge, S^m for the whole piece).
struct SharedPowers {
    BlockPowers edge, s;
    bool edge_valid = false, s_valid = false;
};

void times_power(BlockPowers& powers, const double* base, int n, double* x) {
    double p[B];
    if (BlockPowers::remembers(n)) {
        const double* y = powers(n);
        for (std::size_t i = 0; i < B; ++i) x[i] *= y[i];
        return;
    }
    ipow_block(base, n, p);
    for (std::size_t i = 0; i < B; ++i) x[i] *= p[i];
}

void fast_term_block(const TermPlan& t, const TermPlan* previous, const FastBlock& a, SharedPowers& shared, double* x) {
    double v[B], p[B];
    if (t.var != table::Var::shifted && t.n <= fixed_length) {
        horner_q_of[t.var == table::Var::r][static_cast<std::size_t>(t.n - 1)](t.c, a.q, x);
    } else {
        for (std::size_t i = 0; i < B; ++i)
            v[i] = t.var == table::Var::r    ? a.q[i]
                   : t.var == table::Var::r2 ? a.q[i] * a.q[i]
                                             : mul_add(-t.centre, a.h, a.r[i]) * a.inv_h - t.centre_lo;
        horner_block(t.c, t.n, v, x);
    }
    if (t.low != 0) {
        if (fixed(t.low)) {
            times_ipow_of[power_index(t.low)](a.q, x);
        } else {
            ipow_block(a.q, t.low, p);
            for (std::size_t i = 0; i < B; ++i) x[i] *= p[i];
        }
    }
    const bool shares_edge =
        previous && previous->edge == t.edge && previous->var == t.var && previous->edge_power != 0;
    if (!shares_edge) shared.edge_valid = false;
    if (t.edge_power != 0) {
        const bool support_edge = t.edge == 1.0;
        // A lone power by its own unrolled tree; a series' powers remembered.
        if (fixed(t.edge_power) && !t.continues) {
            times_edge_of[t.var == table::Var::r][support_edge][power_index(t.edge_power)](a.q, a.e, a.r, t.edge, a.h,
                                                                                             a.inv_h, x);
        } else {
            for (std::size_t i = 0; i < B; ++i) {
                const double to_edge = support_edge ? a.e[i] : mul_add(t.edge, a.h, -a.r[i]) * a.inv_h;
                v[i] = t.var == table::Var::r ? to_edge : to_edge * (t.edge + a.q[i]);
            }
            if (!shared.edge_valid) shared.edge.reset(v);
            shared.edge_valid = true;
            times_power(shared.edge, v, t.edge_power, x);
        }
    }
    if (t.basis == table::Basis::sqrt_power) {
        for (std::size_t i = 0; i < B; ++i) v[i] = std::sqrt(a.e[i] * (1 + a.q[i]));
        if (!shared.s_valid) shared.s.reset(v);
        shared.s_valid = true;
        times_power(shared.s, v, t.s_power, x);
    }
    if (t.basis == table::Basis::log || t.basis == table::Basis::arcsech || t.basis == table::Basis::arcsin)
        for (std::size_t i = 0; i < B; ++i) x[i] = with_basis(t, Scaled{a.q[i], a.e[i], a.r[i], a.h, a.inv_h}, x[i]);
}

SharedPowers& shared_powers() {
    thread_local SharedPowers shared;
    return shared;
}

// A term c (distance to the edge)^P S^m, n = 1 (the missing Wendland
// functions' edge series, ~50 terms a piece), in one pass from the
// remembered powers: fast_term_block's products in its order (c, times the
// edge power, times S^m; BlockPowers' tree is ipow<N>'s), added to the sum.
bool series_term(const TermPlan& t) {
    return t.n == 1 && t.low == 0 && t.var != table::Var::shifted &&
           (t.basis == table::Basis::one || t.basis == table::Basis::sqrt_power) &&
           (t.edge_power == 0 || BlockPowers::remembers(t.edge_power)) &&
           (t.basis != table::Basis::sqrt_power || BlockPowers::remembers(t.s_power));
}

void add_series_term(const TermPlan& t, const TermPlan* previous, const FastBlock& a, SharedPowers& shared, double* sum) {
    double v[B];
    const bool shares_edge =
        previous && previous->edge == t.edge && previous->var == t.var && previous->edge_power != 0;
    if (!shares_edge) shared.edge_valid = false;
    const double* ep = nullptr;
    const double* sp = nullptr;
    if (t.edge_power != 0) {
        if (!shared.edge_valid) {
            const bool support_edge = t.edge == 1.0;
            for (std::size_t i = 0; i < B; ++i) {
                const double to_edge = support_edge ? a.e[i] : mul_add(t.edge, a.h, -a.r[i]) * a.inv_h;
                v[i] = t.var == table::Var::r ? to_edge : to_edge * (t.edge + a.q[i]);
            }
            shared.edge.reset(v);
            shared.edge_valid = true;
        }
        ep = shared.edge(t.edge_power);
    }
    if (t.basis == table::Basis::sqrt_power) {
        if (!shared.s_valid) {
            for (std::size_t i = 0; i < B; ++i) v[i] = std::sqrt(a.e[i] * (1 + a.q[i]));
            shared.s.reset(v);
            shared.s_valid = true;
        }
        sp = shared.s(t.s_power);
    }
    const double c = t.c[0];
    const bool first = !previous;
    auto add = [&](auto term) {
        if (first)
            for (std::size_t i = 0; i < B; ++i) sum[i] = 0.0 + term(i);
        else
            for (std::size_t i = 0; i < B; ++i) sum[i] = sum[i] + term(i);
    };
    if (ep && sp) add([&](std::size_t i) { return c * ep[i] * sp[i]; });
    else if (ep) add([&](std::size_t i) { return c * ep[i]; });
    else if (sp) add([&](std::size_t i) { return c * sp[i]; });
    else add([&](std::size_t) { return c; });
}

// sum = from + a fused term where lo <= q < hi (add_term_fixed).
void add_fused_term(const TermPlan& t, const FastBlock& a, double lo, double hi, const double* from, double* sum) {
    add_term_of[static_cast<std::size_t>(t.fast_shape)](
        t.c, a.q, a.e, a.r, t.edge, a.h, a.inv_h, lo, hi, from, sum);
}

void fast_piece_block(const PiecePlan& p, const FastBlock& a, double* sum) {
    SharedPowers* shared = nullptr;  // only where a term is not fused (the buffers are 40 kB)
    double x[B];
    if (p.terms.empty())
        for (std::size_t i = 0; i < B; ++i) sum[i] = 0.0;
    const TermPlan* previous = nullptr;
    for (const TermPlan& t : p.terms) {
        const double* from = previous ? sum : zeros;
        if (fused(t)) {
            add_fused_term(t, a, -infinity, infinity, from, sum);
            if (shared) shared->edge_valid = false;
        } else {
            if (!shared) {
                shared = &shared_powers();
                shared->edge_valid = shared->s_valid = false;
            }
            if (series_term(t)) {
                add_series_term(t, previous, a, *shared, sum);
                previous = &t;
                continue;
            }
            fast_term_block(t, previous, a, *shared, x);
            for (std::size_t i = 0; i < B; ++i) sum[i] = from[i] + x[i];
        }
        previous = &t;
    }
}

struct AccurateBlock {
    double q[B], e[B], r[B], dq2[B];
    DDs qq, ee;
    DDs eu;  // unit_distance, filled where unit_edge (a unit_edge term's edge distance)
    double h, inv_h, binary_unit, significand;
    DoubleDouble scale;
    bool unit_edge;
    // (unit_edge: a quantity read from the block is QuantityPlan::unit_edge)
    AccurateBlock(const Smoothing& s, bool unit_edge)
        : h(s.h()), inv_h(s.inverse()), binary_unit(s.binary_unit()), significand(s.significand()), unit_edge(unit_edge) {}
};

void distance_to_edge_block(const TermPlan& t, const AccurateBlock& a, DDs& out) {
    const DDs& edge = t.unit_edge ? a.eu : a.ee;
    for (std::size_t i = 0; i < B; ++i) {
        DoubleDouble d{edge.hi[i], edge.lo[i]};
        if (t.edge != 1.0) d = interior_distance(t.edge, t.edge_lo, {a.qq.hi[i], a.qq.lo[i]});
        if (t.var != table::Var::r) {
            const DoubleDouble edge_plus_q = plus(t.edge, {a.qq.hi[i], a.qq.lo[i]});
            d = d * DoubleDouble{edge_plus_q.hi, edge_plus_q.lo + t.edge_lo};
        }
        out.hi[i] = d.hi;
        out.lo[i] = d.lo;
    }
}

void times_block(DDs& f, const DDs& g) {
    for (std::size_t i = 0; i < B; ++i) {
        const DoubleDouble y = DoubleDouble{f.hi[i], f.lo[i]} * DoubleDouble{g.hi[i], g.lo[i]};
        f.hi[i] = y.hi;
        f.lo[i] = y.lo;
    }
}

void factor_block(const TermPlan& t, const AccurateBlock& a, DDs& f) {
    bool one = true;
    DDs g, p;
    auto times_f = [&](const DDs& x) {
        if (one) f = x;
        else times_block(f, x);
        one = false;
    };
    for (std::size_t i = 0; i < B; ++i) f.hi[i] = 1.0, f.lo[i] = 0.0;
    if (t.edge_power != 0) {
        distance_to_edge_block(t, a, g);
        ipow_block(g, t.edge_power, p);
        times_f(p);
    }
    if (t.low != 0) {
        ipow_block(a.qq, t.low, p);
        times_f(p);
    }
    if (t.basis == table::Basis::sqrt_power) {
        for (std::size_t i = 0; i < B; ++i) {
            const DoubleDouble s2 = DoubleDouble{a.ee.hi[i], a.ee.lo[i]} * plus(1.0, {a.qq.hi[i], a.qq.lo[i]});
            const DoubleDouble x = t.s_power % 2 == 0 ? s2 : sqrt(s2);
            g.hi[i] = x.hi;
            g.lo[i] = x.lo;
        }
        ipow_block(g, t.s_power % 2 == 0 ? t.s_power / 2 : t.s_power, p);
        times_f(p);
    }
}

void compensated_horner_block(const double* c, const double* lo, int n, bool exact, const double* v, const double* dv,
                              DDs& out, int plain = 0) {
    if (n == 1) {
        for (std::size_t i = 0; i < B; ++i) out.hi[i] = c[0], out.lo[i] = lo[0];
        return;
    }
    if (n <= fixed_length && plain == 0) {
        (exact ? compensated_exact_of : compensated_inexact_of)[static_cast<std::size_t>(n - 2)](c, lo, v, dv, out);
        return;
    }
    double sum[B], error[B], slope[B];
    for (std::size_t i = 0; i < B; ++i) sum[i] = c[n - 1], error[i] = plain > 0 ? 0.0 : lo[n - 1], slope[i] = 0;
    int k = n - 2;
    for (; k >= n - 1 - plain; --k) {
        const double ck = c[k];
        for (std::size_t i = 0; i < B; ++i) {
            slope[i] = mul_add(slope[i], v[i], sum[i]);
            sum[i] = mul_add(sum[i], v[i], ck);
        }
    }
    for (; k >= 0; --k) {
        const double ck = c[k], lk = lo[k];
        for (std::size_t i = 0; i < B; ++i) {
            slope[i] = mul_add(slope[i], v[i], sum[i]);
            const DoubleDouble product = two_product(sum[i], v[i]);
            const DoubleDouble s = two_sum(product.hi, ck);
            sum[i] = s.hi;
            error[i] = exact ? mul_add(error[i], v[i], product.lo + s.lo) : mul_add(error[i], v[i], (product.lo + s.lo) + lk);
        }
    }
    for (std::size_t i = 0; i < B; ++i) out.hi[i] = sum[i], out.lo[i] = mul_add(slope[i], dv[i], error[i]);
}

// (raw: a split term's p_m without its content, content_in_scale)
void accurate_polynomial_block(const TermPlan& t, const AccurateBlock& a, DDs& out, bool raw = false) {
    if (t.split > 0) {
        for (std::size_t i = 0; i < B; ++i) {
            const DoubleDouble x = raw ? split_sum(t.m.data(), t.n, t.split_c, a.qq.hi[i], a.qq.lo[i])
                                       : split_horner(t.m.data(), t.n, t.split_c, t.content, t.content_lo, a.qq.hi[i], a.qq.lo[i]);
            out.hi[i] = x.hi, out.lo[i] = x.lo;
        }
        return;
    }
    double v[B], dv[B];
    for (std::size_t i = 0; i < B; ++i) {
        if (t.var == table::Var::shifted) {
            Scaled s{};
            s.r = a.r[i], s.h = a.h, s.inv_h = a.inv_h;
            const DoubleDouble w = shifted_dd(s, t.centre, t.centre_lo);
            v[i] = w.hi, dv[i] = w.lo;
        } else if (t.var == table::Var::r) {
            v[i] = a.qq.hi[i], dv[i] = a.qq.lo[i];
        } else {
            v[i] = a.qq.hi[i] * a.qq.hi[i], dv[i] = a.dq2[i];
        }
    }
    compensated_horner_block(t.c, t.c_lo.data(), t.n, t.exact, v, dv, out, t.plain);
}

// How a fused term's value joins its piece: the piece's only term, rounded
// once after the scale; or one of several, added to the sum so far (to
// zero_dds for the first: 0 + term, as the generic loop's sum starts at 0).
enum class Fold { single, add };

// A split term's numbers besides its integer coefficients (table::Term::split):
// split_constant(split), the content.
struct SplitArgs {
    double c = 0, content = 0, content_lo = 0;
};

// ([[maybe_unused]] here and on the loops below: only the fused loops use
// them, which the copy without FMA leaves out; clang warns there.)
[[maybe_unused]] SplitArgs split_args(const TermPlan& t) { return {t.split_c, t.content, t.content_lo}; }

// A fused loop's coefficients: m for a split term, else c.
[[maybe_unused]] const double* fused_coefficients(const TermPlan& t) { return t.split > 0 ? t.m.data() : t.c; }

// The scale of a piece of one term (detail::content_in_scale: times the
// content of a split term).
DoubleDouble single_scale(const TermPlan& t, const DoubleDouble& scale) {
    return content_in_scale(t) ? content_times(t, scale) : scale;
}

// One term of accurate_piece_block at one point (Basis::one, not
// continuing a series, Horner length N, edge power P, power of q Low): the
// distance to the edge and its power in double-double, times q^Low (factor_dd's
// order), compensated Horner (split_sum for a split term), the product;
// the same operations in the same order as the generic loops, so the same
// bits. (ah: edge times h as a two-product, the same for every point.)
// (Raw: a split term's factor times p_m, its content left to the scale.)
template <int N, int P, bool VarR, bool SupportEdge, bool Exact, bool Split, bool Raw = false, int Low = 0>
MOLLIFY_INLINE DoubleDouble accurate_term_at(const double* k, const double* l, const SplitArgs& sp, double edge, double edge_lo,
                                             double dq2, const DoubleDouble& qq, const DoubleDouble& ee) {
    DoubleDouble factor{1.0, 0.0};
    if constexpr (P != 0) {
        DoubleDouble d = ee;
        if constexpr (!SupportEdge) d = interior_distance(edge, edge_lo, qq);
        if constexpr (!VarR) {
            // The support edge 1 (edge_lo 0: has_shape) as a constant, so that
            // W's and W'/r's (1 - q^2) and its powers are one common
            // subexpression in a pair loop, as in StaticKernel's; the same
            // operations, + 0.0 included (it makes a -0 low part +0).
            const DoubleDouble edge_plus_q = plus(SupportEdge ? 1.0 : edge, qq);
            d = d * DoubleDouble{edge_plus_q.hi, edge_plus_q.lo + (SupportEdge ? 0.0 : edge_lo)};
        }
        factor = ipow<P>(d);
    }
    if constexpr (Low != 0) factor = P != 0 ? factor * ipow<Low>(qq) : ipow<Low>(qq);
    DoubleDouble x{k[0], l[0]};
    if constexpr (Split) {
        static_assert(VarR && N > 1);
        const DoubleDouble p = split_sum(k, N, sp.c, qq.hi, qq.lo);  // k holds m
        x = Raw ? p : DoubleDouble{sp.content, sp.content_lo} * p;
    } else if constexpr (N > 1) {
        const double v = VarR ? qq.hi : qq.hi * qq.hi, dv = VarR ? qq.lo : dq2;
        double s = k[N - 1], error = l[N - 1], slope = 0;
        MOLLIFY_UNROLLED
        for (int j = N - 2; j >= 0; --j) {
            slope = mul_add(slope, v, s);
            const DoubleDouble product = two_product(s, v);
            const DoubleDouble ps = two_sum(product.hi, k[j]);
            s = ps.hi;
            if constexpr (Exact) error = mul_add(error, v, product.lo + ps.lo);
            else error = mul_add(error, v, (product.lo + ps.lo) + l[j]);
        }
        x = {s, mul_add(slope, dv, error)};
    }
    return factor * x;
}

// The same term on a block in one pass, folded into its piece: one pass
// instead of five (the double-double block arrays between the passes cost
// more than the arithmetic: kernel_bench, README).
template <int N, int P, bool VarR, bool SupportEdge, bool Exact, bool Split, int Low>
MOLLIFY_FLATTEN void accurate_term_fixed(const TermPlan& t, const AccurateBlock& a, Fold fold, const DDs& from, DDs& sum,
                                         double* out) {
    double k[N], l[N];
    const double* c = fused_coefficients(t);
    for (int j = 0; j < N; ++j) k[j] = c[j], l[j] = t.c_lo[static_cast<std::size_t>(j)];
    const SplitArgs sp = split_args(t);
    const double edge = t.edge, edge_lo = t.edge_lo;
    const DDs& to_edge = t.unit_edge ? a.eu : a.ee;
    auto term = [&]<bool Raw>(std::size_t i) {
        return accurate_term_at<N, P, VarR, SupportEdge, Exact, Split, Raw, Low>(
            k, l, sp, edge, edge_lo, a.dq2[i], {a.qq.hi[i], a.qq.lo[i]}, {to_edge.hi[i], to_edge.lo[i]});
    };
    if (fold == Fold::single) {
        const DoubleDouble scale = single_scale(t, a.scale);
        for (std::size_t i = 0; i < B; ++i) out[i] = rounded_product_bounded(term.template operator()<Split>(i), scale);
    } else {
        for (std::size_t i = 0; i < B; ++i) {
            const DoubleDouble y = DoubleDouble{from.hi[i], from.lo[i]} + term.template operator()<false>(i);
            sum.hi[i] = y.hi, sum.lo[i] = y.lo;
        }
    }
}

// A whole quantity that is one term at one radius (x: its accurate_radius),
// its edge in units of 2^e where its shape says so (unit_edge_shape: the
// plan sends only such quantities here; the unit: Smoothing::binary_unit, significand).
struct Unit {
    double binary_unit, significand;
};
template <int N, int P, bool VarR, bool SupportEdge, bool Exact, bool Split>
MOLLIFY_INLINE double accurate_whole_at(const double* k, const double* l, const SplitArgs& sp, double edge, double edge_lo,
                                        double h, double r, const AccurateRadius& x, const DoubleDouble& scale, Unit u) {
    constexpr bool unit = unit_edge_shape({VarR, SupportEdge, Exact, N, P, Split ? 1 : 0, 0});
    const DoubleDouble to_edge =
        unit ? unit_distance(r, u.binary_unit, u.significand) : DoubleDouble{x.ee_hi, x.ee_lo};
    const DoubleDouble y = accurate_term_at<N, P, VarR, SupportEdge, Exact, Split, true>(
        k, l, sp, edge, edge_lo, x.dq2, {x.qq_hi, x.qq_lo}, to_edge);
    return select(r <= h, rounded_product_bounded(y, scale), 0.0);
}

// A whole quantity that is one term (fast_whole_fixed) in one pass from r.
template <int N, int P, bool VarR, bool SupportEdge, bool Exact, bool Split>
MOLLIFY_FLATTEN bool accurate_whole_fixed(const TermPlan& t, const double* __restrict r, double* __restrict out,
                                          std::size_t n, const Smoothing& s, DoubleDouble scale) {
    double k[N], l[N];
    const double* c = fused_coefficients(t);
    for (int j = 0; j < N; ++j) k[j] = c[j], l[j] = t.c_lo[static_cast<std::size_t>(j)];
    const SplitArgs sp = split_args(t);
    const double edge = t.edge, edge_lo = t.edge_lo, h = s.h(), inv_h = s.inverse();
    const DoubleDouble whole = single_scale(t, scale);
    const Unit u{s.binary_unit(), s.significand()};
    std::uint64_t refused = 0;
    for (std::size_t i = 0; i < n; ++i) {
        refused |= not_a_radius(r[i]);
        out[i] = accurate_whole_at<N, P, VarR, SupportEdge, Exact, Split>(k, l, sp, edge, edge_lo, h, r[i],
                                                                          accurate_radius(r[i], h, inv_h), whole, u);
    }
    return refused != 0;
}

// The fused loops of the listed shapes (term_shapes.hpp), compiled where
// the target fuses multiply-add: without an FMA every two_product is
// Veltkamp's split, and the generic-x86-64 copy of the library (for CPUs
// older than Haswell) keeps the general loops rather than double its
// compile time.
constexpr bool fused_loops = MOLLIFY_HAS_FMA;

using AccurateTerm = void (*)(const TermPlan&, const AccurateBlock&, Fold, const DDs&, DDs&, double*);
using AccurateWhole = bool (*)(const TermPlan&, const double*, double*, std::size_t, const Smoothing&, DoubleDouble);
using FastWhole = bool (*)(const TermPlan&, const double*, double*, std::size_t, const Smoothing&, double);

template <const TermShape& S>
[[maybe_unused]] constexpr AccurateTerm accurate_term_loop =
    &accurate_term_fixed<S.n, S.edge_power, S.var_r, S.support_edge, S.exact, (S.split > 0), S.low>;
// (A whole quantity's piece starts at 0: no negative power of q, the
// generator's and the plan's fusable rule.)
template <const TermShape& S>
[[maybe_unused]] constexpr AccurateWhole accurate_whole_loop = [] {
    static_assert(S.low == 0, "a whole quantity's term has no power of q");
    return &accurate_whole_fixed<S.n, S.edge_power, S.var_r, S.support_edge, S.exact, (S.split > 0)>;
}();
template <const TermShape& S>
[[maybe_unused]] constexpr FastWhole fast_whole_loop = [] {
    static_assert(S.low == 0, "a whole quantity's term has no power of q");
    return &fast_whole_fixed<S.n, S.edge_power, S.var_r, S.support_edge>;
}();

template <std::size_t... I>
constexpr std::array<AccurateTerm, sizeof...(I)> accurate_term_loops(std::index_sequence<I...>) {
    if constexpr (fused_loops) return {accurate_term_loop<term_shape<I>>...};
    else return {};
}
template <std::size_t... I>
constexpr std::array<AccurateWhole, sizeof...(I)> accurate_whole_loops(std::index_sequence<I...>) {
    if constexpr (fused_loops) return {accurate_whole_loop<whole_shape<I>>...};
    else return {};
}
template <std::size_t... I>
constexpr std::array<FastWhole, sizeof...(I)> fast_whole_loops(std::index_sequence<I...>) {
    if constexpr (fused_loops) return {fast_whole_loop<whole_shape<I>>...};
    else return {};
}
constexpr auto accurate_term_of = accurate_term_loops(std::make_index_sequence<term_shape_count>{});
constexpr auto accurate_whole_of = accurate_whole_loops(std::make_index_sequence<whole_shape_count>{});
constexpr auto fast_whole_of = fast_whole_loops(std::make_index_sequence<whole_shape_count>{});

// W and grad W at displacements for a kernel whose W and W'/r are both one
// fused term, 0 outside (Plan::whole_pair), in one pass, as
// StaticKernel::pairs_3d: r, W, W'/r, grad W = (W'/r) x, each quantity as
// its whole loop computes it (accurate: one accurate_radius for both), so
// the same bits. The loop is StaticKernel's (detail::pairs_at_radii: the
// roots a block ahead; restrict pointers, so that it vectorises).
// (The fast precision reads no low parts: Exact false, one loop per shape.)
// 2D takes it with x2 = 0 (pairs_batch).
template <Precision Pr, int VN, int VP, bool VR, bool VE, bool VX, bool VS, int GN, int GP, bool GR, bool GE, bool GX,
          bool GS>
MOLLIFY_FLATTEN bool whole_pairs_fixed(const TermPlan& v, const TermPlan& g, const double* __restrict x0,
                                       const double* __restrict x1, const double* __restrict x2, double* __restrict w,
                                       double* __restrict g0, double* __restrict g1, double* __restrict g2, std::size_t n,
                                       const Smoothing& smoothing, DoubleDouble v_accurate_scale,
                                       DoubleDouble g_accurate_scale) {
    const Smoothing s = smoothing;
    const double h = s.h(), inv_h = s.inverse(), v_edge = v.edge, g_edge = g.edge;
    double vk[VN], vl[VN], gk[GN], gl[GN];
    // (the fast precision reads c: VS and GS are false there)
    const double *vc = VS ? v.m.data() : v.c, *gc = GS ? g.m.data() : g.c;
    for (int j = 0; j < VN; ++j) vk[j] = vc[j], vl[j] = v.c_lo[static_cast<std::size_t>(j)];
    for (int j = 0; j < GN; ++j) gk[j] = gc[j], gl[j] = g.c_lo[static_cast<std::size_t>(j)];
    // One grid for both where both split (the plan's one_split_grid): W's
    // constant for W'/r too, so that q is split once a point (the same value).
    const SplitArgs v_sp = split_args(v), g_sp{VS && GS ? v_sp.c : g.split_c, g.content, g.content_lo};
    const double v_scale = s.scale(QuantityId::value), g_scale = s.scale(QuantityId::grad_over_r);
    // (single_scale: a split term's content joins the scale, which has m^-P
    // where the edge is in units of 2^e)
    const DoubleDouble v_scale_dd = single_scale(v, v_accurate_scale), g_scale_dd = single_scale(g, g_accurate_scale);
    const Unit u{s.binary_unit(), s.significand()};
    return pairs_at_radii<true>(n, x0, x1, x2, w, g0, g1, g2, [&](double r) MOLLIFY_INLINE_LAMBDA {
        if constexpr (Pr == Precision::fast) {
            return std::pair{fast_whole_at<VN, VP, VR, VE>(vk, r, v_edge, h, inv_h, s, v_scale),
                             fast_whole_at<GN, GP, GR, GE>(gk, r, g_edge, h, inv_h, s, g_scale)};
        } else {
            const AccurateRadius x = accurate_radius(r, h, inv_h);
            return std::pair{
                accurate_whole_at<VN, VP, VR, VE, VX, VS>(vk, vl, v_sp, v_edge, v.edge_lo, h, r, x, v_scale_dd, u),
                accurate_whole_at<GN, GP, GR, GE, GX, GS>(gk, gl, g_sp, g_edge, g.edge_lo, h, r, x, g_scale_dd, u)};
        }
    });
}

using WholePairs = bool (*)(const TermPlan&, const TermPlan&, const double*, const double*, const double*, double*, double*,
                            double*, double*, std::size_t, const Smoothing&, DoubleDouble, DoubleDouble);

template <Precision Pr, const WholePair& S>
constexpr WholePairs whole_pairs_loop() {
    constexpr bool fast = Pr == Precision::fast;
    constexpr TermShape V = S.value, G = S.over_r;
    static_assert(V.low == 0 && G.low == 0, "a whole quantity's term has no power of q");
    return &whole_pairs_fixed<Pr, V.n, V.edge_power, V.var_r, V.support_edge, V.exact && !fast, (V.split > 0) && !fast, G.n,
                              G.edge_power, G.var_r, G.support_edge, G.exact && !fast, (G.split > 0) && !fast>;
}
template <Precision Pr, std::size_t... I>
constexpr std::array<WholePairs, sizeof...(I)> whole_pairs_loops(std::index_sequence<I...>) {
    if constexpr (fused_loops) return {whole_pairs_loop<Pr, whole_pair<I>>()...};
    else return {};
}
// [Plan::whole_pair]
template <Precision Pr>
constexpr auto whole_pairs_of = whole_pairs_loops<Pr>(std::make_index_sequence<whole_pair_count>{});

// ---- a quantity of pieces of one fused term each (QuantityPlan::pieces_fused) ----

// Such a quantity's pieces (the cubic spline's W and W'/r) read once: each
// piece's coefficients (m for a split term), low parts, edge, split and
// scale (single_scale: a split term's content joins it), its lower end.
template <const ShapeList& S, Precision Pr>
struct Pieces {
    static constexpr std::size_t m = S.m;
    static constexpr int longest = [] {
        int n = 1;
        for (std::size_t p = 0; p < S.m; ++p) n = std::max(n, S.shapes[p].n);
        return n;
    }();
    double k[m][longest], l[m][longest], lo[m], edge[m], edge_lo[m], fast_scale;
    SplitArgs split[m];
    DoubleDouble scale[m];

    Pieces(const QuantityPlan& qp, double quantity_scale, double quantity_scale_lo) : fast_scale(quantity_scale) {
        for (std::size_t p = 0; p < m; ++p) {
            const TermPlan& t = qp.inner[p].terms.front();
            const double* c = Pr == Precision::accurate ? fused_coefficients(t) : t.c;
            for (int j = 0; j < S.shapes[p].n; ++j) k[p][j] = c[j], l[p][j] = t.c_lo[static_cast<std::size_t>(j)];
            lo[p] = qp.inner[p].lo, edge[p] = t.edge, edge_lo[p] = t.edge_lo;
            split[p] = split_args(t);
            scale[p] = single_scale(t, {quantity_scale, quantity_scale_lo});
        }
    }

    // Precision::accurate at r (x: its accurate_radius): radial_block's
    // operations, so its bits (and StaticKernel's): each piece alone
    // (accurate_piece_block's Fold::single), the piece of q (a.q < lo: the
    // one below), 0 beyond h.
    MOLLIFY_INLINE double accurate(double r, double h, const AccurateRadius& x) const {
        double in = 0;
        [&]<std::size_t... P>(std::index_sequence<P...>) MOLLIFY_INLINE_LAMBDA {
            auto piece = [&]<std::size_t Q>(std::integral_constant<std::size_t, Q>) MOLLIFY_INLINE_LAMBDA {
                constexpr TermShape T = S.shapes[Q];
                constexpr bool split_term = T.split > 0;
                const DoubleDouble y = accurate_term_at<T.n, T.edge_power, T.var_r, T.support_edge, T.exact, split_term,
                                                        split_term, T.low>(k[Q], l[Q], split[Q], edge[Q], edge_lo[Q], x.dq2,
                                                                           {x.qq_hi, x.qq_lo}, {x.ee_hi, x.ee_lo});
                const double v = rounded_product_bounded(y, scale[Q]);
                in = Q == 0 ? v : select(x.q < lo[Q], in, v);
            };
            (piece(std::integral_constant<std::size_t, P>{}), ...);
        }(std::make_index_sequence<m>{});
        return select(r <= h, in, 0.0);
    }

    // Precision::fast at r: fast_zero_outside_block's operations (each
    // piece 0 + its term, the selection, the scale, 0 beyond h).
    MOLLIFY_INLINE double fast(double r, double q, double e, double h, double inv_h) const {
        double in = 0;
        [&]<std::size_t... P>(std::index_sequence<P...>) MOLLIFY_INLINE_LAMBDA {
            auto piece = [&]<std::size_t Q>(std::integral_constant<std::size_t, Q>) MOLLIFY_INLINE_LAMBDA {
                constexpr TermShape T = S.shapes[Q];
                const double v =
                    0.0 + fast_term_at<T.n, T.edge_power, T.var_r, T.support_edge, T.low>(k[Q], q, e, r, edge[Q], h, inv_h);
                in = Q == 0 ? v : select(q < lo[Q], in, v);
            };
            (piece(std::integral_constant<std::size_t, P>{}), ...);
        }(std::make_index_sequence<m>{});
        return select(r <= h, in * fast_scale, 0.0);
    }
};

// W and grad W at displacements for a kernel whose W and W'/r are such
// pieces at the same breakpoints (Plan::pieces_pair), in one pass as
// StaticKernel::pairs_3d (every piece at every point, the piece of q
// selected; the roots a block ahead): each quantity radial_block's
// operations, so the same bits. Before it (the quantities in blocks of
// their own, the cubic spline's W'/r outer term q^-1 (1 - q)^2 through the
// general loops) the cubic spline's W + grad W took 3x StaticKernel's time
// accurate, 1.8x fast; in one pass 0.91-1.05x (kernel_bench, the Intel
// host, stop 69). 2D takes it with x2 = 0 (in_3d).
template <Precision Pr, const ShapeList& V, const ShapeList& G>
MOLLIFY_FLATTEN bool pieces_pairs_fixed(const QuantityPlan& value, const QuantityPlan& over_r, const double* __restrict x0,
                                        const double* __restrict x1, const double* __restrict x2, double* __restrict w,
                                        double* __restrict g0, double* __restrict g1, double* __restrict g2, std::size_t n,
                                        const Smoothing& smoothing) {
    const Smoothing s = smoothing;
    const double h = s.h(), inv_h = s.inverse();
    const Pieces<V, Pr> v(value, s.scale(QuantityId::value), s.scale_lo(QuantityId::value));
    const Pieces<G, Pr> g(over_r, s.scale(QuantityId::grad_over_r), s.scale_lo(QuantityId::grad_over_r));
    return pairs_at_radii<true>(n, x0, x1, x2, w, g0, g1, g2, [&](double r) MOLLIFY_INLINE_LAMBDA {
        if constexpr (Pr == Precision::fast) {
            const double q = r * inv_h, e = edge_distance(h - r, s);
            return std::pair{v.fast(r, q, e, h, inv_h), g.fast(r, q, e, h, inv_h)};
        } else {
            const AccurateRadius x = accurate_radius(r, h, inv_h);
            return std::pair{v.accurate(r, h, x), g.accurate(r, h, x)};
        }
    });
}

// Such a quantity alone at n radii in one pass from r (the batch
// evaluation, and the pair loop's chunks in 1D), radial_block's operations:
// the cubic spline's W per 4096 radii took 1.2x StaticKernel's time
// accurate, 2.0x fast in blocks of 64, 1.0-1.1x in one pass (kernel_bench,
// the Intel host, stop 69).
template <Precision Pr, const ShapeList& S>
MOLLIFY_FLATTEN bool pieces_fixed(const QuantityPlan& qp, const double* __restrict r, double* __restrict out, std::size_t n,
                                  const Smoothing& smoothing, double scale, double scale_lo) {
    const Smoothing s = smoothing;
    const double h = s.h(), inv_h = s.inverse();
    const Pieces<S, Pr> pieces(qp, scale, scale_lo);
    std::uint64_t refused = 0;
    for (std::size_t i = 0; i < n; ++i) {
        refused |= not_a_radius(r[i]);
        if constexpr (Pr == Precision::fast)
            out[i] = pieces.fast(r[i], r[i] * inv_h, edge_distance(h - r[i], s), h, inv_h);
        else
            out[i] = pieces.accurate(r[i], h, accurate_radius(r[i], h, inv_h));
    }
    return refused != 0;
}

using PiecesLoop = bool (*)(const QuantityPlan&, const double*, double*, std::size_t, const Smoothing&, double, double);

template <Precision Pr, std::size_t... I>
constexpr std::array<PiecesLoop, sizeof...(I)> pieces_loops(std::index_sequence<I...>) {
    if constexpr (fused_loops) return {&pieces_fixed<Pr, piece_list<I>>...};
    else return {};
}
// [QuantityPlan::pieces_fused]
template <Precision Pr>
constexpr auto pieces_of = pieces_loops<Pr>(std::make_index_sequence<piece_shapes_count>{});

using PiecesPairs = bool (*)(const QuantityPlan&, const QuantityPlan&, const double*, const double*, const double*, double*,
                             double*, double*, double*, std::size_t, const Smoothing&);

template <Precision Pr, std::size_t... I>
constexpr std::array<PiecesPairs, sizeof...(I)> pieces_pairs_loops(std::index_sequence<I...>) {
    if constexpr (fused_loops)
        return {&pieces_pairs_fixed<Pr, piece_list<pieces_pairs[I].value>, piece_list<pieces_pairs[I].over_r>>...};
    else
        return {};
}
// [Plan::pieces_pair]
template <Precision Pr>
constexpr auto pieces_pairs_of = pieces_pairs_loops<Pr>(std::make_index_sequence<pieces_pair_count>{});

bool fused_accurate(const TermPlan& t) { return fused_loops && t.shape >= 0; }

void accurate_term_block(const TermPlan& t, const AccurateBlock& a, Fold fold, const DDs& from, DDs& sum, double* out) {
    accurate_term_of[static_cast<std::size_t>(t.shape)](t, a, fold, from, sum, out);
}

// accurate_piece for pieces of Basis::one terms.
void accurate_piece_block(const PiecePlan& p, const AccurateBlock& a, double* out) {
    DDs factor, x, d, previous, sum;
    if (p.edge_series) {
        const TermPlan& first = p.terms.front();
        distance_to_edge_block(first, a, d);
        for (std::size_t i = 0; i < B; ++i) {
            const DoubleDouble w = fast_two_sum(d.hi[i], d.lo[i]);
            d.hi[i] = w.hi, d.lo[i] = w.lo;
        }
        compensated_horner_block(p.series_c.data(), p.series_lo.data(), static_cast<int>(p.series_c.size()),
                                 p.series_exact, d.hi, d.lo, sum);
        factor_block(first, a, factor);
        for (std::size_t i = 0; i < B; ++i)
            out[i] = rounded_product(DoubleDouble{factor.hi[i], factor.lo[i]} * DoubleDouble{sum.hi[i], sum.lo[i]}, a.scale);
        return;
    }
    const bool single = p.terms.size() == 1;
    if (!p.terms.empty() && std::all_of(p.terms.begin(), p.terms.end(), fused_accurate)) {
        if (single) {
            accurate_term_block(p.terms.front(), a, Fold::single, zero_dds, sum, out);
            return;
        }
        for (std::size_t t = 0; t < p.terms.size(); ++t)
            accurate_term_block(p.terms[t], a, Fold::add, t == 0 ? zero_dds : sum, sum, out);
        for (std::size_t i = 0; i < B; ++i) out[i] = rounded_product(DoubleDouble{sum.hi[i], sum.lo[i]}, a.scale);
        return;
    }
    for (std::size_t i = 0; i < B; ++i) sum.hi[i] = 0.0, sum.lo[i] = 0.0, previous.hi[i] = 1.0, previous.lo[i] = 0.0;
    for (const TermPlan& t : p.terms) {
        if (t.continues) {
            distance_to_edge_block(t, a, d);
            ipow_block(d, t.step, factor);
            for (std::size_t i = 0; i < B; ++i) {
                const DoubleDouble y = DoubleDouble{previous.hi[i], previous.lo[i]} * DoubleDouble{factor.hi[i], factor.lo[i]};
                factor.hi[i] = y.hi, factor.lo[i] = y.lo;
            }
        } else if (t.has_factor) {
            factor_block(t, a, factor);
        } else {
            for (std::size_t i = 0; i < B; ++i) factor.hi[i] = 1.0, factor.lo[i] = 0.0;
        }
        accurate_polynomial_block(t, a, x, single && content_in_scale(t));
        const DoubleDouble scale = single ? single_scale(t, a.scale) : a.scale;
        for (std::size_t i = 0; i < B; ++i) {
            const DoubleDouble term = DoubleDouble{factor.hi[i], factor.lo[i]} * DoubleDouble{x.hi[i], x.lo[i]};
            if (single) {
                out[i] = rounded_product(term, scale);
            } else {
                const DoubleDouble s = DoubleDouble{sum.hi[i], sum.lo[i]} + term;
                sum.hi[i] = s.hi, sum.lo[i] = s.lo;
            }
        }
        previous = factor;
    }
    if (!single)
        for (std::size_t i = 0; i < B; ++i) out[i] = rounded_product(DoubleDouble{sum.hi[i], sum.lo[i]}, a.scale);
}

// scaled_accurate at the B radii r, and where a.unit_edge their unit_distance.
void fill(AccurateBlock& a, const double* r) {
    for (std::size_t i = 0; i < B; ++i) {
        const AccurateRadius x = accurate_radius(r[i], a.h, a.inv_h);
        a.q[i] = x.q, a.e[i] = x.ee_hi + x.ee_lo, a.r[i] = r[i], a.dq2[i] = x.dq2;
        a.qq.hi[i] = x.qq_hi, a.qq.lo[i] = x.qq_lo, a.ee.hi[i] = x.ee_hi, a.ee.lo[i] = x.ee_lo;
    }
    if (a.unit_edge)
        for (std::size_t i = 0; i < B; ++i) {
            const DoubleDouble u = unit_distance(r[i], a.binary_unit, a.significand);
            a.eu.hi[i] = u.hi, a.eu.lo[i] = u.lo;
        }
}

// Precision::fast, a combination's distinct terms (QuantityPlan::
// shared_terms) of the listed shapes (shared_shapes), their coefficients,
// radii and edges read once into registers.
template <const ShapeList& S>
struct SharedTerms {
    static_assert([] {
        for (std::size_t j = 0; j < S.m; ++j)
            if (S.shapes[j].low != 0) return false;
        return true;
    }(), "a combination's shared terms have no power of q (their first piece starts at 0)");
    static constexpr std::size_t m = S.m;
    static constexpr int longest = [] {
        int n = 1;
        for (std::size_t j = 0; j < S.m; ++j) n = std::max(n, S.shapes[j].n);
        return n;
    }();
    double k[m][longest], hi[m], edge[m];

    explicit SharedTerms(const QuantityPlan& qp) { read(qp, std::make_index_sequence<m>{}); }

    template <std::size_t... J>
    MOLLIFY_INLINE void read(const QuantityPlan& qp, std::index_sequence<J...>) {
        auto one = [&]<std::size_t j>(std::integral_constant<std::size_t, j>) {
            const TermPlan& t = qp.inner[qp.shared_terms[j].piece].terms[qp.shared_terms[j].term];
            for (int c = 0; c < S.shapes[j].n; ++c) k[j][c] = t.c[c];
            hi[j] = qp.shared_terms[j].hi, edge[j] = t.edge;
        };
        (one(std::integral_constant<std::size_t, J>{}), ...);
    }

    // Does term J reach q? The terms are radii in order (these loops take
    // only such: shared_shapes_index), each from q = 0 up to its radius, the
    // last to the support: one comparison, none for the last (as StaticKernel's
    // detail::reaches; where q is no number the caller discards the sum).
    template <std::size_t J>
    MOLLIFY_INLINE bool reaches(double q) const {
        if constexpr (J + 1 == S.m) return true;
        else return q < hi[J];
    }

    // The sum at one point: shared_terms_block's operations in its order (0
    // + the first, +0 where a term's pieces end), so its bits, in registers.
    template <std::size_t... J>
    MOLLIFY_INLINE double sum(double q, double e, double r, double h, double inv_h, std::index_sequence<J...> terms) const {
        return sum(q, e, r, h, inv_h, *this, terms);
    }

    // The same with the radii read from `at` (the pair loop's W'/r from W's,
    // AccurateSharedTerms::sum): one distance per radius for both.
    template <class Radii, std::size_t... J>
    MOLLIFY_INLINE double sum(double q, double e, double r, double h, double inv_h, const Radii& at,
                              std::index_sequence<J...>) const {
        double x = 0.0;
        ((x = x + select(reaches<J>(q),
                         fast_term_at<S.shapes[J].n, S.shapes[J].edge_power, S.shapes[J].var_r, S.shapes[J].support_edge>(
                             k[J], q, e, r, at.edge[J], h, inv_h),
                         0.0)),
         ...);
        return x;
    }
};

// A quantity of shared terms, 0 outside, at n radii in one pass from r:
// radial_block's q, e, sum, scale and 0 beyond h for each point.
template <const ShapeList& S>
MOLLIFY_FLATTEN bool shared_whole_loop(const QuantityPlan& qp, const double* __restrict r, double* __restrict out,
                                       std::size_t n, const Smoothing& smoothing, double scale) {
    const Smoothing s = smoothing;
    const SharedTerms<S> t(qp);
    const double h = s.h(), inv_h = s.inverse();
    std::uint64_t refused = 0;
    for (std::size_t i = 0; i < n; ++i) {
        refused |= not_a_radius(r[i]);
        const double x = t.sum(r[i] * inv_h, edge_distance(h - r[i], s), r[i], h, inv_h, std::make_index_sequence<S.m>{});
        out[i] = select(r[i] <= h, x * scale, 0.0);
    }
    return refused != 0;
}

using SharedWhole = bool (*)(const QuantityPlan&, const double*, double*, std::size_t, const Smoothing&, double);

template <std::size_t... I>
constexpr std::array<SharedWhole, sizeof...(I)> shared_whole_loops(std::index_sequence<I...>) {
    return {&shared_whole_loop<shared_list<I>>...};
}
// [QuantityPlan::shared_fused], in both instruction sets (few, short loops)
constexpr auto shared_whole_of = shared_whole_loops(std::make_index_sequence<shared_shapes_count>{});

// Precision::accurate, the same: each distinct term once in double-double
// (accurate_term_at, Exact false: QuantityPlan::shared_accurate), added to
// the sum where its pieces reach and (0, 0) elsewhere. The static form sums
// a piece's terms from (0, 0) as well; adding (0, 0) changes a
// double-double sum's value at most in the sign of a zero low part (two_sum
// is exact), so the result is the pieces' evaluated and selected, but for
// the sign of a zero W (+0 where a one-term piece gives -0 at its edge).
template <const ShapeList& S>
struct AccurateSharedTerms : SharedTerms<S> {
    using SharedTerms<S>::m;
    using SharedTerms<S>::longest;
    // The low parts besides the fast precision's coefficients, ranges and edges.
    double l[m][longest], edge_lo[m];
    double km[m][longest];  // a split term's m (table::Term::split), else its c
    double content[m], content_lo[m];  // a split term's (table::Term::split), else 0

    explicit AccurateSharedTerms(const QuantityPlan& qp) : SharedTerms<S>(qp) {
        read_low_parts(qp, std::make_index_sequence<m>{});
    }

    template <std::size_t... J>
    MOLLIFY_INLINE void read_low_parts(const QuantityPlan& qp, std::index_sequence<J...>) {
        auto one = [&]<std::size_t j>(std::integral_constant<std::size_t, j>) {
            const TermPlan& t = qp.inner[qp.shared_terms[j].piece].terms[qp.shared_terms[j].term];
            for (int c = 0; c < S.shapes[j].n; ++c) l[j][c] = t.c_lo[static_cast<std::size_t>(c)];
            for (int c = 0; c < S.shapes[j].n; ++c) km[j][c] = fused_coefficients(t)[c];
            content[j] = t.content, content_lo[j] = t.content_lo;
            edge_lo[j] = t.edge_lo;
        };
        (one(std::integral_constant<std::size_t, J>{}), ...);
    }

    // StaticKernel's sum (detail::shared_accurate_inside), the same bits:
    // the first term added to (+0, +0) is itself with +0 for -0. Skip: the
    // first Skip terms are (0, 0) at x (radii_in_order: no point of the
    // caller's register reaches them); left out, the same bits (from y =
    // (0, 0) their sums were (+0, +0) + (+0, +0)).
    template <std::size_t Skip = 0, std::size_t... J>
    MOLLIFY_INLINE DoubleDouble sum(const AccurateRadius& x, std::index_sequence<J...> terms) const {
        return sum<Skip>(x, *this, terms);
    }

    // The same with the radii (edge, edge_lo) read from `at`, another
    // quantity's terms at the same radii (the pair loop's W'/r from W's:
    // Plan::shared_pair requires them equal): one distance per radius for
    // both, and their powers' common squares, as in StaticKernel's loop.
    template <std::size_t Skip, class Radii, std::size_t... J>
    MOLLIFY_INLINE DoubleDouble sum(const AccurateRadius& x, const Radii& at, std::index_sequence<J...>) const {
        DoubleDouble y{0.0, 0.0};
        auto add = [&]<std::size_t I>(std::integral_constant<std::size_t, I>) MOLLIFY_INLINE_LAMBDA {
            if constexpr (I >= Skip) {
                // the grid from the shape (S.shapes[I].split: table::Term::split),
                // a constant: terms of one grid share it, as in StaticKernel's sum
                constexpr int grid = S.shapes[I].split;
                const SplitArgs split{grid > 0 ? split_constant(grid) : 0.0, content[I], content_lo[I]};
                const DoubleDouble t =
                    accurate_term_at<S.shapes[I].n, S.shapes[I].edge_power, S.shapes[I].var_r, S.shapes[I].support_edge, false,
                                     (grid > 0)>(km[I], l[I], split, at.edge[I], at.edge_lo[I], x.dq2, {x.qq_hi, x.qq_lo},
                                                 {x.ee_hi, x.ee_lo});
                const bool in = this->template reaches<I>(x.q);
                const DoubleDouble here{select(in, t.hi, 0.0), select(in, t.lo, 0.0)};
                if constexpr (I == Skip) y = {here.hi + 0.0, here.lo + 0.0};
                else y = y + here;
            }
        };
        (add(std::integral_constant<std::size_t, J>{}), ...);
        return y;
    }
};

// The levels of a register of points (at level L the first L terms are 0),
// from the plan's terms, as StaticKernel's: the fused loops take only radii
// in order (shared_shapes_index), and a pair's W'/r only at W's radii
// (same_radii), so the l-th radius is v's.
template <int Levels>
RadiusLevel<Levels> shared_level(const std::vector<QuantityPlan::SharedTerm>& v, double h) {
    return {[&](int l) { return v[static_cast<std::size_t>(l)].hi; }, h};
}

// One quantity's shared terms at n radii, by levels (StaticKernel's
// evaluate: for_each_register_at_levels).
template <const ShapeList& S>
MOLLIFY_FLATTEN bool accurate_shared_loop(const QuantityPlan& qp, const double* __restrict r, double* __restrict out,
                                          std::size_t n, const Smoothing& smoothing, DoubleDouble scale) {
    const double h = smoothing.h(), inv_h = smoothing.inverse();
    const AccurateSharedTerms<S> t(qp);
    constexpr int levels = static_cast<int>(S.m);
    NotRadii refused;
    for_each_register_at_levels<levels>(
        n, r, shared_level<levels>(qp.shared_terms, h),
        [&]<int L>(std::size_t i, std::integral_constant<int, L>) MOLLIFY_INLINE_LAMBDA {
            const DoubleDouble y =
                t.template sum<static_cast<std::size_t>(L)>(accurate_radius(r[i], h, inv_h), std::make_index_sequence<S.m>{});
            out[i] = select(r[i] <= h, rounded_product_bounded(y, scale), 0.0);
        },
        refused);
    return refused.any();
}

using AccurateShared = bool (*)(const QuantityPlan&, const double*, double*, std::size_t, const Smoothing&, DoubleDouble);

template <std::size_t... I>
constexpr std::array<AccurateShared, sizeof...(I)> accurate_shared_loops(std::index_sequence<I...>) {
    if constexpr (fused_loops) return {&accurate_shared_loop<shared_list<I>>...};
    else return {};
}
// [QuantityPlan::shared_fused], where the target fuses multiply-add (fused_loops)
constexpr auto accurate_shared_of = accurate_shared_loops(std::make_index_sequence<shared_shapes_count>{});

// W and grad W at displacements for a combination whose W and W'/r are
// both shared terms (Plan::shared_pair), in one pass, as whole_pairs_fixed:
// each quantity as shared_whole_loop or accurate_shared_loop computes it
// from r (accurate: one accurate_radius for both), so their bits. In the
// fast precision in every instruction set (the generic copy is compared
// with StaticKernel's pair loop bit for bit); 2D takes it with x2 = 0.
// The loop is detail::pairs_at_radii, as there.
template <Precision Pr, const ShapeList& SV, const ShapeList& SG>
MOLLIFY_FLATTEN bool shared_pairs_fixed(const QuantityPlan& value, const QuantityPlan& over_r, const double* __restrict x0,
                                        const double* __restrict x1, const double* __restrict x2, double* __restrict w,
                                        double* __restrict g0, double* __restrict g1, double* __restrict g2,
                                        std::size_t n, const Smoothing& smoothing) {
    const Smoothing s = smoothing;
    const double h = s.h(), inv_h = s.inverse();
    using Terms = std::conditional_t<Pr == Precision::fast, SharedTerms<SV>, AccurateSharedTerms<SV>>;
    using OverR = std::conditional_t<Pr == Precision::fast, SharedTerms<SG>, AccurateSharedTerms<SG>>;
    const Terms v(value);
    const OverR g(over_r);
    const double v_scale = s.scale(QuantityId::value), g_scale = s.scale(QuantityId::grad_over_r);
    const DoubleDouble v_scale_dd{v_scale, s.scale_lo(QuantityId::value)},
        g_scale_dd{g_scale, s.scale_lo(QuantityId::grad_over_r)};
    constexpr int levels = Pr == Precision::accurate && SV.m == SG.m ? static_cast<int>(SV.m) : 1;
    const RadiusLevel<levels> level = shared_level<levels>(value.shared_terms, h);
    return pairs_at_radii_at_levels<true, levels>(
        n, x0, x1, x2, w, g0, g1, g2,
        [&]<int L>(double r, std::integral_constant<int, L>) MOLLIFY_INLINE_LAMBDA {
            double wi, gi;
            if constexpr (Pr == Precision::fast) {
                const double q = r * inv_h, e = edge_distance(h - r, s);
                wi = v.sum(q, e, r, h, inv_h, std::make_index_sequence<SV.m>{}) * v_scale;
                gi = g.sum(q, e, r, h, inv_h, v, std::make_index_sequence<SG.m>{}) * g_scale;
            } else {
                constexpr std::size_t skip = static_cast<std::size_t>(L);
                const AccurateRadius x = accurate_radius(r, h, inv_h);
                wi = rounded_product_bounded(v.template sum<skip>(x, std::make_index_sequence<SV.m>{}), v_scale_dd);
                gi = rounded_product_bounded(g.template sum<skip>(x, v, std::make_index_sequence<SG.m>{}), g_scale_dd);
            }
            const bool inside = r <= h;
            return std::pair{select(inside, wi, 0.0), select(inside, gi, 0.0)};
        },
        level);
}

using SharedPairs = bool (*)(const QuantityPlan&, const QuantityPlan&, const double*, const double*, const double*,
                             double*, double*, double*, double*, std::size_t, const Smoothing&);

template <Precision Pr, std::size_t... I>
constexpr std::array<SharedPairs, sizeof...(I)> shared_pairs_loops(std::index_sequence<I...>) {
    if constexpr (Pr == Precision::fast || fused_loops)
        return {&shared_pairs_fixed<Pr, shared_list<shared_pairs[I].value>, shared_list<shared_pairs[I].over_r>>...};
    else
        return {};
}
// [Plan::shared_pair]
template <Precision Pr>
constexpr auto shared_pairs_of = shared_pairs_loops<Pr>(std::make_index_sequence<shared_pair_count>{});

// Is the quantity evaluated in one pass from r by its shared terms'
// loop (shared_whole_loop, accurate_shared_loop)?
bool shared_one_pass(const QuantityPlan& qp, QuantityId q, int dim, Precision pr) {
    if (qp.shared_fused < 0 || !qp.zero_outside || (q == QuantityId::potential && dim == 2)) return false;
    return pr == Precision::fast || (fused_loops && qp.shared_accurate);
}

// Is the quantity pieces of one fused term each (QuantityPlan::pieces_fused,
// 0 outside), evaluated in one pass from r (pieces_fixed)?
bool pieces_one_pass(const QuantityPlan& qp) { return fused_loops && qp.pieces_fused >= 0; }

// Precision::fast, the inner pieces of a quantity whose pieces share terms
// (QuantityPlan::shared_terms: a combination of m radii), at the B points
// of a: each distinct term once, added where its pieces reach and +0
// elsewhere, which changes no sum: the bits of the pieces evaluated and
// selected, for m instead of m(m+1)/2 terms. (The static form gets there
// by the compiler's common subexpressions.)
void shared_terms_block(const QuantityPlan& qp, const FastBlock& a, double* sum) {
    double x[B];
    const double* from = zeros;
    for (const QuantityPlan::SharedTerm& m : qp.shared_terms) {
        const TermPlan& t = qp.inner[m.piece].terms[m.term];
        if (fused(t)) {
            add_fused_term(t, a, m.lo, m.hi, from, sum);
        } else {
            SharedPowers& shared = shared_powers();
            shared.edge_valid = shared.s_valid = false;
            fast_term_block(t, nullptr, a, shared, x);
            for (std::size_t i = 0; i < B; ++i) sum[i] = from[i] + select((a.q[i] >= m.lo) & (a.q[i] < m.hi), x[i], 0.0);
        }
        from = sum;
    }
}

// Precision::fast, the inner pieces at the B points of a: every piece and
// the selection, or the shared terms once each.
void fast_inner_block(const QuantityPlan& qp, const FastBlock& a, double* in) {
    if (fused_loops && !qp.shared_terms.empty()) {
        shared_terms_block(qp, a, in);
        return;
    }
    double piece[B];
    for (std::size_t p = 0; p < qp.inner.size(); ++p) {
        fast_piece_block(qp.inner[p], a, p == 0 ? in : piece);
        if (p > 0)
            for (std::size_t i = 0; i < B; ++i) in[i] = select(a.q[i] < qp.inner[p].lo, in[i], piece[i]);
    }
}

// Precision::fast, a polynomial_inside quantity that is 0 outside, at the
// B points of a (StaticKernel::emitted): every piece, the selection, the
// scale, 0 beyond h.
void fast_zero_outside_block(const QuantityPlan& qp, const FastBlock& a, double scale, double* out) {
    double in[B];
    fast_inner_block(qp, a, in);
    for (std::size_t i = 0; i < B; ++i) out[i] = select(a.r[i] <= a.h, in[i] * scale, 0.0);
}

// Where the exterior has a logarithm (the 2D potential's log r:
// qp.log_coefficient != 0, StaticKernel::emitted's test) radial_block and
// radial_by_piece keep a branch between the support and the Green's
// function: a logarithm does not vectorise and costs more than the branch.
// Elsewhere outside_block and a select.

// The Green's function at B radii with no logarithm in it, each point
// outside()'s operations (green_term's: Horner's rule in r or r^2, times
// r^low), so its bits; a block loop per term instead of a scalar call per
// point (kernel_bench: the potential of mollifier:M=4 at radii up to 2h).
void outside_block(const QuantityPlan& qp, const double* r, double* out) {
    double v[B], x[B], p[B];
    const double* from = zeros;
    for (const TermPlan& t : qp.exterior.terms) {
        if (t.var == table::Var::r) {
            horner_block(t.c, t.n, r, x);
        } else {
            for (std::size_t i = 0; i < B; ++i) v[i] = r[i] * r[i];
            horner_block(t.c, t.n, v, x);
        }
        if (t.low != 0) {
            ipow_block(r, t.low, p);
            for (std::size_t i = 0; i < B; ++i) x[i] *= p[i];
        }
        for (std::size_t i = 0; i < B; ++i) out[i] = from[i] + x[i];
        from = out;
    }
    if (from == zeros)
        for (std::size_t i = 0; i < B; ++i) out[i] = 0.0;
}

// A polynomial_inside quantity at B radii (StaticKernel::emitted).
template <Precision Pr>
void radial_block(const QuantityPlan& qp, QuantityId q, const double* r, double* out, const Smoothing& s, int dim) {
    double in[B], piece[B];
    if constexpr (Pr == Precision::accurate) {
        AccurateBlock a(s, qp.unit_edge > 0);
        a.scale = accurate_scale(qp, q, s);
        fill(a, r);
        for (std::size_t p = 0; p < qp.inner.size(); ++p) {
            accurate_piece_block(qp.inner[p], a, p == 0 ? in : piece);
            if (p > 0)
                for (std::size_t i = 0; i < B; ++i) in[i] = select(a.q[i] < qp.inner[p].lo, in[i], piece[i]);
        }
    } else {
        FastBlock a;
        a.h = s.h(), a.inv_h = s.inverse();
        for (std::size_t i = 0; i < B; ++i) {
            a.q[i] = r[i] * s.inverse();
            a.e[i] = edge_distance(s.h() - r[i], s);
            a.r[i] = r[i];
        }
        fast_inner_block(qp, a, in);
        const double scale = s.scale(q);
        if (qp.zero_outside && !(q == QuantityId::potential && dim == 2)) {
            // The scale and the selection in one pass.
            for (std::size_t i = 0; i < B; ++i) out[i] = select(r[i] <= s.h(), in[i] * scale, 0.0);
            return;
        }
        for (std::size_t i = 0; i < B; ++i) in[i] = in[i] * scale;
    }
    if (q == QuantityId::potential && dim == 2)
        for (std::size_t i = 0; i < B; ++i) in[i] = mul_add(qp.log_coefficient, s.log_h(), in[i]);
    if (qp.zero_outside) {
        for (std::size_t i = 0; i < B; ++i) out[i] = select(r[i] <= s.h(), in[i], 0.0);
    } else if (qp.log_coefficient != 0) {
        for (std::size_t i = 0; i < B; ++i) out[i] = r[i] <= s.h() ? in[i] : outside(qp, r[i]);
    } else {
        double green[B];
        outside_block(qp, r, green);
        for (std::size_t i = 0; i < B; ++i) out[i] = select(r[i] <= s.h(), in[i], green[i]);
    }
}

// The indices of the n points in each inner piece.
template <Precision Pr>
void sort_into_pieces(const QuantityPlan& qp, const double* r, std::size_t n, const Smoothing& s,
                      std::vector<std::vector<std::size_t>>& members) {
    members.resize(qp.inner.size());
    for (auto& m : members) m.clear();
    for (std::size_t i = 0; i < n; ++i) {
        // The q each path selects its piece by: r/h rounded (radial<fast>),
        // or the rounded double-double quotient (scaled_accurate).
        const double qi = Pr == Precision::accurate ? accurate_radius(r[i], s.h(), s.inverse()).q : r[i] * s.inverse();
        // The last piece starting at or below qi (the pieces ascend), counted
        // without branches: on points in no order a search's branches
        // mispredict (kernel_bench repeats one batch, and the predictor
        // learns it at 4096 points, not at 10^6).
        std::size_t p = 0;
        for (std::size_t k = 1; k < qp.inner.size(); ++k) p += qi >= qp.inner[k].lo;
        members[p].push_back(i);
    }
}

// f_h at n radii: polynomial quantities by blocks (the last one padded
// with r = 0), the others point by point.
// Precision::fast for a quantity with pieces chosen by branches (sqrt,
// log): the points sorted into their pieces first (inner_piece), then each
// piece evaluated on blocks of its own points (the last one padded with a
// copy of its first point), so every block loop runs one piece's terms
// for B points; each point gets radial<fast>'s operations, so its bits.
template <Precision Pr>
void radial_by_piece(const QuantityPlan& qp, QuantityId q, const double* r, double* out, std::size_t n,
                     const Smoothing& s, int dim) {
    thread_local std::vector<std::vector<std::size_t>> members;
    sort_into_pieces<Pr>(qp, r, n, s, members);
    const double scale = s.scale(q);
    FastBlock a;
    AccurateBlock aa(s, qp.unit_edge > 0);
    a.h = s.h(), a.inv_h = s.inverse();
    aa.scale = accurate_scale(qp, q, s);
    double in[B], rb[B], green[B];
    for (std::size_t p = 0; p < qp.inner.size(); ++p) {
        const std::vector<std::size_t>& m = members[p];
        // Only the last piece holds points beyond the support (q >= 1).
        const bool green_by_block = !qp.zero_outside && qp.log_coefficient == 0 && p + 1 == qp.inner.size();
        for (std::size_t start = 0; start < m.size(); start += B) {
            const std::size_t count = std::min(B, m.size() - start);
            for (std::size_t i = 0; i < B; ++i) rb[i] = r[m[start + (i < count ? i : 0)]];
            if constexpr (Pr == Precision::accurate) {
                fill(aa, rb);
                accurate_piece_block(qp.inner[p], aa, in);
            } else {
                for (std::size_t i = 0; i < B; ++i) {
                    a.q[i] = rb[i] * s.inverse();
                    a.e[i] = edge_distance(s.h() - rb[i], s);
                    a.r[i] = rb[i];
                }
                fast_piece_block(qp.inner[p], a, in);
            }
            if (green_by_block) outside_block(qp, rb, green);
            for (std::size_t i = 0; i < count; ++i) {
                double v = Pr == Precision::accurate ? in[i] : in[i] * scale;
                if (q == QuantityId::potential && dim == 2) v = mul_add(qp.log_coefficient, s.log_h(), v);
                const double ri = rb[i];
                out[m[start + i]] = qp.zero_outside ? select(ri <= s.h(), v, 0.0)
                                    : green_by_block ? select(ri <= s.h(), v, green[i])
                                    : ri <= s.h()    ? v
                                                     : outside(qp, ri);
            }
        }
    }
}

// Are the inner pieces worth sorting the points into (Precision::accurate)?
// Evaluating every piece costs all their terms, by piece one piece's terms
// and the sort: kernel_bench measured the sort a loss for the cubic spline
// (two pieces of one term each, 2.5x the static form) and a gain for
// combinations (pieces of 1 to m terms). Counted as work, a term's
// coefficients and edge power, twice where it has no fused loop (the
// general double-double loops): the sort pays where the pieces not taken
// hold at least 6 of it (stop 39, 133 quantities of the classic, Wendland
// and mollifier kernels in D = 1..3 that this adds, mostly potentials and
// phi'/r with their 4- to 25-term series and Taylor pieces: 0.31-1.04 of
// the time, median 0.6; the losses, up to 1.44x, all below 6: 4096 radii in
// [0, 2h), each quantity both ways interleaved in one process).
bool by_piece(const QuantityPlan& qp) {
    std::size_t terms = 0;
    int all = 0, most = 0;  // the pieces' work, all of them and the largest
    for (const PiecePlan& p : qp.inner) {
        terms += p.terms.size();
        int work = 0;
        for (const TermPlan& t : p.terms) work += (t.n + t.edge_power) * (fused_accurate(t) ? 1 : 2);
        all += work;
        most = std::max(most, work);
    }
    return qp.inner.size() > 1 && (terms >= 2 * qp.inner.size() || all - most >= 6);
}

// Is the quantity one fused term inside the support and 0 outside (then
// evaluated in one pass from r)?
bool whole(const QuantityPlan& qp, QuantityId q, int dim) {
    return fused_loops && qp.whole >= 0 && !(q == QuantityId::potential && dim == 2);
}

// Does radial_batch sort the points into their pieces (radial_by_piece)?
// Precision::fast where the pieces are chosen by branches (sqrt, log): the
// blocks then run one piece's terms. Precision::accurate where the pieces
// are polynomial, not one fused term, and worth it (by_piece): each point
// through its own piece only, where the static form evaluates every piece
// and selects (a combination of m radii: m pieces of up to m terms);
// sorting costs less than a piece's double-double terms.
bool sorted_by_piece(const QuantityPlan& qp, QuantityId q, int dim, Precision pr) {
    if (pr == Precision::fast) return !qp.polynomial_inside;
    return qp.polynomial_inside && !whole(qp, q, dim) && !shared_one_pass(qp, q, dim, pr) && !pieces_one_pass(qp) &&
           by_piece(qp);
}

// Up to this many points (a batch, or a batch's last partial block) go
// through the scalar path, the same operations and so the same bits, not
// through a block of B mostly padded points: a caller with one point per
// smoothing length (tests/accuracy_test's log-uniform h) paid a whole
// block per point.
constexpr std::size_t few_points = 8;

// The one-pass loops take any n, one point included (a checked scalar call,
// k(q, r, h)): the scalar path interprets the plan's terms, ~5x their time.
template <Precision Pr>
bool radial_batch(const QuantityPlan& qp, QuantityId q, const double* r, double* out, std::size_t n, const Smoothing& s,
                  int dim) {
    if (qp.polynomial_inside && whole(qp, q, dim)) {
        const TermPlan& t = qp.inner.front().terms.front();
        const auto shape = static_cast<std::size_t>(qp.whole);
        if constexpr (Pr == Precision::accurate)
            return !accurate_whole_of[shape](t, r, out, n, s, accurate_scale(qp, q, s));
        else
            return !fast_whole_of[shape](t, r, out, n, s, s.scale(q));
    }
    if (pieces_one_pass(qp))
        return !pieces_of<Pr>[static_cast<std::size_t>(qp.pieces_fused)](qp, r, out, n, s, s.scale(q), s.scale_lo(q));
    if (qp.polynomial_inside && shared_one_pass(qp, q, dim, Pr)) {
        const auto shapes = static_cast<std::size_t>(qp.shared_fused);
        if constexpr (Pr == Precision::accurate)
            return !accurate_shared_of[shapes](qp, r, out, n, s, {s.scale(q), s.scale_lo(q)});
        else
            return !shared_whole_of[shapes](qp, r, out, n, s, s.scale(q));
    }
    if (n <= few_points) {
        for (std::size_t i = 0; i < n; ++i) out[i] = radial<Pr>(qp, q, r[i], s, dim);
        return false;
    }
    if (sorted_by_piece(qp, q, dim, Pr)) {
        radial_by_piece<Pr>(qp, q, r, out, n, s, dim);
        return false;
    }
    if (!qp.polynomial_inside) {
        for (std::size_t i = 0; i < n; ++i) out[i] = radial<Pr>(qp, q, r[i], s, dim);
        return false;
    }
    std::size_t i = 0;
    for (; i + B <= n; i += B) radial_block<Pr>(qp, q, r + i, out + i, s, dim);
    if (n - i <= few_points) {
        for (; i < n; ++i) out[i] = radial<Pr>(qp, q, r[i], s, dim);
    } else {
        double rb[B] = {}, ob[B];
        for (std::size_t j = i; j < n; ++j) rb[j - i] = r[j];
        radial_block<Pr>(qp, q, rb, ob, s, dim);
        for (std::size_t j = i; j < n; ++j) out[j] = ob[j - i];
    }
    return false;
}

// A quantity singular at 0 below r/h = 2^-150: its leading order there
// (detail/near_origin.hpp), as StaticKernel's mend_near_origin, at the
// radii a branch-free pass over the batch flagged (its callers fold the
// flag into a pass they make anyway where they can). The leading order once,
// at the first such radius (the plan is shared by every instruction set's
// copy of this file, so it holds the table's piece, not this copy's type).
void mend_near_origin(const QuantityPlan& qp, QuantityId q, const double* r, double* out, std::size_t n,
                      const Smoothing& s, int dim) {
    std::optional<origin::Leading> f;
    for (std::size_t i = 0; i < n; ++i) {
        if (!near_origin(r[i], s.h())) continue;
        if (!f) f = origin::leading(*qp.first);
        const double in = near_origin_value(*f, r[i], s.h(), s.scale(q), s.scale_lo(q), qp.spec,
                                            quantity_names[static_cast<int>(q)]);
        out[i] = q == QuantityId::potential && dim == 2 ? mul_add(qp.log_coefficient, s.log_h(), in) : in;
    }
}

// Returns whether the radii were all tested as they were read and found
// valid (radial_batch's one-pass loops); else the caller checks them.
template <Precision Pr>
bool evaluate_batch(const Plan& plan, QuantityId q, const double* __restrict r, double* __restrict out, std::size_t n,
                    const Smoothing& smoothing) {
    const Smoothing s = smoothing;
    const QuantityPlan& qp = plan.quantities[static_cast<std::size_t>(q)];
    const int dim = plan.table->dim;
    const bool tested = radial_batch<Pr>(qp, q, r, out, n, s, dim);
    if (qp.singular_at_origin) {
        const double h = s.h();
        std::uint64_t near = 0;
        for (std::size_t i = 0; i < n; ++i) {
            out[i] = limit_where_nan(qp, out[i]);
            near |= near_origin(r[i], h);
        }
        if (near) mend_near_origin(qp, q, r, out, n, s, dim);
    }
    return tested;
}

// Points per checked chunk (Evaluator::evaluate): few enough that a chunk
// is still in L1 when it is checked after its evaluation; more where the
// points are sorted into their pieces (radial_by_piece pads each piece's
// last block of every chunk).
std::size_t radii_chunk(const QuantityPlan& qp, QuantityId q, int dim, Precision pr) {
    return sorted_by_piece(qp, q, dim, pr) ? 64 * B : 8 * B;
}

// Each chunk's radii checked as they are evaluated where radial_batch's
// one-pass loops take them (each r's bits tested, as StaticKernel's
// loops do), else just after the chunk is evaluated, from L1 (a NaN,
// infinite or negative r makes no more than NaNs or wrong numbers there:
// pieces are chosen by comparisons). Only where some r was refused is the
// chunk read again, to name it. A bad value leaves the outputs
// unspecified, as StaticKernel::evaluate does.
void evaluate(const Plan& plan, Precision pr, QuantityId q, const double* r, double* out, std::size_t n,
              const Smoothing& s) {
    const std::size_t chunk = radii_chunk(plan.quantities[static_cast<std::size_t>(q)], q, plan.table->dim, pr);
    for (std::size_t start = 0; start < n; start += chunk) {
        const std::size_t m = std::min(chunk, n - start);
        const bool tested = pr == Precision::accurate
                                ? evaluate_batch<Precision::accurate>(plan, q, r + start, out + start, m, s)
                                : evaluate_batch<Precision::fast>(plan, q, r + start, out + start, m, s);
        if (!tested) check_radii({r + start, m});
    }
}

// One radius (Kernel::operator(), a checked scalar call): radial_batch for
// n = 1, as evaluate took one point, so the same bits, without evaluate's
// chunk loop, its chunk size's piece tests and evaluate_batch's copy of the
// Smoothing around it, which were a third of a call (kernel_bench's W-scalar
// rows); r checked first, as the batch names it.
double at_radius(const Plan& plan, Precision pr, QuantityId q, double r, const Smoothing& s) {
    check_radius(r);
    const QuantityPlan& qp = plan.quantities[static_cast<std::size_t>(q)];
    const int dim = plan.table->dim;
    double out;
    if (pr == Precision::accurate)
        radial_batch<Precision::accurate>(qp, q, &r, &out, 1, s, dim);
    else
        radial_batch<Precision::fast>(qp, q, &r, &out, 1, s, dim);
    if (qp.singular_at_origin) mend_near_origin(qp, q, &r, &out, 1, s, dim);
    return limit_where_nan(qp, out);
}

// ---- W and grad W at displacements (StaticKernel::pairs_unchecked) ----

// |x| at m points from `start`, on raw restrict pointers so that the loop
// vectorises. In 1D |x_0| itself, as StaticKernel's 1D pair takes it (the
// square's root is |x_0| only where the square does not underflow).
void radii(const std::span<const double>* x, int dim, std::size_t start, std::size_t m, double* __restrict r) {
    const double* __restrict x0 = x[0].data() + start;
    if (dim == 1) {
        for (std::size_t i = 0; i < m; ++i) r[i] = std::abs(x0[i]);
        return;
    }
    const double* __restrict x1 = x[1].data() + start;
    if (dim == 3) {
        const double* __restrict x2 = x[2].data() + start;
        for (std::size_t i = 0; i < m; ++i) r[i] = radius(x0[i], x1[i], x2[i]);
    } else {
        for (std::size_t i = 0; i < m; ++i) r[i] = radius(x0[i], x1[i]);
    }
}

// A cusp's radii where their squares underflowed, again without
// (unscaled_radius), as StaticKernel's norm: its W'(r) x/r and a W singular
// at 0 need r itself there. A branch-free scan first. Not inlined: inlined
// after radii (restrict r) into pairs_batch, GCC 12 at -O3 with AVX2 kept
// radii's 0 in r (spiky's grad W 0 at |x| = 1e-170; right in the generic
// build and with this out of line).
[[gnu::noinline]] void mend_tiny_radii(const std::span<const double>* x, int dim, std::size_t start, std::size_t m, double* r) {
    if (dim == 1) return;
    std::uint64_t tiny = 0;
    for (std::size_t i = 0; i < m; ++i) tiny |= r[i] < radius_underflow;
    if (!tiny) return;
    for (std::size_t i = 0; i < m; ++i) {
        if (!(r[i] < radius_underflow)) continue;
        const std::size_t j = start + i;
        r[i] = dim == 2 ? unscaled_radius(x[0][j], x[1][j]) : unscaled_radius(x[0][j], x[1][j], x[2][j]);
    }
}

// out = g x componentwise.
void times(const double* __restrict g, const double* __restrict x, double* __restrict out, std::size_t m) {
    for (std::size_t i = 0; i < m; ++i) out[i] = g[i] * x[i];
}

// Does pairs_batch take W and W'/r by radial_batch on whole batches, so
// that radial_by_piece fills its blocks (Precision::fast, pieces chosen by
// branches)?
bool pairs_by_piece(const Plan& plan, Precision pr) {
    return pr == Precision::fast && !(plan.quantities[static_cast<std::size_t>(QuantityId::value)].polynomial_inside &&
                                      plan.quantities[static_cast<std::size_t>(QuantityId::grad_over_r)].polynomial_inside);
}

// Precision::accurate: do W and W'/r sort the points into the same pieces
// (a combination's), both 0 outside?
bool accurate_pairs_by_piece(const QuantityPlan& value, const QuantityPlan& over_r, int dim) {
    if (!sorted_by_piece(value, QuantityId::value, dim, Precision::accurate) ||
        !sorted_by_piece(over_r, QuantityId::grad_over_r, dim, Precision::accurate) || !value.zero_outside ||
        !over_r.zero_outside || value.inner.size() != over_r.inner.size())
        return false;
    for (std::size_t k = 0; k < value.inner.size(); ++k)
        if (value.inner[k].lo != over_r.inner[k].lo) return false;
    return true;
}

// W and grad W at the m displacements from `start` (radii r) for such a
// kernel: one sort, each block filled once for both quantities, the
// gradient written from the block; radial_by_piece's operations for each
// quantity, so its bits.
void accurate_pairs_block_by_piece(const QuantityPlan& value, const QuantityPlan& over_r, const std::span<const double>* x,
                                   int dim, std::size_t start, std::size_t m, const double* r, const Smoothing& s,
                                   double* w, const std::span<double>* grad) {
    thread_local std::vector<std::vector<std::size_t>> members;
    sort_into_pieces<Precision::accurate>(value, r, m, s, members);
    AccurateBlock a(s, value.unit_edge > 0 || over_r.unit_edge > 0);
    const DoubleDouble value_scale = accurate_scale(value, QuantityId::value, s),
                       over_r_scale = accurate_scale(over_r, QuantityId::grad_over_r, s);
    double wb[B], gb[B], rb[B];
    for (std::size_t p = 0; p < value.inner.size(); ++p) {
        const std::vector<std::size_t>& in = members[p];
        for (std::size_t first = 0; first < in.size(); first += B) {
            const std::size_t count = std::min(B, in.size() - first);
            for (std::size_t i = 0; i < B; ++i) rb[i] = r[in[first + (i < count ? i : 0)]];
            fill(a, rb);
            a.scale = value_scale;
            accurate_piece_block(value.inner[p], a, wb);
            a.scale = over_r_scale;
            accurate_piece_block(over_r.inner[p], a, gb);
            for (std::size_t i = 0; i < count; ++i) {
                const std::size_t j = start + in[first + i];
                const bool inside = rb[i] <= s.h();
                w[j] = select(inside, wb[i], 0.0);
                const double g = select(inside, gb[i], 0.0);
                for (int c = 0; c < dim; ++c) grad[c][j] = g * x[c][j];
            }
        }
    }
}

// A 3D pair loop loop(x0, x1, x2, w, g0, g1, g2, m) run on D = 2 or 3
// displacements: 2D with x2 = 0 (fma(0, 0, y) = y, the same r, and half
// the instantiations), its gradient component dropped. Whether some r was
// not finite (the loops' flag: a coordinate to check, or a huge finite
// displacement whose r overflowed).
template <class Loop>
bool in_3d(const std::span<const double>* x, int dim, double* w, const std::span<double>* grad, std::size_t n,
           const Loop& loop) {
    if (dim == 3) return loop(x[0].data(), x[1].data(), x[2].data(), w, grad[0].data(), grad[1].data(), grad[2].data(), n);
    constexpr std::size_t chunk = 8 * B;
    static constexpr double no_x2[chunk] = {};
    double dropped[chunk];
    bool suspect = false;
    for (std::size_t start = 0; start < n; start += chunk)
        suspect |= loop(x[0].data() + start, x[1].data() + start, no_x2, w + start, grad[0].data() + start,
                        grad[1].data() + start, dropped, std::min(chunk, n - start));
    return suspect;
}

// Returns whether the displacements were all tested as they were read and
// found finite: a NaN or infinite coordinate makes r = sqrt(sum of
// squares) (|x_0| in 1D) NaN or infinite, as in StaticKernel's pair loop,
// and the one-pass loops test each r they compute or read (radial_batch's
// as radii); the other paths (the fast blocks, the accurate sort into
// pieces) leave the check to the caller.
template <Precision Pr>
bool pairs_batch(const Plan& plan, const std::span<const double>* x, const Smoothing& smoothing, double* __restrict w,
                 const std::span<double>* grad, std::size_t n) {
    const Smoothing s = smoothing;
    const int dim = plan.table->dim;
    const QuantityPlan& value = plan.quantities[static_cast<std::size_t>(QuantityId::value)];
    const QuantityPlan& over_r = plan.quantities[static_cast<std::size_t>(QuantityId::grad_over_r)];
    const QuantityPlan& dr = plan.quantities[static_cast<std::size_t>(QuantityId::dr)];
    const bool cusp = over_r.singular_at_origin;
    // Every kernel in blocks, 1D too (r = |x_0|): point by point (radial
    // per pair) the run-time form's 1D pairs and every odd or cusped
    // kernel's took 31-76 ns each, 25-50x the blocks' (2026-11-28, Intel
    // host), and the report's Franz studies, all 1D, were 7/8 of its time.
    // Odd and cusped kernels take the chunks at the end (their gradient is
    // not (W'/r) x); the others the one-pass loops where they fit.
    const bool plain = !plan.odd && !cusp;
    if (plain && fused_loops && plan.whole_pair >= 0) {
        // W and W'/r in one pass (whole_pairs_fixed), as the static form.
        const WholePairs loop = whole_pairs_of<Pr>[static_cast<std::size_t>(plan.whole_pair)];
        const TermPlan& v = value.inner.front().terms.front();
        const TermPlan& g = over_r.inner.front().terms.front();
        const DoubleDouble v_scale = accurate_scale(value, QuantityId::value, s),
                           g_scale = accurate_scale(over_r, QuantityId::grad_over_r, s);
        return !in_3d(x, dim, w, grad, n, [&](const double* x0, const double* x1, const double* x2, double* wc, double* g0,
                                              double* g1, double* g2, std::size_t m) {
            return loop(v, g, x0, x1, x2, wc, g0, g1, g2, m, s, v_scale, g_scale);
        });
    }
    if (plain && fused_loops && plan.pieces_pair >= 0) {
        // W and W'/r of pieces in one pass (pieces_pairs_fixed), as the static form.
        const PiecesPairs loop = pieces_pairs_of<Pr>[static_cast<std::size_t>(plan.pieces_pair)];
        return !in_3d(x, dim, w, grad, n, [&](const double* x0, const double* x1, const double* x2, double* wc, double* g0,
                                              double* g1, double* g2, std::size_t m) {
            return loop(value, over_r, x0, x1, x2, wc, g0, g1, g2, m, s);
        });
    }
    if (plain && plan.shared_pair >= 0 && shared_one_pass(value, QuantityId::value, dim, Pr) &&
        shared_one_pass(over_r, QuantityId::grad_over_r, dim, Pr)) {
        // A combination's W and W'/r in one pass (shared_pairs_fixed).
        const SharedPairs loop = shared_pairs_of<Pr>[static_cast<std::size_t>(plan.shared_pair)];
        return !in_3d(x, dim, w, grad, n, [&](const double* x0, const double* x1, const double* x2, double* wc, double* g0,
                                              double* g1, double* g2, std::size_t m) {
            return loop(value, over_r, x0, x1, x2, wc, g0, g1, g2, m, s);
        });
    }
    if (plain && pairs_by_piece(plan, Pr)) {
        thread_local std::vector<double> lengths, over;
        lengths.resize(n);
        over.resize(n);
        radii(x, dim, 0, n, lengths.data());
        const bool value_tested = radial_batch<Pr>(value, QuantityId::value, lengths.data(), w, n, s, dim);
        const bool over_r_tested = radial_batch<Pr>(over_r, QuantityId::grad_over_r, lengths.data(), over.data(), n, s, dim);
        for (int c = 0; c < dim; ++c)
            for (std::size_t i = 0; i < n; ++i) grad[c][i] = over[i] * x[c][i];
        return value_tested || over_r_tested;  // the same radii: either test covers them
    }
    // (Both quantities one pass from r each, whole or a combination's shared
    // terms: the chunks below.)
    const bool from_r = (whole(value, QuantityId::value, dim) || shared_one_pass(value, QuantityId::value, dim, Pr)) &&
                        (whole(over_r, QuantityId::grad_over_r, dim) ||
                         shared_one_pass(over_r, QuantityId::grad_over_r, dim, Pr));
    if (plain && Pr == Precision::fast && value.zero_outside && over_r.zero_outside && !from_r) {
        // Both quantities from one block of q and e (radial_block's first
        // pass done once), the last block padded with r = 0.
        FastBlock a;
        a.h = s.h(), a.inv_h = s.inverse();
        const double value_scale = s.scale(QuantityId::value), over_r_scale = s.scale(QuantityId::grad_over_r);
        double wb[B], g[B], pad[3][B];
        for (std::size_t start = 0; start < n; start += B) {
            const std::size_t m = std::min(B, n - start);
            const double* c[3] = {nullptr, nullptr, nullptr};
            for (int d = 0; d < dim; ++d) c[d] = x[d].data() + start;
            if (m < B)  // the last block padded with x = 0
                for (int d = 0; d < dim; ++d) {
                    for (std::size_t i = 0; i < B; ++i) pad[d][i] = i < m ? c[d][i] : 0.0;
                    c[d] = pad[d];
                }
            const double* __restrict x0 = c[0];
            const double* __restrict x1 = c[1];
            if (dim == 1) {
                for (std::size_t i = 0; i < B; ++i) a.r[i] = std::abs(x0[i]);
            } else if (dim == 3) {
                const double* __restrict x2 = c[2];
                for (std::size_t i = 0; i < B; ++i) a.r[i] = radius(x0[i], x1[i], x2[i]);
            } else {
                for (std::size_t i = 0; i < B; ++i) a.r[i] = radius(x0[i], x1[i]);
            }
            for (std::size_t i = 0; i < B; ++i) {
                a.q[i] = a.r[i] * s.inverse();
                a.e[i] = edge_distance(s.h() - a.r[i], s);
            }
            // Straight into w where the block is whole (a copy compiles to rep movs).
            fast_zero_outside_block(value, a, value_scale, m == B ? w + start : wb);
            fast_zero_outside_block(over_r, a, over_r_scale, g);
            if (m < B)
                for (std::size_t i = 0; i < m; ++i) w[start + i] = wb[i];
            for (int d = 0; d < dim; ++d) {
                const double* __restrict xd = c[d];
                double* __restrict gd = grad[d].data() + start;
                for (std::size_t i = 0; i < m; ++i) gd[i] = g[i] * xd[i];
            }
        }
        return false;
    }
    // Chunks of 8 blocks: a quantity evaluated in one pass from r
    // (whole) then pays its dispatch once per 256 points, not per 32.
    constexpr std::size_t chunk = 8 * B;
    double r[chunk], g[chunk];
    // (An odd or cusped kernel, as StaticKernel's pair: W sign(x), x
    // oriented to |x| (W'(x) = f'(|x|)); grad W = W'(r) (x/r), 0 at r = 0.)
    const bool one_sort = plain && Pr == Precision::accurate && accurate_pairs_by_piece(value, over_r, dim);
    const QuantityPlan& slope = cusp ? dr : over_r;
    const QuantityId slope_id = cusp ? QuantityId::dr : QuantityId::grad_over_r;
    bool tested = !one_sort;  // every chunk's radii tested by one of its radial_batch loops
    for (std::size_t start = 0; start < n; start += chunk) {
        const std::size_t m = std::min(chunk, n - start);
        radii(x, dim, start, m, r);
        if (cusp) mend_tiny_radii(x, dim, start, m, r);
        if (one_sort) {
            accurate_pairs_block_by_piece(value, over_r, x, dim, start, m, r, s, w, grad);
            continue;
        }
        double* __restrict wc = w + start;
        const bool value_tested = radial_batch<Pr>(value, QuantityId::value, r, wc, m, s, dim);
        const bool slope_tested = radial_batch<Pr>(slope, slope_id, r, g, m, s, dim);
        tested = tested && (value_tested || slope_tested);
        if (cusp) {  // (a W singular at 0 has a cusp: plain kernels have neither)
            const double h = s.h();
            std::uint64_t near = 0;
            for (std::size_t i = 0; i < m; ++i) near |= near_origin(r[i], h);
            if (near) {
                if (value.singular_at_origin) mend_near_origin(value, QuantityId::value, r, wc, m, s, dim);
                if (slope.singular_at_origin) mend_near_origin(slope, slope_id, r, g, m, s, dim);
            }
        }
        if (plain) {
            for (int c = 0; c < dim; ++c) times(g, x[c].data() + start, grad[c].data() + start, m);
            continue;
        }
        if (plan.odd) {  // 1D only
            const double* __restrict x0 = x[0].data() + start;
            for (std::size_t i = 0; i < m; ++i) wc[i] = x0[i] < 0 ? -wc[i] : wc[i];
        }
        for (int c = 0; c < dim; ++c) {
            const double* __restrict xc = x[c].data() + start;
            double* __restrict gc = grad[c].data() + start;
            for (std::size_t i = 0; i < m; ++i) {
                const double oriented = plan.odd ? std::abs(xc[i]) : xc[i];
                gc[i] = cusp ? (r[i] > 0 ? g[i] * (oriented / r[i]) : 0.0) : g[i] * oriented;
            }
        }
    }
    return tested;
}

// Displacements per checked chunk (Evaluator::pairs): x still in L2 when
// it is checked; more where pairs_batch sorts the points into pieces.
std::size_t pairs_chunk(const Plan& plan, Precision pr) { return pairs_by_piece(plan, pr) ? 64 * B : 32 * B; }

// Each chunk's displacements checked as they are evaluated where the
// one-pass loops take them (each r's bits tested, pairs_batch), else after
// the chunk is evaluated (a NaN or infinity only makes NaNs there: pieces
// are chosen by comparisons), from cache: checked first, the check waited
// on memory the evaluation then found in cache, where the evaluation alone
// overlaps its reads with its arithmetic (20-28 % of a batch of 10^6
// points on AVX2, Zen 1); after, it still re-read each chunk from L2 (13 %
// of Wendland C4's fast batch of 10^6 on Zen 4). Where some r was not
// finite the chunk's coordinates are checked, to name the bad one (a huge
// finite x whose r overflows passes: W = grad W = 0). A bad value leaves
// the outputs unspecified, as StaticKernel::pairs does.
void pairs(const Plan& plan, Precision pr, const std::span<const double>* x, const Smoothing& s, double* w,
           const std::span<double>* grad, std::size_t n) {
    const int dim = plan.table->dim;
    const std::size_t chunk = pairs_chunk(plan, pr);
    for (std::size_t start = 0; start < n; start += chunk) {
        const std::size_t m = std::min(chunk, n - start);
        std::span<const double> xc[3];
        std::span<double> gc[3];
        for (int c = 0; c < dim; ++c) xc[c] = x[c].subspan(start, m), gc[c] = grad[c].subspan(start, m);
        const bool tested = pr == Precision::accurate ? pairs_batch<Precision::accurate>(plan, xc, s, w + start, gc, m)
                                                      : pairs_batch<Precision::fast>(plan, xc, s, w + start, gc, m);
        if (!tested)
            for (int c = 0; c < dim; ++c) check_coordinates(xc[c], c);
    }
}

}  // namespace

#define MOLLIFY_STRINGIFY2(x) #x
#define MOLLIFY_STRINGIFY(x) MOLLIFY_STRINGIFY2(x)
extern const Evaluator isa_evaluator;
const Evaluator isa_evaluator{MOLLIFY_STRINGIFY(MOLLIFY_ISA), &evaluate, &pairs, &at_radius};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail
