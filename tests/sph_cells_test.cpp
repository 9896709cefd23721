// The cell-by-cell SPH sweep (CellList::half_pairs, BarotropicEuler's
// Newton's-third-law path) against the O(N^2) baseline AllPairs: every pair
// within eps exactly once, on random and lattice particles, in a periodic
// box and in R^D, with fewer than 3 cells per side (aliasing), pairs at
// exactly eps and particles on cell boundaries, coincident particles, a
// crowded cell; densities and accelerations against the particle sweep; in
// 1D (the default search there too), 2D and 3D.
// Built for the default target, for x86-64-v3 (the pair test's and the 3D
// sums' AVX2 forms) and, on a machine with AVX-512, for x86-64-v4 (the
// pair test's AVX-512 form and gathers, pair_batch.hpp): tests/CMakeLists.txt.
#include <mollify/sph.hpp>
#include <mollify/tables/wendland/k_2_D1.hpp>
#include <mollify/tables/wendland/k_2_D2.hpp>
#include <mollify/tables/mollifier/M_1_D3.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>
#include "sanitized.hpp"
#include "sph_points.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <string>

#if defined(_OPENMP)
#include <omp.h>
#endif
#if defined(_OPENMP) && defined(__clang__) && defined(MOLLIFY_SANITIZED_BUILD)
#include <sanitizer/lsan_interface.h>
#endif

namespace {

// While alive, LeakSanitizer skips this thread's allocations (clang
// sanitizer builds with OpenMP only; elsewhere nothing). LLVM's libomp (14)
// never frees the team it grows to 3, 5 and 8 threads (__kmp_fork_call's
// allocations, on this thread): not mollify's memory. mollify's own
// allocations in that scope are skipped too (its sweeps are leak-checked in
// the other tests); out-of-bounds and use-after-free are checked as everywhere.
struct LeaksOfThisThreadUnchecked {
#if defined(_OPENMP) && defined(__clang__) && defined(MOLLIFY_SANITIZED_BUILD)
    LeaksOfThisThreadUnchecked() { __lsan_disable(); }
    ~LeaksOfThisThreadUnchecked() { __lsan_enable(); }
    LeaksOfThisThreadUnchecked(const LeaksOfThisThreadUnchecked&) = delete;
    LeaksOfThisThreadUnchecked& operator=(const LeaksOfThisThreadUnchecked&) = delete;
#endif
};

using namespace mollify;
using namespace mollify::sph;

constexpr Precision fast = Precision::fast;  // as the scenes run SPH
using Wendland1D = StaticKernel<tables::wendland_k_2_D1, fast>;
using Wendland2D = StaticKernel<tables::wendland_k_2_D2, fast>;
using Wendland3D = StaticKernel<tables::wendland_k_2_D3, fast>;
using MollifierM1 = StaticKernel<tables::mollifier_M_1_D3, fast>;  // C^0: grad W jumps at the edge

using mollify::testing::random_points;

#if defined(MOLLIFY_EXPECT_AVX2)
// The v3 build must exercise the AVX2 pair test, not the scalar fallback.
static_assert(MOLLIFY_EXPECT_AVX2 == 1);
#if !defined(__AVX2__)
#error "sph_cells_v3_test is built without AVX2: the SIMD pair test would go untested"
#endif
TEST(NeighboursV3, CpuHasAvx2) {
    // A CPU without AVX2 cannot run this build's tests: a failure, not a skip.
    ASSERT_TRUE(__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"));
}
#endif

#if defined(MOLLIFY_EXPECT_AVX512)
// The v4 build must exercise the AVX-512 pair test and gathers.
static_assert(MOLLIFY_EXPECT_AVX512 == 1);
#if !defined(__AVX512F__) || !defined(__AVX512VL__)
#error "sph_cells_v4_test is built without AVX-512: the AVX-512 pair test would go untested"
#endif
TEST(NeighboursV4, CpuHasAvx512) {
    ASSERT_TRUE(__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl"));
}
#endif

// The unordered pairs {i, j}, i < j, with x_i - x_j: from CellList's
// half_pairs (each must come once) and from AllPairs.
template <int D>
using PairSet = std::map<std::pair<std::size_t, std::size_t>, std::array<double, D>>;

template <int D>
PairSet<D> half_pairs_of(const CellList<D>& s) {
    PairSet<D> out;
    PairBatch<D> batch;
    for (std::size_t cell = 0; cell < s.cells(); ++cell)
        s.half_pairs(cell, batch, [&](const PairBatch<D>& b) {
            for (std::size_t q = 0; q < b.size; ++q) {
                std::size_t i = s.members()[b.a[q]], j = s.members()[b.b[q]];
                std::array<double, D> d;
                for (int c = 0; c < D; ++c) d[c] = b.d[c][q];
                EXPECT_NE(i, j) << "a particle paired with itself";
                if (i > j) {
                    std::swap(i, j);
                    for (auto& v : d) v = -v;
                }
                EXPECT_TRUE(out.emplace(std::pair{i, j}, d).second) << "pair " << i << ", " << j << " met twice";
            }
        });
    return out;
}

template <int D>
void expect_half_pairs_as_all_pairs(const Domain<D>& dom, double eps, const Field<D>& x) {
    CellList<D> fast(dom, eps);
    AllPairs<D> slow(dom, eps);
    fast.update(view<D>(x));
    slow.update(view<D>(x));
    // Twice: the second update starts from the first one's order.
    for (int round = 0; round < 2; ++round) {
        const PairSet<D> a = half_pairs_of(fast);
        PairSet<D> b;
        for (std::size_t i = 0; i < x[0].size(); ++i)
            slow.visit(i, [&](std::size_t j, const Vector<D>& d) {
                if (j > i) b.emplace(std::pair{i, j}, std::array<double, D>(d));
            });
        ASSERT_EQ(a.size(), b.size());
        ASSERT_GT(b.size(), 0u) << "no pairs at all: the comparison checked nothing";
        auto ia = a.begin();
        for (auto ib = b.begin(); ib != b.end(); ++ia, ++ib) {
            ASSERT_EQ(ia->first, ib->first);
            // Equal to rounding: the cell path shifts the neighbour by L
            // where the minimum image subtracts L from the difference.
            for (int c = 0; c < D; ++c) EXPECT_NEAR(ia->second[c], ib->second[c], 1e-15);
        }
        fast.update(view<D>(x));
    }
}

// Under the sanitizers (-O0 + ASan) the all-pairs baselines cost ~40x the
// release build's (190 s of CI for these tests): a quarter of the random
// particles and a lattice of side 8 there, the same cases.
constexpr std::size_t fewer = mollify::testing::sanitized_build ? 4 : 1;
constexpr int lattice_side = mollify::testing::sanitized_build ? 8 : 16;

// A cubic lattice of spacing 1/16 in [0, 1)^D with eps = 2/16 (dyadic: every
// distance, cell boundary and image shift exact): neighbours at exactly
// eps, particles exactly on cell boundaries (cells of side 1/8), and a few
// coincident particles.
template <int D>
Field<D> dyadic_lattice(int side) {
    Field<D> x;
    int total = 1;
    for (int c = 0; c < D; ++c) total *= side;
    for (int i = 0; i < total; ++i) {
        int k = i;
        for (int c = 0; c < D; ++c) {
            x[c].push_back((k % side) / static_cast<double>(side));
            k /= side;
        }
    }
    if (total <= 77) ADD_FAILURE() << "a lattice of " << total << " sites has no site 77 to repeat";
    for (int i : {0, 5, 5, 77})
        for (int c = 0; c < D; ++c) x[c].push_back(x[c][static_cast<std::size_t>(std::min(i, total - 1))]);
    return x;
}

// Random points on the grid of spacing 2^-20 (dyadic, so that both paths
// compute identical displacements), with coincident ones.
template <int D>
Field<D> dyadic_random(std::size_t n, double lo, double hi, unsigned seed) {
    Field<D> x = random_points<D>(n, lo, hi, seed);
    for (auto& c : x)
        for (auto& v : c) v = std::ldexp(std::floor(std::ldexp(v, 20)), -20);
    for (int c = 0; c < D; ++c) {
        x[c].push_back(x[c][3]);
        x[c].push_back(x[c][3]);
    }
    return x;
}

// Where a pair batch's buffers lie within a 4 KiB page (pair_batch.hpp,
// detail::ColouredAllocator): each at its colour's offset, however it grew
// or was copied, all of them apart; close 1-3 colours below each y, so
// that append_near's loads of y never wait on its stores to close.
std::size_t page_offset(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % mollify::detail::page_bytes; }

TEST(PairBatchBuffers, EachAtItsColourApartFromTheOthers) {
    using B = PairBatch<3>;
    B b;
    b.reserve(3000);  // past capacity: the buffers grew
    for (auto& c : b.y) c.resize(700);
    b.slot.resize(700);
    b.close.resize(716);
    const B copy = b;
    for (const B* batch : std::array<const B*, 2>{&b, &copy}) {
        std::map<std::size_t, std::string> at;
        auto expect_colour = [&](const void* p, std::size_t colour, const std::string& name) {
            const std::size_t offset = 64 + mollify::detail::colour_bytes * colour;
            EXPECT_EQ(page_offset(p), offset) << name;
            EXPECT_TRUE(at.emplace(page_offset(p), name).second) << name << " shares its offset with " << at[page_offset(p)];
        };
        for (int c = 0; c < 3; ++c) {
            expect_colour(batch->d[c].data(), B::d_colour + c, "d" + std::to_string(c));
            expect_colour(batch->y[c].data(), B::y_colour + c, "y" + std::to_string(c));
            // close below y by 1-3 colours: y's loads run ahead of close's stores
            const std::size_t below = page_offset(batch->y[c].data()) - page_offset(batch->close.data());
            EXPECT_GE(below, mollify::detail::colour_bytes);
            EXPECT_LE(below, 3 * mollify::detail::colour_bytes);
        }
        expect_colour(batch->a.data(), B::a_colour, "a");
        expect_colour(batch->b.data(), B::b_colour, "b");
        expect_colour(batch->ends.data(), B::ends_colour, "ends");
        expect_colour(batch->slot.data(), B::slot_colour, "slot");
        expect_colour(batch->close.data(), B::close_colour, "close");
        EXPECT_LE(B::next_colour + 3, mollify::detail::colours - 1) << "the sweep's outputs have colours of their own";
    }
}

TEST(Neighbours, CellPairsEqualAllPairs) {
    expect_half_pairs_as_all_pairs<3>(Domain<3>::periodic(2.0), 0.3, random_points<3>(800 / fewer, 0, 2, 4));
    expect_half_pairs_as_all_pairs<3>(Domain<3>::whole_space(), 0.3, random_points<3>(800 / fewer, -1, 1, 5));
    expect_half_pairs_as_all_pairs<2>(Domain<2>::periodic(1.0), 0.07, random_points<2>(600 / fewer, 0, 1, 2));
    expect_half_pairs_as_all_pairs<2>(Domain<2>::whole_space(), 0.07, random_points<2>(600 / fewer, -3, 5, 3));
    expect_half_pairs_as_all_pairs<3>(Domain<3>::periodic(1.0), 0.125, dyadic_lattice<3>(lattice_side));
    expect_half_pairs_as_all_pairs<3>(Domain<3>::whole_space(), 0.125, dyadic_lattice<3>(lattice_side));
    expect_half_pairs_as_all_pairs<3>(Domain<3>::periodic(1.0), 0.125, dyadic_random<3>(3000 / fewer, 0, 1, 7));
    // 1D: a home cell and the next; the lattice's pairs at exactly eps and
    // particles on cell boundaries; in R^1 a few far particles, so that the
    // N + 1 cells are wider than eps and crowded.
    expect_half_pairs_as_all_pairs<1>(Domain<1>::periodic(1.0), 0.02, random_points<1>(2000 / fewer, 0, 1, 30));
    expect_half_pairs_as_all_pairs<1>(Domain<1>::whole_space(), 0.02, random_points<1>(2000 / fewer, -2, 3, 31));
    expect_half_pairs_as_all_pairs<1>(Domain<1>::periodic(1.0), 0.125, dyadic_lattice<1>(128));
    expect_half_pairs_as_all_pairs<1>(Domain<1>::whole_space(), 0.125, dyadic_lattice<1>(128));
    Field<1> spread = random_points<1>(1000 / fewer, 0, 1, 32);
    for (const double far : {-1e6, 3e7, 3e7 + 0.01}) spread[0].push_back(far);
    expect_half_pairs_as_all_pairs<1>(Domain<1>::whole_space(), 0.01, spread);
}

// A lattice of side 8 in the periodic unit box with eps = 1/8 (cells of side
// exactly eps but for CellList's margin) and two particles more, at x = 1/8 -
// 2^-56 and 1/4: 2^-56 more than eps apart, but their difference rounds to
// 1/8, so the pair test accepts them (q = 1 exactly), while x/side puts them
// in cells 0 and 2 (found by a search over the doubles near the cells'
// boundaries, stop 65).
Field<3> pair_at_eps_by_rounding() {
    Field<3> x = dyadic_lattice<3>(8);
    const double near[3] = {0x1.fffffffffffffp-4, 0.5 + 1.0 / 32, 0.5 + 1.0 / 32}, far[3] = {0.25, 0.5 + 1.0 / 32, 0.5 + 1.0 / 32};
    for (int c = 0; c < 3; ++c) {
        x[c].push_back(near[c]);
        x[c].push_back(far[c]);
    }
    return x;
}

TEST(Neighbours, CellPairsAtEpsByRounding) {
    const Domain<3> box = Domain<3>::periodic(1.0);
    const Field<3> x = pair_at_eps_by_rounding();
    const std::size_t near = x[0].size() - 2, far = near + 1;
    // The default cells (SupportEdge::contributes) meet every pair the test accepts.
    expect_half_pairs_as_all_pairs<3>(box, 0.125, x);
    // Cells of side eps miss this one: the case still exercises the rounding
    // the margin is for.
    CellList<3> bare(box, 0.125, SupportEdge::vanishes);
    bare.update(view<3>(x));
    EXPECT_EQ(half_pairs_of(bare).count(std::pair{near, far}), 0u) << "the pair no longer lies two cells apart";
    EXPECT_EQ(bare.support_edge(), SupportEdge::vanishes);
    EXPECT_EQ(CellList<3>(box, 0.125).support_edge(), SupportEdge::contributes);
}

// The order kept from the last update and repaired: particles moved by up
// to a third of eps (some across cell boundaries and the periodic box).
// A cell list updated at x and then at the moved positions: its half pairs
// against all pairs at the moved ones (displacements to rounding).
template <int D>
void expect_half_pairs_after_motion(const Domain<D>& box, double eps, const Field<D>& x, const Field<D>& moved) {
    CellList<D> fast(box, eps);
    AllPairs<D> slow(box, eps);
    fast.update(view<D>(x));
    fast.update(view<D>(moved));
    slow.update(view<D>(moved));
    const PairSet<D> a = half_pairs_of(fast);
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < moved[0].size(); ++i)
        slow.visit(i, [&](std::size_t j, const Vector<D>& d) {
            if (j > i) {
                ++pairs;
                const auto at = a.find(std::pair{i, j});
                ASSERT_NE(at, a.end()) << "pair " << i << ", " << j;
                for (int c = 0; c < D; ++c) EXPECT_NEAR(at->second[c], d[c], 1e-15) << "pair " << i << ", " << j;
            }
        });
    EXPECT_EQ(a.size(), pairs);
    EXPECT_GT(pairs, 0u);
}

TEST(Neighbours, CellPairsAfterMotion) {
    const Domain<3> box = Domain<3>::periodic(1.0);
    const double eps = 0.1;
    Field<3> x = random_points<3>(2000 / fewer, 0, 1, 14), moved = x;
    std::mt19937_64 g(15);
    std::uniform_real_distribution<double> u(-eps / 3, eps / 3);
    for (auto& c : moved)
        for (auto& v : c) v = box.wrap(v + u(g));
    expect_half_pairs_after_motion<3>(box, eps, x, moved);
}

// 1D, where the slots are in order of position (each home particle's
// candidates a window of them): particles mirrored within cells of side
// eps (each cell's order reversed, hardly any particle changing cells)
// must break the kept order, as must particles moved across cells.
TEST(Neighbours, CellPairsAfterMotion1D) {
    const double eps = 0.01;  // cells of side 0.01
    const Field<1> x = random_points<1>(3000 / fewer, 0, 1, 42);
    Field<1> within = x, across = x;
    std::mt19937_64 g(43);
    std::uniform_real_distribution<double> u(-eps / 3, eps / 3);
    for (double& v : within[0]) {
        const double cell = std::floor(v / eps) * eps;
        v = cell + (cell + eps - v);  // mirrored within its cell: the cell's order reversed
        if (!(v < cell + eps)) v = cell;
    }
    for (double& v : across[0]) v = Domain<1>::periodic(1.0).wrap(v + u(g));
    expect_half_pairs_after_motion<1>(Domain<1>::periodic(1.0), eps, x, within);
    expect_half_pairs_after_motion<1>(Domain<1>::periodic(1.0), eps, x, across);
    expect_half_pairs_after_motion<1>(Domain<1>::whole_space(), eps, x, within);
}

// Every particle moved but none left its cell (the usual time step): the
// update keeps the last order and takes the new positions only.
TEST(Neighbours, CellPairsAfterMotionWithinCells) {
    const double eps = 0.1;  // ten cells of side 0.1 a side
    Field<3> x = random_points<3>(2000 / fewer, 0, 1, 18), moved = x;
    for (auto& c : moved)
        for (auto& v : c) {
            const double centre = (std::floor(v / eps) + 0.5) * eps;
            v = centre + 0.5 * (v - centre);  // halfway to its cell's centre
        }
    expect_half_pairs_after_motion<3>(Domain<3>::periodic(1.0), eps, x, moved);
}

// Particles given in cell order already: the first update keeps it (and
// must still number the slots), the second keeps it again; visit() reads
// a particle's slot, so it sees either going wrong.
TEST(Neighbours, VisitWhereTheOrderIsKept) {
    const Domain<3> box = Domain<3>::periodic(1.0);
    const double eps = 0.1;
    const Field<3> random = random_points<3>(1500 / fewer, 0, 1, 21);
    CellList<3> sorter(box, eps);
    sorter.update(view<3>(random));
    Field<3> x;
    for (int c = 0; c < 3; ++c)
        for (const std::size_t i : sorter.members()) x[c].push_back(random[c][i]);
    CellList<3> fast(box, eps);
    AllPairs<3> slow(box, eps);
    slow.update(view<3>(x));
    for (int round = 0; round < 2; ++round) {
        fast.update(view<3>(x));
        EXPECT_EQ(fast.order_kept(), round == 1);
        std::size_t met = 0;
        for (std::size_t i = 0; i < x[0].size(); ++i) {
            std::map<std::size_t, Vector<3>> a, b;
            fast.visit(i, [&](std::size_t j, const Vector<3>& d) { a.emplace(j, d); });
            slow.visit(i, [&](std::size_t j, const Vector<3>& d) { b.emplace(j, d); });
            ASSERT_EQ(a.size(), b.size()) << "particle " << i;
            for (const auto& [j, d] : b) {
                ASSERT_EQ(a.count(j), 1u) << "particle " << i << ", neighbour " << j;
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.at(j)[c], d[c], 1e-15);
            }
            met += b.size();
        }
        EXPECT_GT(met, x[0].size());  // neighbours besides themselves
    }
}

// Fewer than 3 cells on a periodic side (2 cells: offsets -1 and +1 are one
// cell; exactly 3: the smallest count without aliasing), and a clump of
// many particles in one cell (batches flushed mid-cell).
TEST(Neighbours, CellPairsAliasedAndCrowded) {
    expect_half_pairs_as_all_pairs<3>(Domain<3>::periodic(1.0), 0.45, random_points<3>(300 / fewer, 0, 1, 8));
    expect_half_pairs_as_all_pairs<3>(Domain<3>::periodic(1.0), 0.3125, dyadic_lattice<3>(8));  // 3 cells per side
    expect_half_pairs_as_all_pairs<3>(Domain<3>::periodic(1.0), 0.375, dyadic_lattice<3>(8));   // 2 cells per side
    expect_half_pairs_as_all_pairs<2>(Domain<2>::periodic(1.0), 0.45, random_points<2>(100 / fewer, 0, 1, 6));
    expect_half_pairs_as_all_pairs<1>(Domain<1>::periodic(1.0), 0.45, random_points<1>(300 / fewer, 0, 1, 33));
    expect_half_pairs_as_all_pairs<1>(Domain<1>::periodic(1.0), 0.3125, dyadic_lattice<1>(128));  // 3 cells
    expect_half_pairs_as_all_pairs<1>(Domain<1>::periodic(1.0), 0.375, dyadic_lattice<1>(128));   // 2 cells
    Field<1> clump1 = random_points<1>(700 / fewer, 0.5, 0.501, 34);  // all but one in one cell
    clump1[0].push_back(0.9);
    expect_half_pairs_as_all_pairs<1>(Domain<1>::periodic(1.0), 0.05, clump1);
    expect_half_pairs_as_all_pairs<1>(Domain<1>::whole_space(), 0.05, clump1);
    // In R^3 one or two cells per side (no images, nothing aliases).
    expect_half_pairs_as_all_pairs<3>(Domain<3>::whole_space(), 0.1, random_points<3>(60 / fewer, 0, 0.15, 16));
    expect_half_pairs_as_all_pairs<3>(Domain<3>::whole_space(), 0.1, random_points<3>(200 / fewer, 0, 0.25, 17));
    Field<3> clump = random_points<3>(700 / fewer, 0.5, 0.52, 9);
    for (int c = 0; c < 3; ++c) clump[c].push_back(0.9);  // one far particle: the cells span the box
    expect_half_pairs_as_all_pairs<3>(Domain<3>::periodic(1.0), 0.05, clump);
    expect_half_pairs_as_all_pairs<3>(Domain<3>::whole_space(), 0.05, clump);
}

// The most particles in one cell.
template <int D>
std::size_t most_in_a_cell(const CellList<D>& s) {
    std::size_t most = 0;
    for (std::size_t c = 0; c < s.cells(); ++c) most = std::max(most, s.first_slot(c + 1) - s.first_slot(c));
    return most;
}

// Points of `cluster` moved by `by` (every coordinate).
template <int D>
Field<D> shifted(Field<D> cluster, const std::array<double, D>& by) {
    for (int c = 0; c < D; ++c)
        for (double& v : cluster[c]) v += by[static_cast<std::size_t>(c)];
    return cluster;
}

template <int D>
Field<D> joined(Field<D> a, const Field<D>& b) {
    for (int c = 0; c < D; ++c) a[c].insert(a[c].end(), b[c].begin(), b[c].end());
    return a;
}

// visit(i, f) against AllPairs, particle by particle: each neighbour once,
// displacements within `tolerance` (0 in R^D; to rounding in a periodic
// box, where the cell path shifts the neighbour by L).
template <int D>
void expect_visits_as_all_pairs(const CellList<D>& s, const Domain<D>& box, double eps, const Field<D>& x, double tolerance) {
    AllPairs<D> all(box, eps);
    all.update(view<D>(x));
    for (std::size_t i = 0; i < x[0].size(); ++i) {
        std::map<std::size_t, Vector<D>> a, b;
        s.visit(i, [&](std::size_t j, const Vector<D>& d) { EXPECT_TRUE(a.emplace(j, d).second) << i << ", " << j; });
        all.visit(i, [&](std::size_t j, const Vector<D>& d) { b.emplace(j, d); });
        ASSERT_EQ(a.size(), b.size()) << "particle " << i;
        for (const auto& [j, d] : b) {
            ASSERT_EQ(a.count(j), 1u) << "particle " << i << ", neighbour " << j;
            for (int c = 0; c < D; ++c) EXPECT_NEAR(a.at(j)[c], d[c], tolerance);
        }
    }
}

// Pairs as all pairs', and no crowded cell: the cluster of `n` dyadic
// points in [0, 1)^D with eps = 1/8 has ~n/8^D a cell, a cell as wide as
// the spread over N^(1/D) holds the whole cluster. `most`: the most a cell
// may hold, where not that (cells wider than eps).
template <int D>
void expect_spread_pairs(const Field<D>& x, std::size_t cluster, double most = 0) {
    expect_half_pairs_as_all_pairs<D>(Domain<D>::whole_space(), 0.125, x);
    CellList<D> s(Domain<D>::whole_space(), 0.125);
    s.update(view<D>(x));
    expect_visits_as_all_pairs<D>(s, Domain<D>::whole_space(), 0.125, x, 0);
    double per_cell = static_cast<double>(cluster);
    for (int c = 0; c < D; ++c) per_cell /= 8;
    EXPECT_LE(static_cast<double>(most_in_a_cell(s)), most > 0 ? most : 4 * per_cell + 20)
        << "of " << x[0].size() << " particles";
}

// In R^2 and R^3, particles spread far beyond what ~N cells of side eps can
// cover: a cluster and particles far from it (alone; two within eps of each
// other; below it; beyond 2^30 eps, where the slabs are clamped), two
// clusters far apart along an axis and (2D) on a diagonal, a cluster with
// 1 % of its particles scattered far around it (runs left out), a cluster
// in a Gaussian envelope and a far group of more than N/256 (slabs wider
// than eps). The cells lie over each axis's runs of occupied slabs
// (detail::CollapsedAxis) or, where all but N/256 particles at either end
// of each axis span few enough slabs (a few far particles; two clusters
// 4096 apart), are graded over that range (detail::GradedAxis), so the
// pairs are all pairs' and no cell holds a cluster: with cells as wide as
// the bounding box over N^(1/D) (the layout before stop 55), one cell held
// the cluster and its candidates grew like its size squared.
TEST(Neighbours, CellPairsOfSpreadClusters) {
    const std::size_t n = 3000 / fewer;
    const Field<3> cube = dyadic_random<3>(n, 0, 1, 50);
    Field<3> far = cube;
    for (const double v : {1e6, 1e6 + 0.0625, -3e7, 1e12, 1e12 + 0.0625})
        for (int c = 0; c < 3; ++c) far[c].push_back(c == 1 ? 0.5 : v);  // x and z far, y inside
    expect_spread_pairs<3>(far, n);
    expect_spread_pairs<3>(joined<3>(cube, shifted<3>(dyadic_random<3>(n, 0, 1, 51), {0, 0, 4096})), 2 * n);
    expect_spread_pairs<3>(joined<3>(cube, dyadic_random<3>(n / 100, -1e6, 1e6, 56)), n);
    Field<3> envelope = dyadic_random<3>(n / 10, 0, 1, 57);
    std::mt19937_64 g(58);
    std::normal_distribution<double> spread(0.5, 0.5);
    for (auto& c : envelope)
        for (double& v : c) v = std::ldexp(std::round(std::ldexp(spread(g), 20)), -20);  // dyadic
    for (std::size_t j = 0; j <= n / 128; ++j)  // a far group, more than graded cells leave out
        for (int c = 0; c < 3; ++c) envelope[c].push_back(1e6 + 0.0625 * static_cast<double>(j % 4));
    expect_spread_pairs<3>(joined<3>(cube, envelope), n, static_cast<double>(n) / 8);
    const Field<2> square = dyadic_random<2>(n, 0, 1, 52);
    Field<2> far2 = square;
    for (const double v : {-1e6, 5e8, 5e8 + 0.125})
        for (int c = 0; c < 2; ++c) far2[c].push_back(v);
    expect_spread_pairs<2>(far2, n);
    expect_spread_pairs<2>(joined<2>(square, shifted<2>(dyadic_random<2>(n, 0, 1, 53), {1024, 1024})), 2 * n);
}

// A periodic box whose particles crowd part of it: a dense cube of side
// 1/16 (8 eps, ~6 particles a cell of side eps) in a sparse background,
// 90 % of the particles in it, at `centre` (wrapped: at a corner it
// straddles every seam); `side`: the cube's side in eps. Equal cells of at most N^(1/D) + 1 a side (the
// layout before graded cells) put the cube into a few cells of hundreds;
// graded cells (detail::GradedAxis) give it cells of side eps. Pairs as
// all pairs', half_pairs and visit, and no crowded cell.
template <int D>
Field<D> periodic_cluster(std::size_t n, const std::array<double, D>& centre, unsigned seed) {
    const Domain<D> box = Domain<D>::periodic(1.0);
    Field<D> cube = dyadic_random<D>(n - n / 10, -1.0 / 32, 1.0 / 32, seed);
    for (int c = 0; c < D; ++c)
        for (double& v : cube[c]) v = box.wrap(v + centre[static_cast<std::size_t>(c)]);
    return joined<D>(cube, dyadic_random<D>(n / 10, 0, 1, seed + 1));
}

template <int D>
void expect_periodic_cluster_pairs(const Field<D>& x, const Field<D>* before = nullptr, double side = 8) {
    const Domain<D> box = Domain<D>::periodic(1.0);
    const double eps = 1.0 / 128;
    if (before) expect_half_pairs_after_motion<D>(box, eps, *before, x);
    else expect_half_pairs_as_all_pairs<D>(box, eps, x);
    CellList<D> s(box, eps);
    if (before) s.update(view<D>(*before));
    s.update(view<D>(x));
    s.update(view<D>(x));  // a moved cluster: the update after the one that found the cells crowded chooses anew
    expect_visits_as_all_pairs<D>(s, box, eps, x, 1e-15);
    double per_cell = 0.9 * static_cast<double>(x[0].size());  // the cube's particles in each of its side^D cells of side eps
    for (int c = 0; c < D; ++c) per_cell /= side;
    EXPECT_LE(static_cast<double>(most_in_a_cell(s)), 4 * per_cell + 20) << "of " << x[0].size() << " particles";
}

TEST(Neighbours, CellPairsOfPeriodicCluster) {
    const std::size_t n = 3000 / fewer;
    expect_periodic_cluster_pairs<3>(periodic_cluster<3>(n, {0, 0, 0}, 70));  // across every seam
    expect_periodic_cluster_pairs<3>(periodic_cluster<3>(n, {0.5, 0.25, 0.75}, 72));
    expect_periodic_cluster_pairs<2>(periodic_cluster<2>(n, {0, 0.5}, 74));
    // Moved across the box since the last update, and collapsed to half its size.
    Field<3> collapsed = periodic_cluster<3>(n, {0.25, 0.25, 0.25}, 76);
    for (int c = 0; c < 3; ++c)
        for (std::size_t i = 0; i < n - n / 10; ++i) collapsed[c][i] = 0.25 + (collapsed[c][i] - 0.25) / 2;
    const Field<3> before = periodic_cluster<3>(n, {0.75, 0.5, 0.5}, 76);
    expect_periodic_cluster_pairs<3>(collapsed, &before, 4);
    // Spread evenly again: the cells of a cluster no longer there.
    const Field<3> even = dyadic_random<3>(n, 0, 1, 78);
    expect_half_pairs_after_motion<3>(Domain<3>::periodic(1.0), 1.0 / 128, before, even);
}

// R^2, R^3: a cluster of n particles in [0, 1)^D at `at` inside a wide
// Gaussian envelope of n/10 (sigma 5 around it: the bounding box spans ~300
// slabs of eps = 1/8 a side). Collapsed runs (CollapsedAxis) would make the
// envelope one run and coarsen its slabs to fit, 16 eps, the cluster in a
// few cells; graded cells over the particles' range (GradedAxis) give the
// cluster cells of side eps, with far particles too.
template <int D>
Field<D> cluster_in_envelope(std::size_t n, double at, unsigned seed) {
    Field<D> envelope = dyadic_random<D>(n / 10, 0, 1, seed);
    std::mt19937_64 g(seed + 1);
    std::normal_distribution<double> spread(0.5, 5);
    for (auto& c : envelope)
        for (double& v : c) v = std::ldexp(std::round(std::ldexp(spread(g), 20)), -20);  // dyadic
    Field<D> cluster = dyadic_random<D>(n, 0, 1, seed + 2);
    for (auto& c : cluster)
        for (double& v : c) v += at;
    return joined<D>(cluster, envelope);
}

TEST(Neighbours, CellPairsOfClusterInEnvelope) {
    const std::size_t n = 3000 / fewer;
    expect_spread_pairs<3>(cluster_in_envelope<3>(n, 0, 80), n);
    expect_spread_pairs<2>(cluster_in_envelope<2>(n, 0, 82), n);
    // and far particles (at most n/256 beyond either end of an axis: left
    // out of the graded range, clamped into its end slabs)
    Field<3> far = cluster_in_envelope<3>(n, 0, 86);
    for (const double v : {1e6, -3e7, 1e12})
        for (int c = 0; c < 3; ++c) far[c].push_back(c == 1 ? 0.5 : v);
    expect_spread_pairs<3>(far, n);
    // The cluster moved across the envelope since the last update: pairs as
    // all pairs' at once, its cells graded anew at the update after.
    const Field<3> before = cluster_in_envelope<3>(n, 0, 84), after = cluster_in_envelope<3>(n, 6, 84);
    expect_half_pairs_after_motion<3>(Domain<3>::whole_space(), 0.125, before, after);
    CellList<3> s(Domain<3>::whole_space(), 0.125);
    s.update(view<3>(before));
    s.update(view<3>(after));
    s.update(view<3>(after));
    EXPECT_LE(static_cast<double>(most_in_a_cell(s)), 4 * static_cast<double>(n) / 512 + 20);
}

// The runs kept while particles stray into slabs that were empty: those
// share the collapsed cells between and beyond the runs, which must stay
// next to the runs' cells (a stray within eps of a far particle, in the
// slab before or after its run); once many have strayed the next update
// finds the runs again. Pairs as all pairs' after every update. `clusters`
// boxes [0, 1) x [0, 1/2)^2 64 apart along x (more than CollapsedAxis's
// few runs: its bisection) and one particle at `far`; every 7th particle
// moves, half into slabs past the first cluster's run and its margin,
// half onto a chain eps/2 apart through the far particle, 8 slabs either
// side (it crosses the boundaries of the far particle's run, margins
// included, wherever they lie).
void expect_pairs_of_strays(int clusters, std::size_t n, double far) {
    const double eps = 0.125;
    Field<3> x;
    for (int k = 0; k < clusters; ++k) {
        Field<3> cluster = dyadic_random<3>(n / static_cast<std::size_t>(clusters), 0, 1, 60 + static_cast<unsigned>(k));
        for (int c = 1; c < 3; ++c)
            for (double& v : cluster[c]) v /= 2;  // [0, 1) x [0, 1/2)^2: fewer cells for 9 of them
        x = joined<3>(x, shifted<3>(cluster, {64.0 * k, 0, 0}));
    }
    // A group at `far`, more than N/256 (graded cells leave out only that
    // many far particles: CellList::graded_over_most), so the runs are what
    // the layout finds.
    for (std::size_t j = 0; j < n / 256 + 2; ++j)
        for (int c = 0; c < 3; ++c) x[c].push_back(c == 0 ? far + 0.0625 * static_cast<double>(j % 2) : 0.5);
    Field<3> moved = x;
    std::size_t strays = 0;
    for (std::size_t i = 0; i + 1 < x[0].size(); i += 7, ++strays) {
        const double k = static_cast<double>(strays / 2);
        moved[0][i] = strays % 2 ? 1.5 + 0.0625 * std::fmod(k, 3) : far + 0.0625 * (std::fmod(k, 33) - 16);
        moved[1][i] = 0.5 + (moved[1][i] - 0.5) / 16;  // near the far particle's y and z
        moved[2][i] = 0.5 + (moved[2][i] - 0.5) / 16;
    }
    ASSERT_GT(strays, x[0].size() / 256 + 16) << "too few strays to find the runs again";
    CellList<3> fast(Domain<3>::whole_space(), eps);
    AllPairs<3> slow(Domain<3>::whole_space(), eps);
    fast.update(view<3>(x));
    // Every cluster's particles spread over several cells (in cells as wide
    // as the particles' spread over N^(1/3), each cluster fills one; slabs
    // of 2 eps, where the margins of 9 runs exceed the sanitizers' smaller
    // budget, give it 16).
    EXPECT_LE(static_cast<double>(most_in_a_cell(fast)), static_cast<double>(n) / clusters / 4);
    slow.update(view<3>(moved));
    const std::size_t kept_cells = fast.cells();
    for (int round = 0; round < 2; ++round) {
        fast.update(view<3>(moved));
        if (round == 0) EXPECT_EQ(fast.cells(), kept_cells) << "the runs were not kept";
        else EXPECT_NE(fast.cells(), kept_cells) << "the runs were not found again";
        const PairSet<3> a = half_pairs_of(fast);
        std::size_t pairs = 0, near_far = 0;
        for (std::size_t i = 0; i < moved[0].size(); ++i)
            slow.visit(i, [&](std::size_t j, const Vector<3>& d) {
                if (j <= i) return;
                ++pairs;
                near_far += moved[0][i] > far / 2;
                const auto at = a.find(std::pair{i, j});
                ASSERT_NE(at, a.end()) << "round " << round << ", pair " << i << ", " << j;
                for (int c = 0; c < 3; ++c) EXPECT_EQ(at->second[c], d[c]);
            });
        EXPECT_EQ(a.size(), pairs);
        EXPECT_GT(near_far, 0u) << "no pair about the far particle: the test misses its point";
    }
}

TEST(Neighbours, CellPairsOfStrays) {
    expect_pairs_of_strays(1, 2000 / fewer, 1e6);
    expect_pairs_of_strays(9, 6000 / fewer, 1e6);  // 10 runs along x
}

// The cell sweep (Newton's third law, sums in slot order) against the
// particle sweep over AllPairs. Dyadic positions: both paths evaluate the
// kernel at the same displacements (or their negatives, where W is even and
// grad W odd bit for bit), so they differ only in the order of summation:
// each sum of k terms t_q is within (k - 1) u sum |t_q| of the exact one
// (u = 2^-53, recursive summation), so the two within 2 k u sum |t_q|.
template <int D, class Kernel>
void expect_sweep_as_all_pairs(const Domain<D>& dom, double eps, const Field<D>& x, const Field<D>* before = nullptr,
                               std::initializer_list<int> thread_counts = {}) {
    const std::size_t n = x[0].size();
    std::vector<double> mass(n);
    for (std::size_t i = 0; i < n; ++i) mass[i] = 1.0 + 0.5 * std::sin(static_cast<double>(i));
    BarotropicEuler<D, Kernel, AllPairs<D>> all(Kernel{}, eps, dom, mass);
    Field<D> a_all;
    std::vector<double> rho_all;
    all.acceleration(x, a_all, &rho_all);  // once: the cells sweep twice, so twice its count (below)
    // Per particle the bound 2 k u and the sums of |terms| it multiplies.
    AllPairs<D> search(dom, eps);
    search.update(view<D>(x));
    const double u = std::ldexp(1.0, -53);
    const Smoothing h(eps, D);
    std::vector<double> bound(n), scale_rho(n);
    Field<D> scale_a;
    for (auto& c : scale_a) c.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        Field<D> d, g;
        std::vector<double> m;
        search.visit(i, [&](std::size_t j, const Vector<D>& dj) {
            for (int c = 0; c < D; ++c) d[c].push_back(dj[c]);
            m.push_back(mass[j]);
        });
        const std::size_t k = m.size();
        std::vector<double> w(k);
        std::array<std::span<double>, D> gs;
        for (int c = 0; c < D; ++c) {
            g[c].resize(k);
            gs[c] = g[c];
        }
        Kernel{}.pairs(view<D>(d), h, w, gs);
        for (std::size_t q = 0; q < k; ++q) {
            scale_rho[i] += std::abs(m[q] * w[q]);
            for (int c = 0; c < D; ++c) scale_a[c][i] += std::abs(m[q] * g[c][q]);
        }
        bound[i] = 2 * static_cast<double>(k) * u;
    }
    auto expect_cells = [&] {
        BarotropicEuler<D, Kernel, CellList<D>> cells(Kernel{}, eps, dom, mass);
        Field<D> a_cells;
        std::vector<double> rho_cells;
        // Twice: the second sweep runs threaded (when OpenMP has threads) once
        // the first has measured the work, and starts from the kept order.
        // From other positions first, where given: the order (and the masses
        // permuted by it) must follow the particles that changed cells.
        std::size_t met_before = 0;
        if (before) {
            cells.acceleration(*before, a_cells, &rho_cells);
            met_before = cells.interactions();
        }
        cells.acceleration(x, a_cells, &rho_cells);
        cells.acceleration(x, a_cells, &rho_cells);
        EXPECT_EQ(cells.interactions() - met_before, 2 * all.interactions());
        for (std::size_t i = 0; i < n; ++i) {
            EXPECT_NEAR(rho_cells[i], rho_all[i], bound[i] * scale_rho[i]) << "particle " << i;
            for (int c = 0; c < D; ++c)
                EXPECT_NEAR(a_cells[c][i], a_all[c][i], bound[i] * scale_a[c][i]) << "particle " << i << ", component " << c;
        }
    };
    // The cell sweep on each thread count given (a system takes the count at construction).
#if defined(_OPENMP)
    const int threads_before = omp_get_max_threads();
    {
        [[maybe_unused]] const LeaksOfThisThreadUnchecked libomp_teams;
        for (const int threads : thread_counts) {
            SCOPED_TRACE("threads " + std::to_string(threads));
            omp_set_num_threads(threads);
            expect_cells();
        }
    }
    omp_set_num_threads(threads_before);
    if (thread_counts.size() == 0) expect_cells();
#else
    expect_cells();
#endif
    // The comparison sees forces: not all zero (a lattice's are, by symmetry).
    double largest = 0;
    for (int c = 0; c < D; ++c)
        for (double v : a_all[c]) largest = std::max(largest, std::abs(v));
    EXPECT_GT(largest, 0.0);
}

TEST(Euler, CellSweepEqualsAllPairs) {
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::periodic(1.0), 0.125, dyadic_random<3>(3000 / fewer, 0, 1, 10));
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::whole_space(), 0.125, dyadic_random<3>(3000 / fewer, -0.5, 0.5, 11));
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::periodic(1.0), 0.375, dyadic_random<3>(400 / fewer, 0, 1, 12));  // aliased
    Field<3> lattice = dyadic_lattice<3>(lattice_side);
    lattice[0][100] = 0.5 + 1.0 / 64;  // one particle off its site: non-zero forces
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::periodic(1.0), 0.125, lattice);
    expect_sweep_as_all_pairs<2, Wendland2D>(Domain<2>::periodic(1.0), 0.0625, dyadic_random<2>(2000 / fewer, 0, 1, 13));
    expect_sweep_as_all_pairs<1, Wendland1D>(Domain<1>::periodic(1.0), 0.01, dyadic_random<1>(3000 / fewer, 0, 1, 35));
    expect_sweep_as_all_pairs<1, Wendland1D>(Domain<1>::whole_space(), 0.01, dyadic_random<1>(3000 / fewer, -0.5, 0.5, 36));
    expect_sweep_as_all_pairs<1, Wendland1D>(Domain<1>::periodic(1.0), 0.375, dyadic_random<1>(200 / fewer, 0, 1, 37));  // aliased
    Field<1> line = dyadic_lattice<1>(256);
    line[0][100] = 100.0 / 256 + 1.0 / 1024;  // one particle off its site: non-zero forces
    expect_sweep_as_all_pairs<1, Wendland1D>(Domain<1>::periodic(1.0), 0.0625, line);
    // R^3, a cluster and a far particle (cells over the runs of slabs, CellPairsOfSpreadClusters)
    Field<3> spread = dyadic_random<3>(2000 / fewer, 0, 1, 55);
    for (int c = 0; c < 3; ++c) spread[c].push_back(1e6);
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::whole_space(), 0.125, spread, nullptr, {1, 2, 3});
    // A periodic box with a dense cluster across the seams (graded cells, CellPairsOfPeriodicCluster)
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::periodic(1.0), 1.0 / 128,
                                             periodic_cluster<3>(3000 / fewer, {0, 0.5, 0}, 79), nullptr, {1, 2, 3});
}

// The solver's cells follow its kernel: with mollifier:M=1 (grad W jumps at
// the edge) the pair at eps by rounding (above) is met and its force is the
// all-pairs one; with Wendland C4 (C^4: W and grad W vanish there) the cells
// of side eps are kept, the pair missed, and nothing but the count changes.
TEST(Euler, CellSweepMeetsPairsAtEpsWhereTheKernelDoesNotVanish) {
    const Domain<3> box = Domain<3>::periodic(1.0);
    Field<3> x = pair_at_eps_by_rounding();
    x[0][100] = 0.5 + 1.0 / 64;  // one lattice particle off its site: more non-zero forces
    expect_sweep_as_all_pairs<3, MollifierM1>(box, 0.125, x);
    const std::vector<double> mass(x[0].size(), 1.0);
    BarotropicEuler<3, Wendland3D, AllPairs<3>> all(Wendland3D{}, 0.125, box, mass);
    BarotropicEuler<3, Wendland3D> cells(Wendland3D{}, 0.125, box, mass);
    Field<3> a_all, a_cells;
    std::vector<double> rho_all, rho_cells;
    all.acceleration(x, a_all, &rho_all);
    cells.acceleration(x, a_cells, &rho_cells);
    EXPECT_LT(cells.interactions(), all.interactions()) << "Wendland C4's sweep no longer keeps cells of side eps";
    const std::size_t near = x[0].size() - 2;
    EXPECT_DOUBLE_EQ(rho_cells[near], rho_all[near]);
}

TEST(Euler, CellSweepAfterParticlesChangedCells) {
    // Unequal masses (expect_sweep_as_all_pairs) on particles that mostly
    // moved to other cells since the sweep before.
    const Field<3> before = dyadic_random<3>(2000 / fewer, 0, 1, 19), after = dyadic_random<3>(2000 / fewer, 0, 1, 20);
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::periodic(1.0), 0.125, after, &before);
    const Field<1> before1 = dyadic_random<1>(3000 / fewer, 0, 1, 40), after1 = dyadic_random<1>(3000 / fewer, 0, 1, 41);
    expect_sweep_as_all_pairs<1, Wendland1D>(Domain<1>::periodic(1.0), 0.01, after1, &before1);
}

#if defined(_OPENMP)
// The threaded sweep: contiguous ranges of cells, one array of sums each,
// added up per layer from the ranges that reach it (CellList::layers). With
// 2, 3, 5 and 8 threads (more than the machine's cores is still that many
// ranges): ranges that end inside a layer, ranges of one layer, the last
// range's pairs across the periodic seam into layer 0, ranges left empty
// by a crowded cell, more ranges than layers (a flat domain of 2 layers;
// the aliased cells, one layer), the 2D rows; each against the particle sweep.
// A range whose sums were not added where its pairs reach (the next layer,
// or layer 0 across the seam) loses those pairs' halves: far outside the bound.
TEST(Euler, CellSweepOnAnyNumberOfThreads) {
    Field<3> crowded = dyadic_random<3>(3000 / fewer, 0, 1, 21);
    for (std::size_t i = 0; i < 1500 / fewer; ++i)  // half of them in one cell of side 1/8
        for (int c = 0; c < 3; ++c) crowded[c][i] = 0.5 + crowded[c][i] / 16;
    Field<3> flat = dyadic_random<3>(3000 / fewer, 0, 1, 27);
    for (double& z : flat[2]) z /= 4;  // [0, 1/4): two cells of side 1/8 along the last axis
    const auto threads = {2, 3, 5, 8};
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::periodic(1.0), 0.125, dyadic_random<3>(3000 / fewer, 0, 1, 22), nullptr, threads);
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::whole_space(), 0.125, dyadic_random<3>(3000 / fewer, -0.5, 0.5, 23), nullptr, threads);
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::periodic(1.0), 0.125, crowded, nullptr, threads);
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::whole_space(), 0.125, flat, nullptr, threads);
    expect_sweep_as_all_pairs<3, Wendland3D>(Domain<3>::periodic(1.0), 0.375, dyadic_random<3>(800 / fewer, 0, 1, 26), nullptr, threads);
    expect_sweep_as_all_pairs<2, Wendland2D>(Domain<2>::periodic(1.0), 0.0625, dyadic_random<2>(4000 / fewer, 0, 1, 24), nullptr, threads);
    // 1D: each cell a layer (a home cell's pairs reach the next one).
    expect_sweep_as_all_pairs<1, Wendland1D>(Domain<1>::periodic(1.0), 0.005, dyadic_random<1>(6000 / fewer, 0, 1, 38), nullptr, threads);
    expect_sweep_as_all_pairs<1, Wendland1D>(Domain<1>::whole_space(), 0.005, dyadic_random<1>(6000 / fewer, -0.5, 0.5, 39), nullptr, threads);
}

// Each range of cells is summed by one thread in one order and the ranges
// are added in range order, whichever thread took which: two systems on
// three threads give the same bits (one array per thread over cells taken
// as threads came free did not: its partial sums depended on the timing).
TEST(Euler, CellSweepIsReproducible) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(3);
    const Field<3> x = dyadic_random<3>(3000 / fewer, 0, 1, 25);
    std::vector<double> mass(x[0].size());
    for (std::size_t i = 0; i < mass.size(); ++i) mass[i] = 1.0 + 0.5 * std::sin(static_cast<double>(i));
    std::array<std::vector<double>, 2> rho;
    std::array<Field<3>, 2> a;
    for (std::size_t k = 0; k < 2; ++k) {
        BarotropicEuler<3, Wendland3D, CellList<3>> s(Wendland3D{}, 0.125, Domain<3>::periodic(1.0), mass);
        for (int sweep = 0; sweep < 3; ++sweep) s.acceleration(x, a[k], &rho[k]);  // threaded from the second
    }
    omp_set_num_threads(before);
    for (std::size_t i = 0; i < mass.size(); ++i) {
        ASSERT_EQ(rho[0][i], rho[1][i]) << "particle " << i;
        for (int c = 0; c < 3; ++c) ASSERT_EQ(a[0][c][i], a[1][c][i]) << "particle " << i << ", component " << c;
    }
}

// A threaded sweep is one parallel region whose thread 0 checks the
// positions: a bad one is the same error as on one thread (not
// std::terminate from an exception leaving the region), the outputs keep
// their sizes, and the next sweep of good positions gives the bits of a
// system that never saw it.
TEST(Euler, BadPositionInAThreadedSweep) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(2);
    const Field<3> x = dyadic_random<3>(3000 / fewer, 0, 1, 28);
    const std::vector<double> mass(x[0].size(), 1.0);
    using System = BarotropicEuler<3, Wendland3D, CellList<3>>;
    System s(Wendland3D{}, 0.3, Domain<3>::periodic(1.0), mass), clean(Wendland3D{}, 0.3, Domain<3>::periodic(1.0), mass);
    Field<3> a, a_clean;
    s.acceleration(x, a);
    clean.acceleration(x, a_clean);
    ASSERT_GT(s.interactions(), System::parallel_above) << "the next sweep would not run threaded";
    Field<3> bad = x;
    bad[1][17] = NAN;
    try {
        s.acceleration(bad, a);
        ADD_FAILURE() << "a NaN coordinate was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("particle 17"), std::string::npos) << e.what();
    }
    for (int c = 0; c < 3; ++c) EXPECT_EQ(a[c].size(), x[0].size());
    s.acceleration(x, a);
    clean.acceleration(x, a_clean);
    omp_set_num_threads(before);
    for (std::size_t i = 0; i < x[0].size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(a[c][i], a_clean[c][i]) << "particle " << i << ", component " << c;
}
#endif

}  // namespace
