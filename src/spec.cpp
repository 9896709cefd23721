// The kernel-spec grammar's parser (include/mollify/spec.hpp): Boost.Spirit X3
// kept out of the public headers, compiled once into libmollify.
#include <mollify/spec.hpp>

#include <boost/fusion/include/std_pair.hpp>
#include <boost/spirit/home/x3.hpp>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mollify {

namespace detail {

namespace x3 = boost::spirit::x3;

struct FamilyName {
    const char* name;
    Family family;
};
constexpr FamilyName family_names[] = {
    {"mollifier", Family::mollifier},     {"wendland", Family::wendland},
    {"wendland-missing", Family::wendland_missing}, {"combo", Family::combo},
    {"poly6", Family::poly6},             {"spiky", Family::spiky},
    {"viscosity", Family::viscosity},     {"cubic-spline", Family::cubic_spline},
    {"quartic-spline", Family::quartic_spline}, {"quintic-spline", Family::quintic_spline},
    {"box", Family::box},                 {"box-d1", Family::box_d1},
    {"box-d2", Family::box_d2},
};

}  // namespace detail

std::optional<double> hex_float(std::string_view text) {
    const bool negative = !text.empty() && text.front() == '-';
    const std::string_view rest = text.substr(!text.empty() && (text.front() == '-' || text.front() == '+') ? 1 : 0);
    if (rest.size() < 2 || rest[0] != '0' || (rest[1] != 'x' && rest[1] != 'X')) return std::nullopt;
    const std::string_view body = rest.substr(2);  // from_chars' hex form has no prefix, and would take a sign here
    constexpr double not_one = std::numeric_limits<double>::quiet_NaN();
    if (body.empty() || body.front() == '-' || body.front() == '+' || body.find_first_of("pP") == std::string_view::npos)
        return not_one;
    double x = 0;
    const auto [end, ec] = std::from_chars(body.data(), body.data() + body.size(), x, std::chars_format::hex);
    if (end != body.data() + body.size() || (ec != std::errc() && ec != std::errc::result_out_of_range)) return not_one;
    // Out of the doubles' range, above or below (from_chars reports both alike): inf, which
    // every caller refuses as no finite double.
    if (ec == std::errc::result_out_of_range) x = std::numeric_limits<double>::infinity();
    return negative ? -x : x;
}

std::optional<NumberSyntax> split_number(std::string_view text) {
    namespace x3 = detail::x3;
    NumberSyntax parts;
    auto first = text.begin();
    const auto last = text.end();
    auto set_neg = [&](auto&) { parts.negative = true; };
    auto int_digits = [&](auto& ctx) { parts.integer.push_back(x3::_attr(ctx)); };
    auto frac_digits = [&](auto& ctx) { parts.fraction.push_back(x3::_attr(ctx)); };
    auto den_digits = [&](auto& ctx) { parts.denominator.push_back(x3::_attr(ctx)); };
    auto exp_start = [&](auto&) { parts.has_exponent = true; };
    auto exp_neg = [&](auto&) { parts.exponent_negative = true; };
    auto exp_digits = [&](auto& ctx) { parts.exponent.push_back(x3::_attr(ctx)); };
    const auto sign = -(x3::lit('+') | x3::lit('-')[set_neg]);
    const auto exponent = (x3::lit('e') | 'E')[exp_start] >> -(x3::lit('+') | x3::lit('-')[exp_neg]) >>
                          +x3::digit[exp_digits];
    const auto fraction_form = x3::lit('/') >> +x3::digit[den_digits];
    const auto decimal_form = -(x3::lit('.') >> *x3::digit[frac_digits]) >> -exponent;
    const auto leading_dot = x3::lit('.') >> +x3::digit[frac_digits] >> -exponent;
    const auto grammar = sign >> ((+x3::digit[int_digits] >> (fraction_form | decimal_form)) | leading_dot);
    if (text.empty() || !x3::parse(first, last, grammar) || first != last) return std::nullopt;
    return parts;
}

namespace detail {

// Decimal digits to int64 (leading zeros are decimal, not octal); nullopt on overflow.
std::optional<std::int64_t> to_int64(const std::string& digits) {
    std::int64_t v = 0;
    for (char c : digits) {
        if (v > (INT64_MAX - (c - '0')) / 10) return std::nullopt;
        v = v * 10 + (c - '0');
    }
    return v;
}

std::optional<Ratio> make_ratio(__int128 num, __int128 den) {
    if (den < 0) num = -num, den = -den;
    __int128 a = num < 0 ? -num : num, b = den;
    while (b != 0) a %= b, std::swap(a, b);
    if (a > 1) num /= a, den /= a;
    if (num > INT64_MAX || num < -INT64_MAX || den > INT64_MAX) return std::nullopt;
    return Ratio{static_cast<std::int64_t>(num), static_cast<std::int64_t>(den)};
}

}  // namespace detail

Ratio parse_ratio(std::string_view text, std::string_view what) {
    const std::string shown = std::string(what) + ": '" + std::string(text) + "'";
    const auto parts = split_number(text);
    if (!parts) fail(shown + " is not a number (expected an integer, p/q, or a decimal such as 0.25 or 1e-3)");
    auto too_big = [&]() -> Ratio { fail(shown + " does not fit in 64-bit integers"); };
    const auto integer = detail::to_int64(parts->integer.empty() ? "0" : parts->integer);
    if (!integer) return too_big();
    std::optional<Ratio> r;
    if (!parts->denominator.empty()) {
        const auto den = detail::to_int64(parts->denominator);
        if (!den) return too_big();
        if (*den == 0) fail(shown + " has a zero denominator");
        r = detail::make_ratio(*integer, *den);
    } else {
        const auto digits = detail::to_int64((parts->integer.empty() ? "0" : parts->integer) + parts->fraction);
        if (!digits || parts->fraction.size() > 18 || parts->exponent.size() > 2) return too_big();
        int e = (parts->exponent.empty() ? 0 : std::stoi(parts->exponent)) * (parts->exponent_negative ? -1 : 1) -
                static_cast<int>(parts->fraction.size());
        __int128 num = *digits, den = 1;
        for (; e > 0; --e) {
            num *= 10;
            if (num > INT64_MAX) return too_big();
        }
        for (; e < 0; ++e) {
            den *= 10;
            if (den > static_cast<__int128>(INT64_MAX) * 10) return too_big();
        }
        r = detail::make_ratio(num, den);
    }
    if (!r) return too_big();
    if (parts->negative) r->num = -r->num;
    return *r;
}

std::string to_string(const Ratio& r) {
    return r.den == 1 ? std::to_string(r.num) : std::to_string(r.num) + "/" + std::to_string(r.den);
}

std::string family_name(Family f) {
    for (const auto& n : detail::family_names)
        if (n.family == f) return n.name;
    return "?";
}

std::vector<Ratio> equidistant_radii(int m) {
    std::vector<Ratio> r;
    for (int j = 1; j <= m; ++j) r.push_back(*detail::make_ratio(j, m));
    return r;
}

namespace detail {

struct RawSpec {
    std::string name;
    std::vector<std::pair<std::string, std::string>> params;
    std::string base;  // text after "base=", empty if none
};

// spec   := name (':' item (',' item)*)?
// item   := "base=" rest | key '=' value
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
    const Ratio q = parse_ratio(value, "kernel spec '" + spec_text + "', " + key);
    if (q.den != 1 || q.num < lo || q.num > hi)
        fail("kernel spec '" + spec_text + "': " + key + "=" + value + " is out of range (an integer in " +
             std::to_string(lo) + ".." + std::to_string(hi) + ")");
    return static_cast<int>(q.num);
}

std::vector<Ratio> parse_radii(const std::string& spec_text, const std::string& value) {
    std::vector<Ratio> radii;
    std::size_t start = 0;
    while (start <= value.size()) {
        const std::size_t end = std::min(value.find(';', start), value.size());
        radii.push_back(parse_ratio(value.substr(start, end - start), "kernel spec '" + spec_text + "', radius"));
        start = end + 1;
    }
    for (const Ratio& a : radii)
        if (a.num <= 0 || a.num > a.den)
            fail("kernel spec '" + spec_text + "': radius " + to_string(a) + " is outside (0, 1]");
    std::sort(radii.begin(), radii.end());
    if (std::adjacent_find(radii.begin(), radii.end()) != radii.end())
        fail("kernel spec '" + spec_text + "': radii must be distinct (Franz Prop. 4.24)");
    if (!(radii.back() == Ratio{1, 1}))
        fail("kernel spec '" + spec_text + "': the largest radius must be 1 (kernels have support radius 1)");
    if (static_cast<int>(radii.size()) > max_combo_m)
        fail("kernel spec '" + spec_text + "': at most " + std::to_string(max_combo_m) + " radii");
    return radii;
}

}  // namespace detail

Spec parse_spec(std::string_view text) {
    using namespace detail;
    const std::string spec_text(text);
    const RawSpec raw = split_spec(text);
    const auto info = std::find_if(std::begin(family_names), std::end(family_names),
                                   [&](const FamilyName& f) { return raw.name == f.name; });
    if (info == std::end(family_names)) {
        std::string known;
        for (const auto& f : family_names) known += std::string(known.empty() ? "" : ", ") + f.name;
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

std::string spec_string(const Spec& s) {
    std::string out = family_name(s.family);
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
                for (std::size_t i = 0; i < s.radii.size(); ++i) out += (i ? ";" : "") + to_string(s.radii[i]);
            }
            out += ",base=" + spec_string(*s.base);
            break;
        }
        default: break;
    }
    return out;
}

}  // namespace mollify
