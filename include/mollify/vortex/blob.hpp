// Periodic vortex blobs (period 1 in x): the velocity per unit circulation
// at (x, y) from a blob at 0 and all its images (x + n, y). The notes (001,
// "vortex blobs") regularise the Green's function; two kinds here:
//
// AlgebraicBlob: Krasny's delta^2 regularisation of the periodic kernel,
//     u = -sinh(2 pi y) / (2 (D + delta^2)),  v = sin(2 pi x) / (2 (D + delta^2)),
// D = cosh(2 pi y) - cos(2 pi x): the notes' sheet (N = 400, delta = 0.25).
// Near 0, D ~ 2 pi^2 r^2, so it is the free-space algebraic blob
// (-y, x) / (2 pi (r^2 + delta_f^2)) with delta_f = delta / (sqrt(2) pi).
//
// CompactBlob: a mollifier W_h of the tables (support radius h <= 1/2),
// whose mass fraction inside r is 2 pi r phi'(r) (Delta phi = W, 2D), so a
// free blob moves fluid at (-y, x) phi'(r)/r. Beyond r = h it is the point
// vortex, so the periodic sum is exact in closed form: the row of point
// vortices, with the nearest image's point vortex replaced by the blob
// when it lies inside the support (the only image that can, for h <= 1/2).
#pragma once

#include <mollify/dynamic_kernel.hpp>
#include <mollify/error.hpp>
#include <mollify/vortex/periodic_point_vortex.hpp>

#include <cmath>
#include <string>

namespace mollify::vortex {

class AlgebraicBlob {
public:
    explicit AlgebraicBlob(double delta) : delta2_(delta * delta) {
        if (!(delta > 0) || !std::isfinite(delta))
            fail("vortex blob: delta = " + mollify::detail::show(delta) + " is not a positive finite number");
    }
    Velocity operator()(double x, double y) const { return detail::krasny(detail::nearest_image(x), y, delta2_); }
    std::string name() const { return "algebraic"; }

private:
    double delta2_;
};

class CompactBlob {
public:
    CompactBlob(Kernel kernel, double h) : kernel_(kernel), h_(h) {
        if (kernel_.dim() != 2) fail("vortex blob: kernel " + std::string(kernel_.spec()) + " is not a 2D kernel");
        if (!kernel_.has_potential())
            fail("vortex blob: kernel " + std::string(kernel_.spec()) + " has no potential in the tables (its velocity is phi'/r)");
        if (!(h > 0) || !(h <= 0.5))
            fail("vortex blob: support radius h = " + mollify::detail::show(h) +
                 " is not in (0, 1/2] (one image at most inside the support, period 1)");
    }
    Velocity operator()(double x, double y) const {
        x = detail::nearest_image(x);
        const double r = std::hypot(x, y);
        if (r >= h_) return detail::krasny(x, y, 0.0);
        const Velocity images = periodic_point_vortex_images(x, y);
        const double g = kernel_(QuantityId::dpotential_over_r, r, h_);
        return {images[0] - y * g, images[1] + x * g};
    }
    std::string name() const { return std::string(kernel_.spec()); }

private:
    Kernel kernel_;
    double h_;
};

}  // namespace mollify::vortex
