#include "decimal.hpp"

#include <cctype>
#include <cmath>

namespace mollify::gen {

Q simplest_between(const Q& lo, const Q& hi) {
    const Z fl = numerator(lo) / denominator(lo);  // floor, lo > 0
    if (Q(fl) == lo) return lo;
    const Z fh = numerator(hi) / denominator(hi);
    if (fl < fh) return Q(fl + 1);
    return Q(fl) + Q(1) / simplest_between(Q(1) / (hi - Q(fl)), Q(1) / (lo - Q(fl)));
}

std::optional<int> decimal_places(const std::string& text) {
    const auto e_pos = text.find_first_of("eE");
    const std::string mantissa = text.substr(0, e_pos);
    const auto dot = mantissa.find('.');
    if (dot == std::string::npos && e_pos == std::string::npos) return std::nullopt;  // "p/q" or an integer
    const int exponent = e_pos == std::string::npos ? 0 : std::stoi(text.substr(e_pos + 1));
    const int fraction_digits = dot == std::string::npos ? 0 : static_cast<int>(mantissa.size() - dot - 1);
    return fraction_digits - exponent;
}

std::optional<Q> decimal_unit(const std::string& text) {
    const auto places = decimal_places(text);
    if (!places) return std::nullopt;
    return pow(Q(10), -*places);
}

std::optional<Q> decimal_reading(const std::string& text, const Q& value) {
    const auto unit = decimal_unit(text);
    if (!unit) return std::nullopt;
    const std::string mantissa = text.substr(0, text.find_first_of("eE"));
    const auto first = mantissa.find_first_of("123456789");
    int significant = 0;
    for (std::size_t i = first; first != std::string::npos && i < mantissa.size(); ++i)
        significant += std::isdigit(static_cast<unsigned char>(mantissa[i])) != 0;
    if (significant < 5) return std::nullopt;
    const Q half_unit = *unit / 2;
    const Q a = value < 0 ? -value : value;
    if (a <= half_unit) return std::nullopt;
    const Q simplest = simplest_between(a - half_unit, a + half_unit);
    if (simplest == a) return std::nullopt;
    return value < 0 ? -simplest : simplest;
}

Z rounded_sqrt(const Q& square, int places) {
    const Q target = square * pow(Q(100), places);
    // A double's guess, then exact steps to the one N that brackets the target.
    Z N(static_cast<long long>(std::llround(std::sqrt(static_cast<double>(target)))));
    auto below = [&](const Z& n) { return Q(n) - Q(1, 2) <= 0 || (Q(n) - Q(1, 2)) * (Q(n) - Q(1, 2)) <= target; };
    while (!below(N)) --N;
    while ((Q(N) + Q(1, 2)) * (Q(N) + Q(1, 2)) <= target) ++N;
    return N;
}

std::string decimal_string(const Z& n, int places) {
    const bool negative = n < 0;
    std::string t = (negative ? Z(-n) : n).str();
    if (places <= 0) return (negative ? "-" : "") + t + std::string(static_cast<std::size_t>(-places), '0');
    const auto p = static_cast<std::size_t>(places);
    if (t.size() <= p) t.insert(0, p + 1 - t.size(), '0');
    t.insert(t.size() - p, ".");
    return (negative ? "-" : "") + t;
}

}  // namespace mollify::gen
