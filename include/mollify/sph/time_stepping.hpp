// Time integration of the SPH system dx/dt = u, du/dt = a(x): the classical
// fourth-order Runge-Kutta method Franz uses (§6.2), and the symplectic
// kick-drift-kick leapfrog (second order, time-reversible; its energy error
// stays bounded instead of drifting). Positions in a periodic box are
// wrapped back into it after every stage.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/sph/euler.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

namespace mollify::sph {
inline namespace MOLLIFY_ISA {

enum class Integrator { rk4, leapfrog };

inline Integrator integrator(std::string_view name) {
    if (name == "rk4") return Integrator::rk4;
    if (name == "leapfrog") return Integrator::leapfrog;
    fail("unknown integrator '" + std::string(name) + "' (rk4 or leapfrog)");
}
inline const char* name(Integrator i) { return i == Integrator::rk4 ? "rk4" : "leapfrog"; }

// The step of a CFL-type bound: a signal crosses at most the fraction cfl of
// the kernel radius per step. Signal speed: the sound speed sqrt(dp/drho) =
// sqrt(rho) of p = rho^2/2 plus the spread of particle velocities (a common
// translation moves all particles alike and does not limit the step).
template <int D>
double cfl_step(const State<D>& y, const std::vector<double>& rho, double eps, double cfl) {
    if (!(cfl > 0) || !std::isfinite(cfl)) fail("CFL number " + mollify::detail::show(cfl) + " is not positive");
    double c = 0;
    for (const double r : rho) c = std::max(c, std::sqrt(std::max(r, 0.0)));
    double spread = 0;
    for (int k = 0; k < D; ++k) {
        const auto [lo, hi] = std::minmax_element(y.u[k].begin(), y.u[k].end());
        if (lo != y.u[k].end()) spread = std::max(spread, *hi - *lo);
    }
    const double v = c + spread;
    if (!(v > 0) || !std::isfinite(v)) fail("no finite signal speed in the state (speed " + mollify::detail::show(v) + ")");
    return cfl * eps / v;
}

template <int D, class System>
class TimeStepper {
public:
    TimeStepper(System& system, Integrator method) : system_(system), method_(method) {}

    void step(State<D>& y, double dt) {
        if (!(dt > 0) || !std::isfinite(dt)) fail("time step dt = " + mollify::detail::show(dt) + " is not positive");
        if (method_ == Integrator::rk4)
            rk4(y, dt);
        else
            leapfrog(y, dt);
    }

    // Drops the cached acceleration (the leapfrog reuses a(x) of the last
    // step's end) after the caller changed the state.
    void reset() { cached_ = false; }

private:
    void axpy(const Field<D>& x, double a, const Field<D>& v, Field<D>& out, bool wrap) const {
        const Domain<D>& dom = system_.domain();
        for (int c = 0; c < D; ++c) {
            out[c].resize(x[c].size());
            for (std::size_t j = 0; j < x[c].size(); ++j) {
                const double z = x[c][j] + a * v[c][j];
                out[c][j] = wrap ? dom.wrap(z) : z;
            }
        }
    }

    void rk4(State<D>& y, double dt) {
        system_.acceleration(y.x, a1_);
        axpy(y.x, dt / 2, y.u, x2_, true);
        axpy(y.u, dt / 2, a1_, u2_, false);
        system_.acceleration(x2_, a2_);
        axpy(y.x, dt / 2, u2_, x3_, true);
        axpy(y.u, dt / 2, a2_, u3_, false);
        system_.acceleration(x3_, a3_);
        axpy(y.x, dt, u3_, x4_, true);
        axpy(y.u, dt, a3_, u4_, false);
        system_.acceleration(x4_, a4_);
        const Domain<D>& dom = system_.domain();
        for (int c = 0; c < D; ++c)
            for (std::size_t j = 0; j < y.x[c].size(); ++j) {
                const double dx = y.u[c][j] + 2 * u2_[c][j] + 2 * u3_[c][j] + u4_[c][j];
                const double du = a1_[c][j] + 2 * a2_[c][j] + 2 * a3_[c][j] + a4_[c][j];
                y.x[c][j] = dom.wrap(y.x[c][j] + dt / 6 * dx);
                y.u[c][j] += dt / 6 * du;
            }
        cached_ = false;
    }

    void leapfrog(State<D>& y, double dt) {
        if (!cached_) system_.acceleration(y.x, a1_);
        for (int c = 0; c < D; ++c)
            for (std::size_t j = 0; j < y.x[c].size(); ++j) y.u[c][j] += dt / 2 * a1_[c][j];  // kick
        axpy(y.x, dt, y.u, x2_, true);                                                         // drift
        y.x = x2_;
        system_.acceleration(y.x, a1_);
        for (int c = 0; c < D; ++c)
            for (std::size_t j = 0; j < y.x[c].size(); ++j) y.u[c][j] += dt / 2 * a1_[c][j];  // kick
        cached_ = true;
    }

    System& system_;
    Integrator method_;
    bool cached_ = false;
    Field<D> a1_, a2_, a3_, a4_, x2_, x3_, x4_, u2_, u3_, u4_;
};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph
