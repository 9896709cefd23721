#include "softening_certificate.hpp"

#include "error.hpp"
#include "softening.hpp"

#include <algorithm>

namespace mollify::gen {

namespace {

// value_at takes the limit at r = 1 of the sqrt/arcsech/arcsin forms of the
// missing Wendland functions and fails where a negative power of S makes the
// one-sided limit infinite.
std::optional<Exact> limit(const ClosedForm& f, const Q& r) {
    try {
        return value_at(f, r);
    } catch (const Error&) {
        return std::nullopt;
    }
}

std::string text(const std::optional<Exact>& v) { return v ? v->to_string() : "infinite"; }

}  // namespace

int finite_at_origin(const std::vector<Radial>& f) {
    int n = -1;
    for (const Radial& g : f) {
        if (!limit(g.pieces.front(), Q(0))) break;
        ++n;
    }
    return n;
}

std::string join_name(const Join& j) {
    return "phi^(" + std::to_string(j.order) + ") at r = " + short_string(j.at) +
           (j.edge ? " (support edge, against the Green's function)" : "");
}

SofteningSmoothness softening_smoothness(const ExactKernel& k, const std::vector<Radial>& derivatives) {
    SofteningSmoothness s;
    s.guaranteed = std::min(k.claims.smoothness + 2, max_softening_order);
    const Radial& phi = derivatives.front();
    for (std::size_t i = 1; i < phi.breaks.size(); ++i)
        for (std::size_t n = 0; n < derivatives.size(); ++n) {
            const Radial& d = derivatives[n];
            Join j;
            j.order = static_cast<int>(n);
            j.at = d.breaks[i];
            j.edge = i + 1 == d.breaks.size();
            j.left = limit(d.pieces[i - 1], j.at);
            j.right = limit(j.edge ? d.outside : d.pieces[i], j.at);
            s.joins.push_back(std::move(j));
        }
    for (const Join& j : s.joins) {
        if (!j.edge) continue;
        if (!j.continuous()) break;
        s.continuous_at_edge = j.order;
    }
    return s;
}

std::vector<Certificate> softening_certificates(const SofteningSmoothness& s) {
    std::vector<Certificate> out;
    for (const Join& j : s.joins)
        if (j.order <= s.guaranteed)
            out.push_back({join_name(j) + " continuous", j.continuous(), text(j.left) + " vs " + text(j.right)});
    return out;
}

std::vector<Certificate> softening_certificates(const ExactKernel& k) {
    return softening_certificates(softening_smoothness(k, softening_derivatives(k)));
}

Softening certified_softening(const ExactKernel& k) {
    Softening s;
    s.derivatives = softening_derivatives(k);
    s.smoothness = softening_smoothness(k, s.derivatives);
    for (const Certificate& c : softening_certificates(s.smoothness))
        if (!c.passed)
            fail("kernel " + spec_string(k.spec) + " in D = " + std::to_string(k.dim) + ": certificate failed: " +
                 c.what + " [" + c.detail + "]");
    if (k.dim == 3) s.multipole = multipole_factors(k, max_softening_order - 1);
    return s;
}

}  // namespace mollify::gen
