// Piecewise radial functions f(r), r >= 0: closed-form pieces between exact
// breakpoints 0 = b_0 < b_1 < ... < b_n (the support radius), and a closed
// form outside the support (0 for kernels, the Green's function for
// potentials). Piece i covers [b_i, b_{i+1}); the last piece is closed.
#pragma once

#include "closed_form.hpp"

#include <optional>
#include <vector>

namespace mollify::gen {

struct Radial {
    std::vector<Q> breaks{Q(0), Q(1)};
    std::vector<ClosedForm> pieces{ClosedForm()};
    ClosedForm outside;
    // Extension to x < 0 in one dimension: +1 even (all radial kernels), -1 odd
    // (Belley's first-derivative kernel).
    int parity = 1;

    static Radial single(const ClosedForm& f, const Q& support = Q(1));
    const Q& support() const { return breaks.back(); }
    std::size_t piece_index(const Q& r) const;  // r < support
    bool is_elementary() const;
    bool is_zero() const;

    Radial derivative() const;
    Radial times(const Laurent& p) const;  // outside multiplied too
    Radial operator*(const Exact& c) const;
    // a^-dim f(r / a): the kernel scaled to support a * support (Franz (4.17)).
    Radial scaled(const Q& a, int dim) const;
    friend Radial operator+(const Radial& a, const Radial& b);  // merged breakpoints
    friend Radial operator-(const Radial& a, const Radial& b);
    friend bool operator==(const Radial& a, const Radial& b);

    // Exact value at rational r >= 0 (elementary pieces only); nullopt where
    // a piece is singular (e.g. r = 0 for a Laurent term).
    Exact at(const Q& r) const;
    const ClosedForm& form_at(const Q& r) const;
    std::pair<Real, Real> evaluate(const Real& r, unsigned bits) const;
};

// int_a^b f(r) dr for one closed form on [a, b] (a, b rational, 0 <= a < b),
// from its antiderivative (limits at 0 and 1 for the sqrt/arcsech/arcsin
// forms, which are only exact at those two points).
Exact integral(const ClosedForm& f, const Q& a, const Q& b);
// int_0^support r^power f(r) dr over all pieces.
Exact radial_integral(const Radial& f, int power);
// Value of a closed form at r = 1 when it extends continuously there
// (no negative powers of S); nullopt when it blows up.
std::optional<Exact> value_at_one(const ClosedForm& f);

// Surface measure of the unit sphere in R^dim: 2, 2 pi, 4 pi.
Exact sphere_measure(int dim);

}  // namespace mollify::gen
