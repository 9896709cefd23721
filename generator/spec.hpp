// The kernel-spec grammar is mollify's one grammar (include/mollify/spec.hpp,
// shared with the runtime, no GMP); the exact world reads its radii as
// GMP rationals.
#pragma once

#include "number.hpp"

#include <mollify/spec.hpp>

#include <vector>

namespace mollify::gen {

using mollify::Family;
using mollify::family_name;
using mollify::max_combo_m;
using mollify::max_mollifier_M;
using mollify::max_mollifier_order;
using mollify::max_wendland_k;
using mollify::max_wendland_l;
using mollify::parse_spec;
using mollify::Ratio;
using mollify::Spec;
using mollify::spec_string;

inline Q to_q(const Ratio& r) { return Q(r.num) / Q(r.den); }

// The radii a_1 < ... < a_m of a combination, exactly.
inline std::vector<Q> radii(const Spec& s) {
    std::vector<Q> out;
    for (const Ratio& a : s.radii) out.push_back(to_q(a));
    return out;
}

// Equidistant radii j/m of "combo:m=...".
inline std::vector<Q> equidistant_radii(int m) {
    std::vector<Q> out;
    for (const Ratio& a : mollify::equidistant_radii(m)) out.push_back(to_q(a));
    return out;
}

}  // namespace mollify::gen
