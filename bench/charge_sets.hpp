// The particle sets of the treecode comparison (issue 21, goal 2), one
// definition for mollify's treecode_bench and the peers' drivers
// (bench/peers/), so that both solve the same problem: N points uniform in
// [0, 1)^3 and charges uniform in [-0.5, 0.5] ("neutral": the total charge
// near 0, so the far field cancels and relative errors are large) or in
// [0, 1] ("positive": every far cell adds, relative errors look 5-7x
// smaller). Plain std::mt19937_64, seeded by N, so that any driver built
// with any standard library draws the same points. Errors: the relative L2
// of mollify/poisson/field_errors.hpp, for both.
#pragma once

#include <array>
#include <cstddef>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace mollify::bench {

enum class Charges { neutral, positive };

inline const char* name(Charges c) { return c == Charges::neutral ? "neutral" : "positive"; }

inline Charges charges_named(const std::string& s) {
    if (s == "neutral") return Charges::neutral;
    if (s == "positive") return Charges::positive;
    throw std::invalid_argument("charge set '" + s + "': expected neutral or positive");
}

struct ChargeSet {
    std::array<std::vector<double>, 3> x;
    std::vector<double> q;
};

// Uniform draws from [0, 1) mapped by hand (not uniform_real_distribution,
// whose algorithm the standard leaves to the library).
inline ChargeSet charge_set(std::size_t n, Charges c) {
    std::mt19937_64 rng(n);
    const auto u = [&] { return static_cast<double>(rng() >> 11) * 0x1p-53; };
    ChargeSet s;
    for (auto& xc : s.x) xc.reserve(n);
    s.q.reserve(n);
    for (std::size_t j = 0; j < n; ++j) {
        for (auto& xc : s.x) xc.push_back(u());
        s.q.push_back(c == Charges::neutral ? u() - 0.5 : u());
    }
    return s;
}

}  // namespace mollify::bench
