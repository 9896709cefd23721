// --target swift: drop-in replacements of SWIFT's src/kernel_hydro.h and
// (3D, kernels with a potential) src/kernel_gravity.h, one pair per kernel
// and dimension, swift/<id>/ (../shared/peers.md, "SWIFT": u = r/h, support
// H = gamma h, x = u/gamma, W(u) = C gamma^-d w(x), dW/du = C gamma^-(d+1)
// w'(x), float; gravity: u = r/H, kernel_grav_pot_eval = H phi/m,
// kernel_grav_force_eval = (1/u) d/du of it, D_soft_1 = -W_pot,
// D_soft_(n+1) = D_soft_n' - (n-1) D_soft_n/u).
//
// The kernel. mollify's W_1 (unit mass, support 1) is C w with w(0) = 1, so
// C = W_1(0) (conventions.hpp's separate_normalisation) and SWIFT's
// W(u) = gamma^-d W_1(u/gamma): the functions evaluate x = u/gamma in
// double and mollify's factored tables of W_1 and W_1' (Precision::fast:
// Horner times powers of the edge distance 1 - x, pieces) in double, and
// round once to float. gamma = H/(2 sigma) from the exact second moment
// (conventions.hpp's swift_gamma); every power of gamma SWIFT's sources use
// is the correctly rounded square root of an exact rational.
//
// Softening. mollify's potential phi_1 (Delta phi_1 = W_1, -1/(4 pi r)
// outside) on SWIFT's H = 1: W_pot = 4 pi phi_1 (-1/u outside), W_f =
// 4 pi phi_1'/u, D_soft_n = E_(n-1) (softening.hpp's multipole factors), for
// the orders certified_softening certifies and that are finite at u = 0.
// H in units of the Plummer softening: the potential at r = 0 equal to
// Plummer's, -m W_pot(0)/H = -m/eps, so H = -W_pot(0) eps (SWIFT's Wendland
// C2: 3, GADGET-2's cubic spline: 2.8), exact.
#include "c_code.hpp"
#include "target.hpp"
#include "target_code.hpp"

#include "emit_round.hpp"
#include "error.hpp"
#include "kernel_sign.hpp"
#include "rounding.hpp"
#include "softening.hpp"
#include "softening_certificate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace mollify::gen {

namespace {

// factor * sqrt(radicand), exactly (factor rational or q pi^e; radicand > 0 rational).
struct SwiftConstant {
    Exact factor;
    Q radicand{1};
    std::string text() const {
        if (radicand == 1) return factor.to_string();
        return (factor.is_rational() && factor.rational() == 1 ? std::string() : "(" + factor.to_string() + ") * ") +
               "sqrt(" + short_string(radicand) + ")";
    }
    // Value and sum of |terms| at `b` bits (a rounding.hpp Evaluator: Ziv's loop).
    std::pair<Real, Real> evaluated(unsigned b) const {
        Real r(0, b);
        mpfr_set_q(r.backend().data(), radicand.backend().data(), MPFR_RNDN);
        const Real s = sqrt(r);
        auto [v, magnitude] = factor.evaluate(b);
        return {v * s, magnitude * s};
    }
    // Correctly rounded: exact decisions where the value is a rational or its
    // square root (conventions.hpp), Ziv's loop with a rigorous error bound
    // where pi enters (rounding.hpp).
    float to_float() const {
        if (factor.is_rational()) {
            const Q f = factor.rational();
            const Q square = f * f * radicand;
            const float m = sqrt_to_float(square);
            return f < 0 ? -m : m;
        }
        return round_to_float([this](unsigned b) { return evaluated(b); });
    }
    double to_double() const {
        if (factor.is_rational()) {
            const Q f = factor.rational();
            const double m = sqrt_to_double(f * f * radicand);
            return f < 0 ? -m : m;
        }
        return round_to_double([this](unsigned b) { return evaluated(b); });
    }
};

// gamma^n = (gamma^2)^(n/2): a rational for even n, else sqrt(gamma^2) times one.
SwiftConstant gamma_power(const Q& g2, int n) {
    const Q base = n >= 0 ? g2 : Q(1) / g2;
    const int m = n >= 0 ? n : -n;
    return {Exact(pow(base, m / 2)), m % 2 ? base : Q(1)};
}

std::string float_literal(float x) {
    char b[64];
    std::snprintf(b, sizeof b, "%af", static_cast<double>(x));
    return b;
}

std::string float_define(const std::string& name, const SwiftConstant& c) {
    return "#define " + name + " ((float)" + float_literal(c.to_float()) + ") /* " + comment_text(c.text()) + " */\n";
}
std::string double_constant(const std::string& name, const SwiftConstant& c) {
    return "static const double " + name + " = " + hex_literal(c.to_double()) + "; /* " + comment_text(c.text()) + " */\n";
}

// The unit sphere's volume in D dimensions (SWIFT's hydro_dimension_unit_sphere): 2, pi, 4 pi/3.
Exact unit_ball_volume(int dim) { return sphere_measure(dim) * Exact(Q(1, dim)); }

// The functions written here that take mollify's functions straight from
// the exact world (gravity, potential_dh) return floats: planned for float
// results (emit_plan.hpp), each polynomial piece one Horner polynomial where
// that is accurate enough, so that SWIFT's gravity pair loop, which inlines
// kernel_grav_pot_eval and kernel_grav_force_eval, still vectorises (with
// the double plan's Taylor sub-pieces it did not: GCC no longer unswitched
// the loop on `periodic`, 2x the stock run's time, stop 90).
// kernel_grav_eval_*_double (SWIFT's force checks) keep the double plan.
// A combination's potential and force take its terms' (`parts`, w_j f_j times
// 4 pi), each factored at its own radius, as the runtime's tables do: planned
// as one merged sum, kernel_grav_eval_*_double of the m = 3 combinations were
// up to ~1e3 double ulps of max(|f|, |u f'|) off (a by-hand sweep, stop 90).
std::vector<RoundedPiece> round_or_fail(const Radial& f, bool potential_like, const std::string& what,
                                        ResultPrecision result = ResultPrecision::float_value,
                                        const std::vector<Radial>& parts = {}) {
    auto r = rounded_quantity(&f, potential_like, parts, result);
    if (!r) fail("internal: --target swift: " + what + " did not round");
    return std::move(*r);
}

// ---- SWIFT's expanded layout, measured (the comment in kernel_hydro.h) ----

float to_float(const Q& q) { return round_to_float(q); }

// One float operation rounded once to float, whatever the compiler's FMA
// contraction: the operation in double, then to float (a double rounding that
// is the correct one for + and *, since 53 >= 2 * 24 + 2; Figueroa 1995).
float f_mul(float a, float b) { return static_cast<float>(static_cast<double>(a) * static_cast<double>(b)); }
float f_add(float a, float b) { return static_cast<float>(static_cast<double>(a) + static_cast<double>(b)); }

// w = W_1/C on the last piece as SWIFT stores it: float monomial coefficients
// (highest first), float Horner at x = 1 - 2^-k; the error in float ulps of
// the exact w(x), exact arithmetic on the rationals.
std::string expanded_layout_loss(const ExactKernel& k) {
    const ClosedForm& last = k.W.pieces.back();
    const ClosedForm& first = k.W.pieces.front();
    Laurent p, p0;
    Atom a, a0;
    if (!last.single_polynomial(&p, &a) || !first.single_polynomial(&p0, &a0) || !p.is_polynomial() || a != a0 ||
        p0(Q(0)) == 0)
        return "   not measured: the last piece is not a polynomial (SWIFT's layout cannot hold it)\n *   -";
    const Q c0 = p0(Q(0));
    std::vector<float> coeffs;
    for (int j = p.high(); j >= 0; --j) coeffs.push_back(to_float(p.coefficient(j) / c0));
    std::string out;
    double worst = 0;
    for (int e : {4, 8, 12, 16, 20, 24}) {
        const float x = 1.0f - std::ldexp(1.0f, -e);
        float y = coeffs.front();
        for (std::size_t j = 1; j < coeffs.size(); ++j) y = f_add(f_mul(y, x), coeffs[j]);
        const Q exact = p(Q(x)) / c0;
        const double ex = static_cast<double>(exact);
        const double ulp = ulp_of_float(ex);
        const double abs_err = std::fabs(static_cast<double>(Q(y) - exact));
        const double err = abs_err / ulp;
        worst = std::max(worst, err);
        char b[160];
        std::snprintf(b, sizeof b, "%s   x = 1 - 2^-%d: %.3g ulp of w(x) (absolute %.3g ulp of w(0) = 1)\n", out.empty() ? "" : " *",
                      e, err, abs_err / std::ldexp(1.0, -23));
        out += b;
    }
    return out + " *   " + (worst > 4 ? "hence the factored form here" : "within a few ulp here; the factored form all the same");
}

// ---- kernel_hydro.h ----

struct SignCheck {
    bool clamp = true;
    std::string note;  // for the file's comment
};

SignCheck check_signs(const KernelFacts& facts, bool allow) {
    const ExactKernel& k = facts.kernel;
    const SignFact w = non_negative(k.W), dw = non_negative(k.W.derivative() * Exact(Q(-1)));
    bool polynomial = true;
    for (const ClosedForm& p : k.W.pieces) polynomial = polynomial && p.has_only_basis_one();
    if (w.verdict == SignVerdict::proved && dw.verdict == SignVerdict::proved)
        return {true, std::string("W >= 0 and dW/du <= 0 on the whole support (proved exactly: ") +
                          (polynomial ? "Bernstein coefficients of every piece"
                                      : "the closed form's series at 0 and in S at the edge, with their truncation bounds, "
                                        "under interval arithmetic with outward rounding (kernel_sign.cpp)") +
                          "), so SWIFT's clamps max(W, 0), min(dW, 0) are kept and change nothing."};
    auto why = [](const SignFact& f, const std::string& what) {
        if (f.verdict == SignVerdict::disproved)
            return what + " fails at x = " + short_string(*f.witness) + " (exactly: " + f.reason + " times a positive constant)";
        return what + " not proved: " + f.reason;
    };
    const std::string reason = w.verdict != SignVerdict::proved ? why(w, "W >= 0") : why(dw, "dW/du <= 0");
    if (!allow)
        fail("--target swift: kernel " + facts.spec + " in D = " + std::to_string(k.dim) + ": " + reason +
             "; SWIFT's kernel_deval clamps W >= 0 and dW/du <= 0, which " +
             (w.verdict == SignVerdict::disproved || dw.verdict == SignVerdict::disproved ? "would change this kernel"
                                                                                          : "might change this kernel") +
             ". "
             "Pass --allow-negative-lobes to write it without the clamps");
    return {false, "--allow-negative-lobes: " + reason +
                       ". The clamps of SWIFT's stock kernel_deval (W >= 0, dW/du <= 0) are DROPPED: W and dW are the "
                       "kernel's own values, negative lobes included (SWIFT's tests/testKernel.c, which checks W >= 0 "
                       "and dW <= 0, fails for such a kernel)."};
}

// SWIFT's h = 2 sigma needs a positive second moment. A higher-order kernel
// (a combination W = sum_j w_j psi_(a_j), Franz (4.17), moments r^2.. zero)
// has none; it takes its base kernel psi's gamma (both have support 1: the
// combination resolves as its base does), written with --allow-negative-lobes
// only (such kernels are not non-negative); any other kernel without one is
// an Error naming it.
DerivedConstant gamma_of(const ExactKernel& k) {
    if (variance(k) > 0) return swift_gamma(k);
    if (!k.base)
        fail("--target swift: kernel " + spec_string(k.spec) + " in D = " + std::to_string(k.dim) +
             " has second moment 0 (a higher-order kernel): SWIFT's h = 2 sigma, kernel_gamma = H/(2 sigma) is undefined "
             "and it has no base kernel to take gamma from");
    DerivedConstant g = swift_gamma(*k.base);
    g.rule = "the kernel's second moment is 0 (a higher-order combination), so gamma is its base kernel " +
             spec_string(k.base->spec) + "'s: " + g.rule;
    return g;
}

// SWIFT's SIMD kernel functions (src/kernel_hydro.h under WITH_VECTORIZATION;
// hydro/Gadget2/hydro_iact.h's vectorised interactions call deval_1, deval_2
// and dWdx_force): on SWIFT's `vector` (vector.h: a union of VEC_SIZE floats
// f[]), every lane through the scalar function, so each lane is that value
// bit for bit and 0 for u >= gamma where the scalar is. The inputs and
// outputs are copied to locals, so GCC assumes no aliasing and vectorises the
// lane loop (the outputs start as copies of the input: clang's -Weverything
// cannot see that the loop writes every lane) under SWIFT's flags (-O3 -ffast-math; not at -O2 or without fast
// math, where the loop stays scalar: checked by hand, stop 89). One text for
// every kernel: the scalar functions carry the kernel.
constexpr const char* simd_functions = R"(
#if defined(WITH_VECTORIZATION) || defined(WITH_OLD_VECTORIZATION)
/* SWIFT's SIMD kernel functions on its vector (VEC_SIZE floats, vector.h): every lane the scalar function's
 * value bit for bit (the GADGET-2 SPH scheme's hand-vectorised loops call them). */
__attribute__((always_inline)) static inline void kernel_deval_1_vec(vector *u, vector *w, vector *dw_dx) {
    vector x = *u, a = x, b = x;
    int k;
    for (k = 0; k < VEC_SIZE; k++) kernel_deval(x.f[k], &a.f[k], &b.f[k]);
    *w = a;
    *dw_dx = b;
}

__attribute__((always_inline)) static inline void kernel_deval_vec(vector *u, vector *w, vector *dw_dx) {
    kernel_deval_1_vec(u, w, dw_dx);
}

__attribute__((always_inline)) static inline void kernel_deval_2_vec(vector *u, vector *w, vector *dw_dx, vector *u2,
                                                                     vector *w2, vector *dw_dx2) {
    kernel_deval_1_vec(u, w, dw_dx);
    kernel_deval_1_vec(u2, w2, dw_dx2);
}

__attribute__((always_inline)) static inline void kernel_eval_W_vec(vector *u, vector *w) {
    vector x = *u, a = x;
    int k;
    for (k = 0; k < VEC_SIZE; k++) kernel_eval(x.f[k], &a.f[k]);
    *w = a;
}

__attribute__((always_inline)) static inline void kernel_eval_dWdx_vec(vector *u, vector *dw_dx) {
    vector x = *u, b = x;
    int k;
    for (k = 0; k < VEC_SIZE; k++) kernel_eval_dWdx(x.f[k], &b.f[k]);
    *dw_dx = b;
}

/* 0 for u >= gamma, as SWIFT's (the scalar function's value) */
__attribute__((always_inline)) static inline void kernel_eval_dWdx_force_vec(vector *u, vector *dw_dx) {
    kernel_eval_dWdx_vec(u, dw_dx);
}

__attribute__((always_inline)) static inline void kernel_eval_dWdx_force_2_vec(vector *u, vector *dw_dx, vector *u_2,
                                                                               vector *dw_dx_2) {
    kernel_eval_dWdx_vec(u, dw_dx);
    kernel_eval_dWdx_vec(u_2, dw_dx_2);
}
#endif
)";

// SWIFT's adaptive softening (configure --with-adaptive-softening; src/
// adaptive_softening*.h) ties the gravitational softening support to the
// gas's, eps = H = kernel_gamma h, and sums m_j potential_dh(u_ij, 1/h_i)
// (Price & Monaghan 2007, eq. 26). potential_dh is d phi/dh of the softened
// potential phi = m W_pot(r/H)/H of kernel_gravity.h, per unit mass:
//   d/dh [W_pot(x)/H] = -(W_pot(x) + x W_pot'(x)) / (kernel_gamma h^2),
// x = r/H = u/kernel_gamma, and 0 for x >= 1 (outside, -1/r does not depend
// on h; inside it tends to 0 at the edge, the potential being C^1). That is
// softening.hpp's h-derivative (Phantom's dphidh) times 4 pi. Given where
// kernel_gravity.h is (3D, a Poisson potential); elsewhere ADAPTIVE_SOFTENING
// is an #error naming why. A combination's term by term (`parts`), as its
// potential's.
struct PotentialHDerivative {
    Radial f;
    std::vector<Radial> parts;
};
std::optional<PotentialHDerivative> potential_h_derivative(const KernelFacts& facts) {
    if (facts.kernel.dim != 3 || !quantity_of(facts, static_cast<int>(table::QuantityId::potential))) return std::nullopt;
    PotentialHDerivative d{softening_h_derivative(facts.kernel) * sphere_measure(3), {}};
    for (const ComboTerm& t : facts.terms)
        d.parts.push_back(softening_h_derivative(t.kernel) * (sphere_measure(3) * Exact(t.weight)));
    return d;
}

std::string no_potential_dh_reason(const KernelFacts& facts) {
    return facts.kernel.dim != 3 ? "SWIFT's gravity is 3D" : "the kernel has no Poisson potential";
}

std::string potential_dh_note(bool given, const KernelFacts& facts) {
    if (!given)
        return " * potential_dh (SWIFT's adaptive softening) is not given: " + no_potential_dh_reason(facts) +
               " (ADAPTIVE_SOFTENING is an #error).\n";
    return " * potential_dh(u, h_inv): d phi/dh of the softened potential phi = m W_pot(r/H)/H of this kernel's\n"
           " * kernel_gravity.h, per unit mass, with H = kernel_gamma h (SWIFT's adaptive softening sets eps = kernel_gamma h):\n"
           " * -(W_pot(x) + x W_pot'(x)) / (kernel_gamma h^2), x = u/kernel_gamma, 0 for x >= 1 (Price & Monaghan 2007's\n"
           " * d phi/dh, their eq. 26 as SWIFT cites it), in double, rounded once to float. SWIFT's stock potential_dh\n"
           " * (Wendland C2 only) is (d phi/dh - 3/(kernel_gamma h^2))/4: the constant term -W_pot(0)/(kernel_gamma h^2)\n"
           " * and a factor 4 missing (mollify-gen errata --codes). Adaptive softening needs this file's kernel_gravity.h\n"
           " * beside it (the same kernel); SWIFT's configure and adaptive_softening.h accept it only with\n"
           " * --with-kernel=wendland-C2, whose macro these files ignore.\n";
}

std::string potential_dh_function(bool given, const std::string& prefix, const KernelFacts& facts) {
    if (!given)
        return "\n#ifdef ADAPTIVE_SOFTENING\n#error \"" + facts.spec + " in D = " + std::to_string(facts.kernel.dim) +
               ": no potential_dh for SWIFT's adaptive softening (" + no_potential_dh_reason(facts) + ")\"\n#endif\n";
    return "\n/* d phi/dh at u = r/h per unit mass, phi = W_pot(r/H)/H (kernel_gravity.h), H = kernel_gamma h; 0 for u >= "
           "gamma */\n"
           "static inline float potential_dh(const float u, const float h_inv) {\n"
           "    const double x = (double)u * " + prefix + "_gamma_inv;\n"
           "    return (float)(" + prefix + "_dphidh(x) * " + prefix + "_gamma_inv * ((double)h_inv * (double)h_inv));\n}\n";
}

std::string hydro_file(const TargetKernel& tk, const std::string& command) {
    const KernelFacts& facts = tk.facts;
    const ExactKernel& k = facts.kernel;
    const int d = k.dim;
    if (k.normalised_by != Normalisation::unit_mass)
        fail("--target swift: kernel " + facts.spec + " in D = " + std::to_string(d) +
             " is not a unit-mass kernel (a derivative kernel, Belley): SWIFT's kernel_hydro.h needs a density kernel");
    const SignCheck signs = check_signs(facts, tk.allow_negative_lobes);
    const DerivedConstant gamma = gamma_of(k);
    const Q g2 = gamma.square;
    const Exact C = separate_normalisation(tk.convention, k);
    const std::string prefix = "mollify_swift_" + facts.id;
    const Syntax s = c_syntax(prefix);

    const auto& W = tk.tables[static_cast<std::size_t>(table::QuantityId::value)];
    const auto& dW = tk.tables[static_cast<std::size_t>(table::QuantityId::dr)];
    if (!W || !dW) fail("internal: --target swift: " + facts.spec + " without W or W' tables");
    std::vector<CodeConstant> constants;
    std::string functions = c_unit_function(prefix + "_W1", "W_1(x) = C w(x), mollify's kernel on support 1",
                                            code_quantity(prefix + "_W1", *W, constants), s);
    functions += c_unit_function(prefix + "_dW1", "W_1'(x) = C w'(x)", code_quantity(prefix + "_dW1", *dW, constants), s);
    const std::optional<PotentialHDerivative> dphi_dh = potential_h_derivative(facts);
    if (dphi_dh)
        functions += c_unit_function(
            prefix + "_dphidh", "-(W_pot(x) + x W_pot'(x)), W_pot = 4 pi phi_1 (kernel_gravity.h); 0 for x >= 1",
            code_quantity(prefix + "_dphidh",
                          round_or_fail(dphi_dh->f, false, "potential_dh", ResultPrecision::float_value, dphi_dh->parts),
                          constants),
            s);

    const std::string dim_macro = "HYDRO_DIMENSION_" + std::to_string(d) + "D";
    std::string out = "/*\n" + banner(command, " *");
    out += " *\n * SWIFT's src/kernel_hydro.h for " + facts.spec + " in D = " + std::to_string(d) + ":\n * " + k.source + "\n";
    out += " * SWIFT's convention: u = r/h, support H = kernel_gamma h, x = u/kernel_gamma in [0, 1);\n"
           " * W(u) = C gamma^-D w(x), dW/du = C gamma^-(D+1) w'(x) (the caller multiplies by h^-D, h^-(D+1)),\n"
           " * C = kernel_constant, w(0) = 1 (C = W_1(0), W_1 = C w the unit-mass kernel on support 1).\n"
           " * kernel_gamma (Dehnen & Aly 2012): " + gamma.rule + ";\n"
           " *   kernel_gamma^2 = " + short_string(g2) + " exactly.\n"
           " * Evaluation: x = u/gamma in double, then mollify's factored tables of W_1 and W_1' (Horner in x\n"
           " * times powers of the edge distance 1 - x, per piece; mollify's Precision::fast) in double, rounded\n"
           " * once to float: within 1 float ulp of the exact value (correctly rounded constants, a double\n"
           " * evaluation ~2^-29 float ulps off, one rounding to float).\n"
           " * SWIFT's own layout (kernel_coeffs: float monomial coefficients per sub-interval, float Horner in x)\n"
           " * would lose, on the last piece (measured by the generator: float Horner against exact rationals):\n *" +
           expanded_layout_loss(k) + ".\n"
           " * Signs: " + comment_text(signs.note) + "\n"
           " * Not given: kernel_degree, kernel_ivals, kernel_coeffs (SWIFT's table layout, read only inside its stock\n"
           " * kernel_hydro.h).\n" + potential_dh_note(dphi_dh.has_value(), facts) +
           " * The SIMD functions kernel_*_vec (WITH_VECTORIZATION: SWIFT's GADGET-2 SPH scheme's hand-vectorised\n"
           " * loops call them) take every lane through the scalar function, so each lane is its value bit for bit;\n"
           " * GCC vectorises that loop under SWIFT's flags (-O3 -ffast-math). SWIFT's stock file has them for\n"
           " * Wendland C2 and the cubic spline only (--disable-hand-vec for the others).\n"
           " * Each constant is correctly rounded (float where SWIFT uses float), its exact value beside it.\n"
           " * Outside SWIFT define MOLLIFY_SWIFT_STANDALONE (and " + dim_macro + "): no SWIFT headers are included.\n */\n";
    out += "#ifndef SWIFT_KERNEL_HYDRO_H\n#define SWIFT_KERNEL_HYDRO_H\n\n";
    out += "#ifndef MOLLIFY_SWIFT_STANDALONE\n/* SWIFT's headers, as its stock kernel_hydro.h includes them (its includers rely on them) */\n"
           "#include <config.h>\n#endif\n#include <math.h>\n#ifndef MOLLIFY_SWIFT_STANDALONE\n#include \"dimension.h\"\n"
           "#include \"error.h\"\n#include \"inline.h\"\n#include \"minmax.h\"\n#include \"vector.h\"\n#endif\n\n";
    out += "#if !defined(" + dim_macro + ")\n#error \"" + facts.spec + " was generated for " + dim_macro + "\"\n#endif\n";
    out += "\n";
    out += "#define kernel_name \"mollify " + facts.spec + "\"\n";
    out += float_define("kernel_gamma", gamma_power(g2, 1));
    out += float_define("kernel_gamma_inv", gamma_power(g2, -1));
    out += float_define("kernel_gamma2", gamma_power(g2, 2));
    out += float_define("kernel_gamma_dim", gamma_power(g2, d));
    out += float_define("kernel_gamma_dim_plus_one", gamma_power(g2, d + 1));
    out += float_define("kernel_gamma_inv_dim", gamma_power(g2, -d));
    out += float_define("kernel_gamma_inv_dim_plus_one", gamma_power(g2, -(d + 1)));
    out += "/* C = W_1(0) */\n" + float_define("kernel_constant", {C, Q(1)});
    out += "/* W(0) = C gamma^-D, the self contribution */\n" + float_define("kernel_root", {C * gamma_power(g2, -d).factor, gamma_power(g2, -d).radicand});
    out += "/* the unit sphere's volume times gamma^D */\n" +
           float_define("kernel_norm", {unit_ball_volume(d) * gamma_power(g2, d).factor, gamma_power(g2, d).radicand});
    out += "\n" + double_constant(prefix + "_gamma_inv", gamma_power(g2, -1));
    out += double_constant(prefix + "_gamma_inv_dim", gamma_power(g2, -d));
    out += double_constant(prefix + "_gamma_inv_dim_plus_one", gamma_power(g2, -(d + 1)));
    out += "\n" + std::string(c_helpers) + "\n";
    out += "/* The coefficients of W_1 and W_1', in order (function, piece, term, power). */\n";
    out += "static const double " + prefix + "_c[" + std::to_string(constants.size()) + "] = {\n";
    for (std::size_t i = 0; i < constants.size(); ++i)
        out += "    " + hex_literal(constants[i].value) + ", /* [" + std::to_string(i) + "] " + comment_text(constants[i].exact) + " */\n";
    out += "};\n" + functions;

    const std::string clamp_w = signs.clamp ? "fmaxf(w, 0.f)" : "w", clamp_dw = signs.clamp ? "fminf(dw, 0.f)" : "dw";
    const std::string clamp_wd = signs.clamp ? "fmax(w, 0.)" : "w";
    out += "\n/* W and dW/du at u = r/h (times h^-D and h^-(D+1) by the caller); 0 for u >= gamma */\n"
           "static inline void kernel_deval(float u, float *restrict W, float *restrict dW_dx) {\n"
           "    const double x = (double)u * " + prefix + "_gamma_inv;\n"
           "    const float w = (float)(" + prefix + "_gamma_inv_dim * " + prefix + "_W1(x));\n"
           "    const float dw = (float)(" + prefix + "_gamma_inv_dim_plus_one * " + prefix + "_dW1(x));\n"
           "    *W = " + clamp_w + ";\n    *dW_dx = " + clamp_dw + ";\n}\n";
    out += "\nstatic inline void kernel_eval(float u, float *restrict W) {\n"
           "    const float w = (float)(" + prefix + "_gamma_inv_dim * " + prefix + "_W1((double)u * " + prefix + "_gamma_inv));\n"
           "    *W = " + clamp_w + ";\n}\n";
    out += "\nstatic inline void kernel_eval_dWdx(float u, float *restrict dW_dx) {\n"
           "    const float dw = (float)(" + prefix + "_gamma_inv_dim_plus_one * " + prefix + "_dW1((double)u * " + prefix +
           "_gamma_inv));\n    *dW_dx = " + clamp_dw + ";\n}\n";
    out += "\n/* In double (SWIFT's projected kernels): the double evaluation, not rounded to float */\n"
           "static inline void kernel_eval_double(double u, double *restrict W) {\n"
           "    const double w = " + prefix + "_gamma_inv_dim * " + prefix + "_W1(u * " + prefix + "_gamma_inv);\n"
           "    *W = " + clamp_wd + ";\n}\n";
    out += potential_dh_function(dphi_dh.has_value(), prefix, facts);
    out += simd_functions;
    out += "\nvoid hydro_kernel_dump(int N);\n\n#endif /* SWIFT_KERNEL_HYDRO_H */\n";
    return out;
}

// ---- kernel_gravity.h ----

struct GravityFunction {
    std::string name, meaning;
    Radial f;
    ResultPrecision result = ResultPrecision::float_value;
    std::vector<Radial> parts{};  // a combination's terms (round_or_fail)
};

std::string gravity_file(const TargetKernel& tk, const std::string& command) {
    const KernelFacts& facts = tk.facts;
    const ExactKernel& k = facts.kernel;
    const Radial* phi = quantity_of(facts, static_cast<int>(table::QuantityId::potential));
    const Radial* dphi_r = quantity_of(facts, static_cast<int>(table::QuantityId::dpotential_over_r));
    if (!phi || !dphi_r) fail("internal: --target swift: gravity without a potential");
    const Softening soft = certified_softening(k);  // Error naming a failed certificate
    const int finite = finite_at_origin(soft.multipole);
    const int orders = std::min(soft.smoothness.guaranteed + 1, finite + 1);  // D_soft_1..orders
    const std::string prefix = "mollify_swift_grav_" + facts.id;
    const Syntax s = c_syntax(prefix);
    const Exact four_pi = sphere_measure(3);

    const auto times_four_pi = [&four_pi](std::vector<Radial> parts) {
        for (Radial& p : parts) p = p * four_pi;
        return parts;
    };
    const std::vector<Radial> pot_parts = times_four_pi(parts_of(facts, static_cast<int>(table::QuantityId::potential)));
    const std::vector<Radial> force_parts =
        times_four_pi(parts_of(facts, static_cast<int>(table::QuantityId::dpotential_over_r)));
    std::vector<GravityFunction> fs = {
        {prefix + "_pot", "W_pot(u) = 4 pi phi_1(u): H phi/m (-1/u outside)", *phi * four_pi, ResultPrecision::float_value,
         pot_parts},
        {prefix + "_force", "W_f(u) = 4 pi phi_1'(u)/u = W_pot'/u (1/u^3 outside)", *dphi_r * four_pi,
         ResultPrecision::float_value, force_parts},
        {prefix + "_pot_double", "W_pot(u), planned for a double result", *phi * four_pi, ResultPrecision::double_value,
         pot_parts},
        {prefix + "_force_double", "W_f(u), planned for a double result", *dphi_r * four_pi, ResultPrecision::double_value,
         force_parts},
    };
    const std::vector<std::vector<Radial>> dsoft_parts = multipole_factor_parts(facts, orders - 1);
    for (int n = 1; n <= orders; ++n)
        fs.push_back({prefix + "_dsoft" + std::to_string(n),
                      "D_soft_" + std::to_string(n) + "(u) = E_" + std::to_string(n - 1) + "(u) (softening.hpp)",
                      soft.multipole[static_cast<std::size_t>(n - 1)], ResultPrecision::float_value,
                      dsoft_parts[static_cast<std::size_t>(n - 1)]});
    std::vector<CodeConstant> constants;
    std::vector<std::vector<RoundedPiece>> rounded;
    for (const GravityFunction& g : fs) rounded.push_back(round_or_fail(g.f, true, g.name, g.result, g.parts));
    std::string functions;
    for (std::size_t i = 0; i < fs.size(); ++i)
        functions += c_unit_function(fs[i].name, fs[i].meaning, code_quantity(fs[i].name, rounded[i], constants), s);

    // H = -W_pot(0) eps: the potential at 0 equal to Plummer's
    const Exact plummer = plummer_equivalent(fs[0].f * Exact(Q(-1)), facts.spec);  // g = -W_pot
    const SwiftConstant p{plummer, Q(1)};
    SwiftConstant p_inv{plummer.is_rational() ? Exact(Q(1) / plummer.rational()) : plummer.inverse(), Q(1)};

    std::string out = "/*\n" + banner(command, " *");
    out += " *\n * SWIFT's src/kernel_gravity.h for " + facts.spec + " (3D):\n * " + k.source + "\n";
    out += " * SWIFT's convention: u = r/H < 1, H the softening support; the potential is m W_pot(u)/H\n"
           " * (kernel_grav_pot_eval, -1/u outside), the force m W_f(u)/H^3 times the separation\n"
           " * (kernel_grav_force_eval, W_f = W_pot'/u, 1/u^3 outside), both the kernel's exact Poisson potential\n"
           " * (mollify's phi_1 times 4 pi). D_soft_1 = -W_pot, D_soft_(n+1) = D_soft_n' - (n-1) D_soft_n/u\n"
           " * (mollify's multipole factors E_(n-1), softening.hpp; the Green's function's outside).\n"
           " * H = kernel_gravity_softening_plummer_equivalent * eps: the softened potential at r = 0,\n"
           " * -m W_pot(0)/H, equal to Plummer's -m/eps (SWIFT's rule for Wendland C2: H = 3 eps), so the factor\n"
           " * is -W_pot(0) = " + plummer.to_string() + " exactly.\n";
    if (orders < 6)
        out += " * D_soft_" + std::to_string(orders + 1) + " and higher are not given: certified_softening certifies phi^(0.." +
               std::to_string(soft.smoothness.guaranteed) + ") for this kernel and E_0..E_" + std::to_string(finite) +
               " are finite at u = 0;\n * SWIFT's M2P needs D_soft_(order+2), its M2L D_soft_(order+1) (src/gravity_derivatives.h), so\n"
               " * SELF_GRAVITY_MULTIPOLE_ORDER > " + std::to_string(orders - 2) + " is an #error.\n";
    out += " * Evaluated in double and rounded once to float: each piece one polynomial (factored at the edge where it\n"
           " * vanishes there) where that is within 2^-30 of max(|f|, |u f'|), as a float result needs, else as mollify's\n"
           " * Precision::fast (Taylor pieces); short and branch-light, so SWIFT's gravity pair loop vectorises around\n"
           " * them. kernel_grav_eval_*_double (SWIFT's force checks) as Precision::fast, not rounded to float.\n"
           " * Each constant is correctly rounded, its exact value beside it.\n */\n";
    out += "#ifndef SWIFT_KERNEL_GRAVITY_H\n#define SWIFT_KERNEL_GRAVITY_H\n\n#include <math.h>\n"
           "#ifndef MOLLIFY_SWIFT_STANDALONE\n/* as SWIFT's stock kernel_gravity.h */\n#include \"inline.h\"\n#include \"minmax.h\"\n#endif\n\n";
    out += "#if defined(HYDRO_DIMENSION_1D) || defined(HYDRO_DIMENSION_2D)\n#error \"SWIFT's gravity is 3D: "
           "this file is for 3D\"\n#endif\n";
    out += "#ifdef GADGET2_SOFTENING_CORRECTION\n#error \"mollify's kernel_gravity.h replaces both of SWIFT's softening "
           "shapes: undefine GADGET2_SOFTENING_CORRECTION\"\n#endif\n";
    if (orders < 6)
        out += "#if defined(SELF_GRAVITY_MULTIPOLE_ORDER) && SELF_GRAVITY_MULTIPOLE_ORDER > " + std::to_string(orders - 2) +
               "\n#error \"" + facts.spec + ": D_soft_" + std::to_string(orders + 1) + " and higher are not certified\"\n#endif\n";
    out += "\n#define kernel_gravity_softening_plummer_equivalent " + hex_literal(p.to_double()) + " /* " +
           comment_text(p.text()) + " */\n";
    out += "#define kernel_gravity_softening_plummer_equivalent_inv " + hex_literal(p_inv.to_double()) + " /* " +
           comment_text(p_inv.text()) + " */\n";
    out += "#define kernel_gravity_softening_name \"mollify " + facts.spec + "\"\n\n";
    out += std::string(c_helpers) + "\n";
    out += "/* The coefficients of every function, in order (function, piece, term, power). */\n";
    out += "static const double " + prefix + "_c[" + std::to_string(constants.size()) + "] = {\n";
    for (std::size_t i = 0; i < constants.size(); ++i)
        out += "    " + hex_literal(constants[i].value) + ", /* [" + std::to_string(i) + "] " + comment_text(constants[i].exact) + " */\n";
    out += "};\n" + functions;
    out += "\nstatic inline float kernel_grav_pot_eval(const float u) { return (float)" + prefix + "_pot((double)u); }\n";
    out += "static inline float kernel_grav_force_eval(const float u) { return (float)" + prefix + "_force((double)u); }\n";
    out += "static inline void kernel_grav_eval_pot_double(double u, double *const W) { *W = " + prefix + "_pot_double(u); }\n";
    out += "static inline void kernel_grav_eval_force_double(double u, double *const W) { *W = " + prefix + "_force_double(u); }\n";
    for (int n = 1; n <= orders; ++n)
        out += "static inline float D_soft_" + std::to_string(n) + "(const float u) { return (float)" + prefix + "_dsoft" +
               std::to_string(n) + "((double)u); }\n";
    out += "\n#endif /* SWIFT_KERNEL_GRAVITY_H */\n";
    return out;
}

}  // namespace

TargetFiles write_swift(const TargetKernel& tk, const std::string& command) {
    const KernelFacts& facts = tk.facts;
    TargetFiles files;
    files["swift/" + facts.id + "/kernel_hydro.h"] = hydro_file(tk, command);
    // SWIFT's gravity is 3D; a kernel without a Poisson potential has no softening (its reason in the catalogue).
    if (facts.kernel.dim == 3 && quantity_of(facts, static_cast<int>(table::QuantityId::potential)))
        files["swift/" + facts.id + "/kernel_gravity.h"] = gravity_file(tk, command);
    return files;
}

// The gravity file alone, for a caller that asks for it explicitly: Error in D != 3 or without a potential.
TargetFiles write_swift_gravity(const TargetKernel& tk, const std::string& command) {
    const KernelFacts& facts = tk.facts;
    if (facts.kernel.dim != 3)
        fail("--target swift: kernel_gravity.h is 3D only (SWIFT's gravity); " + facts.spec + " was asked in D = " +
             std::to_string(facts.kernel.dim));
    if (!quantity_of(facts, static_cast<int>(table::QuantityId::potential)))
        fail("--target swift: " + facts.spec + " has no Poisson potential: " + facts.kernel.claims.no_potential);
    return {{"swift/" + facts.id + "/kernel_gravity.h", gravity_file(tk, command)}};
}

}  // namespace mollify::gen
