// Closed forms in r: sums of Laurent polynomials times a basis function
//   1, S(r)^j (S = sqrt(1 - r^2), j odd), L(r) = log((1 + S)/r) = arcsech r,
//   log r, A(r) = arcsin r,
// each term carrying an exact constant factor pi^e log(p). Polynomial kernels
// use only the basis 1; missing Wendland functions (Franz §4.3.3) need S and
// L, their potentials also arcsin; 2D potentials need log r. Closed under
// d/dr, and under antiderivatives as far as mollify needs them.
#pragma once

#include "exact.hpp"
#include "laurent.hpp"

#include <mollify/table.hpp>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mollify::gen {

// The basis functions are the tables' (one definition, table.hpp).
using Basis = mollify::table::Basis;

struct TermKey {
    Basis basis = Basis::one;
    int s_power = 0;  // for Basis::sqrt_power: the odd power j of S
    Atom factor;      // pi^e log(p)
    auto operator<=>(const TermKey&) const = default;
};

// The values at one r > 0 that closed forms' terms multiply (r^n, S^j,
// arcsech r, log r, arcsin r, pi^e, log p), each computed on first use and
// kept: f and f' evaluated at the same point share them (MPFR's log and
// asin at 200 bits were most of `mollify-gen emit`'s time).
class PointValues {
public:
    PointValues(const Real& r, unsigned bits);
    // At a rational r (rounded to `bits`, as Real(r) would be): the basis
    // functions there are then taken from, or added to, one table per run
    // (closed_form.cpp), since the Taylor pieces of every quantity and
    // dimension of a missing Wendland function sample the same points.
    PointValues(const Q& r, unsigned bits);
    unsigned digits10() const { return digits10_; }
    const Real& power_of_r(int n);
    const Real& basis(Basis b, int s_power);
    const Real& pi_power(int e);
    const Real& log_of(int p);
    struct Shared;  // the run's table entry of a rational r (closed_form.cpp)

private:
    const Real& S();
    Real fresh() const;  // 0 at the point's precision
    unsigned digits10_;
    Real r_;
    std::optional<Real> s_;
    std::map<int, Real> r_powers_;
    std::map<std::pair<Basis, int>, Real> bases_;
    Shared* shared_ = nullptr;
    // The run's table's values this point has read (a few): each asked again
    // without the table's lock (f and f' at 129 points per Taylor piece ask
    // once per term).
    std::vector<std::pair<std::pair<Basis, int>, const Real*>> seen_;
};

class ClosedForm {
public:
    ClosedForm() = default;
    ClosedForm(const Laurent& p);  // NOLINT: polynomials are closed forms
    ClosedForm(const Laurent& p, const TermKey& key);
    static ClosedForm constant(const Exact& c);

    bool is_zero() const { return terms_.empty(); }
    const std::map<TermKey, Laurent>& terms() const { return terms_; }
    bool is_elementary() const;  // only basis 1 and log r: exact at rational r
    bool has_only_basis_one() const;
    // The Laurent polynomial when the form is q * pi^e * p(r) (basis 1, one factor).
    bool single_polynomial(Laurent* p, Atom* factor) const;

    ClosedForm& operator+=(const ClosedForm& o);
    ClosedForm& operator-=(const ClosedForm& o);
    friend ClosedForm operator+(ClosedForm a, const ClosedForm& b) { return a += b; }
    friend ClosedForm operator-(ClosedForm a, const ClosedForm& b) { return a -= b; }
    friend ClosedForm operator*(const ClosedForm& a, const Exact& c);
    friend ClosedForm operator*(const ClosedForm& a, const Laurent& p);
    friend ClosedForm operator*(const ClosedForm& a, const Q& q) { return a * Exact(q); }
    friend bool operator==(const ClosedForm& a, const ClosedForm& b) { return a.terms_ == b.terms_; }

    ClosedForm derivative() const;
    // An antiderivative; Error for the two integrands outside the closed forms
    // (arcsech(r)/r and arcsin(r)/r) and for log(r)/r.
    ClosedForm antiderivative() const;
    ClosedForm scaled_argument(const Q& s) const;  // f(s r), basis 1 only
    // Exact value at rational r > 0 (or r = 0 when finite); elementary only.
    Exact at(const Q& r) const;
    // Value at r in MPFR, and the sum of |terms| (error bound scale).
    std::pair<Real, Real> evaluate(const Real& r, unsigned bits) const;
    std::pair<Real, Real> evaluate(PointValues& at) const;
    // Exact closed form at rational r for people, any basis.
    std::string to_string_at(const Q& r) const;

    void canonicalise();

private:
    std::map<TermKey, Laurent> terms_;
};

// A closed form prepared for evaluation at many points at one precision
// (a sampled scale takes 257): its rational coefficients converted to MPFR
// once, each term's Laurent polynomial by Horner's rule, r^low times
// sum c_n r^(n-low), then times its constant and basis function. Not the
// same rounding as ClosedForm::evaluate's monomials: both are within a few
// ulps of the working precision of the sum of |terms|.
class PreparedForm {
public:
    PreparedForm(const ClosedForm& f, unsigned bits);
    Real value(PointValues& at) const;

private:
    struct Term {
        TermKey key;
        int low;
        std::vector<Real> c;  // c_low .. c_high
    };
    unsigned digits10_;
    std::vector<Term> terms_;
};

// Value at rational r including the endpoints r = 0 and r = 1 of the
// sqrt/arcsech/arcsin forms, where it is a limit (series at 0; S = L = 0,
// arcsin 1 = pi/2 at 1). Error where the form is singular or irrational.
Exact value_at(const ClosedForm& f, const Q& r);
Exact limit_at_zero(const ClosedForm& f);

// f = c g with c = q pi^e, q and e those of f's first term's lowest
// coefficient (g's is 1): a kernel's quantities in 1, 2 and 3 dimensions
// differ by their normalisation, and the generator's series and Taylor
// pieces of f are c times g's (made once per run: centred_series.hpp,
// edge_series.hpp, series.hpp). f must not be zero.
std::pair<Exact, ClosedForm> normalised(const ClosedForm& f);

}  // namespace mollify::gen
