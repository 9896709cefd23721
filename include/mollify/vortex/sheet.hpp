// The vortex-blob method for a periodic sheet (notes 001, "vortex blobs"):
// particles x_j with circulations Gamma_j move with the velocity they
// induce, dx_i/dt = sum_j Gamma_j K(x_i - x_j), K a periodic blob
// (blob.hpp); direct O(N^2) summation, OpenMP over targets; classical RK4.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/detail/parallel.hpp>
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>
#include <mollify/vortex/blob.hpp>

#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

namespace mollify::vortex {
inline namespace MOLLIFY_ISA {

struct Sheet {
    std::vector<double> x, y, gamma;
    std::size_t size() const { return gamma.size(); }
};

// Krasny's perturbed flat sheet: x = a + eps sin 2 pi a, y = -eps sin 2 pi a
// at a = j/N, unit total circulation shared equally (Gamma_j = 1/N).
inline Sheet krasny_sheet(long n, double eps) {
    if (n < 1) fail("vortex sheet: N = " + std::to_string(n) + " particles (needs at least 1)");
    if (!std::isfinite(eps)) fail("vortex sheet: perturbation eps = " + mollify::detail::show(eps) + " is not finite");
    Sheet s;
    for (long j = 0; j < n; ++j) {
        const double a = static_cast<double>(j) / static_cast<double>(n);
        const double p = eps * std::sin(2 * std::numbers::pi * a);
        s.x.push_back(a + p);
        s.y.push_back(-p);
        s.gamma.push_back(1.0 / static_cast<double>(n));
    }
    return s;
}

namespace detail {

inline void check(const Sheet& s) {
    if (s.size() == 0) fail("vortex sheet: no particles");
    if (s.x.size() != s.size() || s.y.size() != s.size())
        fail("vortex sheet: " + std::to_string(s.size()) + " circulations but " + std::to_string(s.x.size()) + " x and " +
             std::to_string(s.y.size()) + " y coordinates");
    for (std::size_t j = 0; j < s.size(); ++j)
        if (!std::isfinite(s.x[j]) || !std::isfinite(s.y[j]) || !std::isfinite(s.gamma[j]))
            fail("vortex sheet: particle " + std::to_string(j) + " at (" + mollify::detail::show(s.x[j]) + ", " +
                 mollify::detail::show(s.y[j]) + ") with circulation " + mollify::detail::show(s.gamma[j]) +
                 " is not finite");
}

}  // namespace detail

// u_i = sum_{j != i} Gamma_j K(x_i - x_j): a blob induces no velocity at its
// own centre (K is odd), nor do its images (they cancel in pairs).
template <class Blob>
void velocity(const Blob& blob, const Sheet& s, std::vector<double>& u, std::vector<double>& v) {
    const std::size_t n = s.size();
    u.assign(n, 0.0);
    v.assign(n, 0.0);
#pragma omp parallel
    {
        std::vector<double> dx(n), dy(n), g(n);
#pragma omp for schedule(static)
        for (std::size_t i = 0; i < n; ++i) {
            std::size_t m = 0;
            for (std::size_t j = 0; j < n; ++j) {
                if (j == i) continue;
                dx[m] = s.x[i] - s.x[j];
                dy[m] = s.y[i] - s.y[j];
                g[m++] = s.gamma[j];
            }
            const Velocity k = blob.sum(std::span(dx).first(m), std::span(dy).first(m), std::span(g).first(m));
            u[i] = k[0];
            v[i] = k[1];
        }
    }
}

// One classical RK4 step of length dt.
template <class Blob>
void rk4_step(const Blob& blob, Sheet& s, double dt) {
    const std::size_t n = s.size();
    std::vector<double> ku[4], kv[4];
    Sheet stage = s;
    constexpr double a[] = {0.5, 0.5, 1.0};
    for (int k = 0; k < 4; ++k) {
        velocity(blob, stage, ku[k], kv[k]);
        if (k == 3) break;
        for (std::size_t i = 0; i < n; ++i) {
            stage.x[i] = s.x[i] + a[k] * dt * ku[k][i];
            stage.y[i] = s.y[i] + a[k] * dt * kv[k][i];
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        s.x[i] += dt / 6 * (ku[0][i] + 2 * ku[1][i] + 2 * ku[2][i] + ku[3][i]);
        s.y[i] += dt / 6 * (kv[0][i] + 2 * kv[1][i] + 2 * kv[2][i] + kv[3][i]);
    }
}

// Advances s by `steps` RK4 steps of dt; the state is checked first, and
// after each step (a NaN would mean coincident particles of a point-vortex
// kernel, which the blobs exclude).
template <class Blob>
void advance(const Blob& blob, Sheet& s, double dt, long steps) {
    detail::check(s);
    if (!(dt > 0) || !std::isfinite(dt)) fail("vortex sheet: time step dt = " + mollify::detail::show(dt) + " is not positive");
    if (steps < 0) fail("vortex sheet: " + std::to_string(steps) + " steps");
    for (long k = 0; k < steps; ++k) rk4_step(blob, s, dt);
    detail::check(s);
}

// Invariants of the dynamics: total circulation, and the linear impulse
// (sum Gamma y, -sum Gamma x up to the period) conserved since K is odd.
inline double circulation(const Sheet& s) {
    double c = 0;
    for (double g : s.gamma) c += g;
    return c;
}
inline double impulse_y(const Sheet& s) {
    double p = 0;
    for (std::size_t j = 0; j < s.size(); ++j) p += s.gamma[j] * s.y[j];
    return p;
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::vortex
