#include "write_constants.hpp"

#include "emit_metadata.hpp"
#include "exact.hpp"
#include "rounding.hpp"
#include "zeta.hpp"

namespace mollify::gen {

// Six terms: where the runtime sums the series (|z| < 0.05) the first one
// left out, zeta(14)/pi |z|^13, is below 4e-18 (absolute; the other
// branch's rounding there, eps/(2 pi |z|), is above 7e-16).
constexpr int cot_series_terms = 6;

std::string cot_series_header(const std::string& command) {
    std::string out = banner(command, "//");
    out += "// The periodic row of point vortices about its own vortex (Euler; generator/zeta.hpp):\n"
           "//   cot(pi z)/(2i) - 1/(2 pi i z) = (i/pi) sum_{j>=1} zeta(2j) z^(2j-1),\n"
           "// zeta(2j)/pi = (zeta(2j)/pi^(2j)) pi^(2j-1) for j = 1.." +
           std::to_string(cot_series_terms) +
           ", correctly rounded (vortex/periodic_point_vortex.hpp).\n"
           "#pragma once\n\n"
           "namespace mollify::constants {\n\n"
           "inline constexpr double zeta_even_over_pi[" +
           std::to_string(cot_series_terms) + "] = {\n";
    for (int j = 1; j <= cot_series_terms; ++j) {
        const Exact c = Exact::pi_power(zeta_even_over_pi_power(j), 2 * j - 1);
        out += "    " + hex_literal(round_to_double(c)) + ",  // zeta(" + std::to_string(2 * j) + ")/pi = " + c.to_string() + "\n";
    }
    out += "};\n\n}  // namespace mollify::constants\n";
    return out;
}

std::string log_two_header(const std::string& command) {
    const Exact log_two = Exact::of(Atom{0, 2});
    const double hi = round_to_double(log_two);
    const double lo = low_part(log_two, hi);
    std::string out = banner(command, "//");
    out += "// log 2 as a double-double, hi + lo: log q = log m + E log 2 for q = m 2^E\n"
           "// below the doubles' range (detail/near_origin.hpp).\n"
           "#pragma once\n\n"
           "namespace mollify::constants {\n\n"
           "inline constexpr double log_two_hi = " +
           hex_literal(hi) + ";  // log(2) correctly rounded\n" + "inline constexpr double log_two_lo = " + hex_literal(lo) +
           ";  // log(2) - log_two_hi correctly rounded\n\n}  // namespace mollify::constants\n";
    return out;
}

}  // namespace mollify::gen
