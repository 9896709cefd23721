// mollify-stability: how accurate mollify's factored evaluation is, next to
// the naive forms SPH codes use (expanded monomials, textbook pow), for
// every kernel of the catalogue, over the hard points (support edge, origin,
// h sweep) and uniform points. Writes a Markdown report and a CSV of error
// against 1 - r/h near the support edge; both atomically (temporary file,
// then rename), so an interrupted run leaves the previous report intact.
//
//   mollify-stability [--only SPEC ...] [--out docs/stability.md]
//                     [--csv docs/stability_edge.csv] [--uniform N] [--threads T]
#include "accuracy/measure.hpp"

#include <mollify/tables/catalogue.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace acc = mollify::accuracy;
using mollify::QuantityId;

namespace {

struct Job {
    std::string spec;
    int dim;
};

// One row: a quantity of a kernel in every form that exists for it.
struct Row {
    QuantityId q;
    std::optional<acc::Stats> form[3];  // indexed by acc::Form
};

struct Result {
    std::vector<Row> rows;
    std::string naive_note;  // why there is no naive form, if there is none
    std::string error;       // a failure of this kernel (reported, not fatal)
};

bool naive_quantity(QuantityId q) { return q == QuantityId::value || q == QuantityId::grad_over_r; }

// The report's family groups: the classic kernels share one.
std::string group(const std::string& spec) {
    const mollify::Family f = mollify::parse_spec(spec).family;
    switch (f) {
        case mollify::Family::mollifier:
        case mollify::Family::wendland:
        case mollify::Family::wendland_missing:
        case mollify::Family::combo: return mollify::family_name(f);
        default: return "classic";
    }
}

std::vector<Job> select_jobs(const std::vector<std::string>& only) {
    std::vector<std::string> keys;
    for (const std::string& s : only) keys.push_back(mollify::spec_string(mollify::parse_spec(s)));
    std::vector<Job> jobs;
    for (const mollify::table::Kernel* k : mollify::tables::all_kernels)
        if (keys.empty() || std::find(keys.begin(), keys.end(), k->spec) != keys.end()) jobs.push_back({k->spec, k->dim});
    return jobs;
}

// Every quantity in the mollify form; value and W'/r also in the naive forms.
Result measure_kernel(const Job& job, const std::vector<acc::Point>& points) {
    Result out;
    try {
        const acc::Reference ref(job.spec, job.dim);
        for (int i = 0; i < mollify::table::quantity_count; ++i) {
            const auto q = static_cast<QuantityId>(i);
            if (!ref.has(q)) continue;
            const acc::ExactValues exact = acc::exact_values(ref, q, points);
            Row row{q, {}};
            for (const acc::Form f : acc::all_forms) {
                if (f != acc::Form::mollify && !naive_quantity(q)) continue;
                try {
                    row.form[static_cast<int>(f)] = acc::measure(exact, acc::evaluation(job.spec, job.dim, q, f), points);
                } catch (const mollify::Error& e) {
                    out.naive_note = e.what();  // no naive form (missing Wendland)
                }
            }
            out.rows.push_back(row);
        }
    } catch (const std::exception& e) {
        out.error = e.what();
    }
    return out;
}

// The kernels measured on `threads` workers, each with its own references.
std::vector<Result> measure_all(const std::vector<Job>& jobs, const std::vector<acc::Point>& points, int threads) {
    std::vector<Result> results(jobs.size());
    std::atomic<std::size_t> next{0};
    auto work = [&] {
        for (std::size_t i; (i = next++) < jobs.size();) results[i] = measure_kernel(jobs[i], points);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (auto& t : pool) t.join();
    return results;
}

// ---- formatting ----

std::string fmt(const char* f, double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, x);
    return buf;
}

std::string ulps(double u) {
    if (std::isinf(u)) return "inf";
    if (u >= 1e4) return fmt("%.1e", u);
    return fmt(u < 10 ? "%.2f" : "%.0f", u);
}

// Where, compactly: q = r/h near 0, or 1 - q near the edge; h when not 1.
std::string where(const acc::Point& p) {
    if (p.h <= 0) return "-";
    const double q = p.r / p.h;
    std::string s = q > 1 ? "q=" + fmt("%.3g", q) : q >= 0.5 ? "1-q=" + fmt("%.2g", 1 - q) : "q=" + fmt("%.3g", q);
    if (p.h != 1) s += ", h=" + fmt("%.0e", p.h);
    return s;
}

std::string cells(const std::optional<acc::Stats>& s) {
    if (!s) return " – | – | – | – |";
    return " " + ulps(s->max_ulp) + " | " + ulps(s->rms_ulp) + " | " + ulps(s->max_scaled) + " | " + where(s->worst) + " |";
}

bool has_naive(const Result& r) {
    for (const Row& row : r.rows)
        if (row.form[1]) return true;
    return false;
}

// max over kernels of a group of max_ulp, per (group, quantity, form).
using Summary = std::map<std::pair<std::string, QuantityId>, std::array<double, 3>>;

Summary summarise(const std::vector<Job>& jobs, const std::vector<Result>& results) {
    Summary s;
    for (std::size_t i = 0; i < jobs.size(); ++i)
        for (const Row& row : results[i].rows) {
            if (!naive_quantity(row.q)) continue;
            auto [it, fresh] = s.try_emplace({group(jobs[i].spec), row.q}, std::array<double, 3>{-1, -1, -1});
            for (int f = 0; f < 3; ++f)
                if (row.form[f]) it->second[f] = std::max(it->second[f], row.form[f]->max_ulp);
        }
    return s;
}

std::string summary_table(const Summary& s) {
    std::ostringstream out;
    out << "| family | quantity | mollify | expanded | pow |\n|---|---|--:|--:|--:|\n";
    for (const auto& [key, v] : s) {
        out << "| " << key.first << " | " << mollify::quantity_names[static_cast<int>(key.second)] << " |";
        for (double u : v) out << " " << (u < 0 ? "–" : ulps(u)) << " |";
        out << "\n";
    }
    return out.str();
}

bool fma_build() {
#if defined(__FMA__) || defined(__FP_FAST_FMA)
    return true;
#else
    return false;
#endif
}

std::string header(std::size_t npoints, int uniform, const std::string& command) {
    std::ostringstream out;
    out << "# Stability of kernel evaluation: mollify against naive forms\n\n"
        << "Generated by `" << command << "` (tools/stability_report.cpp); do not edit.\n\n"
        << "Error of each double-precision evaluation against the exact value (MPFR, >= 200 correct bits), in ulps of\n"
        << "the exact value (SLEEF's countULP), at " << npoints << " points per kernel: the hard points of\n"
        << "`tools/accuracy` (1 - r/h from 1e-1 down to 1e-15, r/h down to 1e-300 and 0, h from 1e-8 to 1e8) and "
        << uniform << " seeded uniform points.\n"
        << "`max`, `rms`: over points with |exact| >= 1e-10 of the quantity's maximum; `tiny`: the largest error at\n"
        << "the other points, in ulps of the maximum; `worst`: the argument of `max` (q = r/h).\n\n"
        << "Forms: **mollify** — the runtime (`mollify::kernel(spec, dim)`), factored tables, 1 - r/h from h - r;\n"
        << "**expanded** — Horner on the expanded monomials in q (q² for even pieces), q = r·(1/h), h^-D by products\n"
        << "(SWIFT style); **pow** — the textbook factored form `pow(1 - q, n)·p(q)` (Wendland, spiky) or\n"
        << "`pow(1 - q², M)·p(q²)` (Anderson, poly6), and `Σ c_k pow(q, k)` on pieces with no root at their upper end\n"
        << "(inner pieces of the cubic spline and of combinations). Naive forms exist for W and W'/r of the polynomial\n"
        << "kernels; the missing Wendland functions (S·P + L·Q) have none. Every coefficient of every form is the\n"
        << "correctly rounded exact value.\n\n"
        << "Build: " << (fma_build() ? "fused multiply-add (FMA) enabled" : "no FMA (generic x86-64: a·b + c rounded twice)")
        << ".\n\n";
    return out.str();
}

std::string kernel_section(const Job& job, const Result& r) {
    const std::string lead = "| " + job.spec + " | " + std::to_string(job.dim) + " | ";
    if (!r.error.empty()) return lead + "error: " + r.error + " |" + std::string(12, '|') + "\n";
    std::string s;
    for (const Row& row : r.rows) {
        s += lead + mollify::quantity_names[static_cast<int>(row.q)] + " |";
        for (int f = 0; f < 3; ++f) s += cells(row.form[f]);
        s += "\n";
    }
    return s;
}

std::string report(const std::vector<Job>& jobs, const std::vector<Result>& results, std::size_t npoints, int uniform,
                   const std::string& command) {
    std::ostringstream out;
    out << header(npoints, uniform, command);
    out << "## Summary: largest error over each family (ulps)\n\n" << summary_table(summarise(jobs, results)) << "\n";
    out << "## Every kernel\n\n| kernel | D | quantity | mollify max | rms | tiny | worst | expanded max | rms | tiny | worst "
           "| pow max | rms | tiny | worst |\n|---|--:|---|--:|--:|--:|---|--:|--:|--:|---|--:|--:|--:|---|\n";
    for (std::size_t i = 0; i < jobs.size(); ++i) out << kernel_section(jobs[i], results[i]);
    std::string notes;
    for (std::size_t i = 0; i < jobs.size(); ++i)
        if (!has_naive(results[i]) && !results[i].naive_note.empty() && notes.find(jobs[i].spec) == std::string::npos)
            notes += "- " + results[i].naive_note + "\n";
    if (!notes.empty()) out << "\nNo naive form:\n\n" << notes;
    return out.str();
}

// ---- edge CSV ----

// Error against 1 - r/h for a few kernels, h = 1, 1 - q from 1e-1 to 1e-15
// in steps of 10^(1/8): the data of a plot of the edge cancellation.
std::string edge_csv(const std::vector<Job>& jobs) {
    std::ostringstream out;
    out << "kernel,dim,quantity,one_minus_q,mollify_ulp,expanded_ulp,pow_ulp\n";
    std::vector<acc::Point> points;
    for (int j = 8; j <= 120; ++j) {
        const double r = 1 - std::pow(10.0, -j / 8.0);
        points.push_back({r, 1.0, "edge"});
    }
    for (const Job& job : jobs) {
        const acc::Reference ref(job.spec, job.dim);
        for (const QuantityId q : {QuantityId::value, QuantityId::grad_over_r}) {
            const acc::ExactValues exact = acc::exact_values(ref, q, points);
            std::vector<std::vector<double>> y;
            for (const acc::Form f : acc::all_forms) {
                const acc::Evaluation e = acc::evaluation(job.spec, job.dim, q, f);
                std::vector<double> u(points.size());
                for (std::size_t i = 0; i < points.size(); ++i)
                    u[i] = acc::ulp_error(e(points[i].r, points[i].h), exact.values[i]);
                y.push_back(std::move(u));
            }
            for (std::size_t i = 0; i < points.size(); ++i)
                out << job.spec << ',' << job.dim << ',' << mollify::quantity_names[static_cast<int>(q)] << ','
                    << fmt("%.6e", 1 - points[i].r) << ',' << y[0][i] << ',' << y[1][i] << ',' << y[2][i] << "\n";
        }
    }
    return out.str();
}

// Whole file to a temporary next to it, then renamed over the target.
void write_atomically(const std::string& path, const std::string& text) {
    const std::filesystem::path target(path), tmp = target.string() + ".tmp";
    if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path());
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        f.close();
        if (!f) throw std::runtime_error("cannot write " + tmp.string());
    }
    std::filesystem::rename(tmp, target);
}

void print_summary(const std::vector<Job>& jobs, const std::vector<Result>& results, double seconds) {
    std::cout << summary_table(summarise(jobs, results));
    for (std::size_t i = 0; i < jobs.size(); ++i)
        if (!results[i].error.empty()) std::cout << "error: " << jobs[i].spec << " D=" << jobs[i].dim << ": " << results[i].error << "\n";
    std::cout << jobs.size() << " kernels in " << fmt("%.1f", seconds) << " s\n";
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"mollify-stability: ulp errors of mollify's evaluation and the naive forms, against exact values"};
    std::vector<std::string> only;
    std::string out = "docs/stability.md", csv = "docs/stability_edge.csv";
    int uniform = 1000, threads = 2;
    std::uint64_t seed = 1;
    app.add_option("--only", only, "kernel specs to measure (default: the whole catalogue)");
    app.add_option("--out", out, "Markdown report")->capture_default_str();
    app.add_option("--csv", csv, "CSV of error against 1 - r/h (empty: none)")->capture_default_str();
    app.add_option("--uniform", uniform, "uniform points per kernel")->capture_default_str()->check(CLI::Range(0, 1000000));
    app.add_option("--seed", seed, "seed of the uniform points")->capture_default_str();
    app.add_option("--threads", threads, "worker threads")->capture_default_str()->check(CLI::Range(1, 64));
    CLI11_PARSE(app, argc, argv);
    try {
        const auto start = std::chrono::steady_clock::now();
        const std::vector<Job> jobs = select_jobs(only);
        const std::vector<acc::Point> points = acc::hard_points(uniform, seed);
        const std::vector<Result> results = measure_all(jobs, points, threads);
        std::string command = "mollify-stability --uniform " + std::to_string(uniform) + " --seed " + std::to_string(seed);
        for (const std::string& s : only) command += " --only '" + s + "'";
        write_atomically(out, report(jobs, results, points.size(), uniform, command));
        if (!csv.empty()) {
            std::vector<Job> edge;
            for (const Job& j : jobs)
                if (j.dim == 3 && (j.spec == "wendland:k=2" || j.spec == "wendland:k=4,l=4" || j.spec == "mollifier:M=4" ||
                                   j.spec == "cubic-spline" || j.spec == "combo:m=3,base=wendland:k=2"))
                    edge.push_back(j);
            write_atomically(csv, edge_csv(edge));
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        print_summary(jobs, results, seconds);
        std::cout << "wrote " << out << (csv.empty() ? "" : " and " + csv) << "\n";
    } catch (const std::exception& e) {
        std::cerr << "mollify-stability: " << e.what() << "\n";
        return 2;
    }
    return 0;
}
