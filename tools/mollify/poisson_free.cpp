// Free-space Poisson: speed against error of the treecode against direct
// summation (include/mollify/poisson), for several kernels.
//
// Setup: N sources uniform in the unit cube (square), charges uniform in
// [0, 1], one smoothing length delta; targets = sources (self terms exact).
// Direct summation is the reference (its own error against exact values is
// tests/poisson_free_test.cpp's: a few hundred u sum|terms|). For every
// kernel, every (theta, p) of the grid: treecode time (tree build +
// moments + evaluation, wall clock) and the relative L2 / max errors of phi
// and E against direct summation; plus the (theta, p) the accuracy knob
// picks for the requested target error. Output: results.csv, one
// tree_K.csv per kernel, time_vs_error.png, summary.md.
#include "experiment.hpp"

#include <mollify/detail/parallel.hpp>
#include <mollify/exact.hpp>
#include <mollify/kernel.hpp>
#include <mollify/poisson.hpp>
#include <mollify/smoothing.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <sstream>

namespace mollify::app {
namespace {

template <int D>
struct Cloud {
    std::array<std::vector<double>, D> x;
    std::vector<double> q, delta;
    poisson::Sources<D> sources() const {
        Points<D> p;
        for (int c = 0; c < D; ++c) p[c] = x[c];
        return {p, q, delta};
    }
};

template <int D>
Cloud<D> uniform(long n, double delta, unsigned long seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Cloud<D> c;
    for (long j = 0; j < n; ++j) {
        for (int k = 0; k < D; ++k) c.x[k].push_back(u(rng));
        c.q.push_back(u(rng));
    }
    c.delta.push_back(delta);
    return c;
}

template <class F>
double seconds(F&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <int D>
void run(const Scene& scene, Output& out) {
    const long n = scene.integer("poisson_free.particles");
    if (n < 100 || n > 200000) scene.reject("poisson_free.particles", std::to_string(n) + " is outside 100..200000 (direct summation is O(N^2))");
    const double delta = scene.positive("poisson_free.delta");
    const std::vector<std::string> specs = scene.strings("poisson_free.kernels");
    if (specs.empty()) scene.reject("poisson_free.kernels", "needs at least one kernel");
    const std::vector<double> thetas = scene.numbers("poisson_free.thetas");
    const std::vector<long> orders = scene.integers("poisson_free.orders");
    if (thetas.empty() || orders.empty()) scene.reject("poisson_free.thetas", "thetas and orders need at least one value each");
    const long leaf = scene.integer("poisson_free.leaf_size", 0);  // 0: the treecode's default (TreeOptions::leaf_for)
    // Checked as long before they narrow to int (4294967300 had run as p = 4).
    if (leaf < 0 || leaf > n) scene.reject("poisson_free.leaf_size", std::to_string(leaf) + " is outside 0..particles (0: the default)");
    for (const long p : orders)
        if (p < 0 || p > poisson::max_order) scene.reject("poisson_free.orders", std::to_string(p) + " is outside 0.." + std::to_string(poisson::max_order));
    const double target = scene.number("poisson_free.target_error", 1e-6);
    const long seed = scene.integer("poisson_free.seed", 1);
    if (seed < 0) scene.reject("poisson_free.seed", std::to_string(seed) + " is negative");
    // Everything the grid needs is checked before the first (long) run.
    for (const double t : thetas) checked(scene, "poisson_free.thetas", [&] {
        poisson::TreeOptions{.theta = t, .order = 0, .leaf_size = static_cast<int>(leaf)}.check();
    });
    const poisson::TreeOptions knob = checked(scene, "poisson_free.target_error", [&] { return poisson::for_relative_error(target, D); });
    checked(scene, "poisson_free.delta", [&] { (void)Smoothing(delta, D); });
    std::vector<Kernel> kernels;
    for (const std::string& s : specs) {
        kernels.push_back(mollify::exact::kernel(s, D));
        if (!kernels.back().has_potential()) scene.reject("poisson_free.kernels", s + " has no potential in D = " + std::to_string(D));
    }

    const Cloud<D> cloud = uniform<D>(n, delta, static_cast<unsigned long>(seed));
    const auto sources = cloud.sources();
    Table all{{"kernel", "method", "theta", "p", "seconds", "phi_rel_l2", "E_rel_l2", "E_rel_max", "speedup"}, {}};
    std::ostringstream gp;
    gp << "set logscale xy\nset format x '10^{%T}'\nset grid\nset key outside right\n"
       << "set xlabel 'relative L2 error of the field E against direct summation'\nset ylabel 'seconds (wall, "
       << detail::thread_count() << " threads)'\n"
       << "set title 'Free-space Poisson, D = " << D << ", N = " << n << ": treecode over (theta, p) against direct summation' noenhanced\n"
       << "plot ";
    std::string best_lines;
    const std::size_t total = kernels.size() * (1 + thetas.size() * orders.size());
    std::size_t done = 0;
    for (std::size_t ki = 0; ki < kernels.size(); ++ki) {
        const Kernel& k = kernels[ki];
        poisson::Field<D> exact;
        const double t_direct = seconds([&] { exact = poisson::direct<D>(k, sources); });
        progress("poisson-free", ++done, total, specs[ki] + " direct");
        all.add({specs[ki], "direct", "", "", format(t_direct, 4), "0", "0", "0", "1"});
        Table tree{{"E_rel_l2", "seconds", "theta", "p"}, {}};
        double best_time = 0;
        std::string best;
        auto measure = [&](const poisson::TreeOptions& o, const std::string& method) {
            poisson::Field<D> f;
            const double t = seconds([&] { f = poisson::Treecode<D, Kernel>(k, sources, o).evaluate(); });
            const poisson::FieldErrors e = poisson::field_errors(f, exact);
            all.add({specs[ki], method, format(o.theta, 2), std::to_string(o.order), format(t, 4), format(e.phi_l2, 3),
                     format(e.e_l2, 3), format(e.e_max, 3), format(t_direct / t, 3)});
            return std::pair{t, e};
        };
        for (const double theta : thetas)
            for (const long p : orders) {
                const poisson::TreeOptions o{.theta = theta, .order = static_cast<int>(p), .leaf_size = static_cast<int>(leaf)};
                const auto [t, e] = measure(o, "treecode");
                tree.add({format(std::max(e.e_l2, 1e-17), 4), format(t, 4), format(theta, 2), std::to_string(p)});
                if (e.e_l2 <= target && (best.empty() || t < best_time)) {
                    best_time = t;
                    best = "θ = " + format(theta, 2) + ", p = " + std::to_string(p) + ": " + format(t, 3) + " s, " +
                           format(t_direct / t, 3) + "× faster than direct (" + format(t_direct, 3) + " s), E error " +
                           format(e.e_l2, 3);
                }
                progress("poisson-free", ++done, total, specs[ki] + " treecode");
            }
        poisson::TreeOptions ko = knob;
        ko.leaf_size = static_cast<int>(leaf);
        const auto [tk, ek] = measure(ko, "knob");
        best_lines += "- " + specs[ki] + ": fastest treecode with E error ≤ " + format(target, 2) + ": " +
                      (best.empty() ? std::string("none in the grid") : best) + "; the knob (θ = " + format(knob.theta, 2) +
                      ", p = " + std::to_string(knob.order) + ") reaches " + format(ek.e_l2, 3) + " in " + format(tk, 3) + " s.\n";
        const std::string name = "tree_" + std::to_string(ki) + ".csv";
        out.csv(name, tree);
        gp << (ki ? ", \\\n     " : "") << "'" << name << "' using 1:2 with points pt 7 ps 1.2 lc " << ki + 1
           << " title '" << specs[ki] << " treecode', " << t_direct << " with lines lc " << ki + 1 << " dt 2 title '"
           << specs[ki] << " direct'";
    }
    gp << "\n";
    out.csv("results.csv", all);
    out.plot("time_vs_error.png", gp.str(), 1200, 650);

    std::string& md = out.summary();
    md += "# " + scene.title() + "\n\n";
    md += std::to_string(n) + " sources uniform in [0, 1]^" + std::to_string(D) + ", charges uniform in [0, 1], δ = " +
          format(delta, 3) + ", targets = sources (self terms exact), " + std::to_string(detail::thread_count()) +
          " OpenMP threads, wall-clock seconds (treecode: tree, moments and evaluation). Errors are relative to direct "
          "summation (itself checked against MPFR in tests/poisson_free_test.cpp). Target error " + format(target, 2) +
          ".\n\n" + best_lines + "\n![time against error](time_vs_error.png)\n\n" + all.markdown();
}

}  // namespace

void run_poisson_free(const Scene& scene, Output& out) {
    scene.only("poisson_free", {"dim", "particles", "delta", "kernels", "thetas", "orders", "leaf_size", "target_error", "seed"});
    const long dim = scene.integer("poisson_free.dim", 3);
    if (dim == 2)
        run<2>(scene, out);
    else if (dim == 3)
        run<3>(scene, out);
    else
        scene.reject("poisson_free.dim", std::to_string(dim) + " is not 2 or 3");
}

}  // namespace mollify::app
