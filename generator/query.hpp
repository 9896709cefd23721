// Every quantity a user can ask for by name (mollify-gen value --quantity),
// in one list: the tabulated quantities (table::quantity_names, quantities.hpp)
// and the softening families NAME:n of softening.hpp.
#pragma once

#include "kernel.hpp"
#include "rounding.hpp"

#include <optional>
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

// How a tabulated quantity scales with h (mollify's runtime, smoothing.hpp):
// f_h(r) = h^power f(r/h), plus log(h)/(2 pi) for the 2D potential, which
// keeps it the Green's function log(r)/(2 pi) outside the support. Error
// naming a quantity that has no h (the softening families, dphidh).
struct Scaling {
    int power = 0;
    bool log_h = false;
};
Scaling scaling(const std::string& name, int dim);

// One value of a quantity f (`mollify-gen value`, the Python package's
// mollify.exact.value): exact where it is a constant of exact.hpp's form (an
// elementary piece at rational r, or a limit at 0 or 1), else the closed
// form at r; an enclosure at any precision either way, for correct rounding.
struct ExactValue {
    std::optional<Exact> exact;
    std::string closed_form;  // for people: Exact::to_string or the closed form at r
    Evaluator evaluate;       // value and error scale at `bits` (rounding.hpp)
};

// f_h(r) for rational r >= 0 and h > 0 (h = 1: f(r) itself, any quantity).
// Error naming `where` and r where f is singular there.
ExactValue exact_value(const Radial& f, const Q& r, const Q& h, const Scaling& s, const std::string& where);

}  // namespace mollify::gen
