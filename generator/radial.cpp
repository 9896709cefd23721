#include "radial.hpp"

#include "error.hpp"

#include <algorithm>

namespace mollify::gen {

Radial Radial::single(const ClosedForm& f, const Q& support) {
    Radial r;
    r.breaks = {Q(0), support};
    r.pieces = {f};
    return r;
}

std::size_t Radial::piece_index(const Q& r) const {
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i)
        if (r < breaks[i + 1]) return i;
    return pieces.size() - 1;
}

bool Radial::is_elementary() const {
    if (!outside.is_elementary()) return false;
    return std::all_of(pieces.begin(), pieces.end(), [](const ClosedForm& f) { return f.is_elementary(); });
}

bool Radial::is_zero() const {
    return outside.is_zero() &&
           std::all_of(pieces.begin(), pieces.end(), [](const ClosedForm& f) { return f.is_zero(); });
}

Radial Radial::derivative() const {
    Radial d = *this;
    for (auto& p : d.pieces) p = p.derivative();
    d.outside = outside.derivative();
    d.parity = -parity;
    return d;
}

Radial Radial::times(const Laurent& p) const {
    Radial d = *this;
    for (auto& f : d.pieces) f = f * p;
    d.outside = outside * p;
    return d;
}

Radial Radial::operator*(const Exact& c) const {
    Radial d = *this;
    for (auto& f : d.pieces) f = f * c;
    d.outside = outside * c;
    return d;
}

Radial Radial::scaled(const Q& a, int dim) const {
    if (!outside.is_zero()) fail("internal: scaling a radial function with a non-zero exterior");
    Radial d = *this;
    for (auto& b : d.breaks) b *= a;
    const Q inv = Q(1) / a;
    for (auto& f : d.pieces) f = f.scaled_argument(inv) * pow(inv, dim);
    return d;
}

namespace {

Radial combine(const Radial& a, const Radial& b, const Q& sign) {
    std::vector<Q> breaks = a.breaks;
    breaks.insert(breaks.end(), b.breaks.begin(), b.breaks.end());
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    Radial s;
    s.parity = a.parity;
    s.breaks = breaks;
    s.pieces.clear();
    auto piece = [](const Radial& f, const Q& mid) -> ClosedForm {
        return mid < f.support() ? f.pieces[f.piece_index(mid)] : f.outside;
    };
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
        const Q mid = (breaks[i] + breaks[i + 1]) / 2;
        s.pieces.push_back(piece(a, mid) + piece(b, mid) * sign);
    }
    s.outside = a.outside + b.outside * sign;
    return s;
}

}  // namespace

Radial operator+(const Radial& a, const Radial& b) { return combine(a, b, Q(1)); }
Radial operator-(const Radial& a, const Radial& b) { return combine(a, b, Q(-1)); }

bool operator==(const Radial& a, const Radial& b) { return (a - b).is_zero(); }

const ClosedForm& Radial::form_at(const Q& r) const {
    if (r < 0) fail("internal: negative radius");
    return r > support() ? outside : pieces[piece_index(r)];
}

Exact Radial::at(const Q& r) const { return form_at(r).at(r); }

std::pair<Real, Real> Radial::evaluate(const Real& r, unsigned bits) const {
    // The piece is chosen on the exact breakpoints: compare r with each as a
    // rational converted at the working precision.
    const unsigned digits10 = bits * 30103 / 100000 + 2;
    std::size_t i = 0;
    for (; i + 1 < breaks.size(); ++i) {
        Real b(0, digits10);
        mpfr_set_q(b.backend().data(), breaks[i + 1].backend().data(), MPFR_RNDN);
        if (r < b) break;
    }
    Real edge(0, digits10);
    mpfr_set_q(edge.backend().data(), support().backend().data(), MPFR_RNDN);
    if (r > edge) return outside.evaluate(r, bits);
    return pieces[std::min(i, pieces.size() - 1)].evaluate(r, bits);
}

Exact integral(const ClosedForm& f, const Q& a, const Q& b) {
    const ClosedForm F = f.antiderivative();
    return value_at(F, b) - value_at(F, a);
}

Exact radial_integral(const Radial& f, int power) {
    Exact total;
    const Laurent weight = Laurent::monomial(Q(1), power);
    for (std::size_t i = 0; i < f.pieces.size(); ++i)
        total += integral(f.pieces[i] * weight, f.breaks[i], f.breaks[i + 1]);
    return total;
}

std::optional<Exact> value_at_one(const ClosedForm& f) {
    for (const auto& [k, p] : f.terms())
        if (k.basis == Basis::sqrt_power && k.s_power < 0) return std::nullopt;
    return value_at(f, Q(1));
}

Exact sphere_measure(int dim) {
    switch (dim) {
        case 1: return Exact(Q(2));
        case 2: return Exact::pi_power(Q(2), 1);
        case 3: return Exact::pi_power(Q(4), 1);
    }
    fail("dimension " + std::to_string(dim) + " is outside 1..3");
}

}  // namespace mollify::gen
