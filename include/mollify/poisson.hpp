// mollify's free-space Poisson solvers for smoothed sources (D = 2, 3):
// direct summation and the multipole treecode, both with the exact mollified
// potential of any kernel the runtime has a potential for.
//
// Sign convention (poisson/sources.hpp): phi = sum_j q_j phi_delta_j(|x - x_j|)
// with Delta phi_delta = W_delta, so phi = -q/(4 pi r) (3D), q log(r)/(2 pi)
// (2D) beyond the support, and E = -grad phi; in 2D biot_savart() gives the
// vortex-blob velocity u = (E_y, -E_x).
#pragma once

#include <mollify/poisson/direct.hpp>
#include <mollify/poisson/multipole.hpp>
#include <mollify/poisson/sources.hpp>
#include <mollify/poisson/tolerance.hpp>
#include <mollify/poisson/tree.hpp>
#include <mollify/poisson/treecode.hpp>
