// thread_ceiling: what two threads can gain on this machine at all, the
// ceiling beside sph_bench's two-thread speed-up (issue 21: >= 1.8x). Two
// loops, each timed with one and with two OpenMP threads in one run:
//   compute: independent multiply-add chains in registers (no memory): each
//            thread the same work, speed-up = 2 t1 / t2;
//   stream:  a sum over 256 MB (memory bandwidth): the same work split
//            between the threads, speed-up = t1 / t2.
// Best of 5 each; the load before and after.
//
//   cmake --build <build-dir> --target bench-thread-ceiling
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {

std::string loadavg() {
    std::ifstream in("/proc/loadavg");
    std::string s;
    std::getline(in, s);
    return s;
}

double seconds_of(int threads, bool stream, const std::vector<double>& big, double& sink) {
    std::vector<double> out(static_cast<std::size_t>(threads), 0.0);
    const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel num_threads(threads)
    {
        const int t = omp_get_thread_num();
        double a[8] = {1, 2, 3, 4, 5, 6, 7, 8}, s = 0;
        if (!stream) {
            for (long i = 0; i < 200000000L; ++i)
#pragma omp simd
                for (int k = 0; k < 8; ++k) a[k] = a[k] * 0.9999999 + 1e-7;
            for (double v : a) s += v;
        } else {
            const std::size_t n = big.size() / static_cast<std::size_t>(threads), lo = n * static_cast<std::size_t>(t);
            for (int rep = 0; rep < 10; ++rep)
#pragma omp simd reduction(+ : s)
                for (std::size_t i = lo; i < lo + n; ++i) s += big[i];
        }
        out[static_cast<std::size_t>(t)] = s;
    }
    for (double v : out) sink += v;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double best_of(int threads, bool stream, const std::vector<double>& big, double& sink) {
    double best = 1e300;
    for (int run = 0; run < 5; ++run) best = std::min(best, seconds_of(threads, stream, big, sink));
    return best;
}

}  // namespace

int main() {
    const std::vector<double> big(std::size_t{1} << 25, 1.0);
    double sink = 0;
    const std::string before = loadavg();
    const double c1 = best_of(1, false, big, sink), c2 = best_of(2, false, big, sink);
    const double s1 = best_of(1, true, big, sink), s2 = best_of(2, true, big, sink);
    std::printf("| loop | 1 thread s | 2 threads s | speed-up |\n|---|--:|--:|--:|\n");
    std::printf("| compute (registers, same work per thread) | %.3f | %.3f | %.2f |\n", c1, c2, 2 * c1 / c2);
    std::printf("| stream (256 MB sum, work split) | %.3f | %.3f | %.2f |\n", s1, s2, s1 / s2);
    std::printf("\nLoad (/proc/loadavg): before `%s`, after `%s`. (checksum %g)\n", before.c_str(), loadavg().c_str(), sink);
    return 0;
}
