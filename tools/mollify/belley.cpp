// Belley's estimation study (seed 002, chapitre 2 = the English article,
// §5 and Tables 1-25), reproduced with mollify's kernels, plus the same
// estimates with Wendland kernels and their high-order combinations.
//
// Setup (§5): N uniform random points sorted in [-2, 2]; for every point
// x_i in [-1, 1] the error |f^(q)(x_i) - estimate| of f = 2x + 5,
// sin(10 pi x), sin(pi x), x^2, e^x, averaged over those points, for
// N = 2000, 1000, 500, 250 and h = .5, .25, .12, .06, .03, .01.
//   Tables 1-5    classic SPH sums (5.1) with poly6, q = 0, 1, 2
//   Tables 6-10   trapezoidal sums (5.2): poly6 vs delta   (q = 0)
//   Tables 11-15  trapezoidal sums (5.2): poly6' vs delta' (q = 1)
//   Tables 16-20  trapezoidal sums (5.2): poly6'' vs delta'' (q = 2)
//   Tables 21-25  Simpson sums (5.3): poly6'' vs delta'' (q = 2)
// The estimators are tools/studies/studies/estimate.hpp; the printed values
// (scenes/printed/belley_tables.json) are only compared with, never used.
//
// Random points differ from Belley's, so agreement is judged in order of
// magnitude: |log10(ours / printed)| <= 1. Ours is the mean over
// `realisations` independent point sets (seeded); their min and max show
// how much the random points alone move each entry.
#include "experiment.hpp"
#include <mollify/exact.hpp>
#include <mollify/kernel.hpp>
#include "output.hpp"
#include "scene.hpp"

#include <mollify/error.hpp>
#include "studies/estimate.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace mollify::app {
namespace {

// A column name gnuplot can use as a curve title: it splits a header at the
// CSV separator even inside quotes, so commas (E_{h,6}, combo:m=2,base=...)
// become semicolons.
std::string plot_label(std::string s) {
    std::replace(s.begin(), s.end(), ',', ';');
    return s;
}

using std::numbers::pi;

// Belley's five test functions with their exact first and second derivatives.
struct Function {
    const char* name;  // as in the scene and the printed tables
    double (*f[3])(double);
};

const Function test_functions[] = {
    {"2x+5", {[](double x) { return 2 * x + 5; }, [](double) { return 2.0; }, [](double) { return 0.0; }}},
    {"sin(10 pi x)",
     {[](double x) { return std::sin(10 * pi * x); }, [](double x) { return 10 * pi * std::cos(10 * pi * x); },
      [](double x) { return -100 * pi * pi * std::sin(10 * pi * x); }}},
    {"sin(pi x)",
     {[](double x) { return std::sin(pi * x); }, [](double x) { return pi * std::cos(pi * x); },
      [](double x) { return -pi * pi * std::sin(pi * x); }}},
    {"x^2", {[](double x) { return x * x; }, [](double x) { return 2 * x; }, [](double) { return 2.0; }}},
    {"exp(x)", {[](double x) { return std::exp(x); }, [](double x) { return std::exp(x); }, [](double x) { return std::exp(x); }}},
};

// One estimate: kernel spec, rule, derivative order. The paper's use poly6
// and Belley's delta, delta', delta'' (mollify's box, box-d1, box-d2).
struct EstimateSpec {
    std::string kernel;
    sph::Rule rule;
    int q;
    bool paper;
    std::string symbol;  // the paper's name of the error, e.g. "E'_{h,delta}"
};

std::string key_of(const std::string& kernel, sph::Rule rule, int q) {
    return kernel + "|" + sph::rule_name(rule) + "|" + std::to_string(q);
}

std::vector<EstimateSpec> paper_estimates() {
    using sph::Rule;
    return {
        {"poly6", Rule::classic, 0, true, "clE_{h,6}"},
        {"poly6", Rule::classic, 1, true, "clE'_{h,6}"},
        {"poly6", Rule::classic, 2, true, "clE''_{h,6}"},
        {"poly6", Rule::trapezoid, 0, true, "E_{h,6}"},
        {"box", Rule::trapezoid, 0, true, "E_{h,delta}"},
        {"poly6", Rule::trapezoid, 1, true, "E'_{h,6}"},
        {"box-d1", Rule::trapezoid, 1, true, "E'_{h,delta}"},
        {"poly6", Rule::trapezoid, 2, true, "E''_{h,6}"},
        {"box-d2", Rule::trapezoid, 2, true, "E''_{h,delta}"},
        {"poly6", Rule::simpson, 2, true, "qdE''_{h,6}"},
        {"box-d2", Rule::simpson, 2, true, "qdE''_{h,delta}"},
    };
}

// The points of one realisation: N uniform in [-2, 2), sorted. The 53-bit
// mantissa is taken from mt19937_64 directly (std::uniform_real_distribution
// is not the same on every standard library); the seed sequence mixes the
// scene's seed, the realisation and N, so every (r, N) has its own points.
std::vector<double> random_points(std::uint64_t seed, std::size_t realisation, std::size_t n) {
    std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(realisation), static_cast<std::uint32_t>(n)};
    std::mt19937_64 rng(seq);
    std::vector<double> x(n);
    for (double& v : x) v = -2 + 4 * (static_cast<double>(rng() >> 11) * 0x1p-53);
    std::sort(x.begin(), x.end());
    return x;
}

struct Stats {
    std::vector<double> values;  // one per realisation
    double mean() const {
        double s = 0;
        for (double v : values) s += v;
        return s / static_cast<double>(values.size());
    }
    double min() const { return *std::min_element(values.begin(), values.end()); }
    double max() const { return *std::max_element(values.begin(), values.end()); }
};

struct Printed {
    int table;
    std::string symbol, printed, note;
    double value;
};

// Keyed by (estimate key, function, N, h as printed to 2 digits).
using ResultKey = std::tuple<std::string, std::string, long, long>;
long h_key(double h) { return std::lround(h * 1e6); }

std::filesystem::path resolve(const Scene& scene, const std::string& file) {
    std::filesystem::path p(file);
    if (p.is_absolute()) return p;
    const std::filesystem::path beside = std::filesystem::path(scene.origin()).parent_path() / p;
    if (std::filesystem::exists(beside)) return beside;
    return p;
}

std::map<ResultKey, Printed> load_printed(const Scene& scene, const std::string& file, std::vector<int>& tables) {
    std::map<ResultKey, Printed> out;
    const std::filesystem::path path = resolve(scene, file);
    std::ifstream in(path);
    if (!in) scene.reject("belley.printed", "cannot read " + path.string());
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(in);
        for (const auto& t : doc.at("tables")) {
            tables.push_back(t.at("table").get<int>());
            for (const auto& e : t.at("entries")) {
                const std::string key = key_of(e.at("kernel").get<std::string>(), sph::rule(e.at("estimator").get<std::string>()),
                                               e.at("derivative").get<int>());
                Printed p{e.at("table").get<int>(), e.at("symbol").get<std::string>(), e.at("printed").get<std::string>(),
                          e.value("note", std::string()), e.at("value").get<double>()};
                out[{key, e.at("function").get<std::string>(), e.at("n").get<long>(), h_key(e.at("h").get<double>())}] = p;
            }
        }
    } catch (const nlohmann::json::exception& e) {
        scene.reject("belley.printed", path.string() + ": " + e.what());
    }
    return out;
}

// Order-of-magnitude agreement (the brief's criterion): |log10(ours/printed)| <= 1.
bool agrees(double ours, double printed) {
    if (!(ours > 0) || !(printed > 0)) return false;
    return std::abs(std::log10(ours / printed)) <= 1;
}

// Both at the level of double rounding: the estimate is exact for this f
// (the delta sums reproduce linear functions, Simpson's quadratics), and
// what is left is summation noise whose size depends on the summation order.
bool rounding_level(double ours, double printed) { return ours < 1e-9 && printed < 1e-9; }

std::string g3(double x) { return format(x, 3); }

}  // namespace

void run_belley(const Scene& scene, Output& out) {
    const auto started = std::chrono::steady_clock::now();
    scene.only("belley", {"functions", "n", "h", "seed", "realisations", "printed", "extra_kernels", "extra_n",
                          "plot_function", "plot_n"});

    // --- parameters, all checked before any work ---
    std::vector<const Function*> functions;
    for (const std::string& name : scene.strings("belley.functions")) {
        const Function* found = nullptr;
        for (const Function& f : test_functions)
            if (name == f.name) found = &f;
        if (!found) scene.reject("belley.functions", "unknown function '" + name + "' (2x+5, sin(10 pi x), sin(pi x), x^2, exp(x))");
        functions.push_back(found);
    }
    if (functions.empty()) scene.reject("belley.functions", "no function");
    std::vector<long> ns = scene.integers("belley.n");
    if (ns.empty()) scene.reject("belley.n", "no N");
    for (long n : ns)
        if (n < 10 || n > 10'000'000) scene.reject("belley.n", "N = " + std::to_string(n) + " is not in 10 .. 10^7");
    const std::vector<double> hs = scene.numbers("belley.h");
    if (hs.empty()) scene.reject("belley.h", "no h");
    for (double h : hs)
        // h <= 1 keeps [x_i - h, x_i + h] inside the points' [-2, 2] for x_i in [-1, 1], as in the paper.
        if (!(h > 0) || !(h <= 1)) scene.reject("belley.h", "h = " + format(h, 17) + " is not in (0, 1]");
    const long seed = scene.integer("belley.seed");
    if (seed < 0) scene.reject("belley.seed", "seed = " + std::to_string(seed) + " is negative");
    const long realisations = scene.integer("belley.realisations", 1);
    if (realisations < 1 || realisations > 1000)
        scene.reject("belley.realisations", std::to_string(realisations) + " is not in 1 .. 1000");
    std::vector<int> printed_tables;
    const std::string printed_file = scene.string("belley.printed", "");
    const std::map<ResultKey, Printed> printed =
        printed_file.empty() ? std::map<ResultKey, Printed>{} : load_printed(scene, printed_file, printed_tables);
    const std::vector<std::string> extras = scene.has("belley.extra_kernels") ? scene.strings("belley.extra_kernels")
                                                                              : std::vector<std::string>{};
    std::vector<long> extra_ns = scene.has("belley.extra_n") ? scene.integers("belley.extra_n") : std::vector<long>{ns.front()};
    for (long n : extra_ns)
        if (std::find(ns.begin(), ns.end(), n) == ns.end())
            scene.reject("belley.extra_n", "N = " + std::to_string(n) + " is not in belley.n");
    const std::string plot_function = scene.string("belley.plot_function", functions.front()->name);
    if (std::none_of(functions.begin(), functions.end(), [&](const Function* f) { return plot_function == f->name; }))
        scene.reject("belley.plot_function", "'" + plot_function + "' is not in belley.functions");
    const long plot_n = scene.integer("belley.plot_n", ns.front());
    if (std::find(ns.begin(), ns.end(), plot_n) == ns.end())
        scene.reject("belley.plot_n", "N = " + std::to_string(plot_n) + " is not in belley.n");

    // --- the estimates: the paper's, then each extra kernel's ---
    std::vector<EstimateSpec> estimates = paper_estimates();
    std::map<std::string, Kernel> kernels;
    for (const char* k : {"poly6", "box", "box-d1", "box-d2"}) kernels.emplace(k, mollify::exact::kernel(k, 1));
    std::vector<std::string> extra_names;
    for (const std::string& spec : extras) {
        try {
            const Kernel k = mollify::exact::kernel(spec, 1);
            const std::string name(k.spec());
            if (kernels.count(name)) scene.reject("belley.extra_kernels", "kernel " + name + " is named twice");
            if (sph::detail::piecewise_constant(k.table()))
                scene.reject("belley.extra_kernels", "kernel " + name + " is a step kernel; Belley's are already in the study");
            kernels.emplace(name, k);
            extra_names.push_back(name);
            for (int q = 0; q <= std::min(2, k.table().smoothness); ++q) {
                estimates.push_back({name, sph::Rule::classic, q, false, ""});
                estimates.push_back({name, sph::Rule::trapezoid, q, false, ""});
            }
            if (k.table().smoothness >= 2) estimates.push_back({name, sph::Rule::simpson, 2, false, ""});
        } catch (const Error& e) {
            scene.reject("belley.extra_kernels", e.what());
        }
    }

    // --- run ---
    std::map<ResultKey, Stats> results;
    const std::size_t total = static_cast<std::size_t>(realisations) * ns.size() * hs.size();
    std::size_t done = 0;
    sph::Weights w;
    for (long r = 0; r < realisations; ++r) {
        for (long n : ns) {
            const std::vector<double> x = random_points(static_cast<std::uint64_t>(seed), static_cast<std::size_t>(r),
                                                        static_cast<std::size_t>(n));
            const sph::Samples samples(x);
            // The points x_i in [-1, 1] where the errors are measured (§5.1).
            const std::size_t first = samples.first_at_or_after(-1), end = samples.count_at_or_before(1);
            std::vector<std::vector<double>> f(functions.size()), exact(functions.size() * 3);
            for (std::size_t k = 0; k < functions.size(); ++k) {
                f[k].resize(x.size());
                for (int q = 0; q < 3; ++q) exact[3 * k + q].resize(x.size());
                for (std::size_t j = 0; j < x.size(); ++j) {
                    f[k][j] = functions[k]->f[0](x[j]);
                    for (int q = 0; q < 3; ++q) exact[3 * k + q][j] = functions[k]->f[q](x[j]);
                }
            }
            for (double h : hs) {
                for (const EstimateSpec& e : estimates) {
                    const sph::Estimator<Kernel> est(kernels.at(e.kernel), e.rule, e.q, samples, h);
                    std::vector<double> sum(functions.size(), 0.0);
                    for (std::size_t i = first; i < end; ++i) {
                        est.weights(x[i], w);
                        for (std::size_t k = 0; k < functions.size(); ++k)
                            sum[k] += std::abs(exact[3 * k + e.q][i] - w.apply(f[k]));
                    }
                    for (std::size_t k = 0; k < functions.size(); ++k)
                        results[{key_of(e.kernel, e.rule, e.q), functions[k]->name, n, h_key(h)}].values.push_back(
                            sum[k] / static_cast<double>(end - first));
                }
                progress("belley", ++done, total, "N = " + std::to_string(n) + ", h = " + format(h, 3));
            }
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

    // --- all results, one CSV (long form) ---
    struct Verdict {
        std::size_t ok = 0, differs = 0, rounding = 0, spread = 0, noted = 0, missing = 0;
    };
    std::map<int, Verdict> by_table;
    std::vector<std::string> failures;
    Table all{{"kernel", "rule", "derivative", "symbol", "function", "n", "h", "ours_mean", "ours_min", "ours_max", "table",
               "printed", "log10_ratio", "agreement", "note"},
              {}};
    for (const EstimateSpec& e : estimates)
        for (const Function* fn : functions)
            for (long n : ns)
                for (double h : hs) {
                    const std::string key = key_of(e.kernel, e.rule, e.q);
                    const Stats& s = results.at({key, fn->name, n, h_key(h)});
                    std::vector<std::string> row{e.kernel, sph::rule_name(e.rule), std::to_string(e.q), e.symbol, fn->name,
                                                 std::to_string(n), format(h, 3), format(s.mean(), 5), format(s.min(), 5),
                                                 format(s.max(), 5)};
                    const auto p = printed.find({key, fn->name, n, h_key(h)});
                    if (p == printed.end()) {
                        row.insert(row.end(), {"", "", "", "", ""});
                    } else {
                        const Printed& pv = p->second;
                        const bool ok = agrees(s.mean(), pv.value);
                        Verdict& v = by_table[pv.table];
                        std::string why;
                        if (ok) {
                            ++v.ok;
                        } else {
                            ++v.differs;
                            if (rounding_level(s.mean(), pv.value)) {
                                ++v.rounding;
                                why = "rounding level";
                            } else if (pv.value >= s.min() && pv.value <= s.max()) {
                                ++v.spread;
                                why = "within our realisations";
                            } else if (pv.note.find("misprint") != std::string::npos) {
                                ++v.noted;
                                why = "printed value noted as a probable misprint";
                            }
                            failures.push_back("Table " + std::to_string(pv.table) + ", " + pv.symbol + ", N = " + std::to_string(n) +
                                               ", h = " + format(h, 3) + ": ours " + g3(s.mean()) + " [" + g3(s.min()) + ", " +
                                               g3(s.max()) + "], printed " + pv.printed + (why.empty() ? "" : " (" + why + ")"));
                        }
                        row.insert(row.end(), {std::to_string(pv.table), pv.printed,
                                               format(pv.value > 0 && s.mean() > 0 ? std::log10(s.mean() / pv.value) : std::numeric_limits<double>::quiet_NaN(), 3),
                                               ok ? "ok" : "differs", pv.note});
                    }
                    all.add(std::move(row));
                }
    out.csv("belley.csv", all);

    // --- the paper's tables, in its layout, ours beside the printed value ---
    std::string md = "# Belley's Tables 1-25: ours beside the printed values\n\n"
                     "Ours: mean over " + std::to_string(realisations) +
                     " realisations of the random points (CSV `belley.csv` has min and max). "
                     "Agreement: |log10(ours/printed)| <= 1 (\"ok\"); the last column lists the entries that differ "
                     "(ours/printed).\n\n";
    const std::vector<EstimateSpec> paper = paper_estimates();
    const long paper_ns[] = {2000, 1000, 500, 250};
    for (int t = 1; t <= 25; ++t) {
        if (std::find(printed_tables.begin(), printed_tables.end(), t) == printed_tables.end()) continue;
        const int group = (t - 1) / 5;
        const std::string fname = test_functions[(t - 1) % 5].name;
        if (std::none_of(functions.begin(), functions.end(), [&](const Function* f) { return fname == f->name; })) continue;
        std::vector<const EstimateSpec*> cols;
        if (group == 0) {
            cols = {&paper[0], &paper[1], &paper[2]};
        } else {
            cols = {&paper[2 * group + 1], &paper[2 * group + 2]};
        }
        md += "## Table " + std::to_string(t) + ": " + fname + " (" + (group == 0 ? "classic SPH, §5.1" : group < 4 ? "trapezoidal rule, §5.2" : "Simpson's rule, §5.3") + ")\n\n";
        // Tables 1-5 are printed in two blocks (N = 2000 | 1000, N = 500 | 250).
        std::vector<std::vector<long>> blocks = group == 0 ? std::vector<std::vector<long>>{{2000, 1000}, {500, 250}}
                                                           : std::vector<std::vector<long>>{std::vector<long>(paper_ns, paper_ns + 4)};
        for (const auto& block : blocks) {
            Table tab{{"h"}, {}};
            for (long n : block)
                for (const EstimateSpec* c : cols) {
                    tab.columns.push_back("N=" + std::to_string(n) + " " + c->symbol);
                    tab.columns.push_back("printed");
                }
            tab.columns.push_back("agreement");
            bool any = false;
            for (double h : hs) {
                std::vector<std::string> row{format(h, 2)};
                std::string differs;
                for (long n : block)
                    for (const EstimateSpec* c : cols) {
                        const ResultKey k{key_of(c->kernel, c->rule, c->q), fname, n, h_key(h)};
                        const auto rs = results.find(k);
                        const auto p = printed.find(k);
                        row.push_back(rs == results.end() ? "" : g3(rs->second.mean()));
                        row.push_back(p == printed.end() ? "–" : p->second.printed);
                        if (rs != results.end()) any = true;
                        if (rs != results.end() && p != printed.end() && !agrees(rs->second.mean(), p->second.value))
                            differs += (differs.empty() ? "" : ", ") + ("N=" + std::to_string(n) + " " + c->symbol + " ×" +
                                                                         g3(rs->second.mean() / p->second.value));
                    }
                row.push_back(differs.empty() ? "ok" : "differs: " + differs);
                tab.add(std::move(row));
            }
            if (any) md += tab.markdown() + "\n";
        }
    }
    out.write("belley_tables.md", md);

    // --- extra kernels: the same estimates, one table per (q, rule) and N ---
    std::string extra_md = "# The same estimates with Wendland kernels and combinations\n\n"
                           "Mean |error| over x_i in [-1, 1], mean over realisations; columns: kernels. "
                           "poly6 and Belley's delta family (box, box-d1, box-d2) for reference.\n\n";
    const char* box_of[3] = {"box", "box-d1", "box-d2"};
    for (long n : extra_ns)
        for (int q = 0; q < 3; ++q)
            for (sph::Rule rule : {sph::Rule::classic, sph::Rule::trapezoid, sph::Rule::simpson}) {
                if (rule == sph::Rule::simpson && q != 2) continue;
                std::vector<std::string> ks{"poly6"};
                if (rule != sph::Rule::classic) ks.push_back(box_of[q]);
                for (const std::string& k : extra_names)
                    if (results.count({key_of(k, rule, q), functions.front()->name, n, h_key(hs.front())})) ks.push_back(k);
                Table tab{{"function", "h"}, {}};
                for (const std::string& k : ks) tab.columns.push_back(k);
                for (const Function* fn : functions)
                    for (double h : hs) {
                        std::vector<std::string> row{fn->name, format(h, 2)};
                        for (const std::string& k : ks) {
                            const auto rs = results.find({key_of(k, rule, q), fn->name, n, h_key(h)});
                            row.push_back(rs == results.end() ? "" : g3(rs->second.mean()));
                        }
                        tab.add(std::move(row));
                    }
                extra_md += "## N = " + std::to_string(n) + ", " + sph::rule_name(rule) + ", f" + std::string(q, '\'') + "\n\n" +
                            tab.markdown() + "\n";
            }
    out.write("extras.md", extra_md);

    // --- plot: error against h, log-log, one function and N ---
    {
        Table plot{{"h"}, {}};
        std::vector<std::string> titles;
        for (const EstimateSpec& e : paper) {
            plot.columns.push_back(plot_label(e.symbol));
            plot.columns.push_back(plot_label(e.symbol) + " printed");
        }
        for (double h : hs) {
            std::vector<std::string> row{format(h, 3)};
            for (const EstimateSpec& e : paper) {
                const ResultKey k{key_of(e.kernel, e.rule, e.q), plot_function, plot_n, h_key(h)};
                row.push_back(format(results.at(k).mean(), 6));
                const auto p = printed.find(k);
                row.push_back(p == printed.end() ? "NaN" : format(p->second.value, 6));
            }
            plot.add(std::move(row));
        }
        out.csv("plot_paper.csv", plot);
        std::ostringstream gp;
        gp << "set logscale xy\nset format y '10^{%T}'\nset key outside right\nset grid\n"
           << "set xlabel 'h'\nset ylabel 'mean |error| over x_i in [-1,1]'\n"
           << "set title \"Belley §5, f = " << plot_function << ", N = " << plot_n
           << ": ours (lines), printed (points)\"\n"
           << "plot for [i=0:" << paper.size() - 1
           << "] 'plot_paper.csv' using 1:(column(2*i+2)) with linespoints lc i+1 pt 7 ps 0.6 title columnheader(2*i+2) noenhanced, \\\n"
           << "     for [i=0:" << paper.size() - 1
           << "] 'plot_paper.csv' using 1:(column(2*i+3)) with points lc i+1 pt 6 ps 1.5 notitle\n";
        out.plot("error_vs_h.png", gp.str(), 1100, 650);

        if (!extra_names.empty()) {
            Table ex{{"h"}, {}};
            std::vector<std::string> keys;
            for (int q = 0; q < 3; ++q) {
                keys.push_back(key_of(box_of[q], sph::Rule::trapezoid, q));
                keys.push_back(key_of("poly6", sph::Rule::trapezoid, q));
                for (const std::string& k : extra_names) keys.push_back(key_of(k, sph::Rule::trapezoid, q));
            }
            std::vector<std::string> present;
            for (const std::string& k : keys)
                if (results.count({k, plot_function, plot_n, h_key(hs.front())})) present.push_back(k);
            for (const std::string& k : present) ex.columns.push_back(plot_label(k));
            for (double h : hs) {
                std::vector<std::string> row{format(h, 3)};
                for (const std::string& k : present) row.push_back(format(results.at({k, plot_function, plot_n, h_key(h)}).mean(), 6));
                ex.add(std::move(row));
            }
            out.csv("plot_extras.csv", ex);
            std::ostringstream gx;
            gx << "set multiplot layout 1,3 title \"trapezoidal sums, f = " << plot_function << ", N = " << plot_n << "\"\n"
               << "set logscale xy\nset format y '10^{%T}'\nset grid\nset xlabel 'h'\nset key bottom left font ',7'\n";
            std::size_t col = 2;
            for (int q = 0; q < 3; ++q) {
                std::size_t count = 0;
                for (const std::string& k : present)
                    if (k.ends_with("|" + std::to_string(q))) ++count;
                gx << "set title \"f" << std::string(q, '\'') << "\"\nplot for [i=" << col << ":" << col + count - 1
                   << "] 'plot_extras.csv' using 1:i with linespoints title columnheader(i) noenhanced\n";
                col += count;
            }
            gx << "unset multiplot\n";
            out.plot("extras_vs_h.png", gx.str(), 1500, 550);
        }
    }

    // --- summary ---
    std::string& s = out.summary();
    s += "# " + scene.title() + "\n\n";
    s += "Belley (seed 002, chapitre 2, §5): N uniform random points sorted in [-2, 2] (seed " + std::to_string(seed) + ", " +
         std::to_string(realisations) + " realisations), mean |f^(q)(x_i) - estimate| over the points x_i in [-1, 1]. "
         "Kernels from mollify's tables: poly6 is exactly Belley's k_{h,poly6} (8); box, box-d1, box-d2 are his "
         "delta (12), delta' (16), delta'' (20) at h = 1, scaled as h^(-1-q) W(x/h) (`tools/studies/studies/estimate.hpp`).\n\n";
    s += "Run time: " + format(seconds, 3) + " s for the estimates (" + std::to_string(estimates.size()) + " estimates × " +
         std::to_string(functions.size()) + " functions × " + std::to_string(ns.size()) + " N × " + std::to_string(hs.size()) +
         " h × " + std::to_string(realisations) + " realisations).\n\n";
    if (!printed.empty()) {
        s += "## Agreement with the printed tables\n\n"
             "Order of magnitude: |log10(ours/printed)| <= 1. Of the entries that differ: *rounding* = both below 1e-9 "
             "(the estimate is exact for f; the printed digits are summation noise), *spread* = the printed value lies "
             "inside the range of our realisations, *noted* = marked as a probable misprint in "
             "`scenes/printed/belley_tables.json`.\n\n";
        Table agree{{"table", "function", "estimates", "entries", "ok", "differs", "rounding", "spread", "noted", "other"}, {}};
        std::size_t ok = 0, total_entries = 0;
        for (const auto& [t, v] : by_table) {
            const int group = (t - 1) / 5;
            const char* what[] = {"clE, clE', clE'' (poly6)", "E_{h,6}, E_{h,delta}", "E', poly6 vs delta'",
                                  "E'', poly6 vs delta''", "qdE'' (Simpson), poly6 vs delta''"};
            const std::size_t n = v.ok + v.differs;
            ok += v.ok;
            total_entries += n;
            agree.add({std::to_string(t), test_functions[(t - 1) % 5].name, what[group], std::to_string(n), std::to_string(v.ok),
                       std::to_string(v.differs), std::to_string(v.rounding), std::to_string(v.spread), std::to_string(v.noted),
                       std::to_string(v.differs - v.rounding - v.spread - v.noted)});
        }
        s += agree.markdown() + "\n";
        s += "In all: " + std::to_string(ok) + " of " + std::to_string(total_entries) +
             " printed entries agree in order of magnitude. Full tables in the paper's layout: `belley_tables.md`; "
             "every entry with our min and max: `belley.csv`.\n\n";
        // The analysis of the one systematic failure seen with this scene
        // (8 realisations, seed 2007): stated only when it shows up.
        const bool simpson_poly6_fails = std::any_of(failures.begin(), failures.end(), [](const std::string& f) {
            return f.find("qdE''_{h,6}") != std::string::npos;
        });
        if (simpson_poly6_fails)
            s += "### Why Simpson with poly6 (qdE''_{h,6}, Tables 21-25) differs\n\n"
                 "Every other column agrees, including qdE''_{h,delta} (Simpson with delta''), which uses the same "
                 "piecewise quadratic f~ and the same Simpson rule (42), so the points, f~ and the error measure are "
                 "not the cause. Our qdE''_{h,6} is 1-3 orders of magnitude *smaller* than printed, in every table. "
                 "For f = x^2, f~ = f exactly (quadratic interpolation), so our error is only the quadrature of "
                 "f~ k''_{h,poly6} on Belley's pieces (7.6e-5 at h = .5, N = 2000), while the printed values are "
                 ".55-.66 for every N at h = .5 and .25: about 1/3 of f'' = 2. The same relative bias fits e^x "
                 "(.27-.41 against mean |f''| = sinh 1 = 1.18) and sin(pi x) (1.01 at h = .5 is what our smoothing "
                 "error gives with the estimate scaled by 4/3). So the printed Q''_{h,6} carries a bias of about 1/3 "
                 "of f'' that does not shrink with h or N, which §5.3's formulas do not produce (the exact "
                 "convolution f * k''_{h,poly6} of x^2 is exactly 2); on top of it the printed 2x+5 errors are "
                 "14-100x ours. We could not identify the slip in Belley's code (it is not published); our "
                 "implementation follows §5.3 literally (his pieces, oriented, Simpson per piece) and its "
                 "trapezoidal counterpart agrees with Tables 16-20. We report these entries as disagreeing rather "
                 "than tune the method to match.\n\n";
        if (!failures.empty()) {
            s += "### Entries that differ\n\n";
            for (const std::string& f : failures) s += "- " + f + "\n";
            s += "\n";
        }
    }
    s += "## Plots\n\n![error vs h](error_vs_h.png)\n\n";
    if (!extra_names.empty()) s += "![extra kernels](extras_vs_h.png)\n\nThe extra kernels' tables: `extras.md`.\n\n";
}

}  // namespace mollify::app
