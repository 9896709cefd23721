// How far a computed field is from a reference (the treecode's against
// direct summation, the periodic solver's against an exact field): the
// relative L2 error the accuracy knob's target means (tolerance.hpp), and
// the relative max error, in one place for the tests, the tools and the
// benchmarks (the peer's driver too: bench/peers/exafmm_t_laplace.cpp).
#pragma once

#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/poisson/sources.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

// ||a - reference||_2 / ||reference||_2 over every value added: a vector
// field's components added one by one give the L2 norm of the field over
// the targets (not a mean of the components' errors). Each norm is a scaled
// sum of squares (LAPACK's dnrm2), so that fields of any size, 1e-200 or
// 1e200, neither underflow to 0 nor overflow to inf. A zero reference gives
// 0 where a is zero too and +inf where it is not; a value that is not
// finite is an error naming it.
class RelativeL2 {
public:
    void add(std::span<const double> a, std::span<const double> reference) {
        if (a.size() != reference.size())
            fail("relative L2 error of " + std::to_string(a.size()) + " values against a reference of " +
                 std::to_string(reference.size()));
        for (std::size_t i = 0; i < a.size(); ++i) {
            if (!std::isfinite(a[i]) || !std::isfinite(reference[i]))
                fail("relative L2 error: value " + mollify::detail::show(a[i]) + " against reference " +
                     mollify::detail::show(reference[i]) + " at index " + std::to_string(i) + " is not finite");
            difference_.add(a[i] - reference[i]);
            reference_.add(reference[i]);
        }
    }
    double value() const {
        if (reference_.scale == 0) return difference_.scale == 0 ? 0.0 : std::numeric_limits<double>::infinity();
        return difference_.scale / reference_.scale * std::sqrt(difference_.sum / reference_.sum);
    }

private:
    // sum x^2 = scale^2 sum, scale the largest |x| so far (sum in [1, count]).
    struct SumOfSquares {
        double scale = 0, sum = 1;
        void add(double x) {
            const double ax = std::abs(x);
            if (ax == 0) return;
            if (scale < ax) {
                sum = 1 + sum * (scale / ax) * (scale / ax);
                scale = ax;
            } else {
                sum += (ax / scale) * (ax / scale);
            }
        }
    };
    SumOfSquares difference_, reference_;
};

inline double relative_l2(std::span<const double> a, std::span<const double> reference) {
    RelativeL2 e;
    e.add(a, reference);
    return e.value();
}

// Relative L2 and relative max errors of the potential and of the field:
// phi_max = max |phi - phi_ref| / max |phi_ref|, e_max = max |E - E_ref| /
// max |E_ref| with |.| the Euclidean length at a target.
struct FieldErrors {
    double phi_l2, phi_max, e_l2, e_max;
};

template <int D>
FieldErrors field_errors(const Field<D>& a, const Field<D>& reference) {
    if (a.size() != reference.size())
        fail("field at " + std::to_string(a.size()) + " targets compared with a reference at " +
             std::to_string(reference.size()));
    RelativeL2 e;
    for (int c = 0; c < D; ++c) e.add(a.field[c], reference.field[c]);
    double phi = 0, phi_ref = 0, diff = 0, diff_ref = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        phi = std::max(phi, std::abs(a.potential[i] - reference.potential[i]));
        phi_ref = std::max(phi_ref, std::abs(reference.potential[i]));
        double d2 = 0, r2 = 0;
        for (int c = 0; c < D; ++c) {
            const double d = a.field[c][i] - reference.field[c][i];
            d2 += d * d;
            r2 += reference.field[c][i] * reference.field[c][i];
        }
        diff = std::max(diff, std::sqrt(d2));
        diff_ref = std::max(diff_ref, std::sqrt(r2));
    }
    const auto ratio = [](double x, double of) {
        return of > 0 ? x / of : x == 0 ? 0.0 : std::numeric_limits<double>::infinity();
    };
    return {relative_l2(a.potential, reference.potential), ratio(phi, phi_ref), e.value(), ratio(diff, diff_ref)};
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
