#include "query.hpp"

#include "error.hpp"
#include "quantities.hpp"
#include "softening.hpp"

#include <mollify/smoothing.hpp>

#include <charconv>
#include <memory>

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

Scaling scaling(const std::string& name, int dim) {
    for (int q = 0; q < table::quantity_count; ++q)
        if (name == table::quantity_names[q]) {
            const auto id = static_cast<table::QuantityId>(q);
            return {detail::scale_power(id, dim), dim == 2 && id == table::QuantityId::potential};
        }
    fail("quantity '" + name + "' has no scaling in h (only the tabulated ones have: value, dr, ..., potential_hess_radial)");
}

namespace {

Real real_of(const Q& q, unsigned bits) {
    Real x(0, bits * 30103 / 100000 + 2);
    mpfr_set_q(x.backend().data(), q.backend().data(), MPFR_RNDN);
    return x;
}

}  // namespace

ExactValue exact_value(const Radial& f, const Q& r, const Q& h, const Scaling& s, const std::string& where) {
    if (r < 0) fail(where + ": r = " + short_string(r) + " must be >= 0 (a radial distance)");
    if (h <= 0) fail(where + ": h = " + short_string(h) + " must be > 0");
    const Q u = r / h;
    const auto form = std::make_shared<const ClosedForm>(f.form_at(u));
    const Q factor = pow(h, s.power);
    // log(h)/(2 pi): the 2D potential's constant (Scaling).
    const Exact shift = s.log_h && h != 1 ? Exact::pi_power(Q(1) / 2, -1) * Exact::log_of(h) : Exact();
    ExactValue v;
    if (form->is_elementary() || u == 0 || u == 1) {  // exact: rational r, or a limit at 0 and 1
        try {
            v.exact = value_at(*form, u) * factor + shift;
        } catch (const Error&) {
            fail(where + " is singular at r = " + short_string(u));
        }
        v.closed_form = v.exact->to_string();
        v.evaluate = [e = *v.exact](unsigned bits) { return e.evaluate(bits); };
        return v;
    }
    v.closed_form = form->to_string_at(u);
    if (factor != 1) v.closed_form = short_string(factor) + " * (" + v.closed_form + ")";
    if (!shift.is_zero()) v.closed_form += " + " + shift.to_string();
    v.evaluate = [form, u, factor, shift](unsigned bits) {
        auto [x, scale] = form->evaluate(real_of(u, bits), bits);
        if (factor != 1) {
            const Real c = real_of(factor, bits);
            x *= c;
            scale *= abs(c);
        }
        if (!shift.is_zero()) {
            const auto [y, t] = shift.evaluate(bits);
            x += y;
            scale += t;
        }
        return std::pair<Real, Real>(x, scale);
    };
    return v;
}

}  // namespace mollify::gen
