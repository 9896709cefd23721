// The kernel-spec grammar, one for the CLI, scenes and tests:
//   mollifier:M=4            mollifier:M=4,order=4     (Anderson, exponent method)
//   wendland:k=2             wendland:k=2,l=1          (Franz Lemma 4.36)
//   wendland-missing:k=1,l=1                           (Franz §4.3.3)
//   combo:m=3,base=SPEC      combo:radii=1/3;2/3;1,base=SPEC  (Franz Prop. 4.24)
//   poly6  spiky  viscosity  cubic-spline  box  box-d1  box-d2
// `base=` must come last and takes the rest of the text. Parameters may come
// in any order; every kernel has one canonical spelling (spec_string).
#pragma once

#include "number.hpp"

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace mollify::gen {

enum class Family {
    mollifier,
    wendland,
    wendland_missing,
    combo,
    poly6,
    spiky,
    viscosity,
    cubic_spline,
    box,
    box_d1,
    box_d2,
};

struct Spec {
    Family family = Family::mollifier;
    int M = 0;          // mollifier exponent
    int order = 2;      // mollifier order 2K (exponent method)
    int k = 0, l = 0;   // Wendland smoothness and extension
    std::vector<Q> radii;  // combo radii a_1 < ... < a_m = 1
    std::shared_ptr<const Spec> base;

    std::string family_name() const;
    bool is_polynomial() const;  // every piece a (Laurent) polynomial in r
    friend bool operator==(const Spec& a, const Spec& b);
};

Spec parse_spec(std::string_view text);
std::string spec_string(const Spec& s);  // canonical spelling
// Equidistant radii j/m of "combo:m=...".
std::vector<Q> equidistant_radii(int m);

// Parameter ranges, one place: the generator and its error messages use these.
inline constexpr int max_mollifier_M = 64;
inline constexpr int max_mollifier_order = 20;
inline constexpr int max_wendland_k = 12;
inline constexpr int max_wendland_l = 12;
inline constexpr int max_combo_m = 12;

}  // namespace mollify::gen
