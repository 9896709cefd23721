// The treecode's parameters and the accuracy knob: a target relative error
// in, an opening parameter theta and an order p out.
//
// The far-field truncation error of one accepted cell is bounded by
// (multipole.hpp) sum|q| theta^(p+1)/(r (1 - theta)) for the potential, and
// about (p + 2) times that over r (1 - theta) for the field. These worst
// cases (every source on the cell's sphere, in line with the target)
// overestimate the error of a whole evaluation by orders of magnitude: most
// accepted cells lie well inside the theta limit, so the measured error
// falls like (alpha theta)^(p+1) with alpha < 1. The knob uses that fitted
// form,
//     relative L2 field error ~ C (alpha theta)^(p+1),
// alpha and C calibrated by measurement (calibration below), and picks,
// among theta in {0.3, 0.4, ..., 0.8}, the cheapest (theta, p) meeting the
// target by a cost model fitted to measured times (cost below).
// tests/poisson_free_test.cpp (AccuracyKnob) checks the achieved error on
// positive and on neutral charges.
#pragma once

#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/poisson/multipole.hpp>
#include <mollify/smoothing.hpp>

#include <cmath>
#include <limits>
#include <string>

namespace mollify::poisson {

struct TreeOptions {
    double theta = 0.5;  // opening parameter: a cell is expanded when rho_c / R < theta
    int order = 6;       // multipole order p
    // At most this many sources in a leaf. 128: uniform sources in 3D fill
    // octree boxes with N/8^level sources, and 128 splits every level above
    // ~50 per leaf (N = 2e5: 49, 1e6: 31, 1e5: 24, 1e4: 20), where 256 left
    // 244 per leaf at N = 1e6 (2.4x slower there, the same tree at 2e5).
    int leaf_size = 128;

    void check() const {
        if (!(theta > 0 && theta < 1))
            fail("opening parameter theta = " + mollify::detail::show(theta) +
                 " is not in (0, 1) (the multipole series converges only for rho/R < 1)");
        check_order(order);
        if (leaf_size < 1) fail("tree leaf size " + std::to_string(leaf_size) + " is not >= 1");
    }
};

namespace detail {

// Fit of the relative L2 field error against direct summation over
// theta in {0.3, ..., 0.8}, p = 2..20, on NEUTRAL charges (uniform in
// [-0.5, 0.5]: the far field cancels, so the same absolute truncation error
// is a 5-10x larger relative one than on positive charges, where the model
// was first fitted and which it then underestimated 4-5x): 10^5 sources in
// the unit cube and 5000 in a Gaussian blob, 2D and 3D (bench/
// treecode_bench.cpp's sets). The error falls by 1/(alpha theta) per order,
// alpha = 0.905 (2D) and 0.92 (3D) by least squares of the log error, with
// no visible (1 - theta) factor; C is the largest measured ratio error /
// (alpha theta)^(p+1), 0.175 (2D) and 0.33 (3D), rounded up. Positive
// charges measured 0.1-0.2x the model, 10^6 sources below 10^5's.
struct Calibration {
    double alpha, c;
};
inline constexpr Calibration calibration[2] = {{0.91, 0.2}, {0.92, 0.4}};  // D = 2, D = 3

inline double error_model(int dim, double theta, int p) {
    const Calibration k = calibration[dim - 2];
    return k.c * std::pow(k.alpha * theta, p + 1);
}

// Relative cost of an evaluation at (theta, p). 3D (dual traversal), fitted
// to treecode_bench's one-thread times at N = 10^5: the near field grows like
// theta^-1.5 (leaf pairs that fail the test), the translations like
// (p + 1)^4 (the harmonic M2L, multipole.hpp) times the theta^-3 accepted
// pairs; 1.5e5 is the ratio of the two at theta = 1. 2D (particle-cluster,
// per target): (p + 1) per accepted cell, theta^-2 cells.
inline double cost_model(int dim, double theta, int p) {
    if (dim == 3) return (1.5e5 * std::pow(theta, 1.5) + std::pow(p + 1.0, 4)) / (theta * theta * theta);
    return (p + 1.0) / (theta * theta);
}

}  // namespace detail

// The cheapest (theta, p) whose modelled relative L2 field error is at most
// `relative_error` (in (0, 1)) in dimension dim (2 or 3).
inline TreeOptions for_relative_error(double relative_error, int dim) {
    if (!(relative_error > 0 && relative_error < 1))
        fail("target relative error " + mollify::detail::show(relative_error) + " is not in (0, 1)");
    if (dim != 2 && dim != 3) fail("dimension " + std::to_string(dim) + " is not 2 or 3");
    TreeOptions best;
    double best_cost = std::numeric_limits<double>::infinity();
    for (int t = 3; t <= 8; ++t) {
        const double theta = 0.1 * t;
        for (int p = 0; p <= max_order; ++p) {
            if (detail::error_model(dim, theta, p) > relative_error) continue;
            const double cost = detail::cost_model(dim, theta, p);
            if (cost < best_cost) {
                best_cost = cost;
                best.theta = theta;
                best.order = p;
            }
            break;
        }
    }
    if (!(best_cost < std::numeric_limits<double>::infinity()))
        fail("target relative error " + mollify::detail::show(relative_error) + " needs an order above " +
             std::to_string(max_order));
    return best;
}

}  // namespace mollify::poisson
