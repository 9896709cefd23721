// mollify's Poisson solvers. Free space, smoothed sources (D = 2, 3):
// direct summation and the multipole treecode, both with the exact mollified
// potential of any kernel the runtime has a potential for. Periodic (D = 1,
// 2, 3): the FFT solver with finite-difference or pseudospectral symbols,
// NMP/CIC/kernel charge assignment (needs FFTW3: link fftw3), and the 1D
// periodic BVP -phi'' + sigma^2 phi = f.
//
// Sign convention (poisson/sources.hpp): phi = sum_j q_j phi_delta_j(|x - x_j|)
// with Delta phi_delta = W_delta, so phi = -q/(4 pi r) (3D), q log(r)/(2 pi)
// (2D) beyond the support, and E = -grad phi; in 2D biot_savart() gives the
// vortex-blob velocity u = (E_y, -E_x).
#pragma once

#include <mollify/poisson/direct.hpp>
#include <mollify/poisson/multipole.hpp>
#include <mollify/poisson/charge_assignment.hpp>
#include <mollify/poisson/field_errors.hpp>
#include <mollify/poisson/periodic.hpp>
#include <mollify/poisson/periodic_bvp.hpp>
#include <mollify/poisson/periodic_grid.hpp>
#include <mollify/poisson/sources.hpp>
#include <mollify/poisson/tolerance.hpp>
#include <mollify/poisson/tree.hpp>
#include <mollify/poisson/treecode.hpp>
