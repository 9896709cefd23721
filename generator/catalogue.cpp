#include "catalogue.hpp"

#include "error.hpp"
#include "kernel.hpp"

namespace mollify::gen {

std::vector<Spec> default_specs() {
    std::vector<std::string> texts;
    for (int M = 1; M <= 9; ++M)
        for (int order : {2, 4, 6})
            texts.push_back("mollifier:M=" + std::to_string(M) + (order == 2 ? "" : ",order=" + std::to_string(order)));
    for (int k = 0; k <= 4; ++k)
        for (int l = 0; l <= 4; ++l) texts.push_back("wendland:k=" + std::to_string(k) + ",l=" + std::to_string(l));
    for (int k = 1; k <= 2; ++k)
        for (int l = 0; l <= 2; ++l)
            texts.push_back("wendland-missing:k=" + std::to_string(k) + ",l=" + std::to_string(l));
    for (int m : {2, 3}) {
        for (int k = 1; k <= 3; ++k)
            for (int l = 0; l <= 2; ++l)
                texts.push_back("combo:m=" + std::to_string(m) + ",base=wendland:k=" + std::to_string(k) +
                                ",l=" + std::to_string(l));
        for (int M : {4, 9}) texts.push_back("combo:m=" + std::to_string(m) + ",base=mollifier:M=" + std::to_string(M));
    }
    for (const char* c : {"poly6", "spiky", "viscosity", "cubic-spline", "quartic-spline", "quintic-spline", "box", "box-d1", "box-d2"}) texts.push_back(c);
    std::vector<Spec> specs;
    for (const auto& t : texts) specs.push_back(parse_spec(t));
    return specs;
}

bool defined_in(const Spec& s, int dim) {
    if (dim < 1 || dim > 3) return false;
    return !((s.family == Family::viscosity && dim == 1) ||
             ((s.family == Family::box_d1 || s.family == Family::box_d2) && dim != 1));
}

std::vector<CatalogueEntry> expand_dimensions(const std::vector<Spec>& specs) {
    std::vector<CatalogueEntry> out;
    for (const Spec& s : specs)
        for (int dim = 1; dim <= 3; ++dim)
            if (defined_in(s, dim)) out.push_back({s, dim});
    return out;
}

}  // namespace mollify::gen
