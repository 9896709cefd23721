// Scene files with toml++ (header-only, compiled in this translation unit
// only). Every error is a mollify::Error "ORIGIN[:LINE]: KEY[ = VALUE]: WHY".
#include "scene.hpp"
#include "toml_guard.hpp"

#include <mollify/error.hpp>

#define TOML_HEADER_ONLY 1
#define TOML_EXCEPTIONS 1
#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace mollify::app {

namespace {

// The parsed file (the helpers below take it; Scene::Impl is private).
struct Doc {
    std::string origin;
    std::string text;
    toml::table root;
};

}  // namespace

struct Scene::Impl : Doc {};

namespace {

// The [scene] table's keys (README, "Scenes and the mollify command").
const std::vector<std::string_view> scene_keys = {"name", "experiment", "title", "description"};

std::string type_name(toml::node_type t) {
    switch (t) {
        case toml::node_type::string: return "a string";
        case toml::node_type::integer: return "an integer";
        case toml::node_type::floating_point: return "a floating-point number";
        case toml::node_type::boolean: return "a boolean";
        case toml::node_type::array: return "an array";
        case toml::node_type::table: return "a table";
        default: return "a date/time";
    }
}

// The value as TOML text, written here for arrays and tables too: toml++'s
// formatter (3.x) converts log10 of a float below 0.1 to an unsigned integer,
// undefined behaviour that UBSan reports (found by fuzz/fuzz_scene.cpp with
// epsilon = [0.05, ...] where a number was expected).
std::string toml_text(const toml::node& n) {
    if (const auto* str = n.as_string()) {  // as written in a scene: "..."
        std::string v = "\"";
        for (char c : str->get()) v += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
        return v + "\"";
    }
    if (const auto* x = n.as_floating_point()) {  // shortest round trip: 0.7, not 0.69999999999999996
        char buf[64];
        return std::string(buf, std::to_chars(buf, buf + sizeof buf, x->get()).ptr);
    }
    if (const auto* i = n.as_integer()) return std::to_string(i->get());
    if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
    if (const auto* a = n.as_array()) {
        std::string v = "[";
        for (std::size_t k = 0; k < a->size() && v.size() < 80; ++k) v += (k ? ", " : "") + toml_text(*a->get(k));
        return v + "]";
    }
    if (const auto* t = n.as_table()) {
        std::string v = "{";
        for (auto it = t->begin(); it != t->end() && v.size() < 80; ++it)
            v += (it == t->begin() ? " " : ", ") + std::string(it->first.str()) + " = " + toml_text(it->second);
        return v + " }";
    }
    std::ostringstream s;  // a date or time: no floating point in its formatting
    s << toml::node_view<const toml::node>{&n};
    return s.str();
}

// The value as TOML text, shortened: for messages only.
std::string show(const toml::node& n) {
    std::string v = toml_text(n);
    std::replace(v.begin(), v.end(), '\n', ' ');
    if (v.size() > 60) v = v.substr(0, 57) + "...";
    return v;
}

}  // namespace

Scene::Scene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;
Scene::~Scene() = default;

namespace {

// "ORIGIN:LINE" where the node's line is known, else "ORIGIN".
std::string where(const std::string& origin, const toml::node* n) {
    if (n && n->source().begin.line > 0) return origin + ":" + std::to_string(n->source().begin.line);
    return origin;
}

[[noreturn]] void bad(const std::string& origin, std::string_view key, const toml::node* n, const std::string& why) {
    std::string m = where(origin, n) + ": " + std::string(key);
    if (n && !n->is_table()) m += " = " + show(*n);
    fail(m + ": " + why);
}

const toml::node* lookup(const toml::table& root, std::string_view key) {
    return toml::at_path(root, key).node();
}

const toml::node& require(const Doc& s, std::string_view key) {
    const toml::node* n = lookup(s.root, key);
    if (!n) fail(s.origin + ": missing key " + std::string(key));
    return *n;
}

[[noreturn]] void wrong_type(const Doc& s, std::string_view key, const toml::node& n, const char* wanted) {
    bad(s.origin, key, &n, std::string("expected ") + wanted + ", got " + type_name(n.type()));
}

double as_number(const Doc& s, std::string_view key, const toml::node& n) {
    if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
    if (const auto* f = n.as_floating_point()) return f->get();
    wrong_type(s, key, n, "a number");
}

// Integers; a float is accepted when it is an exact integer (N = 1e4).
long as_integer(const Doc& s, std::string_view key, const toml::node& n) {
    if (const auto* i = n.as_integer()) return static_cast<long>(i->get());
    if (const auto* f = n.as_floating_point()) {
        const double x = f->get();
        if (std::isfinite(x) && x == std::trunc(x) && std::fabs(x) < 9.2e18) return static_cast<long>(x);
        bad(s.origin, key, &n, "expected an integer");
    }
    wrong_type(s, key, n, "an integer");
}

std::string as_string(const Doc& s, std::string_view key, const toml::node& n) {
    if (const auto* v = n.as_string()) return v->get();
    wrong_type(s, key, n, "a string");
}

template <class T, class Convert>
std::vector<T> array_of(const Doc& s, std::string_view key, const char* wanted, Convert convert) {
    const toml::node& n = require(s, key);
    const toml::array* a = n.as_array();
    if (!a) wrong_type(s, key, n, wanted);
    std::vector<T> out;
    for (std::size_t i = 0; i < a->size(); ++i)
        out.push_back(convert(s, std::string(key) + "[" + std::to_string(i) + "]", *a->get(i)));
    return out;
}

// A scene name is also a folder name (out/NAME).
bool valid_name(const std::string& name) {
    if (name.empty() || name.size() > 100 || name[0] == '.' || name[0] == '-') return false;
    return std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_' ||
               c == '.';
    });
}

}  // namespace

Scene Scene::load(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) fail(file.string() + ": cannot read scene file (" + std::strerror(errno) + ")");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) fail(file.string() + ": cannot read scene file");
    return parse(text.str(), file.string());
}

Scene Scene::parse(std::string_view text, std::string origin) {
    auto impl = std::make_unique<Impl>();
    impl->origin = std::move(origin);
    impl->text = std::string(text);
    check_toml_characters(impl->text, impl->origin);  // before toml++ (toml_guard.hpp)
    try {
        (void)toml::parse(ascii_placeholders(impl->text), impl->origin);  // the structure first (toml_guard.hpp)
        impl->root = toml::parse(impl->text, impl->origin);
    } catch (const toml::parse_error& e) {
        const auto& b = e.source().begin;
        fail(impl->origin + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) +
             ": TOML syntax error: " + std::string(e.description()));
    }
    Scene s(std::move(impl));
    const Impl& i = *s.impl_;
    const toml::node* table = lookup(i.root, "scene");
    if (!table) fail(i.origin + ": missing [scene] table (with name and experiment)");
    if (!table->is_table()) wrong_type(i, "scene", *table, "a table");
    s.only("scene", scene_keys);
    const std::string name = s.string("scene.name");
    if (!valid_name(name))
        s.reject("scene.name", "must be a folder name: letters, digits, '-', '_', '.', not starting with '.' or '-'");
    (void)s.string("scene.experiment");
    (void)s.string("scene.title", "");
    (void)s.string("scene.description", "");
    return s;
}

const std::string& Scene::origin() const { return impl_->origin; }
const std::string& Scene::text() const { return impl_->text; }
std::string Scene::name() const { return string("scene.name"); }
std::string Scene::experiment() const { return string("scene.experiment"); }
std::string Scene::title() const { return string("scene.title", name()); }

bool Scene::has(std::string_view key) const { return lookup(impl_->root, key) != nullptr; }

double Scene::number(std::string_view key) const { return as_number(*impl_, key, require(*impl_, key)); }
double Scene::number(std::string_view key, double fallback) const {
    return has(key) ? number(key) : fallback;
}
long Scene::integer(std::string_view key) const { return as_integer(*impl_, key, require(*impl_, key)); }
long Scene::integer(std::string_view key, long fallback) const { return has(key) ? integer(key) : fallback; }
std::string Scene::string(std::string_view key) const { return as_string(*impl_, key, require(*impl_, key)); }
std::string Scene::string(std::string_view key, std::string_view fallback) const {
    return has(key) ? string(key) : std::string(fallback);
}
bool Scene::boolean(std::string_view key, bool fallback) const {
    if (!has(key)) return fallback;
    const toml::node& n = require(*impl_, key);
    if (const auto* b = n.as_boolean()) return b->get();
    wrong_type(*impl_, key, n, "a boolean (true or false)");
}

std::vector<double> Scene::numbers(std::string_view key) const {
    return array_of<double>(*impl_, key, "an array of numbers",
                            [](const Doc& s, const std::string& k, const toml::node& n) { return as_number(s, k, n); });
}
std::vector<long> Scene::integers(std::string_view key) const {
    return array_of<long>(*impl_, key, "an array of integers",
                          [](const Doc& s, const std::string& k, const toml::node& n) { return as_integer(s, k, n); });
}
std::vector<std::string> Scene::strings(std::string_view key) const {
    return array_of<std::string>(*impl_, key, "an array of strings",
                                 [](const Doc& s, const std::string& k, const toml::node& n) { return as_string(s, k, n); });
}

double Scene::positive(std::string_view key) const {
    const double x = number(key);
    if (!(x > 0) || !std::isfinite(x)) reject(key, "must be positive and finite");
    return x;
}

void Scene::reject(std::string_view key, const std::string& why) const {
    bad(impl_->origin, key, lookup(impl_->root, key), why);
}

void Scene::only(std::string_view section, const std::vector<std::string_view>& known) const {
    const toml::node* n = section.empty() ? &impl_->root : lookup(impl_->root, section);
    if (!n) return;
    const toml::table* t = n->as_table();
    if (!t) wrong_type(*impl_, section, *n, "a table");
    std::vector<std::string> unknown;
    const toml::node* first = nullptr;
    for (const auto& [k, v] : *t)
        if (std::find(known.begin(), known.end(), k.str()) == known.end()) {
            unknown.push_back(section.empty() ? std::string(k.str()) : std::string(section) + "." + std::string(k.str()));
            if (!first) first = &v;
        }
    if (unknown.empty()) return;
    std::string m = where(impl_->origin, first) + ": unknown key" + (unknown.size() > 1 ? "s " : " ");
    for (std::size_t i = 0; i < unknown.size(); ++i) m += (i ? ", " : "") + unknown[i];
    m += " (known in [" + std::string(section) + "]: ";
    for (std::size_t i = 0; i < known.size(); ++i) m += (i ? ", " : "") + std::string(known[i]);
    fail(m + ")");
}

}  // namespace mollify::app
