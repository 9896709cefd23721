// Certificates (issue item 7): exact proofs, per kernel and dimension, of
// unit mass (or Belley's derivative normalisation), vanishing moments up to
// the claimed order, Delta phi = W identically, and continuity of W and its
// derivatives up to the claimed smoothness across every breakpoint and at
// the support edge, and of phi, phi' with the Green's function.
#pragma once

#include "quantities.hpp"

#include <string>
#include <vector>

namespace mollify::gen {

struct Certificate {
    std::string what;    // e.g. "unit mass", "moment r^2 = 0", "Delta phi = W"
    bool passed = false;
    std::string detail;  // the exact values compared
};

std::vector<Certificate> certify(const ExactKernel& k, const Quantities& q);

}  // namespace mollify::gen
