// The errata of Belley 2007 (seed 002): the classic kernels (poly6, spiky,
// viscosity) as printed formulas with their support, and the discontinuous
// kernels delta, delta', delta'' (box, box-d1, box-d2): their moments
// int x^n K_h(x0 - x) dx, eqs. (13), (17), (21), and their constant values
// on intervals, eqs. (12), (16), (20).
#include "errata_checker.hpp"

#include "error.hpp"

#include <algorithm>

namespace mollify::gen::errata {

// ---------------------------------------------------------------------------
// The kernel formulas W_h(r) = h^-D W(r/h)

namespace {

// A printed term c r^r h^h of the bracket.
struct ClassicTerm {
    Q c;
    int r, h;
    int degree() const { return r + h; }
    std::string str() const { return monomial_string(c, {{"r", r}, {"h", h}}); }
};

// What Belley prints: value pi^pi_power * h^h_power * (bracket) or
// |bracket|, and the support.
struct PrintedClassic {
    Q value;
    int pi_power, h_power;
    std::vector<ClassicTerm> terms;
    bool abs;
    std::string support;

    std::string prefactor() const {
        return Exact::pi_power(value, pi_power).to_string() + (h_power != 0 ? " * h^" + std::to_string(h_power) : "");
    }
    std::string bracket() const {
        std::vector<std::string> ts;
        for (const auto& t : terms) ts.push_back(t.str());
        return sum_string(ts);
    }
    std::string str() const { return prefactor() + " * " + (abs ? "|" + bracket() + "|" : "(" + bracket() + ")"); }

    Exact at(const Q& r, const Q& h) const {
        Q sum = 0;
        for (const auto& term : terms) sum += term.c * pow(r, term.r) * pow(h, term.h);
        return Exact::pi_power(value * pow(h, h_power) * (abs && sum < 0 ? Q(-sum) : sum), pi_power);
    }
};

PrintedClassic read_classic(const Entry& e) {
    const json& pr = e.printed();
    const json& pre = e.need(pr, "prefactor", "printed");
    PrintedClassic p;
    p.value = e.rational(pre, "value", "printed.prefactor");
    p.pi_power = e.integer(pre, "pi_power", "printed.prefactor");
    p.h_power = e.integer(pre, "h_power", "printed.prefactor");
    for (const json& t : e.printed_array("terms"))
        p.terms.push_back({e.rational(t, "coeff", "printed.terms[]"), e.integer(t, "r_power", "printed.terms[]"),
                           e.integer(t, "h_power", "printed.terms[]")});
    p.abs = e.boolean(pr, "abs", "printed");
    p.support = e.text(pr, "support", "printed");
    return p;
}

// W_h(r) = h^-D W(r/h) = normalisation h^-D sum c_n (r/h)^n, W = factor *
// shape; written with the printed prefactor when the normalisations differ
// by a rational.
std::string exact_formula(const PrintedClassic& printed, const Laurent& shape, const Atom& factor, int D) {
    const auto rel = ratio(exact_from(Q(1), factor), Exact::pi_power(printed.value, printed.pi_power));
    std::vector<std::string> ts;
    for (int n = shape.high(); n >= shape.low(); --n) {
        const Q c = shape.coefficient(n);
        if (c == 0) continue;
        if (rel) ts.push_back(monomial_string(c * *rel, {{"r", n}, {"h", -n - D - printed.h_power}}));
        else ts.push_back(monomial_string(c, {{"(r/h)", n}}));
    }
    return rel ? printed.prefactor() + " * (" + sum_string(ts) + ")"
               : exact_from(Q(1), factor).to_string() + " * h^" + std::to_string(-D) + " * (" + sum_string(ts) + ")";
}

// The formulas are compared by value at h = 2 and a few r = t h in (0, h).
Q sample_h() { return Q(2); }
std::vector<Q> sample_t() { return {Q(1, 7), Q(2, 5), Q(3, 4), Q(9, 10)}; }

// printed / exact when it is one rational at every sample.
std::optional<Q> common_ratio(const PrintedClassic& printed, const Radial& W, int D) {
    std::vector<std::optional<Q>> ratios;
    const Q h = sample_h();
    for (const Q& t : sample_t()) {
        const Exact p = printed.at(t * h, h);
        const Exact x = W.at(t) * pow(h, -D);
        ratios.push_back(x.is_zero() ? std::nullopt : (p.is_zero() ? std::optional<Q>(Q(0)) : ratio(p, x)));
    }
    const bool proportional = std::all_of(ratios.begin(), ratios.end(), [&](const auto& r) { return r && r == ratios[0]; });
    return proportional ? ratios[0] : std::nullopt;
}

bool positive_at_samples(const Laurent& shape) {
    const std::vector<Q> ts = sample_t();
    return std::all_of(ts.begin(), ts.end(), [&](const Q& t) { return shape(t) > 0; });
}

// Dimension check: every term r^a h^b of the bracket should have the same
// degree a + b (the most common one).
std::string degree_remark(const std::vector<ClassicTerm>& terms) {
    std::map<int, int> degree_count;
    for (const auto& t : terms) ++degree_count[t.degree()];
    int common = 0, best = -1;
    for (const auto& t : terms)
        if (degree_count[t.degree()] > best) {
            best = degree_count[t.degree()];
            common = t.degree();
        }
    std::vector<std::string> odd;
    for (const auto& t : terms)
        if (t.degree() != common) odd.push_back(t.str() + " (degree " + std::to_string(t.degree()) + ")");
    std::string remark = "differs in form";
    if (!odd.empty())
        remark += ": dimensionally inconsistent term " + join(odd, ", ") + "; the other terms have degree " +
                  std::to_string(common) + " in r and h";
    return remark;
}

// Support: |r| <= h, in any of the usual spellings.
void compare_support(const Entry& e, const std::string& support) {
    std::string s = support;
    for (const std::string le : {"\\leq", "\\le"})
        for (std::size_t at; (at = s.find(le)) != std::string::npos;) s.replace(at, le.size(), "<=");
    std::string compact;
    for (char ch : s)
        if (ch != ' ') compact += ch;
    const bool support_ok = compact == "-h<=r<=h" || compact == "-h<=x<=h" || compact == "|r|<=h" ||
                            compact == "|x|<=h" || compact == "0<=r<=h" || compact == "r<=h";
    const std::string var = compact.find('x') != std::string::npos ? "x" : "r";
    e.compare(support_ok, "support", s, "-h <= " + var + " <= h", support_ok ? "" : "the support must scale with h");
}

}  // namespace

void Checker::classic_kernel(const Entry& e) {
    const std::string name = e.param_text("kernel");
    const int D = e.param("D");
    const ExactKernel& k = kernel(name, D);
    const PrintedClassic printed = read_classic(e);
    Laurent shape;
    Atom factor;
    if (k.W.pieces.size() != 1 || !k.W.pieces[0].single_polynomial(&shape, &factor))
        fail("internal: " + name + " is not a single polynomial piece");

    const std::optional<Q> r = common_ratio(printed, k.W, D);
    const bool same = r && *r == 1;
    const std::string remark = same ? "" : r ? "differs by a factor " + short_string(*r) : degree_remark(printed.terms);
    e.compare(same, "formula", printed.str(), exact_formula(printed, shape, factor, D), remark);
    e.compare(!printed.abs, "absolute value", "|" + printed.bracket() + "|", "no absolute value",
              std::string("the kernel has no absolute value") +
                  (positive_at_samples(shape) ? "; its bracket is positive for 0 < r < h, where the bars change nothing"
                                              : ""));
    compare_support(e, printed.support);
}

// ---------------------------------------------------------------------------
// Moments and values of the one-dimensional kernels

namespace {

// 0 for W itself, 1 and 2 for the kernels of the first and second derivative.
int derivative_order(const ExactKernel& k) {
    switch (k.normalised_by) {
        case Normalisation::unit_mass: return 0;
        case Normalisation::first_derivative: return 1;
        case Normalisation::second_derivative: return 2;
    }
    return 0;
}

// W(x) for x of either sign in one dimension.
Exact value_1d(const Radial& W, const Q& x) {
    const Exact v = W.at(x < 0 ? Q(-x) : x);
    return x < 0 && W.parity < 0 ? -v : v;
}

// Coefficients of x0^a h^b, keyed (a, b); zeros dropped.
using Bivariate = std::map<std::pair<int, int>, Q>;

void add_term(Bivariate& poly, const std::pair<int, int>& key, const Q& c) {
    Q& slot = poly[key];
    slot += c;
    if (slot == 0) poly.erase(key);
}

// K_h(y) = h^(-1-p) W(y/h): int y^m K_h = h^(m-p) mu_m, mu_m = int_R s^m W.
// int x^n K_h(x0 - x) dx = sum_m C(n,m) (-1)^m x0^(n-m) h^(m-p) mu_m.
Bivariate exact_moment(const ExactKernel& k, const std::string& name, int n) {
    const int p = derivative_order(k);
    Bivariate exact;
    for (int m = 0; m <= n; ++m) {
        const Exact half = radial_integral(k.W, m);
        if (!half.is_rational()) fail("internal: moment of " + name + " is not rational");
        const Q mu = half.rational() * (1 + k.W.parity * (m % 2 == 0 ? 1 : -1));
        const Q c = Q(binomial(static_cast<unsigned>(n), static_cast<unsigned>(m))) * (m % 2 == 0 ? 1 : -1) * mu;
        if (c == 0) continue;
        add_term(exact, {n - m, m - p}, c);
    }
    return exact;
}

Bivariate printed_moment(const Entry& e) {
    Bivariate printed;
    for (const json& t : e.printed_array("terms")) {
        const Q c = e.rational(t, "coeff", "printed.terms[]");
        const auto key = std::make_pair(e.integer(t, "x0_power", "printed.terms[]"), e.integer(t, "h_power", "printed.terms[]"));
        add_term(printed, key, c);
    }
    return printed;
}

// The values of W on (lo, hi), cut at 0 and at the breakpoints +-b: one
// (interval, value) per run of equal values.
std::vector<std::pair<std::string, Exact>> values_on(const Radial& W, const Q& lo, const Q& hi) {
    std::vector<Q> cuts{lo, hi, Q(0)};
    for (const Q& b : W.breaks) {
        cuts.push_back(b);
        cuts.push_back(-b);
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    std::vector<std::pair<std::string, Exact>> parts;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
        if (cuts[i] < lo || cuts[i + 1] > hi) continue;
        const Exact v = value_1d(W, (cuts[i] + cuts[i + 1]) / 2);
        if (parts.empty() || !(parts.back().second == v))
            parts.emplace_back("(" + short_string(cuts[i]) + " h, " + short_string(cuts[i + 1]) + " h)", v);
    }
    return parts;
}

}  // namespace

void Checker::belley_moment(const Entry& e) {
    const std::string name = e.param_text("kernel");
    const int n = e.param("n");
    if (n < 0 || n > 40) e.bad("params.n out of range");
    const Bivariate exact = exact_moment(kernel(name, 1), name, n);
    const Bivariate printed = printed_moment(e);
    std::set<std::pair<int, int>> keys;
    for (const auto& [key, c] : exact) keys.insert(key);
    for (const auto& [key, c] : printed) keys.insert(key);
    if (keys.empty()) {
        e.compare(true, "", "0", "0");
        return;
    }
    for (const auto& key : keys) {
        const Q pv = printed.count(key) ? printed.at(key) : Q(0);
        const Q xv = exact.count(key) ? exact.at(key) : Q(0);
        const std::string mono = monomial_string(Q(1), {{"x0", key.first}, {"h", key.second}});
        e.compare(pv == xv, "coefficient of " + (mono == "1" ? std::string("x0^0 h^0") : mono), short_string(pv),
                  short_string(xv), pv != xv && pv != 0 && xv != 0 ? factor_remark(pv / xv) : "");
    }
}

// A value printed as constant on an interval (in units of h): the kernel
// must be that one constant on all of it.
void Checker::belley_kernel_value(const Entry& e) {
    const std::string name = e.param_text("kernel");
    e.param_text("piece");
    const ExactKernel& k = kernel(name, 1);
    const int exact_hp = -1 - derivative_order(k);
    const json& pr = e.printed();
    const Q value = e.rational(pr, "value", "printed");
    const int hp = e.integer(pr, "h_power", "printed");
    const json& interval = e.need(pr, "interval", "printed");
    if (!interval.is_array() || interval.size() != 2) e.bad("printed.interval must be [lo, hi]");
    const Q lo = e.rational(interval[0], "printed.interval[0]"), hi = e.rational(interval[1], "printed.interval[1]");
    if (!(lo < hi)) e.bad("printed.interval must have lo < hi");
    const auto parts = values_on(k.W, lo, hi);
    const std::string printed_string = short_string(value) + " * h^" + std::to_string(hp);
    if (parts.size() != 1) {
        std::vector<std::string> desc;
        for (const auto& [where, v] : parts) desc.push_back(v.to_string() + " * h^" + std::to_string(exact_hp) + " on " + where);
        e.compare(false, "", printed_string, join(desc, ", "), "the kernel is not constant on this interval");
        return;
    }
    const Exact& v = parts[0].second;
    const bool same = v == Exact(value) && hp == exact_hp;
    std::string remark;
    if (!same && hp != exact_hp) remark = "printed h^" + std::to_string(hp) + ", exact h^" + std::to_string(exact_hp);
    e.compare(same, "", printed_string, v.to_string() + " * h^" + std::to_string(exact_hp), remark);
}

}  // namespace mollify::gen::errata
