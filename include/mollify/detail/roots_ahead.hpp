// A batch loop over points whose first step is a square root (r = |x|),
// with the roots taken a block ahead of their use: the roots of points
// i + B .. i + 2B - 1 are issued before the arithmetic of points i .. i + B - 1.
//
// Why: the root runs on the divider, the rest on the multiply-add ports,
// and the two overlap only if the processor finds the next roots while this
// point's arithmetic waits for its own. In the plain loop the next root
// comes after ~60 (fast) to ~200 (accurate) operations that wait for this
// one, and the scheduler is full of them first: the accurate W + grad W of
// Wendland C4 took about the time of its roots plus its arithmetic. Issued
// a block ahead, each root is done before its point's arithmetic starts
// (kernel_bench, an Intel Xeon of the Sapphire Rapids line, stop 64, W +
// grad W per 4096 points: accurate 7.1-7.4 -> 5.3 us, fast 3.8 -> 3.4-3.5
// us, the roots' own rate; combo:m=3,base=wendland:k=2 21.5-22.0 -> 17.3-
// 17.8 us and 7.5 -> 5.4-5.6 us; an x86-64-v3 build 9.6 -> 7.0 us accurate).
// B = 16 was the fastest of 8, 16, 32 and 64 with 256- and 512-bit
// vectors: two to four registers of roots.
//
// The same operations on the same values as the plain loop: the same bits.
#pragma once

#include <mollify/detail/isa.hpp>
#include <mollify/detail/lanes.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <type_traits>
#include <utility>

MOLLIFY_VECTOR_MISSES_ALLOWED_BEGIN

namespace mollify::detail {
inline namespace MOLLIFY_ISA {

inline constexpr std::size_t roots_ahead_block = 16;

// |x| in 2D and 3D as every batch loop takes it: the squares summed with
// fused multiply-adds, then one correctly rounded root (the same bits in
// StaticKernel's loops and the run-time form's).
inline double radius(double a, double b) { return std::sqrt(mul_add(b, b, a * a)); }
inline double radius(double a, double b, double c) { return std::sqrt(mul_add(c, c, mul_add(b, b, a * a))); }

// Below 2^-484 the squares' sum loses bits (subnormal below 2^-968, 0 below
// ~2^-538): there the same sum of the coordinates scaled by 2^600 (exact),
// the root scaled back: the bits radius would give without underflow. For
// kernels with a cusp (W'(r) x/r, a W singular at 0), which need r itself
// near 0; the others' values there are their values at 0.
inline constexpr double radius_underflow = 0x1p-484;
inline double unscaled_radius(double a, double b) { return radius(a * 0x1p600, b * 0x1p600) * 0x1p-600; }
inline double unscaled_radius(double a, double b, double c) {
    return radius(a * 0x1p600, b * 0x1p600, c * 0x1p600) * 0x1p-600;
}

// How far ahead the outputs are fetched for writing, in points: where a
// batch comes from memory (10^6 points), the loop above without it ran
// slower than the plain one (Wendland C4 accurate 2.3 -> 3.0 ms), with it
// faster (1.9-2.0 ms; the combination's 6.0 -> 4.6 ms; fast 2.5 -> 1.9-2.0 ms;
// kernel_bench, W + grad W).
// 128 and 256 points did alike, 512 was slower.
inline constexpr std::size_t outputs_ahead = 128;

// block(i, roots, count): the roots of points i .. i + count - 1, in blocks
// of B (count a std::integral_constant), each block's roots taken while the
// block before it is evaluated; check(roots, count) sees each block's roots
// as they are taken (the pair loops' input check, NonFiniteRoots), before
// the block that reads them; the lines of `out` (the arrays the blocks
// write) fetched outputs_ahead points ahead. Where B does not divide n the
// last block ends at n and overlaps the one before: its first points are
// evaluated twice, so a block must be idempotent (it stores a function of
// i, or ORs a flag). The plain loop's last n mod B points, which the
// vectoriser leaves to narrower or scalar code, had made the SPH sweep's
// batches (mostly 64-256 pairs) 3 % slower; overlapped, as fast as before.
// Fewer than B points: one block of count = n (a std::size_t), without
// roots ahead. Root and block are inlined (MOLLIFY_INLINE_LAMBDA at the
// caller): a call left in the loop stops its vectorisation, and flattening
// did not reach them. A user's unit compiles the block twice (B and n < B).
template <class Root, class Block, class Check, class... Out>
MOLLIFY_INLINE void for_each_block_of_roots(std::size_t n, Root root, Block block, Check&& check, Out*... out) {
    constexpr std::size_t B = roots_ahead_block, line = 64 / sizeof(double);
    constexpr std::integral_constant<std::size_t, B> whole{};
    if (n < B) {
        // zeroed: a register's level reads whole registers of it (RadiusLevel),
        // count of them filled, which GCC cannot always see (-Wmaybe-uninitialized)
        double roots[B]{};
        MOLLIFY_VECTOR_LOOP
        for (std::size_t i = 0; i < n; ++i) roots[i] = root(i);
        check(static_cast<const double*>(roots), n);
        block(std::size_t{0}, static_cast<const double*>(roots), n);
        return;
    }
    double ahead[2][B];
    MOLLIFY_VECTOR_LOOP
    for (std::size_t j = 0; j < B; ++j) ahead[0][j] = root(j);
    check(static_cast<const double*>(ahead[0]), whole);
    int now = 0;
    for (std::size_t i = 0;;) {
        // the next block; the last one ends at n (it may overlap this one)
        const std::size_t next = i + B < n ? std::min(i + B, n - B) : n;
        double* __restrict later = ahead[now ^ 1];
#if defined(__GNUC__)
        if (i + outputs_ahead + B <= n)
            for (std::size_t j = 0; j < B; j += line) (__builtin_prefetch(out + i + outputs_ahead + j, 1), ...);
#endif
        if (next < n) {
            MOLLIFY_VECTOR_LOOP
            for (std::size_t j = 0; j < B; ++j) later[j] = root(next + j);
            check(static_cast<const double*>(later), whole);
        }
        block(i, static_cast<const double*>(ahead[now]), whole);
        if (next == n) return;
        i = next;
        now ^= 1;
    }
}

// A check that looks at no root (the unchecked loops).
struct NoRootCheck {
    MOLLIFY_INLINE void operator()(const double*, std::size_t) const {}
};

// f(std::integral_constant<int, L>{}) for the L = level in [0, Levels).
template <int Levels, class F, int... L>
MOLLIFY_INLINE void at_level(int level, F& f, std::integer_sequence<int, L...>) {
    static_cast<void>(((level == L ? (f(std::integral_constant<int, L>{}), true) : false) || ...));
}

// The level of a register of points from their radii: L where every r is
// at least at_least[L - 1] (increasing; +inf for levels never taken), the
// radius a_L h of a combination's L-th radius with 2^-48 to spare over the
// rounding of q = r/h, so that a_L's term is 0 at each point (the pair
// loops of StaticKernel and of the run-time form's shared terms). A NaN
// first radius gives level 0; a register of roots (count = register_doubles)
// with a NaN lane, level 0 (the NaN lane's output is 0, selected by r <= h,
// whichever terms are summed; the others' bits do not depend on the level).
// A register's level by lane masks where there are lanes (MOLLIFY_LANES):
// one comparison per radius and the count of those every lane passes,
// without a branch, where the scalar minimum of the register's roots had
// been a chain of minima (7 of 8 roots), and the loop on it a branch per radius
// (combo:m=3,base=wendland:k=2's accurate W + grad W per 4096 points, with
// static_kernel.hpp's NonFiniteRoots: 15.2 -> 14.9 us; sorted by radius, so
// that each register is at its points' own level, 10.6 -> 10.3 us; stop 71).
template <int Levels>
struct RadiusLevel {
    double at_least[Levels]{};  // zeroed: with one level none is set, and the copy reads it (-Wuninitialized at -O1)
    // bound(l): the l-th radius a_l in units of h, l < Levels - 1.
    template <class Bound>
    RadiusLevel(Bound bound, double h) {
        for (int l = 0; l + 1 < Levels; ++l) at_least[l] = bound(l) * h * (1 + 0x1p-48);
    }
    MOLLIFY_INLINE int operator()(const double* __restrict r, std::size_t count) const {
#if defined(MOLLIFY_LANES)
        if (count == register_doubles) {
            const Lanes v = load_lanes(r);
            int l = 0;
            for (int k = 0; k + 1 < Levels; ++k) l += clear_lanes(at_least_lanes(v, Lanes{} + at_least[k])) == 0;
            return l;
        }
#endif
        double least = r[0];
        for (std::size_t j = 1; j < count; ++j) least = r[j] < least ? r[j] : least;
        int l = 0;
        while (l + 1 < Levels && least >= at_least[l]) ++l;
        return l;
    }
};

// body(i, std::integral_constant<int, L>{}) for i = 0 .. n-1, L =
// level(r + k, register_doubles) chosen once per register of points from
// their radii r: the batch evaluation of a combination's W or W'/r alone
// (StaticKernel::evaluate, the run-time form's accurate_shared_loop), where
// the radii are given and no root is taken. The body is compiled once per
// level and once more for the last n mod register_doubles points, which
// take level 0.
// check(r + i, count) sees each register's radii (count a std::
// integral_constant) and the last ones (a std::size_t) before the body
// reads them (the input check, NotRadii).
template <int Levels, class Level, class Body, class Check>
MOLLIFY_INLINE void for_each_register_at_levels(std::size_t n, const double* __restrict r, Level level, Body body,
                                                Check&& check) {
    constexpr std::size_t S = register_doubles;
    std::size_t i = 0;
    for (; i + S <= n; i += S) {
        check(r + i, std::integral_constant<std::size_t, S>{});
        auto run = [&](auto at) MOLLIFY_INLINE_LAMBDA {
            MOLLIFY_VECTOR_LOOP
            for (std::size_t j = 0; j < S; ++j) body(i + j, at);
        };
        at_level<Levels>(level(r + i, S), run, std::make_integer_sequence<int, Levels>{});
    }
    // the last, shorter register at level 0 (every term): one more body, not Levels
    check(r + i, n - i);
    for (; i < n; ++i) body(i, std::integral_constant<int, 0>{});
}

// body(i, root(i), std::integral_constant<int, L>{}) for i = 0 .. n-1, the
// roots a block ahead, L = level(roots, count) in [0, Levels) chosen once
// per register of points (register_doubles) from their roots: a level the
// body may rely on for each of those points (a combination's terms that
// none of them reaches, left out: StaticKernel::pairs_3d). Per register,
// not per block of 16: combo:m=3's accurate W + grad W per 4096 points
// 17.5 -> 13.0-13.3 us per register of 8, 16.0 per block, 24 per half
// register (kernel_bench, an Intel Xeon with AVX-512, stop 65). The body is
// compiled once per level (Levels = 1: each block's points in one loop);
// body must be idempotent (for_each_block_of_roots).
template <int Levels, class Root, class Level, class Body, class Check, class... Out>
MOLLIFY_INLINE void for_each_root_ahead_at_levels(std::size_t n, Root root, Level level, Body body, Check&& check,
                                                  Out*... out) {
    for_each_block_of_roots(
        n, root,
        [&body, &level](std::size_t i, const double* __restrict these, auto count) MOLLIFY_INLINE_LAMBDA {
            constexpr std::size_t S = register_doubles;
            if constexpr (Levels == 1) {
                static_cast<void>(level);
                MOLLIFY_VECTOR_LOOP
                for (std::size_t j = 0; j < count; ++j) body(i + j, these[j], std::integral_constant<int, 0>{});
            } else if constexpr (std::is_same_v<decltype(count), std::size_t> || count % S != 0) {
                auto run = [&](auto at) MOLLIFY_INLINE_LAMBDA {
                    MOLLIFY_VECTOR_LOOP
                    for (std::size_t j = 0; j < count; ++j) body(i + j, these[j], at);
                };
                at_level<Levels>(level(these, std::size_t{count}), run, std::make_integer_sequence<int, Levels>{});
            } else {
                for (std::size_t k = 0; k < count; k += S) {
                    auto run = [&](auto at) MOLLIFY_INLINE_LAMBDA {
                        MOLLIFY_VECTOR_LOOP
                        for (std::size_t j = 0; j < S; ++j) body(i + k + j, these[k + j], at);
                    };
                    at_level<Levels>(level(these + k, S), run, std::make_integer_sequence<int, Levels>{});
                }
            }
        },
        check, out...);
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify::detail

MOLLIFY_VECTOR_MISSES_ALLOWED_END
