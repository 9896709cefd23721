// vortex_sheet_bench: the periodic vortex sheet's velocity (one evaluation
// at every particle) by the treecode against direct summation (issue 21:
// "give the 2D vortex-sheet scene the 2D treecode so its N can grow to
// 10^5"), speed against error, one thread, process CPU seconds.
//
// The sheet: Krasny's (N particles, eps = 0.01) rolled by nothing, i.e. the
// hardest case for the tree (a line: leaves are long and thin), with a
// compact blob (Wendland C4) of support h = 20 / N (about 40 particles
// within each support, the resolution a sheet of N particles asks for) and
// h = 0.25 / 0.01 fixed. Direct summation is measured at every N (at N >
// 2e4 on the first 2,000 targets only and scaled by N / 2,000: the sum is
// the same per target); the treecode's error is the largest |u - u_direct|
// over those targets, relative to the largest |u_direct|.
//
//   vortex_sheet_bench [--md=FILE]   (cmake --build build --target bench-vortex-sheet)
#include <mollify/kernel.hpp>
#include <mollify/vortex.hpp>

#include "cpu_time.hpp"
#include "load_average.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <span>
#include <string>
#include <vector>

namespace vortex = mollify::vortex;
namespace bench = mollify::bench;

namespace {

constexpr std::size_t sampled = 2000;

// Direct sums at the first m targets (as vortex::velocity, which does all N).
void direct(const vortex::CompactBlob& blob, const vortex::Sheet& s, std::size_t m, std::vector<double>& u, std::vector<double>& v) {
    const std::size_t n = s.size();
    u.assign(m, 0.0);
    v.assign(m, 0.0);
    std::vector<double> dx(n), dy(n), g(n);
    for (std::size_t i = 0; i < m; ++i) {
        std::size_t k = 0;
        for (std::size_t j = 0; j < n; ++j) {
            if (j == i) continue;
            dx[k] = s.x[i] - s.x[j];
            dy[k] = s.y[i] - s.y[j];
            g[k++] = s.gamma[j];
        }
        const vortex::Velocity w = blob.sum(std::span(dx).first(k), std::span(dy).first(k), std::span(g).first(k));
        u[i] = w[0];
        v[i] = w[1];
    }
}

struct Row {
    long n;
    double h;
    int order;
    double direct_s, tree_s, error;
    bool direct_scaled;
};

Row measure(long n, double h, double theta, int order) {
    const vortex::Sheet s = vortex::krasny_sheet(n, 0.01);
    const vortex::CompactBlob blob(mollify::kernel("wendland:k=2", 2), h);
    const std::size_t m = std::min<std::size_t>(s.size(), n > 20000 ? sampled : s.size());
    std::vector<double> ud, vd, ut, vt;
    double t0 = bench::cpu_seconds();
    direct(blob, s, m, ud, vd);
    const double direct_s = (bench::cpu_seconds() - t0) * static_cast<double>(n) / static_cast<double>(m);
    const vortex::SheetTreecode tree(blob, theta, order);
    double tree_s = INFINITY;
    for (int rep = 0; rep < 3; ++rep) {  // best of 3: the host is shared
        t0 = bench::cpu_seconds();
        vortex::velocity(tree, s, ut, vt);
        tree_s = std::min(tree_s, bench::cpu_seconds() - t0);
    }
    double e = 0, top = 0;
    for (std::size_t i = 0; i < m; ++i) {
        e = std::max(e, std::hypot(ut[i] - ud[i], vt[i] - vd[i]));
        top = std::max(top, std::hypot(ud[i], vd[i]));
    }
    return {n, h, order, direct_s, tree_s, e / top, m < s.size()};
}

void print(const Row& r) {
    std::printf("N %7ld  h %.2e  p %2d  direct %9.3f s%s  treecode %7.3f s  speed-up %7.1f  error %.1e\n", r.n, r.h, r.order, r.direct_s,
                r.direct_scaled ? "*" : " ", r.tree_s, r.direct_s / r.tree_s, r.error);
    std::fflush(stdout);
}

std::string fmt(const char* f, double x) {
    char b[64];
    std::snprintf(b, sizeof b, f, x);
    return b;
}

}  // namespace

int main(int argc, char** argv) {
    std::string md;
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]).rfind("--md=", 0) == 0) md = argv[i] + 5;
    const std::string before = bench::load_average();
    std::vector<Row> rows;
    const double theta = 0.4;
    for (long n : {1000L, 4000L, 16000L, 64000L, 100000L})
        for (int order : {10, 20}) {
            rows.push_back(measure(n, 20.0 / static_cast<double>(n), theta, order));
            print(rows.back());
        }
    for (long n : {4000L, 16000L})
        for (double h : {0.01, 0.25}) {
            rows.push_back(measure(n, h, theta, 20));
            print(rows.back());
        }
    const std::string after = bench::load_average();
    std::printf("load before: %s\nload after:  %s\n", before.c_str(), after.c_str());
    if (md.empty()) return 0;
    std::string t =
        "# The periodic vortex sheet's velocity: treecode against direct summation\n\n"
        "`bench/vortex_sheet_bench.cpp` (`cmake --build build --target bench-vortex-sheet`): one evaluation of the velocity at "
        "every particle of Krasny's sheet (eps = 0.01), Wendland C4 blobs of support h, one thread, process CPU seconds "
        "(treecode: best of 3), theta = 0.4. Error: the largest |u_tree - u_direct| over the targets summed directly, relative "
        "to the largest |u_direct|. * direct summation timed on the first 2,000 targets and scaled by N / 2,000.\n\n"
        "load before: `" + before + "`  \nload after: `" + after + "`\n\n"
        "| N | h | order p | direct s | treecode s | speed-up | relative error |\n|---|---|---|---|---|---|---|\n";
    for (const Row& r : rows)
        t += "| " + std::to_string(r.n) + " | " + fmt("%.3g", r.h) + " | " + std::to_string(r.order) + " | " + fmt("%.3g", r.direct_s) +
             (r.direct_scaled ? "*" : "") + " | " + fmt("%.3g", r.tree_s) + " | " + fmt("%.1f", r.direct_s / r.tree_s) + " | " +
             fmt("%.1e", r.error) + " |\n";
    std::ofstream f(md + ".tmp");
    f << t;
    f.close();
    if (!f || std::rename((md + ".tmp").c_str(), md.c_str()) != 0) {
        std::fprintf(stderr, "vortex_sheet_bench: cannot write %s\n", md.c_str());
        return 1;
    }
    return 0;
}
