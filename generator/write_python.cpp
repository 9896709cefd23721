// --target python: one Python 3 module per kernel and dimension,
// python/<prefix>.py, for NumPy: the kernel's constants as floats (from
// their hex literals, exact) with their exact values beside them and as
// attributes (fractions.Fraction where rational, else the closed form as
// text), and a vectorised function per quantity in mollify's convention:
// <q>(r) (h = 1) and <q>_h(r, h) = h^p f(r/h), r and h anything NumPy
// broadcasts, evaluated in the runtime's Precision::fast form
// (target_code.hpp) piece by piece on the points of each piece. NumPy has
// no fused multiply-add: (a h - r)/h and (r - c h)/h round c h first (as the
// runtime does without an FMA).
#include "target.hpp"
#include "target_code.hpp"

#include "rounding.hpp"

namespace mollify::gen {

namespace {

const char* python_helpers = R"py(

# The evaluation helpers of mollify's Precision::fast form
# (include/mollify/detail/evaluate.hpp).
def _horner(first, n, v):
    y = np.full(np.shape(v), C[first + n - 1])
    for k in range(first + n - 2, first - 1, -1):
        y = y * v + C[k]
    return y


def _shifted(r, h, centre, centre_lo):
    # r/h - centre of a Taylor piece, the centre's own rounding after
    return (r - centre * h) / h - centre_lo


def _to_edge(r, h, a):
    # (a h - r)/h: the distance to a combination's inner radius a
    return (a * h - r) / h


def _sqrt_s(q, e):
    # S = sqrt(1 - q^2) from the accurate edge distance e = 1 - q
    return np.sqrt(e * (1 + q))


def _arcsech(q, e):
    # log((1 + S)/q): two positive logs near 0, log1p of a small number near 1
    s = _sqrt_s(q, e)
    return np.where(q < 0.5, np.log1p(s) - np.log(q), np.log1p((e + s) / q))


def _log_q(q, e):
    return np.where(q < 0.5, np.log(q), np.log1p(-e))


def _times_arcsech(x, q, e):
    # x carries a positive power of q: the limit 0 at q = 0
    return np.where(q == 0, 0.0, x * _arcsech(q, e))


def _times_log(x, q, e):
    return np.where(q == 0, 0.0, x * _log_q(q, e))


def _at_origin(x, limit):
    # a quantity singular at r = 0: its limit (+-inf) where its terms give inf - inf or 0 * inf
    return np.where(np.isnan(x), limit, x)


def _arcsin(q, e):
    # atan2(q, S): asin would magnify the rounding of q by 1/S near q = 1
    return np.arctan2(q, _sqrt_s(q, e))


def _near_origin(r, h, p, low, a, b):
    # f_h(r) = h^p f(r/h) of a quantity singular at r = 0, where r/h < 2^-150: its leading order
    # h^p q^low (a + b log q) (the terms beyond it are below 2^-150 of it), with q = m 2^e and
    # h = mh 2^eh taken apart so that neither q^low nor h^p overflows alone (f(r/h) first
    # overflows below r/h ~ 1e-100 where f_h is finite for a large h)
    mr, er = np.frexp(r)
    mh, eh = np.frexp(h)
    m, e = mr / mh, er - eh
    f = a + b * (np.log(m) + e * _LOG_2) if b != 0 else np.full(np.shape(m), a)
    return np.ldexp(f * m ** float(low) * mh ** float(p), e * low + eh * p)


def _arguments(r, h):
    r = np.asarray(r, dtype=np.float64)
    h = np.asarray(h, dtype=np.float64)
    bad = r[~(r >= 0)]
    if bad.size:
        raise ValueError(f"r = {bad.flat[0]!r} is not a radius (r >= 0)")
    bad = h[~((h > 0) & np.isfinite(h))]
    if bad.size:
        raise ValueError(f"h = {bad.flat[0]!r} is not a smoothing length (finite h > 0)")
    return np.broadcast_arrays(r, h)


def _evaluate(r, h, quantity):
    lows, pieces, exterior, scale_power, log_h_index, near_origin = quantity
    r, h = _arguments(r, h)
    out = np.empty(r.shape)
    with np.errstate(all="ignore"):  # np.where evaluates both sides; the chosen one is finite
        outside = r > h
        out[outside] = exterior(r[outside])
        inside = ~outside
        ri, hi = r[inside], h[inside]
        q = ri / hi
        e = (hi - ri) / hi
        index = np.searchsorted(lows, q, side="right")  # piece p: lows[p - 1] <= q < lows[p]
        x = np.empty(q.shape)
        for p, piece in enumerate(pieces):
            m = index == p
            if np.any(m):
                x[m] = piece(q[m], e[m], ri[m], hi[m])
        x = x * hi ** float(scale_power)
        if log_h_index is not None:
            x = x + C[log_h_index] * np.log(hi)
        out[inside] = x
        if near_origin is not None:  # singular at 0: its leading order below r/h = 2^-150
            near = (r > 0) & (r < NEAR_ORIGIN_BOUND * h)
            if np.any(near):
                out[near] = _near_origin(r[near], h[near], scale_power, *near_origin)
    return out[()] if out.ndim == 0 else out
)py";

Syntax python_syntax() {
    Syntax s;
    s.constant = [](std::size_t i) { return "C[" + std::to_string(i) + "]"; };
    s.horner = [](std::size_t first, std::size_t n, const std::string& v) {
        return "_horner(" + std::to_string(first) + ", " + std::to_string(n) + ", " + v + ")";
    };
    s.power = [](const std::string& x, int n) { return n == 1 ? x : x + " ** " + (n < 0 ? "(" + std::to_string(n) + ")" : std::to_string(n)); };
    s.literal = [](double x) { return x == 0 && !std::signbit(x) ? std::string("0.0") : "float.fromhex(\"" + hex_literal(x) + "\")"; };
    s.call = [](const std::string& name, const std::vector<std::string>& args) {
        std::string out = "_" + name + "(";
        for (std::size_t i = 0; i < args.size(); ++i) out += (i ? ", " : "") + args[i];
        return out + ")";
    };
    s.log = "np.log";
    s.infinity = "np.inf";
    return s;
}

std::string python_string(const std::string& s) {
    std::string out = "\"";
    for (char c : s) out += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
    return out + "\"";
}

std::string fraction(const Q& q) { return "Fraction(" + numerator(q).str() + ", " + denominator(q).str() + ")"; }

// A Fraction where the exact value is rational; a sum q pi^e log p as the
// tuple of its terms (Fraction(q), e, p) (p = 1: no logarithm); else (a
// Taylor coefficient with arcsech, arcsin or square roots of its centre)
// the closed form as text.
std::string exact_attribute(const CodeConstant& c) {
    if (!c.exact_value) return python_string(c.exact);
    if (c.exact_value->is_rational()) return fraction(c.exact_value->rational());
    std::string out = "(";
    for (const auto& [atom, q] : c.exact_value->terms())
        out += "(" + fraction(q) + ", " + std::to_string(atom.pi_power) + ", " + std::to_string(atom.log_of) + "), ";
    return out + ")";
}

std::string quantity_code(const CodeQuantity& q, const Syntax& s) {
    std::string out, pieces;
    for (std::size_t p = 0; p < q.inside.size(); ++p) {
        const std::string name = "_" + q.name + "_" + std::to_string(p);
        out += "\n\ndef " + name + "(q, e, r, h):\n    # " + q.inside[p].note + "\n";
        out += "    return (" + inside_piece(s, q, p) + ")\n";
        pieces += name + ", ";
    }
    out += "\n\ndef _" + q.name + "_exterior(r):\n";
    out += q.exterior.terms.empty() ? "    return np.zeros_like(r)\n" : "    return (" + piece_sum(s, q.exterior, true) + ")\n";
    std::string lows;
    for (std::size_t p = 1; p < q.inside.size(); ++p) lows += s.literal(q.inside[p].lo) + ", ";
    const std::string table = "_" + q.name;
    std::string near_origin = "None";
    if (q.near_origin) {
        const CodeQuantity::NearOrigin& o = *q.near_origin;
        out += "\n\n# Below r/h = 2^-150: h^p q^" + std::to_string(o.low) + " (a + b log q), a = " + o.plain.exact + ", b = " +
               o.logarithm.exact + "\n";
        near_origin = "(" + std::to_string(o.low) + ", " + s.literal(o.plain.value) + ", " + s.literal(o.logarithm.value) + ")";
    }
    out += "\n\n" + table + " = (np.array([" + lows + "]), (" + pieces + "), _" + q.name + "_exterior, " +
           std::to_string(q.scale_power) + ", " + (q.log_h_coefficient ? std::to_string(*q.log_h_coefficient) : "None") + ", " + near_origin + ")\n";
    out += "\n\ndef " + q.name + "_h(r, h):\n    \"\"\"" + quantity_description(q.id) + ": f_h(r) = h^(" +
           std::to_string(q.scale_power) + ") f(r/h)" + (q.log_h_coefficient ? " + log(h)/(2 pi)" : "") +
           "; ValueError for r < 0 or h not finite > 0.\"\"\"\n";
    out += "    return _evaluate(r, h, " + table + ")\n";
    out += "\n\ndef " + q.name + "(r):\n    \"\"\"The same for h = 1.\"\"\"\n    return " + q.name + "_h(r, 1.0)\n";
    return out;
}

}  // namespace

TargetFiles write_python(const TargetKernel& tk, const std::string& command) {
    const CodeKernel k = code_kernel(tk);
    const Syntax s = python_syntax();
    std::string out = banner(command, "#");
    out += "\"\"\"" + k.spec + " in D = " + std::to_string(k.dim) + ": " + tk.facts.kernel.source + "\n\n";
    out += "mollify's convention: support radius h (q = r/h <= 1), W_h(r) = h^-" + std::to_string(k.dim) +
           " W(r/h), unit mass;\n" + tk.convention.potential.description +
           ".\n<quantity>(r) is h = 1, <quantity>_h(r, h) any h (NumPy broadcasting). Evaluated as mollify's\n"
           "Precision::fast. Each constant is correctly rounded, its exact value beside it and in C_EXACT:\n"
           "a Fraction where rational, a tuple of terms (Fraction(q), e, p) for a sum of q pi^e log(p)\n"
           "(p = 1: no logarithm), else the closed form as text.\n\"\"\"\n";
    out += "from fractions import Fraction\n\nimport numpy as np\n\n";
    out += "SPEC = " + python_string(k.spec) + "\nDIM = " + std::to_string(k.dim) + "\n";
    out += "NORMALISATION = float.fromhex(\"" + hex_literal(k.normalisation.value) + "\")  # " + k.normalisation.exact + "\n";
    out += "NORMALISATION_EXACT = " + exact_attribute(k.normalisation) + "\n\n";
    out += "# The coefficients of every piece, in order (quantity, piece, term, power).\nC = np.array([\n";
    for (std::size_t i = 0; i < k.constants.size(); ++i)
        out += "    float.fromhex(\"" + hex_literal(k.constants[i].value) + "\"),  # [" + std::to_string(i) + "] " +
               k.constants[i].exact + "\n";
    out += "])\n# Their exact values (see above).\nC_EXACT = (\n";
    for (std::size_t i = 0; i < k.constants.size(); ++i) out += "    " + exact_attribute(k.constants[i]) + ",\n";
    out += ")\n";
    out += "# Below this r/h a quantity singular at 0 is its leading order (_near_origin); log(2).\n";
    out += "NEAR_ORIGIN_BOUND = float.fromhex(\"" + hex_literal(detail::near_origin_bound) + "\")\n";
    out += "_LOG_2 = float.fromhex(\"" + hex_literal(round_to_double(Exact::log_of(Q(2)))) + "\")  # log(2)\n";
    out += std::string(python_helpers);
    std::string names;
    for (const CodeQuantity& q : k.quantities) {
        out += quantity_code(q, s);
        names += "    \"" + q.name + "\",\n";
    }
    out += "\n\nQUANTITIES = (\n" + names + ")\n";
    return {{"python/" + k.prefix + ".py", out}};
}

}  // namespace mollify::gen
