#include "search_choices.hpp"

#include <atomic>
#include <cstdio>
#include <initializer_list>
#include <map>
#include <mutex>

namespace mollify::gen {

namespace {

std::atomic<bool> afresh{false};

// One search's choices: compiled in (search_choices.def), and those this run
// made while searching afresh.
template <class Choice>
struct Choices {
    std::map<std::uint64_t, Choice> known;
    std::mutex mutex;
    std::map<std::uint64_t, Choice> recorded;
};

struct All {
    All();  // the compiled-in choices
    Choices<ZeroChoice> zero;
    Choices<EdgeChoice> edge;
    Choices<CentredChoices> centred;
    Choices<RecentreChoices> recentre;
};

// One line of search_choices.def as static data (a table, not code: it
// compiles in a moment however long it gets).
enum class Search { zero, edge, centred, recentre };
struct Line {
    Search search;
    std::uint64_t key;
    int n[4];
    const char* q;
};

All::All() {
    static constexpr std::initializer_list<Line> lines = {
#define MOLLIFY_ZERO_CHOICE(key, m, order) {Search::zero, key, {m, order}, nullptr},
#define MOLLIFY_EDGE_CHOICE(key, r1, order) {Search::edge, key, {order}, r1},
#define MOLLIFY_CENTRED_CHOICE(key, piece, k, j, order, tenth, scale) {Search::centred, key, {k, j, order, tenth}, scale},
#define MOLLIFY_RECENTRE_CHOICE(key, piece, hi, own) {Search::recentre, key, {own}, hi},
#include "search_choices.def"
#undef MOLLIFY_ZERO_CHOICE
#undef MOLLIFY_EDGE_CHOICE
#undef MOLLIFY_CENTRED_CHOICE
#undef MOLLIFY_RECENTRE_CHOICE
    };
    for (const Line& l : lines) {  // the file lists a key's pieces in order
        const int* n = l.n;
        switch (l.search) {
            case Search::zero: zero.known[l.key] = {n[0], n[1]}; break;
            case Search::edge: edge.known[l.key] = {Q(l.q), n[0]}; break;
            case Search::centred: centred.known[l.key].push_back({n[0], n[1], n[2], n[3], Q(l.q)}); break;
            case Search::recentre: recentre.known[l.key].push_back({Q(l.q), n[0] != 0}); break;
        }
    }
}

All& all() {
    static All a;
    return a;
}

template <class Choice>
const Choice* known_in(const Choices<Choice>& c, std::uint64_t key) {
    if (afresh) return nullptr;
    auto it = c.known.find(key);
    return it == c.known.end() ? nullptr : &it->second;
}

template <class Choice>
void record_in(Choices<Choice>& c, std::uint64_t key, const Choice& choice) {
    std::lock_guard lock(c.mutex);
    c.recorded[key] = choice;
}

void hash_text(std::uint64_t& h, const std::string& s) {
    for (const char ch : s) {
        h ^= static_cast<unsigned char>(ch);
        h *= 0x100000001b3ULL;
    }
    h ^= 0xff;  // a separator: ("1", "23") and ("12", "3") differ
    h *= 0x100000001b3ULL;
}

std::string hex_key(std::uint64_t key) {
    char s[32];
    std::snprintf(s, sizeof s, "0x%016llxULL", static_cast<unsigned long long>(key));
    return s;
}

// "MACRO(key, fields)" per recorded choice, by key.
template <class Choice, class Fields>
void append_lines(std::string& out, Choices<Choice>& c, const char* macro, Fields fields) {
    std::lock_guard lock(c.mutex);
    for (const auto& [key, choice] : c.recorded)
        for (const std::string& f : fields(choice)) {
            out += macro;
            out += "(" + hex_key(key) + ", ";
            out += f;
            out += ")\n";
        }
}

}  // namespace

std::uint64_t search_key(const std::string& search, const ClosedForm& f, std::initializer_list<Q> given) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    hash_text(h, search);
    for (const auto& [key, p] : f.terms()) {
        hash_text(h, std::to_string(static_cast<int>(key.basis)) + " " + std::to_string(key.s_power) + " " +
                         std::to_string(key.factor.pi_power) + " " + std::to_string(key.factor.log_of));
        for (int k = p.low(); k <= p.high(); ++k) hash_text(h, std::to_string(k) + " " + p.coefficient(k).str());
    }
    for (const Q& q : given) hash_text(h, q.str());
    return h;
}

const ZeroChoice* known_choice(std::uint64_t key, const ZeroChoice*) { return known_in(all().zero, key); }
const EdgeChoice* known_choice(std::uint64_t key, const EdgeChoice*) { return known_in(all().edge, key); }
const CentredChoices* known_choice(std::uint64_t key, const CentredChoices*) { return known_in(all().centred, key); }
const RecentreChoices* known_choice(std::uint64_t key, const RecentreChoices*) { return known_in(all().recentre, key); }

void search_afresh() { afresh = true; }
bool searching_afresh() { return afresh; }

void record_choice(std::uint64_t key, const ZeroChoice& choice) { record_in(all().zero, key, choice); }
void record_choice(std::uint64_t key, const EdgeChoice& choice) { record_in(all().edge, key, choice); }
void record_choice(std::uint64_t key, const CentredChoices& choices) { record_in(all().centred, key, choices); }
void record_choice(std::uint64_t key, const RecentreChoices& choices) { record_in(all().recentre, key, choices); }

std::string search_choices_file() {
    auto s = [](int x) { return std::to_string(x); };
    std::string out =
        "// Written by `mollify-gen emit --search-choices FILE` (search_choices.hpp): the\n"
        "// searches' choices, as they made them. Do not edit.\n"
        "// MOLLIFY_ZERO_CHOICE(key, m, order)\n"
        "// MOLLIFY_EDGE_CHOICE(key, r1, order)\n"
        "// MOLLIFY_CENTRED_CHOICE(key, piece, k, j, order, tenth, scale)\n"
        "// MOLLIFY_RECENTRE_CHOICE(key, piece, hi, own)\n";
    append_lines(out, all().zero, "MOLLIFY_ZERO_CHOICE",
                 [&](const ZeroChoice& c) { return std::vector{s(c.m) + ", " + s(c.order)}; });
    append_lines(out, all().edge, "MOLLIFY_EDGE_CHOICE",
                 [&](const EdgeChoice& c) { return std::vector{"\"" + c.r1.str() + "\", " + s(c.order)}; });
    append_lines(out, all().centred, "MOLLIFY_CENTRED_CHOICE", [&](const CentredChoices& pieces) {
        std::vector<std::string> lines;
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            const CentredChoice& c = pieces[i];
            lines.push_back(s(static_cast<int>(i)) + ", " + s(c.k) + ", " + s(c.j) + ", " + s(c.order) + ", " +
                            s(c.tenth) + ", \"" + c.scale.str() + "\"");
        }
        return lines;
    });
    append_lines(out, all().recentre, "MOLLIFY_RECENTRE_CHOICE", [&](const RecentreChoices& pieces) {
        std::vector<std::string> lines;
        for (std::size_t i = 0; i < pieces.size(); ++i)
            lines.push_back(s(static_cast<int>(i)) + ", \"" + pieces[i].hi.str() + "\", " + s(pieces[i].own));
        return lines;
    });
    return out;
}

}  // namespace mollify::gen
