// Where the particles live: all of R^D (Franz §2.3, finitely many particles
// of a compactly supported density) or the periodic box [0, L)^D (the torus
// T^D of Franz §3.5), whose displacements are taken by the minimum image.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>

#include <cmath>
#include <string>

namespace mollify::sph {
inline namespace MOLLIFY_ISA {

template <int D>
class Domain {
public:
    static Domain whole_space() { return Domain(false, 0); }
    static Domain periodic(double length) {
        if (!(length > 0) || !std::isfinite(length))
            fail("periodic box length L = " + mollify::detail::show(length) + " is not a positive finite number");
        return Domain(true, length);
    }

    bool is_periodic() const { return periodic_; }
    double length() const { return length_; }

    // x - y, by the minimum image in a periodic box.
    double displacement(double x, double y) const {
        double d = x - y;
        if (periodic_) d -= length_ * std::nearbyint(d * inverse_);
        return d;
    }
    // x mapped into [0, L) (periodic), unchanged otherwise.
    double wrap(double x) const {
        if (!periodic_) return x;
        double w = x - length_ * std::floor(x / length_);
        return w < length_ ? w : 0.0;  // x = -tiny rounds up to L
    }

    // A kernel of support radius eps sees each neighbour once only while
    // 2 eps < L; beyond, a particle would interact with several images.
    void check_support(double eps) const {
        if (periodic_ && !(2 * eps < length_))
            fail("support radius eps = " + mollify::detail::show(eps) + " is not below half the periodic box length L = " +
                 mollify::detail::show(length_) + " (a particle would meet several images of a neighbour)");
    }

private:
    Domain(bool periodic, double length) : periodic_(periodic), length_(length), inverse_(periodic ? 1 / length : 0) {}
    bool periodic_;
    double length_, inverse_;
};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph
