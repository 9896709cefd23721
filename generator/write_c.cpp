// --target c: one C99 header per kernel and dimension, c/<prefix>.h, with
// the kernel's constants as static const doubles (correctly rounded hex
// literals, the exact value beside each) and a static inline function per
// quantity in mollify's convention (conventions.hpp, "c"): <prefix>_<q>(r)
// for h = 1 and <prefix>_<q>_h(r, h) = h^p f(r/h), evaluated in the
// runtime's Precision::fast form (target_code.hpp).
#include "c_code.hpp"
#include "target.hpp"
#include "target_code.hpp"

#include "error.hpp"
#include "rounding.hpp"

#include <cctype>

namespace mollify::gen {

// Shared by every header: defined once per translation unit.
const char* const c_helpers = R"(#ifndef MOLLIFY_C_HELPERS_1
#define MOLLIFY_C_HELPERS_1
/* The evaluation helpers of mollify's Precision::fast form
   (include/mollify/detail/evaluate.hpp), shared by every kernel header. */
static inline double mollify_c_horner(const double *c, int n, double v) {
    double y = c[n - 1];
    int k;
    for (k = n - 2; k >= 0; --k) y = y * v + c[k];
    return y;
}
/* x^n by binary powering, |n| < 256 (the writers emit no larger power): eight steps whatever n,
   so that a compiler unrolls them for a constant n and can vectorise a loop around the call */
static inline double mollify_c_ipow(double x, int n) {
    double y = 1.0, b = x;
    int m = n < 0 ? -n : n, k;
    for (k = 0; k < 8; ++k) {
        if (m & 1) y *= b;
        b *= b;
        m >>= 1;
    }
    return n < 0 ? 1.0 / y : y;
}
/* r/h - centre of a Taylor piece: one rounding of r - c h (FMA), then the centre's own rounding c_lo */
static inline double mollify_c_shifted(double r, double h, double c, double c_lo) {
    return fma(-c, h, r) / h - c_lo;
}
/* (a h - r)/h: the distance to a combination's inner radius a, one rounding of a h - r */
static inline double mollify_c_to_edge(double r, double h, double a) { return fma(a, h, -r) / h; }
/* S = sqrt(1 - q^2) from the accurate edge distance e = 1 - q */
static inline double mollify_c_sqrt_s(double q, double e) { return sqrt(e * (1 + q)); }
/* arcsech q = log((1 + S)/q): two positive logs near 0, log1p of a small number near 1 */
static inline double mollify_c_arcsech(double q, double e) {
    const double s = mollify_c_sqrt_s(q, e);
    return q < 0.5 ? log1p(s) - log(q) : log1p((e + s) / q);
}
static inline double mollify_c_log_q(double q, double e) { return q < 0.5 ? log(q) : log1p(-e); }
/* x arcsech q and x log q where x carries a positive power of q: the limit 0 at q = 0 */
/* (q >= 0 here: q <= 0 is q == 0, without a floating-point equality that -Wfloat-equal flags) */
static inline double mollify_c_times_arcsech(double x, double q, double e) {
    return q <= 0 ? 0.0 : x * mollify_c_arcsech(q, e);
}
static inline double mollify_c_times_log(double x, double q, double e) { return q <= 0 ? 0.0 : x * mollify_c_log_q(q, e); }
/* arcsin q as atan2(q, S): asin would magnify the rounding of q by 1/S near q = 1 */
static inline double mollify_c_arcsin(double q, double e) { return atan2(q, mollify_c_sqrt_s(q, e)); }
#endif
)";

// mollify's own C files only (the drop-in files of other codes have no
// quantity singular at r = 0): a guard of its own, so that headers written
// before it still combine with these.
const char* const c_at_origin_helper = R"(#ifndef MOLLIFY_C_AT_ORIGIN
#define MOLLIFY_C_AT_ORIGIN
/* A quantity singular at r = 0: its limit (+-inf) where its terms give inf - inf or 0 * inf */
static inline double mollify_c_at_origin(double x, double limit) { return isnan(x) ? limit : x; }
#endif
)";

namespace {

// The same, for quantities singular at 0 below r/h = 2^-150 (target_code.hpp,
// CodeQuantity::near_origin); @LOG2@ is log 2, correctly rounded.
const char* const c_near_origin_helper = R"(#ifndef MOLLIFY_C_NEAR_ORIGIN
#define MOLLIFY_C_NEAR_ORIGIN
/* f_h(r) = h^p f(r/h) of a quantity singular at r = 0, where r/h < 2^-150: its leading order
   h^p q^low (a + b log q) (the terms beyond it are below 2^-150 of it), with q = m 2^e and
   h = mh 2^eh taken apart so that neither q^low nor h^p overflows alone (f(r/h) first overflows
   below r/h ~ 1e-100 where f_h is finite for a large h) */
static inline double mollify_c_near_origin(double r, double h, int p, int low, double a, double b) {
    int er, eh;
    const double mr = frexp(r, &er), mh = frexp(h, &eh), m = mr / mh;
    const int e = er - eh;
    const double f = a + b * (log(m) + e * @LOG2@); /* log(2); m in (1/2, 2) as r > 0: b = 0 adds 0 */
    return ldexp(f * mollify_c_ipow(m, low) * mollify_c_ipow(mh, p), e * low + eh * p);
}
#endif
)";

std::string c_near_origin_helper_text() {
    std::string s = c_near_origin_helper;
    s.replace(s.find("@LOG2@"), 6, hex_literal(round_to_double(Exact::log_of(Q(2)))));
    return s;
}

}  // namespace

void check_c_power(int n) {
    if (n <= -256 || n >= 256) fail("internal: a power " + std::to_string(n) + " beyond mollify_c_ipow's eight steps");
}

Syntax c_syntax(const std::string& prefix) {
    Syntax s;
    s.constant = [prefix](std::size_t i) { return prefix + "_c[" + std::to_string(i) + "]"; };
    s.horner = [prefix](std::size_t first, std::size_t n, const std::string& v) {
        return "mollify_c_horner(" + prefix + "_c + " + std::to_string(first) + ", " + std::to_string(n) + ", " + v + ")";
    };
    s.power = [](const std::string& x, int n) {
        check_c_power(n);
        return n == 1 ? x : "mollify_c_ipow(" + x + ", " + std::to_string(n) + ")";
    };
    s.literal = [](double x) { return hex_literal(x); };
    s.call = [](const std::string& name, const std::vector<std::string>& args) {
        std::string out = "mollify_c_" + name + "(";
        for (std::size_t i = 0; i < args.size(); ++i) out += (i ? ", " : "") + args[i];
        return out + ")";
    };
    s.log = "log";
    s.infinity = "(double)INFINITY";  // C's INFINITY and NAN are floats: clang's -Wdouble-promotion
    return s;
}

std::string comment_text(std::string s) {
    for (std::size_t i = s.find("*/"); i != std::string::npos; i = s.find("*/", i)) s.insert(i + 1, " ");
    return s;
}

std::string c_piece_chain(const CodeQuantity& q, const Syntax& s, const std::string& indent, const std::string& target) {
    std::string body;
    for (std::size_t p = 0; p < q.inside.size(); ++p) {
        const CodePiece& piece = q.inside[p];
        const bool last = p + 1 == q.inside.size();
        body += indent + "/* " + comment_text(piece.note) + " */\n";
        if (q.inside.size() > 1)
            body += indent + (p == 0 ? "" : last ? "else" : "else ") +
                    (last ? std::string() : "if (q < " + s.literal(q.inside[p + 1].lo) + ")") + "\n";
        body += indent + "    " + target + " = " + inside_piece(s, q, p) + ";\n";
    }
    return body;
}

std::string c_unit_function(const std::string& name, const std::string& meaning, const CodeQuantity& q, const Syntax& syntax) {
    Syntax s = syntax;
    s.unit_h = true;
    std::string out = "\n/* " + meaning + " */\nstatic inline double " + name + "(double q) {\n";
    const std::string body = c_piece_chain(q, s, "    ", "y");
    const std::string outside = piece_sum(s, q.exterior, true);
    const std::string code = without_comments(body, "/*", "*/");
    const bool r_used = uses(code, "r") || uses(outside, "r"), h_used = uses(code, "h"), e_used = uses(code, "e");
    out += "    double y;\n";
    if (r_used) out += "    const double r = q;\n";
    if (h_used) out += "    const double h = 1.0;\n";
    out += "    if (q > 1) return " + outside + ";\n";
    out += "    {\n";
    if (e_used) out += "    const double e = 1 - q;\n";
    out += body + "    }\n    return y;\n}\n";
    return out;
}

namespace {

std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return s;
}

std::string c_function(const CodeKernel& k, const CodeQuantity& q, const Syntax& s) {
    const std::string name = k.prefix + "_" + q.name;
    std::string out = "\n/* " + quantity_description(q.id) + ": f_h(r) = h^(" + std::to_string(q.scale_power) +
                      ") f(r/h)" + (q.log_h_coefficient ? " + log(h)/(2 pi)" : "") + " */\n";
    out += "static inline double " + name + "_h(double r, double h) {\n";
    out += "    if (!(r >= 0) || !(h > 0) || isinf(h)) return (double)NAN; /* r >= 0 and a finite h > 0 */\n";
    if (q.near_origin) {
        const CodeQuantity::NearOrigin& o = *q.near_origin;
        check_c_power(q.scale_power);
        check_c_power(o.low);
        out += "    if (r > 0 && r < " + hex_literal(detail::near_origin_bound) + " * h) /* below r/h = 2^-150: h^p q^" +
               std::to_string(o.low) + " (a + b log q) */\n";
        out += "        return mollify_c_near_origin(r, h, " + std::to_string(q.scale_power) + ", " + std::to_string(o.low) +
               ", " + hex_literal(o.plain.value) + " /* " + comment_text(o.plain.exact) + " */, " +
               hex_literal(o.logarithm.value) + " /* " + comment_text(o.logarithm.exact) + " */);\n";
    }
    out += "    if (r > h) return " + piece_sum(s, q.exterior, true) + ";\n";
    const std::string body = c_piece_chain(q, s, "        ", "x");
    out += "    {\n";
    const std::string code = without_comments(body, "/*", "*/");
    if (uses(code, "q")) out += "        const double q = r / h;\n";
    if (uses(code, "e")) out += "        const double e = (h - r) / h;\n";
    out += "        double x;\n" + body;
    out += "        x *= pow(h, " + std::to_string(q.scale_power) + ");\n";
    if (q.log_h_coefficient) out += "        x += " + s.constant(*q.log_h_coefficient) + " * log(h);\n";
    out += "        return x;\n    }\n}\n";
    out += "static inline double " + name + "(double r) { return " + name + "_h(r, 1.0); }\n";
    return out;
}

}  // namespace

TargetFiles write_c(const TargetKernel& tk, const std::string& command) {
    const CodeKernel k = code_kernel(tk);
    const Syntax s = c_syntax(k.prefix);
    const std::string guard = upper(k.prefix) + "_H";
    std::string out = "/*\n" + banner(command, " *");
    out += " *\n * " + k.spec + " in D = " + std::to_string(k.dim) + ": " + tk.facts.kernel.source + "\n";
    out += " * mollify's convention: support radius h (q = r/h <= 1), W_h(r) = h^-" + std::to_string(k.dim) +
           " W(r/h), unit mass;\n"
           " * " + tk.convention.potential.description + ".\n"
           " * <prefix>_<quantity>(r) is h = 1, <prefix>_<quantity>_h(r, h) any h; r >= 0, h > 0 finite (else NaN).\n"
           " * Evaluated as mollify's Precision::fast (factored at the support edge; README, \"Kernel files for\n"
           " * other languages\"). Each constant is correctly rounded, its exact value beside it.\n */\n";
    out += "#ifndef " + guard + "\n#define " + guard + "\n\n#include <math.h>\n\n" + c_helpers + c_at_origin_helper;
    bool near_origin = false;
    for (const CodeQuantity& q : k.quantities) near_origin = near_origin || q.near_origin.has_value();
    if (near_origin) out += c_near_origin_helper_text();
    out += "\n";
    out += "enum { " + k.prefix + "_dim = " + std::to_string(k.dim) + " };\n";
    out += "static const double " + k.prefix + "_normalisation = " + hex_literal(k.normalisation.value) + "; /* " +
           comment_text(k.normalisation.exact) + " */\n";
    out += "/* The coefficients of every piece, in order (quantity, piece, term, power). */\n";
    out += "static const double " + k.prefix + "_c[" + std::to_string(k.constants.size()) + "] = {\n";
    for (std::size_t i = 0; i < k.constants.size(); ++i)
        out += "    " + hex_literal(k.constants[i].value) + ", /* [" + std::to_string(i) + "] " + comment_text(k.constants[i].exact) + " */\n";
    out += "};\n";
    for (const CodeQuantity& q : k.quantities) out += c_function(k, q, s);
    out += "\n#endif\n";
    return {{"c/" + k.prefix + ".h", out}};
}

}  // namespace mollify::gen
