// The hierarchical subdivision of the sources into clusters (notes 001,
// "Barnes-Hut treecode: tree = hierarchical subdivision of the particles
// into clusters c"): a quadtree (2D) or octree (3D) of boxes, each box
// split at its midpoint into 2^D children until it holds at most leaf_size
// sources. The sources are permuted so that every cell is a contiguous range
// [begin, end). Each cell keeps what the multipole acceptance test needs:
// its centre c (the box centre), radius rho = max |x_j - c| over its
// sources, and the largest smoothing length delta in it; and, for the near
// field, the bounding box of its sources.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/error.hpp>

#include <algorithm>
#include <cmath>
#include <array>
#include <cstddef>
#include <numeric>
#include <span>
#include <string>
#include <vector>

namespace mollify::poisson {
inline namespace MOLLIFY_ISA {

template <int D>
struct Cell {
    std::array<double, D> centre;
    double half;       // half the box side
    double radius;     // max |x_j - centre| over the cell's sources
    double delta_max;  // largest smoothing length in the cell
    std::array<double, D> lo, hi;  // bounding box of the cell's sources (their coordinates' min and max)
    std::size_t begin, end;
    int first_child = -1, children = 0;  // children are contiguous in Tree::cells
    bool leaf() const { return children == 0; }
};

template <int D>
class Tree {
public:
    // x: D coordinate arrays, delta: per source (or one value); leaf_size >= 1.
    Tree(const std::array<std::span<const double>, D>& x, std::span<const double> delta, int leaf_size)
        : delta_(delta), leaf_size_(leaf_size) {
        if (leaf_size < 1) fail("tree leaf size " + std::to_string(leaf_size) + " is not >= 1");
        const std::size_t n = x[0].size();
        order_.resize(n);
        std::iota(order_.begin(), order_.end(), std::size_t{0});
        std::array<double, D> lo, hi;
        for (int c = 0; c < D; ++c) {
            const auto [a, b] = std::minmax_element(x[c].begin(), x[c].end());
            lo[c] = *a;
            hi[c] = *b;
        }
        double half = 0;
        Cell<D> root{};
        for (int c = 0; c < D; ++c) {
            root.centre[c] = lo[c] + 0.5 * (hi[c] - lo[c]);
            half = std::max(half, 0.5 * (hi[c] - lo[c]));
        }
        root.half = half;
        root.begin = 0;
        root.end = n;
        cells_.push_back(root);
        // The coordinates (and smoothing lengths) in tree order while the
        // tree is built: each level reads its cells' sources in sequence
        // instead of through order_ (at N = 10^6 the build took ~4 % of a
        // treecode evaluation, mostly in those scattered reads).
        for (int c = 0; c < D; ++c) at_[c].assign(x[c].begin(), x[c].end());
        if (delta.size() != 1) delta_at_.assign(delta.begin(), delta.end());
        split(0, 0);
        at_ = {};
        delta_at_ = {};
        child_ = {};
        moved_ = {};
        moved_order_ = {};
    }

    const std::vector<Cell<D>>& cells() const { return cells_; }
    // Source order in the tree: position i holds the caller's source order()[i].
    const std::vector<std::size_t>& order() const { return order_; }
    int depth() const { return depth_; }

private:
    // Coincident or nearly coincident sources: a box below this many levels is a leaf.
    static constexpr int max_depth = 40;

    double coordinate(std::size_t i, int c) const { return at_[c][i]; }
    double delta_of(std::size_t i) const { return delta_.size() == 1 ? delta_[0] : delta_at_[i]; }

    void finish(Cell<D>& cell) const {
        cell.radius = 0;
        cell.delta_max = 0;
        cell.lo = cell.hi = cell.centre;
        if (cell.begin < cell.end)
            for (int c = 0; c < D; ++c) cell.lo[c] = cell.hi[c] = coordinate(cell.begin, c);
        for (std::size_t i = cell.begin; i < cell.end; ++i) {
            double r2 = 0;
            for (int c = 0; c < D; ++c) {
                const double d = coordinate(i, c) - cell.centre[c];
                r2 += d * d;
                cell.lo[c] = std::min(cell.lo[c], coordinate(i, c));
                cell.hi[c] = std::max(cell.hi[c], coordinate(i, c));
            }
            cell.radius = std::max(cell.radius, std::sqrt(r2));
            cell.delta_max = std::max(cell.delta_max, delta_of(i));
        }
    }

    void split(int index, int level) {
        depth_ = std::max(depth_, level);
        Cell<D> cell = cells_[static_cast<std::size_t>(index)];
        finish(cell);
        const bool small = cell.end - cell.begin <= static_cast<std::size_t>(leaf_size_);
        if (small || level >= max_depth || cell.radius == 0) {
            cells_[static_cast<std::size_t>(index)] = cell;
            return;
        }
        // Sort [begin, end) by the child box (bit c: coordinate c above the
        // centre), stably: counts, then each source moved once.
        constexpr int nchild = 1 << D;
        std::array<std::size_t, nchild + 1> bound{};
        const std::size_t n = cell.end - cell.begin;
        child_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            int b = 0;
            for (int c = 0; c < D; ++c)
                if (coordinate(cell.begin + i, c) >= cell.centre[c]) b |= 1 << c;
            child_[i] = static_cast<unsigned char>(b);
            ++bound[static_cast<std::size_t>(b) + 1];
        }
        bound[0] = cell.begin;
        for (int b = 0; b < nchild; ++b) bound[static_cast<std::size_t>(b) + 1] += bound[static_cast<std::size_t>(b)];
        std::array<std::size_t, nchild> next;
        std::copy(bound.begin(), bound.end() - 1, next.begin());
        move(cell.begin, n, next, order_, moved_order_);
        for (int c = 0; c < D; ++c) move(cell.begin, n, next, at_[c], moved_);
        if (!delta_at_.empty()) move(cell.begin, n, next, delta_at_, moved_);
        cell.first_child = static_cast<int>(cells_.size());
        for (int b = 0; b < nchild; ++b) {
            if (bound[static_cast<std::size_t>(b)] == bound[static_cast<std::size_t>(b) + 1]) continue;
            Cell<D> child{};
            child.half = 0.5 * cell.half;
            for (int c = 0; c < D; ++c) child.centre[c] = cell.centre[c] + ((b >> c) & 1 ? child.half : -child.half);
            child.begin = bound[static_cast<std::size_t>(b)];
            child.end = bound[static_cast<std::size_t>(b) + 1];
            cells_.push_back(child);
            ++cell.children;
        }
        cells_[static_cast<std::size_t>(index)] = cell;
        const int first_child = cell.first_child, children = cell.children;
        for (int k = 0; k < children; ++k) split(first_child + k, level + 1);
    }

    // v[begin + i] to its child's next place (next: the children's first
    // places), through the scratch vector to.
    template <class T>
    void move(std::size_t begin, std::size_t n, std::array<std::size_t, 1 << D> next, std::vector<T>& v,
              std::vector<T>& to) const {
        to.resize(n);
        for (std::size_t i = 0; i < n; ++i) to[next[child_[i]]++ - begin] = v[begin + i];
        std::copy(to.begin(), to.end(), v.begin() + static_cast<std::ptrdiff_t>(begin));
    }

    std::span<const double> delta_;
    // While building: coordinates and smoothing lengths in tree order, each
    // source's child, a moved range.
    std::array<std::vector<double>, D> at_;
    std::vector<double> delta_at_;
    std::vector<unsigned char> child_;
    std::vector<double> moved_;
    std::vector<std::size_t> moved_order_;
    int leaf_size_;
    std::vector<std::size_t> order_;
    std::vector<Cell<D>> cells_;
    int depth_ = 0;
};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::poisson
