// The emission's own certificate: the planned terms of every piece sum
// exactly to the quantity's closed form there (emit_plan.hpp); Taylor
// pieces about a centre, truncated, are checked numerically in MPFR.
#pragma once

#include "emit_plan.hpp"

#include <vector>

namespace mollify::gen {

// Throws Error ("internal: ...") naming the first piece that misses.
void check_emitted(const Radial& f, const std::vector<EmittedPiece>& pieces);

}  // namespace mollify::gen
