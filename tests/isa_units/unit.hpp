// What one unit of isa_units_test holds and computes (unit.cpp, compiled
// once per instruction set).
#pragma once

#include <cstdint>
#include <vector>

namespace isa_units {

// Where the unit's solver code is: one instantiated function of each solver.
struct UnitCode {
    const char* isa;  // MOLLIFY_ISA as the unit saw it
    std::uintptr_t sph, poisson, vortex;
};

// A small problem of each solver, computed by the unit's copy.
struct UnitValues {
    std::vector<double> density, potential, u;
    // The 3D treecode's E and direct summation's, components one after another.
    std::vector<double> tree_field, direct_field;
};

UnitCode generic_code();
UnitValues generic_values();
UnitCode v3_code();
UnitValues v3_values();

}  // namespace isa_units
