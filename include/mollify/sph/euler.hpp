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
#include <memory>
#include <new>
#include <numeric>
#include <ranges>
#include <span>
#include <string>
#include <vector>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace mollify::sph {

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
        : kernel_(std::move(kernel)), smoothing_(eps, D), domain_(domain), search_(domain, eps), mass_(std::move(mass)) {
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

private:
    struct Scratch {
        Field<D> dx, grad;
        std::vector<double> w, m;
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
        search_.update(view<D>(x));
        if (a)
            for (auto& c : *a) c.resize(n);
        if (rho) rho->resize(n);
        if constexpr (requires(PairBatch<D>& b) { search_.half_pairs(std::size_t{}, b, [](PairBatch<D>&) {}); })
            sweep_cells(a, rho);
        else
            sweep_particles(a, rho);
    }

    // Particle by particle: each particle's neighbours gathered, one kernel
    // call on them, the sums (SortedSweep, AllPairs).
    void sweep_particles(Field<D>* a, std::vector<double>* rho) {
        const std::size_t n = size();
        std::size_t met = 0;
        const long count = static_cast<long>(n);
        // Positions were checked by the search's update, so the kernel sees
        // finite displacements and does not throw inside the parallel loop.
        // Threads only where there is work to share: a few hundred particles
        // cost less than waking the thread team (measured: 2x slower at N = 250).
        [[maybe_unused]] const bool parallel = met_last_ > 50000;
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
    // order, the same bits in every run on as many threads. Then permuted
    // back to the caller's indices. The self term m_a W(0) once.
    void sweep_cells(Field<D>* a, std::vector<double>* rho) {
        const std::size_t n = size(), cells = search_.cells();
        const std::vector<std::size_t>& member = search_.members();
        [[maybe_unused]] const bool parallel = met_last_ > 50000;
        // The masses in slot order, again only where the order changed.
        bool kept = false;
        if constexpr (requires { search_.order_kept(); }) kept = search_.order_kept();
        if (!kept || mass_sorted_.size() != n) {
            mass_sorted_.resize(n);
            MOLLIFY_PARALLEL_FOR(if(parallel) schedule(static))
            for (long ls = 0; ls < static_cast<long>(n); ++ls)
                mass_sorted_[static_cast<std::size_t>(ls)] = mass_[member[static_cast<std::size_t>(ls)]];
        }
        // W(0), grad W(0): one kernel call on the zero displacement.
        Scratch& s0 = scratch_[0];
        s0.reserve(1);
        for (int c = 0; c < D; ++c) s0.dx[c][0] = 0.0;
        kernel_.pairs(points(s0.dx, 1), smoothing_, std::span<double>(s0.w.data(), 1), outputs(s0.grad, 1));
        const double w0 = s0.w[0];
        std::array<double, D> g0;
        for (int c = 0; c < D; ++c) g0[c] = s0.grad[c][0];
        // No more threads than scratch spaces (the count may have changed since construction).
        [[maybe_unused]] const int threads =
            parallel ? std::min(mollify::detail::thread_count(), static_cast<int>(scratch_.size())) : 1;
        const std::size_t layers = std::max<std::size_t>(search_.layers(), 1);
        // Up to four ranges per thread, taken as threads come free: a slower
        // thread (a shared host, a denser region) takes fewer of them. No more
        // ranges than layers unless that leaves a thread idle (a flat domain):
        // then ~2 T / L arrays per slot, still fewer than one per thread.
        const auto team = static_cast<std::size_t>(threads);
        const std::size_t ranges = team == 1 ? 1 : std::min(4 * team, std::max(layers, team));
        split_cells(n, cells, ranges);
        reaching_ranges(cells, layers, ranges);
        if (sums_.size() < ranges) sums_.resize(ranges);
        for (std::size_t t = 0; t < ranges; ++t) sums_[t].zeroed((D + 1) * n);
        std::size_t met = 0;
        MOLLIFY_PARALLEL_FOR(if(ranges > 1) num_threads(threads) schedule(dynamic, 1) reduction(+ : met))
        for (long lt = 0; lt < static_cast<long>(ranges); ++lt) {
            const auto t = static_cast<std::size_t>(lt);
            Scratch& s = scratch_[static_cast<std::size_t>(mollify::detail::thread_index())];
            s.sums = sums_[t].data();
            const std::size_t first = cut_[t], last = cut_[t + 1];
            for (std::size_t home = first; home < last; ++home)
                search_.half_pairs(home, s.batch, [&](PairBatch<D>& b) {
                    met += 2 * b.size;
                    accumulate(b, s);
                });
        }
        const std::size_t per_layer = cells / layers;
        MOLLIFY_PARALLEL_FOR(if(parallel) num_threads(threads) schedule(static))
        for (long lz = 0; lz < static_cast<long>(layers); ++lz) {
            const auto z = static_cast<std::size_t>(lz);
            const std::size_t first = search_.first_slot(z * per_layer), last = search_.first_slot((z + 1) * per_layer);
            for (std::size_t sl = first; sl < last; ++sl) {
                const std::size_t i = member[sl];
                double r = mass_sorted_[sl] * w0;
                std::array<double, D> g;
                for (int c = 0; c < D; ++c) g[c] = mass_sorted_[sl] * g0[c];
                for (std::size_t k = reach_start_[z]; k < reach_start_[z + 1]; ++k) {
                    double* sum = sums_[reach_[k]].data() + (D + 1) * sl;
                    r += sum[0];
                    for (int c = 0; c < D; ++c) g[c] += sum[1 + c];
                    std::fill(sum, sum + D + 1, 0.0);
                }
                if (rho) (*rho)[i] = r;
                if (a)
                    for (int c = 0; c < D; ++c) (*a)[c][i] = -g[c];
            }
        }
        met += n;
        interactions_.fetch_add(met, std::memory_order_relaxed);
        met_last_ = met;
    }

    // cut_[t], t = 0 .. ranges: range t is the cells [cut_[t], cut_[t + 1]),
    // the first cell whose first slot is at least t n / ranges (a range may
    // be empty where one cell holds many particles).
    void split_cells(std::size_t n, std::size_t cells, std::size_t ranges) {
        cut_.assign(ranges + 1, cells);
        cut_[0] = 0;
        for (std::size_t t = 1; t < ranges; ++t) {
            const std::size_t target = n * t / ranges;
            const auto from = std::views::iota(cut_[t - 1], cells);
            const auto at = std::ranges::partition_point(from, [&](std::size_t c) { return search_.first_slot(c) < target; });
            cut_[t] = cut_[t - 1] + static_cast<std::size_t>(at - from.begin());
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
    static std::array<std::span<double>, D> outputs(Field<D>& f, std::size_t k) {
        std::array<std::span<double>, D> p;
        for (int c = 0; c < D; ++c) p[c] = std::span<double>(f[c].data(), k);
        return p;
    }

    Kernel kernel_;
    Smoothing smoothing_;
    Domain<D> domain_;
    NeighbourSearch search_;
    std::vector<double> mass_, mass_sorted_;  // mass_sorted_: in the search's slot order
    std::vector<Scratch> scratch_;
    // Per range of cells, per slot rho, grad_0 .. grad_{D-1} side by side (one
    // cache line per neighbour updated); zero between sweeps. The ranges and
    // which of them reach each layer (sweep_cells).
    std::vector<detail::SlotSums> sums_;
    std::vector<std::size_t> cut_, reach_, reach_start_, fill_;
    std::atomic<std::size_t> interactions_{0};
    std::size_t met_last_ = 0;  // interactions of the last sweep: the work estimate
};

}  // namespace mollify::sph
