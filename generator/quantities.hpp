// Every quantity the runtime evaluates, as exact piecewise closed forms, so
// that no derivative, quotient or Laplacian is formed in floating point:
//   value W, dr W', d2r W'', laplacian W'' + (D-1)W'/r,
//   grad_over_r W'/r (grad W = (W'/r) x: finite at r = 0),
//   hess_radial (W'' - W'/r)/r^2 (Hessian = hess_radial x x^T + (W'/r) I),
// and the same for the potential phi (Delta phi = W).
#pragma once

#include "kernel.hpp"

#include <optional>
#include <string>
#include <vector>

namespace mollify::gen {

struct Quantities {
    Radial value, dr, d2r, laplacian, grad_over_r, hess_radial;
    std::optional<Radial> potential, dpotential, dpotential_over_r, potential_hess_radial;
};

Quantities derive_quantities(const ExactKernel& k);

// Named access for the CLI and the emitters: "value", "dr", ... , "potential".
const std::vector<std::string>& quantity_names();
const Radial& quantity(const ExactKernel& k, const Quantities& q, const std::string& name);

}  // namespace mollify::gen
