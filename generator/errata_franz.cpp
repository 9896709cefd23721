// The errata of Franz 2019 (seed 003): the equidistant Vandermonde weights,
// the Wendland functions psi_{d,k,l} and their "missing" relatives, and the
// higher-order combinations Phi = sum_j w_j psi_{a_j}, a_j = j/K, printed
// both as whole polynomials and as weight tables.
#include "errata_checker.hpp"

#include "error.hpp"
#include "spec.hpp"
#include "vandermonde.hpp"
#include "wendland.hpp"

#include <algorithm>

namespace mollify::gen::errata {

void Checker::vandermonde_equidistant(const Entry& e) {
    const int m = e.param("m"), j = e.param("j");
    if (m < 1 || m > max_combo_m) e.bad("params.m = " + std::to_string(m) + " is outside 1.." + std::to_string(max_combo_m));
    if (j < 1 || j > m) e.bad("params.j = " + std::to_string(j) + " is outside 1..m");
    scalar(e, vandermonde_weights(equidistant_radii(m))[static_cast<std::size_t>(j - 1)]);
}

namespace {

Laurent polynomial_of(const std::map<int, Q>& coefficients) {
    Laurent p;
    for (const auto& [n, c] : coefficients) p += Laurent::monomial(c, n);
    return p;
}

// The powers of p with a non-zero coefficient, added to `keys`.
void insert_powers(std::set<int>& keys, const Laurent& p) {
    for (int n = p.low(); n <= p.high(); ++n)
        if (p.coefficient(n) != 0) keys.insert(n);
}

std::set<int> union_of_keys(const Coefficients& a, const Coefficients& b) {
    std::set<int> keys;
    for (const auto& [n, v] : a) keys.insert(n);
    for (const auto& [n, v] : b) keys.insert(n);
    return keys;
}

Exact at_or_zero(const Coefficients& c, int n) { return c.count(n) ? c.at(n) : Exact(); }

void check_wendland_params(const Entry& e, int d, int k, int l) {
    if (d < 1 || d > 3 || k < 0 || k > max_wendland_k || l < 0 || l > max_wendland_l) e.bad("params out of range");
}

// "weight psi(scale r)", with weight 1 / -1 folded into the sign.
std::string psi_term(const Q& weight, const Q& scale) {
    const std::string psi = "psi(" + (scale == 1 ? std::string("r") : short_string(scale) + " r") + ")";
    return weight == 1 ? psi : weight == -1 ? "-" + psi : short_string(weight) + " " + psi;
}

// w psi_a(r) = w a^-d psi(r / a) (Franz (4.17)): the weight of psi(r / a).
Q member_weight(const Q& w, const Q& a, int d) { return w * pow(Q(1) / a, d); }

}  // namespace

// ---------------------------------------------------------------------------
// Wendland functions psi_{d,k,l} = (1-r)^edge * poly

void Checker::wendland_shape_entry(const Entry& e) {
    const int d = e.param("d"), k = e.param("k"), l = e.param("l");
    check_wendland_params(e, d, k, l);
    const Laurent exact = wendland_shape(d, k, l);
    const int edge = exact.multiplicity_of_root(Q(1));
    const json& pr = e.printed();
    const int printed_edge = e.integer(pr, "edge_power", "printed");
    if (printed_edge < 0 || printed_edge > 200) e.bad("printed.edge_power must be in 0..200");
    const std::map<int, Q> printed_coefficients = e.coefficient_map(pr, "poly", "printed");
    const Laurent printed_poly = polynomial_of(printed_coefficients);
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
    for (const auto& [n, c] : printed_coefficients) keys.insert(n);
    insert_powers(keys, x);
    insert_powers(keys, p);
    std::vector<Proportional> items;
    for (int n : keys) items.push_back({what + std::to_string(n), Exact(p.coefficient(n)), Exact(x.coefficient(n))});
    compare_proportional(e, items, std::nullopt, "");
}

// Wendland's missing functions: psi = L(r) arcsech(r) + S(r) sqrt(1 - r^2).
void Checker::wendland_missing(const Entry& e) {
    const int d = e.param("d"), k = e.param("k"), l = e.param("l");
    check_wendland_params(e, d, k, l);
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
        insert_powers(ks, *exact);
        for (int n : ks)
            items.push_back({name + " coefficient of r^" + std::to_string(n),
                             Exact(printed.count(n) ? printed.at(n) : Q(0)), Exact(exact->coefficient(n))});
    }
    compare_proportional(e, items, std::nullopt, "");
}

// ---------------------------------------------------------------------------
// The combination Phi = sum_j w_j psi_{a_j}, a_j = j/K, as whole polynomials

namespace {

// A printed term weight (1 - scale r)_+^edge_power poly(r).
struct ComboTerm {
    Q weight, scale;
    int edge_power = 0;
    Laurent poly;
    Laurent expanded() const { return Laurent::binomial_power(Q(1), -scale, edge_power) * poly * weight; }
};

std::vector<ComboTerm> read_combo_terms(const Entry& e) {
    std::vector<ComboTerm> terms;
    for (const json& t : e.printed_array("terms")) {
        ComboTerm ct;
        ct.weight = e.rational(t, "weight", "printed.terms[]");
        ct.scale = e.rational(t, "scale", "printed.terms[]");
        ct.edge_power = e.integer(t, "edge_power", "printed.terms[]");
        if (ct.scale <= 0) e.bad("printed.terms[].scale must be positive");
        if (ct.edge_power < 0 || ct.edge_power > 200) e.bad("printed.terms[].edge_power must be in 0..200");
        ct.poly = polynomial_of(e.coefficient_map(t, "poly", "printed.terms[]"));
        terms.push_back(ct);
    }
    return terms;
}

Radial zero_radial() {
    Radial r;
    r.breaks = {Q(0), Q(1)};
    r.pieces = {ClosedForm()};
    return r;
}

// The printed terms summed, each supported on [0, 1/scale].
Radial printed_combination(const std::vector<ComboTerm>& terms) {
    Radial printed = zero_radial();
    for (const auto& t : terms) printed = printed + Radial::single(ClosedForm(t.expanded()), Q(1) / t.scale);
    return printed;
}

// The closed form of f on the piece containing mid (outside: past the support).
const ClosedForm& form_on(const Radial& f, const Q& mid) {
    static const ClosedForm zero;
    if (mid >= f.support()) return f.outside.is_zero() ? zero : f.outside;
    return f.pieces[f.piece_index(mid)];
}

// The exact members w_j psi_{a_j}, a_j = j/K, of the combination.
struct ComboMembers {
    const Radial& psi;
    int d, K;
    std::vector<Q> radii = equidistant_radii(K);
    std::vector<Q> w = vandermonde_weights(radii);

    Coefficients term(std::size_t j) const {
        const Radial t = psi.scaled(radii[j], d) * Exact(w[j]);
        return coefficients(t.pieces[0]);
    }
};

// The paired printed term of largest support: it fixes the constant factor
// and the normalisation of psi the table uses.
std::optional<std::size_t> anchor_term(const Pairing& pairing, const std::vector<Q>& radii) {
    std::optional<std::size_t> anchor;
    for (std::size_t i = 0; i < pairing.match.size(); ++i)
        if (pairing.match[i] && (!anchor || radii[*pairing.match[i]] > radii[*pairing.match[*anchor]])) anchor = i;
    return anchor;
}

// printed = factor * exact for most coefficients of the anchor term.
std::optional<Q> anchor_factor(const ComboTerm& anchor, const Coefficients& exact) {
    const Coefficients p = coefficients(anchor.expanded());
    std::vector<std::pair<Exact, Exact>> pairs;
    for (const auto& [n, v] : exact) pairs.emplace_back(at_or_zero(p, n), v);
    return common_factor(pairs);
}

// Franz's psi as the table prints it, read off the anchor term
// weight * psi(scale r), and what turns the exact members' weights
// w_j a_j^-d into that normalisation.
struct PrintedPsi {
    std::optional<Laurent> psi;
    Q weight_scale = 1;

    PrintedPsi() = default;
    PrintedPsi(const ComboTerm& anchor, const Q& w, const Q& a, int d)
        : psi((anchor.expanded() * (Q(1) / anchor.weight)).scaled_argument(Q(1) / anchor.scale)),
          weight_scale(anchor.weight / member_weight(w, a, d)) {}

    // "weight psi(s r)" and, when psi is known, " = weight (1 - s r)_+^e (...)".
    std::string member(const Q& weight, const Q& s) const {
        std::string text = psi_term(weight, s);
        if (!psi) return text;
        const Laurent p = psi->scaled_argument(s);
        const int edge = p.multiplicity_of_root(Q(1) / s);
        const Laurent q = *p.divided_by_linear_power(Q(1) / s, edge) * pow(Q(1) / s, edge);
        std::vector<std::string> ts;
        for (int n = q.high(); n >= q.low(); --n)
            if (q.coefficient(n) != 0) ts.push_back(monomial_string(q.coefficient(n), {{"r", n}}));
        const std::string body = "(1 - " + (s == 1 ? std::string("r") : short_string(s) + " r") + ")_+^" +
                                 std::to_string(edge) + " (" + sum_string(ts) + ")";
        return text + " = " + (weight == 1 ? body : weight == -1 ? "-" + body : short_string(weight) + " " + body);
    }
};

// What the term structure says, for the remarks: the printed terms and
// members left unpaired (paired up in order), then the paired printed terms
// that differ from their member times the common factor c.
class ComboRemark {
public:
    ComboRemark(const std::vector<ComboTerm>& terms, const ComboMembers& members, const Pairing& pairing,
                const PrintedPsi& psi, const Q& c)
        : terms_(terms), members_(members), pairing_(pairing), psi_(psi), c_(c) {}

    std::string str() const {
        std::vector<std::string> notes = unpaired();
        for (std::size_t i = 0; i < terms_.size(); ++i)
            if (pairing_.match[i] && !same_as_member(i))
                notes.push_back("printed term " + printed(i) + " differs from the exact member " +
                                psi_.member(lambda(*pairing_.match[i]), terms_[i].scale));
        return join(notes, "; ");
    }

private:
    std::string printed(std::size_t i) const { return psi_term(terms_[i].weight, terms_[i].scale); }
    // The weight of member j in the table's normalisation.
    Q lambda(std::size_t j) const {
        return member_weight(members_.w[j], members_.radii[j], members_.d) * psi_.weight_scale;
    }
    std::string member(std::size_t j) const { return psi_.member(lambda(j), Q(1) / members_.radii[j]); }
    std::string radii_j_over_K() const { return "j/" + std::to_string(members_.K); }

    std::vector<std::string> unpaired() const {
        std::vector<std::size_t> lone_printed, lone_exact;
        for (std::size_t i = 0; i < terms_.size(); ++i)
            if (!pairing_.match[i]) lone_printed.push_back(i);
        for (std::size_t j = 0; j < members_.radii.size(); ++j)
            if (!pairing_.used[j]) lone_exact.push_back(j);
        std::vector<std::string> notes;
        for (std::size_t n = 0; n < std::max(lone_printed.size(), lone_exact.size()); ++n) {
            if (n < lone_printed.size() && n < lone_exact.size()) {
                const std::size_t i = lone_printed[n], j = lone_exact[n];
                notes.push_back("printed term " + printed(i) + " should be the radius-" +
                                short_string(members_.radii[j]) + " member " + member(j) + " (radii a_j = " +
                                radii_j_over_K() + ")");
            } else if (n < lone_printed.size()) {
                notes.push_back("printed term " + printed(lone_printed[n]) + " matches no radius " + radii_j_over_K());
            } else {
                notes.push_back("term " + member(lone_exact[n]) + " missing");
            }
        }
        return notes;
    }

    bool same_as_member(std::size_t i) const {
        const Coefficients x = members_.term(*pairing_.match[i]);
        const Coefficients p = coefficients(terms_[i].expanded());
        bool same = true;
        for (int n : union_of_keys(x, p)) same = same && at_or_zero(p, n) == (x.count(n) ? x.at(n) * c_ : Exact());
        return same;
    }

    const std::vector<ComboTerm>& terms_;
    const ComboMembers& members_;
    const Pairing& pairing_;
    const PrintedPsi& psi_;
    Q c_;
};

// Piece by piece on the merged breakpoints, coefficient by coefficient.
std::vector<Proportional> piecewise_items(const Radial& printed, const Radial& exact) {
    std::vector<Q> breaks = printed.breaks;
    breaks.insert(breaks.end(), exact.breaks.begin(), exact.breaks.end());
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    std::vector<Proportional> items;
    for (std::size_t b = 0; b + 1 < breaks.size(); ++b) {
        const Q mid = (breaks[b] + breaks[b + 1]) / 2;
        const Coefficients p = coefficients(form_on(printed, mid));
        const Coefficients x = coefficients(form_on(exact, mid));
        const std::string piece = "piece [" + short_string(breaks[b]) + ", " + short_string(breaks[b + 1]) +
                                  (b + 2 == breaks.size() ? "]" : ")");
        for (int n : union_of_keys(x, p))
            items.push_back({piece + ", coefficient of r^" + std::to_string(n), at_or_zero(p, n), at_or_zero(x, n)});
    }
    return items;
}

}  // namespace

void Checker::wendland_combo(const Entry& e) {
    const int d = e.param("d"), k = e.param("k"), l = e.param("l"), m = e.param("m");
    if (m < 2 || m % 2 != 0 || m / 2 > max_combo_m) e.bad("params.m (the moment order) must be even and at least 2");
    const int K = m / 2;
    const std::string base = "wendland:k=" + std::to_string(k) + ",l=" + std::to_string(l);
    const ExactKernel& combo = kernel("combo:m=" + std::to_string(K) + ",base=" + base, d);
    const ComboMembers members{kernel(base, d).shape, d, K};
    const std::vector<ComboTerm> terms = read_combo_terms(e);
    const Radial printed = printed_combination(terms);

    // Pair printed terms with the exact members w_j psi_{a_j} (scale 1/a_j).
    Pairing pairing(terms.size(), members.radii.size());
    pairing.pair([&](std::size_t i, std::size_t j) { return terms[i].scale * members.radii[j] == 1; });
    std::optional<Q> factor;
    PrintedPsi psi;
    if (const auto anchor = anchor_term(pairing, members.radii)) {
        const std::size_t ja = *pairing.match[*anchor];
        factor = anchor_factor(terms[*anchor], members.term(ja));
        psi = PrintedPsi(terms[*anchor], members.w[ja], members.radii[ja], d);
    }
    const std::string remark = ComboRemark(terms, members, pairing, psi, factor.value_or(Q(1))).str();
    compare_proportional(e, piecewise_items(printed, combo.shape), factor, remark);
}

// ---------------------------------------------------------------------------
// The combination as a table of weights: Phi = sum_j lambda_j psi(r / a_j)

namespace {

// Leftovers pair up with the free members of largest radius (smallest scale) first.
void pair_leftovers(Pairing& pairing) {
    std::vector<std::size_t> lone_exact;
    for (std::size_t j = pairing.used.size(); j-- > 0;)
        if (!pairing.used[j]) lone_exact.push_back(j);
    std::size_t next = 0;
    for (auto& match : pairing.match)
        if (!match && next < lone_exact.size()) {
            match = lone_exact[next++];
            pairing.used[*match] = true;
        }
}

// The printed term t against the member lambda psi(scale r) of radius a,
// lambda already times the common factor c.
void compare_weight_member(const Entry& e, const std::string& part, const ScaledTerm& t, const Q& expected,
                           const Q& scale, const Q& a, const Q& c, int K) {
    std::vector<std::string> remark;
    if (t.weight != expected && c != 1) remark.push_back("exact value times the common factor " + short_string(c));
    if (t.weight != expected && c < 0) remark.push_back("differs by a sign");
    e.compare(t.weight == expected, part + ", weight", short_string(t.weight), short_string(expected),
              join(remark, "; "));
    e.compare(t.scale == scale, part + ", argument scale", "psi(" + short_string(t.scale) + " r)",
              "psi(" + short_string(scale) + " r)",
              "the radii are a_j = j/" + std::to_string(K) + " (Franz: a_j = b j); the weight " +
                  short_string(t.weight) + " fits the radius-" + short_string(a) + " member psi(" +
                  short_string(scale) + " r), while psi(" + short_string(t.scale) + " r) has radius " +
                  short_string(Q(1) / t.scale));
}

}  // namespace

void Checker::wendland_combo_weights(const Entry& e) {
    const int d = e.param("d"), m = e.param("m");
    if (m < 2 || m % 2 != 0 || m / 2 > max_combo_m) e.bad("params.m (the moment order) must be even and at least 2");
    const int K = m / 2;
    const std::vector<Q> radii = equidistant_radii(K);
    const std::vector<Q> w = vandermonde_weights(radii);
    // Phi = sum_j w_j psi_{a_j} = sum_j w_j a_j^-d psi(r / a_j).
    std::vector<Q> lambda, scale;
    for (std::size_t j = 0; j < radii.size(); ++j) {
        lambda.push_back(member_weight(w[j], radii[j], d));
        scale.push_back(Q(1) / radii[j]);
    }
    const std::vector<ScaledTerm> printed = read_scaled_terms(e, "scale");  // weight * psi(scale r)
    Pairing pairing(printed.size(), radii.size());
    pairing.pair([&](std::size_t i, std::size_t j) { return printed[i].scale == scale[j]; });
    // The common factor comes from the terms paired by their scale only.
    std::vector<std::pair<Exact, Exact>> pairs;
    for (std::size_t i = 0; i < printed.size(); ++i)
        if (const auto j = pairing.match[i]) pairs.emplace_back(Exact(printed[i].weight), Exact(lambda[*j]));
    pair_leftovers(pairing);
    const Q c = common_factor(pairs).value_or(Q(1));
    for (std::size_t i = 0; i < printed.size(); ++i) {
        const std::string part = "term " + psi_term(printed[i].weight, printed[i].scale);
        if (const auto j = pairing.match[i])
            compare_weight_member(e, part, printed[i], lambda[*j] * c, scale[*j], radii[*j], c, K);
        else
            e.compare(false, part, psi_term(printed[i].weight, printed[i].scale), "no such term",
                      "only " + std::to_string(K) + " radii j/" + std::to_string(K));
    }
    for (std::size_t j = 0; j < radii.size(); ++j)
        if (!pairing.used[j])
            e.compare(false, "term of radius " + short_string(radii[j]), "missing", psi_term(lambda[j] * c, scale[j]));
}

}  // namespace mollify::gen::errata
