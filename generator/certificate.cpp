#include "certificate.hpp"

#include "potential.hpp"

namespace mollify::gen {

namespace {

Certificate equal(std::string what, const Exact& got, const Exact& want) {
    return {std::move(what), got == want, got.to_string() + " vs " + want.to_string()};
}

// One-sided limits of a piecewise form at breakpoint index i (> 0).
std::optional<Exact> left_limit(const Radial& f, std::size_t i) {
    const ClosedForm& form = f.pieces[i - 1];
    if (form.is_elementary()) return form.at(f.breaks[i]);
    if (f.breaks[i] == 1) return value_at_one(form);
    return std::nullopt;
}

std::optional<Exact> right_limit(const Radial& f, std::size_t i) {
    const ClosedForm& form = i + 1 < f.breaks.size() ? f.pieces[i] : f.outside;
    if (form.is_elementary()) return form.at(f.breaks[i]);
    if (f.breaks[i] == 1) return value_at_one(form);
    return std::nullopt;
}

void continuity(std::vector<Certificate>& out, const Radial& f, int up_to, const std::string& name) {
    Radial d = f;
    for (int n = 0; n <= up_to; ++n) {
        for (std::size_t i = 1; i < d.breaks.size(); ++i) {
            const auto l = left_limit(d, i), r = right_limit(d, i);
            const std::string what = name + (n ? "^(" + std::to_string(n) + ")" : "") + " continuous at r = " +
                                     short_string(d.breaks[i]);
            if (!l || !r) {
                out.push_back({what, false, "one-sided limit is infinite or not computable"});
                continue;
            }
            out.push_back(equal(what, *l, *r));
        }
        d = d.derivative();
    }
}

}  // namespace

std::vector<Certificate> certify(const ExactKernel& k, const Quantities& q) {
    std::vector<Certificate> out;
    switch (k.normalised_by) {
        case Normalisation::unit_mass: out.push_back(equal("unit mass", radial_moment(k, 0), Exact(Q(1)))); break;
        case Normalisation::first_derivative:
            out.push_back(equal("int x W dx = -1 (f * W ~ f')", radial_integral(k.W, 1) * Q(2), Exact(Q(-1))));
            break;
        case Normalisation::second_derivative:
            out.push_back(equal("zero mass", radial_integral(k.W, 0) * Q(2), Exact(Q(0))));
            out.push_back(equal("int x^2 W dx = 2 (f * W ~ f'')", radial_integral(k.W, 2) * Q(2), Exact(Q(2))));
            break;
    }
    for (int j = 2; j < k.claims.order; j += 2)
        out.push_back(equal("moment |x|^" + std::to_string(j) + " = 0", radial_moment(k, j), Exact(Q(0))));
    if (k.normalised_by == Normalisation::unit_mass) {
        const Exact next = radial_moment(k, k.claims.order);
        out.push_back({"moment |x|^" + std::to_string(k.claims.order) + " != 0 (order exactly " +
                           std::to_string(k.claims.order) + ")",
                       !next.is_zero(), next.to_string()});
    }
    if (k.claims.smoothness >= 0) continuity(out, k.W, k.claims.smoothness, "W");
    if (q.potential) {
        const Radial residual = radial_laplacian(*q.potential, k.dim) - k.W;
        out.push_back({"Delta phi = W identically", residual.is_zero(), "Delta phi - W on every piece and outside"});
        continuity(out, *q.potential, 1, "phi");
    }
    return out;
}

}  // namespace mollify::gen
