// The periodic vortex sheet roll-up (notes 001, "vortex blobs": Kelvin-
// Helmholtz, N = 400, delta = 0.25) with Krasny's algebraic blob and with
// compact mollifiers of the tables (include/mollify/vortex). Output: one
// CSV per blob (positions at every snapshot time), a picture per blob (the
// sheet at each time), a picture of all blobs at the last time, and a summary
// with the invariants and the step-halving check.
#include "experiment.hpp"

#include <mollify/detail/parallel.hpp>
#include <mollify/exact.hpp>
#include <mollify/kernel.hpp>
#include <mollify/vortex.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>

namespace mollify::app {
namespace {

using VelocityKernel = std::function<vortex::Velocity(double, double)>;

struct Blob {
    std::string label;  // "algebraic, delta = 0.25" / the kernel spec
    std::function<void(vortex::Sheet&, double dt, long steps)> advance;
};

template <class B>
Blob make_blob(std::string label, B blob) {
    return {std::move(label), [blob](vortex::Sheet& s, double dt, long steps) { vortex::advance(blob, s, dt, steps); }};
}

// How the velocities are summed: pair by pair (every blob), or by the
// periodic treecode (compact blobs only: its far field is the point-vortex
// row, exact beyond the support; Krasny's algebraic blob differs from it at
// every distance).
struct Summation {
    bool treecode = false;
    double theta = 0.4;
    int order = 20;
};

struct Run {
    std::vector<vortex::Sheet> snapshots;  // at t = 0 and every requested time
    double seconds = 0;
};

Run evolve(const Blob& blob, const vortex::Sheet& start, const std::vector<double>& times, double dt) {
    Run r;
    r.snapshots.push_back(start);
    vortex::Sheet s = start;
    double t = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const double target : times) {
        const long steps = std::lround((target - t) / dt);
        blob.advance(s, dt, steps);
        t += static_cast<double>(steps) * dt;
        r.snapshots.push_back(s);
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

double max_distance(const vortex::Sheet& a, const vortex::Sheet& b) {
    double d = 0;
    for (std::size_t j = 0; j < a.size(); ++j) d = std::max(d, std::hypot(a.x[j] - b.x[j], a.y[j] - b.y[j]));
    return d;
}

std::string sheet_plot(const std::string& csv, const std::string& title, const std::vector<double>& times) {
    // One panel per time; columns 2k+3, 2k+4 are x, y at times[k] (after j, gamma).
    const std::size_t panels = times.size();
    const std::size_t cols = panels <= 2 ? panels : 2, rows = (panels + cols - 1) / cols;
    std::string s = "set multiplot layout " + std::to_string(rows) + "," + std::to_string(cols) + " title '" + title +
                    "' noenhanced\nset size ratio -1\nset xrange [0:1]\nset yrange [-0.3:0.3]\nunset key\nset grid\n";
    for (std::size_t k = 0; k < panels; ++k)
        s += "set title 't = " + format(times[k], 3) + "'\nplot '" + csv + "' using " + std::to_string(2 * k + 3) + ":" +
             std::to_string(2 * k + 4) + " with lines lw 1.5 lc 1, '' using " + std::to_string(2 * k + 3) + ":" +
             std::to_string(2 * k + 4) + " with points pt 7 ps 0.3 lc 1\n";
    return s + "unset multiplot\n";
}

}  // namespace

void run_vortex_sheet(const Scene& scene, Output& out) {
    scene.only("vortex_sheet", {"particles", "epsilon", "algebraic_delta", "kernels", "support", "times", "dt", "check_halving", "summation",
                                "treecode_theta", "treecode_order"});
    Summation sum;
    const std::string summation = scene.string("vortex_sheet.summation", "direct");
    if (summation == "treecode")
        sum.treecode = true;
    else if (summation != "direct")
        scene.reject("vortex_sheet.summation", "\"" + summation + "\" is not \"direct\" or \"treecode\"");
    if (!sum.treecode && (scene.has("vortex_sheet.treecode_theta") || scene.has("vortex_sheet.treecode_order")))
        scene.reject(scene.has("vortex_sheet.treecode_theta") ? "vortex_sheet.treecode_theta" : "vortex_sheet.treecode_order",
                     "only the treecode has it, and summation is \"direct\"");
    if (sum.treecode) {
        sum.theta = scene.number("vortex_sheet.treecode_theta", sum.theta);
        if (!(sum.theta > 0 && sum.theta < 1)) scene.reject("vortex_sheet.treecode_theta", format(sum.theta) + " is not in (0, 1)");
        const long order = scene.has("vortex_sheet.treecode_order") ? scene.integer("vortex_sheet.treecode_order") : sum.order;
        if (order < 1 || order > vortex::SheetTreecode<vortex::CompactBlob>::max_order)
            scene.reject("vortex_sheet.treecode_order",
                         std::to_string(order) + " is outside 1.." + std::to_string(vortex::SheetTreecode<vortex::CompactBlob>::max_order));
        sum.order = static_cast<int>(order);
    }
    const long n = scene.integer("vortex_sheet.particles");
    const long most = sum.treecode ? 1000000 : 20000;
    if (n < 2 || n > most)
        scene.reject("vortex_sheet.particles", std::to_string(n) + " is outside 2.." + std::to_string(most) +
                                                   (sum.treecode ? " (the treecode's range)" : " (direct summation is O(N^2); summation = \"treecode\" goes further)"));
    const double eps = scene.number("vortex_sheet.epsilon", 0.01);
    if (!std::isfinite(eps) || std::abs(eps) > 0.25) scene.reject("vortex_sheet.epsilon", format(eps) + " is not a small perturbation (|eps| <= 0.25)");
    const double dt = scene.positive("vortex_sheet.dt");
    const std::vector<double> times = scene.numbers("vortex_sheet.times");
    if (times.empty()) scene.reject("vortex_sheet.times", "needs at least one time");
    for (std::size_t k = 0; k < times.size(); ++k) {
        const double prev = k ? times[k - 1] : 0.0;
        if (!(times[k] > prev) || !std::isfinite(times[k]))
            scene.reject("vortex_sheet.times", format(times[k]) + " is not after " + format(prev) + " (times increase from 0)");
        const double steps = (times[k] - prev) / dt;
        check_step_count(scene, "vortex_sheet.times", times[k] / dt, format(times[k]) + " in steps dt = " + format(dt));
        if (std::abs(steps - std::round(steps)) > 1e-9 * std::max(1.0, steps))
            scene.reject("vortex_sheet.times", format(times[k]) + " is not a whole number of steps dt = " + format(dt) + " after " + format(prev));
    }
    const bool halving = scene.boolean("vortex_sheet.check_halving", true);

    std::vector<Blob> blobs;
    if (scene.has("vortex_sheet.algebraic_delta")) {
        const double delta = scene.positive("vortex_sheet.algebraic_delta");
        if (sum.treecode)
            scene.reject("vortex_sheet.algebraic_delta",
                         "Krasny's algebraic blob is not compact, so the treecode's far field (the point-vortex row) would not be "
                         "its velocity; drop it or use summation = \"direct\"");
        blobs.push_back(make_blob("algebraic, δ = " + format(delta, 3), vortex::AlgebraicBlob(delta)));
    }
    const std::vector<std::string> specs = scene.has("vortex_sheet.kernels") ? scene.strings("vortex_sheet.kernels") : std::vector<std::string>{};
    if (!specs.empty()) {
        const double h = scene.positive("vortex_sheet.support");
        if (h > 0.5) scene.reject("vortex_sheet.support", format(h) + " exceeds 1/2, half the period");
        for (const std::string& spec : specs) {
            try {
                vortex::CompactBlob blob(mollify::exact::kernel(spec, 2), h);
                if (sum.treecode)
                    blobs.push_back(make_blob(spec + ", h = " + format(h, 3), vortex::SheetTreecode(std::move(blob), sum.theta, sum.order)));
                else
                    blobs.push_back(make_blob(spec + ", h = " + format(h, 3), std::move(blob)));
            } catch (const Error& e) {
                scene.reject("vortex_sheet.kernels", e.what());
            }
        }
    }
    if (blobs.empty()) scene.reject("vortex_sheet.kernels", "no blob: give algebraic_delta and/or kernels");

    const vortex::Sheet start = vortex::krasny_sheet(n, eps);
    std::vector<double> all_times{0.0};
    all_times.insert(all_times.end(), times.begin(), times.end());
    Table summary{{"blob", "seconds", "circulation", "impulse drift", "max |Δx| dt vs dt/2", "max |y| at t = " + format(times.back(), 3)}, {}};
    std::string last_plot = "set size ratio -1\nset xrange [0:1]\nset yrange [-0.3:0.3]\nset grid\nset key below\nset title 'the sheet at t = " +
                            format(times.back(), 3) + "' noenhanced\nplot ";
    for (std::size_t b = 0; b < blobs.size(); ++b) {
        progress("vortex-sheet", b, blobs.size(), blobs[b].label);
        const Run run = evolve(blobs[b], start, times, dt);
        std::string halved = "–";
        if (halving) {
            const Run fine = evolve(blobs[b], start, {times.back()}, dt / 2);
            halved = format(max_distance(run.snapshots.back(), fine.snapshots.back()), 3);
        }
        Table t{{"j"}, {}};
        for (double time : all_times) {
            t.columns.push_back("x(t=" + format(time, 3) + ")");
            t.columns.push_back("y(t=" + format(time, 3) + ")");
        }
        t.columns.insert(t.columns.begin() + 1, "gamma");
        for (long j = 0; j < n; ++j) {
            std::vector<std::string> row{std::to_string(j), format(start.gamma[j], 17)};
            for (const auto& s : run.snapshots) {
                row.push_back(format(s.x[j], 10));
                row.push_back(format(s.y[j], 10));
            }
            t.add(std::move(row));
        }
        const std::string csv = "sheet_" + std::to_string(b) + ".csv";
        out.csv(csv, t);
        out.plot("sheet_" + std::to_string(b) + ".png", sheet_plot(csv, "vortex sheet, " + blobs[b].label + ", N = " + std::to_string(n), all_times),
                 1100, 300 * static_cast<int>((all_times.size() + 1) / 2) + 80);
        last_plot += std::string(b ? ", " : "") + "'" + csv + "' using " + std::to_string(2 * all_times.size() + 1) + ":" +
                     std::to_string(2 * all_times.size() + 2) + " with lines lw 1.5 title '" + blobs[b].label + "'";
        const vortex::Sheet& end = run.snapshots.back();
        double ymax = 0;
        for (double y : end.y) ymax = std::max(ymax, std::abs(y));
        summary.add({blobs[b].label, format(run.seconds, 3), format(vortex::circulation(end), 17),
                     format(vortex::impulse_y(end) - vortex::impulse_y(start), 3), halved, format(ymax, 4)});
    }
    progress("vortex-sheet", blobs.size(), blobs.size(), "plots");
    out.plot("sheets_last.png", last_plot + "\n", 1100, 450);

    std::string& md = out.summary();
    md += "# " + scene.title() + "\n\n";
    md += "Krasny's sheet: N = " + std::to_string(n) + " particles at x = a + ε sin 2πa, y = −ε sin 2πa (a = j/N, ε = " + format(eps, 3) +
          "), Γ_j = 1/N, period 1 in x; classical RK4 with dt = " + format(dt, 3) + ", " +
          (sum.treecode ? "the periodic treecode (θ = " + format(sum.theta, 3) + ", order " + std::to_string(sum.order) +
                              "; exact blobs within the support, the point-vortex row's Taylor series beyond)"
                        : std::string("direct summation over the periodic kernel")) +
          " (" + std::to_string(detail::thread_count()) + " OpenMP threads, wall-clock seconds). The algebraic blob is Krasny's δ² regularisation "
          "of the periodic kernel; a compact blob is a mollifier of the tables with support radius h, exact beyond it (the point-vortex row). "
          "\"impulse drift\" is the change of Σ Γ y (zero for the exact dynamics); \"dt vs dt/2\" the largest distance between the runs "
          "with dt and dt/2 at the last time.\n\n" + summary.markdown() + "\n![all blobs at the last time](sheets_last.png)\n\n";
    for (std::size_t b = 0; b < blobs.size(); ++b)
        md += "![" + blobs[b].label + "](sheet_" + std::to_string(b) + ".png)\n\n";
}

}  // namespace mollify::app
