// What batch_loops_test's x86-64-v3 unit (batches.cpp) computes.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace batch_loops {

struct Comparison {
    std::size_t compared = 0;             // values compared
    std::vector<std::string> mismatches;  // where a batch and a single point differ, or the run-time form too far
    double worst_against_runtime = 0;     // ulps (fused_bound.hpp) from the run-time form's copy
};

// Every quantity (both precisions) and W + grad W of a few tables, in
// batches and point by point, in a unit tuned for AMD Zen 1; the batches
// against the run-time form (the caller chooses its x86-64-v3 copy).
Comparison batches_against_points();

// The pair loops' input check (NonFiniteRoots, on each block of roots as it
// is taken): a NaN or infinite coordinate in the first block of roots, a
// middle one, the last (which overlaps the one before) and a batch shorter
// than a block, in StaticKernel's 3D and 2D pair loops of the unit's
// instruction set and in the run-time form's (the caller chooses its copy),
// each must be an Error naming that coordinate. The cases that were not.
std::vector<std::string> unflagged_bad_inputs();

// The same for the batch evaluation of W and W'/r by levels (NotRadii, on
// each register of radii): a NaN, infinite or negative radius (-0 is a
// radius) anywhere in a batch must be an Error naming it.
std::vector<std::string> unflagged_bad_radii();

}  // namespace batch_loops
