// The quasi-analytical solution of Franz §6.1: the inviscid Burgers equation
// J_t + J J_x = 0, J(., 0) = f, is solved by J(x, t) = f(y) with y the foot
// of the characteristic, x = y + t f(y) (Thm. 6.2; unique while
// 1 + t f' > 0, i.e. t < T = -1/min f'), and
//   u = 2/3 J + 1,   rho = (1 - J/3)^2                                (Thm. 6.3)
// solves the 1D Euler equations with p = rho^2/2. The foot is found by
// Newton's method safeguarded by bisection on the bracket
// [x - t sup|f|, x + t sup|f|], to 1e-14.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>

#include <cmath>
#include <string>

namespace mollify::sph {
inline namespace MOLLIFY_ISA {

struct BurgersData {
    double (*f)(double);
    double (*df)(double);
    double sup_abs_f;  // sup |f|, for the bracket
    double min_df;     // min f' < 0: the solution exists for t < -1/min_df
};

class Burgers {
public:
    explicit Burgers(BurgersData data) : data_(data) {}

    double blow_up_time() const { return data_.min_df < 0 ? -1 / data_.min_df : INFINITY; }

    // y with x = y + t f(y).
    double foot(double x, double t) const {
        if (!std::isfinite(x)) fail("Burgers: position x = " + mollify::detail::show(x) + " is not finite");
        if (!(t >= 0) || !(t < blow_up_time()))
            fail("Burgers: time t = " + mollify::detail::show(t) + " is outside [0, " + mollify::detail::show(blow_up_time()) +
                 "), where the characteristics do not cross");
        double lo = x - t * data_.sup_abs_f, hi = x + t * data_.sup_abs_f;
        double y = x - t * data_.f(x);
        for (int it = 0; it < 200; ++it) {
            const double g = y + t * data_.f(y) - x;  // increasing in y (1 + t f' > 0)
            if (g == 0) return y;
            (g > 0 ? hi : lo) = y;
            const double tol = 1e-14 * std::max(1.0, std::abs(y));
            double next = y - g / (1 + t * data_.df(y));
            if (std::abs(next - y) <= tol) return next;  // converged (quadratically: next is far better than tol)
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
            if (hi - lo <= tol) return next;
            y = next;
        }
        fail("Burgers: no convergence for the foot of x = " + mollify::detail::show(x) + " at t = " + mollify::detail::show(t));
    }

    double f(double x) const { return data_.f(x); }  // J(x, 0)
    double J(double x, double t) const { return data_.f(foot(x, t)); }
    double velocity(double x, double t) const { return 2.0 / 3.0 * J(x, t) + 1; }
    double density(double x, double t) const {
        const double b = 1 - J(x, t) / 3;
        return b * b;
    }
    double initial_velocity(double x) const { return 2.0 / 3.0 * data_.f(x) + 1; }
    double initial_density(double x) const {
        const double b = 1 - data_.f(x) / 3;
        return b * b;
    }

private:
    BurgersData data_;
};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph
