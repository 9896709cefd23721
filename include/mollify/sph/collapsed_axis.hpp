// An axis of a cell list in R^D (D >= 2) whose particles spread far beyond
// what ~N cells of side eps can cover: a dense cluster and particles far
// from it, clusters far apart, a diffuse envelope. Uniform cells would then
// be as wide as the particles' spread over N^(1/D), and a cluster's
// candidates would grow like its size squared. Here the axis is a lattice
// of slabs of width side 2^level (side a little over eps); each run of
// slabs that held particles when the runs were found (those holding at
// least `threshold` particles, widened by a margin of two slabs for the
// particles' next moves) gets cells of its own, one per slab, and each
// stretch of slabs between the runs is collapsed into one cell. Which level
// and threshold: Layout::choose, the finest level, and at it the smallest
// threshold, whose cells fit the budget.
//
// Why the 3^D stencil stays exact: the map from position to cell never
// decreases and grows by at most one from a slab of width side to the next,
// so two particles within eps of each other (at most one such slab apart)
// lie in cells at most one apart, whatever slab they are in: a particle in
// a slab outside the runs (one dropped by the threshold, or empty when the
// runs were found) shares its collapsed cell, which costs time, never a
// pair (CellList counts such particles and finds the runs again when more
// of them have strayed).
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/parallel.hpp>  // MOLLIFY_SIMD
#include <mollify/sph/graded_axis.hpp>  // slab_margin

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN  // its MOLLIFY_SIMD loops (detail/isa.hpp)

namespace mollify::sph {
inline namespace MOLLIFY_ISA {
namespace detail {

// One axis's occupied slabs of width side from origin (positions clamped to
// within 2^30 slabs of it), sorted, each with its particle count; and the
// runs of consecutive ones at a level (slabs 2^level times as wide).
class OccupiedSlabs {
public:
    struct Run {
        double first, last, total;  // slabs (at the run's level) and particles
    };

    // Slabs of width eps slab_margin (graded_axis.hpp), positions clamped
    // to within 2^30 slabs of origin: the slab floor((v - origin)/side) is
    // then off by at most 2^-21. Clamping, like the coarser levels'
    // floor(slab / 2^level), moves no two positions further apart in slabs.
    OccupiedSlabs(std::span<const double> x, double origin, double eps) : origin_(origin), side_(eps * slab_margin) {
        std::vector<double> slabs(x.size());
        std::transform(x.begin(), x.end(), slabs.begin(), [&](double v) { return slab(v); });
        std::sort(slabs.begin(), slabs.end());
        for (std::size_t k = 0; k < slabs.size(); ++k) {
            if (k > 0 && slabs[k] == slabs[k - 1]) ++counts_.back().second;
            else counts_.emplace_back(slabs[k], 1.0);
        }
    }

    double slab(double v) const { return slab(v, origin_, side_); }
    static double slab(double v, double origin, double side) {
        const double reach = 0x1p30 * side;
        return std::floor((std::clamp(v, origin - reach, origin + reach) - origin) / side);
    }

    // The runs of occupied slabs 2^level times as wide, in order.
    std::vector<Run> runs(int level) const {
        const double scale = std::ldexp(1.0, -level);
        std::vector<Run> out;
        for (const auto& [s, count] : counts_) {
            const double t = std::floor(s * scale);
            if (!out.empty() && t <= out.back().last + 1) {
                out.back().last = t;
                out.back().total += count;
            } else {
                out.push_back({t, t, count});
            }
        }
        return out;
    }

    double origin() const { return origin_; }
    double side() const { return side_; }

private:
    double origin_, side_;
    std::vector<std::pair<double, double>> counts_;  // occupied slab, its particles
};

class CollapsedAxis {
public:
    using Run = OccupiedSlabs::Run;
    static constexpr double margin = 2;  // slabs added on each side of a run

    // The runs with at least `threshold` particles, each widened by the
    // margin, those that then touch merged: {first, last} slabs.
    static std::vector<std::pair<double, double>> kept(const std::vector<Run>& runs, double threshold) {
        std::vector<std::pair<double, double>> out;
        for (const Run& r : runs) {
            if (r.total < threshold) continue;
            const double first = r.first - margin, last = r.last + margin;
            if (!out.empty() && first <= out.back().second + 1) out.back().second = last;
            else out.emplace_back(first, last);
        }
        return out;
    }

    // The cells such runs take: one below the first run, each run's slabs
    // and one after each run.
    static double cells(const std::vector<std::pair<double, double>>& runs) {
        double count = 1;
        for (const auto& [first, last] : runs) count += last - first + 2;
        return count;
    }

    CollapsedAxis(const OccupiedSlabs& slabs, int level, const std::vector<std::pair<double, double>>& runs)
        : origin_(slabs.origin()), side_(slabs.side()), scale_(std::ldexp(1.0, -level)) {
        long count = 1;  // cell 0: the slabs below the first run
        for (const auto& [first, last] : runs) {
            first_.push_back(first);
            length_.push_back(last - first + 1);
            cell_.push_back(count);
            count += static_cast<long>(last - first) + 2;  // the run and the collapsed cell after it
        }
        count_ = count;
    }

    long count() const { return count_; }

    // The cell of position v, and whether it lies outside every run (in a
    // collapsed cell): the last run starting at or below its slab, by
    // bisection.
    std::pair<std::size_t, bool> coordinate(double v) const {
        const double s = slab(v);
        const auto after = std::upper_bound(first_.begin(), first_.end(), s);
        if (after == first_.begin()) return {0, true};
        const std::size_t run = static_cast<std::size_t>(after - first_.begin()) - 1;
        const double into = s - first_[run];
        const bool outside = into >= length_[run];
        return {static_cast<std::size_t>(cell_[run] + static_cast<long>(outside ? length_[run] : into)), outside};
    }

    // k[i] = k[i] count() + the cell of v[i], for i < n; the number of v
    // outside every run. Where the runs are few, in chunks of points, one
    // loop over the chunk per run adding its term (add_run), which
    // vectorises (omp simd: at -O2 GCC's cost model leaves it scalar);
    // otherwise a bisection per point.
    std::size_t append_coordinates(const double* v, std::size_t n, std::size_t* k) const {
        const std::size_t count = static_cast<std::size_t>(count_);
        std::size_t strays = 0;
        if (first_.size() > few) {
            for (std::size_t i = 0; i < n; ++i) {
                const auto [cell, outside] = coordinate(v[i]);
                k[i] = k[i] * count + cell;
                strays += outside;
            }
            return strays;
        }
        constexpr std::size_t chunk = 256;
        double s[chunk], cell[chunk], runs[chunk];
        for (std::size_t from = 0; from < n; from += chunk) {
            const std::size_t m = std::min(chunk, n - from);
            MOLLIFY_SIMD
            for (std::size_t i = 0; i < m; ++i) {
                s[i] = slab(v[from + i]);
                cell[i] = runs[i] = 0;
            }
            for (std::size_t r = 0; r < first_.size(); ++r) {
                const double first = first_[r], length = length_[r];
                MOLLIFY_SIMD
                for (std::size_t i = 0; i < m; ++i) add_run(s[i], first, length, cell[i], runs[i]);
            }
            MOLLIFY_SIMD_SUM(strays)
            for (std::size_t i = 0; i < m; ++i) {
                k[from + i] = k[from + i] * count + static_cast<std::size_t>(cell[i]);
                strays += runs[i] == 0;
            }
        }
        return strays;
    }

private:
    static constexpr std::size_t few = 8;

    // The cell of slab s is the sum over the runs of clamp(s - first + 1, 0,
    // length + 1): a run below s adds its cells and the collapsed one after
    // it, the run holding s its cells up to s, a run above s nothing.
    // add_run adds one run's term to `cell`, and 1 to `runs` where s lies
    // in it (arithmetic and selects only: it vectorises over points; with
    // more than `few` runs, coordinate's bisection costs less).
    static void add_run(double s, double first, double length, double& cell, double& runs) {
        const double t = s - first + 1;  // s's place in the run, 1 at its first slab
        cell += std::min(std::max(t, 0.0), length + 1);
        runs += t >= 1 && t <= length ? 1.0 : 0.0;
    }

    // OccupiedSlabs::slab at this level.
    double slab(double v) const { return std::floor(OccupiedSlabs::slab(v, origin_, side_) * scale_); }

    double origin_, side_, scale_;  // scale_ = 2^-level
    std::vector<double> first_, length_;  // each run's first slab and its number of slabs
    std::vector<long> cell_;              // each run's first cell
    long count_ = 1;
};

}  // namespace detail
}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph

MOLLIFY_VECTOR_MISSES_ALLOWED_END
