// Schoenberg's centred B-spline M_n (Schoenberg 1946; Monaghan 2005, §4:
// M_4 the cubic, M_5 the quartic, M_6 the quintic spline of SPH codes),
// built from its definition as a sum of truncated powers, never from a
// printed table:
//   M_n(x) = 1/(n-1)! sum_{j >= 0, n/2 - j > 0} (-1)^j binom(n, j) (n/2 - j - |x|)_+^(n-1),
// rescaled to support radius 1 (s = |x| / (n/2)) and left unnormalised, like
// the classic shapes (classic.hpp): the shapes of the quartic-spline (M_5)
// and quintic-spline (M_6) kernels.
#pragma once

#include "radial.hpp"

namespace mollify::gen {

// n = 2..12 (order n, degree n - 1); Error otherwise.
Radial schoenberg_shape(int n);

}  // namespace mollify::gen
