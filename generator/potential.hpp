// Poisson potentials of radial kernels: phi with Delta phi = W in R^D,
// equal to the free-space Green's function outside the support
// (3D -1/(4 pi r), 2D log(r)/(2 pi), 1D |r|/2), continuous with it and with
// its derivative at the support edge (Anderson §4, for any radial W).
#pragma once

#include "radial.hpp"

namespace mollify::gen {

ClosedForm green_function(int dim);
// Requires unit mass and elementary (polynomial or Laurent) pieces.
Radial potential(const Radial& W, int dim);
// Radial Laplacian f'' + (D-1) f'/r, piecewise, exactly.
Radial radial_laplacian(const Radial& f, int dim);

}  // namespace mollify::gen
