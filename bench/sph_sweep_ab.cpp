// sph_sweep_ab: the 3D cell-by-cell SPH sweep (BarotropicEuler::acceleration
// over a CellList, Wendland C4, Precision::fast; one thread, or as many as
// OpenMP is given, timed by the wall clock then) of two versions
// of include/mollify/sph, interleaved sweep by sweep in one process, so that
// the shared host's changing speed falls on both alike: issue 21, goal 1.
// bench/sph_sweep_ab.sh builds it from two checkouts (their three sweep
// headers copied into the namespaces mollify::sph_before and
// mollify::sph_after); it is not built by CMake.
//
//   sph_sweep_ab SIDE SWEEPS [moving]   (SIDE^3 particles on the benchmark's lattice;
//   moving: every other sweep with all particles shifted by a quarter spacing
//   along x, so that each sweep finds many particles in other cells than the
//   sweep before: the search's full update, not its kept order)
#include "before/euler.hpp"
#include "after/euler.hpp"
#include <mollify/static_kernel.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>

#include "lattice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <omp.h>
#include <string>
#include <vector>

namespace {

// Process CPU time on one thread; wall time on several (their CPU times add up).
double cpu_seconds() {
    static const clockid_t clock = omp_get_max_threads() > 1 ? CLOCK_MONOTONIC : CLOCK_PROCESS_CPUTIME_ID;
    timespec t;
    clock_gettime(clock, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

using C4 = mollify::StaticKernel<mollify::tables::wendland_k_2_D3, mollify::Precision::fast>;

template <class System>
double sweep(System& s, const mollify::sph::Field<3>& x, std::array<std::vector<double>, 3>& a, std::vector<double>& rho) {
    const double t0 = cpu_seconds();
    s.acceleration(x, a, &rho);
    return cpu_seconds() - t0;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
    const bool args = argc == 3 || (argc == 4 && std::string(argv[3]) == "moving");
    const long side = args ? std::strtol(argv[1], nullptr, 10) : 0;
    const long sweeps = args ? std::strtol(argv[2], nullptr, 10) : 0;
    if (side < 4 || sweeps < 1) {
        std::fprintf(stderr, "usage: sph_sweep_ab SIDE SWEEPS [moving] (SIDE >= 4, SWEEPS >= 1)\n");
        return 2;
    }
    const bool moving = argc == 4;
    const auto x = mollify::bench::lattice<3>(side);
    auto shifted = x;
    for (double& v : shifted[0]) v = mollify::sph::Domain<3>::periodic(1.0).wrap(v + 0.25 / static_cast<double>(side));
    const std::size_t n = x[0].size();
    const double dx = 1.0 / static_cast<double>(side);
    const auto box = mollify::sph::Domain<3>::periodic(1.0);
    const std::vector<double> mass(n, dx * dx * dx);
    mollify::sph_before::BarotropicEuler<3, C4, mollify::sph_before::CellList<3>> before(C4{}, 2 * dx, box, mass);
    mollify::sph_after::BarotropicEuler<3, C4, mollify::sph_after::CellList<3>> after(C4{}, 2 * dx, box, mass);
    std::array<std::vector<double>, 3> a0, a1;
    std::vector<double> rho0, rho1;
    sweep(before, x, a0, rho0);  // warm-up: the first sort, the scratch
    sweep(after, x, a1, rho1);
    const std::size_t met0 = before.interactions(), met1 = after.interactions();
    std::vector<double> t0, t1, ratio;
    for (long r = 0; r < sweeps; ++r) {
        const auto& at = moving && r % 2 == 0 ? shifted : x;
        t0.push_back(sweep(before, at, a0, rho0));
        t1.push_back(sweep(after, at, a1, rho1));
        ratio.push_back(t1.back() / t0.back());
    }
    if (before.interactions() - met0 != after.interactions() - met1) {
        std::fprintf(stderr, "sph_sweep_ab: the two versions met different pairs\n");
        return 1;
    }
    // The same sums up to their order: densities within 1e-12 relative.
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, std::abs(rho1[i] - rho0[i]) / std::abs(rho0[i]));
    if (!(worst <= 1e-12)) {
        std::fprintf(stderr, "sph_sweep_ab: densities differ by %.3g relative\n", worst);
        return 1;
    }
    const double per_sweep = static_cast<double>(after.interactions() - met1) / static_cast<double>(sweeps);
    std::sort(t0.begin(), t0.end());
    std::sort(t1.begin(), t1.end());
    // | N | positions | sweeps | before: best, median ms, inter/s | after: the same | after/before: best, median of the per-sweep ratios | max rel. rho difference |
    std::printf("| %zu | %s | %ld | %.3f | %.3f | %.3g | %.3f | %.3f | %.3g | %.3f | %.3f | %.1e |\n", n,
                moving ? "moved each sweep" : "fixed", sweeps, 1e3 * t0[0],
                1e3 * median(t0), per_sweep / t0[0], 1e3 * t1[0], 1e3 * median(t1), per_sweep / t1[0], t1[0] / t0[0],
                median(ratio), worst);
    return 0;
}
