// Particle-mesh charge assignment and field interpolation on a periodic grid
// (notes 001, "PIC": NMP = nearest mesh point, CIC = cloud in cell), and by
// the smooth kernels of the tables. Interpolation uses the assignment's own
// weights, so the self-force vanishes and the total force sum_p q_p E(x_p)
// is zero for an odd gradient symbol (momentum conservation of PIC).
//
// The density on the grid is rho_g = sum_p q_p w_pg / V (V the cell volume);
// NMP and CIC weights sum to 1 per particle, so the grid holds the total
// charge exactly up to rounding (the notes' discrete charge neutrality, hw3).
// A kernel's weights W_delta(|x_g - x_p|) are normalised by their sum per
// particle for the same reason: the grid sum of a mollifier is 1 only up to
// its quadrature error.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/dynamic_kernel.hpp>
#include <mollify/poisson/periodic.hpp>
#include <mollify/static_kernel.hpp>

#include <cmath>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

enum class Assignment { nmp, cic, kernel };

// A scheme: NMP, CIC, or a kernel with support radius delta.
struct Scheme {
    Assignment kind = Assignment::cic;
    const Kernel* kernel = nullptr;  // kind == kernel
    double delta = 0;
};

template <int D>
struct Charges {
    Points<D> x;                // positions in [0, L)^D
    std::span<const double> q;  // charges
};

namespace detail {

template <int D>
void check_charges(const PeriodicGrid<D>& grid, const Charges<D>& p) {
    grid.check();
    for (int c = 0; c < D; ++c)
        if (p.x[c].size() != p.q.size())
            fail("charges: " + std::to_string(p.q.size()) + " charges but " + std::to_string(p.x[c].size()) +
                 " coordinates x[" + std::to_string(c) + "]");
    for (std::size_t j = 0; j < p.q.size(); ++j) {
        if (!std::isfinite(p.q[j])) fail("charge q[" + std::to_string(j) + "] = " + mollify::detail::show(p.q[j]) + " is not finite");
        for (int c = 0; c < D; ++c)
            if (!(p.x[c][j] >= 0 && p.x[c][j] < grid.length))
                fail("particle " + std::to_string(j) + ": x[" + std::to_string(c) + "] = " + mollify::detail::show(p.x[c][j]) +
                     " is outside the periodic box [0, " + mollify::detail::show(grid.length) + ")");
    }
}

inline std::size_t wrap(long j, std::size_t n) {
    const auto m = static_cast<long>(n);
    return static_cast<std::size_t>(((j % m) + m) % m);
}

// Calls visit(flat grid index, weight) for each grid point particle p
// touches, with weights summing to 1.
template <int D, class Visit>
void stencil(const PeriodicGrid<D>& grid, const Charges<D>& p, std::size_t j, const Scheme& s, Visit&& visit) {
    std::array<double, D> x;
    for (int c = 0; c < D; ++c) x[c] = p.x[c][j] / grid.spacing(c);  // in grid units
    if (s.kind == Assignment::nmp) {
        std::array<std::size_t, D> g;
        for (int c = 0; c < D; ++c) g[c] = wrap(std::lround(x[c]), grid.n[c]);
        visit(grid.index(g), 1.0);
        return;
    }
    if (s.kind == Assignment::cic) {
        std::array<long, D> lo;
        std::array<double, D> t;
        for (int c = 0; c < D; ++c) {
            lo[c] = static_cast<long>(std::floor(x[c]));
            t[c] = x[c] - static_cast<double>(lo[c]);
        }
        for (int corner = 0; corner < (1 << D); ++corner) {
            double w = 1;
            std::array<std::size_t, D> g;
            for (int c = 0; c < D; ++c) {
                const bool up = (corner >> c) & 1;
                w *= up ? t[c] : 1 - t[c];
                g[c] = wrap(lo[c] + up, grid.n[c]);
            }
            visit(grid.index(g), w);
        }
        return;
    }
    // Kernel: every grid point within delta (one image per axis: delta < L/2).
    thread_local std::vector<double> r, w;
    thread_local std::vector<std::size_t> at;
    r.clear();
    at.clear();
    std::array<long, D> lo, hi;
    for (int c = 0; c < D; ++c) {
        lo[c] = static_cast<long>(std::ceil(x[c] - s.delta / grid.spacing(c)));
        hi[c] = static_cast<long>(std::floor(x[c] + s.delta / grid.spacing(c)));
    }
    bool empty = false;
    for (int c = 0; c < D; ++c) empty = empty || lo[c] > hi[c];
    std::array<long, D> g = lo;
    while (!empty) {
        double r2 = 0;
        std::array<std::size_t, D> gw;
        for (int c = 0; c < D; ++c) {
            const double d = (static_cast<double>(g[c]) - x[c]) * grid.spacing(c);
            r2 += d * d;
            gw[c] = wrap(g[c], grid.n[c]);
        }
        if (r2 < s.delta * s.delta) {
            r.push_back(std::sqrt(r2));
            at.push_back(grid.index(gw));
        }
        int c = D - 1;
        while (c >= 0 && g[c] == hi[c]) g[c] = lo[c], --c;
        if (c < 0) break;
        ++g[c];
    }
    w.resize(r.size());
    s.kernel->evaluate(QuantityId::value, r, s.delta, w);
    double sum = 0;
    for (double v : w) sum += v;
    if (!(sum > 0))
        fail("kernel assignment: no grid point inside the support of particle " + std::to_string(j) + " (delta = " +
             mollify::detail::show(s.delta) + " against a grid spacing " + mollify::detail::show(grid.spacing(0)) +
             "): take delta of at least two grid spacings");
    for (std::size_t i = 0; i < at.size(); ++i) visit(at[i], w[i] / sum);
}

template <int D>
void check_scheme(const PeriodicGrid<D>& grid, const Scheme& s) {
    if (s.kind != Assignment::kernel) return;
    if (!s.kernel) fail("kernel assignment: no kernel given");
    if (s.kernel->dim() != D)
        fail("kernel assignment: " + std::string(s.kernel->spec()) + " is a " + std::to_string(s.kernel->dim()) +
             "D kernel on a " + std::to_string(D) + "D grid");
    if (!(s.delta > 0) || !std::isfinite(s.delta))
        fail("kernel assignment: delta = " + mollify::detail::show(s.delta) + " is not a positive finite number");
    if (!(s.delta < grid.length / 2))
        fail("kernel assignment: delta = " + mollify::detail::show(s.delta) + " is not below half the box length " +
             mollify::detail::show(grid.length / 2));
}

}  // namespace detail

// rho on the grid (charge per volume).
template <int D>
std::vector<double> assign(const PeriodicGrid<D>& grid, const Charges<D>& p, const Scheme& s) {
    detail::check_charges(grid, p);
    detail::check_scheme(grid, s);
    std::vector<double> rho(grid.size(), 0.0);
    const double inv_v = 1 / grid.cell_volume();
    for (std::size_t j = 0; j < p.q.size(); ++j)
        detail::stencil(grid, p, j, s, [&](std::size_t g, double w) { rho[g] += p.q[j] * w * inv_v; });
    return rho;
}

// E at the particles, interpolated with the assignment's weights.
template <int D>
std::array<std::vector<double>, D> interpolate(const PeriodicGrid<D>& grid, const GridField<D>& f, const Charges<D>& p,
                                               const Scheme& s) {
    detail::check_charges(grid, p);
    detail::check_scheme(grid, s);
    std::array<std::vector<double>, D> e;
    for (auto& c : e) c.assign(p.q.size(), 0.0);
    for (std::size_t j = 0; j < p.q.size(); ++j)
        detail::stencil(grid, p, j, s, [&](std::size_t g, double w) {
            for (int c = 0; c < D; ++c) e[c][j] += w * f.field[c][g];
        });
    return e;
}

// Particles -> grid -> solve -> field at the particles (one PIC solve).
template <int D>
std::array<std::vector<double>, D> particle_field(const PeriodicGrid<D>& grid, const Charges<D>& p, const Scheme& s,
                                                  const PeriodicOptions& o = {}) {
    const std::vector<double> rho = assign(grid, p, s);
    return interpolate(grid, solve_periodic(grid, rho, o), p, s);
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
