// The runtime's constants that are not kernel tables, written as C++
// headers under generated/mollify/constants/ (by every `mollify-gen emit`
// of C++ tables): correctly rounded hex floats with their exact values.
#pragma once

#include <string>

namespace mollify::gen {

// mollify/constants/cot_series.hpp: zeta(2j)/pi, j = 1 .. 6, the Laurent
// coefficients of the periodic row of point vortices at its own vortex
// (vortex/periodic_point_vortex.hpp).
std::string cot_series_header(const std::string& command);

// mollify/constants/log_two.hpp: log 2 as a double-double (hi correctly
// rounded, lo the remainder correctly rounded): log q = log m + E log 2 for
// q = m 2^E far below the doubles' range (detail/near_origin.hpp).
std::string log_two_header(const std::string& command);

}  // namespace mollify::gen
