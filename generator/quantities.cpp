#include "quantities.hpp"

#include "error.hpp"
#include "potential.hpp"

#include <iterator>

namespace mollify::gen {

namespace {

// f/r: dividing by r flips the parity of the 1D extension.
Radial over_r(const Radial& f) {
    Radial g = f.times(Laurent::monomial(Q(1), -1));
    g.parity = -f.parity;
    return g;
}

Radial hessian_radial(const Radial& d1, const Radial& d2) {
    Radial h = (d2 - over_r(d1)).times(Laurent::monomial(Q(1), -2));
    h.parity = d2.parity;
    return h;
}

}  // namespace

Quantities derive_quantities(const ExactKernel& k) {
    Quantities q;
    q.value = k.W;
    q.dr = k.W.derivative();
    q.d2r = q.dr.derivative();
    q.laplacian = radial_laplacian(k.W, k.dim);
    q.grad_over_r = over_r(q.dr);
    q.hess_radial = hessian_radial(q.dr, q.d2r);
    if (k.claims.no_potential.empty()) {
        q.potential = potential(k.W, k.dim);
        q.dpotential = q.potential->derivative();
        q.dpotential_over_r = over_r(*q.dpotential);
        q.potential_hess_radial = hessian_radial(*q.dpotential, q.dpotential->derivative());
    }
    return q;
}

const std::vector<std::string>& quantity_names() {
    static const std::vector<std::string> names(std::begin(table::quantity_names), std::end(table::quantity_names));
    return names;
}

const Radial& quantity(const ExactKernel& k, const Quantities& q, const std::string& name) {
    if (name == "value") return q.value;
    if (name == "dr") return q.dr;
    if (name == "d2r") return q.d2r;
    if (name == "laplacian") return q.laplacian;
    if (name == "grad_over_r") return q.grad_over_r;
    if (name == "hess_radial") return q.hess_radial;
    const std::optional<Radial>* p = nullptr;
    if (name == "potential") p = &q.potential;
    else if (name == "dpotential") p = &q.dpotential;
    else if (name == "dpotential_over_r") p = &q.dpotential_over_r;
    else if (name == "potential_hess_radial") p = &q.potential_hess_radial;
    else {
        std::string known;
        for (const auto& n : quantity_names()) known += (known.empty() ? "" : ", ") + n;
        fail("unknown quantity '" + name + "' (known: " + known + ")");
    }
    if (!*p) fail("kernel " + spec_string(k.spec) + " in D = " + std::to_string(k.dim) + ": " + k.claims.no_potential);
    return **p;
}

}  // namespace mollify::gen
