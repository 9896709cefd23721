// The exact reference f_h(r) of every runtime quantity, from the
// generator's closed forms, in MPFR with >= 200 correct bits (Ziv).
//
// Speed matters (the accuracy test asks for ~25 million values), so the
// closed forms are compiled once into arrays of MPFR coefficients per
// working precision, and a point is evaluated with raw mpfr_t and
// per-thread temporaries; what depends on the point alone (q, 1 - q, S,
// the logarithms and arctangents of the bases, powers of q, S and h) is
// kept until the next point, so the quantities of one kernel at one point
// share it. Each term c * r^low * P(r) * basis(r) of a piece
// keeps two exact forms of P: in powers of q = r/h, and in powers of the
// distance to the piece's upper breakpoint, e = hi - q (exact Taylor
// coefficients). Near the support edge the first cancels like (1 - q)^n
// (1e-200 relative for Wendland k = 4 at 1 - q = 1e-15), the second not at
// all; near 0 it is the other way round. Each point uses the form whose
// sum of |terms| is smaller, which is the one with the smaller error bound.
//
// Error bound (Ziv): every term is a product of O(degree) correctly rounded
// MPFR operations on q, e and the exact coefficients (an integer power x^n,
// formed by products from x or 1/x, counts as |n| of them), and q, e,
// S = sqrt(e (1 + q)), arcsech q = log1p((e + S)/q), log q = log1p(-e), arcsin q =
// atan2(q, S) all have relative condition numbers O(1) in q and e, so the
// error of the sum is below 2^(margin - P) * sum |terms|, with margin = 20
// bits covering degrees up to ~1000 (Higham, Accuracy and Stability, 5.1:
// Horner's error is gamma_2n sum |c_k| |x|^k). The precision is raised until
// that bound is below 2^-201 |value|.
#include "verify/reference.hpp"

#include "closed_form.hpp"
#include "kernel.hpp"
#include "quantities.hpp"

#include <mollify/error.hpp>

#include <mpfr.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <optional>

namespace mollify::accuracy {

namespace gen = mollify::gen;

namespace {

// Working precisions: 64 bits, for the 24-bit scales (max_abs, slope), then
// 256 * 2^i bits, where the >= 200-bit values start. Beyond the last, a
// value still below its error bound is 0 within 2^(margin - 32768) * sum |terms|.
constexpr int level_count = 9;
constexpr double margin_bits = 20;
constexpr double wanted_bits = 201;  // 200 correct bits after rounding to the output
constexpr long output_bits = 320;

long level_bits(int level) { return level == 0 ? 64 : 256L << (level - 1); }

// An array of MPFR numbers of one precision (raw mpfr_t: Boost's value
// type allocates on every temporary).
class MpArray {
public:
    MpArray(std::size_t n, long bits) : x_(n) {
        for (auto& v : x_) mpfr_init2(&v, bits);
    }
    ~MpArray() {
        for (auto& v : x_) mpfr_clear(&v);
    }
    MpArray(const MpArray&) = delete;
    MpArray& operator=(const MpArray&) = delete;
    mpfr_ptr operator[](std::size_t i) { return &x_[i]; }
    mpfr_srcptr operator[](std::size_t i) const { return &x_[i]; }
    std::size_t size() const { return x_.size(); }

private:
    std::vector<__mpfr_struct> x_;
};

double log2_abs(mpfr_srcptr x) {
    if (mpfr_zero_p(x)) return -std::numeric_limits<double>::infinity();
    if (mpfr_inf_p(x)) return std::numeric_limits<double>::infinity();
    long e = 0;
    const double m = mpfr_get_d_2exp(&e, x, MPFR_RNDN);
    return static_cast<double>(e) + std::log2(std::abs(m));
}

// log2(2^a + 2^b) without overflow.
double log2_sum(double a, double b) {
    if (a < b) std::swap(a, b);
    if (b == -std::numeric_limits<double>::infinity()) return a;
    return a + std::log2(1 + std::exp2(b - a));
}

// Exact constant pi^e log(p) at `bits` (+ guard bits), into x.
void set_atom(mpfr_ptr x, const gen::Atom& a, long bits) {
    const gen::Exact c = gen::Exact::of(a);
    const gen::Real v = c.evaluate(static_cast<unsigned>(bits + 64)).first;
    mpfr_set(x, v.backend().data(), MPFR_RNDN);
}

// One form of P: exact coefficients in its variable, their magnitudes as
// doubles (form choice and error bound), and MPFR copies per precision.
struct Poly {
    std::vector<gen::Q> exact;
    std::vector<double> abs;
    std::array<std::unique_ptr<MpArray>, level_count> at;

    // sum |c_k| v^k in double (v >= 0): the magnitude of the form.
    double magnitude(double v) const {
        double m = 0;
        for (std::size_t k = abs.size(); k-- > 0;) m = m * v + abs[k];
        return m;
    }
};

struct Term {
    gen::Basis basis;
    int s_power;
    gen::Atom factor;
    int low;       // power of r in front of P
    Poly in_q;     // P in powers of q
    Poly in_edge;  // P in powers of e = hi - q (polynomial pieces only)
    bool has_edge_form;
};

struct Piece {
    gen::Q lo, hi;
    long hi_num = 0, hi_den = 1;
    std::vector<Term> terms;
};

struct Form {
    bool present = false;
    std::vector<Piece> pieces;
    Piece outside;            // in r itself: 0 or the Green's function
    int power = 0;            // f_h = h^power f(r/h)
    gen::Exact log_coefficient;  // 2D potential: c of c log r (c log h added inside)
    std::optional<gen::Exact> at_zero;  // limit at q = 0 where the form is singular termwise
    bool singular_at_zero = false;
    std::array<std::unique_ptr<MpArray>, level_count> log_coefficient_at;
    mutable std::once_flag max_once;
    mutable double max_abs = 0;  // Reference::max_abs
};

double to_double_abs(const gen::Q& c, const gen::Atom& a) {
    const gen::Real v = (gen::Exact(c) * gen::Exact::of(a)).evaluate(64).first;
    return std::abs(static_cast<double>(v));
}

Poly make_poly(std::vector<gen::Q> coefficients, const gen::Atom& factor) {
    Poly p;
    p.exact = std::move(coefficients);
    for (const gen::Q& c : p.exact) p.abs.push_back(to_double_abs(c, factor));
    return p;
}

Term make_term(const gen::TermKey& key, const gen::Laurent& p, const gen::Q& hi, bool edge_form) {
    Term t{key.basis, key.s_power, key.factor, p.low(), {}, {}, false};
    const gen::Laurent shifted = p.shifted(-p.low());  // P, a polynomial with P(0) != 0
    std::vector<gen::Q> in_q;
    for (int n = 0; n <= shifted.high(); ++n) in_q.push_back(shifted.coefficient(n));
    t.in_q = make_poly(in_q, key.factor);
    if (!edge_form) return t;
    t.in_edge = make_poly(shifted.taylor_at(hi), key.factor);
    t.has_edge_form = true;
    return t;
}

Piece make_piece(const gen::ClosedForm& f, const gen::Q& lo, const gen::Q& hi, bool edge_form = true) {
    Piece p;
    p.lo = lo;
    p.hi = hi;
    if (!mpz_fits_slong_p(numerator(hi).backend().data()) || !mpz_fits_slong_p(denominator(hi).backend().data()))
        fail("internal: breakpoint " + gen::short_string(hi) + " does not fit a machine integer");
    p.hi_num = mpz_get_si(numerator(hi).backend().data());
    p.hi_den = mpz_get_si(denominator(hi).backend().data());
    for (const auto& [key, poly] : f.terms()) p.terms.push_back(make_term(key, poly, hi, edge_form));
    return p;
}

bool termwise_singular_at_zero(const gen::ClosedForm& f) {
    for (const auto& [k, p] : f.terms())
        if (p.low() < 0 || k.basis == gen::Basis::log || k.basis == gen::Basis::arcsech) return true;
    return false;
}

gen::Exact green_log_coefficient(const gen::Radial& f) {
    for (const auto& [k, p] : f.outside.terms())
        if (k.basis == gen::Basis::log) return gen::Exact(p.coefficient(0)) * gen::Exact::of(k.factor);
    return gen::Exact();
}

// `slope`: the form of r d/dr f_h = h^p q f'(q) (no c log h: its r-derivative is 0).
void make_form(Form& form, const gen::Radial& f, QuantityId q, int dim, bool slope = false) {
    form.present = true;
    form.power = mollify::detail::scale_power(q, dim);
    for (std::size_t i = 0; i < f.pieces.size(); ++i)
        form.pieces.push_back(make_piece(f.pieces[i], f.breaks[i], f.breaks[i + 1]));
    form.outside = make_piece(f.outside, f.support(), f.support(), false);
    if (q == QuantityId::potential && dim == 2 && !slope) form.log_coefficient = green_log_coefficient(f);
    const gen::ClosedForm& first = f.pieces.front();
    if (termwise_singular_at_zero(first)) {
        try {
            form.at_zero = gen::limit_at_zero(first);
        } catch (const std::exception&) {
            form.singular_at_zero = true;  // e.g. spiky's W'/r = -3 (1 - r)^2 / r
        }
    }
}

void build_poly(Poly& p, const gen::Atom& factor, int level) {
    const long bits = level_bits(level);
    auto a = std::make_unique<MpArray>(p.exact.size(), bits);
    mpfr_t f, c;
    mpfr_init2(f, bits + 64);
    mpfr_init2(c, bits + 64);
    set_atom(f, factor, bits);
    for (std::size_t k = 0; k < p.exact.size(); ++k) {
        mpfr_set_q(c, p.exact[k].backend().data(), MPFR_RNDN);
        mpfr_mul(c, c, f, MPFR_RNDN);
        mpfr_set((*a)[k], c, MPFR_RNDN);
    }
    mpfr_clear(f);
    mpfr_clear(c);
    p.at[static_cast<std::size_t>(level)] = std::move(a);
}

void build_piece(Piece& p, int level) {
    for (Term& t : p.terms) {
        build_poly(t.in_q, t.factor, level);
        if (t.has_edge_form) build_poly(t.in_edge, t.factor, level);
    }
}

void build_form(Form& form, int level) {
    for (Piece& p : form.pieces) build_piece(p, level);
    build_piece(form.outside, level);
    auto c = std::make_unique<MpArray>(1, level_bits(level));
    const gen::Real v = form.log_coefficient.evaluate(static_cast<unsigned>(level_bits(level) + 64)).first;
    mpfr_set((*c)[0], v.backend().data(), MPFR_RNDN);
    form.log_coefficient_at[static_cast<std::size_t>(level)] = std::move(c);
}

// Per-thread temporaries of one precision, and what depends only on the
// point: q, e1 = 1 - q, S and the bases, powers of q, S and h. Every
// quantity of a kernel (and its slope) at one point shares them, so a
// caller that asks for all quantities at a point before moving on computes
// each logarithm, arctangent and square root once, not once per quantity.
class Scratch {
public:
    enum : std::size_t { q, e1, ehi, acc, term, s, tmp, tmp2, log_h_at, arcsech_at, log_at, arcsin_at, near_zero, zero, count };
    static constexpr long max_power = 40;  // cached powers x^n, |n| <= max_power

    explicit Scratch(long bits)
        : v(count, bits), key_(2, 64), q_powers_(2 * max_power + 1, bits), s_powers_(2 * max_power + 1, bits),
          h_powers_(2 * max_power + 1, bits) {
        mpfr_set_zero(v[zero], 1);
    }

    MpArray v;

    // Makes (r, h) the cached point: inside the support q = r/h and
    // e1 = 1 - r/h (from the exact h - r); outside q = r, e1 = 1 - r (the
    // exterior form is in r itself).
    void at(mpfr_srcptr r, mpfr_srcptr h, bool outside);

    mpfr_srcptr s_value();                    // S = sqrt((1 - q)(1 + q)) from e1
    mpfr_srcptr basis(gen::Basis b, int s_power);  // not Basis::one
    mpfr_srcptr q_power(long n) { return power(q_powers_, have_q_, v[q], n); }
    mpfr_srcptr h_power(long n) { return power(h_powers_, have_h_, key_[1], n); }
    mpfr_srcptr log_h();

private:
    using Have = std::array<bool, 2 * max_power + 1>;
    mpfr_srcptr power(MpArray& cache, Have& have, mpfr_srcptr x, long n);

    MpArray key_;  // r, h of the cached point
    bool valid_ = false, outside_ = false;
    bool have_s_ = false, have_log_h_ = false, have_arcsech_ = false, have_log_ = false, have_arcsin_ = false;
    Have have_q_{}, have_s_powers_{}, have_h_{};
    MpArray q_powers_, s_powers_, h_powers_;
};

Scratch& scratch(int level) {
    thread_local std::array<std::unique_ptr<Scratch>, level_count> s;
    auto& p = s[static_cast<std::size_t>(level)];
    if (!p) p = std::make_unique<Scratch>(level_bits(level));
    return *p;
}

void edge_distance(mpfr_ptr out, mpfr_srcptr r, mpfr_srcptr h, long num, long den);

void Scratch::at(mpfr_srcptr r, mpfr_srcptr h, bool outside) {
    if (valid_ && outside_ == outside && mpfr_equal_p(key_[0], r) && mpfr_equal_p(key_[1], h)) return;
    for (std::size_t i : {std::size_t{0}, std::size_t{1}}) {
        mpfr_srcptr x = i == 0 ? r : h;
        if (mpfr_get_prec(key_[i]) < mpfr_get_prec(x)) mpfr_set_prec(key_[i], mpfr_get_prec(x));
        mpfr_set(key_[i], x, MPFR_RNDN);  // exact
    }
    valid_ = true;
    outside_ = outside;
    have_s_ = have_log_h_ = have_arcsech_ = have_log_ = have_arcsin_ = false;
    have_q_.fill(false);
    have_s_powers_.fill(false);
    have_h_.fill(false);
    if (outside) {
        mpfr_set(v[q], r, MPFR_RNDN);
        mpfr_ui_sub(v[e1], 1, r, MPFR_RNDN);  // for log r near 1
    } else {
        mpfr_div(v[q], r, h, MPFR_RNDN);
        edge_distance(v[e1], r, h, 1, 1);
    }
}

mpfr_srcptr Scratch::s_value() {
    if (!have_s_) {
        // S = sqrt((1 - q)(1 + q)) from e1: accurate where q is within an ulp of 1.
        mpfr_add_ui(v[tmp2], v[q], 1, MPFR_RNDN);
        mpfr_mul(v[s], v[tmp2], v[e1], MPFR_RNDN);
        mpfr_sqrt(v[s], v[s], MPFR_RNDN);
        have_s_ = true;
    }
    return v[s];
}

// x^n, n != 0, from x^(n -+ 1): |n| roundings (n < 0: one division for
// 1/x, then products), which the margin covers as it covers Horner's; a
// point's powers of h for the quantities' scalings are then one product each.
mpfr_srcptr Scratch::power(MpArray& cache, Have& have, mpfr_srcptr x, long n) {
    if (n == 0 || n < -max_power || n > max_power)
        fail("internal: power " + std::to_string(n) + " outside the reference's cache");
    const auto i = static_cast<std::size_t>(n + max_power);
    if (!have[i]) {
        if (n == 1) mpfr_set(cache[i], x, MPFR_RNDN);
        else if (n == -1) mpfr_ui_div(cache[i], 1, x, MPFR_RNDN);
        else if (n > 1) mpfr_mul(cache[i], power(cache, have, x, n - 1), x, MPFR_RNDN);
        else mpfr_mul(cache[i], power(cache, have, x, n + 1), power(cache, have, x, -1), MPFR_RNDN);
        have[i] = true;
    }
    return cache[i];
}

mpfr_srcptr Scratch::log_h() {
    if (!have_log_h_) {
        mpfr_log(v[log_h_at], key_[1], MPFR_RNDN);
        have_log_h_ = true;
    }
    return v[log_h_at];
}

mpfr_srcptr Scratch::basis(gen::Basis b, int s_power) {
    switch (b) {
        case gen::Basis::one: break;
        case gen::Basis::sqrt_power: return power(s_powers_, have_s_powers_, s_value(), s_power);
        case gen::Basis::arcsech:  // log1p((e + S)/q)
            if (!have_arcsech_) {
                mpfr_add(v[arcsech_at], v[e1], s_value(), MPFR_RNDN);
                mpfr_div(v[arcsech_at], v[arcsech_at], v[q], MPFR_RNDN);
                mpfr_log1p(v[arcsech_at], v[arcsech_at], MPFR_RNDN);
                have_arcsech_ = true;
            }
            return v[arcsech_at];
        case gen::Basis::log:
            if (!have_log_) {
                if (mpfr_cmp_d(v[q], 0.5) < 0) {
                    mpfr_log(v[log_at], v[q], MPFR_RNDN);
                } else {
                    mpfr_neg(v[log_at], v[e1], MPFR_RNDN);
                    mpfr_log1p(v[log_at], v[log_at], MPFR_RNDN);
                }
                have_log_ = true;
            }
            return v[log_at];
        case gen::Basis::arcsin:
            if (!have_arcsin_) {
                mpfr_atan2(v[arcsin_at], v[q], s_value(), MPFR_RNDN);
                have_arcsin_ = true;
            }
            return v[arcsin_at];
    }
    fail("internal: the basis 1 has no value to cache");
}

// Two per-thread numbers wide enough for the exact products of r and h
// with machine integers (64 spare bits).
struct Products {
    mpfr_ptr a, b;
};

Products products(mpfr_srcptr r, mpfr_srcptr h) {
    thread_local MpArray p(2, 128);
    const long bits = std::max(mpfr_get_prec(r), mpfr_get_prec(h)) + 64;
    if (mpfr_get_prec(p[0]) < bits) {
        mpfr_set_prec(p[0], bits);
        mpfr_set_prec(p[1], bits);
    }
    return {p[0], p[1]};
}

// Exact comparison of r with (num/den) h: sign of den r - num h.
int compare_scaled(mpfr_srcptr r, mpfr_srcptr h, long num, long den) {
    const Products p = products(r, h);
    mpfr_mul_si(p.a, r, den, MPFR_RNDN);  // exact
    mpfr_mul_si(p.b, h, num, MPFR_RNDN);
    return mpfr_cmp(p.a, p.b);
}

// (num/den - r/h) to precision of out, from the exact num h - den r.
void edge_distance(mpfr_ptr out, mpfr_srcptr r, mpfr_srcptr h, long num, long den) {
    const Products p = products(r, h);
    mpfr_mul_si(p.a, h, num, MPFR_RNDN);
    mpfr_mul_si(p.b, r, den, MPFR_RNDN);
    mpfr_sub(out, p.a, p.b, MPFR_RNDN);  // the only rounding
    if (den == 1) {
        mpfr_div(out, out, h, MPFR_RNDN);
    } else {
        mpfr_mul_si(p.a, h, den, MPFR_RNDN);
        mpfr_div(out, out, p.a, MPFR_RNDN);
    }
}

// A value with the log2 of its error bound's scale (sum of |terms|).
struct Sum {
    double log2_magnitude = -std::numeric_limits<double>::infinity();
};

// Horner's rule in MPFR: out = sum c_k v^k.
void horner(mpfr_ptr out, const MpArray& c, mpfr_srcptr v) {
    mpfr_set(out, c[c.size() - 1], MPFR_RNDN);
    // mul + add: two roundings instead of mpfr_fma's one, but about twice
    // as fast (the bound's margin covers the extra rounding).
    for (std::size_t k = c.size() - 1; k-- > 0;) {
        mpfr_mul(out, out, v, MPFR_RNDN);
        mpfr_add(out, out, c[k], MPFR_RNDN);
    }
}

// acc += the piece at the point (q, e1, ehi in the scratch); returns log2 sum |terms|.
double add_piece(const Piece& p, int level, Scratch& w) {
    const auto L = static_cast<std::size_t>(level);
    const double qd = mpfr_get_d(w.v[Scratch::q], MPFR_RNDN), ed = mpfr_get_d(w.v[Scratch::ehi], MPFR_RNDN);
    const double log2_q = log2_abs(w.v[Scratch::q]);
    double total = -std::numeric_limits<double>::infinity();
    for (const Term& t : p.terms) {
        const double mq = t.in_q.magnitude(std::abs(qd));
        const double me = t.has_edge_form ? t.in_edge.magnitude(std::abs(ed)) : mq;
        const bool edge = t.has_edge_form && me < mq;
        horner(w.v[Scratch::term], *(edge ? t.in_edge : t.in_q).at[L], w.v[edge ? Scratch::ehi : Scratch::q]);
        double log2_m = std::log2(edge ? me : mq);
        if (t.low != 0) {
            mpfr_mul(w.v[Scratch::term], w.v[Scratch::term], w.q_power(t.low), MPFR_RNDN);
            log2_m += t.low * log2_q;
        }
        if (t.basis != gen::Basis::one) {
            mpfr_srcptr b = w.basis(t.basis, t.s_power);
            mpfr_mul(w.v[Scratch::term], w.v[Scratch::term], b, MPFR_RNDN);
            log2_m += log2_abs(b);
        }
        // The double magnitude can underflow where MPFR does not.
        log2_m = std::max(log2_m, log2_abs(w.v[Scratch::term]));
        mpfr_add(w.v[Scratch::acc], w.v[Scratch::acc], w.v[Scratch::term], MPFR_RNDN);
        total = log2_sum(total, log2_m);
    }
    return total;
}

std::size_t piece_index(const Form& f, mpfr_srcptr r, mpfr_srcptr h) {
    for (std::size_t i = 0; i + 1 < f.pieces.size(); ++i)
        if (compare_scaled(r, h, f.pieces[i].hi_num, f.pieces[i].hi_den) < 0) return i;
    return f.pieces.size() - 1;
}

// f(r/h) -> h^p f(r/h) (+ c log h for a 2D potential), as the runtime scales;
// returns log2 of the updated sum of |terms|.
// h is the cached point's (Scratch::at).
double scale_by_h(const Form& f, int level, Scratch& w, double log2_m) {
    if (f.power != 0) {
        mpfr_srcptr scale = w.h_power(f.power);
        mpfr_mul(w.v[Scratch::acc], w.v[Scratch::acc], scale, MPFR_RNDN);
        log2_m += log2_abs(scale);
    }
    if (!f.log_coefficient.is_zero()) {
        mpfr_mul(w.v[Scratch::tmp], w.log_h(), (*f.log_coefficient_at[static_cast<std::size_t>(level)])[0],
                 MPFR_RNDN);
        mpfr_add(w.v[Scratch::acc], w.v[Scratch::acc], w.v[Scratch::tmp], MPFR_RNDN);
        log2_m = log2_sum(log2_m, log2_abs(w.v[Scratch::tmp]));
    }
    return log2_m;
}

// One attempt at `level`: acc = f_h(r); returns log2 of the error bound.
double attempt_inside(const Form& f, mpfr_srcptr r, mpfr_srcptr h, int level, Scratch& w) {
    const Piece& p = f.pieces[piece_index(f, r, h)];
    w.at(r, h, false);
    if (p.hi_num == p.hi_den) mpfr_set(w.v[Scratch::ehi], w.v[Scratch::e1], MPFR_RNDN);
    else edge_distance(w.v[Scratch::ehi], r, h, p.hi_num, p.hi_den);
    mpfr_set_zero(w.v[Scratch::acc], 1);
    double log2_m = add_piece(p, level, w);
    log2_m = scale_by_h(f, level, w, log2_m);
    return log2_m + margin_bits - static_cast<double>(level_bits(level));
}

// Outside: the exterior form at r itself (no h: the Green's function is the
// same for every h, as in the runtime).
double attempt_outside(const Form& f, mpfr_srcptr r, mpfr_srcptr h, int level, Scratch& w) {
    w.at(r, h, true);
    mpfr_set(w.v[Scratch::ehi], w.v[Scratch::e1], MPFR_RNDN);
    mpfr_set_zero(w.v[Scratch::acc], 1);
    if (f.outside.terms.empty()) return -std::numeric_limits<double>::infinity();
    const double log2_m = add_piece(f.outside, level, w);
    return log2_m + margin_bits - static_cast<double>(level_bits(level));
}

// At q = 0 exactly, where the closed form is singular termwise: its limit.
double attempt_at_zero(const Form& f, mpfr_srcptr h, int level, Scratch& w) {
    const long bits = level_bits(level);
    if (f.singular_at_zero) {
        // The sign of the singularity: the form just right of 0.
        mpfr_set_ui_2exp(w.v[Scratch::near_zero], 1, -100000, MPFR_RNDN);
        mpfr_mul(w.v[Scratch::near_zero], w.v[Scratch::near_zero], h, MPFR_RNDN);
        attempt_inside(f, w.v[Scratch::near_zero], h, level, w);
        mpfr_set_inf(w.v[Scratch::acc], mpfr_sgn(w.v[Scratch::acc]));
        return -std::numeric_limits<double>::infinity();
    }
    const auto [v, m] = f.at_zero->evaluate(static_cast<unsigned>(bits));
    w.at(w.v[Scratch::zero], h, false);  // the point r = 0, whose h scales
    mpfr_set(w.v[Scratch::acc], v.backend().data(), MPFR_RNDN);
    double log2_m = log2_abs(m.backend().data());
    log2_m = scale_by_h(f, level, w, log2_m);
    return log2_m + margin_bits - static_cast<double>(bits);
}

// The level whose precision is at least `bits`, or -1.
int level_for(double bits) {
    for (int l = 0; l < level_count; ++l)
        if (static_cast<double>(level_bits(l)) >= bits) return l;
    return -1;
}

}  // namespace

namespace {

void check_arguments(mpfr_srcptr r, mpfr_srcptr h) {
    if (!mpfr_number_p(r) || mpfr_sgn(r) < 0) fail("reference: radius is not a finite number >= 0");
    if (!mpfr_number_p(h) || mpfr_sgn(h) <= 0) fail("reference: smoothing length is not a finite number > 0");
}

}  // namespace

struct Reference::Impl {
    int dim = 0;
    gen::ExactKernel kernel;
    std::array<Form, table::quantity_count> forms;
    std::array<Form, table::quantity_count> slopes;  // r d/dr of each
    std::array<std::once_flag, level_count> built;
    std::once_flag all_maxima_once;

    // The grid of Reference::max_abs for one form.
    static std::vector<double> max_grid(const Form& f) {
        std::vector<double> grid;
        constexpr int cells = 2048;
        for (int i = f.singular_at_zero ? 1 : 0; i <= cells; ++i) grid.push_back(static_cast<double>(i) / cells);
        for (const Piece& p : f.pieces)
            for (double x : {static_cast<double>(p.lo), static_cast<double>(p.hi)})
                for (double y : {std::nextafter(x, 0.0), x, std::nextafter(x, 2.0)})
                    if (y >= (f.singular_at_zero ? 1.0 / cells : 0.0) && y <= 1) grid.push_back(y);
        return grid;
    }

    // max_abs of the forms given, point by point over the union of their
    // grids, so that at each point they share its bases (Scratch).
    std::vector<double> find_maxima(const std::vector<const Form*>& fs) {
        std::map<double, std::vector<std::size_t>> sampled;  // point -> the forms sampled there
        for (std::size_t i = 0; i < fs.size(); ++i)
            for (double r : max_grid(*fs[i])) sampled[r].push_back(i);
        std::vector<double> out(fs.size(), 0.0);
        // 24 correct bits are plenty for a scale.
        mpfr_t rr, one, v;
        mpfr_inits2(64, rr, one, v, static_cast<mpfr_ptr>(nullptr));
        mpfr_set_ui(one, 1, MPFR_RNDN);
        for (const auto& [r, at] : sampled) {
            mpfr_set_d(rr, r, MPFR_RNDN);
            for (std::size_t i : at) {
                value(*fs[i], rr, one, v, 24);
                out[i] = std::max(out[i], std::abs(mpfr_get_d(v, MPFR_RNDN)));
            }
        }
        mpfr_clears(rr, one, v, static_cast<mpfr_ptr>(nullptr));
        return out;
    }

    void ensure(int level) {
        std::call_once(built[static_cast<std::size_t>(level)], [&] {
            for (auto* set : {&forms, &slopes})
                for (Form& f : *set)
                    if (f.present) build_form(f, level);
        });
    }

    double attempt(const Form& f, mpfr_srcptr r, mpfr_srcptr h, int level, Scratch& w) {
        if (compare_scaled(r, h, 1, 1) > 0) return attempt_outside(f, r, h, level, w);
        if (mpfr_zero_p(r) && (f.at_zero || f.singular_at_zero)) return attempt_at_zero(f, h, level, w);
        return attempt_inside(f, r, h, level, w);
    }

    // The form at double r and h (exact), `wanted` correct bits, in a number of `bits`.
    Real at(const Form& f, double r, double h, long bits, double wanted) {
        thread_local MpArray rh(2, 53);
        mpfr_set_d(rh[0], r, MPFR_RNDN);
        mpfr_set_d(rh[1], h, MPFR_RNDN);
        check_arguments(rh[0], rh[1]);
        Real out(0, static_cast<unsigned>(bits * 30103 / 100000 + 2));
        value(f, rh[0], rh[1], out.backend().data(), wanted);
        return out;
    }

    // Ziv's loop; out gets the value (0 when it stays below its bound at
    // the largest precision: |f| < 2^(margin - 32768) sum |terms|).
    void value(const Form& f, mpfr_srcptr r, mpfr_srcptr h, mpfr_ptr out, double wanted = wanted_bits) {
        // The first precision that can give `wanted` bits when no term cancels.
        int level = level_for(wanted + margin_bits + 8);
        if (level < 0) level = level_count - 1;
        for (;;) {
            ensure(level);
            Scratch& w = scratch(level);
            const double log2_err = attempt(f, r, h, level, w);
            const double log2_v = log2_abs(w.v[Scratch::acc]);
            if (log2_err == -std::numeric_limits<double>::infinity() || log2_v - log2_err >= wanted) {
                mpfr_set(out, w.v[Scratch::acc], MPFR_RNDN);
                return;
            }
            // Bits still missing; when the value is not even above its bound,
            // its size is unknown: double the precision.
            const double bits = static_cast<double>(level_bits(level));
            const double need = log2_v > log2_err + 1 ? bits + (wanted - (log2_v - log2_err)) + 16 : 2 * bits;
            const int next = level_for(need);
            if (next < 0 || level + 1 >= level_count) {
                if (log2_v > log2_err) mpfr_set(out, w.v[Scratch::acc], MPFR_RNDN);
                else mpfr_set_zero(out, 1);
                return;
            }
            level = std::max(next, level + 1);
        }
    }
};

Reference::Reference(const std::string& spec, int dim) : impl_(std::make_unique<Impl>()) {
    impl_->dim = dim;
    impl_->kernel = gen::make_kernel(parse_spec(spec), dim);
    const gen::Quantities qs = gen::derive_quantities(impl_->kernel);
    for (int i = 0; i < table::quantity_count; ++i) {
        const std::string& name = gen::quantity_names()[static_cast<std::size_t>(i)];
        if (!impl_->kernel.claims.no_potential.empty() && table::is_potential(static_cast<table::QuantityId>(i))) continue;
        const gen::Radial& f = gen::quantity(impl_->kernel, qs, name);
        make_form(impl_->forms[static_cast<std::size_t>(i)], f, static_cast<QuantityId>(i), dim);
        make_form(impl_->slopes[static_cast<std::size_t>(i)], f.derivative().times(gen::Laurent::monomial(gen::Q(1), 1)),
                  static_cast<QuantityId>(i), dim, true);
    }
}

Reference::~Reference() = default;
Reference::Reference(Reference&&) noexcept = default;

int Reference::dim() const { return impl_->dim; }

const gen::ExactKernel& Reference::kernel() const { return impl_->kernel; }

bool Reference::has(QuantityId q) const {
    const int i = static_cast<int>(q);
    return i >= 0 && i < table::quantity_count && impl_->forms[static_cast<std::size_t>(i)].present;
}

namespace {

void require(const Reference& ref, QuantityId q) {
    if (!ref.has(q))
        fail(std::string("the reference has no ") +
             (static_cast<int>(q) >= 0 && static_cast<int>(q) < table::quantity_count ? quantity_names[static_cast<int>(q)]
                                                                              : "such quantity"));
}


}  // namespace

Real Reference::value(QuantityId q, const Real& r, const Real& h) const {
    require(*this, q);
    check_arguments(r.backend().data(), h.backend().data());
    Real out(0, static_cast<unsigned>(output_bits * 30103 / 100000 + 2));
    impl_->value(impl_->forms[static_cast<std::size_t>(q)], r.backend().data(), h.backend().data(),
                 out.backend().data());
    return out;
}

Real Reference::value(QuantityId q, double r, double h) const {
    require(*this, q);
    return impl_->at(impl_->forms[static_cast<std::size_t>(q)], r, h, output_bits, wanted_bits);
}

Real Reference::slope(QuantityId q, double r, double h) const {
    require(*this, q);
    return impl_->at(impl_->slopes[static_cast<std::size_t>(q)], r, h, 64, 24);
}

// max |f| over [0, 1] (h = 1) on a grid of 2048 cells plus every breakpoint
// (and its neighbours): a scale, accurate to a few per cent. A quantity
// singular at 0 (spiky's W'/r) is sampled from q = 2^-11 on.
double Reference::max_abs(QuantityId q) const {
    require(*this, q);
    const Form& f = impl_->forms[static_cast<std::size_t>(q)];
    std::call_once(f.max_once, [&] { f.max_abs = impl_->find_maxima({&f}).front(); });
    return f.max_abs;
}

void Reference::find_all_maxima() const {
    std::call_once(impl_->all_maxima_once, [&] {
        std::vector<const Form*> fs;
        for (const Form& f : impl_->forms)
            if (f.present) fs.push_back(&f);
        const std::vector<double> m = impl_->find_maxima(fs);
        for (std::size_t i = 0; i < fs.size(); ++i) std::call_once(fs[i]->max_once, [&] { fs[i]->max_abs = m[i]; });
    });
}

// SLEEF's countULP (sleef/src/libm-tester/testerutil.c): ulp(x) = 2^(e-52)
// for 2^e <= |x| < 2^(e+1), never below 2^-1074 (the ulp of the smallest
// normal). Both infinite with one sign: 0; a NaN: +inf; an infinite result
// for a finite exact value counts as DBL_MAX plus one ulp, except where the
// exact value itself rounds to infinity (then inf is the correct result).
double ulp_error(double y, const Real& x) {
    mpfr_srcptr c = x.backend().data();
    if (std::isnan(y) || mpfr_nan_p(c)) return std::numeric_limits<double>::infinity();
    const double xd = mpfr_get_d(c, MPFR_RNDN);
    if (std::isinf(xd) && y == xd) return 0;
    if (std::isinf(xd)) return std::numeric_limits<double>::infinity();
    double extra = 0;
    if (std::isinf(y)) {
        y = std::copysign(std::numeric_limits<double>::max(), y);
        extra = 1;
    }
    if (mpfr_zero_p(c) && y == 0) return extra;
    mpfr_t d;
    mpfr_init2(d, std::max<long>(mpfr_get_prec(c), 64) + 1100);
    const long e = mpfr_zero_p(c) ? -100000 : mpfr_get_exp(c);  // 2^(e-1) <= |x| < 2^e
    mpfr_set_d(d, y, MPFR_RNDN);
    mpfr_sub(d, d, c, MPFR_RNDN);
    mpfr_mul_2si(d, d, -std::max(e - 53, -1074L), MPFR_RNDN);  // / ulp(x), exact
    const double out = std::abs(mpfr_get_d(d, MPFR_RNDN)) + extra;
    mpfr_clear(d);
    return out;
}

// |y - x| / ulp(scale), with ulp as in ulp_error.
double scaled_error(double y, const Real& x, double scale) {
    if (std::isnan(y) || mpfr_nan_p(x.backend().data())) return std::numeric_limits<double>::infinity();
    if (std::isinf(y)) return std::numeric_limits<double>::infinity();
    int e = 0;
    std::frexp(scale, &e);  // 2^(e-1) <= scale < 2^e
    mpfr_t d;
    mpfr_init2(d, std::max<long>(mpfr_get_prec(x.backend().data()), 64) + 1100);
    mpfr_set_d(d, y, MPFR_RNDN);
    mpfr_sub(d, d, x.backend().data(), MPFR_RNDN);
    mpfr_mul_2si(d, d, -std::max(e - 53, -1074), MPFR_RNDN);  // / ulp(scale), exact
    const double out = std::abs(mpfr_get_d(d, MPFR_RNDN));
    mpfr_clear(d);
    return out;
}

}  // namespace mollify::accuracy
