#include "errata_checker.hpp"

#include "error.hpp"
#include "spec.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>

namespace mollify::gen::errata {

// ---------------------------------------------------------------------------
// Exact helpers

Exact exact_from(const Q& q, const Atom& a) { return Exact::of(a) * q; }

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

Coefficients coefficients(const ClosedForm& f) {
    Coefficients c;
    for (const auto& [key, p] : f.terms()) {
        if (key.basis != Basis::one) fail("internal: expected a polynomial closed form");
        for (int n = p.low(); n <= p.high(); ++n) add_coefficient(c, n, exact_from(p.coefficient(n), key.factor));
    }
    return c;
}

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

// ---------------------------------------------------------------------------
// Values spelled for people

json read_transcription(const std::filesystem::path& path, std::initializer_list<const char*> string_fields) {
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
    for (const char* key : string_fields)
        if (!doc.contains(key) || !doc[key].is_string()) fail(file + ": missing string field '" + key + "'");
    if (!doc.contains("entries") || !doc["entries"].is_array()) fail(file + ": missing array field 'entries'");
    return doc;
}

namespace {

// "x^n" spelled for people: "" for n = 0, "x" for n = 1.
std::string power_of(const std::string& x, int n) {
    if (n == 0) return "";
    if (n == 1) return x;
    return x + "^" + std::to_string(n);
}

}  // namespace

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
// Entry

void Entry::bad(const std::string& what) const { fail(context() + ": " + what); }

void Entry::compare(bool equal, const std::string& part, const std::string& printed, const std::string& exact,
                    const std::string& remark) const {
    ++report->checked;
    if (equal) return;
    report->discrepancies.push_back(
        Discrepancy{document, where, part.empty() ? label : label + ", " + part, printed, exact, remark});
}

const json& Entry::need(const json& obj, const std::string& key, const std::string& path) const {
    if (!obj.is_object()) bad("field '" + path + "' must be an object");
    auto it = obj.find(key);
    if (it == obj.end()) bad("missing field '" + (path.empty() ? key : path + "." + key) + "'");
    return *it;
}

int Entry::integer(const json& obj, const std::string& key, const std::string& path) const {
    const json& v = need(obj, key, path);
    if (!v.is_number_integer()) bad("field '" + path + "." + key + "' must be an integer");
    return v.get<int>();
}

std::string Entry::text(const json& obj, const std::string& key, const std::string& path) const {
    const json& v = need(obj, key, path);
    if (!v.is_string()) bad("field '" + (path.empty() ? key : path + "." + key) + "' must be a string");
    return v.get<std::string>();
}

bool Entry::boolean(const json& obj, const std::string& key, const std::string& path) const {
    const json& v = need(obj, key, path);
    if (!v.is_boolean()) bad("field '" + path + "." + key + "' must be true or false");
    return v.get<bool>();
}

Q Entry::rational(const json& v, const std::string& path) const {
    if (!v.is_string()) bad("field '" + path + "' must be a rational written as a string (\"p/q\")");
    return parse_rational(v.get<std::string>(), context() + ": field '" + path + "'");
}

Q Entry::rational(const json& obj, const std::string& key, const std::string& path) const {
    return rational(need(obj, key, path), path + "." + key);
}

std::map<int, Q> Entry::coefficient_map(const json& obj, const std::string& key, const std::string& path) const {
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

const json& Entry::printed_array(const std::string& key) const {
    const json& a = need(printed(), key, "printed");
    if (!a.is_array()) bad("field 'printed." + key + "' must be an array");
    return a;
}

// ---------------------------------------------------------------------------
// Comparisons shared by the documents

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

// ---------------------------------------------------------------------------
// Checker: the exact side

const ExactKernel& Checker::kernel(const std::string& spec, int dim) {
    const auto key = std::make_pair(spec, dim);
    auto it = kernels_.find(key);
    if (it == kernels_.end()) it = kernels_.emplace(key, make_kernel(parse_spec(spec), dim)).first;
    return it->second;
}

const Quantities& Checker::quantities(const std::string& spec, int dim) {
    const auto key = std::make_pair(spec, dim);
    auto it = quantities_.find(key);
    if (it == quantities_.end()) it = quantities_.emplace(key, derive_quantities(kernel(spec, dim))).first;
    return it->second;
}

void Checker::scalar(const Entry& e, const Q& exact, const std::string& remark_if_wrong) {
    const Q printed = e.rational(e.printed(), "printed");
    std::string remark = remark_if_wrong;
    if (remark.empty() && printed != exact && exact != 0 && printed != 0) remark = factor_remark(printed / exact);
    e.compare(printed == exact, "", short_string(printed), short_string(exact), remark);
}

std::vector<ScaledTerm> read_scaled_terms(const Entry& e, const std::string& scale_key) {
    std::vector<ScaledTerm> terms;
    for (const json& t : e.printed_array("terms"))
        terms.push_back({e.rational(t, "weight", "printed.terms[]"), e.rational(t, scale_key, "printed.terms[]")});
    return terms;
}

}  // namespace mollify::gen::errata
