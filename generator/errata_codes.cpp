// `mollify-gen errata --codes` (errata_codes.hpp). A code writes its kernel
// as W(r, h) = C pi^p h^-D w(q), q = r/h, support R h, and its gradient as
// grad W = C' pi^p' h^-(D+2) G(q) x. mollify's kernel K of the entry's spec
// has support 1 and unit mass, so the code is right when
//   C pi^p w(q) = K(q/R) / R^D   and   C' pi^p' G(q) = K'(q/R) / (R^(D+1) q).
// Both sides are compared piece by piece as exact polynomials in s = q/R;
// their ratio, when it is c s^k on every piece, is the diagnosis.
#include "errata_codes.hpp"

#include "conventions.hpp"
#include "decimal.hpp"
#include "errata_checker.hpp"
#include "error.hpp"
#include "kernel.hpp"
#include "rounding.hpp"
#include "softening.hpp"

#include <gmp.h>
#include <mpfr.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <tuple>

namespace mollify::gen {

int CodeErrataReport::wrong() const {
    return static_cast<int>(std::count_if(verdicts.begin(), verdicts.end(), [](const CodeVerdict& v) { return !v.right; }));
}

std::string format_line(const CodeVerdict& v) {
    return v.code + " | " + v.source + " | " + v.entry + " | published: " + v.published + " | exact: " + v.exact +
           " | published/exact: " + v.ratio + " | " + v.diagnosis;
}

namespace {

namespace fs = std::filesystem;
using errata::Coefficients;
using errata::Entry;
using errata::json;

// ---------------------------------------------------------------------------
// Constants q * pi^e

struct PiQ {
    Q q;
    int pi = 0;
    friend bool operator==(const PiQ& a, const PiQ& b) { return a.q == b.q && a.pi == b.pi; }
};

Exact exact_of(const PiQ& c) { return Exact::pi_power(c.q, c.pi); }

std::optional<PiQ> single(const Exact& e) {
    if (e.terms().size() != 1) return std::nullopt;
    const auto& [atom, q] = *e.terms().begin();
    if (atom.log_of != 1) return std::nullopt;
    return PiQ{q, atom.pi_power};
}

std::optional<PiQ> quotient(const Exact& a, const Exact& b) {
    const auto x = single(a), y = single(b);
    if (!x || !y) return std::nullopt;
    return PiQ{x->q / y->q, x->pi - y->pi};
}

std::string ratio_string(const PiQ& c) {
    std::string s = short_string(c.q);
    if (c.pi != 0) s += " pi^" + std::to_string(c.pi);
    return s;
}

// "c q^k" for people: "360/359", "q^-1", "q", "16/21 q^2".
std::string monomial_string(const PiQ& c, int k) {
    if (k == 0) return ratio_string(c);
    const std::string q = k == 1 ? "q" : "q^" + std::to_string(k);
    return c == PiQ{Q(1), 0} ? q : ratio_string(c) + " " + q;
}

// The rational gamma with gamma^n = x (x > 0), if there is one.
std::optional<Q> rational_root(const Q& x, int n) {
    if (x <= 0) return std::nullopt;
    auto root = [n](const Z& z) -> std::optional<Z> {
        Z r;
        if (mpz_root(r.backend().data(), z.backend().data(), static_cast<unsigned long>(n)) == 0) return std::nullopt;
        return r;
    };
    const auto p = root(numerator(x)), q = root(denominator(x));
    if (!p || !q) return std::nullopt;
    return Q(*p) / Q(*q);
}

// ---------------------------------------------------------------------------
// The published shape: sum of terms coeff * prod (a + b q)^n on [from, to)

struct Factor {
    Q a, b;
    int n = 1;
};

struct Term {
    Q coeff;
    std::vector<Factor> factors;
    Q from, to;
};

struct Shape {
    std::vector<Term> terms;
    Q support;  // the largest `to`
};

Shape read_shape(const Entry& e, const json& printed) {
    const json& arr = e.need(printed, "shape", "printed");
    if (!arr.is_array() || arr.empty()) e.bad("field 'printed.shape' must be a non-empty array of terms");
    Shape s;
    for (std::size_t i = 0; i < arr.size(); ++i) {
        const std::string path = "printed.shape[" + std::to_string(i) + "]";
        const json& t = arr[i];
        if (!t.is_object()) e.bad("field '" + path + "' must be an object");
        Term term;
        term.coeff = e.rational(t, "coeff", path);
        term.from = t.contains("from") ? e.rational(t, "from", path) : Q(0);
        term.to = e.rational(t, "to", path);
        if (term.from < 0 || term.to <= term.from)
            e.bad("field '" + path + "': need 0 <= from < to, got [" + short_string(term.from) + ", " +
                  short_string(term.to) + ")");
        const json& fs = e.need(t, "factors", path);
        if (!fs.is_array()) e.bad("field '" + path + ".factors' must be an array of [a, b, n] for (a + b q)^n");
        for (std::size_t j = 0; j < fs.size(); ++j) {
            const std::string fp = path + ".factors[" + std::to_string(j) + "]";
            const json& f = fs[j];
            if (!f.is_array() || f.size() != 3 || !f[2].is_number_integer())
                e.bad("field '" + fp + "' must be [a, b, n]: (a + b q)^n with a, b rationals and n an integer");
            Factor fac{e.rational(f[0], fp + "[0]"), e.rational(f[1], fp + "[1]"), f[2].get<int>()};
            if (fac.b == 0) e.bad("field '" + fp + "': b = 0 (write a constant into coeff)");
            if (fac.a != 0 && fac.n < 0) e.bad("field '" + fp + "': only q itself may have a negative power");
            term.factors.push_back(fac);
        }
        s.support = std::max(s.support, term.to);
        s.terms.push_back(term);
    }
    return s;
}

// The term as a polynomial in s, q = scale * s.
Laurent term_polynomial(const Term& t, const Q& scale) {
    Laurent p(t.coeff);
    for (const Factor& f : t.factors)
        p = p * (f.a == 0 ? Laurent::monomial(pow(f.b * scale, f.n), f.n) : Laurent::binomial_power(f.a, f.b * scale, f.n));
    return p;
}

// The shape as a radial function of s = q / scale.
Radial shape_radial(const Shape& shape, const Q& scale) {
    std::set<Q> cuts{Q(0)};
    for (const Term& t : shape.terms) cuts.insert({t.from / scale, t.to / scale});
    Radial r;
    r.breaks.assign(cuts.begin(), cuts.end());
    r.pieces.clear();
    for (std::size_t i = 0; i + 1 < r.breaks.size(); ++i) {
        Laurent p;
        for (const Term& t : shape.terms)
            if (t.from / scale <= r.breaks[i] && r.breaks[i + 1] <= t.to / scale) p += term_polynomial(t, scale);
        r.pieces.push_back(ClosedForm(p));
    }
    return r;
}

// ---------------------------------------------------------------------------
// Piecewise comparison: p = c s^k x on every piece (the same c and k)?

struct Monomial {
    PiQ c;
    int k = 0;
};

ClosedForm piece_at(const Radial& f, const Q& lo) { return lo >= f.support() ? f.outside : f.form_at(lo); }

std::optional<Monomial> monomial_ratio(const Radial& p, const Radial& x) {
    std::set<Q> cuts(p.breaks.begin(), p.breaks.end());
    cuts.insert(x.breaks.begin(), x.breaks.end());
    const std::vector<Q> b(cuts.begin(), cuts.end());
    std::optional<Monomial> found;
    for (std::size_t i = 0; i + 1 < b.size(); ++i) {
        const Coefficients P = errata::coefficients(piece_at(p, b[i]));
        const Coefficients X = errata::coefficients(piece_at(x, b[i]));
        if (P.empty() && X.empty()) continue;
        if (P.empty() || X.empty() || P.size() != X.size()) return std::nullopt;
        const int k = P.begin()->first - X.begin()->first;
        std::optional<PiQ> c;
        for (auto ip = P.begin(), ix = X.begin(); ip != P.end(); ++ip, ++ix) {
            const auto r = quotient(ip->second, ix->second);
            if (ip->first - ix->first != k || !r || (c && !(*c == *r))) return std::nullopt;
            c = r;
        }
        if (found && (found->k != k || !(found->c == *c))) return std::nullopt;
        found = Monomial{*c, k};
    }
    return found;
}

// ---------------------------------------------------------------------------
// The exact side

// Kernels a code's published shape or gradient may turn out to be.
const std::vector<std::string>& candidate_specs() {
    static const std::vector<std::string> specs = {
        "poly6",        "spiky",        "viscosity",    "cubic-spline", "quartic-spline", "quintic-spline",
        "wendland:k=0", "wendland:k=1", "wendland:k=2", "wendland:k=3", "mollifier:M=1",  "mollifier:M=2",
        "mollifier:M=3", "mollifier:M=4",
    };
    return specs;
}

class CodeChecker {
public:
    explicit CodeChecker(CodeErrataReport& report) : report_(report) {}

    void check(const Entry& e, const std::string& code, const std::string& source) {
        CodeVerdict v{code, source, e.label, "", "", "", "", false};
        if (!e.boolean(*e.object, "seen", "")) {
            v.published = e.text(*e.object, "expression", "");
            v.exact = v.ratio = "-";
            v.diagnosis = "not checked: the source was not seen";
            v.right = true;  // nothing claimed
            report_.verdicts.push_back(v);
            return;
        }
        if (e.quantity == "code.normalisation") normalisation(e, v);
        else if (e.quantity == "code.gradient") gradient(e, v);
        else if (e.quantity == "code.h_power") h_power(e, v);
        else if (e.quantity == "code.gamma") gamma(e, v);
        else if (e.quantity == "code.coefficients") coefficients(e, v);
        else if (e.quantity == "code.potential_h_derivative") potential_h_derivative(e, v);
        else e.bad("unknown quantity '" + e.quantity +
                   "' (code.normalisation, code.gradient, code.h_power, code.gamma, code.coefficients, "
                   "code.potential_h_derivative)");
        report_.verdicts.push_back(v);
    }

private:
    // mollify's kernel of `spec` in `dim`: support 1, unit mass.
    const Radial& unit_kernel(const std::string& spec, int dim) {
        const auto key = std::make_pair(spec, dim);
        auto it = kernels_.find(key);
        if (it != kernels_.end()) return it->second;
        const Radial k = make_kernel(parse_spec(spec), dim).W;
        return kernels_.emplace(key, k).first->second;
    }

    // K'(s) / s: grad K = (K'(s)/s) x.
    const Radial& unit_grad_over_r(const std::string& spec, int dim) {
        const auto key = std::make_pair(spec, dim);
        auto it = grads_.find(key);
        if (it != grads_.end()) return it->second;
        return grads_.emplace(key, unit_kernel(spec, dim).derivative().times(Laurent::monomial(Q(1), -1)))
            .first->second;
    }

    struct Setting {
        std::string spec;
        int dim;
        Q support;
        Shape shape;
        PiQ constant;
        std::optional<Q> reading;  // what a printed decimal stands for
        std::string constant_text;
        bool folded = false;  // the decimal approximates constant * pi^pi_power (pi folded in)
    };

    Setting read_setting(const Entry& e) {
        Setting s;
        s.spec = e.param_text("spec");
        s.dim = e.param("dim");
        (void)entry_kernel(e);  // dim and spec checked
        s.support = e.rational(e.params(), "support", "params");
        const json& printed = e.printed();
        s.shape = read_shape(e, printed);
        if (s.shape.support != s.support)
            e.bad("field 'printed.shape': support " + short_string(s.shape.support) + " disagrees with params.support " +
                  short_string(s.support));
        s.constant_text = e.text(printed, "constant", "printed");
        s.constant.q = e.rational(printed, "constant", "printed");
        s.constant.pi = e.integer(printed, "pi_power", "printed");
        s.folded = printed.contains("pi_folded") && e.boolean(printed, "pi_folded", "printed");
        if (s.folded && !decimal_unit(s.constant_text))
            e.bad("field 'printed.constant': pi_folded needs a decimal, got '" + s.constant_text + "'");
        s.reading = s.folded ? std::nullopt : decimal_reading(s.constant_text, s.constant.q);
        return s;
    }

    std::string published_text(const Setting& s) const {
        if (s.folded) return s.constant_text + " (pi folded in)";
        if (!decimal_unit(s.constant_text)) return exact_of(s.constant).to_string();
        const std::string pi = s.constant.pi == 0 ? "" : " * pi^" + std::to_string(s.constant.pi);
        if (!s.reading) return s.constant_text + pi;
        return s.constant_text + pi + " (the decimal reads " + exact_of({*s.reading, s.constant.pi}).to_string() + ")";
    }

    // The candidate kernels c * K_cand matching `f` through `of`; "" if none.
    std::string which_kernel(const Radial& f, const std::string& spec,
                             const std::function<const Radial&(const std::string&)>& of) {
        for (const std::string& cand : candidate_specs()) {
            if (cand == spec) continue;
            try {
                const auto m = monomial_ratio(f, of(cand));
                if (m && m->k == 0) {
                    std::string s = cand;
                    if (!(m->c == PiQ{Q(1), 0})) s += " (times " + ratio_string(m->c) + ")";
                    return s;
                }
            } catch (const Error&) {  // not defined in this dimension (viscosity in 1D)
            }
        }
        return "";
    }

    // Why `printed` = rho * exact for a kernel's constant in `dim`.
    std::string constant_diagnosis(const PiQ& rho, const PiQ& printed, const Setting& s) {
        if (rho == PiQ{Q(1), 0}) return "right";
        if (rho.pi != 0) return "constant factor: a factor pi^" + std::to_string(rho.pi) + " too many";
        if (rho.q == -1) return "wrong sign";
        const Radial w = shape_radial(s.shape, Q(1));  // in q, support R
        for (int d = 1; d <= 3; ++d) {
            if (d == s.dim) continue;
            const auto c = single((sphere_measure(d) * radial_integral(w, d - 1)).inverse());
            if (c && *c == printed) return "another dimension: the constant of this shape in D = " + std::to_string(d);
        }
        if (s.dim == 1 && rho.q == 2) return "normalisation: normalised over the half-line [0, R h] only (omega_1 = 1, not 2)";
        if (rho.q != 1) {
            if (const auto g = rational_root(rho.q, s.dim); g && *g != 1)
                return "support convention: a factor " + short_string(*g) + "^" + std::to_string(s.dim) +
                       ", the constant for a support " + short_string(*g) + " times the code's";
        }
        return "constant factor: wrong normalisation, published/exact = " + ratio_string(rho);
    }

    // A decimal x printed for the constant c pi^e: right when the exact value
    // rounds to it, |x - c pi^e| <= half a unit of x's last digit, decided in
    // MPFR at 320 bits (an error far below any printed digit; a value within
    // 2^-250 of a rounding boundary is reported, not guessed).
    void folded_verdict(const Setting& s, const PiQ& exact, CodeVerdict& v) {
        const Q half = *decimal_unit(s.constant_text) / 2;
        mpfr_t pi, ex, x, d, h;
        for (mpfr_ptr m : {pi, ex, x, d, h}) mpfr_init2(m, 320);
        mpfr_const_pi(pi, MPFR_RNDN);
        mpfr_pow_si(ex, pi, exact.pi, MPFR_RNDN);
        mpfr_mul_q(ex, ex, exact.q.backend().data(), MPFR_RNDN);
        mpfr_set_q(x, s.constant.q.backend().data(), MPFR_RNDN);
        mpfr_set_q(h, half.backend().data(), MPFR_RNDN);
        mpfr_sub(d, x, ex, MPFR_RNDN);
        mpfr_abs(d, d, MPFR_RNDN);
        mpfr_sub(d, d, h, MPFR_RNDN);  // <= 0: right
        const bool undecided = mpfr_zero_p(d) || mpfr_get_exp(d) < mpfr_get_exp(ex) - 250;
        const bool right = mpfr_sgn(d) <= 0;
        char shown[64];
        std::snprintf(shown, sizeof shown, "%.9g", mpfr_get_d(x, MPFR_RNDN) / mpfr_get_d(ex, MPFR_RNDN));
        const double exact_value = mpfr_get_d(ex, MPFR_RNDN);
        for (mpfr_ptr m : {pi, ex, x, d, h}) mpfr_clear(m);
        if (undecided) fail("internal: " + s.constant_text + " lies on a rounding boundary of " + exact_of(exact).to_string());
        char value[64];
        std::snprintf(value, sizeof value, "%.12g", exact_value);
        v.exact = exact_of(exact).to_string() + " = " + value + "...";
        if (v.published.empty()) v.published = s.constant_text + " (pi folded in)";
        v.right = right;
        v.ratio = right ? "1 (to the printed digits)" : shown;
        v.diagnosis = right ? "right (to the printed digits)"
                            : "constant factor: the decimal is not the exact constant rounded (published/exact = " +
                                  std::string(shown) + ")";
    }

    void normalisation(const Entry& e, CodeVerdict& v) {
        const Setting s = read_setting(e);
        v.published = published_text(s);
        const Radial ws = shape_radial(s.shape, s.support);  // w(R s)
        const Radial& K = unit_kernel(s.spec, s.dim);
        const auto m = monomial_ratio(K, ws);
        if (!m || m->k != 0) {
            const std::string other =
                which_kernel(ws, s.spec, [&](const std::string& c) -> const Radial& { return unit_kernel(c, s.dim); });
            v.exact = "-";
            v.ratio = "-";
            v.diagnosis = "mismatched kernel: the printed shape is not " + s.spec +
                          (other.empty() ? "" : "; it is " + other);
            return;
        }
        const PiQ exact{m->c.q / pow(s.support, s.dim), m->c.pi};  // K(q/R)/R^D = lambda w(q)/R^D
        v.exact = exact_of(exact).to_string();
        if (s.folded) return folded_verdict(s, exact, v);
        const PiQ used = s.reading ? PiQ{*s.reading, s.constant.pi} : s.constant;
        const PiQ rho{used.q / exact.q, used.pi - exact.pi};
        v.ratio = ratio_string(rho);
        v.diagnosis = constant_diagnosis(rho, used, s);
        if (s.reading && v.diagnosis == "right") v.diagnosis = "right (to the printed digits)";
        v.right = v.diagnosis.rfind("right", 0) == 0;
    }

    void gradient(const Entry& e, CodeVerdict& v) {
        const Setting s = read_setting(e);
        v.published = e.text(*e.object, "expression", "");
        const PiQ used = s.folded ? PiQ{Q(1), 0} : s.reading ? PiQ{*s.reading, s.constant.pi} : s.constant;
        const Radial Gs = shape_radial(s.shape, s.support) * exact_of(used);  // C pi^p G(R s)
        const Exact scale = Exact(Q(1) / pow(s.support, s.dim + 2));            // K'(s)/(R^(D+2) s)
        const Radial exact = unit_grad_over_r(s.spec, s.dim) * scale;
        v.exact = "W'(q)/q of " + s.spec + " (support " + short_string(s.support) + " h, unit mass)";
        const auto m = monomial_ratio(Gs, exact);
        if (!m) {
            const std::string other = which_kernel(Gs, s.spec, [&](const std::string& c) -> const Radial& {
                const Radial& g = unit_grad_over_r(c, s.dim);
                return scaled_.emplace_back(g * scale);
            });
            v.ratio = "not c q^k";
            v.diagnosis = other.empty() ? "gradient differs from " + s.spec + "'s (no systematic cause found)"
                                        : "mismatched pair: the gradient is that of " + other + ", the kernel " + s.spec;
            return;
        }
        if (s.folded && m->k == 0) {  // G(R s) = c * exact: the constant must be 1/c
            v.published = s.constant_text + " (pi folded in) with " + v.published;
            return folded_verdict(s, PiQ{Q(1) / m->c.q, -m->c.pi}, v);
        }
        // c s^k = c R^-k q^k
        const PiQ c{m->c.q / pow(s.support, m->k), m->c.pi};
        v.ratio = monomial_string(c, m->k);
        std::vector<std::string> why;
        if (m->k == -1) why.push_back("gradient off by q: a factor q missing (W'(q) divided by q twice)");
        else if (m->k == 1) why.push_back("gradient off by q: a factor q too many (dW/dq used where W'(q)/q belongs)");
        else if (m->k != 0) why.push_back("gradient off by q^" + std::to_string(m->k));
        if (!(c == PiQ{Q(1), 0})) why.push_back(c.q == -1 && c.pi == 0 ? "wrong sign" : "constant factor " + ratio_string(c));
        v.diagnosis = why.empty() ? (s.reading ? "right (to the printed digits)" : "right") : errata::join(why, "; ");
        v.right = why.empty();
    }

    // d phi/dh of a softened gravitational potential per unit mass (3D, G = 1;
    // adaptive softening, Price & Monaghan 2007): with support R h and
    // G_K = 4 pi phi_1 of mollify's K (-1/x outside), phi(r, h) = G_K(x)/(R h),
    // x = q/R, so d phi/dh = -(G_K + x G_K')(x) / (R h^2) (softening.hpp's
    // h-derivative; 0 outside, where -1/r does not depend on h); params.outside
    // "1/r" for a code whose potential is positive. Compared in s = q/R piece by
    // piece: a ratio c s^k as for a gradient, or else published = a exact + b
    // with constants a, b (a constant term off: the potential's -phi(0) dropped).
    void potential_h_derivative(const Entry& e, CodeVerdict& v) {
        const Setting s = read_setting(e);
        if (s.dim != 3) e.bad("field 'params.dim': the softened potential's h-derivative is 3D gravity's, got " + std::to_string(s.dim));
        const json& params = e.params();
        const std::string outside = params.contains("outside") ? e.text(params, "outside", "params") : "-1/r";
        if (outside != "-1/r" && outside != "1/r")
            e.bad("field 'params.outside' must be \"-1/r\" or \"1/r\" (the code's potential outside), got '" + outside + "'");
        v.published = e.text(*e.object, "expression", "");
        const PiQ used = s.reading ? PiQ{*s.reading, s.constant.pi} : s.constant;
        const Radial published = shape_radial(s.shape, s.support) * exact_of(used);
        const Q sign = outside == "-1/r" ? Q(1) : Q(-1);
        const Radial exact =
            softening_h_derivative(make_kernel(parse_spec(s.spec), 3)) * (sphere_measure(3) * Exact(sign / s.support));
        const std::string R = short_string(s.support);
        v.exact = (s.support == 1 ? "-(G + q G')(q) / h^2" : "-(G + x G')(x) / (" + R + " h^2), x = q/" + R) + ", G = " +
                  (sign == 1 ? "" : "-") + "4 pi phi_1 of " + s.spec + " (" + outside + " outside)";
        if (const auto m = monomial_ratio(published, exact)) {
            const PiQ c{m->c.q / pow(s.support, m->k), m->c.pi};
            v.ratio = monomial_string(c, m->k);
            v.right = m->k == 0 && c == PiQ{Q(1), 0};
            v.diagnosis = v.right ? (s.reading ? "right (to the printed digits)" : "right")
                          : m->k != 0 ? "off by q^" + std::to_string(m->k)
                          : c.q == -1 && c.pi == 0 ? "wrong sign"
                                                   : "constant factor " + ratio_string(c);
            return;
        }
        const auto ab = affine_ratio(published, exact);
        v.ratio = "not c q^k";
        if (!ab) {
            v.diagnosis = "differs from " + s.spec + "'s d phi/dh (no systematic cause found)";
            return;
        }
        const auto& [a, b, c0] = *ab;
        const bool unit = a == PiQ{Q(1), 0};
        std::vector<std::string> why;
        if (a.q == -1 && a.pi == 0) why.push_back("wrong sign");
        else if (!unit) why.push_back("a factor " + ratio_string(a));
        const Exact scaled_c0 = c0 * exact_of(a);
        const auto dropped = single(scaled_c0 * Exact(Q(-1)));
        why.push_back(dropped && *dropped == b
                          ? "the constant term " + c0.to_string() + " (-phi(0) h, the potential at the centre) missing"
                          : "the constant term off by " + exact_of(b).to_string());
        v.ratio = "published = " + (unit ? std::string() : ratio_string(a) + " ") + "exact + (" + exact_of(b).to_string() + ") h^-2";
        v.diagnosis = errata::join(why, "; ") + ": " + exact_of(b).to_string() +
                      " h^-2 at the support's edge, where d phi/dh is 0 (continuous with the outside's)";
    }

    // published = a exact + b on every piece of the support, a and b constants (q pi^e), and the
    // exact constant term at q = 0; nothing where no such a, b exist.
    static std::optional<std::tuple<PiQ, PiQ, Exact>> affine_ratio(const Radial& p, const Radial& x) {
        std::set<Q> cuts(p.breaks.begin(), p.breaks.end());
        cuts.insert(x.breaks.begin(), x.breaks.end());
        const std::vector<Q> br(cuts.begin(), cuts.end());
        std::optional<PiQ> a, b;
        std::optional<Exact> centre;
        for (std::size_t i = 0; i + 1 < br.size() && br[i] < x.support(); ++i) {
            Coefficients P = errata::coefficients(piece_at(p, br[i]));
            const Coefficients X = errata::coefficients(piece_at(x, br[i]));
            if (!centre) centre = X.count(0) ? X.at(0) : Exact();
            for (const auto& [k, c] : X) {
                if (k == 0) continue;
                const auto it = P.find(k);
                const auto r = it == P.end() ? std::nullopt : quotient(it->second, c);
                if (!r || (a && !(*a == *r))) return std::nullopt;
                a = r;
            }
            for (const auto& [k, c] : P)
                if (k != 0 && !X.count(k)) return std::nullopt;
            if (!a) return std::nullopt;
            const Exact rest = (P.count(0) ? P.at(0) : Exact()) - (X.count(0) ? X.at(0) : Exact()) * exact_of(*a);
            const auto r = rest.terms().empty() ? std::optional<PiQ>(PiQ{Q(0), 0}) : single(rest);
            if (!r || (b && !(*b == *r))) return std::nullopt;
            b = r;
        }
        if (!a || !b || b->q == 0) return std::nullopt;
        return std::make_tuple(*a, *b, *centre);
    }

    void h_power(const Entry& e, CodeVerdict& v) {
        const int dim = e.param("dim");
        const std::string quantity = e.param_text("quantity");
        int exact = 0;
        if (quantity == "value") exact = -dim;
        else if (quantity == "gradient") exact = -(dim + 2);
        else e.bad("field 'params.quantity' must be value or gradient, got '" + quantity + "'");
        const int printed = e.integer(e.printed(), "h_power", "printed");
        v.published = "h^" + std::to_string(printed);
        v.exact = "h^" + std::to_string(exact);
        v.ratio = "h^" + std::to_string(printed - exact);
        v.right = printed == exact;
        v.diagnosis = v.right ? "right"
                              : "support convention: W scaled by h^" + std::to_string(printed) + " instead of h^" +
                                    std::to_string(exact) + " (right only for h = 1)";
    }

    // SWIFT's kernel_gamma = H/h with h = 2 sigma (Dehnen & Aly 2012): gamma^2 =
    // D / (4 int |x|^2 K d^D x), a rational; a printed decimal is right when
    // gamma rounds to it: (x - u/2)^2 <= gamma^2 <= (x + u/2)^2, decided exactly.
    // With printed.precision (SWIFT: `(float)(1.732051)`) the constant the code
    // computes with is that decimal as a C double literal, cast: it must also be
    // gamma correctly rounded to that precision (six decimals name a float only
    // to ~1e-6, a float's spacing near 2 is 2.4e-7).
    // The entry's kernel (params.spec in params.dim), support 1, unit mass; Error naming the field.
    const Radial& entry_kernel(const Entry& e) {
        const std::string spec = e.param_text("spec");
        const int dim = e.param("dim");
        if (dim < 1 || dim > 3) e.bad("field 'params.dim' must be 1, 2 or 3, got " + std::to_string(dim));
        try {
            return unit_kernel(spec, dim);
        } catch (const Error& ex) {
            e.bad(std::string("field 'params.spec': ") + ex.what());
        }
    }

    void gamma(const Entry& e, CodeVerdict& v) {
        const std::string spec = e.param_text("spec");
        const int dim = e.param("dim");
        const Radial* K = &entry_kernel(e);
        const auto m2 = single(sphere_measure(dim) * radial_integral(*K, dim + 1));
        if (!m2 || m2->pi != 0 || m2->q <= 0) fail("internal: the second moment of " + spec + " is not a positive rational");
        const Q g2 = Q(dim) / (Q(4) * m2->q);
        const std::string text = e.text(e.printed(), "gamma", "printed");
        const Q x = e.rational(e.printed(), "gamma", "printed");
        const auto decimal_places_of_text = decimal_places(text);
        if (!decimal_places_of_text) e.bad("field 'printed.gamma' must be a decimal, got '" + text + "'");
        const int places = *decimal_places_of_text;  // x * 10^places is an integer
        const Z N = rounded_sqrt(g2, places);
        const Q printed_units = x * pow(Q(10), places);
        if (!is_integer(printed_units)) fail("internal: a decimal's last digit");
        const Z off = numerator(printed_units) - N;
        char shown[64];
        std::snprintf(shown, sizeof shown, "%.*f", std::max(places, 0) + 3, sqrt_to_double(g2));
        v.published = text;
        v.exact = "sqrt(" + short_string(g2) + ") = " + shown + "...";
        const std::string used = constant_off(e, text, x, g2);
        v.right = off == 0 && used.empty();
        if (off == 0) {
            v.ratio = "1 (to the printed digits)";
            v.diagnosis = used.empty() ? "right (to the printed digits)" : "right to the printed digits; " + used;
            return;
        }
        std::snprintf(shown, sizeof shown, "%.9g", static_cast<double>(x) / sqrt_to_double(g2));
        v.ratio = shown;
        const Z units = off < 0 ? Z(-off) : off;
        if (units <= 2)
            v.diagnosis = "rounding: the exact gamma rounds to " + decimal_string(N, places) + ", the printed value is " + units.str() +
                          " unit" + (units == 1 ? "" : "s") + " of its last digit off";
        else
            v.diagnosis = "support convention: gamma = H/h is not this kernel's (published/exact = " + std::string(shown) + ")";
        if (!used.empty()) v.diagnosis += "; " + used;
    }

    // printed.precision: the precision a code computes a printed constant in,
    // "float" or "double"; Error naming the field otherwise.
    static std::string printed_precision(const Entry& e) {
        const std::string precision = e.text(e.printed(), "precision", "printed");
        if (precision != "float" && precision != "double")
            e.bad("field 'printed.precision' must be float or double, got '" + precision + "'");
        return precision;
    }

    // How many units in the last place of `want` (a float's where single) got is from it.
    static double ulps_apart(double got, double want, bool single_precision) {
        return std::fabs(got - want) / (single_precision ? ulp_of_float(want) : ulp_of_double(want));
    }

    // Where the entry gives printed.precision: why the constant the code
    // computes with, the decimal `text` (value x) as a C double literal cast to
    // that precision, is not sqrt(g2) correctly rounded to it, or "".
    static std::string constant_off(const Entry& e, const std::string& text, const Q& x, const Q& g2) {
        const json& printed = e.printed();
        if (!printed.contains("precision")) return "";
        const std::string precision = printed_precision(e);
        const bool single_precision = precision == "float";
        const double literal = round_to_double(x);
        const double got = single_precision ? static_cast<double>(static_cast<float>(literal)) : literal;
        const double want = single_precision ? static_cast<double>(sqrt_to_float(g2)) : sqrt_to_double(g2);
        if (got == want) return "";
        const double units = ulps_apart(got, want, single_precision);
        char b[256];
        std::snprintf(b, sizeof b, "(%s)(%s) = %s is %.3g %s ulp%s from sqrt(%s) correctly rounded, %s", precision.c_str(),
                      text.c_str(), hex_literal(got).c_str(), units, precision.c_str(), units == 1 ? "" : "s",
                      short_string(g2).c_str(), hex_literal(want).c_str());
        return b;
    }

    // A code's table of monomial coefficients as it prints them (SWIFT's
    // kernel_coeffs: float literals of repeating fractions): W_1(x) = C pi^p w(x)
    // on support 1 (x = r/H), w = sum_k c_k x^k on each piece, highest power
    // first. A literal is right when it rounds to the same float (double) as
    // the exact coefficient of mollify's W_1 / (C pi^p); a wrong one is named
    // with the exact value and how many units in the last place its float is off.
    void coefficients(const Entry& e, CodeVerdict& v) {
        const Radial& K = entry_kernel(e);
        const json& printed = e.printed();
        const PiQ c{e.rational(printed, "constant", "printed"), e.integer(printed, "pi_power", "printed")};
        if (c.q == 0) e.bad("field 'printed.constant' is 0");
        const std::string precision = printed_precision(e);
        const json& pieces = e.need(printed, "pieces", "printed");
        if (!pieces.is_array() || pieces.empty()) e.bad("field 'printed.pieces' must be a non-empty array");
        int literals = 0;
        std::vector<std::string> wrong;
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            const std::string path = "printed.pieces[" + std::to_string(i) + "]";
            const Q from = e.rational(pieces[i], "from", path), to = e.rational(pieces[i], "to", path);
            const json& cs = e.need(pieces[i], "coefficients", path);
            if (!cs.is_array() || cs.empty()) e.bad("field '" + path + ".coefficients' must be a non-empty array");
            const int degree = static_cast<int>(cs.size()) - 1;
            const Laurent p = exact_piece(e, path, K, from, to, c, degree);
            for (int k = degree; k >= 0; --k) {
                const std::string lp = path + ".coefficients[" + std::to_string(degree - k) + "]";
                const json& lit = cs[static_cast<std::size_t>(degree - k)];
                if (!lit.is_string()) e.bad("field '" + lp + "' must be a string (the literal as printed, without its f)");
                ++literals;
                const Q exact = p.is_zero() ? Q(0) : p.coefficient(k) / c.q;
                if (auto off = literal_off(lit.get<std::string>(), e.rational(lit, lp), exact, precision))
                    wrong.push_back("x^" + std::to_string(k) + " on [" + short_string(from) + ", " + short_string(to) + "): " + *off);
            }
        }
        v.published = std::to_string(literals) + " " + precision + " literals, C = " + exact_of(c).to_string();
        v.exact = "the monomial coefficients of W_1 / C (" + e.param_text("spec") + ", D = " + std::to_string(e.param("dim")) + ")";
        v.right = wrong.empty();
        v.ratio = v.right ? "1" : std::to_string(wrong.size()) + " of " + std::to_string(literals) + " off";
        v.diagnosis = v.right ? "right (every literal rounds to the exact coefficient's " + precision + ")" : "coefficients: ";
        for (std::size_t j = 0; j < wrong.size(); ++j) v.diagnosis += (j ? "; " : "") + wrong[j];
    }

    // W_1 on [from, to) as a polynomial times pi^(c.pi), at most of the printed degree; Error naming
    // the piece where it is not one (outside the support, across a breakpoint, another power of pi).
    static Laurent exact_piece(const Entry& e, const std::string& path, const Radial& K, const Q& from, const Q& to,
                               const PiQ& c, int degree) {
        const std::string range = "[" + short_string(from) + ", " + short_string(to) + ")";
        if (from < 0 || to <= from || to > K.support())
            e.bad("field '" + path + "': need 0 <= from < to <= 1 (x = r/H), got " + range);
        for (const Q& b : K.breaks)
            if (from < b && b < to)
                e.bad("field '" + path + "': " + range + " spans " + e.param_text("spec") + "'s breakpoint " +
                      short_string(b) + " (one polynomial each side)");
        Laurent p;
        Atom atom;
        if (!K.form_at((from + to) / 2).single_polynomial(&p, &atom) || !p.is_polynomial() || atom.log_of != 1 ||
            (!p.is_zero() && atom.pi_power != c.pi))
            e.bad("field '" + path + "': " + e.param_text("spec") + " on " + range + " is not a polynomial times pi^" +
                  std::to_string(c.pi));
        if (!p.is_zero() && p.high() > degree)
            e.bad("field '" + path + ".coefficients': " + std::to_string(degree + 1) + " literals, the exact w has degree " +
                  std::to_string(p.high()));
        return p;
    }

    // Why a printed literal (exact value `literal`) is not the exact coefficient in `precision`, or nothing.
    static std::optional<std::string> literal_off(const std::string& text, const Q& literal, const Q& exact,
                                                  const std::string& precision) {
        const bool single_precision = precision == "float";
        const double got = single_precision ? round_to_float(literal) : round_to_double(Exact(literal));
        const double want = single_precision ? round_to_float(exact) : round_to_double(Exact(exact));
        if (got == want) return std::nullopt;
        char b[224];
        std::snprintf(b, sizeof b, "%s, exact %s = %.12g, %.3g %s ulps off (relative %.2g)", text.c_str(),
                      short_string(exact).c_str(), static_cast<double>(exact), ulps_apart(got, want, single_precision),
                      precision.c_str(), exact == 0 ? 0.0 : static_cast<double>((literal - exact) / exact));
        return std::string(b);
    }

    CodeErrataReport& report_;
    std::map<std::pair<std::string, int>, Radial> kernels_, grads_;
    std::deque<Radial> scaled_;
};

// ---------------------------------------------------------------------------
// Files

// "file @ commit", "issue #421", "PR #1144, file @ commit", ...
std::string source_of(const Entry& e) {
    const json& o = *e.object;
    std::vector<std::string> parts;
    for (const char* kind : {"issue", "pr"})
        if (o.contains(kind)) {
            if (!o[kind].is_number_integer()) e.bad(std::string("field '") + kind + "' must be an integer");
            parts.push_back(std::string(kind[0] == 'i' ? "issue #" : "PR #") + std::to_string(o[kind].get<int>()));
        }
    if (o.contains("file")) {
        std::string f = e.text(o, "file", "");
        if (o.contains("commit")) f += " @ " + e.text(o, "commit", "");
        parts.push_back(f);
    }
    if (parts.empty()) e.bad("needs a source: 'file' (with 'commit'), 'issue' or 'pr'");
    return errata::join(parts, ", ");
}

void run_file(CodeChecker& checker, const fs::path& path) {
    const json doc = errata::read_transcription(path, {"code", "repository"});
    const std::string file = path.filename().string();
    const std::string code = doc["code"].get<std::string>() + " (" + doc["repository"].get<std::string>() + ")";
    std::size_t index = 0;
    for (const json& obj : doc["entries"]) {
        Entry e;
        e.file = file;
        e.document = code;
        e.object = &obj;
        e.report = nullptr;
        e.label = "#" + std::to_string(++index);
        e.where = "?";
        if (!obj.is_object()) e.bad("an entry must be an object");
        for (const char* key : {"entry", "quantity", "expression", "says"}) {
            auto it = obj.find(key);
            if (it == obj.end() || !it->is_string()) e.bad(std::string("missing string field '") + key + "'");
        }
        e.label = obj["entry"].get<std::string>();
        e.quantity = obj["quantity"].get<std::string>();
        e.where = source_of(e);
        try {
            checker.check(e, code, e.where);
        } catch (const Error& ex) {
            const std::string message = ex.what();
            if (message.rfind(e.context(), 0) == 0) throw;
            e.bad(message);
        }
    }
}

}  // namespace

CodeErrataReport check_code_errata(const std::filesystem::path& dir) {
    if (!fs::is_directory(dir)) fail("transcriptions directory " + dir.string() + " does not exist");
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
    CodeErrataReport report;
    CodeChecker checker(report);
    for (const auto& f : files) run_file(checker, f);
    return report;
}

}  // namespace mollify::gen
