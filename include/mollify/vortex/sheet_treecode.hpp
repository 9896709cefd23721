// The periodic sheet's velocity by a treecode (issue 21): the far field in
// O(N log N) instead of the O(N^2) direct sum of sheet.hpp (the near field,
// pairs within ~h, stays O(N * N h)), for compact blobs, whose velocity
// beyond the support radius h is exactly the point-vortex row
//     u - i v = sum_j Gamma_j cot(pi (z - z_j)) / (2 i)      (blob.hpp),
// so far clusters need no regularisation and near pairs keep the exact blob.
//
// A binary tree over the particles (x reduced to [0, 1), each cell split at
// the midpoint of its longer side) carries per cell C the moments
//     N_k = sum_{j in C} Gamma_j (-(z_j - c_C) / rho_C)^k,  k = 0..p,
// rho_C the largest |z_j - c_C|. For a leaf L of targets and a cell C whose
// nearest image zeta = c_L - c_C - n (|Re zeta| <= 1/2, so d = |zeta| is the
// distance to the nearest pole of cot(pi .)) satisfies
//     rho_L + rho_C <= theta d   and   d - rho_L - rho_C >= h
// (every pair then lies beyond the support at every image), the Taylor
// series of cot about zeta in t - delta (|t| <= rho_L, |delta| <= rho_C)
// gives the local expansion S(t) = sum_m b_m (t / rho_L)^m at L's targets:
//     b_m = sum_{k <= p - m} C(k+m, m) a_{k+m} (rho_C/d)^k (rho_L/d)^m N_k,
// a_j the Taylor coefficients of cot(pi (zeta + d tau)) in tau, from
// f' = -pi (1 + f^2):  (j+1) a_{j+1} = -pi d (delta_{j0} + sum_m a_m a_{j-m}).
// Everything is scaled by rho and d, so no power over- or underflows at any
// h. Truncation: the series in (t - delta)/d is cut at degree p, with
// |t - delta|/d <= theta, so a cell's error is about
//     |N_0| / (pi d) * theta^(p+1) / (1 - theta)
// relative to its own contribution (the nearest pole dominates; tests/
// vortex_test.cpp checks the sum against the direct velocity). Cells that
// fail the test are opened; leaves that fail it are summed pair by pair with
// the blob (near pairs exact).
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/vortex/sheet.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

namespace mollify::vortex {
inline namespace MOLLIFY_ISA {

template <class Blob>
class SheetTreecode {
public:
    static constexpr int max_order = 40;

    // theta in (0, 1): the opening ratio; order p in 1..40; leaf: the most
    // particles a leaf holds.
    SheetTreecode(Blob blob, double theta, int order, std::size_t leaf = 24)
        : blob_(std::move(blob)), theta_(theta), order_(order), leaf_(leaf) {
        if (!(theta > 0 && theta < 1))
            fail("vortex treecode: theta = " + mollify::detail::show(theta) + " is not in (0, 1)");
        if (order < 1 || order > max_order)
            fail("vortex treecode: order p = " + std::to_string(order) + " is outside 1.." + std::to_string(max_order));
        if (leaf < 1) fail("vortex treecode: leaf size 0");
        for (int n = 0; n <= max_order; ++n)
            for (int k = 0; k <= n; ++k) binomial_[n][k] = k == 0 || k == n ? 1.0 : binomial_[n - 1][k - 1] + binomial_[n - 1][k];
    }

    const Blob& blob() const { return blob_; }
    std::string name() const { return blob_.name(); }
    double theta() const { return theta_; }
    int order() const { return order_; }

    // The velocity at every particle from all the others (as velocity(blob, ...)).
    void velocity(const Sheet& s, std::vector<double>& u, std::vector<double>& v) const;

private:
    struct Complex {
        double re = 0, im = 0;
    };
    struct Cell {
        double cx, cy, rho;
        std::size_t begin, end;
        int left = -1, right = -1;
        bool leaf() const { return left < 0; }
    };
    struct Tree {
        std::vector<double> x, y, gamma;  // in tree order, x in [0, 1)
        std::vector<std::size_t> index;   // tree order -> sheet order
        std::vector<Cell> cells;
        std::vector<Complex> moments;  // (p + 1) per cell
        std::vector<int> leaves;
    };

    Tree build(const Sheet& s) const;
    int split(Tree& t, std::size_t begin, std::size_t end) const;
    void cell_moments(Tree& t, int c) const;
    void cot_taylor(double zr, double zi, double d, Complex* a) const;
    void add_local(const Tree& t, const Cell& target, const Cell& source, double zr, double zi, double d, Complex* b) const;

    Blob blob_;
    double theta_;
    int order_;
    std::size_t leaf_;
    double binomial_[max_order + 1][max_order + 1] = {};
};

template <class Blob>
typename SheetTreecode<Blob>::Tree SheetTreecode<Blob>::build(const Sheet& s) const {
    Tree t;
    const std::size_t n = s.size();
    t.index.resize(n);
    for (std::size_t j = 0; j < n; ++j) t.index[j] = j;
    t.x.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
        const double r = s.x[j] - std::floor(s.x[j]);
        t.x[j] = r < 1 ? r : 0.0;  // x = -tiny rounds to 1
    }
    t.y = s.y;
    t.cells.reserve(2 * (n / leaf_ + 1));
    split(t, 0, n);
    std::vector<double> px(n), py(n), pg(n);
    for (std::size_t j = 0; j < n; ++j) {
        px[j] = t.x[t.index[j]];
        py[j] = s.y[t.index[j]];
        pg[j] = s.gamma[t.index[j]];
    }
    t.x = std::move(px);
    t.y = std::move(py);
    t.gamma = std::move(pg);
    t.moments.assign(t.cells.size() * static_cast<std::size_t>(order_ + 1), Complex{});
    const int cells = static_cast<int>(t.cells.size());
#pragma omp parallel for schedule(dynamic, 16)
    for (int c = 0; c < cells; ++c) cell_moments(t, c);
    for (int c = 0; c < cells; ++c)
        if (t.cells[c].leaf()) t.leaves.push_back(c);
    return t;
}

// Cells in depth-first order over t.index (x, y still in sheet order).
template <class Blob>
int SheetTreecode<Blob>::split(Tree& t, std::size_t begin, std::size_t end) const {
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (std::size_t i = begin; i < end; ++i) {
        const std::size_t j = t.index[i];
        x0 = std::min(x0, t.x[j]);
        x1 = std::max(x1, t.x[j]);
        y0 = std::min(y0, t.y[j]);
        y1 = std::max(y1, t.y[j]);
    }
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    double rho = 0;
    for (std::size_t i = begin; i < end; ++i) {
        const std::size_t j = t.index[i];
        rho = std::max(rho, std::hypot(t.x[j] - cx, t.y[j] - cy));
    }
    const int c = static_cast<int>(t.cells.size());
    t.cells.push_back({cx, cy, rho, begin, end});
    if (end - begin <= leaf_ || rho == 0) return c;
    const bool along_x = x1 - x0 >= y1 - y0;
    const double cut = along_x ? cx : cy;
    const auto first = t.index.begin() + static_cast<std::ptrdiff_t>(begin), last = t.index.begin() + static_cast<std::ptrdiff_t>(end);
    auto mid = std::partition(first, last, [&](std::size_t j) { return (along_x ? t.x[j] : t.y[j]) < cut; });
    // The midpoint of a non-degenerate side leaves both halves non-empty,
    // unless rounding puts it on the lower end: then split by count.
    if (mid == first || mid == last) {
        mid = first + (last - first) / 2;
        std::nth_element(first, mid, last, [&](std::size_t a, std::size_t b) { return along_x ? t.x[a] < t.x[b] : t.y[a] < t.y[b]; });
    }
    const std::size_t m = static_cast<std::size_t>(mid - t.index.begin());
    const int left = split(t, begin, m);
    const int right = split(t, m, end);
    t.cells[c].left = left;
    t.cells[c].right = right;
    return c;
}

template <class Blob>
void SheetTreecode<Blob>::cell_moments(Tree& t, int c) const {
    const Cell& cell = t.cells[c];
    Complex* nk = &t.moments[static_cast<std::size_t>(c) * static_cast<std::size_t>(order_ + 1)];
    const double scale = cell.rho > 0 ? 1 / cell.rho : 0;
    for (std::size_t i = cell.begin; i < cell.end; ++i) {
        const double wr = -(t.x[i] - cell.cx) * scale, wi = -(t.y[i] - cell.cy) * scale;
        double power_re = t.gamma[i], power_im = 0;  // Gamma_j w^k
        for (int k = 0; k <= order_; ++k) {
            nk[k].re += power_re;
            nk[k].im += power_im;
            const double next_re = power_re * wr - power_im * wi;
            power_im = power_re * wi + power_im * wr;
            power_re = next_re;
        }
    }
}

// a_j, j = 0..p: Taylor coefficients of cot(pi (zeta + d tau)) in tau at
// zeta = zr + i zi, |zr| <= 1/2, d = |zeta| > 0.
template <class Blob>
void SheetTreecode<Blob>::cot_taylor(double zr, double zi, double d, Complex* a) const {
    constexpr double pi = std::numbers::pi;
    // cot(pi z) = 2 i (u - i v) = 2 v + 2 i u from the row's velocity (its
    // closed form, free of cancellation near z = 0 and of overflow far off).
    const Velocity row = detail::krasny(zr, zi, 0.0);
    a[0] = {2 * row[1], 2 * row[0]};
    for (int j = 0; j < order_; ++j) {
        double sr = j == 0 ? 1.0 : 0.0, si = 0;
        for (int m = 0; m <= j; ++m) {
            sr += a[m].re * a[j - m].re - a[m].im * a[j - m].im;
            si += a[m].re * a[j - m].im + a[m].im * a[j - m].re;
        }
        const double f = -pi * d / (j + 1);
        a[j + 1] = {f * sr, f * si};
    }
}

// b_m += sum_k C(k+m, m) a_{k+m} (rho_C/d)^k (rho_L/d)^m N_k: cell `source`
// as a local expansion about `target`'s centre, in units of rho_L.
template <class Blob>
void SheetTreecode<Blob>::add_local(const Tree& t, const Cell& target, const Cell& source, double zr, double zi, double d,
                                    Complex* b) const {
    Complex a[max_order + 1];
    cot_taylor(zr, zi, d, a);
    const Complex* nk = &t.moments[static_cast<std::size_t>(&source - t.cells.data()) * static_cast<std::size_t>(order_ + 1)];
    double sc[max_order + 1], sl[max_order + 1];
    sc[0] = sl[0] = 1;
    for (int k = 1; k <= order_; ++k) {
        sc[k] = sc[k - 1] * (source.rho / d);
        sl[k] = sl[k - 1] * (target.rho / d);
    }
    for (int m = 0; m <= order_; ++m) {
        double br = 0, bi = 0;
        for (int k = 0; k + m <= order_; ++k) {
            const double w = binomial_[k + m][m] * sc[k];
            const Complex& c = a[k + m];
            br += w * (c.re * nk[k].re - c.im * nk[k].im);
            bi += w * (c.re * nk[k].im + c.im * nk[k].re);
        }
        b[m].re += sl[m] * br;
        b[m].im += sl[m] * bi;
    }
}

template <class Blob>
void SheetTreecode<Blob>::velocity(const Sheet& s, std::vector<double>& u, std::vector<double>& v) const {
    detail::check(s);  // a NaN would otherwise be sorted into some cell
    const std::size_t n = s.size();
    u.assign(n, 0.0);
    v.assign(n, 0.0);
    const Tree t = build(s);
    const double h = blob_.support();
    const int leaves = static_cast<int>(t.leaves.size());
#pragma omp parallel
    {
        std::vector<int> stack, near;
        std::vector<double> dx, dy, g;
        Complex b[max_order + 1];
#pragma omp for schedule(dynamic, 4)
        for (int l = 0; l < leaves; ++l) {
            const Cell& target = t.cells[t.leaves[l]];
            std::fill(b, b + order_ + 1, Complex{});
            near.clear();
            stack.assign(1, 0);
            while (!stack.empty()) {
                const Cell& source = t.cells[stack.back()];
                const int c = stack.back();
                stack.pop_back();
                double zr = target.cx - source.cx;
                zr -= std::nearbyint(zr);
                const double zi = target.cy - source.cy, d = std::hypot(zr, zi), reach = target.rho + source.rho;
                if (reach <= theta_ * d && d - reach >= h)
                    add_local(t, target, source, zr, zi, d, b);
                else if (source.leaf())
                    near.push_back(c);
                else {
                    stack.push_back(source.right);
                    stack.push_back(source.left);
                }
            }
            const double scale = target.rho > 0 ? 1 / target.rho : 0;
            for (std::size_t i = target.begin; i < target.end; ++i) {
                // The local expansion at t = z_i - c_L (Horner in t / rho_L):
                // S = sum Gamma cot, u - i v = S / (2 i).
                const double tr = (t.x[i] - target.cx) * scale, ti = (t.y[i] - target.cy) * scale;
                double sr = 0, si = 0;
                for (int m = order_; m >= 0; --m) {
                    const double qr = sr * tr - si * ti + b[m].re;
                    si = sr * ti + si * tr + b[m].im;
                    sr = qr;
                }
                dx.clear();
                dy.clear();
                g.clear();
                for (const int c : near)
                    for (std::size_t j = t.cells[c].begin; j < t.cells[c].end; ++j) {
                        if (j == i) continue;
                        dx.push_back(t.x[i] - t.x[j]);
                        dy.push_back(t.y[i] - t.y[j]);
                        g.push_back(t.gamma[j]);
                    }
                const Velocity k = blob_.sum(dx, dy, g);
                u[t.index[i]] = k[0] + 0.5 * si;
                v[t.index[i]] = k[1] + 0.5 * sr;
            }
        }
    }
}

// The treecode in place of the direct sum: rk4_step and advance of
// sheet.hpp take it as they take a blob.
template <class Blob>
void velocity(const SheetTreecode<Blob>& tree, const Sheet& s, std::vector<double>& u, std::vector<double>& v) {
    tree.velocity(s, u, v);
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::vortex
