// Weakly compressible SPH for the barotropic Euler equations with p = rho^2/2
// (Franz eqs. 3.4-3.6, on the torus 3.24-3.26): particles x_j with constant
// masses m_j = h^d rho_0(h j), and
//   dx_j/dt = u_j,
//   du_j/dt = -grad rho(x_j) = -sum_k m_k grad Phi_eps(x_j - x_k),      (3.5)
//   rho(x)  = sum_k m_k Phi_eps(x - x_k).                               (2.15)
// The kernel is a parameter: any type with the runtime's batch pair API
// (StaticKernel<table> or a run-time mollify::Kernel). With a search that
// visits particle by particle (SortedSweep, AllPairs) one call per particle
// on the displacements to all its neighbours; with a CellList one call per
// batch of up to ~1,000 pairs found cell by cell, each pair evaluated once
// for both particles (Newton's third law), so a run-time kernel costs one
// indirect call per particle or per batch and sweep.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/parallel.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/kernel_concept.hpp>
#include <mollify/smoothing.hpp>
#include <mollify/sph/domain.hpp>
#include <mollify/sph/neighbours.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <exception>
#include <memory>
#include <new>
#include <numeric>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace mollify::sph {
inline namespace MOLLIFY_ISA {

template <int D>
using Field = std::array<std::vector<double>, D>;

template <int D>
Positions<D> view(const Field<D>& x) {
    Positions<D> p;
    for (int c = 0; c < D; ++c) p[c] = x[c];
    return p;
}

namespace detail {

// A range of cells' sums over all slots: calloc'd, so that the pages of
// slots the range never reaches are never touched (R ranges' arrays of N
// slots occupy ~N + R layers of memory), and zero between sweeps (the
// reduction clears what it reads).
class SlotSums {
public:
    // Zero, of n values: kept where the size is the same (the sweeps keep it zero).
    void zeroed(std::size_t n) {
        if (n == n_) return;
        data_.reset(static_cast<double*>(std::calloc(std::max<std::size_t>(n, 1), sizeof(double))));
        if (!data_) throw std::bad_alloc();
        n_ = n;
    }
    double* data() { return data_.get(); }

private:
    struct Free {
        void operator()(double* p) const { std::free(p); }
    };
    std::unique_ptr<double[], Free> data_;
    std::size_t n_ = 0;
};

}  // namespace detail

// Particle positions and velocities, the state of the ODE system.
template <int D>
struct State {
    Field<D> x, u;
    std::size_t size() const { return x[0].size(); }
};

template <int D, RadialKernel Kernel, class NeighbourSearch = Search<D>>
class BarotropicEuler {
public:
    BarotropicEuler(Kernel kernel, double eps, Domain<D> domain, std::vector<double> mass)
        : kernel_(std::move(kernel)),
          smoothing_(eps, D),
          domain_(domain),
          search_(make_search(domain, eps, kernel_)),
          mass_(std::move(mass)) {
        for (std::size_t j = 0; j < mass_.size(); ++j)
            if (!(mass_[j] >= 0) || !std::isfinite(mass_[j]))
                fail("particle " + std::to_string(j) + " has mass " + mollify::detail::show(mass_[j]) +
                     " (not a finite number >= 0)");
        scratch_.resize(static_cast<std::size_t>(mollify::detail::thread_count()));
        // A kernel of another dimension fails here, not inside the parallel sweep.
        Scratch& s = scratch_[0];
        kernel_.pairs(points(s.dx, 0), smoothing_, std::span<double>(), outputs(s.grad, 0));
    }

    double eps() const { return smoothing_.h(); }
    const Domain<D>& domain() const { return domain_; }
    const std::vector<double>& mass() const { return mass_; }
    std::size_t size() const { return mass_.size(); }

    // a_j = -grad rho(x_j) (3.5), and rho_j = rho(x_j) (2.15) if rho is given.
    void acceleration(const Field<D>& x, Field<D>& a, std::vector<double>* rho = nullptr) {
        sweep(x, &a, rho);
    }
    void density(const Field<D>& x, std::vector<double>& rho) { sweep(x, nullptr, &rho); }

    // Franz (2.18) with (3.7): kinetic 1/2 sum m |u|^2, potential 1/2 sum m rho.
    double kinetic_energy(const Field<D>& u) const {
        double e = 0;
        for (std::size_t j = 0; j < size(); ++j) {
            double u2 = 0;
            for (int c = 0; c < D; ++c) u2 += u[c][j] * u[c][j];
            e += 0.5 * mass_[j] * u2;
        }
        return e;
    }
    double potential_energy(const std::vector<double>& rho) const {
        double e = 0;
        for (std::size_t j = 0; j < size(); ++j) e += 0.5 * mass_[j] * rho[j];
        return e;
    }

    // Pairs (i, j) with |x_i - x_j| <= eps met so far, i = j included.
    std::size_t interactions() const { return interactions_.load(std::memory_order_relaxed); }

    // Threads only where the last sweep met more pairs than this: a few
    // hundred particles cost less than waking the thread team (measured:
    // 2x slower at N = 250).
    static constexpr std::size_t parallel_above = 50000;

private:
    struct Scratch {
        Field<D> dx;
        // The kernel's outputs, coloured apart from the batch it reads.
        std::array<typename PairBatch<D>::template Buffer<double>, D> grad = PairBatch<D>::template buffers<double>(PairBatch<D>::next_colour + 1);
        typename PairBatch<D>::template Buffer<double> w = PairBatch<D>::template buffer<double>(PairBatch<D>::next_colour);
        std::vector<double> m;
        PairBatch<D> batch;
        double* sums = nullptr;  // the sums of the range of cells this thread sweeps (sweep_cells)

        void reserve(std::size_t k) {  // grows to the largest batch, then stays
            if (w.size() >= k) return;
            w.resize(k);
            for (int c = 0; c < D; ++c) {
                grad[c].resize(k);
                dx[c].resize(k);
            }
        }
    };

    void sweep(const Field<D>& x, Field<D>* a, std::vector<double>* rho) {
        const std::size_t n = size();
        for (int c = 0; c < D; ++c)
            if (x[c].size() != n)
                fail("state has " + std::to_string(x[c].size()) + " particles but " + std::to_string(n) + " masses");
        if constexpr (requires(PairBatch<D>& b) { search_.half_pairs(std::size_t{}, b, [](PairBatch<D>&) {}); }) {
            sweep_cells(x, a, rho);
        } else {
            search_.update(view<D>(x));
            resize_outputs(a, rho);
            sweep_particles(a, rho);
        }
    }

    void resize_outputs(Field<D>* a, std::vector<double>* rho) const {
        if (a)
            for (auto& c : *a) c.resize(size());
        if (rho) rho->resize(size());
    }

    // Particle by particle: each particle's neighbours gathered, one kernel
    // call on them, the sums (SortedSweep, AllPairs).
    void sweep_particles(Field<D>* a, std::vector<double>* rho) {
        const std::size_t n = size();
        std::size_t met = 0;
        const long count = static_cast<long>(n);
        // Positions were checked by the search's update, so the kernel sees
        // finite displacements and does not throw inside the parallel loop.
        [[maybe_unused]] const bool parallel = met_last_ > parallel_above;
        MOLLIFY_PARALLEL_FOR(if(parallel) schedule(dynamic, 64) reduction(+ : met))
        for (long li = 0; li < count; ++li) {
            const auto i = static_cast<std::size_t>(li);
            Scratch& s = scratch_[static_cast<std::size_t>(mollify::detail::thread_index())];
            gather(i, s);
            const std::size_t k = s.m.size();
            met += k;
            kernel_.pairs(points(s.dx, k), smoothing_, std::span<double>(s.w.data(), k), outputs(s.grad, k));
            if (rho) {
                double r = 0;
                for (std::size_t q = 0; q < k; ++q) r += s.m[q] * s.w[q];
                (*rho)[i] = r;
            }
            if (a)
                for (int c = 0; c < D; ++c) {
                    double g = 0;
                    for (std::size_t q = 0; q < k; ++q) g += s.m[q] * s.grad[c][q];
                    (*a)[c][i] = -g;
                }
        }
        interactions_.fetch_add(met, std::memory_order_relaxed);
        met_last_ = met;
    }

    // Cell by cell on the search's sorted copy, Newton's third law: each
    // pair {a, b} once, W(x_a - x_b) = W(x_b - x_a) and grad W odd, so one
    // kernel evaluation updates both (Franz 2.15, 3.5). The cells are cut
    // into R contiguous ranges of equal numbers of particles (up to four per
    // thread), each range summed by one thread into its own array in slot
    // order (no races). A range's pairs reach only its own layers and the
    // next (CellList::layers), so the arrays are added up layer by layer
    // from the ranges that reach each layer: ~N + R layers of reads and of
    // memory touched, where one array per thread over all cells costs T N
    // of both; and, each range's sums made in one order and added in range
    // order, the same bits in every run on as many threads. A layer is
    // added up by the thread that finishes the last range reaching it,
    // while the others still sweep: no loop waiting for every range. Then
    // permuted back to the caller's indices. The self term m_a W(0) once.
    void sweep_cells(const Field<D>& x, Field<D>* a, std::vector<double>* rho) {
        const std::size_t n = size();
        // Threads only where there is work to share (parallel_above), no more
        // than scratch spaces (the count may have changed since construction).
        const int threads = met_last_ > parallel_above ? std::min(mollify::detail::thread_count(), static_cast<int>(scratch_.size())) : 1;
        std::size_t met = 0;
        if (threads > 1) {
            met = threaded_cells(x, a, rho, threads);
        } else {
            search_.update(view<D>(x));
            const CellSweep c = prepare_cells(a, rho, 1);
            if (c.masses_moved) permute_masses(0, n);
            met = sweep_range(0, c, a, rho);
        }
        met += n;
        interactions_.fetch_add(met, std::memory_order_relaxed);
        met_last_ = met;
    }

    // The threaded sweep, one parallel region (where threads sleep between
    // regions, each region's start and end cost ~2 % of a sweep at N ~ 10^4,
    // where there were four): thread 0 begins the search's update while the
    // others wake up; each thread refreshes its part of the slots (and where
    // the order changed, of the masses in slot order); thread 0 finishes the
    // update and prepares the ranges; each thread sweeps the ranges of its
    // own part (schedule(static): its slots and sums stay in its core's
    // cache from sweep to sweep: taken as threads came free, two threads lost
    // ~10 % at N ~ 10^4 and ~6 % at 10^5). The waits between the steps spin,
    // each for one thread's short serial step or the others' equal parts.
    std::size_t threaded_cells(const Field<D>& x, Field<D>* a, std::vector<double>* rho, [[maybe_unused]] int threads) {
        const Positions<D> xv = view<D>(x);
        const std::size_t n = size();
        std::atomic<int> stage{0};  // 1: update begun, 2: ranges prepared, -1: failed
        std::atomic<int> copied{0}, permuted{0}, swept{0};
        std::atomic<bool> broken{false};
        std::exception_ptr failure;
        CellSweep c{};
        std::size_t met = 0;
        auto on_thread_0 = [&](int next, auto&& step) {
            try {
                step();
                stage.store(next, std::memory_order_release);
            } catch (...) {
                failure = std::current_exception();
                stage.store(-1, std::memory_order_release);
            }
        };
        auto wait_past = [&](int now) {
            int s = now;
            mollify::detail::spin_until([&] { return (s = stage.load(std::memory_order_acquire)) != now; });
            return s;
        };
        auto all_done = [](std::atomic<int>& count, int team) {
            count.fetch_add(1, std::memory_order_acq_rel);
            mollify::detail::spin_until([&] { return count.load(std::memory_order_acquire) == team; });
        };
        MOLLIFY_PARALLEL(num_threads(threads) reduction(+ : met)) {
            const int team = mollify::detail::team_size(), me = mollify::detail::thread_index();
            const std::size_t from = NeighbourSearch::part_begin(n, me, team), to = NeighbourSearch::part_begin(n, me + 1, team);
            if (me == 0) on_thread_0(1, [&] { search_.begin_update(xv); });
            if (wait_past(0) == 1) {
                if (!search_.update_slots(xv, from, to)) broken.store(true, std::memory_order_relaxed);
                if (me == 0) {
                    all_done(copied, team);
                    on_thread_0(2, [&] {
                        search_.finish_update(xv, !broken.load(std::memory_order_relaxed));
                        c = prepare_cells(a, rho, team);
                    });
                } else {
                    copied.fetch_add(1, std::memory_order_acq_rel);
                }
                if (wait_past(1) == 2) {
                    if (c.masses_moved) {
                        permute_masses(from, to);
                        all_done(permuted, team);
                    }
                    MOLLIFY_FOR(schedule(static) nowait)
                    for (long lt = 0; lt < static_cast<long>(c.ranges); ++lt)
                        met += sweep_range(static_cast<std::size_t>(lt), c, a, rho);
                }
            }
            // Thread 0 reaches the region's end barrier last: where threads
            // sleep (OMP_WAIT_POLICY=passive) one that arrives early sleeps
            // there until the last one wakes it, ~35 us on the KVM host of
            // stop 63 (5 % of a two-thread sweep at N ~ 10^4), while the
            // others are not waited for once thread 0 has gone on. The
            // pauses after their signal let them reach the barrier first.
            if (me == 0) {
                all_done(swept, team);
                for (int k = 0; k < 20; ++k) mollify::detail::cpu_pause();
            } else {
                swept.fetch_add(1, std::memory_order_acq_rel);
            }
        }
        if (failure) std::rethrow_exception(failure);
        return met;
    }

    // What the ranges need, once the search is updated: the outputs sized,
    // W(0) and grad W(0), the ranges and their layers; and whether the
    // masses in slot order are to be permuted again (the order changed).
    struct CellSweep {
        double w0;
        std::array<double, D> g0;
        std::size_t layers, ranges;
        bool masses_moved;
    };

    CellSweep prepare_cells(Field<D>* a, std::vector<double>* rho, int threads) {
        resize_outputs(a, rho);
        const std::size_t n = size(), cells = search_.cells();
        CellSweep c;
        bool kept = false;
        if constexpr (requires { search_.order_kept(); }) kept = search_.order_kept();
        c.masses_moved = !kept || mass_sorted_.size() != n;
        mass_sorted_.resize(n);
        // W(0), grad W(0): one kernel call on the zero displacement.
        Scratch& s0 = scratch_[0];
        s0.reserve(1);
        for (int k = 0; k < D; ++k) s0.dx[k][0] = 0.0;
        kernel_.pairs(points(s0.dx, 1), smoothing_, std::span<double>(s0.w.data(), 1), outputs(s0.grad, 1));
        c.w0 = s0.w[0];
        for (int k = 0; k < D; ++k) c.g0[k] = s0.grad[k][0];
        c.layers = std::max<std::size_t>(search_.layers(), 1);
        // Up to four ranges per thread (a thread's are contiguous). No more
        // ranges than layers unless that leaves a thread idle (a flat domain):
        // then ~2 T / L arrays per slot, still fewer than one per thread.
        const auto team = static_cast<std::size_t>(threads);
        c.ranges = team == 1 ? 1 : std::min(4 * team, std::max(c.layers, team));
        split_cells(n, cells, c.ranges);
        reaching_ranges(cells, c.layers, c.ranges);
        if (sums_.size() < c.ranges) sums_.resize(c.ranges);
        for (std::size_t t = 0; t < c.ranges; ++t) sums_[t].zeroed((D + 1) * n);
        return c;
    }

    // The masses of the slots [from, to) in slot order.
    void permute_masses(std::size_t from, std::size_t to) {
        const std::vector<std::size_t>& member = search_.members();
        for (std::size_t slot = from; slot < to; ++slot) mass_sorted_[slot] = mass_[member[slot]];
    }

    // Range t's pairs into its own array; then each layer it was the last
    // range to reach (acq_rel: that thread sees the other ranges' sums).
    // The pairs met.
    std::size_t sweep_range(std::size_t t, const CellSweep& c, Field<D>* a, std::vector<double>* rho) {
        Scratch& s = scratch_[static_cast<std::size_t>(mollify::detail::thread_index())];
        s.sums = sums_[t].data();
        std::size_t met = 0;
        for (std::size_t home = cut_[t]; home < cut_[t + 1]; ++home)
            search_.half_pairs(home, s.batch, [&](PairBatch<D>& b) {
                met += 2 * b.size;
                accumulate(b, s);
            });
        for (std::size_t k = layers_of_start_[t]; k < layers_of_start_[t + 1]; ++k)
            if (pending_[layers_of_[k]].fetch_sub(1, std::memory_order_acq_rel) == 1)
                add_layer(layers_of_[k], c, a, rho);
        return met;
    }

    // Layer z's sums: the self term and each reaching range's array, in
    // range order (the same bits whichever thread adds them), the arrays
    // left zero for the next sweep.
    void add_layer(std::size_t z, const CellSweep& c, Field<D>* a, std::vector<double>* rho) {
        const std::vector<std::size_t>& member = search_.members();
        const std::size_t per_layer = search_.cells() / c.layers;
        const std::size_t first = search_.first_slot(z * per_layer), last = search_.first_slot((z + 1) * per_layer);
        for (std::size_t sl = first; sl < last; ++sl) {
            const std::size_t i = member[sl];
            double r = mass_sorted_[sl] * c.w0;
            std::array<double, D> g;
            for (int k = 0; k < D; ++k) g[k] = mass_sorted_[sl] * c.g0[k];
            for (std::size_t k = reach_start_[z]; k < reach_start_[z + 1]; ++k) {
                double* sum = sums_[reach_[k]].data() + (D + 1) * sl;
                r += sum[0];
                for (int j = 0; j < D; ++j) g[j] += sum[1 + j];
                std::fill(sum, sum + D + 1, 0.0);
            }
            if (rho) (*rho)[i] = r;
            if (a)
                for (int k = 0; k < D; ++k) (*a)[k][i] = -g[k];
        }
    }

    // cut_[t], t = 0 .. ranges: range t is the cells [cut_[t], cut_[t + 1]),
    // the first cell whose first slot is at least t n / ranges (a range may
    // be empty where one cell holds many particles).
    void split_cells(std::size_t n, std::size_t cells, std::size_t ranges) {
        cut_.assign(ranges + 1, cells);
        cut_[0] = 0;
        for (std::size_t t = 1; t < ranges; ++t) {
            const std::size_t target = n * t / ranges;
            // bisection over the cells (first_slot does not decrease; not
            // std::ranges::partition_point over views::iota, which clang 14
            // cannot compile with libstdc++ 12's ranges)
            std::size_t lo = cut_[t - 1], hi = cells;
            while (lo < hi) {
                const std::size_t mid = lo + (hi - lo) / 2;
                if (search_.first_slot(mid) < target) lo = mid + 1;
                else hi = mid;
            }
            cut_[t] = lo;
        }
    }

    // reach_[reach_start_[z] .. reach_start_[z + 1]): the ranges whose pairs
    // can reach layer z, those with a cell in layer z or in the layer before
    // (cyclically where periodic), in increasing order: counted, then filled
    // in range order (no allocation once the sizes are reached).
    void reaching_ranges(std::size_t cells, std::size_t layers, std::size_t ranges) {
        const std::size_t per_layer = cells / layers;
        const bool wrap = domain_.is_periodic();
        // Calls f(z) for each layer range t reaches, each once.
        auto each_layer = [&](std::size_t t, auto&& f) {
            if (cut_[t] == cut_[t + 1]) return;
            const std::size_t z0 = cut_[t] / per_layer, z1 = (cut_[t + 1] - 1) / per_layer;
            for (std::size_t z = z0; z <= z1; ++z) f(z);
            const std::size_t next = z1 + 1 < layers ? z1 + 1 : wrap ? 0 : layers;
            if (next < layers && !(next >= z0 && next <= z1)) f(next);
        };
        reach_start_.assign(layers + 1, 0);
        for (std::size_t t = 0; t < ranges; ++t) each_layer(t, [&](std::size_t z) { ++reach_start_[z + 1]; });
        std::partial_sum(reach_start_.begin(), reach_start_.end(), reach_start_.begin());
        reach_.resize(reach_start_[layers]);
        fill_.assign(reach_start_.begin(), reach_start_.end() - 1);
        for (std::size_t t = 0; t < ranges; ++t) each_layer(t, [&](std::size_t z) { reach_[fill_[z]++] = t; });
        // The inverse, the layers each range reaches, and the count of
        // ranges each layer still waits for.
        layers_of_start_.assign(ranges + 1, 0);
        for (std::size_t t = 0; t < ranges; ++t) each_layer(t, [&](std::size_t) { ++layers_of_start_[t + 1]; });
        std::partial_sum(layers_of_start_.begin(), layers_of_start_.end(), layers_of_start_.begin());
        layers_of_.resize(layers_of_start_[ranges]);
        for (std::size_t t = 0, k = 0; t < ranges; ++t) each_layer(t, [&](std::size_t z) { layers_of_[k++] = z; });
        if (pending_size_ < layers) {
            pending_ = std::make_unique<std::atomic<std::size_t>[]>(layers);
            pending_size_ = layers;
        }
        for (std::size_t z = 0; z < layers; ++z)
            pending_[z].store(reach_start_[z + 1] - reach_start_[z], std::memory_order_relaxed);
    }

    // rho_a += m_b W, rho_b += m_a W; grad_a += m_b grad W, grad_b -= m_a grad W.
    void accumulate(const PairBatch<D>& b, Scratch& s) const {
        const std::size_t k = b.size;
        s.reserve(k);
        std::array<std::span<const double>, D> d;
        for (int c = 0; c < D; ++c) d[c] = std::span<const double>(b.d[c].data(), k);
        // Displacements of checked positions are finite and the kernel's
        // dimension was checked by the constructor: a kernel that offers
        // the loop without its checks (StaticKernel) is called so.
        if constexpr (requires { Kernel::pairs_unchecked(d, smoothing_, s.w.data(), outputs(s.grad, k), k); })
            Kernel::pairs_unchecked(d, smoothing_, s.w.data(), outputs(s.grad, k), k);
        else
            kernel_.pairs(d, smoothing_, std::span<double>(s.w.data(), k), outputs(s.grad, k));
        const double* __restrict m = mass_sorted_.data();
        double* __restrict sum = s.sums;
        const double* __restrict w = s.w.data();
        const std::size_t* __restrict pa = b.a.data();
        const std::size_t* __restrict pb = b.b.data();
        std::array<const double*, D> grad;
        for (int c = 0; c < D; ++c) grad[c] = s.grad[c].data();
        // The pairs come grouped by a: a's sums in registers, b's scattered
        // (distinct within a group, so no chain through memory).
        constexpr std::size_t stride = D + 1;
        std::size_t q = 0;
        for (std::size_t g = 0; g < b.groups; ++g) {
            const std::size_t i = pa[q], end = b.ends[g];
            double* __restrict own = sum + stride * i;
#if defined(__AVX2__)
            // In 3D a particle's sums (rho, grad) are one 4-lane vector: one
            // multiply-add per pair and side.
            if constexpr (D == 3) {
                const __m256d mi = _mm256_mul_pd(_mm256_set1_pd(m[i]), _mm256_set_pd(-1.0, -1.0, -1.0, 1.0));
                __m256d sum_i = _mm256_setzero_pd();
                const auto pair = [&](std::size_t j, __m256d v) {  // v = (W, grad W) of the pair (i, j)
                    double* __restrict to = sum + stride * j;
                    sum_i = _mm256_fmadd_pd(_mm256_set1_pd(m[j]), v, sum_i);
                    _mm256_storeu_pd(to, _mm256_fmadd_pd(mi, v, _mm256_loadu_pd(to)));  // m_a W, -m_a grad W
                };
                for (; q + 4 <= end; q += 4) {  // four pairs' (W, grad W) transposed into four vectors
                    const __m256d w4 = _mm256_loadu_pd(w + q), g0 = _mm256_loadu_pd(grad[0] + q);
                    const __m256d g1 = _mm256_loadu_pd(grad[1] + q), g2 = _mm256_loadu_pd(grad[2] + q);
                    const __m256d t0 = _mm256_unpacklo_pd(w4, g0), t1 = _mm256_unpackhi_pd(w4, g0);
                    const __m256d t2 = _mm256_unpacklo_pd(g1, g2), t3 = _mm256_unpackhi_pd(g1, g2);
                    pair(pb[q], _mm256_permute2f128_pd(t0, t2, 0x20));
                    pair(pb[q + 1], _mm256_permute2f128_pd(t1, t3, 0x20));
                    pair(pb[q + 2], _mm256_permute2f128_pd(t0, t2, 0x31));
                    pair(pb[q + 3], _mm256_permute2f128_pd(t1, t3, 0x31));
                }
                for (; q < end; ++q) pair(pb[q], _mm256_set_pd(grad[2][q], grad[1][q], grad[0][q], w[q]));
                _mm256_storeu_pd(own, _mm256_add_pd(_mm256_loadu_pd(own), sum_i));
                continue;
            }
#endif
            const double mi = m[i];
            double ri = 0;
            std::array<double, D> gi{};
            for (; q < end; ++q) {
                double* __restrict to = sum + stride * pb[q];
                const double wq = w[q], mj = m[pb[q]];
                ri += mj * wq;
                to[0] += mi * wq;
                for (int c = 0; c < D; ++c) {
                    const double gc = grad[c][q];
                    gi[c] += mj * gc;
                    to[1 + c] -= mi * gc;
                }
            }
            own[0] += ri;
            for (int c = 0; c < D; ++c) own[1 + c] += gi[c];
        }
    }

    void gather(std::size_t i, Scratch& s) const {
        for (int c = 0; c < D; ++c) s.dx[c].clear();
        s.m.clear();
        search_.visit(i, [&](std::size_t j, const Vector<D>& d) {
            for (int c = 0; c < D; ++c) s.dx[c].push_back(d[c]);
            s.m.push_back(mass_[j]);
        });
        const std::size_t k = s.m.size();
        if (s.w.size() < k) {  // grows to the largest neighbourhood, then stays
            s.w.resize(k);
            for (int c = 0; c < D; ++c) s.grad[c].resize(k);
        }
    }

    static std::array<std::span<const double>, D> points(const Field<D>& f, std::size_t k) {
        std::array<std::span<const double>, D> p;
        for (int c = 0; c < D; ++c) p[c] = std::span<const double>(f[c].data(), k);
        return p;
    }
    template <class Components>
    static std::array<std::span<double>, D> outputs(Components& f, std::size_t k) {
        std::array<std::span<double>, D> p;
        for (int c = 0; c < D; ++c) p[c] = std::span<double>(f[c].data(), k);
        return p;
    }

    Kernel kernel_;
    Smoothing smoothing_;
    Domain<D> domain_;
    // A search told whether pairs at exactly eps matter (CellList: cells of
    // side eps only where they do not, the kernel being C^1 or more).
    static NeighbourSearch make_search(Domain<D> domain, double eps, const Kernel& kernel) {
        if constexpr (std::is_constructible_v<NeighbourSearch, Domain<D>, double, SupportEdge>)
            return NeighbourSearch(domain, eps, support_edge_of(kernel));
        else
            return NeighbourSearch(domain, eps);
    }

    NeighbourSearch search_;
    std::vector<double> mass_, mass_sorted_;  // mass_sorted_: in the search's slot order
    std::vector<Scratch> scratch_;
    // Per range of cells, per slot rho, grad_0 .. grad_{D-1} side by side (one
    // cache line per neighbour updated); zero between sweeps. The ranges and
    // which of them reach each layer (sweep_cells).
    std::vector<detail::SlotSums> sums_;
    std::vector<std::size_t> cut_, reach_, reach_start_, fill_, layers_of_, layers_of_start_;
    std::unique_ptr<std::atomic<std::size_t>[]> pending_;  // per layer: the ranges reaching it not yet summed
    std::size_t pending_size_ = 0;
    std::atomic<std::size_t> interactions_{0};
    std::size_t met_last_ = 0;  // interactions of the last sweep: the work estimate
};

}  // namespace MOLLIFY_ISA
}  // namespace mollify::sph
