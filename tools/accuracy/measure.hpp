// Error statistics of one evaluation form of one kernel quantity against
// the exact values (Reference), in ulps (ulp_error): the numbers of the
// stability report and of the benchmark's error counters.
#pragma once

#include "accuracy.hpp"
#include "naive.hpp"

#include <functional>
#include <string>
#include <vector>

namespace mollify::accuracy {

// A double evaluation f_h(r) of some form (the runtime, a naive form, ...).
using Evaluation = std::function<double(double r, double h)>;

// Values with |exact| below this fraction of the quantity's maximum (at
// that h) count as tiny: their error is reported in ulps of the maximum.
inline constexpr double tiny_fraction = 1e-10;

// The exact values at the points, computed once and shared by every form.
struct ExactValues {
    std::vector<Real> values;
    std::vector<double> thresholds;  // tiny_fraction * max |f_h| per point
    std::vector<double> scales;      // max |f_h| per point
};
ExactValues exact_values(const Reference& ref, QuantityId q, const std::vector<Point>& points);

// Statistics of results y[i] against the exact values.
Stats statistics(const std::vector<double>& y, const ExactValues& exact, const std::vector<Point>& points);

// An evaluation measured at the points.
Stats measure(const Reference& ref, QuantityId q, const Evaluation& f, const std::vector<Point>& points);
Stats measure(const ExactValues& exact, const Evaluation& f, const std::vector<Point>& points);

// A form compiled into this library: mollify's run-time kernel, or a naive
// form (value and grad_over_r of polynomial kernels; Error otherwise).
Evaluation evaluation(const std::string& spec, int dim, QuantityId q, Form form);

// The whole measurement in one call.
Stats measure(const std::string& spec, int dim, QuantityId q, Form form, const std::vector<Point>& points);

}  // namespace mollify::accuracy
