// thread_scaling: what two threads gain, in one run (issue 21: the SPH sweep
// at >= 1.8x one thread), beside what they can gain on this machine at all.
// Each row timed with one and with two OpenMP threads, interleaved, best of
// 5 (the loops), best and median of at least 15 (the sweeps):
//   compute: independent multiply-add chains in registers (no memory): each
//            thread the same work, speed-up = 2 t1 / t2 (the cores' ceiling);
//   stream:  a sum over 256 MB, the work split: speed-up = t1 / t2 (the
//            memory's ceiling);
//   sph:     one BarotropicEuler::acceleration sweep in 3D (CellList,
//            Wendland C4, Precision::fast, eps = 2 dx, bench/lattice.hpp),
//            N = 22^3, 46^3, 100^3, wall time: speed-up = t1 / t2.
// The load before and after.
//
//   thread_scaling [--md=FILE]   (cmake --build build --target bench-threads)
#include <mollify/sph/euler.hpp>
#include <mollify/sph/neighbours.hpp>
#include <mollify/static_kernel.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>

#include "load_average.hpp"
#include "lattice.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace sph = mollify::sph;

double seconds(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// `reps` runs with one and with two threads, the two interleaved (a change
// of the machine's load falls on both), each sorted: on a shared machine the
// best is the run the neighbours disturbed least, the median what a run
// takes.
struct Times {
    std::vector<double> t1, t2;
    double best1() const { return t1.front(); }
    double best2() const { return t2.front(); }
    double median1() const { return t1[t1.size() / 2]; }
    double median2() const { return t2[t2.size() / 2]; }
};

Times interleaved(const std::function<void(int)>& run, int reps) {
    Times t;
    for (int rep = 0; rep < reps; ++rep) {
        t.t1.push_back(seconds([&] { run(1); }));
        t.t2.push_back(seconds([&] { run(2); }));
    }
    std::sort(t.t1.begin(), t.t1.end());
    std::sort(t.t2.begin(), t.t2.end());
    return t;
}

std::pair<double, double> best_of(const std::function<void(int)>& run, int reps) {
    const Times t = interleaved(run, reps);
    return {t.best1(), t.best2()};
}

void compute(int threads, double& sink) {
    std::vector<double> out(static_cast<std::size_t>(threads), 0.0);
#pragma omp parallel num_threads(threads)
    {
        double a[8] = {1, 2, 3, 4, 5, 6, 7, 8}, s = 0;
        for (long i = 0; i < 200000000L; ++i)
#pragma omp simd
            for (int k = 0; k < 8; ++k) a[k] = a[k] * 0.9999999 + 1e-7;
        for (double v : a) s += v;
        out[static_cast<std::size_t>(omp_get_thread_num())] = s;
    }
    for (double v : out) sink += v;
}

void stream(int threads, const std::vector<double>& big, double& sink) {
    std::vector<double> out(static_cast<std::size_t>(threads), 0.0);
#pragma omp parallel num_threads(threads)
    {
        const auto t = static_cast<std::size_t>(omp_get_thread_num());
        const std::size_t n = big.size() / static_cast<std::size_t>(threads), lo = n * t;
        double s = 0;
        for (int rep = 0; rep < 10; ++rep)
#pragma omp simd reduction(+ : s)
            for (std::size_t i = lo; i < lo + n; ++i) s += big[i];
        out[t] = s;
    }
    for (double v : out) sink += v;
}

using C4 = mollify::StaticKernel<mollify::tables::wendland_k_2_D3, mollify::Precision::fast>;

// Seconds per sweep at 1 and 2 threads, and the interactions per sweep.
struct SphRow {
    std::size_t n, interactions;
    Times t;
};

SphRow sph_sweep(long side) {
    const sph::Field<3> x = mollify::bench::lattice<3>(side);
    const std::size_t n = x[0].size();
    const double dx = 1.0 / static_cast<double>(side);
    // One system per thread count: a system sizes its scratch (a pair batch
    // per thread) and its ranges of cells by the thread count.
    using System = sph::BarotropicEuler<3, C4, sph::CellList<3>>;
    std::deque<System> systems;  // not movable (an atomic counter)
    std::vector<sph::Field<3>> a(2);
    for (int threads = 1; threads <= 2; ++threads) {
        omp_set_num_threads(threads);
        systems.emplace_back(C4{}, 2 * dx, sph::Domain<3>::periodic(1.0), std::vector<double>(n, dx * dx * dx));
        // warm-up: the first sort, the scratch, the work estimate
        systems.back().acceleration(x, a[static_cast<std::size_t>(threads - 1)]);
    }
    const std::size_t before = systems[0].interactions();
    systems[0].acceleration(x, a[0]);
    const std::size_t per_sweep = systems[0].interactions() - before;
    // ~0.4 s of one-thread sweeps a row (~0.1 us a particle), at least 15
    // (15 sweeps of ~1 ms at N ~ 10^4 left the speed-up to one lucky run)
    const Times t = interleaved(
        [&](int threads) {
            omp_set_num_threads(threads);
            const auto k = static_cast<std::size_t>(threads - 1);
            systems[k].acceleration(x, a[k]);
        },
        std::max(15, static_cast<int>(4e6 / static_cast<double>(n))));
    omp_set_num_threads(2);
    return {n, per_sweep, t};
}

std::string row(const char* name, double t1, double t2, double speedup) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "| %s | %.4g | %.4g | %.2f | | | |\n", name, t1, t2, speedup);
    return buf;
}

std::string row(const char* name, const Times& t) {
    char buf[320];
    std::snprintf(buf, sizeof buf, "| %s | %.4g | %.4g | %.2f | %.4g | %.4g | %.2f |\n", name, t.best1(), t.best2(),
                  t.best1() / t.best2(), t.median1(), t.median2(), t.median1() / t.median2());
    return buf;
}

}  // namespace

int main(int argc, char** argv) {
    std::string md;
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]).rfind("--md=", 0) == 0) md = argv[i] + 5;
    const std::vector<double> big(std::size_t{1} << 25, 1.0);
    double sink = 0;
    const std::string before = mollify::bench::load_average();
    // The sweeps first: after the ceilings' loops (seconds of both threads
    // busy) unbound threads' sweeps ran 8-30 % slower for the rest of the
    // process on the Intel host of stop 68 (bound ones not: the kernel
    // moved the threads between the cores, README "Two threads").
    std::vector<SphRow> rows;
    for (const long side : {22L, 46L, 100L}) rows.push_back(sph_sweep(side));
    const auto [c1, c2] = best_of([&](int t) { compute(t, sink); }, 5);
    const auto [s1, s2] = best_of([&](int t) { stream(t, big, sink); }, 5);
    const std::string after = mollify::bench::load_average();

    // The waiting threads sleep (passive) or spin (active) between the
    // sweep's parallel loops: a sleeping thread's wake-up is a system call,
    // a larger share of a short sweep (README, "Two threads").
    const char* policy = std::getenv("OMP_WAIT_POLICY");
    // Bound threads stay on their cores; unbound ones the kernel may move,
    // and the sweep's static schedule keeps each thread's slots and sums in
    // its core's cache only while it stays (README, "Two threads").
    const char* bind = std::getenv("OMP_PROC_BIND");
    const char* places = std::getenv("OMP_PLACES");
    std::ostringstream out;
    out << "# thread_scaling results\n\nGenerated by `cmake --build build --target bench-threads` "
           "(bench/thread_scaling.cpp), -O3 -march=native -fno-math-errno: what two OpenMP threads gain over one, "
           "each row timed with one and two threads interleaved in one run, best of 5 (the loops), best and median of at least 15 (the sweeps: ~0.4 s of one-thread sweeps a row), wall seconds. compute: "
           "multiply-add chains in registers, the same work per thread (speed-up 2 t1/t2: the cores' ceiling); "
           "stream: a 256 MB sum split between the threads (t1/t2: the memory's ceiling); sph: one 3D "
           "`BarotropicEuler::acceleration` sweep (CellList, Wendland C4, Precision::fast, eps = 2 dx, jittered "
           "lattice), t1/t2, with one thread's interactions per second.\n\nOMP_WAIT_POLICY="
        << (policy ? policy : "(unset: libgomp's default, spin a while, then sleep)") << ", OMP_PROC_BIND="
        << (bind ? bind : "(unset: threads not bound to cores)") << ", OMP_PLACES=" << (places ? places : "(unset)")
        << ".\n\nLoad (/proc/loadavg): before `"
        << before << "`, after `" << after
        << "`.\n\n| loop | 1 thread s | 2 threads s | speed-up | median 1 thread s | median 2 threads s | speed-up of "
           "medians |\n|---|--:|--:|--:|--:|--:|--:|\n"
        << row("compute", c1, c2, 2 * c1 / c2) << row("stream 256 MB", s1, s2, s1 / s2);
    for (const SphRow& r : rows) {
        char name[128];
        std::snprintf(name, sizeof name, "sph N = %zu (%.3g inter/s on 1 thread)", r.n,
                      static_cast<double>(r.interactions) / r.t.best1());
        out << row(name, r.t);
    }
    std::printf("%s\n(checksum %g)\n", out.str().c_str(), sink);
    if (!md.empty()) {
        std::ofstream f(md + ".tmp");
        f << out.str();
        f.close();
        if (!f || std::rename((md + ".tmp").c_str(), md.c_str()) != 0) {
            std::fprintf(stderr, "thread_scaling: cannot write %s\n", md.c_str());
            return 1;
        }
    }
    return 0;
}
