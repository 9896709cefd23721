// Belley's 1D estimates of f, f' and f'' from scattered samples (seed 002,
// chapter 2, §5): the classic SPH sum (§5.1), the trapezoidal sums (§5.2) and
// the Simpson sums (§5.3), for any 1D kernel of the runtime (the kernel is a
// parameter: StaticKernel<tables::X_D1> or a run-time mollify::Kernel).
//
//   const mollify::sph::Samples x(points);      // sorted, checked once
//   const mollify::sph::Estimator est(kernel, Rule::trapezoid, 1, x, h);
//   double df = est(x0, f);                     // estimate of f'(x0)
//
// Every estimate is linear in the sample values: weights(x0) gives w_j with
// estimate = sum_j w_j f_j, so one set of weights serves many functions.
// The support is found by binary search on the sorted samples: O(log N +
// neighbours) per evaluation point, never a scan over all N.
//
// Kernels and scaling. mollify's tables have support radius 1 and the
// runtime scales W_h(r) = h^-1 W(r/h) in 1D, W'_h = h^-2 W'(r/h), W''_h =
// h^-3 W''(r/h). Belley's k_{h,poly6} (his (8)) is 35/(32 h^7) (h^2 - x^2)^3,
// which is exactly mollify's poly6 W_h (table value 35/32 (1 - r^2)^3), and
// his k'_h, k''_h are its x-derivatives, i.e. W'_h(|x|) sign(x), W''_h(|x|).
// His discontinuous kernels (12), (16), (20) at h = 1 are mollify's box,
// box-d1, box-d2 (values 1/2; -1 for x > 0 (odd); -4 on [0, 1/2), 4 on
// [1/2, 1]), but they scale as derivatives of a delta: delta^(q)_h(x) =
// h^(-1-q) W(x/h) = h^-q W_h(x), q = 0, 1, 2. The runtime's value quantity
// scales only by h^-1, so the piecewise-constant path multiplies by h^-q
// (q read from the table: parity and mass, see box_order).
#pragma once

#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/kernel_concept.hpp>
#include <mollify/smoothing.hpp>
#include <mollify/table.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace mollify::sph {

// Which sum approximates the convolution f * k^(q)_h (Belley §5).
enum class Rule {
    classic,    // §5.1: sum_j (m_j / rho_j) f(x_j) k^(q)_h(x0 - x_j), rho_j = sum_k m_k k_h(x_j - x_k)
    trapezoid,  // §5.2: trapezoidal rule on the samples in [x0 - h, x0 + h], augmented by x0 +- h
    simpson,    // §5.3: Simpson's rule on the piecewise quadratic interpolant f~
};

inline const char* rule_name(Rule r) {
    switch (r) {
        case Rule::classic: return "classic";
        case Rule::trapezoid: return "trapezoid";
        case Rule::simpson: return "simpson";
    }
    return "?";
}

inline Rule rule(const std::string& name) {
    if (name == "classic") return Rule::classic;
    if (name == "trapezoid") return Rule::trapezoid;
    if (name == "simpson") return Rule::simpson;
    fail("unknown estimation rule '" + name + "' (classic, trapezoid, simpson)");
}

// The weights of one estimate over consecutive sample indices: estimate =
// sum_j w_j f_j. Grows to whatever indices are added.
class Weights {
public:
    void clear() {
        first_ = 0;
        w_.clear();
    }
    void add(std::size_t j, double w) {
        if (w_.empty()) {
            first_ = j;
            w_.assign(1, w);
            return;
        }
        if (j < first_) {
            w_.insert(w_.begin(), first_ - j, 0.0);
            first_ = j;
        } else if (j >= first_ + w_.size()) {
            w_.resize(j - first_ + 1, 0.0);
        }
        w_[j - first_] += w;
    }
    std::size_t first() const { return first_; }
    std::size_t size() const { return w_.size(); }
    const std::vector<double>& values() const { return w_; }
    double operator[](std::size_t j) const {
        return j >= first_ && j < first_ + w_.size() ? w_[j - first_] : 0.0;
    }

    // sum_j w_j f_j; checks only the values it uses (no O(N) scan): a NaN or
    // infinite f_j is an Error naming j and the value.
    double apply(std::span<const double> f) const {
        if (!w_.empty() && first_ + w_.size() > f.size())
            fail("estimate needs f[" + std::to_string(first_ + w_.size() - 1) + "] but only " +
                 std::to_string(f.size()) + " values were given");
        double sum = 0;
        for (std::size_t k = 0; k < w_.size(); ++k) {
            const double v = f[first_ + k];
            if (!std::isfinite(v))
                fail("sample value f[" + std::to_string(first_ + k) + "] = " + mollify::detail::show(v) +
                     " is not finite");
            sum += w_[k] * v;
        }
        return sum;
    }

private:
    std::size_t first_ = 0;
    std::vector<double> w_;
};

// Sorted sample points, checked once (O(N)): at least 3 (Simpson's
// quadratics need 3), finite, strictly increasing (Belley's points are
// distinct; interpolation divides by x_{j+1} - x_j). Keeps a view: the
// caller's array must outlive it.
class Samples {
public:
    explicit Samples(std::span<const double> x) : x_(x) {
        if (x.size() < 3) fail("need at least 3 sample points, got " + std::to_string(x.size()));
        for (std::size_t j = 0; j < x.size(); ++j)
            if (!std::isfinite(x[j]))
                fail("sample point x[" + std::to_string(j) + "] = " + mollify::detail::show(x[j]) + " is not finite");
        for (std::size_t j = 0; j + 1 < x.size(); ++j)
            if (!(x[j] < x[j + 1]))
                fail("sample points are not strictly increasing: x[" + std::to_string(j) +
                     "] = " + mollify::detail::show(x[j]) + " >= x[" + std::to_string(j + 1) +
                     "] = " + mollify::detail::show(x[j + 1]));
    }

    std::span<const double> x() const { return x_; }
    std::size_t size() const { return x_.size(); }
    double operator[](std::size_t j) const { return x_[j]; }

    // The samples within distance h of x0, [first, last): the same test the
    // kernel makes, r = |x0 - x_j| <= h with the rounded difference. Rounded
    // subtraction is monotone, so the predicates below are monotone along
    // the sorted points and binary search finds exactly the brute-force set.
    std::pair<std::size_t, std::size_t> within(double x0, double h) const {
        const auto b = x_.begin();
        const auto lo = std::partition_point(b, x_.end(), [&](double xj) { return x0 - xj > h; });
        const auto hi = std::partition_point(lo, x_.end(), [&](double xj) { return xj - x0 <= h; });
        return {static_cast<std::size_t>(lo - b), static_cast<std::size_t>(hi - b)};
    }
    // First index with x_j >= a (N if none); number of samples <= b.
    std::size_t first_at_or_after(double a) const {
        return static_cast<std::size_t>(std::lower_bound(x_.begin(), x_.end(), a) - x_.begin());
    }
    std::size_t count_at_or_before(double b) const {
        return static_cast<std::size_t>(std::upper_bound(x_.begin(), x_.end(), b) - x_.begin());
    }

private:
    std::span<const double> x_;
};

namespace detail {

using mollify::detail::show;

// A piecewise-constant kernel (Belley's box family): every piece of W' has
// no term.
inline bool piecewise_constant(const table::Kernel& t) {
    const table::Quantity& d = t.quantities[static_cast<int>(QuantityId::dr)];
    for (int p = 0; p < d.npieces; ++p)
        if (d.pieces[p].nterms != 0) return false;
    return t.quantities[static_cast<int>(QuantityId::value)].npieces > 0;
}

// Which derivative a piecewise-constant kernel estimates, read from its
// table: odd -> f' (Belley (16), int x W = -1); even with mass 1 -> f
// ((12)); even with zero mass -> f'' ((20), int x^2 W = 2). The mass of an
// even step function is 2 sum_k c_k (b_{k+1} - b_k), c_k at the piece's
// midpoint (table constants, so the sum is exact up to rounding).
inline int box_order(const table::Kernel& t) {
    if (t.parity < 0) return 1;
    const table::Quantity& v = t.quantities[static_cast<int>(QuantityId::value)];
    double mass = 0, scale = 0;
    for (int p = 0; p + 1 < v.npieces; ++p) {
        const double c = table::evaluate(v, 0.5 * (v.pieces[p].lo + v.pieces[p].hi));
        mass += 2 * c * (v.pieces[p].hi - v.pieces[p].lo);
        scale += 2 * std::abs(c) * (v.pieces[p].hi - v.pieces[p].lo);
    }
    return std::abs(mass) > 1e-12 * scale ? 0 : 2;
}

// Lagrange weights of the quadratic through x_{c-1}, x_c, x_{c+1} at t
// (Belley §5.3, f_{j',j,j''}); at the ends the stencil is shifted inwards
// (j' or j'' does not exist there; the study never reaches the ends).
struct Quadratic {
    std::size_t first;  // stencil first, first + 1, first + 2
    std::array<double, 3> w;
};

inline Quadratic quadratic_at(const Samples& x, std::size_t centre, double t) {
    std::size_t a = centre == 0 ? 0 : centre - 1;
    if (a + 2 >= x.size()) a = x.size() - 3;
    const double x0 = x[a], x1 = x[a + 1], x2 = x[a + 2];
    return {a,
            {(t - x1) * (t - x2) / ((x0 - x1) * (x0 - x2)), (t - x0) * (t - x2) / ((x1 - x0) * (x1 - x2)),
             (t - x0) * (t - x1) / ((x2 - x0) * (x2 - x1))}};
}

// Linear interpolation f-bar(t) by the closest samples on each side of t
// (Belley §5.2: f(x_m) - (f(x_m) - f(x_{m-1})) / (x_m - x_{m-1}) (x_m - t));
// a sample at t itself gets weight 1; beyond the first or last sample the
// end segment extrapolates (his Remark 3; the study never needs it).
inline void add_linear(const Samples& x, double t, double c, Weights& w) {
    std::size_t k = x.count_at_or_before(t);
    k = k == 0 ? 0 : k - 1;
    if (k + 1 >= x.size()) k = x.size() - 2;
    if (x[k] == t) {
        w.add(k, c);
        return;
    }
    const double lambda = (t - x[k]) / (x[k + 1] - x[k]);
    w.add(k, c * (1 - lambda));
    w.add(k + 1, c * lambda);
}

// c * int_a^b L, L the piecewise linear interpolant of the samples: the
// trapezoidal rule on the samples in [a, b] augmented by a and b with
// f-bar(a), f-bar(b) (Belley's T and S sums, §5.2), exact for L.
inline void add_trapezoid(const Samples& x, double a, double b, double c, Weights& w) {
    const std::size_t m = x.first_at_or_after(a), end = x.count_at_or_before(b);
    if (m >= end) {  // no sample inside: one segment
        add_linear(x, a, c * (b - a) / 2, w);
        add_linear(x, b, c * (b - a) / 2, w);
        return;
    }
    const std::size_t n = end - 1;
    add_linear(x, a, c * (x[m] - a) / 2, w);
    w.add(m, c * (x[m] - a) / 2);
    for (std::size_t j = m; j < n; ++j) {
        const double half = c * (x[j + 1] - x[j]) / 2;
        w.add(j, half);
        w.add(j + 1, half);
    }
    w.add(n, c * (b - x[n]) / 2);
    add_linear(x, b, c * (b - x[n]) / 2, w);
}

// c * Simpson's rule (42) for the quadratic of sample `centre` on [p, q]
// (exact: Simpson integrates quadratics exactly).
inline void add_simpson_piece(const Samples& x, std::size_t centre, double p, double q, double c, Weights& w) {
    const double k = c * (q - p) / 6;
    const Quadratic lp = quadratic_at(x, centre, p), lm = quadratic_at(x, centre, 0.5 * (p + q)),
                    lq = quadratic_at(x, centre, q);
    for (int l = 0; l < 3; ++l) w.add(lp.first + l, k * (lp.w[l] + 4 * lm.w[l] + lq.w[l]));
}

inline double midpoint(const Samples& x, std::size_t j) { return 0.5 * (x[j] + x[j + 1]); }  // x_{j,j+1}

// c * int_a^b f~ (Belley §5.3): f~ is the quadratic of x_m on [a, x_{m,m+1}),
// of x_j on [x_{j-1,j}, x_{j,j+1}) for m < j < n, of x_n on [x_{n-1,n}, b],
// x_m, x_n the first and last samples in [a, b]; each piece by Simpson.
// No sample in [a, b] (only for an x0 that is not a sample): the quadratic
// of the sample nearest to the middle.
inline void add_simpson(const Samples& x, double a, double b, double c, Weights& w) {
    const std::size_t m = x.first_at_or_after(a), end = x.count_at_or_before(b);
    if (m >= end) {
        const double mid = 0.5 * (a + b);
        std::size_t j = std::min(m, x.size() - 1);
        if (j > 0 && std::abs(x[j - 1] - mid) < std::abs(x[j] - mid)) --j;
        add_simpson_piece(x, j, a, b, c, w);
        return;
    }
    const std::size_t n = end - 1;
    if (m == n) {
        add_simpson_piece(x, m, a, b, c, w);
        return;
    }
    add_simpson_piece(x, m, a, midpoint(x, m), c, w);
    for (std::size_t j = m + 1; j < n; ++j) add_simpson_piece(x, j, midpoint(x, j - 1), midpoint(x, j), c, w);
    add_simpson_piece(x, n, midpoint(x, n - 1), b, c, w);
}

}  // namespace detail

// One estimator: kernel, rule, derivative order q (0: f, 1: f', 2: f'') and
// h, on fixed samples. Not thread-safe (scratch buffers): one per thread.
//
// Smooth kernels (poly6, Wendland, combinations; even, C^q or better):
//   classic   (5.1)  sum_j f_j k^(q)_h(x0 - x_j) / rho_j, m_j = 1 (the
//                    estimate does not depend on a uniform mass)
//   trapezoid (5.2)  T_{h,6}, T'_{h,6}, T''_{h,6}: the trapezoidal rule for
//                    f(t) k^(q)_h(x0 - t) on x0 - h, the samples in
//                    [x0 - h, x0 + h], x0 + h (f-bar at x0 +- h, where
//                    these kernels vanish, so his end terms have no f-bar)
//   simpson   (5.3)  Q''_{h,6}: Simpson's rule (42) for f~(t) k^(q)_h(x0 - t)
//                    on his pieces [x0 - h, x_{m-1,m}], [x_{j-1,j}, x_{j,j+1}]
//                    (m <= j <= n), [x_{n,n+1}, x0 + h] (oriented: an end
//                    piece may run backwards, as his sum of integrals does)
// Piecewise-constant kernels (box, box-d1, box-d2; q is the kernel's):
//   trapezoid (5.2)  T_{h,delta}, T'_{h,delta}, T''_{h,delta}: the kernel's
//                    constants times int L over its pieces, L the linear
//                    interpolant (his sums, written as integrals of L)
//   simpson   (5.3)  Q''_{h,delta}: the same with int f~
//   For an even step kernel K(u) = sum_k d_k 1{|u| <= rho_k} (d_k = c_k -
//   c_{k+1}): f * K = sum_k d_k int_{x0-rho_k}^{x0+rho_k}; for box-d2 this
//   is Belley's 4/h^3 S(h) - 8/h^3 S(h/2). Odd (box-d1): sign(x0 - t), i.e.
//   1/h^2 (int_{x0}^{x0+h} - int_{x0-h}^{x0}), his T'_{h,delta}.
template <RadialKernel K>
class Estimator {
public:
    Estimator(const K& kernel, Rule rule, int derivative, const Samples& samples, double h)
        : kernel_(kernel), rule_(rule), q_(derivative), x_(&samples), s_(h, 1), h_(h) {
        const table::Kernel& t = kernel.table();
        if (t.dim != 1) fail("Belley's estimates are 1D; kernel " + std::string(t.spec) + " is D = " + std::to_string(t.dim));
        if (derivative < 0 || derivative > 2)
            fail("derivative order " + std::to_string(derivative) + " is not 0, 1 or 2");
        box_ = detail::piecewise_constant(t);
        if (box_) {
            const int order = detail::box_order(t);
            if (order != derivative)
                fail("kernel " + std::string(t.spec) + " estimates derivative " + std::to_string(order) +
                     ", not derivative " + std::to_string(derivative));
            if (rule == Rule::classic)
                fail("the classic SPH sum needs a continuous kernel; " + std::string(t.spec) +
                     " is a step function (use rule trapezoid or simpson)");
            setup_steps(t);
        } else {
            if (t.parity < 0) fail("kernel " + std::string(t.spec) + " is odd; the smooth-kernel sums need an even kernel");
            if (t.smoothness < derivative)
                fail("kernel " + std::string(t.spec) + " is C^" + std::to_string(t.smoothness) +
                     "; its derivative " + std::to_string(derivative) + " is not a function");
            if (rule == Rule::classic) setup_density();
        }
    }

    Rule rule() const { return rule_; }
    int derivative() const { return q_; }
    double h() const { return h_; }
    bool step_kernel() const { return box_; }
    const Samples& samples() const { return *x_; }
    // rho_j (classic rule only; empty otherwise).
    const std::vector<double>& density() const { return rho_; }

    // The weights of the estimate of f^(q)(x0): estimate = sum_j w_j f_j.
    void weights(double x0, Weights& w) const {
        if (!std::isfinite(x0)) fail("evaluation point x0 = " + detail::show(x0) + " is not finite");
        w.clear();
        if (box_) {
            step_weights(x0, w);
        } else if (rule_ == Rule::classic) {
            classic_weights(x0, w);
        } else if (rule_ == Rule::trapezoid) {
            trapezoid_weights(x0, w);
        } else {
            simpson_weights(x0, w);
        }
    }

    double operator()(double x0, std::span<const double> f) const {
        if (f.size() != x_->size())
            fail(std::to_string(f.size()) + " sample values for " + std::to_string(x_->size()) + " points");
        weights(x0, scratch_);
        return scratch_.apply(f);
    }

private:
    QuantityId quantity() const { return q_ == 0 ? QuantityId::value : q_ == 1 ? QuantityId::dr : QuantityId::d2r; }

    // k^(q)_h at the displacements u (x0 - t): W^(q)_h(|u|), times sign(u)
    // for q = 1 (the x-derivative of an even kernel; sign(0) = 0 where W'(0)
    // = 0 anyway, or, for a cusp, the symmetric value).
    void kernel_at(std::span<const double> u, std::span<double> out) const {
        radii_.resize(u.size());
        for (std::size_t k = 0; k < u.size(); ++k) radii_[k] = std::abs(u[k]);
        kernel_.evaluate(quantity(), radii_, s_, out);
        if (q_ == 1)
            for (std::size_t k = 0; k < u.size(); ++k) out[k] = u[k] > 0 ? out[k] : u[k] < 0 ? -out[k] : 0.0;
    }

    void setup_density() {
        const Samples& x = *x_;
        rho_.assign(x.size(), 0.0);
        std::vector<double> r, w;
        for (std::size_t j = 0; j < x.size(); ++j) {
            const auto [lo, hi] = x.within(x[j], h_);
            r.resize(hi - lo);
            w.resize(hi - lo);
            for (std::size_t k = lo; k < hi; ++k) r[k - lo] = std::abs(x[j] - x[k]);
            kernel_.evaluate(QuantityId::value, r, s_, w);
            double sum = 0;
            for (const double v : w) sum += v;  // m_k = 1
            rho_[j] = sum;  // > 0: x_j itself contributes W_h(0) > 0
        }
    }

    void classic_weights(double x0, Weights& w) const {
        const Samples& x = *x_;
        const auto [lo, hi] = x.within(x0, h_);
        u_.resize(hi - lo);
        k_.resize(hi - lo);
        for (std::size_t j = lo; j < hi; ++j) u_[j - lo] = x0 - x[j];
        kernel_at(u_, k_);
        for (std::size_t j = lo; j < hi; ++j) w.add(j, k_[j - lo] / rho_[j]);
    }

    // Nodes t_0 = x0 - h, the samples within h, t_last = x0 + h; the
    // trapezoidal weight of node s is g_s (t_{s+1} - t_{s-1}) / 2, g = f k.
    void trapezoid_weights(double x0, Weights& w) const {
        const Samples& x = *x_;
        const auto [lo, hi] = x.within(x0, h_);
        const std::size_t n = hi - lo;
        u_.resize(n + 2);
        k_.resize(n + 2);
        u_[0] = h_;  // t = x0 - h: exactly distance h, not a rounded x0 - (x0 - h)
        for (std::size_t j = lo; j < hi; ++j) u_[j - lo + 1] = x0 - x[j];
        u_[n + 1] = -h_;
        kernel_at(u_, k_);
        // Node positions in the displacement variable: t_{s+1} - t_{s-1} = u_{s-1} - u_{s+1}.
        for (std::size_t s = 0; s < n + 2; ++s) {
            const double before = s == 0 ? u_[0] : u_[s - 1], after = s == n + 1 ? u_[n + 1] : u_[s + 1];
            const double weight = k_[s] * (before - after) / 2;
            if (s == 0) {
                if (weight != 0) detail::add_linear(x, x0 - h_, weight, w);
            } else if (s == n + 1) {
                if (weight != 0) detail::add_linear(x, x0 + h_, weight, w);
            } else {
                w.add(lo + s - 1, weight);
            }
        }
    }

    // Belley's Q''_{h,6} pieces (§5.3); the kernel at the piece ends and
    // middles, one batch.
    void simpson_weights(double x0, Weights& w) const {
        const Samples& x = *x_;
        const auto [lo, hi] = x.within(x0, h_);
        pieces_.clear();
        if (lo >= hi) {  // no sample within h (an x0 between far-apart samples)
            std::size_t j = std::min(lo, x.size() - 1);
            if (j > 0 && std::abs(x[j - 1] - x0) < std::abs(x[j] - x0)) --j;
            pieces_.push_back({x0 - h_, x0 + h_, j});
        } else {
            const std::size_t m = lo, n = hi - 1;
            const double left = m == 0 ? x0 - h_ : detail::midpoint(x, m - 1);
            const double right = n + 1 == x.size() ? x0 + h_ : detail::midpoint(x, n);
            pieces_.push_back({x0 - h_, left, m});
            for (std::size_t j = m; j <= n; ++j)
                pieces_.push_back({j == m ? left : detail::midpoint(x, j - 1), j == n ? right : detail::midpoint(x, j), j});
            pieces_.push_back({right, x0 + h_, n});
        }
        const std::size_t p = pieces_.size();
        u_.resize(3 * p);
        k_.resize(3 * p);
        for (std::size_t i = 0; i < p; ++i) {
            const PieceT& piece = pieces_[i];
            // The outer ends are exactly x0 -+ h: displacement +-h, not rounded.
            u_[3 * i] = i == 0 ? h_ : x0 - piece.a;
            u_[3 * i + 1] = x0 - 0.5 * (piece.a + piece.b);
            u_[3 * i + 2] = i + 1 == p ? -h_ : x0 - piece.b;
        }
        kernel_at(u_, k_);
        for (std::size_t i = 0; i < p; ++i) {
            const PieceT& piece = pieces_[i];
            if (piece.a == piece.b) continue;
            const double c = (piece.b - piece.a) / 6;
            const detail::Quadratic qa = detail::quadratic_at(x, piece.centre, piece.a),
                                    qm = detail::quadratic_at(x, piece.centre, 0.5 * (piece.a + piece.b)),
                                    qb = detail::quadratic_at(x, piece.centre, piece.b);
            for (int l = 0; l < 3; ++l)
                w.add(qa.first + l, c * (k_[3 * i] * qa.w[l] + 4 * k_[3 * i + 1] * qm.w[l] + k_[3 * i + 2] * qb.w[l]));
        }
    }

    // The step kernel as nested intervals: radii rho_k = b_{k+1} h and jumps
    // d_k = c_k - c_{k+1}, c_k = h^-q W_h at the middle of piece k (Belley's
    // scaling; see the top of this file).
    void setup_steps(const table::Kernel& t) {
        const table::Quantity& v = t.quantities[static_cast<int>(QuantityId::value)];
        const int inner = v.npieces - 1;  // the last piece is the exterior
        std::vector<double> mid(static_cast<std::size_t>(inner)), c(static_cast<std::size_t>(inner));
        for (int p = 0; p < inner; ++p) mid[p] = h_ * 0.5 * (v.pieces[p].lo + v.pieces[p].hi);
        kernel_.evaluate(QuantityId::value, mid, s_, c);
        const double to_belley = std::pow(h_, -q_);
        steps_.clear();
        for (int p = 0; p < inner; ++p) {
            const double next = p + 1 < inner ? c[p + 1] : 0.0;
            const double jump = (c[p] - next) * to_belley;
            if (jump != 0) steps_.push_back({v.pieces[p].hi * h_, jump});
        }
        odd_ = t.parity < 0;
    }

    void step_weights(double x0, Weights& w) const {
        const Samples& x = *x_;
        const auto integral = rule_ == Rule::simpson ? &detail::add_simpson : &detail::add_trapezoid;
        for (const auto& [radius, jump] : steps_) {
            if (odd_) {
                // K(u) = sign(u) * jump on |u| <= radius, u = x0 - t: t < x0 gives +.
                integral(x, x0 - radius, x0, jump, w);
                integral(x, x0, x0 + radius, -jump, w);
            } else {
                integral(x, x0 - radius, x0 + radius, jump, w);
            }
        }
    }

    K kernel_;
    Rule rule_;
    int q_;
    const Samples* x_;
    Smoothing s_;
    double h_;
    bool box_ = false;
    bool odd_ = false;
    std::vector<std::pair<double, double>> steps_;  // (radius, jump)
    std::vector<double> rho_;
    struct PieceT {
        double a, b;
        std::size_t centre;
    };
    mutable std::vector<double> u_, k_, radii_;
    mutable std::vector<PieceT> pieces_;
    mutable Weights scratch_;
};

// Belley's error measure (§5.1-5.3): the average over the samples x_i in
// [lo, hi] of |f^(q)(x_i) - estimate|, given the exact f^(q) at the samples.
// The samples in [lo, hi] are found by binary search.
template <class E>
double mean_abs_error(const E& estimator, std::span<const double> f, std::span<const double> exact, double lo, double hi) {
    const Samples& x = estimator.samples();
    if (exact.size() != x.size())
        fail(std::to_string(exact.size()) + " exact values for " + std::to_string(x.size()) + " points");
    const std::size_t first = x.first_at_or_after(lo), end = x.count_at_or_before(hi);
    if (first >= end) fail("no sample point in [" + detail::show(lo) + ", " + detail::show(hi) + "]");
    double sum = 0;
    for (std::size_t i = first; i < end; ++i) sum += std::abs(exact[i] - estimator(x[i], f));
    return sum / static_cast<double>(end - first);
}

}  // namespace mollify::sph
