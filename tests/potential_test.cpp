// Poisson potentials (potential.hpp): Delta phi = W in R^D, phi equal to the
// free-space Green's function outside the support (3D -1/(4 pi r), 2D
// log(r)/(2 pi), 1D |r|/2) and continuous with it, with phi' too.
//
// References: Anderson's §4 (seed 000) series, re-derived below; the cubic
// spline's 2D potential derived by hand; for the whole catalogue the defining
// properties themselves (Laplacian and continuity), which determine phi.
#include "catalogue.hpp"
#include "error.hpp"
#include "kernel.hpp"
#include "potential.hpp"
#include "quantities.hpp"
#include "spec.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace mollify::gen {
namespace {

ExactKernel kernel(const std::string& spec, int dim) { return make_kernel(parse_spec(spec), dim); }

// Which kernels must have a Poisson potential, by a rule on the kernel's
// normalisation, not on the generator's no_potential claim: phi equals the Green's function outside the support, so
// Gauss's law omega_D phi'(1) = int W needs unit mass. The kernels normalised
// otherwise (Belley's derivative estimators box-d1, box-d2: zero mass) have
// none; every unit-mass kernel must have one.
bool expects_potential(const ExactKernel& k) { return k.normalised_by == Normalisation::unit_mass; }

Z choose(int n, int k) {
    Z b = 1;
    for (int i = 1; i <= k; ++i) b = b * (n - k + i) / i;
    return b;
}

// Green's function value at r = 1: 1D 1/2, 2D log(1)/(2 pi) = 0, 3D -1/(4 pi).
Exact green_at_one(int D) {
    switch (D) {
        case 1: return Exact(Q(1, 2));
        case 2: return Exact();
        default: return Exact::pi_power(Q(-1, 4), -1);
    }
}

// Green's function derivative at r = 1: 1/omega_D (Gauss: omega_D r^(D-1) G' = 1).
Exact green_slope_at_one(int D) {
    switch (D) {
        case 1: return Exact(Q(1, 2));
        case 2: return Exact::pi_power(Q(1, 2), -1);
        default: return Exact::pi_power(Q(1, 4), -1);
    }
}

// Left and right limits of f at breakpoint i (right: the next piece, or the
// exterior); value_at takes the limit at r = 1 for the sqrt/arcsech/arcsin
// forms of the missing Wendland functions.
Exact left_at(const Radial& f, std::size_t i) { return value_at(f.pieces[i - 1], f.breaks[i]); }
Exact right_at(const Radial& f, std::size_t i) {
    return value_at(i + 1 < f.breaks.size() ? f.pieces[i] : f.outside, f.breaks[i]);
}

// Empty when phi and phi' are continuous at every breakpoint (r = 1 included).
std::string discontinuities(const Radial& phi) {
    std::string out;
    Radial d = phi;
    for (int n = 0; n <= 1; ++n) {
        for (std::size_t i = 1; i < d.breaks.size(); ++i) {
            const Exact l = left_at(d, i), r = right_at(d, i);
            if (!(l == r))
                out += (n ? "phi'" : "phi") + std::string(" jumps at r = ") + short_string(d.breaks[i]) + ": " +
                       l.to_string() + " vs " + r.to_string() + "; ";
        }
        d = d.derivative();
    }
    return out;
}

// (a) Anderson §4. In D dimensions, Delta r^(2j) = (2j)(2j + D - 2) r^(2j-2): (2j)^2 in 2D,
// (2j)(2j+1) in 3D. Since (1-r^2)^M = sum_{k=0}^M (-1)^k binom(M,k) r^(2k), the term k is
// matched by j = k+1:
//   v_2 = sum_{j=1}^{M+1} (-1)^(j-1) binom(M, j-1) / (2j)^2       r^(2j)     (13)
//   v_3 = sum_{j=1}^{M+1} (-1)^(j-1) binom(M, j-1) / ((2j)(2j+1)) r^(2j)     (14)
// solve Delta v = (1-r^2)^M; phi = N v + c with the constant fixed by phi(1) = G(1).
Laurent anderson_series(int M, int D) {
    Laurent v;
    for (int j = 1; j <= M + 1; ++j) {
        const Q sign = (j - 1) % 2 == 0 ? Q(1) : Q(-1);
        v += Laurent::monomial(sign * Q(choose(M, j - 1)) / Q((2 * j) * (2 * j + D - 2)), 2 * j);
    }
    return v;
}

TEST(Potential, AndersonSeriesSolvesThePoissonEquation) {
    // The derivation itself, with coefficients checked here: sum_j a_j (2j)(2j+D-2) r^(2j-2)
    // equals (1-r^2)^M coefficient by coefficient.
    for (int D = 2; D <= 3; ++D)
        for (int M = 1; M <= 9; ++M) {
            const Laurent v = anderson_series(M, D);
            for (int k = 0; k <= M; ++k) {
                const int j = k + 1;
                const Q sign = k % 2 == 0 ? Q(1) : Q(-1);
                EXPECT_EQ(v.coefficient(2 * j) * (2 * j) * (2 * j + D - 2), sign * Q(choose(M, k)));
            }
        }
}

TEST(Potential, AndersonInnerPotential) {
    for (int D = 2; D <= 3; ++D)
        for (int M = 1; M <= 9; ++M) {
            SCOPED_TRACE("M = " + std::to_string(M) + ", D = " + std::to_string(D));
            const ExactKernel k = kernel("mollifier:M=" + std::to_string(M), D);
            const Radial phi = potential(k.W, D);
            ASSERT_EQ(phi.pieces.size(), 1u);
            const Laurent v = anderson_series(M, D);
            // phi_in = N (v - v(1)) + G(1): Anderson's c_0 makes v(1) = 0 (Table 2), then
            // 2D: phi(1) = log(1)/(2 pi) = 0; 3D: phi(1) = -1/(4 pi).
            const ClosedForm want = ClosedForm(v - Laurent(v(Q(1)))) * k.normalisation + ClosedForm::constant(green_at_one(D));
            EXPECT_TRUE(phi.pieces[0] == want);
            // phi - N v is a constant (the derivative of the difference vanishes).
            EXPECT_TRUE((phi.pieces[0] - ClosedForm(v) * k.normalisation).derivative().is_zero());
            EXPECT_TRUE(phi.outside == green_function(D));
            EXPECT_EQ(discontinuities(phi), "");
        }
}

// Anderson App. B, M = 4 (delta = 1, so log(delta) = 0):
//   2D: phi = 10/(2 pi) [-137/1200 + r^2/4 - r^4/4 + r^6/6 - r^8/16 + r^10/100]
//   3D: phi = 3465/128 / (4 pi) [-437/6930 + r^2/6 - r^4/5 + r^6/7 - r^8/18 + r^10/110] - 1/(4 pi)
// The brackets are (13)/(14) with M = 4 (j = 1..5: binom(4, j-1) = 1, 4, 6, 4, 1 over
// (2j)^2 = 4, 16, 36, 64, 100 or (2j)(2j+1) = 6, 20, 42, 72, 110), and the constants make
// them vanish at 1: 1/4 - 1/4 + 1/6 - 1/16 + 1/100 = 137/1200 and
// 1/6 - 1/5 + 1/7 - 1/18 + 1/110 = 437/6930. App. B prints the 3D constant as
// "+ 1/(4 pi delta)": with the bracket zero at r = 1 that would give phi(1) = +1/(4 pi),
// not G(1) = -1/(4 pi); §4 has the correct -1/(4 pi).
// Fourth order (App. B): -60/(2 pi) [23/800 - r^2/10 + 3r^4/16 - 2r^6/9 + 5r^8/32 - 3r^10/50
// + 7r^12/720] in 2D; -45045/256/(4 pi) [6961/360360 - r^2/12 + 7r^4/40 - 3r^6/14 + 11r^8/72
// - 13r^10/220 + r^12/104] - 1/(4 pi) in 3D. Derivation: for W = g/omega (t^4 + a t^5),
// t = 1 - r^2 = sum of r^(2k) terms, each r^(2k) integrates to r^(2k+2)/((2k+2)(2k+D)); e.g. in
// 2D t^4 - 7/5 t^5 = -2/5 + 3r^2 - 8r^4 + 10r^6 - 6r^8 + 7/5 r^10, so the bracket's r^2
// coefficient is -(2/5)/4 = -1/10, r^4: 3/16, r^6: -8/36 = -2/9, r^8: 10/64 = 5/32,
// r^10: -6/100 = -3/50, r^12: (7/5)/144 = 7/720 (all as printed), constant = minus their sum.
Laurent even(std::initializer_list<Q> c) {  // c_0 + c_1 r^2 + c_2 r^4 + ...
    Laurent p;
    int n = 0;
    for (const Q& x : c) p += Laurent::monomial(x, 2 * n++);
    return p;
}

TEST(Potential, AndersonAppendixB) {
    const Exact inv2pi = Exact::pi_power(Q(1, 2), -1), inv4pi = Exact::pi_power(Q(1, 4), -1);
    const Laurent b2 = even({Q(-137, 1200), Q(1, 4), Q(-1, 4), Q(1, 6), Q(-1, 16), Q(1, 100)});
    const Laurent b3 = even({Q(-437, 6930), Q(1, 6), Q(-1, 5), Q(1, 7), Q(-1, 18), Q(1, 110)});
    const Radial p2 = potential(kernel("mollifier:M=4", 2).W, 2);
    const Radial p3 = potential(kernel("mollifier:M=4", 3).W, 3);
    EXPECT_TRUE(p2.pieces[0] == ClosedForm(b2) * (inv2pi * Q(10)));
    EXPECT_TRUE(p3.pieces[0] == ClosedForm(b3) * (inv4pi * Q(3465, 128)) - ClosedForm::constant(inv4pi));
    // The printed "+ 1/(4 pi)" is detected.
    EXPECT_FALSE(p3.pieces[0] == ClosedForm(b3) * (inv4pi * Q(3465, 128)) + ClosedForm::constant(inv4pi));

    const Laurent f2 = even({Q(23, 800), Q(-1, 10), Q(3, 16), Q(-2, 9), Q(5, 32), Q(-3, 50), Q(7, 720)});
    const Laurent f3 = even({Q(6961, 360360), Q(-1, 12), Q(7, 40), Q(-3, 14), Q(11, 72), Q(-13, 220), Q(1, 104)});
    const Radial q2 = potential(kernel("mollifier:M=4,order=4", 2).W, 2);
    const Radial q3 = potential(kernel("mollifier:M=4,order=4", 3).W, 3);
    EXPECT_TRUE(q2.pieces[0] == ClosedForm(f2) * (inv2pi * Q(-60)));
    EXPECT_TRUE(q3.pieces[0] == ClosedForm(f3) * (inv4pi * Q(-45045, 256)) - ClosedForm::constant(inv4pi));
    // A perturbed coefficient is detected.
    const Laurent g2 = even({Q(23, 800), Q(-1, 10), Q(3, 16), Q(-2, 9), Q(5, 32), Q(-3, 50), Q(7, 72)});
    EXPECT_FALSE(q2.pieces[0] == ClosedForm(g2) * (inv2pi * Q(-60)));
}

// (b) The whole catalogue: Delta phi = W identically (every piece and outside), phi
// equals the Green's function outside, and phi, phi' are continuous at every
// breakpoint and at r = 1 (so the flux omega_D phi'(1) equals the unit mass).
TEST(Potential, CatalogueLaplacianAndContinuity) {
    int checked = 0;
    std::vector<std::string> without;
    for (const CatalogueEntry& e : expand_dimensions(default_specs())) {
        const ExactKernel k = make_kernel(e.spec, e.dim);
        const std::string what = spec_string(e.spec) + " in D = " + std::to_string(e.dim);
        ASSERT_EQ(k.claims.no_potential.empty(), expects_potential(k))
            << what << (expects_potential(k) ? ": unit mass but no potential: " + k.claims.no_potential
                                             : ": not unit mass but claims a potential");
        if (!expects_potential(k)) {
            without.push_back(what);
            continue;
        }
        const Radial phi = potential(k.W, e.dim);
        EXPECT_TRUE(radial_laplacian(phi, e.dim) == k.W) << what;
        EXPECT_TRUE(phi.outside == green_function(e.dim)) << what;
        EXPECT_EQ(discontinuities(phi), "") << what;
        EXPECT_EQ(value_at(phi.pieces.back(), Q(1)), green_at_one(e.dim)) << what;
        EXPECT_EQ(value_at(phi.pieces.back().derivative(), Q(1)), green_slope_at_one(e.dim)) << what;
        ++checked;
    }
    // Everything but Belley's derivative kernels (box-d1, box-d2, 1D only).
    EXPECT_EQ(without, (std::vector<std::string>{"box-d1 in D = 1", "box-d2 in D = 1"}));
    EXPECT_EQ(checked, static_cast<int>(expand_dimensions(default_specs()).size()) - 2);
}

// A kernel without a potential says why when the potential is asked for.
TEST(Potential, ZeroMassKernelsNameWhyThereIsNone) {
    for (const char* spec : {"box-d1", "box-d2"}) {
        const ExactKernel k = kernel(spec, 1);
        const Quantities q = derive_quantities(k);
        EXPECT_FALSE(q.potential.has_value()) << spec;
        try {
            (void)quantity(k, q, "potential");
            ADD_FAILURE() << spec << ": quantity potential did not throw";
        } catch (const Error& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find(spec), std::string::npos) << m;
            EXPECT_NE(m.find("no Poisson potential"), std::string::npos) << m;
        }
    }
}

// Missing Wendland functions (sqrt/arcsech closed forms; their potentials need
// arcsin as well): the same defining properties, with one-sided values taken as
// limits (value_at). Delta phi = W on (0, 1) together with phi(1) = G(1) and
// phi'(1) = G'(1) determines phi (a second-order ODE with initial data at 1).
TEST(Potential, MissingWendland) {
    int checked = 0;
    for (int D = 1; D <= 3; ++D)
        for (int k = 0; k <= 2; ++k)
            for (int l = 0; l <= 2; ++l) {
                const std::string spec = "wendland-missing:k=" + std::to_string(k) + ",l=" + std::to_string(l);
                const ExactKernel K = kernel(spec, D);
                const std::string what = spec + " in D = " + std::to_string(D);
                ASSERT_TRUE(expects_potential(K)) << what;
                ASSERT_EQ(K.claims.no_potential, "") << what;
                const Radial phi = potential(K.W, D);
                ASSERT_EQ(phi.pieces.size(), 1u) << what;
                EXPECT_TRUE(radial_laplacian(phi, D) == K.W) << what;
                EXPECT_TRUE(phi.outside == green_function(D)) << what;
                EXPECT_EQ(value_at(phi.pieces[0], Q(1)), green_at_one(D)) << what;
                EXPECT_EQ(value_at(phi.pieces[0].derivative(), Q(1)), green_slope_at_one(D)) << what;
                ++checked;
            }
    EXPECT_EQ(checked, 3 * 3 * 3);
    // A perturbed mass is detected here too.
    const ExactKernel K = kernel("wendland-missing:k=1,l=1", 3);
    const Radial phi = potential(K.W * Exact(Q(1001, 1000)), 3);
    EXPECT_NE(value_at(phi.pieces[0].derivative(), Q(1)), green_slope_at_one(3));
}

// phi(0) for the missing Wendland functions, derived independently. With
// phi' = r^(1-D) int_0^r t^(D-1) W dt and phi(1) = G(1),
//   phi(0) = G(1) - int_0^1 phi' = G(1) - int_0^1 t^(D-1) W(t) int_t^1 s^(1-D) ds dt,
// i.e. G(1) - int (1 - t) W in 1D and G(1) - int (t - t^2) W in 3D. For
// psi(t) = int_t^1 s g(s)/sqrt(s^2 - t^2) ds (the generator's convention, see
// wendland_test), Fubini and t = s u give int_0^1 t^p psi = c_p int_0^1 s^(p+1) g,
// c_p = int_0^1 u^p/sqrt(1-u^2) du = pi/2, 1, pi/4 for p = 0, 1, 2. With the unit-mass
// N = 1/(pi G_1) in 1D and 1/(pi^2 G_3) in 3D (G_p = int s^p g):
//   1D: phi(0) = 1/2 - N (pi/2 G_1 - G_2) = G_2/(pi G_1),
//   3D: phi(0) = -1/(4 pi) - N (G_2 - pi/4 G_3) = -G_2/(pi^2 G_3).
// In 2D, int_t^1 ds/s = -log t and the inner integral becomes
// int_0^s t (-log t)/sqrt(s^2 - t^2) dt = s (-log s) + s (1 - log 2), using
// int_0^1 u (-log u)/sqrt(1-u^2) du = 1 - log 2; with int_0^1 s^n (-log s) ds = 1/(n+1)^2
// and N = 1/(2 pi G_2):
//   2D: phi(0) = 0 - N (H + (1 - log 2) G_2) = -H/(2 pi G_2) - (1 - log 2)/(2 pi),
// H = sum_i g_i/(i+3)^2 (g = sum_i g_i s^i).
using Poly = std::vector<Q>;

Q integral01(const Poly& p, int power) {
    Q s = 0;
    for (std::size_t i = 0; i < p.size(); ++i) s += p[i] / (static_cast<int>(i) + power + 1);
    return s;
}

// g = I^k (1-s)^n with I f(r) = int_r^1 s f(s) ds, on coefficient vectors.
Poly wendland_inner(int n, int k) {
    Poly f{Q(1)};
    for (int i = 0; i < n; ++i) {
        Poly g(f.size() + 1, Q(0));
        for (std::size_t j = 0; j < f.size(); ++j) {
            g[j] += f[j];
            g[j + 1] -= f[j];
        }
        f = g;
    }
    for (int i = 0; i < k; ++i) {
        Poly F(f.size() + 2, Q(0));
        for (std::size_t j = 0; j < f.size(); ++j) F[j + 2] = f[j] / (static_cast<int>(j) + 2);
        Q F1 = 0;
        for (const Q& c : F) F1 += c;
        for (Q& c : F) c = -c;
        F[0] += F1;
        f = F;
    }
    return f;
}

TEST(Potential, MissingWendlandValueAtZero) {
    for (int D = 1; D <= 3; ++D)
        for (int k = 0; k <= 2; ++k)
            for (int l = 0; l <= 2; ++l) {
                const std::string spec = "wendland-missing:k=" + std::to_string(k) + ",l=" + std::to_string(l);
                const ExactKernel K = kernel(spec, D);
                ASSERT_EQ(K.claims.no_potential, "") << spec << " in D = " << D << " has unit mass";
                const Poly g = wendland_inner((D + 1) / 2 + k + 1 + l, k);
                Exact want;
                if (D == 1) want = Exact::pi_power(integral01(g, 2) / integral01(g, 1), -1);
                if (D == 3) want = Exact::pi_power(-integral01(g, 2) / integral01(g, 3), -2);
                if (D == 2) {
                    Q H = 0;
                    for (std::size_t i = 0; i < g.size(); ++i) H += g[i] / Q((i + 3) * (i + 3));
                    want = Exact::pi_power(-H / (2 * integral01(g, 2)) - Q(1, 2), -1) +
                           Exact::log_of(Q(2)) * Exact::pi_power(Q(1, 2), -1);
                }
                const Radial phi = potential(K.W, D);
                EXPECT_EQ(value_at(phi.pieces[0], Q(0)), want)
                    << spec << " in D = " << D << ": " << value_at(phi.pieces[0], Q(0)).to_string() << " vs "
                    << want.to_string();
            }
    // The reference can fail: phi(0) of the l = 0 kernel is not that of l = 1.
    const Poly g = wendland_inner(2 + 1 + 1 + 1, 1);
    EXPECT_NE(value_at(potential(kernel("wendland-missing:k=1", 3).W, 3).pieces[0], Q(0)),
              Exact::pi_power(-integral01(g, 2) / integral01(g, 3), -2));
}

// The Green's functions themselves: G'' + (D-1)/r G' = 0 for r > 0, and the flux
// omega_D r^(D-1) G'(r) = 1 (checked at r = 1 and 3).
TEST(Potential, GreenFunctions) {
    const Exact omega[] = {Exact(Q(2)), Exact::pi_power(Q(2), 1), Exact::pi_power(Q(4), 1)};
    for (int D = 1; D <= 3; ++D) {
        const ClosedForm G = green_function(D);
        const ClosedForm d1 = G.derivative();
        EXPECT_TRUE((d1.derivative() + d1 * Laurent::monomial(Q(D - 1), -1)).is_zero()) << "D = " << D;
        for (const Q& r : {Q(1), Q(3)}) {
            Q rpow = 1;
            for (int i = 1; i < D; ++i) rpow *= r;
            EXPECT_EQ(d1.at(r) * omega[D - 1] * rpow, Exact(Q(1))) << "D = " << D;
        }
        EXPECT_EQ(G.at(Q(1)), green_at_one(D));
    }
}

// (c) Cubic spline in 2D, N = 40/(7 pi). Gauss: phi'(r) = m(r)/r with m(r) = int_0^r s W(s) ds.
// Inner piece: m = N (r^2/2 - 3r^4/2 + 6r^5/5). Outer piece: with P(r) = r^2 - 2r^3 + 3r^4/2 - 2r^5/5
// (the antiderivative of 2s(1-s)^3 vanishing at 0), m = N (11/160 + P(r) - P(1/2)) and
// P(1/2) = 13/160, so m has the constant N (11 - 13)/160 = -1/(14 pi): phi_out contains
// -log(r)/(14 pi). Integrating and fixing phi_out(1) = 0:
//   phi_out = (600 r^2 - 800 r^3 + 450 r^4 - 96 r^5 - 154)/(210 pi) - log(r)/(14 pi),
// and continuity at 1/2 (log(1/2) = -log 2) gives
//   phi_in = 10 r^2/(7 pi) - 15 r^4/(7 pi) + 48 r^5/(35 pi) - 77/(120 pi) + log(2)/(14 pi).
TEST(Potential, CubicSpline2DHasLogTwo) {
    const Radial phi = potential(kernel("cubic-spline", 2).W, 2);
    ASSERT_EQ(phi.breaks, (std::vector<Q>{Q(0), Q(1, 2), Q(1)}));
    const Exact inv_pi = Exact::pi_power(Q(1), -1);
    const ClosedForm inner = ClosedForm(Laurent::monomial(Q(10, 7), 2) + Laurent::monomial(Q(-15, 7), 4) +
                                        Laurent::monomial(Q(48, 35), 5) + Laurent(Q(-77, 120))) *
                                 inv_pi +
                             ClosedForm::constant(Exact::log_of(Q(2)) * Exact::pi_power(Q(1, 14), -1));
    const ClosedForm outer =
        ClosedForm(Laurent::monomial(Q(600), 2) + Laurent::monomial(Q(-800), 3) + Laurent::monomial(Q(450), 4) +
                   Laurent::monomial(Q(-96), 5) + Laurent(Q(-154))) *
            Exact::pi_power(Q(1, 210), -1) +
        ClosedForm(Laurent(Q(-1, 14)), TermKey{Basis::log, 0, Atom{-1, 1}});
    EXPECT_TRUE(phi.pieces[0] == inner);
    EXPECT_TRUE(phi.pieces[1] == outer);
    // The log 2 constant, explicitly: phi(0) = -77/(120 pi) + log(2)/(14 pi).
    const Exact at0 = phi.pieces[0].at(Q(0));
    ASSERT_EQ(at0.terms().count(Atom{-1, 2}), 1u) << at0.to_string();
    EXPECT_EQ(at0.terms().at(Atom{-1, 2}), Q(1, 14));
    EXPECT_EQ(discontinuities(phi), "");
    EXPECT_TRUE(radial_laplacian(phi, 2) == kernel("cubic-spline", 2).W);
    // A wrong log coefficient is detected.
    EXPECT_FALSE(phi.pieces[0] == inner + ClosedForm::constant(Exact::log_of(Q(2)) * Exact::pi_power(Q(1, 1000), -1)));
    // In 3D phi' = m(r)/r^2, whose constant part integrates to a multiple of 1/r: no logarithms.
    const Radial phi3 = potential(kernel("cubic-spline", 3).W, 3);
    for (const ClosedForm& f : phi3.pieces)
        for (const auto& [key, p] : f.terms()) {
            EXPECT_EQ(key.basis, Basis::one);
            EXPECT_EQ(key.factor.log_of, 1);
        }
    EXPECT_EQ(discontinuities(phi3), "");
}

// (d) The checks can fail: W + 1/1000 on [0, 1] has mass 1 + omega_D/(1000 D). Its potential
// still satisfies Delta phi = W + 1/1000 (the construction integrates whatever it is given) and is
// continuous at r = 1 by construction, but phi'(1) = mass/omega_D no longer matches G'(1).
TEST(Potential, PerturbedKernelBreaksSlopeContinuity) {
    for (const char* spec : {"mollifier:M=4", "wendland:k=2", "cubic-spline"})
        for (int D = 1; D <= 3; ++D) {
            const std::string what = std::string(spec) + " in D = " + std::to_string(D);
            const ExactKernel k = kernel(spec, D);
            const Radial W = k.W + Radial::single(ClosedForm(Laurent(Q(1, 1000))));
            const Radial phi = potential(W, D);
            EXPECT_TRUE(radial_laplacian(phi, D) == W) << what;
            EXPECT_FALSE(radial_laplacian(phi, D) == k.W) << what;
            EXPECT_EQ(phi.pieces.back().at(Q(1)), green_at_one(D)) << what;
            EXPECT_NE(phi.pieces.back().derivative().at(Q(1)), green_slope_at_one(D)) << what;
            EXPECT_NE(discontinuities(phi), "") << what;
        }
}

}  // namespace
}  // namespace mollify::gen
