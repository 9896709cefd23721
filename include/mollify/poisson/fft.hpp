// Real-to-complex FFTs of a D-dimensional periodic grid through FFTW3 (the
// Debian-packaged FFT: any size, not only powers of two, and the fastest
// there is on one core; plans with FFTW_ESTIMATE, so results do not depend
// on timing measurements). Row-major grids; the last dimension is halved in
// the spectrum (n_last/2 + 1 complex values), FFTW's r2c layout.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/error.hpp>

#include <fftw3.h>

#include <array>
#include <complex>
#include <cstddef>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

// FFTW's planner is not thread-safe: plan creation is serialised, by one
// mutex in the program, outside the instruction set's namespace below (units
// built for different instruction sets plan under the same lock).
namespace mollify::poisson::fftw {
inline std::mutex& planner_mutex() {
    static std::mutex m;
    return m;
}
}  // namespace mollify::poisson::fftw

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {
namespace detail {

template <int D>
class RealFft {
public:
    explicit RealFft(const std::array<std::size_t, D>& n) : n_(n) {
        real_size_ = complex_size_ = 1;
        for (int c = 0; c < D; ++c) {
            dims_[c] = static_cast<int>(n[c]);
            real_size_ *= n[c];
            complex_size_ *= c == D - 1 ? n[c] / 2 + 1 : n[c];
        }
        real_ = static_cast<double*>(fftw_malloc(sizeof(double) * real_size_));
        spectrum_ = static_cast<fftw_complex*>(fftw_malloc(sizeof(fftw_complex) * complex_size_));
        if (!real_ || !spectrum_) fail("FFT: cannot allocate a grid of " + std::to_string(real_size_) + " points");
        const std::lock_guard lock(fftw::planner_mutex());
        forward_ = fftw_plan_dft_r2c(D, dims_.data(), real_, spectrum_, FFTW_ESTIMATE);
        backward_ = fftw_plan_dft_c2r(D, dims_.data(), spectrum_, real_, FFTW_ESTIMATE);
        if (!forward_ || !backward_) fail("FFT: FFTW cannot plan a grid of " + std::to_string(real_size_) + " points");
    }
    RealFft(const RealFft&) = delete;
    RealFft& operator=(const RealFft&) = delete;
    ~RealFft() {
        const std::lock_guard lock(fftw::planner_mutex());
        fftw_destroy_plan(forward_);
        fftw_destroy_plan(backward_);
        fftw_free(real_);
        fftw_free(spectrum_);
    }

    std::size_t real_size() const { return real_size_; }
    std::size_t complex_size() const { return complex_size_; }
    const std::array<std::size_t, D>& shape() const { return n_; }

    // The unnormalised DFT of f (sum_j f_j e^(-2 pi i k.j/n)).
    std::vector<std::complex<double>> forward(std::span<const double> f) {
        std::copy(f.begin(), f.end(), real_);
        fftw_execute(forward_);
        const auto* s = reinterpret_cast<const std::complex<double>*>(spectrum_);
        return {s, s + complex_size_};
    }
    // The inverse DFT divided by the number of points (so backward(forward(f)) = f).
    std::vector<double> backward(std::span<const std::complex<double>> s) {
        std::copy(s.begin(), s.end(), reinterpret_cast<std::complex<double>*>(spectrum_));
        fftw_execute(backward_);  // c2r overwrites its input: the spectrum is a scratch copy
        std::vector<double> f(real_, real_ + real_size_);
        for (double& x : f) x /= static_cast<double>(real_size_);
        return f;
    }

    // The signed wavenumber index of spectrum entry `flat` along each axis
    // (k in (-n/2, n/2]; the last axis holds 0..n/2 only).
    std::array<long, D> wavenumber(std::size_t flat) const {
        std::array<long, D> k{};
        for (int c = D - 1; c >= 0; --c) {
            const std::size_t len = c == D - 1 ? n_[c] / 2 + 1 : n_[c];
            const auto j = static_cast<long>(flat % len);
            flat /= len;
            const auto nc = static_cast<long>(n_[c]);
            k[c] = c == D - 1 ? j : (2 * j > nc ? j - nc : j);
        }
        return k;
    }

private:
    std::array<std::size_t, D> n_;
    std::array<int, D> dims_{};
    std::size_t real_size_, complex_size_;
    double* real_ = nullptr;
    fftw_complex* spectrum_ = nullptr;
    fftw_plan forward_ = nullptr, backward_ = nullptr;
};

}  // namespace detail
}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
