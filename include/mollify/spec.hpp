// The kernel-spec grammar, one for the generator's CLI, scenes, tests and the
// runtime (no GMP; the parser, Boost.Spirit X3, is compiled in src/spec.cpp):
//   mollifier:M=4            mollifier:M=4,order=4     (Anderson, exponent method)
//   wendland:k=2             wendland:k=2,l=1          (Franz Lemma 4.36)
//   wendland-missing:k=1,l=1                           (Franz §4.3.3)
//   combo:m=3,base=SPEC      combo:radii=1/3;2/3;1,base=SPEC  (Franz Prop. 4.24)
//   poly6  spiky  viscosity  cubic-spline  box  box-d1  box-d2
// `base=` must come last and takes the rest of the text. Parameters may come
// in any order; every kernel has one canonical spelling (spec_string), the
// key under which the generator emits its tables.
#pragma once

#include <mollify/error.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mollify {

enum class Family {
    mollifier,
    wendland,
    wendland_missing,
    combo,
    poly6,
    spiky,
    viscosity,
    cubic_spline,
    quartic_spline,
    quintic_spline,
    box,
    box_d1,
    box_d2,
};

// An exact rational with machine integers: what a spec can hold (radii).
struct Ratio {
    std::int64_t num = 0, den = 1;  // den > 0, gcd(num, den) = 1
    friend bool operator==(const Ratio&, const Ratio&) = default;
    friend bool operator<(const Ratio& a, const Ratio& b) {
        return static_cast<__int128>(a.num) * b.den < static_cast<__int128>(b.num) * a.den;
    }
};

struct Spec {
    Family family = Family::mollifier;
    int M = 0;               // mollifier exponent
    int order = 2;           // mollifier order 2K (exponent method)
    int k = 0, l = 0;        // Wendland smoothness and extension
    std::vector<Ratio> radii;  // combo radii a_1 < ... < a_m = 1
    std::shared_ptr<const Spec> base;

    bool is_polynomial() const { return family != Family::wendland_missing; }
};

// Parameter ranges, one place: the generator and every error message use these.
inline constexpr int max_mollifier_M = 64;
inline constexpr int max_mollifier_order = 20;
inline constexpr int max_wendland_k = 12;
inline constexpr int max_wendland_l = 12;
inline constexpr int max_combo_m = 12;

// The digits of a number as written, before any conversion:
//   number := sign? digits ( '/' digits | ('.' digits*)? (e sign? digits)? )
//           | sign? '.' digits (e sign? digits)?
struct NumberSyntax {
    bool negative = false;
    std::string integer, fraction, denominator;
    bool has_exponent = false, exponent_negative = false;
    std::string exponent;
};

// The syntax of a number, or nullopt if the text is not one.
std::optional<NumberSyntax> split_number(std::string_view text);

// A C99 hex-float, a double's exact value as C's %a, Python's float.hex and
// Fortran's EX write it: sign? 0[xX] hexdigits ('.' hexdigits*)? [pP] sign? digits
// (or '.' hexdigits after the prefix). nullopt where the text does not start
// with the prefix (after one sign): not meant as a hex-float; else its value
// (+-inf where it lies beyond the doubles' range, above or below), or NaN where
// the text is no whole hex-float ("0x-1p3", "0x1.8", "0x1p"): the caller names
// the error.
std::optional<double> hex_float(std::string_view text);

// "3", "-3/4", "0.125", "1e-3" as an exact Ratio; Error naming `what`.
Ratio parse_ratio(std::string_view text, std::string_view what);

std::string to_string(const Ratio& r);
std::string family_name(Family f);

// Equidistant radii j/m of "combo:m=...".
std::vector<Ratio> equidistant_radii(int m);

// Any spelling of the grammar; Error naming the bad part.
Spec parse_spec(std::string_view text);

// The canonical spelling: fixed parameter order, defaults (order=2, l=0)
// omitted, equidistant radii written as m=.
std::string spec_string(const Spec& s);

inline bool operator==(const Spec& a, const Spec& b) { return spec_string(a) == spec_string(b); }

}  // namespace mollify
