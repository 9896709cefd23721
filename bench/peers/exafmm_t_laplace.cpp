// exafmm-t (https://github.com/exafmm/exafmm-t, BSD-3) on the particle sets
// of bench/charge_sets.hpp: the peer of issue 21's treecode comparison. Built
// only when the benchmark is configured with -DMOLLIFY_EXAFMM_T_DIR=<a clone
// of exafmm-t> (not a Debian package; it needs FFTW, BLAS and LAPACK, which
// are). Through exafmm-t's public example interface only (examples/cpp/
// laplace.cpp's steps); no code of it is copied here.
//
//   exafmm_t_laplace N neutral|positive NCRIT P [P ...]
//
// One thread. For each expansion order P, one line
//   exafmm-t,<charges>,N,P,NCRIT,<CPU s of everything>,<CPU s of evaluation>,<grad rel. L2>,<phi rel. L2>
// Everything = tree, lists, its operators (read from its cache file, see
// main), M2L setup, upward and downward passes (as mollify's treecode_bench
// times a whole evaluation). Errors at the first 1000 points against direct summation
// (plain double sums of q/(4 pi r), at most 1e6 terms: ~1e-13 relative).
// (the standard headers first: exafmm-t's headers include the intrinsics
// inside their namespace)
#include <mollify/poisson/field_errors.hpp>

#include "../charge_sets.hpp"
#include "../cpu_time.hpp"

#include "build_tree.h"
#include "build_list.h"
#include "laplace.h"

#include <omp.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace {

namespace fs = std::filesystem;

constexpr std::size_t sample = 1000;

// phi and grad phi (exafmm-t's convention: phi = sum q / (4 pi r)) at the
// first `sample` points, self term left out.
void direct(const mollify::bench::ChargeSet& s, std::vector<double>& phi, std::vector<double>& grad) {
    const std::size_t n = s.q.size(), m = std::min(sample, n);
    phi.assign(m, 0);
    grad.assign(3 * m, 0);
    const double c = 1 / (4 * M_PI);
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            if (j == i) continue;
            const double d[3] = {s.x[0][j] - s.x[0][i], s.x[1][j] - s.x[1][i], s.x[2][j] - s.x[2][i]};
            const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], r = std::sqrt(r2);
            phi[i] += c * s.q[j] / r;
            for (int k = 0; k < 3; ++k) grad[3 * i + static_cast<std::size_t>(k)] += c * s.q[j] * d[k] / (r2 * r);
        }
}

// One whole solve (exafmm-t's example's steps) on the set; the CPU seconds of
// all of it and of the passes alone.
struct Solution {
    exafmm_t::Nodes<exafmm_t::real_t> nodes;
    exafmm_t::NodePtrs<exafmm_t::real_t> leafs, nonleafs;
    double total = 0, evaluation = 0;
};

Solution solve(const mollify::bench::ChargeSet& set, int p, int ncrit, bool timed) {
    const std::size_t n = set.q.size();
    exafmm_t::Bodies<exafmm_t::real_t> sources(n), targets(n);
    for (std::size_t i = 0; i < n; ++i) {
        sources[i].ibody = targets[i].ibody = static_cast<int>(i);
        sources[i].q = set.q[i];
        for (int d = 0; d < 3; ++d) sources[i].X[d] = targets[i].X[d] = set.x[static_cast<std::size_t>(d)][i];
    }
    Solution s;
    const double t0 = mollify::bench::cpu_seconds();
    exafmm_t::LaplaceFmm fmm(p, ncrit);
    exafmm_t::get_bounds(sources, targets, fmm.x0, fmm.r0);
    s.nodes = exafmm_t::build_tree(sources, targets, s.leafs, s.nonleafs, fmm);
    exafmm_t::init_rel_coord();
    exafmm_t::build_list(s.nodes, fmm);
    fmm.precompute();
    if (!timed) return s;
    fmm.M2L_setup(s.nonleafs);
    const double t1 = mollify::bench::cpu_seconds();
    fmm.upward_pass(s.nodes, s.leafs);
    fmm.downward_pass(s.nodes, s.leafs);
    const double t2 = mollify::bench::cpu_seconds();
    s.total = t2 - t0;
    s.evaluation = t2 - t1;
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 5) {
        std::fprintf(stderr, "usage: %s N neutral|positive NCRIT P [P ...]\n", argv[0]);
        return 2;
    }
    const std::size_t n = std::strtoul(argv[1], nullptr, 10);
    const auto charges = mollify::bench::charges_named(argv[2]);
    const int ncrit = std::atoi(argv[3]);
    omp_set_num_threads(1);
    const auto set = mollify::bench::charge_set(n, charges);
    std::vector<double> phi_ref, grad_ref;
    direct(set, phi_ref, grad_ref);
    // exafmm-t keeps its precomputed operators in files named by P in the
    // working directory (laplace_d_p<P>.dat, for one tree depth and root
    // radius): here a folder beside this driver, and each P's run is timed
    // after an untimed one that writes them, so every row is exafmm-t's
    // steady state (its operators read from the file, as from the second run
    // of a simulation on), not a mix of computed and cached ones.
    const fs::path cache = fs::canonical("/proc/self/exe").parent_path() / "exafmm_t_cache";
    fs::create_directories(cache);
    fs::current_path(cache);
    for (int a = 4; a < argc; ++a) {
        const int p = std::atoi(argv[a]);
        Solution s;
        for (const bool timed : {false, true}) s = solve(set, p, ncrit, timed);
        std::vector<double> phi(phi_ref.size()), grad(grad_ref.size());
        for (auto* leaf : s.leafs)
            for (std::size_t j = 0; j < leaf->itrgs.size(); ++j) {
                const auto i = static_cast<std::size_t>(leaf->itrgs[j]);
                if (i >= phi.size()) continue;
                phi[i] = leaf->trg_value[4 * j];
                for (std::size_t k = 0; k < 3; ++k) grad[3 * i + k] = leaf->trg_value[4 * j + 1 + k];
            }
        std::printf("exafmm-t,%s,%zu,%d,%d,%.4f,%.4f,%.3e,%.3e\n", mollify::bench::name(charges), n, p, ncrit, s.total,
                    s.evaluation, mollify::poisson::relative_l2(grad, grad_ref), mollify::poisson::relative_l2(phi, phi_ref));
        std::fflush(stdout);
    }
    return 0;
}
