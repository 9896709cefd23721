// StaticKernel's batch loops against single points, bit for bit, and near the
// run-time form's x86-64-v3 copy (tests/fused_bound.hpp), in a unit
// tuned for AMD Zen 1 (batch_loops/batches.cpp, built -march=x86-64-v3
// -mtune=znver1, where MOLLIFY_BATCH_LOOP asks GCC for 256-bit vectors).
// This driver is generic x86-64: it checks the CPU before calling the unit.
#include "batch_loops/batches.hpp"

#include <mollify/kernel.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace {

TEST(BatchLoops, EveryValueOfABatchIsThePointsValueAloneAndNearTheRunTimeForm) {
    if (!(__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")))
        GTEST_SKIP() << "this CPU has no AVX2 + FMA: the x86-64-v3 unit cannot run here";
    const std::string before(mollify::isa());
    mollify::use_isa("x86-64-v3");  // the run-time form's copy for the unit's instruction set
    const batch_loops::Comparison c = batch_loops::batches_against_points();
    mollify::use_isa(before);
    std::printf("[batch loops] %zu values; StaticKernel (x86-64-v3, Zen 1 tuning) against the run-time form's "
                "x86-64-v3 copy: max %.3g ulp\n", c.compared, c.worst_against_runtime);
    // 4 tables x 2 precisions x 4 smoothing lengths x ~1,550 hard and
    // uniform points (hard_points.hpp), each quantity and W + grad W:
    // ~660,000 values.
    EXPECT_GT(c.compared, std::size_t{400000});
    for (const std::string& m : c.mismatches) ADD_FAILURE() << m;
}

}  // namespace
