// Measuring the double-precision runtime against the exact values: the one
// place that defines the exact reference, the ulp error (SLEEF's countULP),
// the hard-case points and the naive evaluation forms compared against.
// Used by tests/accuracy_test.cpp (bounds asserted), tools/stability_report
// (the report) and bench/kernel_bench.cpp (speed against error).
//
// Links the exact generator core (GMP/MPFR); the runtime itself never does.
#pragma once

#include <mollify/kernel.hpp>

#include <boost/multiprecision/mpfr.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

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

// Points (r, h) where kernels are hard to evaluate, kept as named data
// (CORE-MATH style): 1 - r/h from 1e-1 down to 1e-15, r/h from 1e-1 down to
// 1e-300 and exactly 0, h from 1e-8 to 1e8, plus seeded uniform points.
struct Point {
    double r, h;
    const char* why;  // "edge", "origin", "zero", "h-sweep", "uniform", "far" ...
};
std::vector<Point> hard_points(int uniform_count, std::uint64_t seed);

// Statistics of one (kernel, quantity, evaluation form) over a point set.
struct Stats {
    double max_ulp = 0, rms_ulp = 0;       // over points with |exact| >= 1e-10 max
    double max_scaled = 0;                  // over points with |exact| <  1e-10 max, in ulps of the max
    Point worst{0, 0, ""};                  // argument of max_ulp
    long points = 0, tiny_points = 0;
};

}  // namespace mollify::accuracy
