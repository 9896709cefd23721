#include "verify/compared.hpp"
#include "verify/ulps.hpp"

#include "error.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <set>
#include <tuple>
#include <utility>

namespace mollify::verify {

namespace {

using detail::Compared;

std::string argument(double r, double h) {
    char b[96];
    std::snprintf(b, sizeof b, "(r = %.17g, h = %.17g)", r, h);
    return b;
}

Compared judge(const detail::Setup& s, std::size_t i, Sample a, double got) {
    if (!std::isfinite(a.r) || a.r < 0 || !std::isfinite(a.h) || a.h <= 0)
        fail("sample " + std::to_string(i) + " " + argument(a.r, a.h) + ": r must be finite and >= 0, h finite and > 0");
    Compared c{a.r, a.h, got, detail::exact(s, a.r, a.h), 0, 0, 0, 0, 0};
    c.exact_d = static_cast<double>(c.exact);
    c.q = a.r / static_cast<double>(detail::support_of(s, a.h));
    c.magnitude = detail::magnitude(s, a.h);
    c.floor = 1e-10 * c.magnitude;
    // A 2D potential is phi(r/H) + log(H)/(2 pi): where the two cancel (its
    // root) every evaluator errs by an ulp of the terms, so its error is
    // measured in ulps of at least |log(H)|/(2 pi) (the accuracy suite's
    // intrinsic metric, README "Runtime accuracy").
    if (s.id == table::QuantityId::potential && s.dim == 2)
        c.floor = std::max(c.floor, std::abs(std::log(static_cast<double>(detail::support_of(s, a.h))) / (2 * M_PI) *
                                             static_cast<double>(s.value_scale_real)));
    c.ulps = detail::ulps(got, c.exact, c.floor, s.single);
    return c;
}

// How many of the hard points are among the samples, bit for bit (each
// distinct hard point once): the few hundred hard points in a set, the
// samples (up to max_uniform_points more) looked up in it, not stored.
std::pair<std::size_t, std::size_t> hard_points_among(std::span<const Sample> samples, const std::vector<Sample>& hard) {
    auto bits = [](const Sample& a) { return std::pair{std::bit_cast<std::uint64_t>(a.r), std::bit_cast<std::uint64_t>(a.h)}; };
    std::set<std::pair<std::uint64_t, std::uint64_t>> distinct, found;
    for (const Sample& a : hard) distinct.insert(bits(a));
    for (const Sample& a : samples)
        if (distinct.count(bits(a))) found.insert(bits(a));
    return {distinct.size(), found.size()};
}

}  // namespace

Report compare(std::string_view spec, int dim, Quantity quantity, std::span<const Sample> samples,
               std::span<const double> values, const Options& options) {
    if (samples.size() != values.size())
        fail(std::to_string(values.size()) + " values for " + std::to_string(samples.size()) + " samples");
    const detail::Setup s = detail::setup(spec, dim, quantity, options);
    std::vector<Compared> points;
    points.reserve(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) points.push_back(judge(s, i, samples[i], values[i]));

    Report r;
    r.spec = s.spec;
    r.dim = dim;
    r.quantity = quantity;
    r.convention = s.convention->target;
    r.bound = options.ulps;
    r.float_ulps = s.single;
    r.points = points.size();
    double sum = 0;
    std::size_t finite = 0;
    for (const Compared& p : points) {
        r.max_ulps = std::max(r.max_ulps, p.ulps);
        if (std::isfinite(p.ulps)) sum += p.ulps * p.ulps, ++finite;
    }
    r.rms_ulps = finite ? std::sqrt(sum / static_cast<double>(finite)) : 0;
    std::vector<std::size_t> order(points.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    const std::size_t shown = std::min<std::size_t>(5, order.size());
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(shown), order.end(),
                      [&](std::size_t a, std::size_t b) { return points[a].ulps > points[b].ulps; });
    for (std::size_t k = 0; k < shown; ++k) {
        const Compared& p = points[order[k]];
        r.worst.push_back({p.r, p.h, p.got, p.exact_d, p.ulps});
    }
    r.diagnosis = detail::diagnose(s, points, options.ulps);
    std::tie(r.hard_points, r.hard_points_compared) = hard_points_among(samples, detail::hard_samples(s));
    return r;
}

Report verify(const std::function<double(double r, double h)>& f, std::string_view spec, int dim, Quantity quantity,
              const Options& options) {
    const std::vector<Sample> at = samples(spec, dim, quantity, options);
    std::vector<double> values;
    values.reserve(at.size());
    for (const Sample& a : at) values.push_back(f(a.r, a.h));
    return compare(spec, dim, quantity, at, values, options);
}

}  // namespace mollify::verify
