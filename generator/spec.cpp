#include "spec.hpp"

#include "error.hpp"

#include <boost/fusion/include/std_pair.hpp>
#include <boost/spirit/home/x3.hpp>

#include <algorithm>
#include <map>

namespace mollify::gen {

namespace {

namespace x3 = boost::spirit::x3;

struct Family_info {
    const char* name;
    Family family;
};
constexpr Family_info families[] = {
    {"mollifier", Family::mollifier},     {"wendland", Family::wendland},
    {"wendland-missing", Family::wendland_missing}, {"combo", Family::combo},
    {"poly6", Family::poly6},             {"spiky", Family::spiky},
    {"viscosity", Family::viscosity},     {"cubic-spline", Family::cubic_spline},
    {"box", Family::box},                 {"box-d1", Family::box_d1},
    {"box-d2", Family::box_d2},
};

struct RawSpec {
    std::string name;
    std::vector<std::pair<std::string, std::string>> params;
    std::string base;  // text after "base=", empty if none
};

// spec   := name (':' param (',' param)*)?
// param  := "base=" rest | key '=' value
RawSpec split_spec(std::string_view text) {
    RawSpec raw;
    auto first = text.begin();
    const auto last = text.end();
    auto on_name = [&](auto& ctx) { raw.name = x3::_attr(ctx); };
    auto on_base = [&](auto& ctx) { raw.base = x3::_attr(ctx); };
    auto on_param = [&](auto& ctx) { raw.params.push_back(x3::_attr(ctx)); };
    const auto name = x3::rule<struct name_, std::string>{} = +(x3::alnum | x3::char_('-'));
    const auto key = x3::rule<struct key_, std::string>{} = +x3::alpha;
    const auto value = x3::rule<struct value_, std::string>{} = +(x3::char_ - ',');
    const auto rest = x3::rule<struct rest_, std::string>{} = +x3::char_;
    const auto param = x3::rule<struct param_, std::pair<std::string, std::string>>{} = key >> '=' >> value;
    const auto item = (x3::lit("base=") >> rest[on_base]) | param[on_param];
    const auto grammar = name[on_name] >> -(':' >> item >> *(',' >> item));
    if (!x3::parse(first, last, grammar) || first != last)
        fail("kernel spec '" + std::string(text) + "' is malformed near '" + std::string(first, last) +
             "' (expected NAME or NAME:key=value,...; e.g. wendland:k=2,l=1)");
    return raw;
}

int parse_int(const std::string& spec_text, const std::string& key, const std::string& value, int lo, int hi) {
    const Q q = parse_rational(value, "kernel spec '" + spec_text + "', " + key);
    if (!is_integer(q) || q < lo || q > hi)
        fail("kernel spec '" + spec_text + "': " + key + "=" + value + " is out of range (an integer in " +
             std::to_string(lo) + ".." + std::to_string(hi) + ")");
    return numerator(q).convert_to<int>();
}

std::vector<Q> parse_radii(const std::string& spec_text, const std::string& value) {
    std::vector<Q> radii;
    std::size_t start = 0;
    while (start <= value.size()) {
        const std::size_t end = std::min(value.find(';', start), value.size());
        radii.push_back(parse_rational(value.substr(start, end - start), "kernel spec '" + spec_text + "', radius"));
        start = end + 1;
    }
    for (const Q& a : radii)
        if (a <= 0 || a > 1)
            fail("kernel spec '" + spec_text + "': radius " + short_string(a) + " is outside (0, 1]");
    std::vector<Q> sorted = radii;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        fail("kernel spec '" + spec_text + "': radii must be distinct (Franz Prop. 4.24)");
    if (sorted.back() != 1)
        fail("kernel spec '" + spec_text + "': the largest radius must be 1 (kernels have support radius 1)");
    if (static_cast<int>(sorted.size()) > max_combo_m)
        fail("kernel spec '" + spec_text + "': at most " + std::to_string(max_combo_m) + " radii");
    return sorted;
}

}  // namespace

std::vector<Q> equidistant_radii(int m) {
    std::vector<Q> r;
    for (int j = 1; j <= m; ++j) r.emplace_back(j, m);
    return r;
}

Spec parse_spec(std::string_view text) {
    const std::string spec_text(text);
    const RawSpec raw = split_spec(text);
    const auto info = std::find_if(std::begin(families), std::end(families),
                                   [&](const Family_info& f) { return raw.name == f.name; });
    if (info == std::end(families)) {
        std::string known;
        for (const auto& f : families) known += std::string(known.empty() ? "" : ", ") + f.name;
        fail("unknown kernel '" + raw.name + "' in spec '" + spec_text + "' (known: " + known + ")");
    }
    Spec s;
    s.family = info->family;
    std::map<std::string, std::string> params;
    for (const auto& [k, v] : raw.params)
        if (!params.emplace(k, v).second) fail("kernel spec '" + spec_text + "': parameter " + k + " given twice");

    auto take = [&](const std::string& key) -> std::optional<std::string> {
        auto it = params.find(key);
        if (it == params.end()) return std::nullopt;
        std::string v = it->second;
        params.erase(it);
        return v;
    };
    auto require = [&](const std::string& key) {
        auto v = take(key);
        if (!v) fail("kernel spec '" + spec_text + "': " + raw.name + " needs " + key + "=...");
        return *v;
    };

    switch (s.family) {
        case Family::mollifier:
            s.M = parse_int(spec_text, "M", require("M"), 1, max_mollifier_M);
            if (auto o = take("order")) {
                s.order = parse_int(spec_text, "order", *o, 2, max_mollifier_order);
                if (s.order % 2 != 0)
                    fail("kernel spec '" + spec_text + "': order=" + *o + " must be even (radial kernels)");
            }
            break;
        case Family::wendland:
            s.k = parse_int(spec_text, "k", require("k"), 0, max_wendland_k);
            if (auto l = take("l")) s.l = parse_int(spec_text, "l", *l, 0, max_wendland_l);
            break;
        case Family::wendland_missing:
            s.k = parse_int(spec_text, "k", require("k"), 0, max_wendland_k);
            if (auto l = take("l")) s.l = parse_int(spec_text, "l", *l, 0, max_wendland_l);
            break;
        case Family::combo: {
            auto m = take("m");
            auto radii = take("radii");
            if (m && radii) fail("kernel spec '" + spec_text + "': give either m= or radii=, not both");
            if (!m && !radii) fail("kernel spec '" + spec_text + "': combo needs m=... or radii=...");
            s.radii = m ? equidistant_radii(parse_int(spec_text, "m", *m, 1, max_combo_m))
                        : parse_radii(spec_text, *radii);
            if (raw.base.empty()) fail("kernel spec '" + spec_text + "': combo needs base=SPEC (last)");
            Spec base = parse_spec(raw.base);
            if (base.family == Family::combo) fail("kernel spec '" + spec_text + "': a combo base cannot be a combo");
            if (!base.is_polynomial() || base.family == Family::box_d1 || base.family == Family::box_d2)
                fail("kernel spec '" + spec_text + "': base " + raw.base +
                     " is not supported in combinations (needs a polynomial unit-mass kernel)");
            s.base = std::make_shared<const Spec>(std::move(base));
            break;
        }
        default: break;
    }
    if (s.family != Family::combo && !raw.base.empty())
        fail("kernel spec '" + spec_text + "': " + raw.name + " takes no base=");
    if (!params.empty())
        fail("kernel spec '" + spec_text + "': unknown parameter '" + params.begin()->first + "' for " + raw.name);
    return s;
}

std::string Spec::family_name() const {
    for (const auto& f : families)
        if (f.family == family) return f.name;
    return "?";
}

bool Spec::is_polynomial() const { return family != Family::wendland_missing; }

bool operator==(const Spec& a, const Spec& b) { return spec_string(a) == spec_string(b); }

std::string spec_string(const Spec& s) {
    std::string out = s.family_name();
    switch (s.family) {
        case Family::mollifier:
            out += ":M=" + std::to_string(s.M);
            if (s.order != 2) out += ",order=" + std::to_string(s.order);
            break;
        case Family::wendland:
        case Family::wendland_missing:
            out += ":k=" + std::to_string(s.k);
            if (s.l != 0) out += ",l=" + std::to_string(s.l);
            break;
        case Family::combo: {
            const int m = static_cast<int>(s.radii.size());
            if (s.radii == equidistant_radii(m)) {
                out += ":m=" + std::to_string(m);
            } else {
                out += ":radii=";
                for (std::size_t i = 0; i < s.radii.size(); ++i) out += (i ? ";" : "") + short_string(s.radii[i]);
            }
            out += ",base=" + spec_string(*s.base);
            break;
        }
        default: break;
    }
    return out;
}

}  // namespace mollify::gen
