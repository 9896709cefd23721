// mollify's SPH solvers (umbrella header): Franz's weakly compressible SPH
// for the barotropic Euler equations with any kernel of the runtime.
// Franz's test cases and rate fits are study code: tools/studies/
// (CMake target mollify_studies).
#pragma once

#include <mollify/sph/burgers.hpp>
#include <mollify/sph/domain.hpp>
#include <mollify/sph/energy_error.hpp>
#include <mollify/sph/euler.hpp>
#include <mollify/sph/neighbours.hpp>
#include <mollify/sph/time_stepping.hpp>
