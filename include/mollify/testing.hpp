// GoogleTest matchers for SPH developers' own test suites (issue 20): a
// kernel written anywhere, as a callable (r, h) -> value, checked against
// the exact kernel (verify.hpp) at the hard points and seeded uniform points.
//
//   EXPECT_THAT(my_kernel, mollify::testing::MatchesKernel("wendland:k=2", 3).WithinUlps(4));
//   EXPECT_THAT(my_gradient, mollify::testing::MatchesKernel("cubic-spline", 3).Quantity("dr").Convention("phantom"));
//
// On failure the message is the report: max and RMS error in ulps, the worst
// arguments and the diagnosis (a constant factor, a support convention, ...).
// Link mollify::exact and GTest::gmock.
#pragma once

#include <mollify/verify.hpp>

#include <gmock/gmock.h>

#include <ostream>
#include <string>
#include <string_view>
#include <utility>

namespace mollify::testing {

class KernelMatcher {
public:
    using is_gtest_matcher = void;

    KernelMatcher(std::string spec, int dim) : spec_(std::move(spec)), dim_(dim) {}

    // The bound: the largest error allowed in ulps of the exact value.
    KernelMatcher WithinUlps(double ulps) const {
        KernelMatcher m = *this;
        m.options_.ulps = ulps;
        return m;
    }
    KernelMatcher Quantity(verify::Quantity q) const {
        KernelMatcher m = *this;
        m.quantity_ = q;
        return m;
    }
    // "value", "dr", "potential", "force", "grad_over_r" (mollify::Error for another name).
    KernelMatcher Quantity(std::string_view name) const { return Quantity(verify::parse_quantity(name)); }
    // "cpp" (default), "phantom", "swift", "gadget4", ... (verify.hpp, Options).
    KernelMatcher Convention(std::string name) const {
        KernelMatcher m = *this;
        m.options_.convention = std::move(name);
        return m;
    }
    KernelMatcher Seed(std::uint64_t seed) const {
        KernelMatcher m = *this;
        m.options_.seed = seed;
        return m;
    }
    KernelMatcher UniformPoints(std::size_t n) const {
        KernelMatcher m = *this;
        m.options_.uniform = n;
        return m;
    }

    // Any callable (r, h) -> a number.
    template <class F>
    bool MatchAndExplain(const F& f, std::ostream* os) const {
        const verify::Report report =
            verify::verify([&](double r, double h) { return static_cast<double>(f(r, h)); }, spec_, dim_, quantity_, options_);
        if (os) *os << "\n" << report.to_string();
        return report.passed();
    }

    void DescribeTo(std::ostream* os) const {
        *os << "is " << spec_ << " in D = " << dim_ << " (" << verify::name(quantity_) << ", convention "
            << options_.convention << ") within " << options_.ulps << " ulps of the exact value";
    }
    void DescribeNegationTo(std::ostream* os) const {
        *os << "is not " << spec_ << " in D = " << dim_ << " (" << verify::name(quantity_) << ", convention "
            << options_.convention << ") within " << options_.ulps << " ulps of the exact value";
    }

private:
    std::string spec_;
    int dim_;
    verify::Quantity quantity_ = verify::Quantity::value;
    verify::Options options_;
};

// The matcher of kernel `spec` in dimension `dim` (value, convention cpp, 4 ulps).
inline KernelMatcher MatchesKernel(std::string spec, int dim) { return KernelMatcher(std::move(spec), dim); }

}  // namespace mollify::testing
