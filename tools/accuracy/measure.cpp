// Error statistics against the exact values. This TU looks kernels up by
// name (mollify::kernel), so it instantiates every emitted table once
// (about a minute to compile); everything else here is cheap.
#include "measure.hpp"

#include <mollify/kernel.hpp>

#include <cmath>
#include <numbers>
#include <utility>

namespace mollify::accuracy {

namespace {

// max |f_h| over the support: f_h = h^p f(r/h), and a 2D potential adds
// log(h)/(2 pi) (the constant that keeps it equal to the Green's function).
double scale_at(const Reference& ref, QuantityId q, double h) {
    double s = ref.max_abs(q) * std::pow(h, detail::scale_power(q, ref.dim()));
    if (q == QuantityId::potential && ref.dim() == 2) s += std::abs(std::log(h)) / (2 * std::numbers::pi);
    return s;
}

}  // namespace

ExactValues exact_values(const Reference& ref, QuantityId q, const std::vector<Point>& points) {
    ExactValues e;
    e.values.reserve(points.size());
    for (const Point& p : points) {
        e.values.push_back(ref.value(q, p.r, p.h));
        e.scales.push_back(scale_at(ref, q, p.h));
        e.thresholds.push_back(tiny_fraction * e.scales.back());
    }
    return e;
}

Stats statistics(const std::vector<double>& y, const ExactValues& exact, const std::vector<Point>& points) {
    Stats s;
    double sum_squares = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Real& x = exact.values[i];
        if (abs(x) >= exact.thresholds[i]) {
            const double u = ulp_error(y[i], x);
            sum_squares += u * u;
            ++s.points;
            // The first point of the largest error (a NaN result counts as +inf ulps).
            if (u > s.max_ulp || s.points == 1) {
                s.max_ulp = u;
                s.worst = points[i];
            }
        } else {
            s.max_scaled = std::max(s.max_scaled, scaled_error(y[i], x, exact.scales[i]));
            ++s.tiny_points;
        }
    }
    if (s.points > 0) s.rms_ulp = std::sqrt(sum_squares / static_cast<double>(s.points));
    return s;
}

Stats measure(const ExactValues& exact, const Evaluation& f, const std::vector<Point>& points) {
    std::vector<double> y;
    y.reserve(points.size());
    for (const Point& p : points) y.push_back(f(p.r, p.h));
    return statistics(y, exact, points);
}

Stats measure(const Reference& ref, QuantityId q, const Evaluation& f, const std::vector<Point>& points) {
    return measure(exact_values(ref, q, points), f, points);
}

Evaluation evaluation(const std::string& spec, int dim, QuantityId q, Form form) {
    if (form == Form::mollify) {
        const Kernel k = kernel(spec, dim);
        return [k, q](double r, double h) { return k(q, r, h); };
    }
    const NaiveAny f(naive_polynomial(spec, dim, q));
    if (form == Form::pow)
        return [f](double r, double h) { return naive_at<Form::pow>(f, r, NaiveScale(h, f.scale_power)); };
    return [f](double r, double h) { return naive_at<Form::expanded>(f, r, NaiveScale(h, f.scale_power)); };
}

Stats measure(const std::string& spec, int dim, QuantityId q, Form form, const std::vector<Point>& points) {
    const Reference ref(spec, dim);
    return measure(ref, q, evaluation(spec, dim, q, form), points);
}

}  // namespace mollify::accuracy
