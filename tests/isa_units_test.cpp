// Units built for different instruction sets in one program (a user's
// -march=native unit beside generic ones, or one unit per ISA chosen at run
// time): each keeps its own copy of the solvers' inline code
// (mollify/detail/isa.hpp). Without the inline namespace the linker keeps
// one copy of each function for both units: the same address, and on a CPU
// without AVX2 the generic unit would run AVX2 instructions.
#include "isa_units/unit.hpp"

#include <mollify/poisson/field_errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

// The x86-64-v3 unit is AVX2 code throughout (this program's static
// initialisers too): a CPU without AVX2 and FMA cannot run these tests, nor
// sph_cells_v3_test.
bool runs_x86_64_v3() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }

TEST(IsaUnits, EachUnitKeepsItsOwnSolverCode) {
    if (!runs_x86_64_v3()) GTEST_SKIP() << "this CPU has no AVX2 + FMA: the x86-64-v3 unit cannot run here";
    const isa_units::UnitCode generic = isa_units::generic_code(), v3 = isa_units::v3_code();
    EXPECT_EQ(std::string(generic.isa), "isa_generic");
    EXPECT_EQ(std::string(v3.isa), "isa_avx2_fma");
    EXPECT_NE(generic.sph, v3.sph) << "sph: one copy of detail::near_pairs<3, true> for both units";
    EXPECT_NE(generic.poisson, v3.poisson) << "poisson: one copy of direct<3, Kernel> for both units";
    EXPECT_NE(generic.vortex, v3.vortex) << "vortex: one copy of velocity<CompactBlob> for both units";
}

// The two copies compute the same physics: the sums' order and the FMAs of
// the AVX2 paths differ, so agreement to 1e-13 relative of each sum's size
// (a few hundred terms of size ~1, each rounded once or twice more or less).
void expect_close(const std::vector<double>& a, const std::vector<double>& b, const char* what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    ASSERT_FALSE(a.empty()) << what;
    double scale = 0;
    for (double x : a) scale = std::max(scale, std::abs(x));
    ASSERT_GT(scale, 0) << what;
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-13 * scale) << what << " at " << i;
}

TEST(IsaUnits, BothCopiesComputeTheSameValues) {
    if (!runs_x86_64_v3()) GTEST_SKIP() << "this CPU has no AVX2 + FMA: the x86-64-v3 unit cannot run here";
    const isa_units::UnitValues generic = isa_units::generic_values(), v3 = isa_units::v3_values();
    expect_close(generic.density, v3.density, "SPH density");
    expect_close(generic.potential, v3.potential, "Poisson potential");
    expect_close(generic.u, v3.u, "vortex velocity");
    // The treecode: each unit's against its own direct summation (the
    // truncation error at theta 0.5, p = 10, measured 2.7e-7 in both, 2.6e-8
    // with the sanitizers' 1000 sources: a translation loop that mixed lanes
    // would be off by O(1)), and the two units' fields alike to 1e-13: the
    // same sources (isa_units/unit.cpp), sums of 3000 terms up to ~10^4
    // against fields of ~10^3 in other orders and with FMAs, measured
    // 4.2e-16; a term of the expansions dropped or doubled in one unit's
    // loops would show near the truncation error's size. (Until stop 51 the units'
    // sources differed by an ulp, 7.0e-11 between them, and the bound was
    // 1e-9.)
    const double g_err = mollify::poisson::relative_l2(generic.tree_field, generic.direct_field),
                 v_err = mollify::poisson::relative_l2(v3.tree_field, v3.direct_field),
                 between = mollify::poisson::relative_l2(v3.tree_field, generic.tree_field);
    std::printf("[isa] treecode E against direct: generic unit %.3g, v3 unit %.3g; between the units %.3g\n", g_err, v_err,
                between);
    EXPECT_LE(g_err, 1e-6);
    EXPECT_LE(v_err, 1e-6);
    EXPECT_LE(between, 1e-13);
}

}  // namespace
