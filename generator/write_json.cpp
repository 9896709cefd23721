#include "write_json.hpp"

#include "error.hpp"
#include "rounding.hpp"

namespace mollify::gen {

namespace {

using json = nlohmann::ordered_json;

json exact_json(const Exact& x) {
    json terms = json::array();
    for (const auto& [atom, q] : x.terms())
        terms.push_back({{"q", pq(q)}, {"pi_power", atom.pi_power}, {"log_of", atom.log_of}});
    return {{"value", x.to_string()}, {"terms", terms}};
}

json radial_json(const Radial& f) {
    auto form_json = [](const ClosedForm& form) {
        json terms = json::array();
        for (const auto& [k, p] : form.terms()) {
            json c = json::object();
            for (int n = p.low(); n <= p.high(); ++n)
                if (p.coefficient(n) != 0) c[std::to_string(n)] = pq(p.coefficient(n));
            terms.push_back({{"basis", table::basis_name(k.basis)},
                             {"s_power", k.s_power},
                             {"pi_power", k.factor.pi_power},
                             {"log_of", k.factor.log_of},
                             {"coefficients", c}});
        }
        return terms;
    };
    json pieces = json::array();
    for (std::size_t i = 0; i < f.pieces.size(); ++i)
        pieces.push_back({{"lo", pq(f.breaks[i])}, {"hi", pq(f.breaks[i + 1])}, {"terms", form_json(f.pieces[i])}});
    pieces.push_back({{"lo", pq(f.support())}, {"hi", "inf"}, {"terms", form_json(f.outside)}});
    return pieces;
}

}  // namespace

json kernel_json(const KernelFacts& f) {
    const ExactKernel& k = f.kernel;
    json moments = json::object();
    if (k.normalised_by == Normalisation::unit_mass)
        for (int p = 0; p <= k.claims.order; p += 2) moments[std::to_string(p)] = exact_json(radial_moment(k, p));
    json out = {{"spec", f.spec},
                {"dim", k.dim},
                {"identifier", f.id},
                {"source", k.source},
                {"normalisation", exact_json(k.normalisation)},
                {"smoothness", k.claims.smoothness},
                {"order", k.claims.order},
                {"parity", k.W.parity},
                {"radial_moments", moments}};
    if (!k.claims.no_potential.empty()) out["no_potential"] = k.claims.no_potential;
    if (k.spec.family == Family::combo) {  // Franz Prop. 4.24
        json radii = json::array(), weights = json::array();
        for (const Q& a : gen::radii(k.spec)) radii.push_back(pq(a));
        for (const Q& w : k.weights) weights.push_back(pq(w));
        out["radii"] = radii;
        out["weights"] = weights;
    }
    if (k.spec.family == Family::mollifier) {  // Anderson (12): normalisation * sum alpha_j (1-r^2)^(M+j)
        json alpha = json::array();
        for (const Q& a : k.alpha) alpha.push_back(pq(a));
        out["alpha"] = alpha;
        // Anderson §4: phi = normalisation * v(r) + G(1) inside, with v(1) = 0; c_0 = v(0).
        const Radial& phi = *f.quantities.potential;
        const Exact c0 = (value_at(phi.pieces.front(), Q(0)) - value_at(phi.outside, Q(1))) * k.normalisation.inverse();
        out["potential_c0"] = exact_json(c0);
    }
    json certs = json::array();
    for (const Certificate& c : f.certificates)
        certs.push_back({{"what", c.what}, {"passed", c.passed}, {"detail", c.detail}});
    out["certificates"] = certs;
    json quantities = json::object();
    for (int i = 0; i < table::quantity_count; ++i)
        if (const Radial* q = quantity_of(f, i)) quantities[table::quantity_names[i]] = radial_json(*q);
    out["quantities"] = quantities;
    return out;
}

std::string kernel_entry(const KernelFacts& k) {
    // dump(1) of the entry alone, each line two spaces deeper: the entry's
    // depth in the document (object, "kernels" array). Strings are printed
    // with their newlines escaped, so every line break is the layout's.
    const std::string alone = kernel_json(k).dump(1);
    std::string out = "  ";
    out.reserve(alone.size() + alone.size() / 8);
    for (char c : alone) {
        out += c;
        if (c == '\n') out += "  ";
    }
    return out;
}

std::string catalogue_json(const std::string& command, const std::vector<std::string>& entries) {
    const json doc = {{"generated_by", "mollify-gen " + generator_version()},
                      {"command", command},
                      {"note", "Generated; do not edit. Exact values as p/q strings; pi_power/log_of give the factor pi^e log(p)."},
                      {"kernels", json::array()}};
    std::string out = doc.dump(1);  // ... "kernels": []\n}
    const std::string empty = "[]\n}";
    if (!out.ends_with(empty)) fail("internal: catalogue.json's layout is not nlohmann's dump(1) as assumed");
    if (entries.empty()) return out + "\n";
    out.resize(out.size() - empty.size());
    std::size_t size = out.size() + 16;
    for (const std::string& e : entries) size += e.size() + 2;
    out.reserve(size);
    out += "[\n";
    for (std::size_t i = 0; i < entries.size(); ++i) {
        out += entries[i];
        out += i + 1 < entries.size() ? ",\n" : "\n";
    }
    out += " ]\n}\n";
    return out;
}

}  // namespace mollify::gen
