// An axis of a cell list whose particles crowd part of its extent: a dense
// cluster (a collapsing cloud, a droplet) in a sparse background of a
// periodic box, or in R^2/R^3 inside a wide diffuse envelope. A periodic
// box gets at most N^(1/D) + 1 equal cells a side, wider than eps where
// the box holds more slabs of width eps than that; such cells put a
// cluster of width w into about w N^(1/D)/L cells a side, and its
// candidates grow like its size squared (10^5 particles, 90 % in a ball of
// radius L/20: 1734 particles in a cell, 344 ms a sweep against 11 for the
// same count spread evenly). In R^D the collapsed runs (collapsed_axis.hpp)
// see an envelope as one run and coarsen its slabs until they fit, the
// cluster's core with them. Here the axis is a lattice of slabs a little
// wider than eps (periodic: n = floor(L/eps) of width L/n; open: from the
// particles' lowest coordinate over their bounding box), at most
// max_slabs, and the cells are runs of consecutive slabs chosen from the
// particles' marginal distribution along the axis: a cell ends once it
// holds `per_cell` particles, so a crowded stretch gets a cell per slab and
// a sparse one few wide cells; `per_cell` is the smallest whose cells fit
// the axis's budget.
//
// Why the 3^D stencil stays exact, seam included: the map from slab to cell
// never decreases and grows by at most one from a slab to the next (each
// cell a run of whole slabs), its first slab in cell 0 and its last in the
// last cell; two particles within eps of each other are at most one slab
// apart, across a periodic seam too (slab n - 1 and slab 0), so at most one
// cell, counted around the box; positions beyond the slabs (particles that
// moved since) are clamped into the end slabs, which keeps the map
// monotone. CellList only ever uses the cells' indices, so their widths
// need not be equal.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/parallel.hpp>  // MOLLIFY_SIMD

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN  // its MOLLIFY_SIMD loops (detail/isa.hpp)

namespace mollify::sph {
inline namespace MOLLIFY_ISA {
namespace detail {

// Slabs of a cell list's axes are eps times this wide, a little over eps:
// with a slab computed as a rounded quotient (off by at most ~2^-21 of a
// slab for up to 2^30 slabs), two positions at most eps (1 + 2^-52) apart,
// all the pair test can accept, land at most one slab apart.
inline constexpr double slab_margin = 1 + 0x1p-19;

// The particles of each slab of one axis: of a periodic side [0, L), n
// slabs of width L/n; of an open one, slabs of width eps (1 + 2^-19) from
// the particles' lowest coordinate lo over [lo, hi] (where that takes at
// most max_slabs; positions that later move beyond are clamped into the
// end slabs, which keeps the map monotone).
class SlabCounts {
public:
    // Slabs no narrower than eps slab_margin (the quotient (v - origin) n / L
    // rounded to within 2^-34 for up to 2^16 slabs). At most max_slabs (the
    // cell map is a table of that many entries; periodic: wider slabs only
    // coarsen it).
    static constexpr long max_slabs = 1L << 16;
    static constexpr double margin = slab_margin;

    static SlabCounts periodic(std::span<const double> x, double length, double eps) {
        const long n = static_cast<long>(std::clamp(std::floor(length / (eps * margin)), 1.0, double(max_slabs)));
        return SlabCounts(x, 0, static_cast<double>(n) / length, n);
    }

    // The slabs [lo, hi] takes (a double: beyond any long where the particles spread far).
    static double open_slabs(double lo, double hi, double eps) { return std::floor((hi - lo) / (eps * margin)) + 1; }
    static SlabCounts open(std::span<const double> x, double lo, double hi, double eps) {
        return SlabCounts(x, lo, 1 / (eps * margin), static_cast<long>(open_slabs(lo, hi, eps)));
    }

    std::size_t slab(double v) const { return slab(v, origin_, per_length_, slabs_); }
    // Clamped as a double (v may lie anywhere once particles moved), then truncated: the floor of a non-negative number.
    static std::size_t slab(double v, double origin, double per_length, long slabs) {
        return static_cast<std::size_t>(std::clamp((v - origin) * per_length, 0.0, static_cast<double>(slabs - 1)));
    }

    double origin() const { return origin_; }
    double per_length() const { return per_length_; }
    long slabs() const { return slabs_; }
    const std::vector<std::uint32_t>& counts() const { return counts_; }

    // The most particles in one of `cells` equal runs of slabs (the equal
    // cells along this axis, at slab resolution).
    double most_in(long cells) const {
        std::vector<double> in(static_cast<std::size_t>(cells));
        for (std::size_t s = 0; s < counts_.size(); ++s)
            in[s * static_cast<std::size_t>(cells) / counts_.size()] += counts_[s];
        return *std::max_element(in.begin(), in.end());
    }

private:
    SlabCounts(std::span<const double> x, double origin, double per_length, long slabs)
        : origin_(origin), per_length_(per_length), slabs_(slabs), counts_(static_cast<std::size_t>(slabs)) {
        for (const double v : x) ++counts_[slab(v)];
    }

    double origin_, per_length_;
    long slabs_;
    std::vector<std::uint32_t> counts_;
};

class GradedAxis {
public:
    // Cells of consecutive slabs, each ending once it holds `per_cell`
    // particles (or at the last slab); their number, and each slab's cell
    // into `cell` where given.
    static long cells(const SlabCounts& slabs, double per_cell, std::uint32_t* cell = nullptr) {
        std::uint32_t at = 0;
        double held = 0;
        const auto& counts = slabs.counts();
        for (std::size_t s = 0; s < counts.size(); ++s) {
            if (cell) cell[s] = at;
            held += counts[s];
            if (held >= per_cell && s + 1 < counts.size()) ++at, held = 0;
        }
        return static_cast<long>(at) + 1;
    }

    // The cells for the smallest per_cell whose count is at most max_cells
    // (the count never grows with per_cell: bisection over the integers).
    GradedAxis(const SlabCounts& slabs, long max_cells)
        : origin_(slabs.origin()), per_length_(slabs.per_length()), slabs_(slabs.slabs()) {
        double lo = 1, hi = 1;
        for (const std::uint32_t c : slabs.counts()) hi += c;  // one cell: always fits
        while (hi - lo > 1) {  // cells(hi) fits, cells(lo) may not
            const double mid = std::floor((lo + hi) / 2);
            (cells(slabs, mid) <= max_cells ? hi : lo) = mid;
        }
        cell_.resize(slabs.counts().size());
        count_ = cells(slabs, cells(slabs, lo) <= max_cells ? lo : hi, cell_.data());
    }

    long count() const { return count_; }
    std::size_t coordinate(double v) const { return cell_[SlabCounts::slab(v, origin_, per_length_, slabs_)]; }

    // k[i] = k[i] count() + the cell of v[i], for i < n (a table lookup, which vectorises as a gather).
    void append_coordinates(const double* __restrict v, std::size_t n, std::size_t* __restrict k) const {
        const std::size_t count = static_cast<std::size_t>(count_);
        const std::uint32_t* __restrict cell = cell_.data();
        const double origin = origin_, per_length = per_length_;
        const long slabs = slabs_;
        MOLLIFY_SIMD
        for (std::size_t i = 0; i < n; ++i) k[i] = k[i] * count + cell[SlabCounts::slab(v[i], origin, per_length, slabs)];
    }

private:
    double origin_, per_length_;
    long slabs_;
    std::vector<std::uint32_t> cell_;  // the cell of each slab
    long count_ = 1;
};

}  // namespace detail
}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph

MOLLIFY_VECTOR_MISSES_ALLOWED_END
