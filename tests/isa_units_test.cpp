// Units built for different instruction sets in one program (a user's
// -march=native unit beside generic ones, or one unit per ISA chosen at run
// time): each keeps its own copy of the solvers' inline code
// (mollify/detail/isa.hpp). Without the inline namespace the linker keeps
// one copy of each function for both units: the same address, and on a CPU
// without AVX2 the generic unit would run AVX2 instructions.
#include "isa_units/unit.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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
}

}  // namespace
