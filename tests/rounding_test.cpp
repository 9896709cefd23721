// Correct rounding: to double (hex-float literals of the tables) and to
// N decimal digits (mollify-gen value). References are independent: exact
// binary expansions, and pi's digits (OEIS A000796).
#include "error.hpp"
#include "number.hpp"
#include "rounding.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace mollify::gen;

TEST(Rounding, RationalsToDouble) {
    EXPECT_EQ(round_to_double(Q(1, 3)), 1.0 / 3.0);  // IEEE division is correctly rounded
    EXPECT_EQ(round_to_double(Q(-22, 7)), -22.0 / 7.0);
    // Ties go to even: 1 + 2^-53 lies halfway between 1 and 1 + 2^-52.
    const Q two53 = pow(Q(2), 53);
    EXPECT_EQ(round_to_double(Q(1) + Q(1) / two53), 1.0);
    EXPECT_EQ(round_to_double(Q(1) + Q(3) / two53), 1.0 + 4.0 / std::ldexp(1.0, 53));
    // Just above the tie rounds up.
    EXPECT_EQ(round_to_double(Q(1) + Q(1) / two53 + Q(1) / pow(Q(2), 200)), std::nextafter(1.0, 2.0));
}

// Below the smallest normal the grid is 2^-1074 (double) and 2^-149
// (float): one rounding onto it, not one to 53 (24) bits and another to the
// subnormal grid. Just above half the smallest subnormal goes up to it; a
// 53-bit rounding first made it exactly half, and the tie went to 0.
TEST(Rounding, SubnormalsAreRoundedOnce) {
    const Q tiny = pow(Q(2), -1074), tiny_float = pow(Q(2), -149);
    const Q above_half = tiny * (Q(1, 2) + pow(Q(2), -60));
    EXPECT_EQ(round_to_double(above_half), 0x1p-1074);
    EXPECT_EQ(round_to_double(-above_half), -0x1p-1074);
    EXPECT_EQ(round_to_double(tiny / 2), 0.0);                      // a tie: to even, 0
    EXPECT_EQ(round_to_double(tiny * Q(3, 2)), 0x1p-1073);           // a tie: to even, 2 x 2^-1074
    EXPECT_EQ(round_to_double(tiny * (Q(5) + Q(1, 3))), 0x5p-1074);  // 5.33 x 2^-1074
    EXPECT_EQ(round_to_double(pow(Q(2), -1022) - tiny / 3), 0x1p-1022);  // up to the smallest normal
    EXPECT_EQ(round_to_double(pow(Q(2), -1023) + pow(Q(2), -1100)), 0x1p-1023);
    const Q float_above_half = tiny_float * (Q(1, 2) + pow(Q(2), -40));
    EXPECT_EQ(round_to_float(float_above_half), 0x1p-149f);
    EXPECT_EQ(round_to_float(tiny_float / 2), 0.0f);
    EXPECT_EQ(round_to_float(tiny_float * Q(7, 2)), 0x1p-147f);  // 3.5: a tie, to even 4
    EXPECT_EQ(round_to_float(pow(Q(2), -126) - tiny_float / 3), 0x1p-126f);
}

TEST(Rounding, TranscendentalToDouble) {
    EXPECT_EQ(round_to_double(Exact::pi_power(Q(1), 1)), M_PI);
    EXPECT_EQ(round_to_double(Exact::pi_power(Q(1), -1)), M_1_PI);
    EXPECT_EQ(round_to_double(Exact::log_of(Q(2))), M_LN2);
    EXPECT_EQ(round_to_double(Exact::pi_power(Q(21, 2), -1)), 0x1.abcef9018d72bp+1);  // 21/(2 pi): mpmath at 400 bits, rounded by Python fractions
}

TEST(Rounding, HexLiteralsRoundTrip) {
    for (double x : {0.0, 1.0, -0.1, 1e-300, 6.02214076e23, M_PI, std::nextafter(1.0, 0.0)})
        EXPECT_EQ(std::strtod(hex_literal(x).c_str(), nullptr), x) << hex_literal(x);
}

// exact_decimal_literal (GADGET-4's C++11 headers): every digit of the
// double's value, so the text's own rational is the double exactly (parsed
// here by the generator's decimal grammar, not by a compiler), and strtod
// gives it back; signed zero, subnormals and the largest double included.
TEST(Rounding, ExactDecimalLiteralsAreTheDoublesExactly) {
    const std::vector<double> xs = {0.0, -0.0, 1.0, -0.1, 0.375, 1e-300, 6.02214076e23, M_PI, 0x1.abcef9018d72bp+1,
                                    std::nextafter(1.0, 0.0), 0x1p-1074, -0x1.8p-1070, std::numeric_limits<double>::max(),
                                    4503599627370497.0, 1e22};
    for (double x : xs) {
        const std::string t = exact_decimal_literal(x);
        EXPECT_EQ(parse_rational(t, "literal"), Q(x)) << t;
        EXPECT_EQ(std::strtod(t.c_str(), nullptr), x) << t;
        EXPECT_EQ(std::signbit(std::strtod(t.c_str(), nullptr)), std::signbit(x)) << t;
    }
    EXPECT_EQ(exact_decimal_literal(0.375), "3.75e-01");
    EXPECT_EQ(exact_decimal_literal(-2.0), "-2.0e+00");
    EXPECT_EQ(exact_decimal_literal(1e22), "1.0000000000000000000000e+22");
    EXPECT_EQ(exact_decimal_literal(0.1), "1.000000000000000055511151231257827021181583404541015625e-01");
    EXPECT_EQ(exact_decimal_literal(0x1p-1074).size(), 757u);  // 2^-1074 = 4.94...e-324: 751 significant digits
    EXPECT_THROW(exact_decimal_literal(INFINITY), Error);
}

// hex_literal is std::to_chars's hex form: the same text as printf's "%a"
// (the emitted tables' literals did not change), signed zeros, subnormals,
// the extremes and 10^5 random bit patterns.
TEST(Rounding, HexLiteralsAreThoseOfPrintf) {
    auto printf_a = [](double x) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%a", x);
        return std::string(buf);
    };
    std::vector<double> xs = {0.0, -0.0, 1.0, -1.0, 0.5, 0.1, 1.0 / 3, 0x1p-1074, -0x1p-1074, 0x1.8p-1060,
                              std::numeric_limits<double>::min(), std::numeric_limits<double>::max(),
                              std::nextafter(1.0, 2.0), -std::numeric_limits<double>::max()};
    std::mt19937_64 bits(20261129);
    while (xs.size() < 100000) {
        const std::uint64_t u = bits();
        double x;
        std::memcpy(&x, &u, sizeof x);
        if (std::isfinite(x)) xs.push_back(x);
    }
    for (double x : xs) ASSERT_EQ(hex_literal(x), printf_a(x));
    for (double x : {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()})
        EXPECT_EQ(hex_literal(x), printf_a(x));
}

TEST(Rounding, DecimalDigits) {
    EXPECT_EQ(decimal(Q(1, 3), 5), "3.3333e-01");
    EXPECT_EQ(decimal(Q(2, 3), 5), "6.6667e-01");
    EXPECT_EQ(decimal(Q(-1, 8), 2), "-1.2e-01");   // 0.125: half to even
    EXPECT_EQ(decimal(Q(3, 8), 2), "3.8e-01");     // 0.375: half to even
    EXPECT_EQ(decimal(Q(999999, 1000000), 3), "1.00e+00");
    EXPECT_EQ(decimal(Q(999999, 1000), 3), "1.00e+03");
    EXPECT_EQ(decimal(Q(0), 3), "0.00e+00");
    EXPECT_EQ(decimal(Q(12345), 1), "1e+04");
    EXPECT_EQ(decimal(Exact::pi_power(Q(1), 1), 40), "3.141592653589793238462643383279502884197e+00");
    EXPECT_EQ(decimal(Exact::pi_power(Q(1), -1), 20), "3.1830988618379067154e-01");
    EXPECT_THROW(decimal(Q(1), 0), Error);
}

// The low parts of the double-double coefficients (table::Term::c_lo).
// References: 1/3 - round(1/3) = 2^-54/3 exactly; pi's double-double
// 0x1.921fb54442d18p+1 + 0x1.1a62633145c07p-53 (= 1.224646799147353207e-16,
// the QD library's dd_real::_pi).
TEST(Rounding, LowPartsOfDoubleDoubles) {
    EXPECT_EQ(low_part(Q(1, 3), 1.0 / 3.0), 0x1.5555555555555p-56);
    EXPECT_EQ(low_part(Q(-1, 3), -1.0 / 3.0), -0x1.5555555555555p-56);
    EXPECT_EQ(low_part(Q(3, 8), 0.375), 0.0);  // a double: no low part
    EXPECT_EQ(low_part(Exact::pi_power(Q(1), 1), M_PI), 0x1.1a62633145c07p-53);
    EXPECT_EQ(low_part(Exact::pi_power(Q(2), 1), 2 * M_PI), 2 * 0x1.1a62633145c07p-53);
    // An Evaluator (a value at any precision, refined by the Ziv loop): pi
    // from MPFR's constant.
    const Evaluator pi = [](unsigned bits) {
        Real v(0, bits), magnitude(4, 64);
        mpfr_const_pi(v.backend().data(), MPFR_RNDN);
        return std::pair<Real, Real>(v, magnitude);
    };
    EXPECT_EQ(low_part(pi, M_PI), 0x1.1a62633145c07p-53);
}

// Quotients of exact constants (Phantom's cnormk_drag, av_factor): decided
// where a fixed precision cannot see the side of the tie, refused on the tie.
// q = pi (1 + 2^-53) +- 2^-400 log 2 over pi lies 2^-400 log(2)/pi from the
// tie between 1 and 1 + 2^-52 (invisible at the first 256 bits).
TEST(Rounding, QuotientsNearATieAreDecidedOrRefused) {
    const Exact pi = Exact::pi_power(Q(1), 1), tiny = Exact::log_of(Q(2)) * pow(Q(2), -400);
    const Exact tie = Exact::pi_power(Q(1) + pow(Q(2), -53), 1);
    EXPECT_EQ(round_quotient_to_double(tie + tiny, pi), std::nextafter(1.0, 2.0));
    EXPECT_EQ(round_quotient_to_double(tie - tiny, pi), 1.0);
    // the same over pi + 1 (a denominator of two terms)
    const Exact den = pi + Exact(Q(1));
    EXPECT_EQ(round_quotient_to_double((tie + tiny) * Exact::pi_power(Q(1), -1) * den, den),
              std::nextafter(1.0, 2.0));
    try {
        round_quotient_to_double(tie * Exact::log_of(Q(3)), pi * Exact::log_of(Q(3)));
        FAIL() << "an exact tie was rounded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("could not round"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("log(3)"), std::string::npos) << e.what();
    }
    EXPECT_EQ(round_quotient_to_double(Exact::log_of(Q(2)), Exact(Q(1))), M_LN2);
    EXPECT_EQ(round_quotient_to_double(Exact(Q(1)), Exact::pi_power(Q(1), 1)), M_1_PI);
    EXPECT_EQ(decimal_quotient(Exact::pi_power(Q(1), 1), Exact(Q(1)), 20), "3.1415926535897932385e+00");  // OEIS A000796
    EXPECT_THROW(round_quotient_to_double(pi, Exact()), Error);
}

// Floats (SWIFT's constants): ties to even, just above a tie up, pi by Ziv.
TEST(Rounding, ToFloat) {
    const Q tie = Q(1) + pow(Q(2), -24);  // halfway between 1 and 1 + 2^-23
    EXPECT_EQ(round_to_float(tie), 1.0f);
    EXPECT_EQ(round_to_float(tie + pow(Q(2), -300)), std::nextafter(1.0f, 2.0f));
    EXPECT_EQ(round_to_float(Q(1) + 3 * pow(Q(2), -24)), 1.0f + 0x1p-22f);  // the tie above 1 + 2^-23 goes to even 1 + 2^-22
    const Exact pi = Exact::pi_power(Q(1), 1);
    EXPECT_EQ(round_to_float([&](unsigned bits) { return pi.evaluate(bits); }), 0x1.921fb6p+1f);  // pi = 0x1.921fb54442d18...p+1
}
