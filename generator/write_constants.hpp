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

}  // namespace mollify::gen
