// What one unit of isa_units_test computed, and where its solvers' code is
// (unit.cpp, compiled once per instruction set).
#pragma once

#include <cstdint>
#include <vector>

namespace isa_units {

struct UnitReport {
    const char* isa;                           // MOLLIFY_ISA as the unit saw it
    std::uintptr_t sph, poisson, vortex;       // one instantiated solver function of each
    std::vector<double> density, potential, u; // a small problem of each solver
};

UnitReport generic_unit();
UnitReport v3_unit();

}  // namespace isa_units
