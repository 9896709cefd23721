// Internal to `mollify-gen errata` (errata*.cpp): what the document checkers
// share. An Entry is one transcription entry with typed access to its fields
// and the primitive that counts a comparison and records a discrepancy; the
// Checker holds the exact side (cached kernels and quantities) and one check
// per quantity kind, defined in the file of the document that prints it:
// errata_anderson.cpp, errata_franz.cpp, errata_belley.cpp.
#pragma once

#include "errata.hpp"
#include "kernel.hpp"
#include "quantities.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace mollify::gen::errata {

using nlohmann::json;

// Coefficients of a polynomial in one variable, each an exact constant.
using Coefficients = std::map<int, Exact>;

// A transcription file (JSON) read and its top level checked: an object
// with the given string fields and an array "entries"; else an Error naming
// the file and the field.
json read_transcription(const std::filesystem::path& path, std::initializer_list<const char*> string_fields);

// ---------------------------------------------------------------------------
// Exact helpers

Exact exact_from(const Q& q, const Atom& a);  // q * pi^e log p
void add_coefficient(Coefficients& c, int n, const Exact& v);
Coefficients coefficients(const Laurent& p);
// A closed form made of basis-1 terms only (polynomials times pi^e log p).
Coefficients coefficients(const ClosedForm& f);

// a / b when it is rational (a and b the same combination of atoms).
std::optional<Q> ratio(const Exact& a, const Exact& b);

// The factor c with printed = c * exact shared by most (printed, exact)
// pairs; ties go to the pair listed first. Robust against a single wrong
// coefficient, wherever it sits.
std::optional<Q> common_factor(const std::vector<std::pair<Exact, Exact>>& pairs);

// ---------------------------------------------------------------------------
// Values spelled for people

// "sign differs", "printed/exact = c", or "" when the ratio is unknown.
std::string factor_remark(const std::optional<Q>& printed_over_exact);
// The non-empty parts, separated by `sep`.
std::string join(const std::vector<std::string>& parts, const std::string& sep);
// "c x^a y^b" with c = 1 / -1 folded into the sign.
std::string monomial_string(const Q& c, const std::vector<std::pair<std::string, int>>& powers);
// "a + b - c"; "0" for no terms.
std::string sum_string(const std::vector<std::string>& terms);
std::string delta_string(int n);  // "delta^n"

// ---------------------------------------------------------------------------
// One transcription entry: its identity, typed access to its fields, and the
// comparison primitive that counts and records.

struct Entry {
    std::string file, document, where, label, quantity;
    const json* object = nullptr;
    ErrataReport* report = nullptr;

    std::string context() const { return file + ", entry '" + label + "' (" + where + ")"; }
    [[noreturn]] void bad(const std::string& what) const;

    // Counts one comparison; records a discrepancy unless `equal`. `part`
    // extends the entry's label.
    void compare(bool equal, const std::string& part, const std::string& printed, const std::string& exact,
                 const std::string& remark = "") const;

    // Fields of `obj`, a sub-object at `path` ("" for the entry itself).
    const json& need(const json& obj, const std::string& key, const std::string& path) const;
    int integer(const json& obj, const std::string& key, const std::string& path) const;
    std::string text(const json& obj, const std::string& key, const std::string& path) const;
    bool boolean(const json& obj, const std::string& key, const std::string& path) const;
    Q rational(const json& v, const std::string& path) const;
    Q rational(const json& obj, const std::string& key, const std::string& path) const;
    // {"2": "1/4", ...}: keys are exponents in decimal.
    std::map<int, Q> coefficient_map(const json& obj, const std::string& key, const std::string& path) const;

    const json& params() const { return need(*object, "params", ""); }
    const json& printed() const { return need(*object, "printed", ""); }
    int param(const std::string& key) const { return integer(params(), key, "params"); }
    std::string param_text(const std::string& key) const { return text(params(), key, "params"); }
    const json& printed_array(const std::string& key) const;
};

// A printed term "weight * f(scale r)" of a combination (Anderson (9)-(10),
// Franz Tables 4.2/4.4), whose scale field is named `scale_key`.
struct ScaledTerm {
    Q weight, scale;
};
std::vector<ScaledTerm> read_scaled_terms(const Entry& e, const std::string& scale_key);

// ---------------------------------------------------------------------------
// Comparisons shared by the documents

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
// the factor is the one most coefficients share (unless given); the exact
// column shows the exact coefficient times that factor.
struct Proportional {
    std::string part;
    Exact printed, exact;
};

void compare_proportional(const Entry& e, const std::vector<Proportional>& items, std::optional<Q> factor,
                          const std::string& extra_remark);

// Printed terms of a combination paired with its exact members (one per
// radius): match[i] is the member of printed term i, used[j] whether member
// j has a printed term.
struct Pairing {
    Pairing(std::size_t printed, std::size_t members) : match(printed), used(members, false) {}

    // Gives each unpaired printed term i the first free member j with fits(i, j).
    template <class Fits>
    void pair(Fits fits) {
        for (std::size_t i = 0; i < match.size(); ++i) {
            if (match[i]) continue;
            for (std::size_t j = 0; j < used.size(); ++j)
                if (!used[j] && fits(i, j)) {
                    match[i] = j;
                    used[j] = true;
                    break;
                }
        }
    }

    std::vector<std::optional<std::size_t>> match;
    std::vector<bool> used;
};

// ---------------------------------------------------------------------------
// The exact side and one check per quantity kind.

class Checker {
public:
    // Compares the entry's printed value(s) with the exact ones by its
    // "quantity"; an unknown kind is a malformed transcription.
    void check(const Entry& e);

private:
    const ExactKernel& kernel(const std::string& spec, int dim);
    const Quantities& quantities(const std::string& spec, int dim);

    // A printed rational against an exact one.
    void scalar(const Entry& e, const Q& exact, const std::string& remark_if_wrong = "");

    // Anderson 2014 (errata_anderson.cpp).
    Q table1_sigma(int dim, int M);
    void anderson_sigma(const Entry& e);
    void anderson_c0(const Entry& e);
    void anderson_gamma(const Entry& e);
    void anderson_alpha(const Entry& e);
    void anderson_sigma_formula(const Entry& e);
    void anderson_second_moment(const Entry& e);
    void anderson_radii_combination(const Entry& e);
    void anderson_formula(const Entry& e);

    // Franz: Vandermonde weights and Wendland functions (errata_franz.cpp).
    void vandermonde_equidistant(const Entry& e);
    void wendland_shape_entry(const Entry& e);
    void wendland_combo(const Entry& e);
    void wendland_combo_weights(const Entry& e);
    void wendland_missing(const Entry& e);

    // Belley: classic and discontinuous kernels (errata_belley.cpp).
    void classic_kernel(const Entry& e);
    void belley_moment(const Entry& e);
    void belley_kernel_value(const Entry& e);

    std::map<std::pair<std::string, int>, ExactKernel> kernels_;
    std::map<std::pair<std::string, int>, Quantities> quantities_;
};

}  // namespace mollify::gen::errata
