// StaticKernel's batch loops against single points, bit for bit, and near the
// run-time form's copy for the same instruction set (tests/fused_bound.hpp),
// in a unit whose GCC tuning prefers other vectors than MOLLIFY_BATCH_LOOP
// asks for (batch_loops/batches.cpp): built -march=x86-64-v3 -mtune=znver1
// (128-bit preferred, 256 asked), and as batch_loops_v4_test where this
// machine has AVX-512, -march=x86-64-v4 -mtune=sapphirerapids (256-bit
// preferred, 512 asked). This driver is generic x86-64: it checks the CPU
// before calling the unit.
#include "batch_loops/batches.hpp"

#include <mollify/kernel.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace {

#if defined(BATCH_LOOPS_V4)
constexpr const char* unit_isa = "x86-64-v4";
constexpr const char* unit_tuning = "Sapphire Rapids tuning";
bool cpu_runs_unit() {
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
}
#else
constexpr const char* unit_isa = "x86-64-v3";
constexpr const char* unit_tuning = "Zen 1 tuning";
bool cpu_runs_unit() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
#endif

TEST(BatchLoops, EveryValueOfABatchIsThePointsValueAloneAndNearTheRunTimeForm) {
    if (!cpu_runs_unit()) GTEST_SKIP() << "this CPU cannot run the " << unit_isa << " unit";
    const std::string before(mollify::isa());
    mollify::use_isa(unit_isa);  // the run-time form's copy for the unit's instruction set
    const batch_loops::Comparison c = batch_loops::batches_against_points();
    mollify::use_isa(before);
    std::printf("[batch loops] %zu values; StaticKernel (%s, %s) against the run-time form's %s copy: max %.3g ulp\n",
                c.compared, unit_isa, unit_tuning, unit_isa, c.worst_against_runtime);
    // 4 tables x 2 precisions x 4 smoothing lengths x ~1,550 hard and
    // uniform points (hard_points.hpp), each quantity and W + grad W:
    // ~660,000 values.
    EXPECT_GT(c.compared, std::size_t{400000});
    for (const std::string& m : c.mismatches) ADD_FAILURE() << m;
}

TEST(BatchLoops, PairLoopsNameEveryNonFiniteCoordinate) {
    if (!cpu_runs_unit()) GTEST_SKIP() << "this CPU cannot run the " << unit_isa << " unit";
    const std::string before(mollify::isa());
    mollify::use_isa(unit_isa);
    const std::vector<std::string> missed = batch_loops::unflagged_bad_inputs();
    mollify::use_isa(before);
    for (const std::string& m : missed) ADD_FAILURE() << m;
}

TEST(BatchLoops, BatchEvaluationNamesEveryBadRadius) {
    if (!cpu_runs_unit()) GTEST_SKIP() << "this CPU cannot run the " << unit_isa << " unit";
    const std::string before(mollify::isa());
    mollify::use_isa(unit_isa);
    const std::vector<std::string> missed = batch_loops::unflagged_bad_radii();
    mollify::use_isa(before);
    for (const std::string& m : missed) ADD_FAILURE() << m;
}

}  // namespace
