#include "number.hpp"

#include "error.hpp"

#include <mollify/spec.hpp>  // the number syntax, shared with kernel specs

#include <cmath>
#include <optional>
#include <string>

namespace mollify::gen {

namespace {

// Z(text) would read a leading 0 as octal ("010" is 8): strip it first.
Z decimal_integer(const std::string& digits) {
    const std::size_t first = digits.find_first_not_of('0');
    return first == std::string::npos ? Z(0) : Z(digits.substr(first));
}

}  // namespace

Q parse_rational(std::string_view text, std::string_view what) {
    const auto syntax = mollify::split_number(text);
    if (!syntax)
        fail(std::string(what) + ": '" + std::string(text) +
             "' is not a number (expected an integer, p/q, or a decimal such as 0.25 or 1e-3)");
    const mollify::NumberSyntax& parts = *syntax;
    const Z integer = decimal_integer(parts.integer);
    Q value;
    if (!parts.denominator.empty()) {
        const Z den = decimal_integer(parts.denominator);
        if (den == 0) fail(std::string(what) + ": '" + std::string(text) + "' has a zero denominator");
        value = Q(integer, den);
    } else {
        Z scale = 1;
        Z digits = integer;
        for (char c : parts.fraction) {
            digits = digits * 10 + (c - '0');
            scale *= 10;
        }
        value = Q(digits, scale);
        if (parts.has_exponent) {
            if (parts.exponent.size() > 6)
                fail(std::string(what) + ": exponent of '" + std::string(text) + "' is out of range");
            int e = std::stoi(parts.exponent);
            value *= pow(Q(10), parts.exponent_negative ? -e : e);
        }
    }
    return parts.negative ? Q(-value) : value;
}

Q parse_rational_or_hex_float(std::string_view text, std::string_view what) {
    const std::optional<double> x = hex_float(text);  // the number grammar's hex-floats (spec.hpp)
    if (!x) return parse_rational(text, what);
    if (!std::isfinite(*x))
        fail(std::string(what) + ": '" + std::string(text) + "' is not a finite hex-float (expected e.g. 0x1.8p-2)");
    return Q(*x);  // mpq_set_d: exact
}

std::string pq(const Q& q) { return numerator(q).str() + "/" + denominator(q).str(); }

std::vector<Q> equispaced(const Q& lo, const Q& hi, int n) {
    const Q step = (hi - lo) / Q(n);
    std::vector<Q> out;
    out.reserve(static_cast<std::size_t>(n) + 1);
    out.push_back(lo);
    for (int i = 1; i < n; ++i) out.push_back(out.back() + step);
    out.push_back(hi);
    return out;
}

std::string short_string(const Q& q) {
    return is_integer(q) ? numerator(q).str() : pq(q);
}

Q pow(const Q& base, int exponent) {
    if (exponent < 0) {
        if (base == 0) fail("division by zero in a power");
        return pow(Q(1) / base, -exponent);
    }
    // (a/b)^n = a^n / b^n, already in lowest terms (a and b coprime): two
    // integer powers, no gcd (squaring rationals took a gcd per step).
    Q result;
    mpz_pow_ui(mpq_numref(result.backend().data()), mpq_numref(base.backend().data()), static_cast<unsigned long>(exponent));
    mpz_pow_ui(mpq_denref(result.backend().data()), mpq_denref(base.backend().data()), static_cast<unsigned long>(exponent));
    return result;
}

Z factorial(unsigned n) {
    Z f = 1;
    for (unsigned i = 2; i <= n; ++i) f *= i;
    return f;
}

Z binomial(unsigned n, unsigned k) {
    if (k > n) return 0;
    Z b = 1;
    for (unsigned i = 1; i <= k; ++i) b = b * (n - k + i) / i;
    return b;
}

Q central_binomial_ratio(int k) {
    return Q(factorial(static_cast<unsigned>(2 * k)), factorial(static_cast<unsigned>(k)) * factorial(static_cast<unsigned>(k))) /
           pow(Q(4), k);
}

Q binomial(const Q& a, int k) {
    if (k < 0) return 0;
    Q b = 1;
    for (int i = 0; i < k; ++i) b *= (a - i) / Q(i + 1);
    return b;
}

}  // namespace mollify::gen
