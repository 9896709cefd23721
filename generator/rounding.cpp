#include "rounding.hpp"

#include "error.hpp"

#include <charconv>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <utility>

namespace mollify::gen {

namespace {

// Ziv's first precision: the rounded result does not depend on it (the loop
// doubles it until the enclosure decides), only the time does; 128 bits
// decide nearly every coefficient the first time (53 bits + the 24 of the
// error term + ~50 of cancellation), at half the cost of 256.
constexpr unsigned start_bits = 128;
constexpr unsigned max_bits = 1u << 16;

Q to_rational(const Real& x) {
    Q q;
    mpfr_get_q(q.backend().data(), x.backend().data());
    return q;
}

// The bound on an evaluation's error at `bits`: magnitude 2^(headroom -
// bits) + 2^(-floor_factor bits), generous (the evaluators round a few times
// per term, each by 2^-bits of at most the sum of |terms|, the magnitude).
constexpr unsigned error_headroom = 24, error_floor_factor = 4;

// [v - e, v + e] with e that bound.
std::pair<Q, Q> enclosure(const Evaluator& f, unsigned bits) {
    const auto [v, magnitude] = f(bits);
    // By exact shifts (rational powers of 2 by squaring were a sixth of
    // `emit`'s time).
    Q err = to_rational(magnitude), floor_term = 1;
    mpq_div_2exp(err.backend().data(), err.backend().data(), bits - error_headroom);
    mpq_div_2exp(floor_term.backend().data(), floor_term.backend().data(), error_floor_factor * bits);
    err += floor_term;
    const Q center = to_rational(v);
    return {center - err, center + err};
}

Evaluator of(const Exact& x) {
    return [x](unsigned bits) { return x.evaluate(bits); };
}

int decimal_exponent(const Q& a) {  // floor(log10 a), a > 0
    int e = static_cast<int>(numerator(a).str().size()) - static_cast<int>(denominator(a).str().size());
    while (a < pow(Q(10), e)) --e;
    while (a >= pow(Q(10), e + 1)) ++e;
    return e;
}

Z round_half_even(const Q& x) {  // x >= 0
    Z floor_part = numerator(x) / denominator(x);
    const Q frac = x - Q(floor_part);
    if (frac > Q(1, 2) || (frac == Q(1, 2) && floor_part % 2 != 0)) floor_part += 1;
    return floor_part;
}

// [a/b] from a's and b's enclosures at `bits`; nullopt while b's contains 0.
std::optional<std::pair<Q, Q>> quotient_enclosure(const Exact& a, const Exact& b, unsigned bits) {
    const auto [alo, ahi] = a.is_rational() ? std::pair{a.rational(), a.rational()} : enclosure(of(a), bits);
    const auto [blo, bhi] = b.is_rational() ? std::pair{b.rational(), b.rational()} : enclosure(of(b), bits);
    if (blo <= 0 && bhi >= 0) return std::nullopt;
    Q lo = alo / blo, hi = lo;
    for (const Q& q : {Q(alo / bhi), Q(ahi / blo), Q(ahi / bhi)}) {
        if (q < lo) lo = q;
        if (q > hi) hi = q;
    }
    return std::pair{lo, hi};
}

// Both ends of a/b's enclosure mapped alike by `round`, at rising precision.
template <class F>
auto decide_quotient(const Exact& a, const Exact& b, F round, const std::string& what) {
    if (b.is_zero()) fail("cannot round " + a.to_string() + " / 0");
    if (a.is_rational() && b.is_rational()) return round(a.rational() / b.rational());
    for (unsigned bits = start_bits; bits <= max_bits; bits *= 2) {
        const auto e = quotient_enclosure(a, b, bits);
        if (!e) continue;
        auto x = round(e->first), y = round(e->second);
        if (x == y) return x;
    }
    fail("could not round (" + a.to_string() + ") / (" + b.to_string() + ") correctly to " + what + " at " +
         std::to_string(max_bits) + " bits (an exact tie or a value on a rounding boundary?)");
}

}  // namespace

double round_quotient_to_double(const Exact& a, const Exact& b) {
    return decide_quotient(a, b, [](const Q& q) { return round_to_double(q); }, "a double");
}

std::string decimal_quotient(const Exact& a, const Exact& b, int digits) {
    return decide_quotient(a, b, [digits](const Q& q) { return decimal(q, digits); }, std::to_string(digits) + " digits");
}

namespace {

// q on the grid of multiples of 2^-grid, rounded once (to nearest, ties to
// even), exactly: the subnormals, where a rounding to the format's
// precision first and to the grid after would round twice (just above half
// the smallest subnormal became exactly half, and the tie went to 0).
double on_subnormal_grid(const Q& q, int grid) {
    const Q scaled = q * pow(Q(2), grid);
    Z n;
    mpz_fdiv_q(n.backend().data(), mpq_numref(scaled.backend().data()), mpq_denref(scaled.backend().data()));
    const Q above = scaled - Q(n);  // in [0, 1)
    if (above > Q(1, 2) || (above == Q(1, 2) && mpz_odd_p(n.backend().data()))) n += 1;
    if (n == 0) return q < 0 ? -0.0 : 0.0;
    return std::ldexp(mpz_get_d(n.backend().data()), -grid);  // |n| <= 2^52 (2^23 for floats): exact
}

}  // namespace

double round_to_double(const Q& q) {
    mpfr_t x;
    mpfr_init2(x, 53);
    mpfr_set_q(x, q.backend().data(), MPFR_RNDN);
    // Below 2^-1022 (the smallest normal, MPFR exponent -1021) the subnormal grid.
    const bool subnormal = !mpfr_zero_p(x) && mpfr_get_exp(x) <= -1022;
    const double d = subnormal ? on_subnormal_grid(q, 1074) : mpfr_get_d(x, MPFR_RNDN);  // exact: x has 53 bits
    mpfr_clear(x);
    return d;
}

namespace {

// Ziv's loop: both ends of f's enclosure mapped alike by `round`, at rising precision.
template <class Round>
auto ziv_round(const Evaluator& f, Round round, const std::string& to) {
    for (unsigned bits = start_bits; bits <= max_bits; bits *= 2) {
        const auto [lo, hi] = enclosure(f, bits);
        const auto a = round(lo), b = round(hi);
        if (a == b) return a;
    }
    fail("internal: could not round a value correctly to " + to + " (is it exactly zero or a rounding boundary?)");
}

// Ziv's loop to a double in MPFR alone (the rational enclosure's
// conversions and divisions were a third of the rounding's time): the
// enclosure's ends moved outward, v - e rounded down and v + e up (e the
// same bound, rounded up), each rounded to the nearest double by
// mpfr_get_d (correctly, subnormals included); where they agree, every
// point of the wider interval, the value among them, rounds so.
// One step of it: the double the value v stands for rounds to where its
// enclosure at `bits` ([v - e, v + e], e = magnitude 2^(headroom - bits) +
// 2^(-floor bits)) rounds to one double; nullopt where the ends round apart.
std::optional<double> decided(const Real& v, const Real& magnitude, unsigned bits) {
    mpfr_t e, tiny, lo, hi;
    mpfr_inits2(64, e, tiny, static_cast<mpfr_ptr>(nullptr));
    const mpfr_prec_t p = mpfr_get_prec(v.backend().data()) + 2;
    mpfr_inits2(p, lo, hi, static_cast<mpfr_ptr>(nullptr));
    mpfr_set(e, magnitude.backend().data(), MPFR_RNDU);
    mpfr_abs(e, e, MPFR_RNDU);
    mpfr_mul_2si(e, e, static_cast<long>(error_headroom) - static_cast<long>(bits), MPFR_RNDU);
    mpfr_set_ui_2exp(tiny, 1, -static_cast<long>(error_floor_factor * bits), MPFR_RNDU);
    mpfr_add(e, e, tiny, MPFR_RNDU);
    mpfr_sub(lo, v.backend().data(), e, MPFR_RNDD);
    mpfr_add(hi, v.backend().data(), e, MPFR_RNDU);
    const double a = mpfr_get_d(lo, MPFR_RNDN), b = mpfr_get_d(hi, MPFR_RNDN);
    mpfr_clears(e, tiny, lo, hi, static_cast<mpfr_ptr>(nullptr));
    if (a == b) return a;
    return std::nullopt;
}

double ziv_round_to_double(const Evaluator& f, unsigned first_bits) {
    for (unsigned bits = first_bits; bits <= max_bits; bits *= 2) {
        const auto [v, magnitude] = f(bits);
        if (const auto d = decided(v, magnitude, bits)) return *d;
    }
    fail("internal: could not round a value correctly to double (is it exactly zero or a rounding boundary?)");
}

}  // namespace

double round_to_double(const Evaluator& f) { return ziv_round_to_double(f, start_bits); }

double ulp_of_double(double x) { return std::ldexp(1.0, std::max(std::ilogb(std::fabs(x)), -1022) - 52); }
double ulp_of_float(double x) { return std::ldexp(1.0, std::max(std::ilogb(std::fabs(x)), -126) - 23); }

float round_to_float(const Q& q) {
    mpfr_t x;
    mpfr_init2(x, 24);
    mpfr_set_q(x, q.backend().data(), MPFR_RNDN);
    // Below 2^-126 (the smallest normal float) the subnormal grid 2^-149.
    const bool subnormal = !mpfr_zero_p(x) && mpfr_get_exp(x) <= -126;
    const float f = subnormal ? static_cast<float>(on_subnormal_grid(q, 149))  // a multiple of 2^-149: exact
                              : mpfr_get_flt(x, MPFR_RNDN);                    // exact: x has 24 bits
    mpfr_clear(x);
    return f;
}

float round_to_float(const Evaluator& f) {
    return ziv_round(f, [](const Q& q) { return round_to_float(q); }, "float");
}

namespace {

// q pi^e (e != 0, the kernels' normalisations) when 128 bits decide it: q,
// pi and the power each rounded once, the product once, so the relative
// error is below (|e| + 4) 2^-128; where that interval rounds to one double
// (mpfr_can_round, the value being irrational: no ties), that double is the
// correctly rounded one, as Ziv's loop would find. nullopt otherwise (and
// outside the normal doubles), for the loop.
std::optional<double> single_pi_term(const Exact& x) {
    if (x.terms().size() != 1) return std::nullopt;
    const auto& [atom, q] = *x.terms().begin();
    if (atom.log_of != 1 || atom.pi_power == 0 || std::abs(atom.pi_power) > 64) return std::nullopt;
    mpfr_t v, pi;
    mpfr_inits2(128, v, pi, static_cast<mpfr_ptr>(nullptr));
    mpfr_const_pi(pi, MPFR_RNDN);
    mpfr_pow_si(pi, pi, atom.pi_power, MPFR_RNDN);
    mpfr_set_q(v, q.backend().data(), MPFR_RNDN);
    mpfr_mul(v, v, pi, MPFR_RNDN);
    std::optional<double> out;
    const long e = mpfr_get_exp(v);
    if (e > -1000 && e < 1000 && mpfr_can_round(v, 128 - 8, MPFR_RNDN, MPFR_RNDZ, 53 + 1)) out = mpfr_get_d(v, MPFR_RNDN);
    mpfr_clears(v, pi, static_cast<mpfr_ptr>(nullptr));
    return out;
}

}  // namespace

double round_to_double(const Exact& x) {
    if (x.is_rational()) return round_to_double(x.rational());
    if (const auto d = single_pi_term(x)) return *d;
    return round_to_double(of(x));
}

double low_part(const Q& q, double hi) { return round_to_double(q - Q(hi)); }

namespace {

// x - hi for x = q pi^e (as single_pi_term) when 256 bits decide it: x's
// relative error is below (|e| + 4) 2^-256, the subtraction of hi (within
// half an ulp of x) exact, so the difference is off by at most
// 2^(E(x) - 249); where that rounds to one double, it is the low part.
std::optional<double> single_pi_low_part(const Exact& x, double hi) {
    if (x.terms().size() != 1 || hi == 0) return std::nullopt;
    const auto& [atom, q] = *x.terms().begin();
    if (atom.log_of != 1 || atom.pi_power == 0 || std::abs(atom.pi_power) > 64) return std::nullopt;
    mpfr_t v, pi;
    mpfr_inits2(256, v, pi, static_cast<mpfr_ptr>(nullptr));
    mpfr_const_pi(pi, MPFR_RNDN);
    mpfr_pow_si(pi, pi, atom.pi_power, MPFR_RNDN);
    mpfr_set_q(v, q.backend().data(), MPFR_RNDN);
    mpfr_mul(v, v, pi, MPFR_RNDN);
    const long ex = mpfr_get_exp(v);
    std::optional<double> out;
    if (mpfr_sub_d(v, v, hi, MPFR_RNDN) == 0 && !mpfr_zero_p(v)) {
        const long ed = mpfr_get_exp(v), err = 249 - (ex - ed);
        if (ex > -900 && ex < 1000 && ed > -1000 && err > 60 && mpfr_can_round(v, err, MPFR_RNDN, MPFR_RNDZ, 53 + 1))
            out = mpfr_get_d(v, MPFR_RNDN);
    }
    mpfr_clears(v, pi, static_cast<mpfr_ptr>(nullptr));
    return out;
}

}  // namespace

// A low part's Ziv loop starts at 256 bits: x - hi, below 2^-53 |x|, is
// decided only by an enclosure narrower than 2^-106 |x|, which 128 bits
// (2^-104 of the sum of |terms| >= |x|) never are.
constexpr unsigned low_part_bits = 2 * start_bits;

double low_part(const Exact& x, double hi) {
    if (x.is_rational()) return low_part(x.rational(), hi);
    if (const auto d = single_pi_low_part(x, hi)) return *d;
    return ziv_round_to_double(of(x - Exact(Q(hi))), low_part_bits);
}

std::pair<double, double> round_to_double_double(const Evaluator& f) {
    // One evaluation at the low part's first precision decides both where
    // it can (each correctly rounded, so the same doubles as the two loops,
    // which run where it cannot).
    auto [v, magnitude] = f(low_part_bits);
    if (const auto hi = decided(v, magnitude, low_part_bits)) {
        // Exact: v is within a factor 2 of hi (Sterbenz), at v's precision.
        mpfr_sub_d(v.backend().data(), v.backend().data(), *hi, MPFR_RNDN);
        if (const auto lo = decided(v, magnitude, low_part_bits)) return {*hi, *lo};
        return {*hi, low_part(f, *hi)};
    }
    const double hi = round_to_double(f);
    return {hi, low_part(f, hi)};
}

double low_part(const Evaluator& f, double hi) {
    return ziv_round_to_double(
        [&](unsigned bits) {
            auto [v, magnitude] = f(bits);
            // Exact: v is within a factor 2 of hi (Sterbenz), at v's precision.
            mpfr_sub_d(v.backend().data(), v.backend().data(), hi, MPFR_RNDN);
            return std::pair<Real, Real>(std::move(v), std::move(magnitude));
        },
        low_part_bits);
}

// std::to_chars's hex form after "0x" (its sign before): the text of
// printf's "%a" (Rounding.HexLiteralsAreThoseOfPrintf), without printf's
// format parsing and locale, which were a fifth of the C++ writer's work.
// Infinities and NaN as printf writes them ("inf", "-inf", "nan").
std::string hex_literal(double x) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    char buf[64];
    char* p = buf;
    if (std::signbit(x)) *p++ = '-';
    *p++ = '0';
    *p++ = 'x';
    const auto end = std::to_chars(p, buf + sizeof buf, std::abs(x), std::chars_format::hex).ptr;
    return std::string(buf, end);
}

std::string exact_decimal_literal(double x) {
    if (!std::isfinite(x)) fail("internal: exact_decimal_literal of a non-finite double");
    const std::string sign = std::signbit(x) ? "-" : "";
    if (x == 0) return sign + "0.0";
    // |x| = M 2^p with M odd: M 5^-p / 10^-p for p < 0, an integer otherwise
    int e = 0;
    auto M = static_cast<std::int64_t>(std::ldexp(std::frexp(std::abs(x), &e), 53));
    int p = e - 53;
    while ((M & 1) == 0) M >>= 1, ++p;
    const Z digits = p >= 0 ? Z(Z(M) << p) : Z(Z(M) * boost::multiprecision::pow(Z(5), static_cast<unsigned>(-p)));
    const std::string d = digits.str();
    const int exponent = static_cast<int>(d.size()) - 1 + std::min(p, 0);
    std::string out = sign + d.substr(0, 1) + "." + (d.size() > 1 ? d.substr(1) : "0") + "e";
    out += (exponent < 0 ? "-" : "+") + std::string(std::abs(exponent) < 10 ? "0" : "") + std::to_string(std::abs(exponent));
    return out;
}

std::string decimal(const Q& q, int digits) {
    if (digits < 1) fail("digits = " + std::to_string(digits) + " must be at least 1");
    if (q == 0) return "0." + std::string(static_cast<std::size_t>(std::max(digits - 1, 0)), '0') + "e+00";
    const Q a = q < 0 ? Q(-q) : q;
    int e = decimal_exponent(a);
    Z n = round_half_even(a * pow(Q(10), digits - 1 - e));
    if (n == pow(Q(10), digits)) {  // rounded up to the next power of ten
        n /= 10;
        ++e;
    }
    const std::string d = n.str();
    std::string out = q < 0 ? "-" : "";
    out += d.substr(0, 1);
    if (digits > 1) out += "." + d.substr(1);
    char exp[16];
    std::snprintf(exp, sizeof exp, "e%+03d", e);
    return out + exp;
}

std::string decimal(const Evaluator& f, int digits) {
    // 4 bits a digit (log2 10 = 3.32 and a margin); the loop may double it
    // three times, past max_bits where the digits ask for more (100,000
    // digits start at ~400,000 bits).
    const unsigned first = start_bits + static_cast<unsigned>(digits) * 4;
    for (unsigned bits = first; bits <= std::max(max_bits, 8 * first); bits *= 2) {
        const auto [lo, hi] = enclosure(f, bits);
        const std::string a = decimal(lo, digits), b = decimal(hi, digits);
        if (a == b) return a;
    }
    fail("internal: could not round a value correctly to " + std::to_string(digits) + " digits");
}

std::string decimal(const Exact& x, int digits) {
    if (x.is_rational()) return decimal(x.rational(), digits);
    return decimal(of(x), digits);
}

}  // namespace mollify::gen
