#include "query.hpp"

#include "error.hpp"
#include "quantities.hpp"
#include "softening.hpp"

#include <charconv>

namespace mollify::gen {

const std::vector<OrderedFamily>& ordered_families() {
    static const std::vector<OrderedFamily> families{
        {"softening", 0, max_softening_order, "d^n phi/dr^n, the n-th radial derivative of the potential",
         softening_derivatives},
        {"d_soft", 1, max_d_soft, "SWIFT's D_soft_n(u), u = r/H (softening.hpp)", swift_d_soft},
        {"gfactor", 0, max_gfactor, "GADGET-4's g-factor fac_n(u), u = r/h (softening.hpp)", gadget_gfactors},
    };
    return families;
}

const std::vector<NamedQuantity>& softening_quantities() {
    static const std::vector<NamedQuantity> named{
        {"dphidh", "d/dh of phi(r/h)/h at h = 1, Phantom's dphidh (softening.hpp)", softening_h_derivative},
    };
    return named;
}

std::string query_names() {
    std::string s;
    for (const auto& n : quantity_names()) s += (s.empty() ? "" : "|") + n;
    for (const auto& q : softening_quantities()) s += "|" + q.name;
    for (const auto& f : ordered_families())
        s += "|" + f.name + ":" + std::to_string(f.low) + ".." + std::to_string(f.high);
    return s;
}

Radial query(const ExactKernel& k, const std::string& name) {
    const auto colon = name.find(':');
    if (colon == std::string::npos) {
        for (const auto& n : quantity_names())
            if (n == name) return quantity(k, derive_quantities(k), name);
        for (const auto& q : softening_quantities())
            if (q.name == name) return q.of(k);
        fail("unknown quantity '" + name + "' (known: " + query_names() + ")");
    }
    const std::string family = name.substr(0, colon), digits = name.substr(colon + 1);
    int n = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
    if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size())
        fail("quantity '" + name + "': order '" + digits + "' is not an integer");
    for (const auto& f : ordered_families())
        if (f.name == family) return f.up_to(k, n).back();
    fail("unknown quantity '" + name + "' (known: " + query_names() + ")");
}

}  // namespace mollify::gen
