// A periodic box [0, L)^D sampled at n_c points per axis (spacing L/n_c),
// row-major; the grid the periodic Poisson solver and the charge assignment
// share.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

template <int D>
struct PeriodicGrid {
    std::array<std::size_t, D> n;
    double length = 1;

    // n_c >= 2 per axis (the notes' smallest periodic grid; FFTW takes any
    // size), at most 2^30 points in all, L > 0 finite.
    void check() const {
        std::size_t total = 1;
        for (int c = 0; c < D; ++c) {
            if (n[c] < 2 || n[c] > (std::size_t{1} << 30))
                fail("periodic grid: n[" + std::to_string(c) + "] = " + std::to_string(n[c]) +
                     " points (the FFT needs 2 to 2^30 per axis)");
            total *= n[c];
            if (total > (std::size_t{1} << 30))
                fail("periodic grid: " + std::to_string(total) + "+ points in all (more than 2^30)");
        }
        if (!(length > 0) || !std::isfinite(length))
            fail("periodic grid: box length L = " + mollify::detail::show(length) + " is not a positive finite number");
    }
    std::size_t size() const {
        std::size_t s = 1;
        for (int c = 0; c < D; ++c) s *= n[c];
        return s;
    }
    double spacing(int c) const { return length / static_cast<double>(n[c]); }
    double cell_volume() const {
        double v = 1;
        for (int c = 0; c < D; ++c) v *= spacing(c);
        return v;
    }
    // Flat index of the grid point (j_0, ..., j_{D-1}), each already in [0, n_c).
    std::size_t index(const std::array<std::size_t, D>& j) const {
        std::size_t f = 0;
        for (int c = 0; c < D; ++c) f = f * n[c] + j[c];
        return f;
    }
    std::array<std::size_t, D> point(std::size_t flat) const {
        std::array<std::size_t, D> j{};
        for (int c = D - 1; c >= 0; --c) {
            j[c] = flat % n[c];
            flat /= n[c];
        }
        return j;
    }
};

// Potential and field E = -grad phi on the grid points.
template <int D>
struct GridField {
    std::vector<double> potential;
    std::array<std::vector<double>, D> field;
};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
