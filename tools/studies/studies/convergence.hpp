// Convergence rates: the a of Q ~ C eps^a, by least squares on
// (log eps, log Q) as Franz does (§6.2, "linear regression"), with Eigen's
// QR solve of the 2-column system.
#pragma once

#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>

namespace mollify::sph {

struct Rate {
    double rate = 0;      // a
    double constant = 0;  // C
    double residual = 0;  // RMS of the log residuals: how straight the line is
};

inline Rate convergence_rate(std::span<const double> eps, std::span<const double> error) {
    if (eps.size() != error.size()) fail("convergence_rate: " + std::to_string(eps.size()) + " eps but " +
                                         std::to_string(error.size()) + " errors");
    if (eps.size() < 2) fail("convergence_rate: needs at least 2 points, got " + std::to_string(eps.size()));
    const auto n = static_cast<Eigen::Index>(eps.size());
    Eigen::MatrixXd a(n, 2);
    Eigen::VectorXd b(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        const double e = eps[static_cast<std::size_t>(i)], q = error[static_cast<std::size_t>(i)];
        if (!(e > 0) || !(q > 0) || !std::isfinite(e) || !std::isfinite(q))
            fail("convergence_rate: point (eps, Q) = (" + mollify::detail::show(e) + ", " + mollify::detail::show(q) +
                 ") is not positive and finite");
        a(i, 0) = std::log(e);
        a(i, 1) = 1;
        b(i) = std::log(q);
    }
    // One eps repeated leaves the slope undetermined (QR would return some
    // solution of the rank-1 system: a rate that means nothing).
    if (std::all_of(eps.begin(), eps.end(), [&](double e) { return e == eps.front(); }))
        fail("convergence_rate: every point has eps = " + mollify::detail::show(eps.front()) + "; a rate needs two distinct eps");
    const Eigen::Vector2d x = a.colPivHouseholderQr().solve(b);
    const Eigen::VectorXd r = a * x - b;
    return {x(0), std::exp(x(1)), std::sqrt(r.squaredNorm() / static_cast<double>(n))};
}

}  // namespace mollify::sph
