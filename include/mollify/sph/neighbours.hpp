// Neighbour search for a kernel of support radius eps, O(N) per update: a
// cell list (cells of side >= eps, filled by a counting sort; a particle's
// neighbours lie in the 3^D cells around its own), the default in 1D, 2D
// and 3D. In 1D also a sorted sweep (the particles sorted by position, each
// particle's neighbours a contiguous run on either side of it), visited
// particle by particle; the cell list's half pairs, each pair evaluated once
// for both particles, sweep 1D SPH 1.7-2.4x faster (bench/sph_bench.cpp, the
// 1D rows of both). AllPairs is the O(N^2) baseline the benchmarks compare against. All three
// visit, for particle i, every j with |x_i - x_j| <= eps (i itself
// included, at displacement 0) exactly once, with the displacement x_i - x_j
// (minimum image in a periodic box). CellList also hands out each unordered
// pair {i, j}, i != j, once, cell by cell (half_pairs), for sweeps that use
// Newton's third law.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/parallel.hpp>  // MOLLIFY_SIMD
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/sph/collapsed_axis.hpp>
#include <mollify/sph/domain.hpp>
#include <mollify/sph/graded_axis.hpp>
#include <mollify/sph/pair_batch.hpp>
#include <mollify/static_kernel.hpp>  // mollify::Vector

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <utility>
#include <vector>

MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN  // its MOLLIFY_SIMD loops (detail/isa.hpp)

namespace mollify::sph {
inline namespace MOLLIFY_ISA {

template <int D>
using Positions = std::array<std::span<const double>, D>;

namespace detail {

inline void check_radius(double eps) {
    if (!(eps > 0) || !std::isfinite(eps))
        fail("kernel support radius eps = " + mollify::detail::show(eps) + " is not a positive finite number");
}

// Particles of a periodic box must lie in it: a position outside [0, L) is a
// state the caller lost track of (or a NaN), not one to fold back silently.
template <int D>
void check_positions(const Positions<D>& x, const Domain<D>& domain) {
    for (int c = 1; c < D; ++c)
        if (x[c].size() != x[0].size()) fail("positions: components of different lengths");
    // One branch-free pass (it vectorises): each coordinate in [lo, hi), which
    // NaN and +-inf never are; the loop below names the first bad value.
    const double lo = domain.is_periodic() ? 0.0 : -std::numeric_limits<double>::max();
    const double hi = domain.is_periodic() ? domain.length() : std::numeric_limits<double>::infinity();
    int good = 1;
    for (int c = 0; c < D; ++c)
        for (const double v : x[c]) good &= static_cast<int>(v >= lo) & static_cast<int>(v < hi);
    if (good) return;
    for (int c = 0; c < D; ++c)
        for (std::size_t i = 0; i < x[c].size(); ++i) {
            const double v = x[c][i];
            if (!std::isfinite(v))
                fail("particle " + std::to_string(i) + " has coordinate x[" + std::to_string(c) +
                     "] = " + mollify::detail::show(v) + " (not finite)");
            if (domain.is_periodic() && !(v >= 0 && v < domain.length()))
                fail("particle " + std::to_string(i) + " at x[" + std::to_string(c) + "] = " + mollify::detail::show(v) +
                     " lies outside the periodic box [0, " + mollify::detail::show(domain.length()) + ")");
        }
}

// What every search is made for: a domain and a support radius eps, checked
// once (eps > 0, and 2 eps < L in a periodic box).
template <int D>
struct Reach {
    Reach(Domain<D> d, double e) : domain(d), eps(e) {
        check_radius(e);
        d.check_support(e);
    }
    Domain<D> domain;
    double eps;
};

}  // namespace detail

// Whether pairs at exactly eps change a sweep: W and grad W of a kernel of
// smoothness C^1 or more (table::Kernel::smoothness, at its breakpoints and
// edge) vanish there, so a pair the cells miss within a few ulps of eps adds
// (about) 0; a box kernel's W (C^-1) and mollifier:M=1's grad W (C^0) do not.
enum class SupportEdge { contributes, vanishes };

template <class Kernel>
SupportEdge support_edge_of(const Kernel& k) {
    return k.table().smoothness >= 1 ? SupportEdge::vanishes : SupportEdge::contributes;
}

// 1D: the particles sorted by position. The order is kept between updates
// and repaired by insertion sort, O(N) when particles barely reorder (the
// usual case from one time step to the next). The 1D default until stop 54,
// kept as the benchmarks' particle-by-particle baseline.
class SortedSweep {
public:
    static constexpr int dim = 1;

    SortedSweep(Domain<1> domain, double eps) : reach_(domain, eps) {}

    void update(const Positions<1>& x) {
        detail::check_positions<1>(x, reach_.domain);
        const std::size_t n = x[0].size();
        if (order_.size() != n) {
            order_.resize(n);
            std::iota(order_.begin(), order_.end(), std::size_t{0});
        }
        sorted_.resize(n);
        rank_.resize(n);
        for (std::size_t p = 0; p < n; ++p) sorted_[p] = x[0][order_[p]];
        for (std::size_t p = 1; p < n; ++p) {  // insertion sort, carrying order_ along
            const double v = sorted_[p];
            const std::size_t id = order_[p];
            std::size_t q = p;
            for (; q > 0 && sorted_[q - 1] > v; --q) {
                sorted_[q] = sorted_[q - 1];
                order_[q] = order_[q - 1];
            }
            sorted_[q] = v;
            order_[q] = id;
        }
        for (std::size_t p = 0; p < n; ++p) rank_[order_[p]] = p;
    }

    // f(j, {x_i - x_j}) for every j within eps of particle i (i included).
    template <class F>
    void visit(std::size_t i, F&& f) const {
        const std::size_t n = sorted_.size(), p = rank_[i];
        const double xi = sorted_[p];
        f(i, Vector<1>{0.0});
        // In cyclic order from p the forward distances grow monotonically
        // (likewise backward), and no j is within eps both ways since 2 eps < L.
        // A coincident particle (d = 0) belongs to the scan that reaches it
        // without wrapping round the box; a wrapped scan sees the image
        // shifted by L (no minimum-image division per neighbour).
        const double L = reach_.domain.is_periodic() ? reach_.domain.length() : 0.0;
        for (std::size_t step = 1; step < n; ++step) {
            std::size_t q = p + step;
            double d;
            if (q < n) {
                d = xi - sorted_[q];
            } else {
                if (L == 0) break;
                q -= n;
                d = xi - (sorted_[q] + L);
                if (d >= 0) break;
            }
            if (-d > reach_.eps) break;
            f(order_[q], Vector<1>{d});
        }
        for (std::size_t step = 1; step < n; ++step) {
            std::size_t q;
            double d;
            if (step <= p) {
                q = p - step;
                d = xi - sorted_[q];
            } else {
                if (L == 0) break;
                q = p + n - step;
                d = xi - (sorted_[q] - L);
                if (d <= 0) break;
            }
            if (d > reach_.eps) break;
            f(order_[q], Vector<1>{d});
        }
    }

private:
    detail::Reach<1> reach_;
    std::vector<std::size_t> order_, rank_;
    std::vector<double> sorted_;
};

// A cell list, 1D to 3D. In a periodic box the cells tile [0, L)^D; in R^D
// they cover the particles' bounding box or, in 2D and 3D where the
// particles spread further than ~N cells of side eps reach (a few far from
// a dense cluster, clusters far apart), each axis's runs of occupied slabs
// (layout, detail::CollapsedAxis), so that a cluster's cells stay of side
// eps. In 1D the slots are in order of position, cells being intervals,
// and each particle's candidates are a window of them (half_pairs_runs):
// O(neighbours) however wide the cells.
template <int D>
class CellList {
public:
    static constexpr int dim = D;

    // Where L/eps (or the bounding box's extent over eps) is an integer the
    // cells would have side exactly eps, and a particle's cell, a rounded
    // quotient, can be one off within a few ulps of a boundary: two
    // particles at eps (the pair test accepts them) can lie two cells apart
    // (x = 1/8 - 2^-56 and 1/4 with eps = 1/8: their difference rounds to
    // eps, their cells are 0 and 2). SupportEdge::contributes (the default) keeps cells of
    // side eps (1 + 2^-19) (detail::slab_margin, as graded cells do), so
    // every pair the test accepts is met: one cell a side fewer where L/eps
    // is an integer (the benchmark lattice at N = 10^4: 11 -> 10 a side,
    // 1.33x the candidates). SupportEdge::vanishes (BarotropicEuler with a
    // kernel of C^1 or more: support_edge_of) keeps side eps there.
    CellList(Domain<D> domain, double eps, SupportEdge edge = SupportEdge::contributes)
        : reach_(domain, eps), margin_(edge == SupportEdge::contributes ? detail::slab_margin : 1.0) {}

    SupportEdge support_edge() const { return margin_ == 1.0 ? SupportEdge::vanishes : SupportEdge::contributes; }

    // Up to this many particles update() runs on one thread (the loops are
    // shorter than waking the others).
    static constexpr std::size_t serial_below = 50000;

    // A stable counting sort by cell that starts from the last update's
    // order: particles that stayed in their cells keep their slots, so the
    // sorted copy is written almost in sequence when particles barely move.
    void update(const Positions<D>& x) {
        begin_update(x);
        const std::size_t n = x[0].size();
        const long parts = n > serial_below ? mollify::detail::thread_count() : 1;
        bool kept = true;
        MOLLIFY_PARALLEL_FOR(if(parts > 1) schedule(static) reduction(&& : kept))
        for (long p = 0; p < parts; ++p)
            kept = update_slots(x, part_begin(n, p, parts), part_begin(n, p + 1, parts)) && kept;
        finish_update(x, kept);
    }

    // update() in three steps, for a caller that runs the middle one on its
    // threads inside its own parallel region (BarotropicEuler's small
    // sweeps, where each thread then sweeps the slots it copied: they stay
    // in its core's cache). begin_update and finish_update on one thread;
    // update_slots on slot ranges [from, to) that cover [0, n) (part_begin),
    // each on one thread, between them.
    void begin_update(const Positions<D>& x) {
        detail::check_positions<D>(x, reach_.domain);
        const std::size_t n = x[0].size();
        // half_pairs numbers a cell's candidates in 32 bits.
        if (n > std::size_t{1} << 31) fail("CellList: " + std::to_string(n) + " particles (at most 2^31)");
        layout(x, n);
        strays_ = 0;  // layout() has read the last update's
        std::size_t cells = 1;
        for (int c = 0; c < D; ++c) cells *= static_cast<std::size_t>(count_[c]);
        start_.resize(cells + 1);
        slot_cell_.resize(n);
        first_ = members_.size() != n;
        if (first_) {
            members_.resize(n);
            std::iota(members_.begin(), members_.end(), std::size_t{0});
        }
        slot_.resize(n);
        for (int c = 0; c < D; ++c) sorted_[c].resize(n + copy_chunk);  // half_pairs_runs copies whole chunks
    }

    // Part p of `parts` equal slot ranges: [part_begin(n, p, parts), part_begin(n, p + 1, parts)).
    static std::size_t part_begin(std::size_t n, long p, long parts) {
        return n * static_cast<std::size_t>(p) / static_cast<std::size_t>(parts);
    }

    // The last order tried on the slots [from, to): each particle's cell,
    // its sorted copy and, while the cells do not decrease from slot
    // from - 1 on, the first slots of the cells they enter (the entries of
    // the range's cells only, so parts write disjoint entries where the
    // order holds; relaxed atomic stores, as parts may meet where it broke,
    // and finish_update then sorts afresh). Whether the order held.
    bool update_slots(const Positions<D>& x, std::size_t from, std::size_t to) {
        const std::size_t n = x[0].size();
        // The copy and the cells in separate loops over raw pointers (they
        // vectorise: gathers, then the cells from the copy), then the check.
        const std::size_t* __restrict member = members_.data();
        for (int c = 0; c < D; ++c) {
            const double* __restrict source = x[c].data();
            double* __restrict copy = sorted_[c].data();
            for (std::size_t slot = from; slot < to; ++slot) copy[slot] = source[member[slot]];
        }
        std::size_t* __restrict cell_at = slot_cell_.data();
        const std::array<double, D> origin = origin_, side = side_;
        const std::array<long, D> count = count_;
        std::array<const double*, D> v;
        for (int c = 0; c < D; ++c) v[c] = sorted_[c].data();
        if (!graded_.empty()) {
            std::fill(cell_at + from, cell_at + to, std::size_t{0});
            for (int c = D - 1; c >= 0; --c) graded_[static_cast<std::size_t>(c)].append_coordinates(v[c] + from, to - from, cell_at + from);
        } else if (collapsed_.empty()) {
            for (std::size_t slot = from; slot < to; ++slot) {
                std::size_t k = 0;
                for (int c = D - 1; c >= 0; --c)
                    k = k * static_cast<std::size_t>(count[c]) + coordinate(v[c][slot], origin[c], side[c], count[c]);
                cell_at[slot] = k;
            }
        } else {
            // Axis by axis (each a loop that vectorises); a particle outside
            // the runs on several axes counts as several strays.
            std::fill(cell_at + from, cell_at + to, std::size_t{0});
            std::size_t strays = 0;
            for (int c = D - 1; c >= 0; --c)
                strays += collapsed_[static_cast<std::size_t>(c)].append_coordinates(v[c] + from, to - from, cell_at + from);
            std::atomic_ref<std::size_t>(strays_).fetch_add(strays, std::memory_order_relaxed);
        }
        if (first_)
            for (std::size_t slot = from; slot < to; ++slot) slot_[member[slot]] = slot;
        if constexpr (D == 1) {  // the order is by position (half_pairs_runs' windows), the cells follow
            double last = from > 0 ? x[0][member[from - 1]] : -std::numeric_limits<double>::infinity();
            for (std::size_t slot = from; slot < to; ++slot) {
                if (v[0][slot] < last) return false;
                last = v[0][slot];
            }
        }
        auto first_slot_of = [&](std::size_t c, std::size_t slot) {
            std::atomic_ref<std::size_t>(start_[c]).store(slot, std::memory_order_relaxed);
        };
        // The cell before the range (none before slot 0: cells from 0 on start there).
        std::size_t previous = from > 0 ? cell(x, member[from - 1]) : 0;
        std::size_t next = from > 0 ? previous + 1 : 0;  // the first cell whose first slot is still to be set
        for (std::size_t slot = from; slot < to; ++slot) {
            const std::size_t k = cell_at[slot];
            if (k < previous) return false;
            for (; next <= k; ++next) first_slot_of(next, slot);
            previous = k;
        }
        // After the last particle every cell starts at n (start_[cells] too).
        if (to == n)
            for (const std::size_t cells = start_.size() - 1; next <= cells; ++next) first_slot_of(next, n);
        return true;
    }

    // Where every part kept the order (most time steps) the first slots are
    // set; else the stable counting sort from the last order.
    void finish_update(const Positions<D>& x, bool kept) {
        if (kept) {
            order_kept_ = !first_;
            return;
        }
        order_kept_ = false;
        const std::size_t n = x[0].size();
        std::fill(start_.begin(), start_.end(), 0);
        for (std::size_t p = 0; p < n; ++p) ++start_[slot_cell_[p] + 1];
        std::partial_sum(start_.begin(), start_.end(), start_.begin());
        fill_.assign(start_.begin(), start_.end() - 1);
        previous_.swap(members_);
        previous_cell_.swap(slot_cell_);
        members_.resize(n);
        slot_cell_.resize(n);
        for (std::size_t p = 0; p < n; ++p) {
            const std::size_t i = previous_[p], k = previous_cell_[p];
            const std::size_t slot = fill_[k]++;
            members_[slot] = i;
            slot_cell_[slot] = k;
            slot_[i] = slot;
            for (int c = 0; c < D; ++c) sorted_[c][slot] = x[c][i];
        }
        if constexpr (D == 1) order_cells_by_position();
    }

    // 1D: each cell's slots in order of position (stable: equal positions
    // keep the last order); the cells being intervals in order, so are all
    // the slots.
    void order_cells_by_position() {
        std::vector<std::pair<double, std::size_t>>& by_x = by_position_;
        const auto at = [&](std::size_t slot) { return sorted_[0].begin() + static_cast<std::ptrdiff_t>(slot); };
        for (std::size_t k = 0; k + 1 < start_.size(); ++k) {
            const std::size_t lo = start_[k], hi = start_[k + 1];
            if (std::is_sorted(at(lo), at(hi))) continue;
            by_x.clear();
            for (std::size_t slot = lo; slot < hi; ++slot) by_x.emplace_back(sorted_[0][slot], members_[slot]);
            std::stable_sort(by_x.begin(), by_x.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
            for (std::size_t slot = lo; slot < hi; ++slot) {
                sorted_[0][slot] = by_x[slot - lo].first;
                members_[slot] = by_x[slot - lo].second;
                slot_[members_[slot]] = slot;
            }
        }
    }

    // The sorted copy: slot s holds particle members()[s]; the particles of
    // a cell occupy consecutive slots, cells in row-major order (axis 0 fastest).
    std::size_t cells() const { return start_.empty() ? 0 : start_.size() - 1; }
    const std::vector<std::size_t>& members() const { return members_; }
    // Whether the last update kept the order of the update before it (no
    // particle changed cells): what a caller permuted by members() still holds.
    bool order_kept() const { return order_kept_; }
    // The first slot of a cell (first_slot(cells()) is the particle count).
    std::size_t first_slot(std::size_t cell) const { return start_[cell]; }
    // The cells' layers along the last axis (planes in 3D, rows in 2D), the
    // cells of layer z being [z cells()/layers(), (z + 1) cells()/layers()).
    // A home cell's half pairs reach only its own layer and the next one
    // (layer 0 after the last where the domain is periodic): half_rows'
    // last non-zero offset is +1, the first axes wrap within a layer. So
    // threads that take contiguous cells sum into their own arrays and meet
    // only where those ranges' layers touch (BarotropicEuler::sweep_cells).
    // 1 where the cells alias (a periodic side of fewer than 3 cells: half
    // pairs may then reach a lower layer), so that every range reaches it.
    std::size_t layers() const { return aliased_ ? 1 : static_cast<std::size_t>(count_[D - 1]); }

    // Each unordered pair {a, b}, a != b, |x_a - x_b| <= eps, exactly once
    // over all home cells: a in the home cell, b later in the home cell or
    // in a neighbouring cell of larger index (Newton's third law: the caller
    // updates both). The pairs go into the batch as slots and displacements
    // x_a - x_b (minimum image), and flush(batch) is called whenever it
    // fills and at the end; the batch is left empty.
    template <class Flush>
    void half_pairs(std::size_t home, PairBatch<D>& b, Flush&& flush) const {
        if (start_[home + 1] == start_[home]) return;  // no home particle (the neighbours' copy would be wasted)
        if (aliased_)
            half_pairs_aliased(home, b, flush);
        else
            half_pairs_runs(home, b, flush);
    }

    template <class Flush>
    void half_pairs_aliased(std::size_t home, PairBatch<D>& b, Flush& flush) const {
        gather_candidates(home, b);
        const std::size_t nh = start_[home + 1] - start_[home], nc = b.candidates;
        const std::size_t rows = std::max<std::size_t>(1, PairBatch<D>::block / std::max<std::size_t>(nc, 1));
        const std::size_t cap = std::max(rows * nc, PairBatch<D>::capacity);
        b.reserve(cap);
        if (b.r2.size() < rows * nc) {
            b.r2.resize(rows * nc);
            b.near.resize(rows * nc);
        }
        if (b.row_end.size() < rows) b.row_end.resize(rows);
        for (std::size_t a0 = 0; a0 < nh; a0 += rows) {
            const std::size_t a1 = std::min(nh, a0 + rows);
            if (b.size + (a1 - a0) * nc > cap) {
                flush(b);
                b.clear();
            }
            b.size = detail::near_pairs<D, true>(b, a0, a1, nc, reach_.eps, reach_.domain);
        }
        if (b.size) flush(b);
        b.clear();
    }

    // Without aliasing each pair of neighbouring cells is met once from the
    // cell it lies at a positive offset of (the first non-zero offset, from
    // the last axis down, is +1): the home cell with the next along axis 0,
    // then the rows of 3 cells along axis 0 at positive offsets on the
    // other axes (4 rows in 3D). Consecutive cells of a row with the same
    // image shift are one run of slots; the home particles' own run starts
    // after each one (the triangle of the home cell).
    template <class Flush>
    void half_pairs_runs(std::size_t home, PairBatch<D>& b, Flush& flush) const {
        std::array<detail::Run<D>, 2 * 9> runs;
        std::size_t nruns = 0, total = 0;
        std::array<long, D> at;
        std::size_t k = home;
        for (int c = 0; c < D; ++c) {
            at[c] = static_cast<long>(k % static_cast<std::size_t>(count_[c]));
            k /= static_cast<std::size_t>(count_[c]);
        }
        const bool periodic = reach_.domain.is_periodic();
        const double L = reach_.domain.length();
        for (std::size_t r = 0; r < detail::half_rows<D>.size(); ++r) {
            const std::array<int, D>& off = detail::half_rows<D>[r];  // off[0] unused: the row runs along axis 0
            const bool home_row = r == 0;
            bool inside = true;
            std::size_t row = 0;  // the row's cell at axis-0 coordinate 0
            std::array<double, D> shift{};
            for (int c = D - 1; c >= 1; --c) {
                long v = at[c] + off[static_cast<std::size_t>(c)];
                if (v < 0 || v >= count_[c]) {
                    inside = inside && periodic;
                    shift[static_cast<std::size_t>(c)] = v < 0 ? -L : L;
                    v = (v + count_[c]) % count_[c];
                }
                row = row * static_cast<std::size_t>(count_[c]) + static_cast<std::size_t>(v);
            }
            row *= static_cast<std::size_t>(count_[0]);
            if (!inside) continue;
            for (long dx = home_row ? 0 : -1; dx <= 1; ++dx) {
                long v = at[0] + dx;
                double sx = 0;
                if (v < 0 || v >= count_[0]) {
                    if (!periodic) continue;
                    sx = v < 0 ? -L : L;
                    v = (v + count_[0]) % count_[0];
                }
                const std::size_t cell = row + static_cast<std::size_t>(v);
                shift[0] = sx;
                if (nruns > 0 && runs[nruns - 1].hi == start_[cell] && runs[nruns - 1].shift == shift) {
                    runs[nruns - 1].hi = start_[cell + 1];
                } else {
                    runs[nruns++] = {start_[cell], start_[cell + 1], shift};
                }
                total += start_[cell + 1] - start_[cell];
            }
        }
        // The runs copied, shifted, into one contiguous candidate list (the
        // home cell first): one loop per home particle, not one per run
        // (each loop's exit is a mispredicted branch and a drained pipeline).
        // Each run in whole chunks, all components in one loop: the copy past
        // a run's end is overwritten by the next run or lies in the padding
        // (one loop exit per run, not one per component with a vector loop's
        // peeling and remainder: those mispredicted ~30 times per cell).
        if (b.slot.size() < total + 2 * copy_chunk) {
            for (auto& c : b.y) c.resize(total + 2 * copy_chunk);
            b.slot.resize(total + 2 * copy_chunk);
        }
        std::size_t at_slot = 0;
        for (std::size_t r = 0; r < nruns; ++r) {
            const std::size_t lo = runs[r].lo, len = runs[r].hi - runs[r].lo;
            std::array<const double*, D> from;
            std::array<double*, D> to;
            for (int c = 0; c < D; ++c) {
                from[static_cast<std::size_t>(c)] = sorted_[c].data() + lo;
                to[static_cast<std::size_t>(c)] = b.y[c].data() + at_slot;
            }
            std::size_t* slots = b.slot.data() + at_slot;
            const std::array<double, D> sh = runs[r].shift;
            for (std::size_t t = 0; t < len; t += copy_chunk) {
                for (std::size_t c = 0; c < D; ++c) detail::shifted_chunk<copy_chunk>(to[c] + t, from[c] + t, sh[c]);
                detail::numbered_chunk<copy_chunk>(slots + t, lo + t);
            }
            at_slot += len;
        }
        const std::size_t cap = std::max(total, PairBatch<D>::capacity);
        b.reserve(cap + 16);  // store_pairs' two chunks of 8 (masked) past the last pair
        std::array<const double*, D> y;
        for (int c = 0; c < D; ++c) y[static_cast<std::size_t>(c)] = b.y[c].data();
        if (b.close.size() < total + 16) b.close.resize(total + 16);
        std::uint32_t* close = b.close.data();
        const std::size_t* slot = b.slot.data();
        const double eps2 = reach_.eps * reach_.eps;
        const std::size_t nh = start_[home + 1] - start_[home];
        std::size_t end = 0;  // 1D: the end of the last home particle's window
        for (std::size_t a = 0; a < nh; ++a) {
            std::array<double, D> xa;
            for (int c = 0; c < D; ++c) xa[static_cast<std::size_t>(c)] = y[static_cast<std::size_t>(c)][a];
            if constexpr (D == 1) {
                // The candidates are in order of position (the home cell's
                // slots, then the next cell's, shifted by L across the seam),
                // so those within eps of x_a are the ones up to the first
                // beyond it, by append_near's test (the distance grows with
                // the position, rounded or not): each particle's window, not
                // its cells, however wide the cells are; all of it near.
                end = std::max(end, a + 1);
                while (end < total && (xa[0] - y[0][end]) * (xa[0] - y[0][end]) <= eps2) ++end;
            }
            if (b.size + (D == 1 ? end - a : total) > cap) {  // at most that many pairs to come
                flush(b);
                b.clear();
            }
            std::size_t m = 0;
            if constexpr (D == 1) {
                for (std::size_t q = a + 1; q < end; ++q) close[m++] = static_cast<std::uint32_t>(q);
            } else {
                m = detail::append_near<D>(close, 0, xa, y, a + 1, total, eps2);
            }
            detail::store_pairs<D>(b, b.size, close, m, xa, y, slot, slot[a]);
            b.close_group(b.size + m);
        }
        if (b.size) flush(b);
        b.clear();
    }

    template <class F>
    void visit(std::size_t i, F&& f) const {
        std::array<long, D> home;
        std::size_t k = slot_cell_[slot_[i]];
        for (int c = 0; c < D; ++c) {
            home[c] = static_cast<long>(k % static_cast<std::size_t>(count_[c]));
            k /= static_cast<std::size_t>(count_[c]);
        }
        Vector<D> xi;
        for (int c = 0; c < D; ++c) xi[c] = sorted_[c][slot_[i]];
        // The 3^D cells around home. With at least 3 cells per side each is a
        // distinct cell, and a periodic neighbour across the box is the cell's
        // image shifted by +-L: one shift per cell, no minimum image per
        // candidate. With fewer, offsets alias: each cell once, minimum image.
        bool aliased = false;
        for (int c = 0; c < D; ++c) aliased = aliased || (reach_.domain.is_periodic() && count_[c] < 3);
        std::array<std::size_t, 27> seen{};
        int nseen = 0;
        std::array<int, D> off;
        off.fill(-1);
        const double eps2 = reach_.eps * reach_.eps, L = reach_.domain.length();
        for (;;) {
            bool inside = true;
            std::size_t cell = 0;
            Vector<D> origin = xi;  // xi minus the image shift of this cell
            for (int c = D - 1; c >= 0; --c) {
                long v = home[c] + off[c];
                if (v < 0 || v >= count_[c]) {
                    if (!reach_.domain.is_periodic()) inside = false;
                    origin[c] += v < 0 ? L : -L;
                    v = (v + count_[c]) % count_[c];
                }
                cell = cell * static_cast<std::size_t>(count_[c]) + static_cast<std::size_t>(v);
            }
            if (inside && aliased) {
                inside = std::find(seen.begin(), seen.begin() + nseen, cell) == seen.begin() + nseen;
                if (inside) seen[static_cast<std::size_t>(nseen++)] = cell;
            }
            if (inside)
                for (std::size_t s = start_[cell]; s < start_[cell + 1]; ++s) {
                    Vector<D> d;
                    double r2 = 0;
                    for (int c = 0; c < D; ++c) {
                        d[c] = aliased ? reach_.domain.displacement(xi[c], sorted_[c][s]) : origin[c] - sorted_[c][s];
                        r2 += d[c] * d[c];
                    }
                    if (r2 <= eps2) f(members_[s], d);
                }
            int c = 0;
            while (c < D && off[c] == 1) off[c++] = -1;
            if (c == D) break;
            ++off[c];
        }
    }

private:
    // The aliased case's candidates of a home cell, into b.y and b.slot: its
    // own particles first, then those of each distinct neighbouring cell of
    // larger index. With fewer than 3 cells on a periodic side no single
    // image serves a whole cell: positions unshifted, minimum image per pair
    // (near_pairs).
    void gather_candidates(std::size_t home, PairBatch<D>& b) const {
        std::array<std::size_t, 27> cell{};
        std::size_t cells = 1;
        cell[0] = home;
        std::array<long, D> at;
        std::size_t k = home;
        for (int c = 0; c < D; ++c) {
            at[c] = static_cast<long>(k % static_cast<std::size_t>(count_[c]));
            k /= static_cast<std::size_t>(count_[c]);
        }
        std::array<int, D> off;
        off.fill(-1);
        const bool periodic = reach_.domain.is_periodic();
        for (;;) {
            bool inside = true;
            std::size_t g = 0;
            for (int c = D - 1; c >= 0; --c) {
                long v = at[c] + off[c];
                if (v < 0 || v >= count_[c]) {
                    inside = inside && periodic;
                    v = (v + count_[c]) % count_[c];
                }
                g = g * static_cast<std::size_t>(count_[c]) + static_cast<std::size_t>(v);
            }
            if (inside && g > home && std::find(cell.begin() + 1, cell.begin() + cells, g) == cell.begin() + cells)
                cell[cells++] = g;
            int c = 0;
            while (c < D && off[c] == 1) off[c++] = -1;
            if (c == D) break;
            ++off[c];
        }
        std::size_t total = 0;
        for (std::size_t q = 0; q < cells; ++q) total += start_[cell[q] + 1] - start_[cell[q]];
        if (b.slot.size() < total) {
            for (auto& c : b.y) c.resize(total);
            b.slot.resize(total);
        }
        b.candidates = total;
        std::size_t at_slot = 0;
        for (std::size_t q = 0; q < cells; ++q) {
            const std::size_t lo = start_[cell[q]], hi = start_[cell[q] + 1];
            for (int c = 0; c < D; ++c) std::copy(sorted_[c].begin() + static_cast<std::ptrdiff_t>(lo),
                                                  sorted_[c].begin() + static_cast<std::ptrdiff_t>(hi),
                                                  b.y[c].begin() + static_cast<std::ptrdiff_t>(at_slot));
            for (std::size_t t = lo; t < hi; ++t) b.slot[at_slot++] = t;
        }
    }

    // Cells of side >= eps, at most ~N of them in all (a sparse open domain
    // must not allocate a huge empty grid): in R^1, at most N + 1, wider
    // than eps where that is too few (harmless: half_pairs_runs' windows).
    // In a periodic box (periodic_layout) at most N^(1/D) + 1 a side, wider
    // than eps where that is too few, or graded ones where the particles
    // crowd part of the box. In R^2 and R^3 cells of side
    // eps over the bounding box where at most 4 (N^(1/D) + 1)^D of them
    // cover it, however they are shared among the axes (a sheet of particles
    // gets many cells along its plane); else, where the particles spread
    // further (a cluster and particles far from it, a diffuse envelope),
    // cells over the runs of occupied slabs of each axis (collapse,
    // detail::CollapsedAxis), kept from update to update until many more
    // particles lie outside the runs than when they were found.
    void layout(const Positions<D>& x, std::size_t n) {
        std::array<double, D> lo{}, hi{};
        for (int c = 0; c < D; ++c) {
            lo[c] = 0, hi[c] = reach_.domain.length();
            if (!reach_.domain.is_periodic()) {
                lo[c] = hi[c] = n ? x[c][0] : 0.0;
                for (std::size_t i = 0; i < n; ++i) {
                    lo[c] = std::min(lo[c], x[c][i]);
                    hi[c] = std::max(hi[c], x[c][i]);
                }
            }
        }
        const double per_side = std::pow(static_cast<double>(std::max<std::size_t>(n, 1)), 1.0 / D) + 1;
        // (hi - lo)/eps slabs a side, counted in double: it may exceed any long.
        auto slabs = [&](int c) { return std::max(1.0, std::floor((hi[c] - lo[c]) / (reach_.eps * margin_))); };
        if (D == 1) {
            uniform(0, lo[0], hi[0], std::min(slabs(0), std::floor(per_side)));
            aliased_ = reach_.domain.is_periodic() && count_[0] < 3;
            return;
        }
        // Four times the cells of the other layouts: empty cells cost a sweep
        // little, and two clusters apart on a diagonal need 2^D their cells.
        const double budget = 4 * std::pow(std::floor(per_side), D);
        if (reach_.domain.is_periodic()) {
            std::array<double, D> even;  // equal cells a side
            for (int c = 0; c < D; ++c) even[c] = std::min(slabs(c), std::floor(per_side));
            periodic_layout(x, n, even, budget);
            return;
        }
        double cells = 1;
        for (int c = 0; c < D; ++c) cells *= slabs(c);
        if (cells <= budget) {
            collapsed_.clear();
            graded_.clear();
            for (int c = 0; c < D; ++c) uniform(c, lo[c], hi[c], slabs(c));
            return;
        }
        // Graded cells kept while their crowding has not doubled; the runs
        // while few more particles than when they were found lie outside
        // them (each adds to a crowded collapsed cell).
        if (!graded_.empty() && !crowding_doubled(n)) return;
        if (!collapsed_.empty() && strays_ <= outside_runs_ + std::max<std::size_t>(16, n / 256)) return;
        // Chosen afresh: graded cells where the particles but the farthest
        // span few enough slabs (a cluster in a wide envelope, with far
        // particles or not: the collapsed runs would make the envelope one
        // run, coarsened to fit, the cluster's core with it); else the runs
        // (clusters far apart: a sort of N slabs a side).
        if (graded_over_most(x, n, budget)) return;
        graded_.clear();
        if (collapse(x, lo, budget, n)) return;
        collapsed_.clear();  // a handful of particles only: the runs' margins alone exceed their budget
        for (int c = 0; c < D; ++c) uniform(c, lo[c], hi[c], std::min(slabs(c), std::floor(per_side)));
    }

    // `count` equal cells over [lo, hi] along axis c (the box in a periodic domain).
    void uniform(int c, double lo, double hi, double count) {
        origin_[c] = lo;
        count_[c] = static_cast<long>(count);
        side_[c] = reach_.domain.is_periodic()
                       ? reach_.domain.length() / count
                       : std::max(std::min(hi - lo, std::numeric_limits<double>::max()) / count, reach_.eps * margin_);
    }

    // A periodic box: N^(1/D) + 1 equal cells a side at most (of side eps
    // where fewer cover it); but where the particles crowd part of the box
    // (on some axis the most in one of those cells' slabs exceeds twice
    // their mean and 16: evenly spread particles stay within a few square
    // roots of it) graded cells on every axis (detail::GradedAxis), at most
    // budget^(1/D) a side. Chosen again when the cells' crowding (the sum of
    // their squared counts, the candidates a sweep tests) has doubled since
    // the first update after the choice: a cloud that collapses or
    // disperses, a cluster that moves.
    void periodic_layout(const Positions<D>& x, std::size_t n, const std::array<double, D>& even, double budget) {
        collapsed_.clear();
        if (!crowding_doubled(n)) return;
        std::vector<detail::SlabCounts> counts;
        bool crowded = false;
        for (int c = 0; c < D; ++c) {
            counts.push_back(detail::SlabCounts::periodic(x[c], reach_.domain.length(), reach_.eps));
            crowded = crowded || (even[c] >= 3 && counts.back().slabs() > even[c] &&
                                  counts.back().most_in(static_cast<long>(even[c])) > 2 * static_cast<double>(n) / even[c] + 16);
        }
        if (crowded) {
            graded(counts, budget);
            return;
        }
        graded_.clear();
        crowding_ = 0;
        aliased_ = false;
        for (int c = 0; c < D; ++c) {
            uniform(c, 0, reach_.domain.length(), even[c]);
            aliased_ = aliased_ || count_[c] < 3;
        }
    }

    // Whether the cells' crowding (the sum of their squared counts, from
    // the last update) has doubled since the first update after the layout
    // was chosen, which records it; true where there is no last update in
    // this layout (the first, or the particle count changed). A layout
    // chosen afresh resets crowding_.
    bool crowding_doubled(std::size_t n) {
        if (members_.size() != n || n == 0) {
            crowding_ = 0;
            return true;
        }
        double crowding = 0;
        for (std::size_t k = 0; k + 1 < start_.size(); ++k) {
            const double m = static_cast<double>(start_[k + 1] - start_[k]);
            crowding += m * m;
        }
        if (crowding_ == 0) crowding_ = crowding;
        if (crowding <= 2 * crowding_) return false;
        crowding_ = 0;
        return true;
    }

    // Graded cells on every axis (detail::GradedAxis) over its slabs
    // (`counts`), at most budget^(1/D) a side.
    void graded(const std::vector<detail::SlabCounts>& counts, double budget) {
        graded_.clear();
        crowding_ = 0;
        aliased_ = false;
        for (int c = 0; c < D; ++c) {
            graded_.emplace_back(counts[static_cast<std::size_t>(c)], static_cast<long>(std::floor(std::pow(budget, 1.0 / D))));
            count_[c] = graded_.back().count();
            aliased_ = aliased_ || (reach_.domain.is_periodic() && count_[c] < 3);
        }
    }

    // R^2, R^3: graded cells over each axis's range without its n/256
    // lowest and n/256 highest coordinates (far particles, an envelope's
    // farthest tails: clamped into the end slabs, where they spread over the
    // other axes' cells), if every such range spans at most
    // SlabCounts::max_slabs slabs (a halo of more, clusters far apart: the
    // collapsed runs).
    bool graded_over_most(const Positions<D>& x, std::size_t n, double budget) {
        const std::size_t k = n / 256;
        std::vector<detail::SlabCounts> counts;
        std::vector<double> v;
        for (int c = 0; c < D; ++c) {
            v.assign(x[c].begin(), x[c].end());
            std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
            const double lo = v[k];
            std::nth_element(v.begin() + static_cast<std::ptrdiff_t>(k), v.end() - 1 - static_cast<std::ptrdiff_t>(k), v.end());
            const double hi = v[n - 1 - k];
            if (!(detail::SlabCounts::open_slabs(lo, hi, reach_.eps) <= detail::SlabCounts::max_slabs)) return false;
            counts.push_back(detail::SlabCounts::open(x[c], lo, hi, reach_.eps));
        }
        collapsed_.clear();
        graded(counts, budget);
        return true;
    }

    // Cells over each axis's runs of occupied slabs (detail::CollapsedAxis),
    // if at most max_cells of them: slabs of side eps if they fit, else
    // 2 eps, 4 eps, ...; at each slab side the runs that hold the fewest
    // particles may be left out (their particles share the collapsed cells
    // between the runs), n/16 particles at most over the axes. The finest
    // slabs, and with them the fewest runs left out, whose cells fit.
    bool collapse(const Positions<D>& x, const std::array<double, D>& lo, double max_cells, std::size_t n) {
        using detail::CollapsedAxis;
        using Run = detail::OccupiedSlabs::Run;
        std::vector<detail::OccupiedSlabs> slabs;
        for (int c = 0; c < D; ++c) slabs.emplace_back(x[c], lo[c], reach_.eps);
        for (int level = 0; level <= 32; ++level) {
            std::array<std::vector<Run>, D> runs;
            std::vector<double> thresholds{1};
            for (int c = 0; c < D; ++c) {
                runs[c] = slabs[c].runs(level);
                for (const Run& r : runs[c]) thresholds.push_back(r.total);
            }
            std::sort(thresholds.begin(), thresholds.end());
            thresholds.erase(std::unique(thresholds.begin(), thresholds.end()), thresholds.end());
            auto cells = [&](double threshold) {
                double product = 1;
                for (int c = 0; c < D; ++c) product *= CollapsedAxis::cells(CollapsedAxis::kept(runs[c], threshold));
                return product;
            };
            // The cells shrink as the threshold grows: the smallest that fits, by bisection.
            const auto fit = std::partition_point(thresholds.begin(), thresholds.end(),
                                                  [&](double t) { return cells(t) > max_cells; });
            if (fit == thresholds.end()) continue;
            std::size_t left_out = 0;
            for (int c = 0; c < D; ++c)
                for (const Run& r : runs[c]) left_out += r.total < *fit ? static_cast<std::size_t>(r.total) : 0;
            if (static_cast<double>(left_out) > static_cast<double>(n) / 16) continue;
            collapsed_.clear();
            for (int c = 0; c < D; ++c) {
                collapsed_.emplace_back(slabs[static_cast<std::size_t>(c)], level, CollapsedAxis::kept(runs[c], *fit));
                count_[c] = collapsed_.back().count();
            }
            outside_runs_ = left_out;
            return true;
        }
        return false;
    }

    std::size_t cell(const Positions<D>& x, std::size_t i) const {
        std::size_t k = 0;
        for (int c = D - 1; c >= 0; --c) k = k * static_cast<std::size_t>(count_[c]) + coordinate(x[c][i], c);
        return k;
    }

    std::size_t coordinate(double v, int c) const {
        if (!collapsed_.empty()) return collapsed_[static_cast<std::size_t>(c)].coordinate(v).first;
        if (!graded_.empty()) return graded_[static_cast<std::size_t>(c)].coordinate(v);
        return coordinate(v, origin_[c], side_[c], count_[c]);
    }
    static std::size_t coordinate(double v, double origin, double side, long count) {
        // clamped as a double: (v - origin)/side may exceed any long
        return static_cast<std::size_t>(std::clamp((v - origin) / side, 0.0, static_cast<double>(count - 1)));
    }

    static constexpr std::size_t copy_chunk = 8;
    detail::Reach<D> reach_;
    double margin_;  // the equal cells' side over eps at least (the constructor's SupportEdge)
    std::array<double, D> origin_{}, side_{};
    std::array<long, D> count_{};
    bool aliased_ = false;  // a periodic side of fewer than 3 cells
    // R^2, R^3: the axes over runs of occupied slabs (layout), or none; the
    // particles the last update found outside the runs, and those left out
    // of the runs when they were found (summed over the axes).
    std::vector<detail::CollapsedAxis> collapsed_;
    std::size_t strays_ = 0, outside_runs_ = 0;
    // Graded cells on every axis (a periodic box where particles crowd part
    // of it; R^2, R^3 where they spread over up to SlabCounts::max_slabs
    // slabs a side), or none; the sum of the cells' squared counts at the
    // first update after the layout was chosen (0: that update is still to
    // come; crowding_doubled).
    std::vector<detail::GradedAxis> graded_;
    double crowding_ = 0;
    bool order_kept_ = false;
    bool first_ = true;  // the update under way is the first (or the particle count changed)
    std::vector<std::size_t> start_, fill_, members_, previous_, slot_;  // slot_ inverts members_
    // The cell of each slot's particle (previous_cell_: of the order before a new sort).
    std::vector<std::size_t> slot_cell_, previous_cell_;
    std::array<std::vector<double>, D> sorted_;
    std::vector<std::pair<double, std::size_t>> by_position_;  // order_cells_by_position's scratch
};

// The O(N^2) baseline: every pair tested.
template <int D>
class AllPairs {
public:
    static constexpr int dim = D;

    AllPairs(Domain<D> domain, double eps) : reach_(domain, eps) {}

    void update(const Positions<D>& x) {
        detail::check_positions<D>(x, reach_.domain);
        for (int c = 0; c < D; ++c) x_[c].assign(x[c].begin(), x[c].end());
    }

    // The coordinates' arrays and particle i's position taken once: the
    // baseline every test of a search compares with, run unoptimised there
    // under the sanitizers (CI), where each subscript is a call.
    template <class F>
    void visit(std::size_t i, F&& f) const {
        const double eps2 = reach_.eps * reach_.eps;
        const std::size_t n = x_[0].size();
        std::array<const double*, D> x;
        Vector<D> xi;
        for (int c = 0; c < D; ++c) {
            x[c] = x_[c].data();
            xi[c] = x_[c][i];
        }
        for (std::size_t j = 0; j < n; ++j) {
            Vector<D> d;
            double r2 = 0;
            for (int c = 0; c < D; ++c) {
                d[c] = reach_.domain.displacement(xi[c], x[c][j]);
                r2 += d[c] * d[c];
            }
            if (r2 <= eps2) f(j, d);
        }
    }

private:
    detail::Reach<D> reach_;
    std::array<std::vector<double>, D> x_;
};

// The default search of a dimension: the cell list in every dimension.
template <int D>
struct DefaultSearch {
    using type = CellList<D>;
};
template <int D>
using Search = typename DefaultSearch<D>::type;

}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph

MOLLIFY_VECTOR_MISSES_ALLOWED_END
