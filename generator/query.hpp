// Every quantity a user can ask for by name (mollify-gen value --quantity),
// in one list: the tabulated quantities (table::quantity_names, quantities.hpp)
// and the softening families NAME:n of softening.hpp.
#pragma once

#include "kernel.hpp"

#include <string>
#include <vector>

namespace mollify::gen {

struct OrderedFamily {
    std::string name;  // spelled NAME:n
    int low, high;     // the orders n
    std::string meaning;
    // The orders up to n (softening.hpp); the last is the one asked for.
    std::vector<Radial> (*up_to)(const ExactKernel&, int max_order);
};

// Names without an order beyond the tabulated ones: dphidh (softening.hpp).
struct NamedQuantity {
    std::string name;
    std::string meaning;
    Radial (*of)(const ExactKernel&);
};
const std::vector<NamedQuantity>& softening_quantities();

// softening:n (d^n phi/dr^n), d_soft:n (SWIFT), gfactor:n (GADGET-4).
const std::vector<OrderedFamily>& ordered_families();

// "value|dr|...|dphidh|softening:0..6|d_soft:1..6|gfactor:0..5", for help and errors.
std::string query_names();

// The named quantity of k, exactly. Error naming the name, the order or the
// kernel when it is unknown, out of range or undefined for k.
Radial query(const ExactKernel& k, const std::string& name);

}  // namespace mollify::gen
