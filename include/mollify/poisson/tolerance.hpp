// The treecode's parameters and the accuracy knob: a target relative error
// in, an opening parameter theta and an order p out.
//
// The far-field truncation error of one accepted cell is bounded by
// (multipole.hpp) sum|q| theta^(p+1)/(r (1 - theta)) for the potential, and
// about (p + 2) times that over r (1 - theta) for the field. These worst
// cases (every source on the cell's sphere, in line with the target)
// overestimate the error of a whole evaluation by orders of magnitude: most
// accepted cells lie well inside the theta limit, so the measured error
// falls like (alpha r)^(p+1) with alpha < 1, r = theta (2D) or
// theta/(2 - theta) (3D's full M2L). The knob uses that fitted form,
//     relative L2 field error ~ C (alpha r)^(p+1),
// alpha and C calibrated by measurement (calibration below), and picks,
// among theta in {0.3, 0.4, ..., 0.8}, the cheapest (theta, p) meeting the
// target by a cost model fitted to measured times (cost below), from the
// order lowest_order(dim) up. tests/poisson_free_test.cpp (AccuracyKnob) checks
// the achieved error on positive, neutral and centrally concentrated
// one-signed charges (masses).
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/poisson/multipole.hpp>
#include <mollify/smoothing.hpp>

#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <string>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

struct TreeOptions {
    double theta = 0.5;  // opening parameter: a cell is expanded when rho_c / R < theta
    int order = 6;       // multipole order p
    // At most this many sources in a leaf; 0: the dimension's default,
    // leaf_for(D). 3D: 400, exafmm-t's ncrit: uniform sources fill octree
    // boxes with N/8^level sources, and 400 stops at 195 per leaf at N = 1e5,
    // 244 at 1e6, where the full M2L (multipole.hpp) at wide opening angles
    // balances a large near field against few translations (N = 1e6,
    // theta 0.7, p = 12, neutral charges, the spheres' pair test: 6.8 CPU s
    // at 400, 8.9 s at 256, which splits some of the 1e6 boxes and not
    // others; 128, 24-49 per
    // leaf, was best for the triangular M2L at theta 0.4-0.5). 2D
    // (particle-cluster, per target): 128.
    int leaf_size = 0;

    int leaf_for(int dim) const { return leaf_size > 0 ? leaf_size : dim == 3 ? 400 : 128; }

    void check() const {
        if (!(theta > 0 && theta < 1))
            fail("opening parameter theta = " + mollify::detail::show(theta) +
                 " is not in (0, 1) (the multipole series converges only for rho/R < 1)");
        check_order(order);
        if (leaf_size < 0)
            fail("tree leaf size " + std::to_string(leaf_size) + " is negative (0: the dimension's default)");
    }
};

namespace detail {

// The relative L2 field error against direct summation on NEUTRAL charges
// (uniform in [-0.5, 0.5]: the far field cancels, so the same absolute
// truncation error is a 5-40x larger relative one than on positive
// charges), modelled as C (alpha r(theta))^(p+1) with r the truncation
// ratio per order at the opening angle: theta in 2D (particle-cluster, one
// expansion per target and cell), theta/(2 - theta) in 3D (the full M2L of
// two cells of radius theta R/2, multipole.hpp).
// 2D: fitted over theta in {0.3, ..., 0.8}, p = 2..20, 10^5 sources in the
// unit square and 5000 in a Gaussian blob: alpha = 0.905 by least squares of
// the log error, C the largest measured ratio 0.175, rounded up.
// 3D: bench/knob_calibration.cpp (bench/results/knob_calibration.md):
// 10^5 sources in the unit cube (theta 0.3..0.8, p = 4..20) and 5000 in a
// Gaussian blob (theta 0.3..0.8, p = 2..20); the tightest envelope (C the
// largest ratio measured/(alpha r)^(p+1) at the alpha minimising the summed
// log(model/measured)): alpha = 0.892, C = 0.32 (0.311 rounded up), 1-2x the
// uniform set's measured errors at p >= 10 (with the box-measured acceptance
// of treecode.hpp's accepted()). Positive charges measure 0.02-0.2x the model
// at high orders, up to 1x at p = 4. Since stop 77 the calibration also has
// two one-signed sets (treecode_bench's positive set and a Plummer sphere of
// equal masses): over all four sets from p = 4 the same envelope comes out
// (alpha 0.892, C 0.311), and none much cheaper for one-signed charges
// alone (alpha 0.805, C 0.517: 1x the neutral model at p = 4, 0.2-0.35x at
// p = 14-20, an order or two saved at the tightest targets only).
struct Calibration {
    double alpha, c;
};
inline constexpr Calibration calibration[2] = {{0.91, 0.2}, {0.892, 0.32}};  // D = 2, D = 3

// The lowest order the knob chooses: the lowest at which every set of its
// calibration was measured, p = 2 in 2D and p = 4 in 3D (treecode_bench's
// uniform set from 4). Below
// it the truncation error no longer falls as the model's power of p on
// equal masses concentrated towards a centre (stop 77, knob_calibration's
// Plummer sphere and a throwaway driver, theta 0.8): in 3D Plummer and
// Hernquist spheres measured 1.03-1.62x the model at p = 2 (N = 2*10^4 and
// 2*10^5), and at p = 3 a Plummer sphere's ratio grew with N, 0.37, 0.71,
// 0.95 and 0.98x at N = 5000, 2*10^4, 2*10^5 and 10^6, while at p = 4 it
// stays below 0.86x (the uniform neutral set's 0.91-0.97x there is the
// envelope itself); in 2D a cusped disc measured 1.04x at p = 1 and at most
// 0.86x at p = 2, at every N from 5000 to 10^6. The cost: 3D targets above
// 0.024 get theta 0.8, p = 4, 2D ones above 0.077 theta 0.8, p = 2, where
// lower orders met the model.
constexpr int lowest_order(int dim) { return dim == 3 ? 4 : 2; }

inline double error_model(int dim, double theta, int p) {
    const Calibration k = calibration[dim - 2];
    const double r = dim == 3 ? theta / (2 - theta) : theta;
    return k.c * std::pow(k.alpha * r, p + 1);
}

// Relative cost of an evaluation at (theta, p). 3D (dual traversal, leaves
// of ~200-250 sources): knob_calibration's one-thread seconds at N = 10^5,
// n(theta) + b (p + 1)^k theta^-j, the near field's time per opening angle
// (theta = 0.3 .. 0.8: it grows in steps as leaf pairs fail the test, which
// theta^-3 averaged 22 % off and so chose theta 0.6, p = 15 for 1e-7 where
// 0.7, p = 20 measured faster) and the far field's power law, fitted by
// least squares of the relative deviation (largest 10 %; stop 42).
// 2D (particle-cluster, per target): (p + 1) per accepted cell, theta^-2 cells.
// The opening angles the knob chooses from, and the 3D near field's cost at each.
inline constexpr double thetas[6] = {0.3, 0.4, 0.5, 0.6, 0.7, 0.8};
inline constexpr double near_cost_3d[6] = {2.654, 1.457, 0.654, 0.4733, 0.2442, 0.2152};
inline constexpr double far_cost_3d = 1.553e-5;  // b; k = 3, j = 2
// At theta = thetas[t].
inline double cost_model(int dim, std::size_t t, int p) {
    const double theta = thetas[t];
    if (dim == 3) return near_cost_3d[t] + far_cost_3d * std::pow(p + 1.0, 3) / (theta * theta);
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
    for (std::size_t t = 0; t < std::size(detail::thetas); ++t) {
        const double theta = detail::thetas[t];
        for (int p = detail::lowest_order(dim); p <= max_order; ++p) {
            if (detail::error_model(dim, theta, p) > relative_error) continue;
            const double cost = detail::cost_model(dim, t, p);
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

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
