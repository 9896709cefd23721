// Kernels users pick instead, for comparison: Mueller et al. 2003 (poly6,
// spiky, viscosity, as quoted in seed 002), Monaghan's cubic spline (M4)
// and the quartic and quintic splines (M5, M6: Schoenberg's B-splines,
// schoenberg.hpp) that Phantom and SWIFT ship,
// and Belley's discontinuous delta, delta', delta'' (seed 002, (12), (16),
// (20)); all with support radius 1, unnormalised.
#pragma once

#include "radial.hpp"
#include "spec.hpp"

namespace mollify::gen {

Radial classic_shape(Family f);

}  // namespace mollify::gen
