#include "errata.hpp"

#include "anderson.hpp"
#include "error.hpp"
#include "kernel.hpp"
#include "quantities.hpp"
#include "spec.hpp"
#include "vandermonde.hpp"
#include "wendland.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

namespace mollify::gen {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// Coefficients of a polynomial in one variable, each an exact constant.
using Coefficients = std::map<int, Exact>;

// ---------------------------------------------------------------------------
// Exact helpers

Exact exact_from(const Q& q, const Atom& a) {
    Exact f = Exact::pi_power(Q(1), a.pi_power);
    if (a.log_of != 1) f = f * Exact::log_of(Q(a.log_of));
    return f * q;
}

void add_coefficient(Coefficients& c, int n, const Exact& v) {
    if (v.is_zero()) return;
    c[n] += v;
    if (c[n].is_zero()) c.erase(n);
}

Coefficients coefficients(const Laurent& p) {
    Coefficients c;
    for (int n = p.low(); n <= p.high(); ++n) add_coefficient(c, n, Exact(p.coefficient(n)));
    return c;
}

// A closed form made of basis-1 terms only (polynomials times pi^e log p).
Coefficients coefficients(const ClosedForm& f) {
    Coefficients c;
    for (const auto& [key, p] : f.terms()) {
        if (key.basis != Basis::one) fail("internal: expected a polynomial closed form");
        for (int n = p.low(); n <= p.high(); ++n) add_coefficient(c, n, exact_from(p.coefficient(n), key.factor));
    }
    return c;
}

// a / b when it is rational (a and b the same combination of atoms).
std::optional<Q> ratio(const Exact& a, const Exact& b) {
    if (a.is_zero() || b.is_zero() || a.terms().size() != b.terms().size()) return std::nullopt;
    std::optional<Q> r;
    auto ib = b.terms().begin();
    for (auto ia = a.terms().begin(); ia != a.terms().end(); ++ia, ++ib) {
        if (ia->first != ib->first) return std::nullopt;
        const Q q = ia->second / ib->second;
        if (r && *r != q) return std::nullopt;
        r = q;
    }
    return r;
}

// The factor c with printed = c * exact shared by most (printed, exact)
// pairs; ties go to the pair listed first. Robust against a single wrong
// coefficient, wherever it sits.
std::optional<Q> common_factor(const std::vector<std::pair<Exact, Exact>>& pairs) {
    std::vector<std::pair<Q, int>> counts;
    for (const auto& [p, e] : pairs) {
        const auto r = ratio(p, e);
        if (!r) continue;
        auto it = std::find_if(counts.begin(), counts.end(), [&](const auto& c) { return c.first == *r; });
        if (it == counts.end()) counts.emplace_back(*r, 1);
        else ++it->second;
    }
    if (counts.empty()) return std::nullopt;
    auto best = counts.begin();
    for (auto it = counts.begin(); it != counts.end(); ++it)
        if (it->second > best->second) best = it;
    return best->first;
}

std::string factor_remark(const std::optional<Q>& printed_over_exact) {
    if (!printed_over_exact) return "";
    if (*printed_over_exact == -1) return "sign differs";
    return "printed/exact = " + short_string(*printed_over_exact);
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
    std::string s;
    for (const auto& p : parts) {
        if (p.empty()) continue;
        if (!s.empty()) s += sep;
        s += p;
    }
    return s;
}

// "x^n" spelled for people: "" for n = 0, "x" for n = 1.
std::string power_of(const std::string& x, int n) {
    if (n == 0) return "";
    if (n == 1) return x;
    return x + "^" + std::to_string(n);
}

// "c x^a y^b" with c = 1 / -1 folded into the sign.
std::string monomial_string(const Q& c, const std::vector<std::pair<std::string, int>>& powers) {
    std::vector<std::string> factors;
    for (const auto& [x, n] : powers)
        if (n != 0) factors.push_back(power_of(x, n));
    const std::string vars = join(factors, " ");
    if (vars.empty()) return short_string(c);
    if (c == 1) return vars;
    if (c == -1) return "-" + vars;
    return short_string(c) + " " + vars;
}

std::string sum_string(const std::vector<std::string>& terms) {
    std::string s;
    for (const auto& t : terms) {
        if (s.empty()) s = t;
        else if (!t.empty() && t[0] == '-') s += " - " + t.substr(1);
        else s += " + " + t;
    }
    return s.empty() ? "0" : s;
}

std::string delta_string(int n) { return "delta^" + std::to_string(n); }

// ---------------------------------------------------------------------------
// One transcription entry: its identity, typed access to its fields, and the
// comparison primitive that counts and records.

struct Entry {
    std::string file, document, where, label, quantity;
    const json* object = nullptr;
    ErrataReport* report = nullptr;

    std::string context() const { return file + ", entry '" + label + "' (" + where + ")"; }
    [[noreturn]] void bad(const std::string& what) const { fail(context() + ": " + what); }

    void compare(bool equal, const std::string& part, const std::string& printed, const std::string& exact,
                 const std::string& remark = "") const {
        ++report->checked;
        if (equal) return;
        report->discrepancies.push_back(
            Discrepancy{document, where, part.empty() ? label : label + ", " + part, printed, exact, remark});
    }

    const json& need(const json& obj, const std::string& key, const std::string& path) const {
        if (!obj.is_object()) bad("field '" + path + "' must be an object");
        auto it = obj.find(key);
        if (it == obj.end()) bad("missing field '" + (path.empty() ? key : path + "." + key) + "'");
        return *it;
    }
    int integer(const json& obj, const std::string& key, const std::string& path) const {
        const json& v = need(obj, key, path);
        if (!v.is_number_integer()) bad("field '" + path + "." + key + "' must be an integer");
        return v.get<int>();
    }
    std::string text(const json& obj, const std::string& key, const std::string& path) const {
        const json& v = need(obj, key, path);
        if (!v.is_string()) bad("field '" + (path.empty() ? key : path + "." + key) + "' must be a string");
        return v.get<std::string>();
    }
    bool boolean(const json& obj, const std::string& key, const std::string& path) const {
        const json& v = need(obj, key, path);
        if (!v.is_boolean()) bad("field '" + path + "." + key + "' must be true or false");
        return v.get<bool>();
    }
    Q rational(const json& v, const std::string& path) const {
        if (!v.is_string()) bad("field '" + path + "' must be a rational written as a string (\"p/q\")");
        return parse_rational(v.get<std::string>(), context() + ": field '" + path + "'");
    }
    Q rational(const json& obj, const std::string& key, const std::string& path) const {
        return rational(need(obj, key, path), path + "." + key);
    }
    // {"2": "1/4", ...}: keys are exponents in decimal.
    std::map<int, Q> coefficient_map(const json& obj, const std::string& key, const std::string& path) const {
        const json& m = need(obj, key, path);
        if (!m.is_object()) bad("field '" + path + "." + key + "' must be an object of coefficients");
        std::map<int, Q> out;
        for (auto it = m.begin(); it != m.end(); ++it) {
            const std::string& k = it.key();
            int n = 0;
            const auto [end, ec] = std::from_chars(k.data(), k.data() + k.size(), n);
            if (ec != std::errc() || end != k.data() + k.size())
                bad("field '" + path + "." + key + "': key '" + k + "' is not an exponent");
            if (!out.emplace(n, rational(it.value(), path + "." + key + "." + k)).second)
                bad("field '" + path + "." + key + "': exponent " + k + " repeated");
        }
        return out;
    }
    const json& params() const { return need(*object, "params", ""); }
    const json& printed() const { return need(*object, "printed", ""); }
    int param(const std::string& key) const { return integer(params(), key, "params"); }
    std::string param_text(const std::string& key) const { return text(params(), key, "params"); }
    const json& printed_array(const std::string& key) const {
        const json& a = need(printed(), key, "printed");
        if (!a.is_array()) bad("field 'printed." + key + "' must be an array");
        return a;
    }
};

// Compares two coefficient maps key by key (the union of the keys; a printed
// explicit zero counts as compared). `remark` may explain one coefficient.
template <class Label, class Remark>
void compare_coefficients(const Entry& e, const Coefficients& printed, const Coefficients& exact,
                          const std::set<int>& printed_keys, Label label, Remark remark) {
    std::set<int> keys = printed_keys;
    for (const auto& [n, v] : exact) keys.insert(n);
    for (int n : keys) {
        const Exact p = printed.count(n) ? printed.at(n) : Exact();
        const Exact x = exact.count(n) ? exact.at(n) : Exact();
        e.compare(p == x, label(n), p.to_string(), x.to_string(), p == x ? "" : remark(n, p, x));
    }
}

// Printed coefficients known only up to one constant factor ("\doteq"):
// the factor is the one most coefficients share; the exact column shows
// the exact coefficient times that factor.
struct Proportional {
    std::string part;
    Exact printed, exact;
};

void compare_proportional(const Entry& e, const std::vector<Proportional>& items, std::optional<Q> factor,
                          const std::string& extra_remark) {
    if (!factor) {
        std::vector<std::pair<Exact, Exact>> pairs;
        for (const auto& it : items) pairs.emplace_back(it.printed, it.exact);
        factor = common_factor(pairs);
    }
    const Q c = factor.value_or(Q(1));
    for (const auto& it : items) {
        const Exact expected = it.exact * c;
        std::vector<std::string> remark;
        if (!(it.printed == expected)) {
            if (c != 1) remark.push_back("exact value times the common factor " + short_string(c));
            if (c < 0) remark.push_back("differs by a sign");
            remark.push_back(extra_remark);
        }
        e.compare(it.printed == expected, it.part, it.printed.to_string(), expected.to_string(), join(remark, "; "));
    }
}

// Anderson's omega_N: 1, 2 pi, 4 pi (his §2; the core uses omega_1 = 2).
Exact omega_anderson(int dim) { return dim == 1 ? Exact(Q(1)) : sphere_measure(dim); }

// "Christopher R. Anderson, ..." + "... 2014 ..." + "000_..." -> "Anderson 2014 (seed 000)".
std::string document_label(const std::string& citation, const std::string& seed) {
    std::string author = citation.substr(0, citation.find(','));
    if (auto sp = author.find_last_of(' '); sp != std::string::npos) author = author.substr(sp + 1);
    std::string year;
    for (std::size_t i = 0; i + 4 <= citation.size(); ++i) {
        const bool digits = std::all_of(citation.begin() + static_cast<long>(i), citation.begin() + static_cast<long>(i + 4),
                                        [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)) != 0; });
        const bool alone = (i == 0 || !std::isdigit(static_cast<unsigned char>(citation[i - 1]))) &&
                           (i + 4 == citation.size() || !std::isdigit(static_cast<unsigned char>(citation[i + 4])));
        if (digits && alone && (citation.compare(i, 2, "19") == 0 || citation.compare(i, 2, "20") == 0)) {
            year = citation.substr(i, 4);
            break;
        }
    }
    const std::string seed_number = seed.substr(0, seed.find('_'));
    return join({author, year}, " ") + " (seed " + seed_number + ")";
}

// ---------------------------------------------------------------------------

class Checker {
public:
    explicit Checker(ErrataReport& report) : report_(report) {}
    void run_file(const fs::path& path);

private:
    const Kernel& kernel(const std::string& spec, int dim) {
        const auto key = std::make_pair(spec, dim);
        auto it = kernels_.find(key);
        if (it == kernels_.end()) it = kernels_.emplace(key, make_kernel(parse_spec(spec), dim)).first;
        return it->second;
    }
    const Quantities& quantities(const std::string& spec, int dim) {
        const auto key = std::make_pair(spec, dim);
        auto it = quantities_.find(key);
        if (it == quantities_.end()) it = quantities_.emplace(key, derive_quantities(kernel(spec, dim))).first;
        return it->second;
    }
    static std::string mollifier_spec(int M, int order = 2) {
        return "mollifier:M=" + std::to_string(M) + (order == 2 ? "" : ",order=" + std::to_string(order));
    }
    Q table1_sigma(int dim, int M) {
        const Exact s = kernel(mollifier_spec(M), dim).W.at(Q(0)) * omega_anderson(dim);
        if (!s.is_rational()) fail("internal: sigma is not rational: " + s.to_string());
        return s.rational();
    }

    void check(const Entry& e);
    void scalar(const Entry& e, const Q& exact, const std::string& remark_if_wrong = "");
    void anderson_sigma_formula(const Entry& e);
    void anderson_second_moment(const Entry& e);
    void anderson_radii_combination(const Entry& e);
    void anderson_formula(const Entry& e);
    void wendland_shape_entry(const Entry& e);
    void wendland_combo(const Entry& e);
    void wendland_combo_weights(const Entry& e);
    void wendland_missing(const Entry& e);
    void classic_kernel(const Entry& e);
    void belley_moment(const Entry& e);
    void belley_kernel_value(const Entry& e);

    ErrataReport& report_;
    std::map<std::pair<std::string, int>, Kernel> kernels_;
    std::map<std::pair<std::string, int>, Quantities> quantities_;
};

void Checker::run_file(const fs::path& path) {
    const std::string file = path.filename().string();
    std::ifstream in(path);
    if (!in) fail(file + ": cannot be read");
    json doc;
    try {
        doc = json::parse(in);
    } catch (const json::exception& ex) {
        fail(file + ": not valid JSON (" + ex.what() + ")");
    }
    if (!doc.is_object()) fail(file + ": the top level must be an object");
    for (const char* key : {"document", "seed"})
        if (!doc.contains(key) || !doc[key].is_string()) fail(file + ": missing string field '" + key + "'");
    if (!doc.contains("entries") || !doc["entries"].is_array()) fail(file + ": missing array field 'entries'");
    const std::string document = document_label(doc["document"].get<std::string>(), doc["seed"].get<std::string>());

    std::size_t index = 0;
    for (const json& obj : doc["entries"]) {
        ++index;
        Entry e;
        e.file = file;
        e.document = document;
        e.object = &obj;
        e.report = &report_;
        e.label = "#" + std::to_string(index);
        e.where = "?";
        if (!obj.is_object()) e.bad("an entry must be an object");
        for (const char* key : {"entry", "where", "quantity"}) {
            auto it = obj.find(key);
            if (it == obj.end() || !it->is_string())
                e.bad(std::string("missing string field '") + key + "'");
        }
        e.label = obj["entry"].get<std::string>();
        e.where = obj["where"].get<std::string>();
        e.quantity = obj["quantity"].get<std::string>();
        try {
            check(e);
        } catch (const Error& ex) {
            const std::string message = ex.what();
            if (message.rfind(e.context(), 0) == 0) throw;
            e.bad(message);
        }
    }
}

void Checker::check(const Entry& e) {
    const std::string& q = e.quantity;
    if (q == "anderson.sigma") {
        scalar(e, table1_sigma(e.param("D"), e.param("M")));
    } else if (q == "anderson.c0") {
        const int D = e.param("D");
        const std::string spec = mollifier_spec(e.param("M"));
        const Kernel& k = kernel(spec, D);
        const Quantities& qs = quantities(spec, D);
        if (!qs.potential) fail("internal: no potential for " + spec);
        // phi = normalisation * v_N + const inside, v_N(1) = 0, c0 = v_N(0).
        const Exact c0 = (qs.potential->at(Q(0)) - qs.potential->at(Q(1))) * k.normalisation.inverse();
        if (!c0.is_rational()) fail("internal: c0 is not rational: " + c0.to_string());
        scalar(e, c0.rational());
    } else if (q == "anderson.gamma") {
        const ExponentMethod m = exponent_method(e.param("M"), e.param("order"), e.param("D"));
        const Exact gamma = m.normalisation * omega_anderson(e.param("D"));
        if (!gamma.is_rational()) fail("internal: gamma is not rational: " + gamma.to_string());
        scalar(e, gamma.rational());
    } else if (q == "anderson.alpha") {
        const ExponentMethod m = exponent_method(e.param("M"), e.param("order"), e.param("D"));
        const int j = e.param("j");
        if (j < 1 || j >= static_cast<int>(m.alpha.size()))
            e.bad("params.j = " + std::to_string(j) + " is outside 1.." + std::to_string(m.alpha.size() - 1));
        scalar(e, m.alpha[static_cast<std::size_t>(j)]);
    } else if (q == "anderson.sigma_formula") {
        anderson_sigma_formula(e);
    } else if (q == "anderson.second_moment") {
        anderson_second_moment(e);
    } else if (q == "anderson.radii_combination") {
        anderson_radii_combination(e);
    } else if (q == "anderson.kernel" || q == "anderson.potential" || q == "anderson.potential_gradient" ||
               q == "anderson.potential_hessian") {
        anderson_formula(e);
    } else if (q == "vandermonde.equidistant") {
        const int m = e.param("m"), j = e.param("j");
        if (m < 1 || m > max_combo_m) e.bad("params.m = " + std::to_string(m) + " is outside 1.." + std::to_string(max_combo_m));
        if (j < 1 || j > m) e.bad("params.j = " + std::to_string(j) + " is outside 1..m");
        scalar(e, vandermonde_weights(equidistant_radii(m))[static_cast<std::size_t>(j - 1)]);
    } else if (q == "wendland.shape") {
        wendland_shape_entry(e);
    } else if (q == "wendland.combo") {
        wendland_combo(e);
    } else if (q == "wendland.combo_weights") {
        wendland_combo_weights(e);
    } else if (q == "wendland_missing.shape") {
        wendland_missing(e);
    } else if (q == "classic.kernel") {
        classic_kernel(e);
    } else if (q == "belley.moment") {
        belley_moment(e);
    } else if (q == "belley.kernel_value") {
        belley_kernel_value(e);
    } else {
        e.bad("unknown quantity '" + q + "'");
    }
}

void Checker::scalar(const Entry& e, const Q& exact, const std::string& remark_if_wrong) {
    const Q printed = e.rational(e.printed(), "printed");
    std::string remark = remark_if_wrong;
    if (remark.empty() && printed != exact && exact != 0 && printed != 0) remark = factor_remark(printed / exact);
    e.compare(printed == exact, "", short_string(printed), short_string(exact), remark);
}

// ---------------------------------------------------------------------------
// Anderson

void Checker::anderson_sigma_formula(const Entry& e) {
    const int D = e.param("D");
    const Q exact = table1_sigma(D, e.param("M"));
    const Q printed = e.rational(e.printed(), "printed");
    std::string remark;
    if (printed != exact && D == 1 && printed == 2 * exact)
        remark = "Theorem 1's formula assumes omega_1 = 2; with the paper's omega_1 = 1 (§2) it is off by a factor 2";
    scalar(e, exact, remark);
}

void Checker::anderson_second_moment(const Entry& e) {
    const int D = e.param("D");
    const Kernel& k = kernel(mollifier_spec(e.param("M")), D);
    const Exact m2 = radial_moment(k, 2) * Q(1, D);  // int B x_i^2 = int B |x|^2 / D, delta = 1
    if (!m2.is_rational()) fail("internal: second moment is not rational: " + m2.to_string());
    const Q printed = e.rational(e.printed(), "value", "printed");
    const int dp = e.integer(e.printed(), "delta_power", "printed");
    e.compare(printed == m2.rational(), "", short_string(printed), short_string(m2.rational()),
              printed == m2.rational() ? "" : factor_remark(printed / m2.rational()));
    // Scaling B_delta(x) = delta^-D B(x/delta) multiplies the second moment by delta^2.
    e.compare(dp == 2, "power of delta", delta_string(dp), delta_string(2));
}

void Checker::anderson_radii_combination(const Entry& e) {
    const int order = e.param("order");
    if (order < 4 || order % 2 != 0 || order / 2 > max_combo_m) e.bad("params.order must be even and at least 4");
    const std::vector<Q> radii = equidistant_radii(order / 2);  // a_j = j/K, eq. (8)
    const std::vector<Q> w = vandermonde_weights(radii);
    std::vector<bool> used(radii.size(), false);
    struct Term {
        Q weight, scale;
    };
    std::vector<Term> printed;
    for (const json& t : e.printed_array("terms"))
        printed.push_back({e.rational(t, "weight", "printed.terms[]"), e.rational(t, "argument_scale", "printed.terms[]")});
    // The member of radius a is B_a(r) = a^-N B(r/a): argument scale 1/a. A
    // printed scale s is matched with the radius 1/s, else with the radius s
    // (the argument read as the radius).
    std::vector<std::optional<std::size_t>> match(printed.size());
    for (int pass = 0; pass < 2; ++pass)
        for (std::size_t i = 0; i < printed.size(); ++i) {
            if (match[i] || printed[i].scale <= 0) continue;
            for (std::size_t j = 0; j < radii.size(); ++j)
                if (!used[j] && (pass == 0 ? radii[j] * printed[i].scale == 1 : radii[j] == printed[i].scale)) {
                    match[i] = j;
                    used[j] = true;
                    break;
                }
        }
    auto b_of = [](const Q& w_, const Q& s) { return short_string(w_) + " * B(" + short_string(s) + " r)"; };
    for (std::size_t i = 0; i < printed.size(); ++i) {
        const std::string part = "term " + b_of(printed[i].weight, printed[i].scale);
        if (!match[i]) {
            e.compare(false, part, b_of(printed[i].weight, printed[i].scale), "no such term",
                      "no radius j/" + std::to_string(order / 2) + " has argument scale " + short_string(printed[i].scale));
            continue;
        }
        const std::size_t j = *match[i];
        const Q& a = radii[j];
        e.compare(printed[i].weight == w[j], part + ", weight", short_string(printed[i].weight), short_string(w[j]),
                  factor_remark(w[j] != 0 ? std::optional<Q>(printed[i].weight / w[j]) : std::nullopt));
        const Q inv = Q(1) / a;
        const std::string exact = short_string(w[j]) + " * B_{" + short_string(a) + "}(r) = " + short_string(w[j]) +
                                  " * " + (is_integer(inv) ? short_string(inv) : "(" + short_string(inv) + ")") +
                                  "^N * B(" + short_string(inv) + " r)";
        e.compare(printed[i].scale == inv, part + ", argument", b_of(printed[i].weight, printed[i].scale), exact,
                  "B(" + short_string(printed[i].scale) + " r) is B_{" + short_string(a) +
                      "}(r) only after rescaling: B_{" + short_string(a) + "}(r) = " +
                      (is_integer(inv) ? short_string(inv) : "(" + short_string(inv) + ")") + "^N B(" +
                      short_string(inv) + " r); the weights give unit mass and vanishing moments only for the radius-" +
                      short_string(a) + " member");
    }
    for (std::size_t j = 0; j < radii.size(); ++j)
        if (!used[j])
            e.compare(false, "term of radius " + short_string(radii[j]), "missing",
                      short_string(w[j]) + " * B_{" + short_string(radii[j]) + "}(r)");
}

// B_delta, phi_delta and its derivatives, Anderson §4 and Appendix B.
void Checker::anderson_formula(const Entry& e) {
    const int D = e.param("D"), M = e.param("M"), order = e.param("order");
    const std::string spec = mollifier_spec(M, order);
    const Kernel& k = kernel(spec, D);
    const json& pr = e.printed();
    const json& pre = e.need(pr, "prefactor", "printed");
    const Exact prefactor = Exact::pi_power(e.rational(pre, "value", "printed.prefactor"),
                                            e.integer(pre, "pi_power", "printed.prefactor"));
    const int printed_dp = e.integer(pre, "delta_power", "printed.prefactor");
    const std::string variable = e.text(pr, "variable", "printed");
    const bool is_kernel = e.quantity == "anderson.kernel";
    const std::string expected_variable = is_kernel ? "1-(r/delta)^2" : "r/delta";
    if (variable != expected_variable) e.bad("printed.variable must be \"" + expected_variable + "\" for " + e.quantity);
    auto var_power = [&](int n) { return "(" + expected_variable + ")^" + std::to_string(n); };

    auto scaled = [&](const std::map<int, Q>& m) {
        Coefficients c;
        for (const auto& [n, v] : m) add_coefficient(c, n, prefactor * v);
        return c;
    };
    auto keys = [](const std::map<int, Q>& m) {
        std::set<int> s;
        for (const auto& [n, v] : m) s.insert(n);
        return s;
    };
    // The printed bracket coefficient and the exact one relative to the
    // printed prefactor, when that is rational.
    auto bracket_remark = [&](int, const Exact& p, const Exact& x) {
        std::vector<std::string> r;
        const auto pb = p.is_zero() ? std::optional<Q>(Q(0)) : ratio(p, prefactor);
        const auto xb = x.is_zero() ? std::optional<Q>(Q(0)) : ratio(x, prefactor);
        if (pb && xb) r.push_back("bracket coefficient printed " + short_string(*pb) + ", exact " + short_string(*xb));
        if (!p.is_zero() && !x.is_zero()) {
            const auto f = ratio(p, x);
            r.push_back(factor_remark(f));
            // A stray sigma in a printed denominator, e.g. (2 sigma k).
            const Q sigma = table1_sigma(D, M);
            if (f && *f == 1 / sigma) r.push_back("consistent with a spurious factor 1/sigma_{M(" + std::to_string(D) +
                                                  ")} = 1/" + short_string(sigma) + " in the printed coefficient");
        }
        return join(r, "; ");
    };
    auto single_piece = [&](const Radial& f, const char* what) -> const ClosedForm& {
        if (f.pieces.size() != 1) fail(std::string("internal: ") + what + " of " + spec + " has several pieces");
        return f.pieces[0];
    };
    auto compare_delta = [&](const std::string& part, int exact_dp) {
        e.compare(printed_dp == exact_dp, part, delta_string(printed_dp), delta_string(exact_dp),
                  printed_dp == exact_dp ? ""
                                         : "printed " + delta_string(printed_dp) + ", exact " + delta_string(exact_dp));
    };

    if (is_kernel) {
        // B_delta(r) = delta^-D B(r/delta); B as a polynomial in u = 1 - s^2.
        Laurent p;
        Atom factor;
        if (!single_piece(k.W, "kernel").single_polynomial(&p, &factor)) fail("internal: kernel is not a polynomial");
        const std::vector<Q> u = p.even_part_in_square().taylor_at(Q(1));
        Coefficients exact;
        for (std::size_t i = 0; i < u.size(); ++i) add_coefficient(exact, static_cast<int>(i), exact_from(u[i], factor));
        const auto printed = e.coefficient_map(pr, "coefficients", "printed");
        compare_coefficients(e, scaled(printed), exact, keys(printed),
                             [&](int n) { return "coefficient of " + var_power(n); }, bracket_remark);
        compare_delta("power of delta", -D);
        return;
    }

    const Quantities& qs = quantities(spec, D);
    if (!qs.potential) fail("internal: no potential for " + spec);
    if (e.quantity == "anderson.potential") {
        // phi_delta(r) = delta^(2-D) phi(r/delta) + [D = 2] g log(delta), g the
        // log r coefficient of the Green's function. Anderson's bracket
        // vanishes at r = delta; the additive part is the Green's function at
        // r = delta, delta^(2-D) phi(1) (+ g log delta).
        const Exact phi1 = qs.potential->at(Q(1));
        Coefficients exact = coefficients(single_piece(*qs.potential, "potential"));
        add_coefficient(exact, 0, -phi1);
        const auto printed = e.coefficient_map(pr, "coefficients", "printed");
        compare_coefficients(e, scaled(printed), exact, keys(printed),
                             [&](int n) { return "coefficient of " + var_power(n); }, bracket_remark);
        compare_delta("power of delta", 2 - D);

        struct Additive {
            Exact c;
            int delta_power;
            bool log;
            bool operator==(const Additive& o) const { return c == o.c && delta_power == o.delta_power && log == o.log; }
            std::string str() const {
                return c.to_string() + (delta_power != 0 ? " * " + delta_string(delta_power) : "") +
                       (log ? " * log(delta)" : "");
            }
        };
        std::vector<Additive> exact_add;
        if (!phi1.is_zero()) exact_add.push_back({phi1, 2 - D, false});
        for (const auto& [key, p] : qs.potential->outside.terms())
            if (key.basis == Basis::log) exact_add.push_back({exact_from(p.coefficient(0), key.factor), 0, true});
        const json& add = e.need(pr, "additive", "printed");
        const Additive printed_add{
            Exact::pi_power(e.rational(add, "value", "printed.additive"), e.integer(add, "pi_power", "printed.additive")),
            e.integer(add, "delta_power", "printed.additive"), e.boolean(add, "log_delta", "printed.additive")};
        std::vector<std::string> exact_strings;
        for (const auto& a : exact_add) exact_strings.push_back(a.str());
        const bool same = exact_add.size() == 1 && exact_add[0] == printed_add;
        std::string remark;
        if (!same && exact_add.size() == 1 && exact_add[0].delta_power == printed_add.delta_power &&
            exact_add[0].log == printed_add.log && exact_add[0].c == -printed_add.c)
            remark = "sign differs: continuity with the exterior potential at r = delta needs " + exact_add[0].str();
        e.compare(same, "additive term", printed_add.str(), join(exact_strings, " + "), remark);
        return;
    }
    if (e.quantity == "anderson.potential_gradient") {
        // d phi_delta / dx_i = delta^-D (phi'/s)(s) x_i, s = r/delta.
        const Coefficients exact = coefficients(single_piece(*qs.dpotential_over_r, "potential gradient"));
        const auto printed = e.coefficient_map(pr, "coefficients", "printed");
        compare_coefficients(e, scaled(printed), exact, keys(printed),
                             [&](int n) { return "coefficient of " + var_power(n) + " x_i"; }, bracket_remark);
        compare_delta("power of delta", -D);
        return;
    }
    // Hessian: delta^-D [delta^-2 H(s) x_i x_j + (phi'/s)(s) eps_ij].
    const Coefficients xx = coefficients(single_piece(*qs.potential_hess_radial, "potential Hessian"));
    const Coefficients dij = coefficients(single_piece(*qs.dpotential_over_r, "potential gradient"));
    const auto printed_xx = e.coefficient_map(pr, "xixj", "printed");
    const auto printed_dij = e.coefficient_map(pr, "delta_ij", "printed");
    compare_coefficients(e, scaled(printed_xx), xx, keys(printed_xx),
                         [&](int n) { return "x_i x_j coefficient of " + var_power(n); }, bracket_remark);
    compare_delta("x_i x_j term, power of delta", -D - 2);
    compare_coefficients(e, scaled(printed_dij), dij, keys(printed_dij),
                         [&](int n) { return "epsilon_ij coefficient of " + var_power(n); }, bracket_remark);
    compare_delta("epsilon_ij term, power of delta", -D);
}

// ---------------------------------------------------------------------------
// Franz: Wendland functions and their combinations

void Checker::wendland_shape_entry(const Entry& e) {
    const int d = e.param("d"), k = e.param("k"), l = e.param("l");
    if (d < 1 || d > 3 || k < 0 || k > max_wendland_k || l < 0 || l > max_wendland_l) e.bad("params out of range");
    const Laurent exact = wendland_shape(d, k, l);
    const int edge = exact.multiplicity_of_root(Q(1));
    const json& pr = e.printed();
    const int printed_edge = e.integer(pr, "edge_power", "printed");
    if (printed_edge < 0 || printed_edge > 200) e.bad("printed.edge_power must be in 0..200");
    Laurent printed_poly;
    for (const auto& [n, c] : e.coefficient_map(pr, "poly", "printed")) printed_poly += Laurent::monomial(c, n);
    // Edge power 0 is a formula printed in monomials (e.g. Thm. 4.38): its
    // factor (1-r)^edge is checked through the expanded coefficients.
    if (printed_edge != 0)
        e.compare(printed_edge == edge, "edge power", "(1-r)^" + std::to_string(printed_edge),
                  "(1-r)^" + std::to_string(edge));
    // Same edge power: compare the brackets; otherwise the expanded psi.
    Laurent p = printed_poly, x = *exact.divided_by_linear_power(Q(1), edge);
    std::string what = "coefficient of r^";
    if (printed_edge != edge) {
        p = printed_poly * Laurent::binomial_power(Q(1), Q(-1), printed_edge);
        x = exact;
        what = "expanded psi, coefficient of r^";
    }
    std::set<int> keys;
    for (const auto& [n, c] : e.coefficient_map(pr, "poly", "printed")) keys.insert(n);
    for (int n = x.low(); n <= x.high(); ++n)
        if (x.coefficient(n) != 0) keys.insert(n);
    for (int n = p.low(); n <= p.high(); ++n)
        if (p.coefficient(n) != 0) keys.insert(n);
    std::vector<Proportional> items;
    for (int n : keys) items.push_back({what + std::to_string(n), Exact(p.coefficient(n)), Exact(x.coefficient(n))});
    compare_proportional(e, items, std::nullopt, "");
}

namespace {

// The printed combination sum weight (1 - scale r)_+^e poly(r), piecewise.
struct ComboTerm {
    Q weight, scale;
    int edge_power = 0;
    Laurent poly;
    Laurent expanded() const { return Laurent::binomial_power(Q(1), -scale, edge_power) * poly * weight; }
};

Radial zero_radial() {
    Radial r;
    r.breaks = {Q(0), Q(1)};
    r.pieces = {ClosedForm()};
    return r;
}

const ClosedForm& form_on(const Radial& f, const Q& mid) {
    static const ClosedForm zero;
    if (mid >= f.support()) return f.outside.is_zero() ? zero : f.outside;
    return f.pieces[f.piece_index(mid)];
}

std::string psi_term(const Q& weight, const Q& scale) {
    const std::string psi = "psi(" + (scale == 1 ? std::string("r") : short_string(scale) + " r") + ")";
    return weight == 1 ? psi : weight == -1 ? "-" + psi : short_string(weight) + " " + psi;
}

}  // namespace

void Checker::wendland_combo(const Entry& e) {
    const int d = e.param("d"), k = e.param("k"), l = e.param("l"), m = e.param("m");
    if (m < 2 || m % 2 != 0 || m / 2 > max_combo_m) e.bad("params.m (the moment order) must be even and at least 2");
    const int K = m / 2;
    const std::string base = "wendland:k=" + std::to_string(k) + ",l=" + std::to_string(l);
    const Kernel& combo = kernel("combo:m=" + std::to_string(K) + ",base=" + base, d);
    const Kernel& psi = kernel(base, d);
    const std::vector<Q> radii = equidistant_radii(K);
    const std::vector<Q> w = vandermonde_weights(radii);

    std::vector<ComboTerm> terms;
    for (const json& t : e.printed_array("terms")) {
        ComboTerm ct;
        ct.weight = e.rational(t, "weight", "printed.terms[]");
        ct.scale = e.rational(t, "scale", "printed.terms[]");
        ct.edge_power = e.integer(t, "edge_power", "printed.terms[]");
        if (ct.scale <= 0) e.bad("printed.terms[].scale must be positive");
        if (ct.edge_power < 0 || ct.edge_power > 200) e.bad("printed.terms[].edge_power must be in 0..200");
        for (const auto& [n, c] : e.coefficient_map(t, "poly", "printed.terms[]")) ct.poly += Laurent::monomial(c, n);
        terms.push_back(ct);
    }
    Radial printed = zero_radial();
    for (const auto& t : terms) printed = printed + Radial::single(ClosedForm(t.expanded()), Q(1) / t.scale);

    // Pair printed terms with the exact members w_j psi_{a_j} (scale 1/a_j).
    std::vector<bool> used(radii.size(), false);
    std::vector<std::optional<std::size_t>> match(terms.size());
    for (std::size_t i = 0; i < terms.size(); ++i)
        for (std::size_t j = 0; j < radii.size(); ++j)
            if (!used[j] && terms[i].scale * radii[j] == 1) {
                match[i] = j;
                used[j] = true;
                break;
            }
    auto exact_term = [&](std::size_t j) {
        const Radial t = psi.shape.scaled(radii[j], d) * Exact(w[j]);
        return coefficients(t.pieces[0]);
    };
    // The constant: from the matched term of largest support.
    std::optional<Q> factor;
    std::optional<std::size_t> anchor;
    for (std::size_t i = 0; i < terms.size(); ++i)
        if (match[i] && (!anchor || radii[*match[i]] > radii[*match[*anchor]])) anchor = i;
    if (anchor) {
        const Coefficients x = exact_term(*match[*anchor]);
        const Coefficients p = coefficients(terms[*anchor].expanded());
        std::vector<std::pair<Exact, Exact>> pairs;
        for (const auto& [n, v] : x) pairs.emplace_back(p.count(n) ? p.at(n) : Exact(), v);
        factor = common_factor(pairs);
    }
    // Franz's psi as the table prints it, read off the anchor term
    // weight * psi(scale r); the exact members in that normalisation.
    std::optional<Laurent> psi_printed;
    Q weight_scale = 1;
    if (anchor) {
        const ComboTerm& t = terms[*anchor];
        psi_printed = (t.expanded() * (Q(1) / t.weight)).scaled_argument(Q(1) / t.scale);
        const std::size_t ja = *match[*anchor];
        weight_scale = t.weight / (w[ja] * pow(Q(1) / radii[ja], d));
    }
    auto lambda = [&](std::size_t j) { return w[j] * pow(Q(1) / radii[j], d) * weight_scale; };
    auto member = [&](const Q& weight, const Q& s) {
        std::string text = psi_term(weight, s);
        if (!psi_printed) return text;
        const Laurent p = psi_printed->scaled_argument(s);
        const int edge = p.multiplicity_of_root(Q(1) / s);
        const Laurent q = *p.divided_by_linear_power(Q(1) / s, edge) * pow(Q(1) / s, edge);
        std::vector<std::string> ts;
        for (int n = q.high(); n >= q.low(); --n)
            if (q.coefficient(n) != 0) ts.push_back(monomial_string(q.coefficient(n), {{"r", n}}));
        const std::string body = "(1 - " + (s == 1 ? std::string("r") : short_string(s) + " r") + ")_+^" +
                                 std::to_string(edge) + " (" + sum_string(ts) + ")";
        return text + " = " + (weight == 1 ? body : weight == -1 ? "-" + body : short_string(weight) + " " + body);
    };
    // What the term structure says, for the remarks.
    std::vector<std::string> notes;
    std::vector<std::size_t> lone_printed, lone_exact;
    for (std::size_t i = 0; i < terms.size(); ++i)
        if (!match[i]) lone_printed.push_back(i);
    for (std::size_t j = 0; j < radii.size(); ++j)
        if (!used[j]) lone_exact.push_back(j);
    const Q c = factor.value_or(Q(1));
    for (std::size_t n = 0; n < std::max(lone_printed.size(), lone_exact.size()); ++n) {
        if (n < lone_printed.size() && n < lone_exact.size()) {
            const std::size_t i = lone_printed[n], j = lone_exact[n];
            notes.push_back("printed term " + psi_term(terms[i].weight, terms[i].scale) + " should be the radius-" +
                            short_string(radii[j]) + " member " + member(lambda(j), Q(1) / radii[j]) +
                            " (radii a_j = j/" + std::to_string(K) + ")");
        } else if (n < lone_printed.size()) {
            const std::size_t i = lone_printed[n];
            notes.push_back("printed term " + psi_term(terms[i].weight, terms[i].scale) + " matches no radius j/" +
                            std::to_string(K));
        } else {
            const std::size_t j = lone_exact[n];
            notes.push_back("term " + member(lambda(j), Q(1) / radii[j]) + " missing");
        }
    }
    for (std::size_t i = 0; i < terms.size(); ++i) {
        if (!match[i]) continue;
        const Coefficients x = exact_term(*match[i]);
        const Coefficients p = coefficients(terms[i].expanded());
        bool same = true;
        std::set<int> ks;
        for (const auto& [n, v] : x) ks.insert(n);
        for (const auto& [n, v] : p) ks.insert(n);
        for (int n : ks)
            same = same && (p.count(n) ? p.at(n) : Exact()) == (x.count(n) ? x.at(n) * c : Exact());
        if (!same)
            notes.push_back("printed term " + psi_term(terms[i].weight, terms[i].scale) + " differs from the exact member " +
                            member(lambda(*match[i]), terms[i].scale));
    }
    const std::string remark = join(notes, "; ");

    // Piece by piece on the merged breakpoints, coefficient by coefficient.
    std::vector<Q> breaks = printed.breaks;
    breaks.insert(breaks.end(), combo.shape.breaks.begin(), combo.shape.breaks.end());
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    std::vector<Proportional> items;
    for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
        const Q mid = (breaks[b] + breaks[b + 1]) / 2;
        const Coefficients p = coefficients(form_on(printed, mid));
        const Coefficients x = coefficients(form_on(combo.shape, mid));
        std::set<int> ks;
        for (const auto& [n, v] : x) ks.insert(n);
        for (const auto& [n, v] : p) ks.insert(n);
        const std::string piece = "piece [" + short_string(breaks[b]) + ", " + short_string(breaks[b + 1]) +
                                  (b + 2 == breaks.size() ? "]" : ")");
        for (int n : ks)
            items.push_back({piece + ", coefficient of r^" + std::to_string(n), p.count(n) ? p.at(n) : Exact(),
                             x.count(n) ? x.at(n) : Exact()});
    }
    compare_proportional(e, items, factor, remark);
}

void Checker::wendland_combo_weights(const Entry& e) {
    const int d = e.param("d"), m = e.param("m");
    if (m < 2 || m % 2 != 0 || m / 2 > max_combo_m) e.bad("params.m (the moment order) must be even and at least 2");
    const int K = m / 2;
    const std::vector<Q> radii = equidistant_radii(K);
    const std::vector<Q> w = vandermonde_weights(radii);
    // Phi = sum_j w_j psi_{a_j} = sum_j w_j a_j^-d psi(r / a_j).
    std::vector<Q> lambda, scale;
    for (std::size_t j = 0; j < radii.size(); ++j) {
        lambda.push_back(w[j] * pow(Q(1) / radii[j], d));
        scale.push_back(Q(1) / radii[j]);
    }
    struct Term {
        Q weight, scale;
    };
    std::vector<Term> printed;
    for (const json& t : e.printed_array("terms"))
        printed.push_back({e.rational(t, "weight", "printed.terms[]"), e.rational(t, "scale", "printed.terms[]")});
    std::vector<bool> used(radii.size(), false);
    std::vector<std::optional<std::size_t>> match(printed.size());
    for (std::size_t i = 0; i < printed.size(); ++i)
        for (std::size_t j = 0; j < radii.size(); ++j)
            if (!used[j] && printed[i].scale == scale[j]) {
                match[i] = j;
                used[j] = true;
                break;
            }
    // Leftovers pair up in order of decreasing scale (as the tables list them).
    std::vector<std::size_t> lone_exact;
    for (std::size_t j = radii.size(); j-- > 0;)
        if (!used[j]) lone_exact.push_back(j);
    std::vector<bool> scale_matched(printed.size());
    std::size_t next = 0;
    for (std::size_t i = 0; i < printed.size(); ++i) {
        scale_matched[i] = match[i].has_value();
        if (!match[i] && next < lone_exact.size()) {
            match[i] = lone_exact[next++];
            used[*match[i]] = true;
        }
    }
    std::vector<std::pair<Exact, Exact>> pairs;
    for (std::size_t i = 0; i < printed.size(); ++i)
        if (match[i] && scale_matched[i]) pairs.emplace_back(Exact(printed[i].weight), Exact(lambda[*match[i]]));
    const Q c = common_factor(pairs).value_or(Q(1));
    for (std::size_t i = 0; i < printed.size(); ++i) {
        const std::string part = "term " + psi_term(printed[i].weight, printed[i].scale);
        if (!match[i]) {
            e.compare(false, part, psi_term(printed[i].weight, printed[i].scale), "no such term",
                      "only " + std::to_string(K) + " radii j/" + std::to_string(K));
            continue;
        }
        const std::size_t j = *match[i];
        const Q expected = lambda[j] * c;
        std::vector<std::string> remark;
        if (printed[i].weight != expected && c != 1) remark.push_back("exact value times the common factor " + short_string(c));
        if (printed[i].weight != expected && c < 0) remark.push_back("differs by a sign");
        e.compare(printed[i].weight == expected, part + ", weight", short_string(printed[i].weight), short_string(expected),
                  join(remark, "; "));
        e.compare(printed[i].scale == scale[j], part + ", argument scale", "psi(" + short_string(printed[i].scale) + " r)",
                  "psi(" + short_string(scale[j]) + " r)",
                  "the radii are a_j = j/" + std::to_string(K) + " (Franz: a_j = b j); the weight " +
                      short_string(printed[i].weight) + " fits the radius-" + short_string(radii[j]) + " member psi(" +
                      short_string(scale[j]) + " r), while psi(" + short_string(printed[i].scale) + " r) has radius " +
                      short_string(Q(1) / printed[i].scale));
    }
    for (std::size_t j = 0; j < radii.size(); ++j)
        if (!used[j])
            e.compare(false, "term of radius " + short_string(radii[j]), "missing", psi_term(lambda[j] * c, scale[j]));
}

void Checker::wendland_missing(const Entry& e) {
    const int d = e.param("d"), k = e.param("k"), l = e.param("l");
    if (d < 1 || d > 3 || k < 0 || k > max_wendland_k || l < 0 || l > max_wendland_l) e.bad("params out of range");
    const ClosedForm psi = missing_wendland_shape(d, k, l);
    Laurent L, S;
    for (const auto& [key, p] : psi.terms()) {
        if (key.factor != Atom{}) fail("internal: missing Wendland function with a constant factor");
        if (key.basis == Basis::arcsech) L += p;
        else if (key.basis == Basis::sqrt_power && key.s_power == 1) S += p;
        else fail("internal: missing Wendland function outside span{L, S}");
    }
    const json& pr = e.printed();
    std::vector<Proportional> items;
    for (const auto& [name, exact] : {std::pair<std::string, const Laurent*>{"L", &L}, {"S", &S}}) {
        const auto printed = e.coefficient_map(pr, name, "printed");
        std::set<int> ks;
        for (const auto& [n, v] : printed) ks.insert(n);
        for (int n = exact->low(); n <= exact->high(); ++n)
            if (exact->coefficient(n) != 0) ks.insert(n);
        for (int n : ks)
            items.push_back({name + " coefficient of r^" + std::to_string(n),
                             Exact(printed.count(n) ? printed.at(n) : Q(0)), Exact(exact->coefficient(n))});
    }
    compare_proportional(e, items, std::nullopt, "");
}

// ---------------------------------------------------------------------------
// Belley

namespace {

int derivative_order(const Kernel& k) {
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

}  // namespace

void Checker::classic_kernel(const Entry& e) {
    const std::string name = e.param_text("kernel");
    const int D = e.param("D");
    const Kernel& k = kernel(name, D);
    const json& pr = e.printed();
    const json& pre = e.need(pr, "prefactor", "printed");
    const Q pre_value = e.rational(pre, "value", "printed.prefactor");
    const int pre_pi = e.integer(pre, "pi_power", "printed.prefactor");
    const int pre_h = e.integer(pre, "h_power", "printed.prefactor");
    struct Term {
        Q c;
        int r, h;
    };
    std::vector<Term> terms;
    for (const json& t : e.printed_array("terms"))
        terms.push_back({e.rational(t, "coeff", "printed.terms[]"), e.integer(t, "r_power", "printed.terms[]"),
                         e.integer(t, "h_power", "printed.terms[]")});
    const bool abs = e.boolean(pr, "abs", "printed");
    const std::string support = e.text(pr, "support", "printed");

    // Printed and exact expressions for people.
    std::vector<std::string> term_strings;
    for (const auto& t : terms) term_strings.push_back(monomial_string(t.c, {{"r", t.r}, {"h", t.h}}));
    const std::string pre_string = Exact::pi_power(pre_value, pre_pi).to_string() +
                                   (pre_h != 0 ? " * h^" + std::to_string(pre_h) : "");
    const std::string bracket = sum_string(term_strings);
    const std::string printed_string = pre_string + " * " + (abs ? "|" + bracket + "|" : "(" + bracket + ")");
    // W_h(r) = h^-D W(r/h) = normalisation h^-D sum c_n (r/h)^n; written with
    // the printed prefactor when the normalisations differ by a rational.
    Laurent shape;
    Atom factor;
    if (k.W.pieces.size() != 1 || !k.W.pieces[0].single_polynomial(&shape, &factor))
        fail("internal: " + name + " is not a single polynomial piece");
    std::string exact_string;
    {
        const auto rel = ratio(exact_from(Q(1), factor), Exact::pi_power(pre_value, pre_pi));
        std::vector<std::string> ts;
        for (int n = shape.high(); n >= shape.low(); --n) {
            const Q c = shape.coefficient(n);
            if (c == 0) continue;
            if (rel) ts.push_back(monomial_string(c * *rel, {{"r", n}, {"h", -n - D - pre_h}}));
            else ts.push_back(monomial_string(c, {{"(r/h)", n}}));
        }
        exact_string = rel ? pre_string + " * (" + sum_string(ts) + ")"
                           : exact_from(Q(1), factor).to_string() + " * h^" + std::to_string(-D) + " * (" + sum_string(ts) + ")";
    }

    // Values at h = 2 and a few r in (0, h).
    const Q h(2);
    std::vector<std::optional<Q>> ratios;
    bool exact_bracket_positive = true;
    for (const Q& t : {Q(1, 7), Q(2, 5), Q(3, 4), Q(9, 10)}) {
        const Q r = t * h;
        Q sum = 0;
        for (const auto& term : terms) sum += term.c * pow(r, term.r) * pow(h, term.h);
        const Exact printed = Exact::pi_power(pre_value * pow(h, pre_h) * (abs && sum < 0 ? Q(-sum) : sum), pre_pi);
        const Exact exact = k.W.at(t) * pow(h, -D);
        if (shape(t) <= 0) exact_bracket_positive = false;
        ratios.push_back(exact.is_zero() ? std::nullopt : (printed.is_zero() ? std::optional<Q>(Q(0)) : ratio(printed, exact)));
    }
    const bool proportional = std::all_of(ratios.begin(), ratios.end(), [&](const auto& r) { return r && r == ratios[0]; });
    std::string remark;
    bool same = false;
    if (proportional && *ratios[0] == 1) {
        same = true;
    } else if (proportional) {
        remark = "differs by a factor " + short_string(*ratios[0]);
    } else {
        // Dimension check: every term r^a h^b of the bracket should have the
        // same degree a + b.
        std::map<int, int> degree_count;
        for (const auto& t : terms) ++degree_count[t.r + t.h];
        int common = 0, best = -1;
        for (const auto& t : terms)
            if (degree_count[t.r + t.h] > best) {
                best = degree_count[t.r + t.h];
                common = t.r + t.h;
            }
        std::vector<std::string> odd;
        for (const auto& t : terms)
            if (t.r + t.h != common)
                odd.push_back(monomial_string(t.c, {{"r", t.r}, {"h", t.h}}) + " (degree " + std::to_string(t.r + t.h) +
                              ")");
        remark = "differs in form";
        if (!odd.empty())
            remark += ": dimensionally inconsistent term " + join(odd, ", ") + "; the other terms have degree " +
                      std::to_string(common) + " in r and h";
    }
    e.compare(same, "formula", printed_string, exact_string, remark);
    e.compare(!abs, "absolute value", "|" + bracket + "|", "no absolute value",
              std::string("the kernel has no absolute value") +
                  (exact_bracket_positive ? "; its bracket is positive for 0 < r < h, where the bars change nothing" : ""));

    // Support: |r| <= h, in any of the usual spellings.
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

void Checker::belley_moment(const Entry& e) {
    const std::string name = e.param_text("kernel");
    const int n = e.param("n");
    if (n < 0 || n > 40) e.bad("params.n out of range");
    const Kernel& k = kernel(name, 1);
    const int p = derivative_order(k);
    // K_h(y) = h^(-1-p) W(y/h): int y^m K_h = h^(m-p) mu_m, mu_m = int_R s^m W.
    // int x^n K_h(x0 - x) dx = sum_m C(n,m) (-1)^m x0^(n-m) h^(m-p) mu_m.
    std::map<std::pair<int, int>, Q> exact;
    for (int m = 0; m <= n; ++m) {
        const Exact half = radial_integral(k.W, m);
        if (!half.is_rational()) fail("internal: moment of " + name + " is not rational");
        const Q mu = half.rational() * (1 + k.W.parity * (m % 2 == 0 ? 1 : -1));
        const Q c = Q(binomial(static_cast<unsigned>(n), static_cast<unsigned>(m))) * (m % 2 == 0 ? 1 : -1) * mu;
        if (c == 0) continue;
        Q& slot = exact[{n - m, m - p}];
        slot += c;
        if (slot == 0) exact.erase({n - m, m - p});
    }
    std::map<std::pair<int, int>, Q> printed;
    for (const json& t : e.printed_array("terms")) {
        const Q c = e.rational(t, "coeff", "printed.terms[]");
        const auto key = std::make_pair(e.integer(t, "x0_power", "printed.terms[]"), e.integer(t, "h_power", "printed.terms[]"));
        printed[key] += c;
        if (printed[key] == 0) printed.erase(key);
    }
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

void Checker::belley_kernel_value(const Entry& e) {
    const std::string name = e.param_text("kernel");
    e.param_text("piece");
    const Kernel& k = kernel(name, 1);
    const int exact_hp = -1 - derivative_order(k);
    const json& pr = e.printed();
    const Q value = e.rational(pr, "value", "printed");
    const int hp = e.integer(pr, "h_power", "printed");
    const json& interval = e.need(pr, "interval", "printed");
    if (!interval.is_array() || interval.size() != 2) e.bad("printed.interval must be [lo, hi]");
    const Q lo = e.rational(interval[0], "printed.interval[0]"), hi = e.rational(interval[1], "printed.interval[1]");
    if (!(lo < hi)) e.bad("printed.interval must have lo < hi");
    // Split (lo, hi) at 0 and at the breakpoints +-b; the kernel must be one
    // constant on every part.
    std::vector<Q> cuts{lo, hi, Q(0)};
    for (const Q& b : k.W.breaks) {
        cuts.push_back(b);
        cuts.push_back(-b);
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    std::vector<std::pair<std::string, Exact>> parts;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
        if (cuts[i] < lo || cuts[i + 1] > hi) continue;
        const Exact v = value_1d(k.W, (cuts[i] + cuts[i + 1]) / 2);
        if (parts.empty() || !(parts.back().second == v))
            parts.emplace_back("(" + short_string(cuts[i]) + " h, " + short_string(cuts[i + 1]) + " h)", v);
    }
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

}  // namespace

ErrataReport check_errata(const std::filesystem::path& dir) {
    if (!fs::is_directory(dir)) fail("transcriptions directory " + dir.string() + " does not exist");
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
    ErrataReport report;
    Checker checker(report);
    for (const auto& f : files) checker.run_file(f);
    return report;
}

std::string format_line(const Discrepancy& d) {
    std::string s = d.document + " | " + d.where + " | " + d.entry + " | printed: " + d.printed + " | exact: " + d.exact;
    if (!d.remark.empty()) s += " | " + d.remark;
    return s;
}

}  // namespace mollify::gen
