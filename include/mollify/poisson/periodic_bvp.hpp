// The 1D periodic boundary-value problem of the notes (001, "1D periodic
// BVP"): -phi'' + sigma^2 phi = f on [0, 1), phi and phi' periodic, at the
// N grid points x_j = j h, h = 1/N, by the notes' three methods:
//   finite differences  the circulant -D+D- + sigma^2, diagonalised by the
//                       DFT: eigenvalues lambda_n = 4 sin^2(pi n h)/h^2 + sigma^2;
//   pseudospectral      -phi'' by spectral differentiation: (2 pi n)^2 + sigma^2;
//   Green's function    phi(x) = int_0^1 g(x, y) f(y) dy with
//                       g = cosh(sigma (|x - y| - 1/2)) / (2 sigma sinh(sigma/2)),
//                       by the trapezoidal rule on the grid: a periodic
//                       convolution, summed by FFT (O(N log N), the same sum).
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/poisson/fft.hpp>

#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

enum class BvpMethod { finite_difference, pseudospectral, green };

inline std::vector<double> solve_periodic_bvp(std::span<const double> f, double sigma, BvpMethod method) {
    if (f.size() < 2) fail("periodic BVP: N = " + std::to_string(f.size()) + " grid points (needs at least 2)");
    if (!(sigma > 0) || !std::isfinite(sigma) || sigma > 700)
        fail("periodic BVP: sigma = " + mollify::detail::show(sigma) +
             " is not in (0, 700] (sigma = 0 is the Poisson problem, which needs a neutral f; sinh overflows beyond 710)");
    for (std::size_t j = 0; j < f.size(); ++j)
        if (!std::isfinite(f[j])) fail("periodic BVP: f[" + std::to_string(j) + "] = " + mollify::detail::show(f[j]) + " is not finite");
    const std::size_t n = f.size();
    const double h = 1.0 / static_cast<double>(n);
    constexpr double pi = std::numbers::pi;
    detail::RealFft<1> fft({n});
    std::vector<std::complex<double>> s = fft.forward(f);
    if (method == BvpMethod::green) {
        // phi_i = h sum_j g(x_i - x_j) f_j: g as a periodic function of x - y.
        std::vector<double> g(n);
        for (std::size_t j = 0; j < n; ++j) {
            const double d = static_cast<double>(j) * h;  // |x - y| for x - y = d in [0, 1)
            g[j] = std::cosh(sigma * (d - 0.5)) / (2 * sigma * std::sinh(sigma / 2));
        }
        const std::vector<std::complex<double>> gs = fft.forward(g);
        for (std::size_t k = 0; k < s.size(); ++k) s[k] *= h * gs[k];
        return fft.backward(s);
    }
    for (std::size_t k = 0; k < s.size(); ++k) {
        const double kk = static_cast<double>(k);
        const double sn = std::sin(pi * kk * h);
        const double lambda = method == BvpMethod::finite_difference ? 4 * sn * sn / (h * h) + sigma * sigma
                                                                      : (2 * pi * kk) * (2 * pi * kk) + sigma * sigma;
        s[k] /= lambda;
    }
    return fft.backward(s);
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
