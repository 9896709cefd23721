// The two test cases of Franz §6.2, both with min f' = -1, so the solution
// exists up to T = 1 and is compared at t = 0.8.
//  - On R (§6.2.1): f = 3 - c0 b(x), b(x) = exp(1/(4 (x - 1/2)^2 - 1)) on
//    |x - 1/2| < 1/2 (0 elsewhere); rho_0 = (c0 b / 3)^2 is compactly
//    supported, so finitely many particles; h = eps^2.
//  - On T = [0, 1) (§6.2.2): f = sin(2 pi x)/(2 pi); h = eps^2/10.
// Two printing errors of the thesis are corrected here (the scene summary
// reports them): the bump is printed as exp(1/(4x^2 - 1)), singular at
// x = 1/2 inside its own support |x - 1/2| < 1/2 (it must be centred there),
// and c0 is printed as 3^(1/4) e^(3/(3 - sqrt 3)) (4 - sqrt 3)/12, which
// gives min f' = -(4 - sqrt 3)/(4 - 2 sqrt 3) = -4.23 and a blow-up at
// t = 0.236 < 0.8; min f' = -1 (the stated value, and T = 1) needs
// (4 - 2 sqrt 3) = (sqrt 3 - 1)^2 in place of (4 - sqrt 3).
#pragma once

#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/sph/burgers.hpp>
#include <mollify/sph/domain.hpp>
#include <mollify/sph/euler.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace mollify::sph {

namespace franz {

inline double c0() {
    const double s3 = std::numbers::sqrt3;
    return std::pow(3.0, 0.25) * std::exp(3 / (3 - s3)) * (4 - 2 * s3) / 12;
}
inline double bump(double x) {
    const double s = x - 0.5, q = 4 * s * s - 1;
    return q < 0 ? std::exp(1 / q) : 0.0;
}
inline double line_f(double x) { return 3 - c0() * bump(x); }
inline double line_df(double x) {
    const double s = x - 0.5, q = 4 * s * s - 1;
    return q < 0 ? c0() * std::exp(1 / q) * 8 * s / (q * q) : 0.0;
}
inline double torus_f(double x) { return std::sin(2 * std::numbers::pi * x) / (2 * std::numbers::pi); }
inline double torus_df(double x) { return std::cos(2 * std::numbers::pi * x); }

}  // namespace franz

struct FranzCase {
    std::string name;  // "line" or "torus"
    Domain<1> domain;
    Burgers solution;
    double spacing_factor;  // h = spacing_factor eps^2

    // The particle spacing h of a kernel radius eps; on T, h = 1/N exactly.
    double spacing(double eps) const {
        const double h = spacing_factor * eps * eps;
        if (!domain.is_periodic()) return h;
        return 1.0 / std::round(1.0 / h);
    }
};

inline FranzCase franz_line() {
    return {"line", Domain<1>::whole_space(), Burgers({franz::line_f, franz::line_df, 3.0, -1.0}), 1.0};
}
inline FranzCase franz_torus() {
    return {"torus", Domain<1>::periodic(1.0),
            Burgers({franz::torus_f, franz::torus_df, 1 / (2 * std::numbers::pi), -1.0}), 0.1};
}

// Particles on the lattice h j with masses h rho_0(h j) (Franz 3.6): on R
// the j with rho_0(h j) > 0, on T j = 0..N-1, N = 1/h.
struct Lattice {
    State<1> state;
    std::vector<double> mass, rho0;
};

inline Lattice lattice(const FranzCase& c, double h) {
    if (!(h > 0) || !std::isfinite(h)) fail("particle spacing h = " + mollify::detail::show(h) + " is not positive");
    Lattice l;
    long first = 0, last = 0;
    if (c.domain.is_periodic()) {
        const double n = std::round(c.domain.length() / h);
        if (std::abs(n * h - c.domain.length()) > 1e-9 * c.domain.length())
            fail("particle spacing h = " + mollify::detail::show(h) + " does not divide the torus length");
        last = static_cast<long>(n) - 1;
    } else {
        first = static_cast<long>(std::floor(-1 / h)) - 1;  // the support of rho_0 lies in (0, 1)
        last = static_cast<long>(std::ceil(2 / h)) + 1;
    }
    for (long j = first; j <= last; ++j) {
        const double x = static_cast<double>(j) * h;
        const double r0 = c.solution.initial_density(x);
        if (!c.domain.is_periodic() && !(r0 > 0)) continue;
        l.state.x[0].push_back(x);
        l.state.u[0].push_back(c.solution.initial_velocity(x));
        l.rho0.push_back(r0);
        l.mass.push_back(h * r0);
    }
    return l;
}

}  // namespace mollify::sph
