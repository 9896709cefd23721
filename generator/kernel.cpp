#include "kernel.hpp"

#include "anderson.hpp"
#include "classic.hpp"
#include "error.hpp"
#include "vandermonde.hpp"
#include "wendland.hpp"

#include <algorithm>

namespace mollify::gen {

namespace {

Exact unit_mass_normalisation(const Radial& shape, int dim) {
    return (sphere_measure(dim) * radial_integral(shape, dim - 1)).inverse();
}

void finish(ExactKernel& k) { k.W = k.shape * k.normalisation; }

ExactKernel mollifier(const Spec& s, int dim) {
    ExactKernel k;
    const ExponentMethod e = exponent_method(s.M, s.order, dim);
    Laurent shape;
    for (std::size_t j = 0; j < e.alpha.size(); ++j) shape += one_minus_r2_power(s.M + static_cast<int>(j)) * e.alpha[j];
    k.shape = Radial::single(shape);
    k.normalisation = e.normalisation;
    k.alpha = e.alpha;
    k.claims.smoothness = s.M - 1;
    k.claims.order = s.order;
    k.source = s.order == 2 ? "Anderson 2014, eq. (3)" : "Anderson 2014, eqs. (11)-(12), exponent method";
    return k;
}

ExactKernel wendland(const Spec& s, int dim) {
    ExactKernel k;
    k.shape = Radial::single(wendland_shape(dim, s.k, s.l));
    k.normalisation = unit_mass_normalisation(k.shape, dim);
    k.claims.smoothness = wendland_edge_power(dim, s.k, s.l) - 1;  // Franz Cor. 4.37
    k.source = "Franz 2019, Lemma 4.36 / Cor. 4.39 (psi_{d,k,l}, d = D)";
    return k;
}

ExactKernel missing_wendland(const Spec& s, int dim) {
    ExactKernel k;
    k.shape = Radial::single(missing_wendland_shape(dim, s.k, s.l));
    k.normalisation = unit_mass_normalisation(k.shape, dim);
    // psi ~ (1-r)^(mu+l+k+1/2) at the edge, mu = floor((d+1)/2) + k + 1.
    k.claims.smoothness = (dim + 1) / 2 + 2 * s.k + s.l + 1;
    k.source = "Franz 2019, §4.3.3, Thm. 4.65 (psi_{d,k+1/2,l}, d = D)";
    return k;
}

ExactKernel classic(const Spec& s, int dim) {
    ExactKernel k;
    k.shape = classic_shape(s.family);
    switch (s.family) {
        case Family::poly6: k.claims.smoothness = 2; k.source = "Mueller et al. 2003 (seed 002 eq. (6))"; break;
        case Family::spiky: k.claims.smoothness = 2; k.source = "Desbrun & Cani 1996, Mueller et al. 2003 (seed 002 eq. (7))"; break;
        case Family::viscosity:
            if (dim == 1) fail("kernel viscosity is not integrable in dimension 1 (its 1/(2r) term); use D = 2 or 3");
            k.claims.smoothness = 2;
            k.source = "Mueller et al. 2003 (seed 002 ch. 1)";
            break;
        case Family::cubic_spline: k.claims.smoothness = 2; k.source = "Monaghan & Lattanzio 1985 (M4), support radius 1"; break;
        case Family::quartic_spline:  // M_n is C^(n-2) (Schoenberg 1946)
            k.claims.smoothness = 3;
            k.source = "Schoenberg 1946, Monaghan 2005 sec. 4 (M5), support radius 1";
            break;
        case Family::quintic_spline:
            k.claims.smoothness = 4;
            k.source = "Schoenberg 1946, Monaghan 2005 sec. 4 (M6), support radius 1";
            break;
        case Family::box:
            k.claims.smoothness = -1;
            k.source = "Belley 2007, eq. (12)";
            break;
        case Family::box_d1:
        case Family::box_d2:
            if (dim != 1)
                fail("kernel " + family_name(s.family) + " is one-dimensional (Belley 2007); dimension " + std::to_string(dim) +
                     " is not available");
            k.claims.smoothness = -1;
            k.source = s.family == Family::box_d1 ? "Belley 2007, eq. (16)" : "Belley 2007, eq. (20)";
            k.claims.no_potential = family_name(s.family) + " is a derivative estimator (zero mass); it has no Poisson potential";
            break;
        default: fail("internal: not a classic kernel");
    }
    if (s.family == Family::box_d1) {
        k.normalised_by = Normalisation::first_derivative;  // 2 int_0^1 r W = -1
        k.normalisation = Exact(Q(-1, 2)) * radial_integral(k.shape, 1).inverse();
        k.claims.order = 0;
    } else if (s.family == Family::box_d2) {
        k.normalised_by = Normalisation::second_derivative;  // 2 int_0^1 r^2 W = 2
        k.normalisation = radial_integral(k.shape, 2).inverse();
        k.claims.order = 0;
    } else {
        k.normalisation = unit_mass_normalisation(k.shape, dim);
    }
    return k;
}

ExactKernel combo(const Spec& s, int dim) {
    ExactKernel k;
    k.base = std::make_shared<const ExactKernel>(make_kernel(*s.base, dim));
    const ExactKernel& base = *k.base;
    const std::vector<Q> a = radii(s);
    k.weights = vandermonde_weights(a);
    k.shape.breaks = {Q(0), Q(1)};
    k.shape.pieces = {ClosedForm()};
    for (std::size_t j = 0; j < a.size(); ++j) k.shape = k.shape + base.shape.scaled(a[j], dim) * Exact(k.weights[j]);
    k.normalisation = base.normalisation;
    k.claims.smoothness = base.claims.smoothness;
    const int m = static_cast<int>(s.radii.size());
    k.claims.order = base.claims.order == 2 ? 2 * m : std::max(2 * m, base.claims.order);
    k.claims.no_potential = base.claims.no_potential;
    k.source = "Franz 2019, (4.17) and Prop. 4.24, base " + spec_string(*s.base);
    return k;
}

}  // namespace

ExactKernel make_kernel(const Spec& spec, int dim) {
    if (dim < 1 || dim > 3) fail("dimension " + std::to_string(dim) + " is outside 1..3");
    ExactKernel k;
    switch (spec.family) {
        case Family::mollifier: k = mollifier(spec, dim); break;
        case Family::wendland: k = wendland(spec, dim); break;
        case Family::wendland_missing: k = missing_wendland(spec, dim); break;
        case Family::combo: k = combo(spec, dim); break;
        default: k = classic(spec, dim); break;
    }
    k.spec = spec;
    k.dim = dim;
    finish(k);
    return k;
}

std::vector<ComboTerm> combo_terms(const ExactKernel& k) {
    if (k.spec.family != Family::combo) return {};
    const ExactKernel& base = *k.base;
    const std::vector<Q> a = radii(k.spec);
    std::vector<ComboTerm> out;
    for (std::size_t j = 0; j < a.size(); ++j) {
        ExactKernel psi = base;
        psi.shape = base.shape.scaled(a[j], k.dim);
        psi.W = base.W.scaled(a[j], k.dim);
        out.push_back({k.weights[j], std::move(psi)});
    }
    return out;
}

Exact radial_moment(const ExactKernel& k, int p) {
    return sphere_measure(k.dim) * radial_integral(k.W, k.dim - 1 + p);
}

}  // namespace mollify::gen
