// The default catalogue emitted into generated/ (README, "Default catalogue").
#pragma once

#include "spec.hpp"

#include <vector>

namespace mollify::gen {

struct CatalogueEntry {
    Spec spec;
    int dim;
};

// Anderson M = 1..9, orders 2/4/6; Wendland k = 0..4, l = 0..4; missing
// Wendland k = 1..2, l = 0..2; combinations
// m = 2, 3 of Wendland k = 1..3, l = 0..2 and of mollifier M = 4, 9; the
// classic kernels; each in every dimension 1..3 where it is defined.
std::vector<Spec> default_specs();
// Does the kernel exist in dimension dim (viscosity: D = 2, 3; Belley's
// delta', delta'': D = 1)?
bool defined_in(const Spec& s, int dim);
// Specs expanded over D = 1..3, skipping dimensions a kernel does not exist in.
std::vector<CatalogueEntry> expand_dimensions(const std::vector<Spec>& specs);

}  // namespace mollify::gen
