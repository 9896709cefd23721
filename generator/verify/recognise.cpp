#include "verify/recognise.hpp"

#include <cmath>
#include <numbers>

namespace mollify::verify::detail {

namespace {

// The convergent p/q of x's continued fraction with the largest q <=
// max_denominator that is within relative tolerance, if any.
std::optional<gen::Q> convergent(double x, double tolerance, long max_denominator) {
    if (!std::isfinite(x) || x == 0) return std::nullopt;
    const double target = x;
    long double a = std::abs(x);
    // p_{n-1}/q_{n-1} and p_n/q_n (Khinchin, Continued Fractions, ch. 1).
    long long p0 = 0, q0 = 1, p1 = 1, q1 = 0;
    for (int step = 0; step < 40; ++step) {
        const long double whole = std::floor(a);
        if (whole > 1e15L) break;
        const auto n = static_cast<long long>(whole);
        const long long p2 = n * p1 + p0, q2 = n * q1 + q0;
        if (q2 > max_denominator) break;
        p0 = p1, q0 = q1, p1 = p2, q1 = q2;
        const double approx = static_cast<double>(p1) / static_cast<double>(q1);
        if (std::abs(approx - std::abs(target)) <= tolerance * std::abs(target))
            return gen::Q(x < 0 ? -p1 : p1, q1);
        const long double rest = a - whole;
        if (rest == 0) break;
        a = 1 / rest;
    }
    return std::nullopt;
}

}  // namespace

std::optional<gen::Exact> recognise(double x, double tolerance, long max_denominator) {
    for (int k : {0, -1, 1, -2, 2}) {
        const double y = x / std::pow(std::numbers::pi, k);
        if (const auto q = convergent(y, tolerance, max_denominator)) return gen::Exact::pi_power(*q, k);
    }
    return std::nullopt;
}

std::string pretty(const gen::Exact& c) {
    std::string out;
    for (const auto& [atom, q] : c.terms()) {
        gen::Q a = abs(q);
        const bool negative = q < 0;
        const std::string num = numerator(a).str(), den = denominator(a).str();
        std::string pi = atom.pi_power == 0 ? "" : std::abs(atom.pi_power) == 1 ? "pi" : "pi^" + std::to_string(std::abs(atom.pi_power));
        std::string log = atom.log_of == 1 ? "" : "log(" + std::to_string(atom.log_of) + ")";
        std::string top = num, bottom = den == "1" ? "" : den;
        auto join = [](const std::string& x, const std::string& y) { return x.empty() ? y : y.empty() ? x : x + " " + y; };
        if (atom.pi_power > 0) top = (top == "1" ? pi : join(top, pi));
        if (atom.pi_power < 0) bottom = join(bottom, pi);
        if (!log.empty()) top = top == "1" ? log : join(top, log);
        std::string term = bottom.empty() ? top : top + "/" + (bottom.find(' ') == std::string::npos ? bottom : "(" + bottom + ")");
        out += out.empty() ? (negative ? "-" : "") + term : (negative ? " - " : " + ") + term;
    }
    return out.empty() ? "0" : out;
}

}  // namespace mollify::verify::detail
