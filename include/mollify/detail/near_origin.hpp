// f_h(r) = h^p f(r/h) of a quantity singular at r = 0 (viscosity's W,
// spiky's and Wendland k = 0's W'/r, W'' terms, the missing Wendland
// functions' log r) where r/h is below near_origin_bound. There the emitted
// form, f(q) first and h^p after, overflows or loses q: q^-3 passes DBL_MAX
// below q ~ 2^-341 and q is subnormal below 2^-1022, while h^p f(q) is
// finite for a large h (viscosity's W'/r at r/h = 1e-106, h = 1e8: 1e299).
// Below the bound the quantity is its leading order at 0,
//   f(q) = q^L (A + B log q) (1 + O(q)),
// A, B summed from the first piece's terms of the lowest order L (the terms
// beyond it are below 2^-150 of it), and q^L h^p taken apart into powers of
// two and a double-double, q = m 2^E with m near 1 from r and h themselves:
// one rounding at the end (<= 0.5 ulp plus ~2^-60 relative). Every product
// here is an explicit fma or an exact two-product, so the bits are the same
// in every unit whatever it contracts (the compile-time form in a user's
// unit, the run-time form per instruction set). A cold path: the forms call
// it only where near_origin(r, h) holds.
#pragma once

#include <mollify/constants/log_two.hpp>
#include <mollify/detail/double_double.hpp>
#include <mollify/detail/evaluate.hpp>
#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/table.hpp>

#include <cmath>
#include <string>

namespace mollify::detail {
inline namespace MOLLIFY_ISA {

// r > 0 with r/h below the bound (r = 0 is the quantity's limit there):
// r < 2^-150 h, without q's rounding (exact where 2^-150 h is normal), one
// expression in every form, so they choose alike.
MOLLIFY_INLINE bool near_origin(double r, double h) { return (r > 0) & (r < near_origin_bound * h); }

namespace origin {

// Double-doubles (detail/double_double.hpp), their products by explicit
// fmas here (DoubleDouble's use mul_add, unfused without FMA) and every
// result normalised.
using Dd = DoubleDouble;

inline Dd normalised(const Dd& x) { return fast_two_sum(x.hi, x.lo); }

inline Dd times(const Dd& a, const Dd& b) {
    const double p = a.hi * b.hi;
    return normalised({p, std::fma(a.hi, b.lo, std::fma(a.lo, b.hi, std::fma(a.hi, b.hi, -p)))});
}

inline Dd sum(const Dd& a, const Dd& b) { return normalised(a + b); }

inline Dd inverse(const Dd& x) {
    const double y = 1 / x.hi;
    const double residual = std::fma(-y, x.hi, 1.0);  // exact
    return normalised({y, std::fma(-y, x.lo, residual) / x.hi});
}

// x^n for any integer n (n < 0 through the inverse).
inline Dd power(Dd x, int n) {
    if (n < 0) x = inverse(x), n = -n;
    Dd y{1.0, 0.0};
    for (; n > 0; n >>= 1, x = times(x, x))
        if (n & 1) y = times(y, x);
    return y;
}

// The leading order of a piece at q -> 0: q^low (plain + logarithm log q);
// size, the sum of its terms' |coefficients| (A and B cancelling against
// it leave the order unknown); found: some term has a leading order.
struct Leading {
    int low = 0;
    Dd plain{0.0, 0.0}, logarithm{0.0, 0.0};
    double size = 0;
    bool found = false;
};

// A term's leading coefficient and order: its polynomial at v = 0 (its
// first nonzero coefficient, of q^k or q^2k), at v = -centre for a Taylor
// piece; its edge factor (edge - 0)^p or (edge^2 - 0)^p; S(0) = 1;
// arcsin q ~ q.
struct TermOrder {
    int order;
    Dd c;
};

inline TermOrder term_order(const table::Term& t) {
    auto coefficient = [&t](int k) { return Dd{t.c[k], t.c_lo ? t.c_lo[k] : 0.0}; };
    TermOrder o{t.low, {0.0, 0.0}};
    if (t.var == table::Var::shifted) {
        const Dd v{-t.centre, -t.centre_lo};
        for (int k = t.n; k-- > 0;) o.c = sum(times(o.c, v), coefficient(k));
    } else {
        int k = 0;
        while (k + 1 < t.n && t.c[k] == 0 && (t.c_lo == nullptr || t.c_lo[k] == 0)) ++k;
        o.c = coefficient(k);
        o.order += t.var == table::Var::r2 ? 2 * k : k;
    }
    if (t.edge_power != 0) o.c = times(o.c, power({t.edge, t.edge_lo}, t.var == table::Var::r2 ? 2 * t.edge_power : t.edge_power));
    if (t.basis == table::Basis::arcsin) ++o.order;
    return o;
}

inline Leading leading(const table::Piece& first) {
    Leading out;
    for (int t = 0; t < first.nterms; ++t) {
        const TermOrder o = term_order(first.terms[t]);
        if (o.c.hi == 0) continue;
        if (!out.found || o.order < out.low) out = Leading{o.order, {0.0, 0.0}, {0.0, 0.0}, 0.0, true};
        if (o.order > out.low) continue;
        out.size += std::abs(o.c.hi);
        switch (first.terms[t].basis) {
            case table::Basis::log: out.logarithm = sum(out.logarithm, o.c); break;
            case table::Basis::arcsech:  // log((1 + S)/q) = log 2 - log q + O(q^2)
                out.logarithm = sum(out.logarithm, {-o.c.hi, -o.c.lo});
                out.plain = sum(out.plain, times(o.c, {constants::log_two_hi, constants::log_two_lo}));
                break;
            default: out.plain = sum(out.plain, o.c); break;
        }
    }
    return out;
}

}  // namespace origin

// h^p f(r/h) r^k for 0 < r/h < near_origin_bound, from the leading order
// f of the quantity's first piece (origin::leading: once per batch, or per
// plan) and h^p = scale + scale_lo (Smoothing); k > 0 for a product that is
// finite where the quantity alone is not (the Hessian's (f'' - f'/r)/r^2
// times r^2). spec and quantity name it where its lowest terms cancel
// (then its order at 0 is not in the table).
MOLLIFY_NOINLINE double near_origin_value(const origin::Leading& f, double r, double h, double scale, double scale_lo,
                                          const char* spec, const char* quantity, int times_r_power = 0) {
    int er = 0, eh = 0;
    const double mr = std::frexp(r, &er), mh = std::frexp(h, &eh);  // in [1/2, 1)
    const double y = mr / mh;
    origin::Dd m{y, std::fma(-y, mh, mr) / mh};  // mr/mh to ~2^-104
    int e = er - eh;                      // q = m 2^e
    if (y < 0.75) m = {2 * m.hi, 2 * m.lo}, --e;  // m in [3/4, 3/2): |log m| < 0.41
    else if (y >= 1.5) m = {m.hi / 2, m.lo / 2}, ++e;
    origin::Dd a = f.plain;
    if (f.logarithm.hi != 0) {
        // log q = log m + e log 2; log m within an ulp of 0.41 is 2^-62 of
        // |log q| >= 103 here.
        const origin::Dd log_m = two_sum(std::log(m.hi), m.lo / m.hi);
        const double de = e;
        const double p = de * constants::log_two_hi;
        const origin::Dd log_q = origin::sum({p, std::fma(de, constants::log_two_lo, std::fma(de, constants::log_two_hi, -p))}, log_m);
        a = origin::sum(a, origin::times(f.logarithm, log_q));
    }
    if (!f.found || !(std::abs(a.hi) > 0x1p-40 * f.size))
        fail("kernel " + std::string(spec) + ": " + quantity + " at r/h below 2^-150 (r = " + show(r) + ", h = " + show(h) + "): its lowest-order terms at 0 cancel, so its value there is not in the table");
    // r^k = (q h)^k: q^(L + k) and the mantissa of h^k here, their powers of two below.
    const int k = times_r_power;
    const origin::Dd v = origin::times(origin::times(origin::times({scale, scale_lo}, a), origin::power(m, f.low + k)),
                                       origin::power({mh, 0.0}, k));
    return std::ldexp(v.hi + v.lo, e * (f.low + k) + eh * k);
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail
