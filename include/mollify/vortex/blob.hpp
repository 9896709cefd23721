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

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/dynamic_kernel.hpp>
#include <mollify/error.hpp>
#include <mollify/vortex/periodic_point_vortex.hpp>

#include <cmath>
#include <span>
#include <string>
#include <vector>

namespace mollify::vortex {
inline namespace MOLLIFY_ISA {

class AlgebraicBlob {
public:
    explicit AlgebraicBlob(double delta) : delta2_(delta * delta) {
        if (!(delta > 0) || !std::isfinite(delta))
            fail("vortex blob: delta = " + mollify::detail::show(delta) + " is not a positive finite number");
    }
    Velocity operator()(double x, double y) const { return detail::krasny(detail::nearest_image(x), y, delta2_); }
    // sum_j g_j K(dx_j, dy_j)
    Velocity sum(std::span<const double> dx, std::span<const double> dy, std::span<const double> g) const {
        double u = 0, v = 0;
        for (std::size_t j = 0; j < g.size(); ++j) {
            const Velocity k = (*this)(dx[j], dy[j]);
            u += g[j] * k[0];
            v += g[j] * k[1];
        }
        return {u, v};
    }
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
    // sum_j g_j K(dx_j, dy_j): the blobs inside the support through one
    // batch of the runtime (phi'/r), the rest through the closed form.
    Velocity sum(std::span<const double> dx, std::span<const double> dy, std::span<const double> g) const {
        thread_local std::vector<double> r, w;
        thread_local std::vector<std::size_t> near;
        r.clear();
        near.clear();
        double u = 0, v = 0;
        for (std::size_t j = 0; j < g.size(); ++j) {
            const double x = detail::nearest_image(dx[j]);
            // Outside the support by r^2 >= h^2 where h^2 is a normal number
            // (a pair misplaced by the rounding of r^2 lies within an ulp of
            // the edge, where blob and point vortex agree); hypot, slower,
            // for r itself and for extreme h.
            const bool outside = normal_h2_ ? x * x + dy[j] * dy[j] >= h2_ : std::hypot(x, dy[j]) >= h_;
            if (outside) {
                const Velocity k = detail::krasny(x, dy[j], 0.0);
                u += g[j] * k[0];
                v += g[j] * k[1];
            } else {
                r.push_back(std::hypot(x, dy[j]));
                near.push_back(j);
            }
        }
        w.resize(r.size());
        kernel_.evaluate(QuantityId::dpotential_over_r, r, smoothing_, w);
        for (std::size_t i = 0; i < near.size(); ++i) {
            const std::size_t j = near[i];
            const double x = detail::nearest_image(dx[j]);
            const Velocity images = periodic_point_vortex_images(x, dy[j]);
            u += g[j] * (images[0] - dy[j] * w[i]);
            v += g[j] * (images[1] + x * w[i]);
        }
        return {u, v};
    }
    std::string name() const { return std::string(kernel_.spec()); }
    // Beyond it the blob is the point-vortex row (sheet_treecode.hpp's far field).
    double support() const { return h_; }

private:
    Kernel kernel_;
    double h_;
    Smoothing smoothing_ = kernel_.smoothing(h_);
    double h2_ = h_ * h_;
    bool normal_h2_ = h_ >= 1e-150;  // h <= 1/2
};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::vortex
