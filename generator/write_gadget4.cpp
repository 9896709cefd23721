// --target gadget4: the per-kernel part of GADGET-4's src/sph/kernel.h
// (../shared/peers.md, "GADGET-4": Hsml = H the support, u = r/H in [0, 1),
// wk = NORM hinv3 w(u), dwk = NORM hinv4 w'(u), mode -1/0/1 = W only / both /
// dW only, hinv3 = H^-D, hinv4 = H^-(D+1)), one header per dimension
// (ONEDIMS, TWODIMS or 3D, as GADGET-4's Config.sh), and in 3D the
// softening g-factors fac0..fac5 of its multipole tree (softening.hpp's
// gadget_gfactors: g = -4 pi phi the softened 1/r, E_n = r^n ((1/r) d/dr)^n g;
// fac_n(r) = h^-(n+1) E_n(r/h), h the softening support).
//
// w is the kernel's shape s on support 1 scaled to w(0) = 1 (GADGET-4's
// stock form) and NORM = N s(0) (conventions.hpp's separate_normalisation;
// s and N where s(0) is not a nonzero rational): mollify's tables of s, s' and E_n, evaluated
// as mollify's Precision::fast (factored at the edge).
#include "c_code.hpp"
#include "target.hpp"
#include "target_code.hpp"

#include "emit_round.hpp"
#include "error.hpp"
#include "rounding.hpp"
#include "softening.hpp"
#include "softening_certificate.hpp"

namespace mollify::gen {

namespace {

std::vector<RoundedPiece> round_or_fail(const Radial& f, bool potential_like, const std::vector<Radial>& parts,
                                        const std::string& what) {
    auto r = rounded_quantity(&f, potential_like, parts);
    if (!r) fail("internal: --target gadget4: " + what + " did not round");
    return std::move(*r);
}

// GADGET-4's EXPLICIT_VECTORIZATION form (Vec4d of its vectorclass): the
// helpers of the four-lane functions below, the scalar helpers' operations
// in the same order on four lanes.
const char* const vector_helpers = R"(#ifndef MOLLIFY_G4_VECTOR_HELPERS_1
#define MOLLIFY_G4_VECTOR_HELPERS_1
/* mollify_c_horner and mollify_c_ipow on the four lanes of a Vec4d: the same operations in the same order */
static inline Vec4d mollify_g4_v4_horner(const double *c, int n, Vec4d v) {
    Vec4d y(c[n - 1]);
    int k;
    for (k = n - 2; k >= 0; --k) y = y * v + Vec4d(c[k]);
    return y;
}
static inline Vec4d mollify_g4_v4_ipow(Vec4d x, int n) {
    Vec4d y(1.0), b = x;
    int m = n < 0 ? -n : n, k;
    for (k = 0; k < 8; ++k) {
        if (m & 1) y = y * b;
        b = b * b;
        m >>= 1;
    }
    return n < 0 ? Vec4d(1.0) / y : y;
}
#endif
)";

// Every lane evaluates every piece (then a select per boundary): beyond a
// few pieces four scalar evaluations, each one piece, cost less.
constexpr std::size_t max_vector_pieces = 4;

// Whether q's four-lane form is the scalar one's arithmetic on Vec4d:
// polynomial pieces only (no sqrt, logarithm or arcsin, which Vec4d has
// only through vectorclass's own approximations), zero outside, none
// singular at 0, and few pieces.
bool vectorisable(const CodeQuantity& q) {
    if (q.inside.empty() || q.inside.size() > max_vector_pieces || !q.exterior.terms.empty() || q.at_origin) return false;
    for (const CodePiece& p : q.inside)
        for (const CodeTerm& t : p.terms)
            if (t.term->basis != table::Basis::one) return false;
    return true;
}

// q's pieces on four lanes, `static inline Vec4d name(Vec4d q)`: each piece
// the scalar function's expression (the same terms in the same order), the
// pieces chosen by select from the last down, as the scalar chain from the
// first up, and 0 beyond the support.
std::string vector_function(const std::string& prefix, const std::string& name, const std::string& meaning, const CodeQuantity& q,
                            const Syntax& scalar) {
    Syntax s = scalar;
    s.unit_h = true;
    s.horner = [prefix](std::size_t first, std::size_t n, const std::string& v) {
        return "mollify_g4_v4_horner(" + prefix + "_c + " + std::to_string(first) + ", " + std::to_string(n) + ", " + v + ")";
    };
    s.power = [](const std::string& x, int n) {
        check_c_power(n);
        return n == 1 ? x : "mollify_g4_v4_ipow(" + x + ", " + std::to_string(n) + ")";
    };
    std::string body;
    for (std::size_t p = q.inside.size(); p-- > 0;) {
        const std::string piece = inside_piece(s, q, p);
        body += "    /* " + comment_text(q.inside[p].note) + " */\n";
        body += p + 1 == q.inside.size() ? "    Vec4d y = " + piece + ";\n"
                                         : "    y = select(q < " + s.literal(q.inside[p + 1].lo) + ", " + piece + ", y);\n";
    }
    const std::string code = without_comments(body, "/*", "*/");
    if (uses(code, "r") || uses(code, "h")) fail("internal: --target gadget4: a four-lane piece of " + name + " reads r or h");
    std::string out = "\n/* " + meaning + ": on four lanes, every piece, then select */\nstatic inline Vec4d " + name + "(Vec4d q) {\n";
    if (uses(code, "e")) out += "    const Vec4d e = 1.0 - q;\n";
    return out + body + "    return select(q > 1.0, Vec4d(0.0), y);\n}\n";
}

}  // namespace

TargetFiles write_gadget4(const TargetKernel& tk, const std::string& command) {
    const KernelFacts& facts = tk.facts;
    const ExactKernel& k = facts.kernel;
    const std::string prefix = "mollify_g4_" + facts.id;
    // GADGET-4 builds with -std=c++11, which has no hexadecimal floating
    // literals (C++17): every double as its exact decimal, the hex form beside it.
    Syntax s = c_syntax(prefix);
    s.literal = exact_decimal_literal;

    // w = s/s(0) (GADGET-4's stock w(0) = 1) and NORM the convention's
    // separate_normalisation where s(0) is a nonzero rational; else w = s, NORM = N.
    Q s0(1);
    bool unit = false;
    if (k.shape.form_at(Q(0)).is_elementary()) {
        try {
            const Exact v = k.shape.at(Q(0));
            if (v.is_rational() && v.rational() != 0) s0 = v.rational(), unit = true;
        } catch (const Error&) {  // singular at 0 (the viscosity kernel's 1/r): w = s, NORM = N
        }
    }
    const Exact norm = unit ? separate_normalisation(tk.convention, k) : k.normalisation;
    const Radial w = k.shape * Exact(Q(1) / s0);
    // A combination's shape term by term (its inner edges factored): W's parts over NORM.
    const Exact inv_norm = norm.inverse();
    std::vector<Radial> parts = parts_of(facts, static_cast<int>(table::QuantityId::value)), dparts;
    for (Radial& p : parts) p = p * inv_norm;
    for (const Radial& p : parts) dparts.push_back(p.derivative());

    std::vector<std::vector<RoundedPiece>> rounded;
    std::vector<std::pair<std::string, std::string>> names;  // function, meaning
    rounded.push_back(round_or_fail(w, false, parts, "w"));
    names.push_back({prefix + "_w", "w(u), W = NORM w(u) H^-D"});
    rounded.push_back(round_or_fail(w.derivative(), false, dparts, "w'"));
    names.push_back({prefix + "_dw", "w'(u) = dw/du"});
    const bool gravity = k.dim == 3 && quantity_of(facts, static_cast<int>(table::QuantityId::potential)) != nullptr;
    int finite = -1;  // fac0..fac<finite> have finite limits at r = 0
    Exact plummer;    // h / eps of the Plummer-equivalent softening, E_0(0)
    const std::string plummer_name = "MOLLIFY_G4_" + facts.id + "_PLUMMER";
    if (gravity) {
        const std::vector<Radial> g = gadget_gfactors(k, max_gfactor);
        const std::vector<std::vector<Radial>> g_parts = multipole_factor_parts(facts, max_gfactor);
        finite = finite_at_origin(g);
        if (finite >= 0) plummer = plummer_equivalent(g[0], facts.spec);  // E_0 = g
        for (std::size_t n = 0; static_cast<int>(n) <= finite; ++n) {
            rounded.push_back(round_or_fail(g[n], true, g_parts[n], "fac" + std::to_string(n)));
            names.push_back({prefix + "_fac" + std::to_string(n), "E_" + std::to_string(n) + "(u), fac" + std::to_string(n) +
                                                                       " at h = 1 (softening.hpp; 1/r-like outside)"});
        }
    }
    std::vector<CodeConstant> constants;
    std::vector<CodeQuantity> quantities;
    std::string functions;
    for (std::size_t i = 0; i < rounded.size(); ++i) {
        quantities.push_back(code_quantity(names[i].first, rounded[i], constants));
        functions += c_unit_function(names[i].first, names[i].second, quantities.back(), s);
    }

    const std::string dim_macro = k.dim == 1 ? "defined(ONEDIMS)" : k.dim == 2 ? "defined(TWODIMS)" : "!defined(ONEDIMS) && !defined(TWODIMS)";
    const std::string guard = "MOLLIFY_G4_" + facts.id + "_H";
    std::string out = "/*\n" + banner(command, " *");
    out += " *\n * GADGET-4's per-kernel part of src/sph/kernel.h for " + facts.spec + " in D = " + std::to_string(k.dim) +
           ":\n * " + k.source + "\n"
           " * GADGET-4's convention: Hsml = H the support, u = r/H in [0, 1); wk = NORM hinv3 w(u),\n"
           " * dwk = NORM hinv4 w'(u) (hinv3 = H^-D, hinv4 = H^-(D+1), kernel_hinv); mode -1: wk only,\n"
           " * 0: both, 1: dwk only. w is the kernel's shape on support 1 with w(0) = 1, NORM the\n"
           " * exact constant making W unit-mass. Evaluated as mollify's Precision::fast (factored at the edge).\n";
    if (gravity && finite >= 0)
        out += " * Softening (3D): " + prefix + "_gfactors(r, h, fac) gives fac[n] = h^-(n+1) E_n(r/h), n = 0..5,\n"
               " * E_0 = g the softened 1/r (-4 pi phi, phi the kernel's exact Poisson potential), E_1 = g',\n"
               " * E_2 = g'' - g'/r, E_(n+1) = E_n' - n E_n/r (GADGET-4's gfactors fac0..fac5; 1/r, -1/r^2,\n"
               " * 3/r^3, ... outside the support h). " + plummer_name + " = E_0(0): h = it times GADGET-4's\n"
               " * Plummer-equivalent eps (the potential at r = 0 equal to Plummer's; GADGET-4 hard-codes its cubic\n"
               " * spline's 2.8 = 14/5). As the softening beside another SPH kernel (GADGET-4's gravity tree takes\n"
               " * the cubic spline whatever the SPH kernel), define MOLLIFY_G4_SOFTENING_ONLY before including this\n"
               " * file: its prefixed functions only, no NORM or kernel_main.\n";
    out += " * Each constant is correctly rounded, written as that double's exact decimal expansion (C++11 has\n"
           " * no hex floats; a conforming compiler converts a representable literal exactly), its hex form\n"
           " * and exact value beside it.\n */\n";
    out += "#ifndef " + guard + "\n#define " + guard + "\n\n#if !(" + dim_macro + ")\n#error \"" + facts.spec +
           " was generated for D = " + std::to_string(k.dim) + "\"\n#endif\n\n#include <math.h>\n\n" + c_helpers + "\n";
    out += "static const double " + prefix + "_c[" + std::to_string(constants.size()) + "] = {\n";
    for (std::size_t i = 0; i < constants.size(); ++i)
        out += "    " + s.literal(constants[i].value) + ", /* [" + std::to_string(i) + "] " + hex_literal(constants[i].value) + ", " +
               comment_text(constants[i].exact) + " */\n";
    out += "};\n" + functions;
    if (gravity && finite >= 0) {
        if (finite < max_gfactor)
            out += "\n/* fac" + std::to_string(finite + 1) + " and higher have no finite limit at r = 0 for " +
                   facts.spec + " (odd powers or logarithms\n   of r at the origin): not given, and a higher MULTIPOLE_ORDER is an error. */\n"
                   "#if defined(MULTIPOLE_ORDER) && MULTIPOLE_ORDER > " + std::to_string(finite) + "\n#error \"" + facts.spec +
                   ": the g-factors beyond fac" + std::to_string(finite) + " blow up at r = 0\"\n#endif\n";
        out += "\n/* fac[0.." + std::to_string(finite) + "] */\nstatic inline void " + prefix +
               "_gfactors(double r, double h, double fac[6])\n{\n    const double u = r / h, hinv = 1 / h;\n";
        for (int n = 0; n <= finite; ++n)
            out += "    fac[" + std::to_string(n) + "] = " + prefix + "_fac" + std::to_string(n) + "(u) * pow(hinv, " +
                   std::to_string(n + 1) + ");\n";
        out += "}\n\n";
        const double plummer_value = round_to_double(plummer);
        out += "/* h / eps of the Plummer-equivalent softening: E_0(0) */\n#define " + plummer_name + " " +
               s.literal(plummer_value) + " /* " + hex_literal(plummer_value) + ", " + comment_text(plummer.to_string()) + " */\n";
    }
    out += "\n#endif\n";
    // GADGET-4's SPH kernel interface, apart: unprefixed names, one kernel per unit
    const std::string sph_guard = "MOLLIFY_G4_" + facts.id + "_SPH_H";
    const double norm_value = round_to_double(norm);
    out += "\n#if !defined(MOLLIFY_G4_SOFTENING_ONLY) && !defined(" + sph_guard + ")\n#define " + sph_guard + "\n";
    out += "#define NORM " + s.literal(norm_value) + " /* " + hex_literal(norm_value) + ", " + comment_text(norm.to_string()) + " */\n";
    out += "#ifndef COMPUTE_WK\n#define COMPUTE_WK -1\n#define COMPUTE_WK_AND_DWK 0\n#define COMPUTE_DWK 1\n#endif\n";
    out += "static inline void kernel_main(double u, double hinv3, double hinv4, double *wk, double *dwk, int mode)\n{\n"
           "    if (mode <= COMPUTE_WK_AND_DWK) *wk = NORM * hinv3 * " + prefix + "_w(u);\n"
           "    if (mode >= COMPUTE_WK_AND_DWK) *dwk = NORM * hinv4 * " + prefix + "_dw(u);\n}\n";
    // GADGET-4's EXPLICIT_VECTORIZATION (Config.sh) calls kernel_main_vector
    // in its density and hydro loops (src/sph/density.cc, hydra.cc), four
    // neighbours at once in its vectorclass Vec4d, NORM already in the
    // hinv3 and hinv4 it passes (its stock form multiplies by them alone);
    // without it such a build stopped at an undeclared function.
    out += "#ifdef EXPLICIT_VECTORIZATION\n";
    if (vectorisable(quantities[0]) && vectorisable(quantities[1])) {
        // w and w' on four lanes: the scalar pieces' operations (bit for bit
        // kernel_main's values where the compiler fuses neither or both)
        out += vector_helpers;
        out += vector_function(prefix, prefix + "_w_v4", names[0].second, quantities[0], s);
        out += vector_function(prefix, prefix + "_dw_v4", names[1].second, quantities[1], s);
        out += "\n/* GADGET-4's four-lane form (EXPLICIT_VECTORIZATION: density.cc, hydra.cc; Vec4d from its vectorclass),\n"
               "   NORM in hinv3 and hinv4 as its callers pass them */\n"
               "static inline void kernel_main_vector(Vec4d u, Vec4d hinv3, Vec4d hinv4, Vec4d *wk, Vec4d *dwk)\n{\n"
               "    *wk = hinv3 * " + prefix + "_w_v4(u);\n    *dwk = hinv4 * " + prefix + "_dw_v4(u);\n}\n";
    } else {
        out += "/* GADGET-4's four-lane form (EXPLICIT_VECTORIZATION: density.cc, hydra.cc; Vec4d from its vectorclass),\n"
               "   NORM in hinv3 and hinv4 as its callers pass them: each lane by the scalar form's functions\n"
               "   (" + facts.spec + "'s pieces are not few polynomials, which four lanes could share) */\n"
               "static inline void kernel_main_vector(Vec4d u, Vec4d hinv3, Vec4d hinv4, Vec4d *wk, Vec4d *dwk)\n{\n"
               "    double x[4], h3[4], h4[4], w[4], dw[4];\n    int i;\n"
               "    u.store(x);\n    hinv3.store(h3);\n    hinv4.store(h4);\n"
               "    for (i = 0; i < 4; ++i) {\n"
               "        w[i] = h3[i] * " + prefix + "_w(x[i]);\n"
               "        dw[i] = h4[i] * " + prefix + "_dw(x[i]);\n    }\n"
               "    wk->load(w);\n    dwk->load(dw);\n}\n";
    }
    out += "#endif\n#endif\n";
    return {{"gadget4/" + facts.id + ".h", out}};
}

}  // namespace mollify::gen
