// The exact reference of every runtime quantity f_h(r) (MPFR, >= 200 correct
// bits) and the ulp error against it: shared by mollify's own accuracy suite
// (tools/accuracy) and the verification of anyone's kernel (verify.hpp), in
// the exact library mollify::exact.
#pragma once

#include "../kernel.hpp"

#include <mollify/kernel.hpp>

#include <boost/multiprecision/mpfr.hpp>

#include <memory>
#include <string>

namespace mollify::accuracy {

using Real = boost::multiprecision::mpfr_float;

// The exact value of a runtime quantity f_h(r) = h^p f(r/h) (plus log(h)/(2 pi)
// for a 2D potential inside the support), exactly as <mollify/kernel.hpp>
// defines it, from the generator's exact closed forms, evaluated in MPFR with
// at least 200 correct bits (Ziv: precision raised until the error bound,
// from the sum of |terms|, is below 2^-200 relative; near the support edge
// and near roots that takes more working bits).
class Reference {
public:
    Reference(const std::string& spec, int dim);  // Error if the spec is bad
    ~Reference();
    Reference(Reference&&) noexcept;

    int dim() const;
    bool has(QuantityId q) const;  // kernels without a potential lack 4 of the 10
    // r >= 0 and h > 0 exact (doubles or MPFR numbers, e.g. |x| of a vector).
    Real value(QuantityId q, const Real& r, const Real& h) const;
    Real value(QuantityId q, double r, double h) const;
    // r d/dr f_h(r) = h^p q f'(q) (q = r/h; outside the support r G'(r)),
    // to >= 24 correct bits: the change of f_h under a relative perturbation
    // of r, the scale of the intrinsic error metric (tests/accuracy_test.cpp).
    Real slope(QuantityId q, double r, double h) const;
    // max |f| over the support for h = 1 (the scale of "tiny" values).
    double max_abs(QuantityId q) const;
    // Every quantity's max_abs at once: the same numbers, in a fraction of
    // the time of asking for each in turn (the quantities share each point's
    // bases), for callers that want them all.
    void find_all_maxima() const;
    // The exact kernel the values come from.
    const gen::ExactKernel& kernel() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Error of a double result y against the exact x in ulps of x (SLEEF's
// countULP: ulp(x) = 2^(e-52) for 2^e <= |x| < 2^(e+1), floored at the
// smallest normal; 0 when both are 0; +inf for NaN or an inf result).
double ulp_error(double y, const Real& x);
// |y - x| in ulps of a scale (the quantity's maximum): for tiny exact values.
double scaled_error(double y, const Real& x, double scale);

}  // namespace mollify::accuracy
