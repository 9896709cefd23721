// The periodic Poisson solver by FFT (notes 001, "periodic Poisson problem":
// the DFT diagonalises the periodic finite-difference Laplacian). On the grid
// of periodic_grid.hpp it solves
//     Delta phi = rho - rho_bar,     E = -grad phi,
// the sign of the free-space solvers (sources.hpp: Delta phi = rho). The mean
// of phi (the zero mode) is set to 0. Two discretisations of -Delta, by their
// symbols at the wavenumber k (integer per axis):
//   finite differences   sum_c 4 sin^2(pi k_c / n_c) / h_c^2   (the notes'
//                        eigenvalues lambda_n of the circulant -D+D-), with
//                        the centred difference E = -(phi_{j+1} - phi_{j-1})/2h,
//                        symbol i sin(2 pi k_c/n_c)/h_c;
//   pseudospectral       sum_c (2 pi k_c / L)^2, E by spectral differentiation
//                        (i 2 pi k_c / L; the odd Nyquist mode's derivative is 0).
// Periodic solutions exist only for neutral sources (integrate Delta phi over
// the box): a net charge is an error naming it, unless the caller asks for
// the neutralising uniform background rho_bar of the notes.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/poisson/fft.hpp>
#include <mollify/poisson/periodic_grid.hpp>

#include <complex>
#include <limits>
#include <numbers>
#include <span>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

enum class Symbol { finite_difference, pseudospectral };

struct PeriodicOptions {
    Symbol symbol = Symbol::pseudospectral;
    bool neutralising_background = false;  // subtract the mean charge density instead of failing
};

namespace detail {

// |sum rho| above the rounding of the sum itself (N u sum |rho|, a bound for
// recursive summation, doubled) is a net charge, not rounding.
[[maybe_unused]] inline double net_density(std::span<const double> rho, bool background) {
    double sum = 0, abs = 0;
    for (double r : rho) {
        if (!std::isfinite(r)) fail("periodic Poisson: a charge density is " + mollify::detail::show(r));
        sum += r;
        abs += std::abs(r);
    }
    const double mean = sum / static_cast<double>(rho.size());
    const double rounding = 2.0 * static_cast<double>(rho.size()) * std::numeric_limits<double>::epsilon() / 2 * abs;
    if (!background && std::abs(sum) > rounding)
        fail("periodic Poisson: the charge is not neutral: mean density " + mollify::detail::show(mean) +
             " (sum " + mollify::detail::show(sum) + " over " + std::to_string(rho.size()) +
             " grid points; periodic solutions need zero net charge: neutralise it, or ask for the neutralising background)");
    return mean;
}

}  // namespace detail

template <int D>
GridField<D> solve_periodic(const PeriodicGrid<D>& grid, std::span<const double> rho, const PeriodicOptions& options = {}) {
    grid.check();
    if (rho.size() != grid.size())
        fail("periodic Poisson: " + std::to_string(rho.size()) + " densities for a grid of " + std::to_string(grid.size()) + " points");
    detail::net_density(rho, options.neutralising_background);  // the zero mode (mean or background) is dropped below
    detail::RealFft<D> fft(grid.n);
    std::vector<std::complex<double>> s = fft.forward(rho);
    constexpr double pi = std::numbers::pi;
    // d[c]: the derivative symbol along c (times i), lap: the symbol of -Delta.
    std::array<std::vector<std::complex<double>>, D> grad;
    for (auto& g : grad) g.assign(s.size(), 0.0);
    for (std::size_t f = 0; f < s.size(); ++f) {
        const std::array<long, D> k = fft.wavenumber(f);
        double lap = 0;
        std::array<double, D> d{};
        bool zero = true;
        for (int c = 0; c < D; ++c) {
            const double h = grid.spacing(c), n = static_cast<double>(grid.n[c]), kc = static_cast<double>(k[c]);
            zero = zero && k[c] == 0;
            if (options.symbol == Symbol::finite_difference) {
                const double sn = std::sin(pi * kc / n);
                lap += 4 * sn * sn / (h * h);
                d[c] = std::sin(2 * pi * kc / n) / h;
            } else {
                lap += (2 * pi * kc / grid.length) * (2 * pi * kc / grid.length);
                d[c] = 2 * std::abs(k[c]) == static_cast<long>(grid.n[c]) ? 0.0 : 2 * pi * kc / grid.length;
            }
        }
        // Delta phi = rho: phi_k = -rho_k / lap; E = -grad phi: E_k = -i d phi_k.
        const std::complex<double> phi = zero ? 0.0 : -s[f] / lap;
        s[f] = phi;
        for (int c = 0; c < D; ++c) grad[c][f] = std::complex<double>(0, -d[c]) * phi;
    }
    GridField<D> out;
    out.potential = fft.backward(s);
    for (int c = 0; c < D; ++c) out.field[c] = fft.backward(grad[c]);
    return out;
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
