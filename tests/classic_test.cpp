// Classic comparison kernels (classic.hpp): exact normalisations in D = 1, 2, 3,
// the shapes themselves, Belley's derivative kernels and the dimensions in
// which kernels do not exist.
//
// Every reference normalisation is derived below by integrating the shape by
// hand (N = 1 / (omega_D int_0^1 r^(D-1) shape dr), omega = 2, 2 pi, 4 pi), and
// re-derived in the test by term-wise integration written here; the literature
// value it agrees with is named. Comparisons are of Exact values, so a
// transposed digit (e.g. 315/(46 pi) or 3/359) cannot pass.
#include "error.hpp"
#include "kernel.hpp"
#include "radial.hpp"
#include "spec.hpp"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

namespace mollify::gen {
namespace {

ExactKernel kernel(const std::string& spec, int dim) { return make_kernel(parse_spec(spec), dim); }

Exact pi_power(long long p, long long q, int e) { return Exact::pi_power(Q(p, q), e); }

// A piece c_n r^n (n may be -1 for viscosity) on [a, b], integrated here.
struct Piece {
    Q a, b;
    std::map<int, Q> c;  // power -> coefficient
};

Q power_of(const Q& x, int n) {
    Q p = 1;
    for (int i = 0; i < n; ++i) p *= x;
    return p;
}

// int_a^b r^w sum c_n r^n dr (no log terms arise for the weights used).
Q integrate(const std::vector<Piece>& shape, int w) {
    Q s = 0;
    for (const Piece& p : shape)
        for (const auto& [n, c] : p.c) s += c * (power_of(p.b, n + w + 1) - power_of(p.a, n + w + 1)) / (n + w + 1);
    return s;
}

// Schoenberg's M_n on support 1 from its definition as truncated powers
// (Schoenberg 1946; Monaghan 2005 §4): with x = (n/2) r,
//   M_n = 1/(n-1)! sum_{j < n/2} (-1)^j binom(n, j) (n/2 - j - x)_+^(n-1)
//       = (n/2)^(n-1)/(n-1)! sum_j (-1)^j binom(n, j) (k_j - r)_+^(n-1),  k_j = 1 - 2j/n,
// each power expanded here by the binomial theorem on the pieces between knots.
std::vector<Piece> schoenberg_pieces(int n) {
    const int d = n - 1;
    auto binom = [](int a, int b) {
        Q c = 1;
        for (int i = 1; i <= b; ++i) c = c * Q(a - b + i) / Q(i);
        return c;
    };
    Q scale = 1;
    for (int i = 1; i <= d; ++i) scale = scale * Q(n, 2) / Q(i);
    std::vector<Q> knots;  // ascending: 1 - 2j/n for the largest j first
    for (int j = (n - 1) / 2; j >= 0; --j) knots.push_back(Q(1) - Q(2 * j, n));
    std::vector<Piece> pieces;
    Q a = 0;
    for (const Q& b : knots) {
        Piece p{a, b, {}};
        for (int j = 0; Q(1) - Q(2 * j, n) >= b; ++j) {
            const Q k = Q(1) - Q(2 * j, n), sign = j % 2 == 0 ? Q(1) : Q(-1);
            for (int i = 0; i <= d; ++i)  // (k - r)^d = sum_i binom(d, i) k^(d-i) (-r)^i
                p.c[i] += scale * sign * binom(n, j) * binom(d, i) * power_of(k, d - i) * (i % 2 == 0 ? Q(1) : Q(-1));
        }
        pieces.push_back(p);
        a = b;
    }
    return pieces;
}

// Shapes, written from their definitions:
//   poly6  (1 - r^2)^3 = 1 - 3r^2 + 3r^4 - r^6              (Mueller et al. 2003)
//   spiky  (1 - r)^3   = 1 - 3r + 3r^2 - r^3                 (Desbrun & Cani 1996)
//   viscosity -r^3/2 + r^2 + 1/(2r) - 1                      (Mueller et al. 2003)
//   cubic-spline 1 - 6r^2 + 6r^3 on [0,1/2), 2(1-r)^3 on [1/2,1]  (Monaghan M4, support 1)
//   box    1                                                 (Belley (12))
const std::map<std::string, std::vector<Piece>> shapes = {
    {"poly6", {{Q(0), Q(1), {{0, Q(1)}, {2, Q(-3)}, {4, Q(3)}, {6, Q(-1)}}}}},
    {"spiky", {{Q(0), Q(1), {{0, Q(1)}, {1, Q(-3)}, {2, Q(3)}, {3, Q(-1)}}}}},
    {"viscosity", {{Q(0), Q(1), {{3, Q(-1, 2)}, {2, Q(1)}, {-1, Q(1, 2)}, {0, Q(-1)}}}}},
    {"cubic-spline",
     {{Q(0), Q(1, 2), {{0, Q(1)}, {2, Q(-6)}, {3, Q(6)}}},
      {Q(1, 2), Q(1), {{0, Q(2)}, {1, Q(-6)}, {2, Q(6)}, {3, Q(-2)}}}}},
    {"quartic-spline", schoenberg_pieces(5)},
    {"quintic-spline", schoenberg_pieces(6)},
    {"box", {{Q(0), Q(1), {{0, Q(1)}}}}},
};

// Hand integrals (B(a,b) = (a-1)!(b-1)!/(a+b-1)!):
//   poly6:  1D int (1-r^2)^3 = 1 - 1 + 3/5 - 1/7 = 16/35, x2 = 32/35      -> 35/32     (Belley (8))
//           2D int r(1-r^2)^3 = 1/8, x 2 pi = pi/4                        -> 4/pi
//           3D int r^2(1-r^2)^3 = 1/3 - 3/5 + 3/7 - 1/9 = 16/315, x 4 pi  -> 315/(64 pi) (Mueller)
//   spiky:  1D int (1-r)^3 = 1/4, x2 = 1/2                                -> 2
//           2D int r(1-r)^3 = B(2,4) = 1/20, x 2 pi = pi/10               -> 10/pi
//           3D int r^2(1-r)^3 = B(3,4) = 1/60, x 4 pi = pi/15             -> 15/pi     (Mueller)
//   viscosity: 2D int r(...) = -1/10 + 1/4 + 1/2 - 1/2 = 3/20, x 2 pi     -> 10/(3 pi)
//              3D int r^2(...) = -1/12 + 1/5 + 1/4 - 1/3 = 1/30, x 4 pi   -> 15/(2 pi) (Mueller)
//   cubic spline: 1D 11/32 + 1/32 = 3/8, x2 = 3/4                         -> 4/3       (Monaghan)
//                 2D int_0^1/2 (r - 6r^3 + 6r^4) = 11/160, int_1/2^1 2r(1-r)^3 = 3/160;
//                    7/80 x 2 pi = 7 pi/40                                -> 40/(7 pi) (Monaghan)
//                 3D 19/960 + 11/960 = 1/32, x 4 pi = pi/8                -> 8/pi      (Monaghan)
//   box:    1D 1 x 2 -> 1/2; 2D 1/2 x 2 pi -> 1/pi; 3D 1/3 x 4 pi         -> 3/(4 pi)
//   quartic, quintic spline (M5, M6): Monaghan 2005 §4 prints W = sigma w(q)/h^D on support R h
//   (R = 5/2, 3) with w = (n-1)! M_n, sigma = 1/24, 96/(1199 pi), 1/(20 pi) (M5) and 1/120,
//   7/(478 pi), 1/(120 pi) (M6) in D = 1, 2, 3; on support 1 the shape is M_n(R r), so
//   N = sigma R^D (n-1)!:                                               M5 -> 5/2, 14400/(1199 pi), 75/(4 pi)
//                                                                       M6 -> 3, 3780/(239 pi), 27/pi
struct Expected {
    const char* spec;
    int D;
    Exact N;
};
const std::vector<Expected> expected = {
    {"poly6", 1, pi_power(35, 32, 0)},         {"poly6", 2, pi_power(4, 1, -1)},
    {"poly6", 3, pi_power(315, 64, -1)},       {"spiky", 1, pi_power(2, 1, 0)},
    {"spiky", 2, pi_power(10, 1, -1)},         {"spiky", 3, pi_power(15, 1, -1)},
    {"viscosity", 2, pi_power(10, 3, -1)},     {"viscosity", 3, pi_power(15, 2, -1)},
    {"cubic-spline", 1, pi_power(4, 3, 0)},    {"cubic-spline", 2, pi_power(40, 7, -1)},
    {"cubic-spline", 3, pi_power(8, 1, -1)},   {"box", 1, pi_power(1, 2, 0)},
    {"box", 2, pi_power(1, 1, -1)},            {"box", 3, pi_power(3, 4, -1)},
    {"quartic-spline", 1, pi_power(5, 2, 0)},  {"quartic-spline", 2, pi_power(14400, 1199, -1)},
    {"quartic-spline", 3, pi_power(75, 4, -1)}, {"quintic-spline", 1, pi_power(3, 1, 0)},
    {"quintic-spline", 2, pi_power(3780, 239, -1)}, {"quintic-spline", 3, pi_power(27, 1, -1)},
};

Q omega_rational(int D) { return D == 3 ? Q(4) : Q(2); }
int omega_pi(int D) { return D == 1 ? 0 : 1; }

TEST(Classic, NormalisationsDerivedHere) {
    for (const auto& e : expected) {
        const Q integral = integrate(shapes.at(e.spec), e.D - 1);
        EXPECT_EQ(Exact::pi_power(Q(1) / (omega_rational(e.D) * integral), -omega_pi(e.D)), e.N)
            << e.spec << " in D = " << e.D << ": hand value disagrees with integration here";
    }
}

TEST(Classic, GeneratorNormalisations) {
    for (const auto& e : expected) {
        const ExactKernel k = kernel(e.spec, e.D);
        EXPECT_EQ(k.normalisation, e.N) << e.spec << " in D = " << e.D << ": " << k.normalisation.to_string();
        EXPECT_EQ(radial_moment(k, 0), Exact(Q(1))) << e.spec << " in D = " << e.D;
        // W = N * shape, with the shape's value at 0 (finite except viscosity).
        if (std::string(e.spec) != "viscosity") {
            const auto& first = shapes.at(e.spec).front().c;
            EXPECT_EQ(k.W.at(Q(0)), e.N * first.at(0)) << e.spec << " in D = " << e.D;
        }
    }
}

// The comparison can fail: mistyped constants are not equal.
TEST(Classic, MistypedConstantsAreRejected) {
    EXPECT_NE(kernel("poly6", 3).normalisation, pi_power(315, 46, -1));
    EXPECT_NE(kernel("poly6", 3).normalisation, pi_power(315, 64, 0));  // pi dropped
    EXPECT_NE(kernel("box", 3).normalisation, pi_power(3, 359, -1));
    EXPECT_NE(kernel("cubic-spline", 2).normalisation, pi_power(10, 7, -1));  // 3D-style "10/(7 pi)"
    EXPECT_NE(kernel("viscosity", 2).normalisation, pi_power(15, 2, -1));  // the 3D value in 2D
    EXPECT_NE(kernel("spiky", 1).normalisation, Exact(Q(2) + pow(Q(10), -30)));
    // PySPH's 3D quintic 3/(359 pi) (pypr/pysph, fixed in 4f733660) for 1/(120 pi), scaled alike
    EXPECT_NE(kernel("quintic-spline", 3).normalisation, pi_power(3 * 27 * 120, 359, -1));
    EXPECT_NE(kernel("quartic-spline", 2).normalisation, pi_power(14400, 1119, -1));
}

// The shapes, piece by piece, against the definitions above.
TEST(Classic, Shapes) {
    for (const auto& [name, pieces] : shapes) {
        const Radial shape = kernel(name, 3).shape;
        ASSERT_EQ(shape.pieces.size(), pieces.size()) << name;
        EXPECT_TRUE(shape.outside.is_zero()) << name;
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            Laurent want;
            for (const auto& [n, c] : pieces[i].c) want += Laurent::monomial(c, n);
            EXPECT_EQ(shape.breaks[i], pieces[i].a) << name;
            EXPECT_EQ(shape.breaks[i + 1], pieces[i].b) << name;
            EXPECT_TRUE(shape.pieces[i] == ClosedForm(want)) << name << ", piece " << i;
        }
    }
    // The cubic spline is C^2 at r = 1/2 and its third derivative jumps:
    // inner 1 - 6r^2 + 6r^3: values 1/4, -3/2, 6, 36; outer 2(1-r)^3: 1/4, -3/2, 6, -12.
    const Radial cs = kernel("cubic-spline", 1).shape;
    const Q want[4][2] = {{Q(1, 4), Q(1, 4)}, {Q(-3, 2), Q(-3, 2)}, {Q(6), Q(6)}, {Q(36), Q(-12)}};
    Radial d = cs;
    for (int n = 0; n < 4; ++n) {
        EXPECT_EQ(d.pieces[0].at(Q(1, 2)), Exact(want[n][0])) << "derivative " << n;
        EXPECT_EQ(d.pieces[1].at(Q(1, 2)), Exact(want[n][1])) << "derivative " << n;
        d = d.derivative();
    }
}

TEST(Classic, Claims) {
    for (const char* c : {"poly6", "spiky", "viscosity", "cubic-spline"}) EXPECT_EQ(kernel(c, 3).claims.smoothness, 2) << c;
    EXPECT_EQ(kernel("quartic-spline", 3).claims.smoothness, 3);  // M_n is C^(n-2)
    EXPECT_EQ(kernel("quintic-spline", 3).claims.smoothness, 4);
    EXPECT_EQ(kernel("box", 2).claims.smoothness, -1);
    EXPECT_EQ(kernel("box-d1", 1).claims.smoothness, -1);
    EXPECT_EQ(kernel("box-d2", 1).claims.smoothness, -1);
    EXPECT_FALSE(kernel("box-d1", 1).claims.no_potential.empty());
    EXPECT_FALSE(kernel("box-d2", 1).claims.no_potential.empty());
    EXPECT_TRUE(kernel("cubic-spline", 2).claims.no_potential.empty());
}

// Belley 2007 (seed 002) (16): delta' = 1/h^2 on [-h, 0], -1/h^2 on (0, h]; with
// h = 1, W(x) = -sign(x), and (17) at x_0 = 0 reads int x delta'(-x) dx = 1, i.e.
// int x W(x) dx = -1 (f * W ~ f'). By hand: int_{-1}^1 x (-sign x) dx = -2 int_0^1 x = -1.
TEST(Classic, BelleyFirstDerivative) {
    const ExactKernel k = kernel("box-d1", 1);
    EXPECT_EQ(k.normalised_by, Normalisation::first_derivative);
    EXPECT_EQ(k.W.parity, -1);
    EXPECT_EQ(k.W.at(Q(1, 2)), Exact(Q(-1)));
    EXPECT_EQ(k.normalisation, Exact(Q(1)));
    // The odd extension: int_R x W = 2 int_0^1 r W(r) dr.
    EXPECT_EQ(radial_integral(k.W, 1) * Q(2), Exact(Q(-1)));
    // Perturbed: twice the kernel gives -2.
    EXPECT_NE(radial_integral(k.W * Exact(Q(2)), 1) * Q(2), Exact(Q(-1)));
}

// Belley (20): delta'' = 4/h^3 for h/2 < |x| < h, -4/h^3 for |x| < h/2. With h = 1:
// mass 2 (-4 * 1/2 + 4 * 1/2) = 0 and int x^2 W = 2 (-4/24 + 4 (1/3 - 1/24)) = 2 (-1/6 + 7/6) = 2.
TEST(Classic, BelleySecondDerivative) {
    const ExactKernel k = kernel("box-d2", 1);
    EXPECT_EQ(k.normalised_by, Normalisation::second_derivative);
    EXPECT_EQ(k.normalisation, Exact(Q(4)));
    EXPECT_EQ(k.W.breaks, (std::vector<Q>{Q(0), Q(1, 2), Q(1)}));
    EXPECT_EQ(k.W.at(Q(1, 4)), Exact(Q(-4)));
    EXPECT_EQ(k.W.at(Q(3, 4)), Exact(Q(4)));
    EXPECT_EQ(k.W.parity, 1);
    EXPECT_TRUE(radial_integral(k.W, 0).is_zero());
    EXPECT_EQ(radial_integral(k.W, 2) * Q(2), Exact(Q(2)));
    // int x^3 W = 0 by symmetry; int x^4 W = 2 (-4/160 + 4 (1/5 - 1/160)) = 3/2, the h^2 term of
    // Belley's fifth condition 12 x_0^2 + 3h^2/2 at x_0 = 0.
    EXPECT_EQ(radial_integral(k.W, 4) * Q(2), Exact(Q(3, 2)));
    // Perturbed: moving the breakpoint breaks the zero mass.
    Radial moved = k.W;
    moved.breaks[1] = Q(2, 5);
    EXPECT_FALSE(radial_integral(moved, 0).is_zero());
}

void expect_error_mentioning(const std::string& spec, int dim, const std::string& needle) {
    try {
        kernel(spec, dim);
        ADD_FAILURE() << spec << " in D = " << dim << " did not throw";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

TEST(Classic, UndefinedDimensionsThrow) {
    // viscosity's 1/(2r) term is not integrable against r^0 dr on [0, 1].
    expect_error_mentioning("viscosity", 1, "dimension 1");
    for (int D : {2, 3}) {
        expect_error_mentioning("box-d1", D, "dimension " + std::to_string(D));
        expect_error_mentioning("box-d2", D, "dimension " + std::to_string(D));
    }
    for (const char* c : {"poly6", "box", "cubic-spline"}) {
        EXPECT_THROW(kernel(c, 0), Error);
        EXPECT_THROW(kernel(c, 4), Error);
    }
    EXPECT_NO_THROW(kernel("box-d1", 1));
    EXPECT_NO_THROW(kernel("viscosity", 2));
}

}  // namespace
}  // namespace mollify::gen
