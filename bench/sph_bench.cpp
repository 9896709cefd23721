// sph_bench: particle–neighbour interactions per second of one SPH sweep,
// BarotropicEuler::acceleration (neighbour update + gather + kernel pairs +
// accumulation), on the periodic unit box, d = 1 and d = 3, with the O(N)
// searches (CellList, the default in both; in 1D also SortedSweep, the 1D
// default until stop 54) for N = 10^4 .. 10^6 and the O(N^2) AllPairs
// baseline for N = 10^3 .. 10^4 (Google Benchmark). In 3D the cell list
// also in R^3, on the lattice alone and with one far particle (Space): the
// far particle must not widen the cells (CellList::layout).
//
// Particles: the lattice of spacing dx = 1/n per side, each coordinate
// jittered by a seeded uniform +-jitter*dx, masses dx^d (rho_0 = 1). Support
// radius eps = 20 dx in 1D (41 lattice points within eps, ~40 after the
// jitter: the two at exactly 20 dx are in or out), eps = 2 dx in 3D (33
// lattice points within eps, ~30 after the jitter: the six at exactly 2 dx);
// the neighbour count per particle is constant in N and measured.
//
// Kernels: Wendland C4 (wendland:k=2, D1 and D3); in 1D also the order-6
// combination of Wendland C6 (combo:m=3,base=wendland:k=3), a costly
// high-order kernel; in both a zero kernel (writes W = grad W = 0, no
// arithmetic), which leaves the search, gather and accumulation: the
// kernel's share of a sweep is the difference.
//
// Interactions: ordered pairs (i, j) with |x_i - x_j| <= eps, i = j
// included, the same count for every search. The CellList sweep
// (BarotropicEuler's cell-by-cell path, Newton's third law) evaluates the
// kernel once per unordered pair {i, j}, i != j, and updates both
// particles: it counts that pair twice, as AllPairs and SortedSweep (which
// evaluate it once from each side) do; i = i once (W(0), one evaluation per
// sweep). So with CellList the kernel is called on about half the interactions.
//
// Counters, with as many OpenMP threads as the environment allows (bench-sph
// runs one), from the process's CPU time with one thread (one core's work,
// whatever else the shared machine runs), from wall time with several:
// inter/s = particle–neighbour pairs met per second (i = j included),
// ns/particle, ms/sweep (the console prints these two inverted rates with a
// unit "s"), nbrs = pairs per particle. The Markdown adds the wall time, the
// fit of time ∝ N^α, the kernel's share, the speed-up over all pairs and
// the far particle's cost.
//
//   sph_bench [benchmark flags] [--md=FILE]   (cmake --build build --target bench-sph)
#include <mollify/detail/parallel.hpp>
#include <mollify/kernel.hpp>
#include <mollify/sph/euler.hpp>
#include <mollify/static_kernel.hpp>
#include <mollify/tables/combo/m_3_base_wendland_k_3_D1.hpp>
#include <mollify/tables/wendland/k_2_D1.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>

#include "lattice.hpp"
#include "report.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace sph = mollify::sph;
namespace tables = mollify::tables;

namespace {

constexpr double all_pairs_cap = 2;   // seconds: AllPairs sweeps slower than this are skipped
constexpr double linear_within = 0.15;  // |alpha - 1| (or |alpha - 2|) that counts as O(N) (O(N^2))

// W = grad W = 0 on every pair (and 0 for any one quantity, for a sweep
// that evaluates one alone): the sweep without the kernel arithmetic. A
// RadialKernel like any other (what the solvers take), its description that
// of Wendland C4 in D, its values zero.
template <int D>
struct ZeroKernel {
    using Described = mollify::StaticKernel<D == 1 ? mollify::tables::wendland_k_2_D1 : mollify::tables::wendland_k_2_D3>;
    static constexpr int dimension = D;
    static constexpr int dim() { return D; }
    static std::string_view spec() { return "zero"; }
    static const mollify::table::Kernel& table() { return Described::table(); }
    static constexpr bool has_potential() { return false; }
    static mollify::Smoothing smoothing(double h) { return mollify::Smoothing(h, D); }
    template <class Points, class Out>
    void pairs(const Points&, const mollify::Smoothing&, std::span<double> w, const Out& grad) const {
        std::fill(w.begin(), w.end(), 0.0);
        for (const auto& c : grad) std::fill(c.begin(), c.end(), 0.0);
    }
    template <mollify::QuantityId>
    void evaluate(std::span<const double>, const mollify::Smoothing&, std::span<double> out) const {
        std::fill(out.begin(), out.end(), 0.0);
    }
    void evaluate(mollify::QuantityId, std::span<const double>, const mollify::Smoothing&, std::span<double> out) const {
        std::fill(out.begin(), out.end(), 0.0);
    }
    double operator()(mollify::QuantityId, double, double) const { return 0.0; }
    double value(double, double) const { return 0.0; }
};
static_assert(mollify::RadialKernel<ZeroKernel<3>>);

// Wendland C4 through the run-time form (mollify::kernel by its spec, the
// data-driven loops of libmollify), as the scenes and `mollify report` run
// their kernels: one indirect call per particle (1D) or batch of pairs (3D).
template <int D>
struct RunTimeC4 : mollify::Kernel {
    RunTimeC4() : mollify::Kernel(mollify::kernel("wendland:k=2", D, mollify::Precision::fast)) {}
};
static_assert(mollify::RadialKernel<RunTimeC4<3>>);

// The CellList visited particle by particle (update and visit only, no
// half_pairs): BarotropicEuler's per-particle sweep, as it ran in 3D before
// the cell-by-cell sweep, measured in the same run for the comparison.
template <int D>
class CellListByParticle {
public:
    static constexpr int dim = D;
    CellListByParticle(sph::Domain<D> domain, double eps, sph::SupportEdge edge) : cells_(domain, eps, edge) {}
    void update(const sph::Positions<D>& x) { cells_.update(x); }
    template <class F>
    void visit(std::size_t i, F&& f) const {
        cells_.visit(i, std::forward<F>(f));
    }

private:
    sph::CellList<D> cells_;
};

// One benchmark's parameters, kept for the Markdown table.
struct Case {
    int d;
    std::string search, kernel;
    long side;  // particles per side
    std::size_t n;
    double eps_over_dx;
    std::string domain;  // "periodic box", "R^d", "R^d, one far particle"
};

// Where the lattice lies: the periodic unit box (the benchmark's usual
// case); R^d; R^d with one more particle far from the lattice (at 10^6 on
// every axis), which the cell list's layout must not let crowd the
// lattice's cells (CellList::layout; before stop 55 it made cells as wide
// as the bounding box over N^(1/d), one of them holding the lattice); the
// periodic box with 9 in 10 of the lattice's particles drawn into its
// middle eighth on every axis (spacing dx/8, eps scaled with it), the
// rest a sparse background, whose cells must not crowd (before stop 56 a
// cell of side 1/(N^(1/d) + 1) held ~460 of the cluster's particles); R^d
// with N/10 more particles in a wide Gaussian envelope about the lattice
// (sigma 5) and one at 10^6 (before stop 56 the envelope's slabs were
// coarsened to fit, the lattice's with them).
enum class Space { periodic, open, open_far, periodic_cluster, open_envelope };

const char* space_name(Space s) {
    switch (s) {
        case Space::periodic: return "periodic box";
        case Space::open: return "R^d";
        case Space::open_far: return "R^d, one far particle";
        case Space::periodic_cluster: return "periodic box, a cluster";
        case Space::open_envelope: return "R^d, an envelope and a far particle";
    }
    return "";
}

const char* space_path(Space s) {
    switch (s) {
        case Space::periodic: return "";
        case Space::open: return "open/";
        case Space::open_far: return "open+far/";
        case Space::periodic_cluster: return "periodic+cluster/";
        case Space::open_envelope: return "open+envelope/";
    }
    return "";
}
std::map<std::string, Case>& cases() {
    static std::map<std::string, Case> c;
    return c;
}
std::vector<std::string>& order() {  // registration order
    static std::vector<std::string> o;
    return o;
}

template <int D, class Kernel, class Search>
void sweep(benchmark::State& state, long side, double eps_over_dx, bool capped, Space space) {
    sph::Field<D> x = mollify::bench::lattice<D>(side);
    if (space == Space::open_far || space == Space::open_envelope)
        for (auto& c : x) c.push_back(1e6);
    if (space == Space::open_envelope) {
        std::mt19937_64 g(7);
        std::normal_distribution<double> spread(0.5, 5);
        for (std::size_t i = 0, m = x[0].size() / 10; i < m; ++i)
            for (auto& c : x) c.push_back(spread(g));
    }
    const bool cluster = space == Space::periodic_cluster, periodic = space == Space::periodic || cluster;
    if (cluster)
        for (auto& c : x)
            for (std::size_t i = 0; i < c.size(); ++i)
                if (i % 10 != 0) c[i] = 0.5 + (c[i] - 0.5) / 8;
    const std::size_t n = x[0].size();
    const double dx = 1.0 / static_cast<double>(side);
    sph::BarotropicEuler<D, Kernel, Search> system(
        Kernel{}, eps_over_dx * dx / (cluster ? 8 : 1), periodic ? sph::Domain<D>::periodic(1.0) : sph::Domain<D>::whole_space(),
        std::vector<double>(n, std::pow(dx, D)));
    sph::Field<D> a;
    // Warm-up: the first sort, the scratch buffers, the work estimate.
    const auto t0 = std::chrono::steady_clock::now();
    system.acceleration(x, a);
    const double first = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (capped && first > all_pairs_cap) {
        state.SkipWithError(("one sweep takes " + std::to_string(first) + " s (cap " + std::to_string(all_pairs_cap) +
                             " s)").c_str());
        for (auto _ : state) {
        }
        return;
    }
    const std::size_t before = system.interactions();
    for (auto _ : state) {
        system.acceleration(x, a);
        benchmark::DoNotOptimize(a[0].data());
        benchmark::ClobberMemory();
    }
    const double iterations = static_cast<double>(state.iterations());
    const double met = static_cast<double>(system.interactions() - before);
    using benchmark::Counter;
    state.counters["inter/s"] = Counter(met, Counter::kIsRate);
    state.counters["ns/particle"] = Counter(iterations * static_cast<double>(n) * 1e-9, Counter::kIsRate | Counter::kInvert);
    state.counters["ms/sweep"] = Counter(iterations * 1e-3, Counter::kIsRate | Counter::kInvert);
    state.counters["nbrs"] = met / (iterations * static_cast<double>(n));
}

// One thread: the rates come from the process's CPU time, the work done by
// one core whatever else the shared machine runs; several: from wall time.
bool per_core() { return mollify::detail::thread_count() == 1; }

template <int D, class Kernel, class Search>
void register_sweeps(const char* search, const char* kernel, double eps_over_dx, std::initializer_list<long> sides,
                     Space space = Space::periodic) {
    const bool capped = std::strcmp(search, "AllPairs") == 0;
    for (const long side : sides) {
        std::size_t lattice = 1;
        for (int c = 0; c < D; ++c) lattice *= static_cast<std::size_t>(side);
        std::size_t n = lattice + (space == Space::open_far ? 1 : 0);
        if (space == Space::open_envelope) n += 1 + (lattice + 1) / 10;
        const std::string name =
            "sweep/d=" + std::to_string(D) + "/" + space_path(space) + search + "/" + kernel + "/" + std::to_string(n);
        cases().emplace(name, Case{D, search, kernel, side, n, eps_over_dx, space_name(space)});
        order().push_back(name);
        auto* b = benchmark::RegisterBenchmark(name.c_str(), [side, eps_over_dx, capped, space](benchmark::State& st) {
            sweep<D, Kernel, Search>(st, side, eps_over_dx, capped, space);
        });
        b->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
        // The fastest repetition beside the median: on a shared host the
        // median moves ~1.5x between runs of one build, the fastest far
        // less (README, "Speed: O(N) neighbour search"). Read for
        // interactions/s only, where the largest is the fastest (a time's
        // largest is its slowest).
        b->ComputeStatistics("max", [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); });
        if (!per_core()) b->UseRealTime();
    }
}

// ---- Markdown ----

using mollify::bench::Collector;
using mollify::bench::number;
using mollify::bench::slope;

std::string uptime() {
    std::string line;
    if (FILE* p = popen("uptime", "r")) {
        char buf[256];
        while (std::fgets(buf, sizeof buf, p)) line += buf;
        pclose(p);
    }
    while (!line.empty() && (line.back() == '\n' || line.back() == ' ')) line.pop_back();
    line.erase(0, line.find_first_not_of(' '));
    return line.empty() ? "(uptime unavailable)" : line;
}

struct Row {
    double inter_s = 0, ns_particle = 0, ms_sweep = 0, nbrs = 0, wall_ms = 0, best_inter_s = NAN;
};

void write_markdown(const std::string& path, const std::vector<benchmark::BenchmarkReporter::Run>& runs,
                    const std::vector<std::string>& skipped, const std::string& load_before,
                    const std::string& load_after) {
    // Medians when repeated, the single run otherwise.
    const bool repeated = std::any_of(runs.begin(), runs.end(), [](const auto& r) { return r.aggregate_name == "median"; });
    std::map<std::string, Row> rows;
    for (const auto& r : runs) {
        if (repeated ? r.aggregate_name != "median" : r.run_type != benchmark::BenchmarkReporter::Run::RT_Iteration)
            continue;
        auto at = [&](const char* k) { return r.counters.count(k) ? r.counters.at(k).value : NAN; };
        rows[r.run_name.function_name] =  // the registered name, without /real_time
             {at("inter/s"), at("ns/particle"), at("ms/sweep"), at("nbrs"),
                                             r.GetAdjustedRealTime()};  // in ms (Unit)
    }
    if (repeated)  // the fastest repetition (ComputeStatistics "max"), after the medians
        for (const auto& r : runs)
            if (r.aggregate_name == "max" && r.counters.count("inter/s") && rows.count(r.run_name.function_name))
                rows[r.run_name.function_name].best_inter_s = r.counters.at("inter/s").value;
    std::ofstream out(path + ".tmp");
    out << "# sph_bench results\n\nGenerated by `cmake --build build --target bench-sph` (bench/sph_bench.cpp), built with "
        << "-O3 -march=native -fno-math-errno, " << mollify::detail::thread_count() << " OpenMP thread(s)"
        << (repeated ? ", medians of the repetitions" : ", one run each") << "; rates and ms/sweep from "
        << (per_core() ? "the process's CPU time (one core's work, whatever else the machine runs)" : "wall time")
        << ", wall = wall-clock ms/sweep.\n"
        << "One `BarotropicEuler::acceleration` sweep (neighbour update + gather + kernel pairs + accumulation) on the\n"
        << "periodic unit box (d = 3 also in R^3, alone, with one more particle at 10^6 on every axis and with an envelope "
        << "and that particle, and in the box with a cluster); particles "
        << "on the lattice of spacing dx, jittered by +-" << mollify::bench::lattice_jitter
        << " dx (seeded), masses dx^d; eps = 20 dx (d = 1), 2 dx (d = 3).\n"
        << "inter/s = particle–neighbour pairs met per second (ordered pairs (i, j) within eps, i = j included); "
        << "neighbours/particle measured.\n"
        << "CellList (the default search, d = 1 and 3): the cell-by-cell sweep with Newton's third law, one kernel "
        << "evaluation per unordered pair {i, j} (counted as the two interactions (i, j) and (j, i), as AllPairs counts "
        << "them), particles sorted by cell and the order kept between sweeps. SortedSweep (d = 1, the default until "
        << "stop 54): particle by particle, each pair evaluated from both sides. Kernels in `Precision::fast` unless "
        << "marked (accurate).\n\n"
        << "Load (`uptime`), shared machine:\n\n- before: `" << load_before << "`\n- after: `" << load_after << "`\n\n"
        << (repeated ? "Best = interactions/s of the fastest repetition (the other columns: medians).\n\n" : "")
        << "| d | domain | search | kernel | N | neighbours/particle | interactions/s | best | ns/particle | ms/sweep | wall |\n"
        << "|--:|---|---|---|--:|--:|--:|--:|--:|--:|--:|\n";
    std::vector<std::string> series;  // d/search/kernel in order
    std::map<std::string, std::vector<std::pair<double, double>>> fits;
    for (const auto& name : order()) {
        const auto it = rows.find(name);
        if (it == rows.end()) continue;
        const Case& c = cases().at(name);
        const Row& r = it->second;
        out << "| " << c.d << " | " << c.domain << " | " << c.search << " | " << c.kernel << " | " << c.n << " | "
            << number("%.1f", r.nbrs)
            << " | " << number("%.3g", r.inter_s) << " | "
            << (std::isnan(r.best_inter_s) ? std::string("–") : number("%.3g", r.best_inter_s)) << " | "
            << number("%.1f", r.ns_particle) << " | "
            << number("%.3g", r.ms_sweep) << " | " << number("%.3g", r.wall_ms) << " |\n";
        const std::string key = "d = " + std::to_string(c.d) + ", " + c.domain + ", " + c.search + ", " + c.kernel;
        if (!fits.count(key)) series.push_back(key);
        fits[key].emplace_back(static_cast<double>(c.n), r.ms_sweep);
    }
    out << "\nFit of time per sweep ∝ N^α (least squares on log t against log N over the N measured); \"O(N)\" / \"O(N²)\" "
        << "when |α − 1| / |α − 2| ≤ " << linear_within << ":\n\n| series | N | α | growth |\n|---|---|--:|---|\n";
    for (const auto& key : series) {
        const auto& nt = fits.at(key);
        if (nt.size() < 2) {
            out << "| " << key << " | " << number("%.0f", nt[0].first) << " | – | one point |\n";
            continue;
        }
        const double alpha = slope(nt);
        const std::string verdict = std::abs(alpha - 1) <= linear_within   ? "O(N) growth shown"
                                    : std::abs(alpha - 2) <= linear_within ? "O(N²) growth shown"
                                                                           : "neither O(N) nor O(N²)";
        out << "| " << key << " | " << number("%.0f", nt.front().first) << " – " << number("%.0f", nt.back().first)
            << " | " << number("%.3f", alpha) << " | " << verdict << " |\n";
    }
    // The kernel's share: against the zero kernel on the same search and N.
    // The speed-up of the default search over the baselines at the N both ran.
    auto is_baseline = [](const std::string& search) {
        return search == "AllPairs" || search == "CellListByParticle" || search == "SortedSweep";
    };
    std::string shares, speedups;
    for (const auto& name : order()) {
        const Case& c = cases().at(name);
        if (c.kernel == "zero" || !rows.count(name)) continue;
        for (const auto& [other, o] : cases()) {
            if (o.d != c.d || o.n != c.n || o.domain != c.domain || !rows.count(other)) continue;
            const double t = rows.at(name).ms_sweep, u = rows.at(other).ms_sweep;
            if (o.kernel == "zero" && o.search == c.search)
                shares += "| " + std::to_string(c.d) + " | " + c.search + " | " + c.kernel + " | " + std::to_string(c.n) +
                          " | " + number("%.0f", 100 * (1 - u / t)) + " % |\n";
            if (o.kernel == c.kernel && is_baseline(o.search) && !is_baseline(c.search))
                speedups += "| " + std::to_string(c.d) + " | " + c.search + " | " + o.search + " | " + c.kernel + " | " +
                            std::to_string(c.n) + " | " + number("%.1f", u / t) + " |\n";
        }
    }
    if (!shares.empty())
        out << "\nThe kernel's share of a sweep, 1 − t(zero kernel) / t(kernel), same search and N (negative: within "
            << "the noise):\n\n| d | search | kernel | N | share |\n|--:|---|---|--:|--:|\n"
            << shares;
    if (!speedups.empty())
        out << "\nSpeed-up over the baselines at the same N, same run:\n\n| d | search | baseline | kernel | N | "
            << "t(baseline) / t |\n|--:|---|---|---|--:|--:|\n"
            << speedups;
    // A lattice's variant against the lattice itself (the same side, search
    // and kernel), the same run: ms/sweep and their ratio.
    auto against = [&](Space variant, Space plain) {
        std::string table;
        for (const auto& name : order()) {
            const Case& c = cases().at(name);
            if (c.domain != space_name(variant) || !rows.count(name)) continue;
            for (const auto& [other, o] : cases())
                if (o.d == c.d && o.side == c.side && o.search == c.search && o.kernel == c.kernel &&
                    o.domain == space_name(plain) && rows.count(other))
                    table += "| " + std::to_string(c.d) + " | " + c.search + " | " + c.kernel + " | " + std::to_string(o.n) +
                             " | " + number("%.3g", rows.at(other).ms_sweep) + " | " +
                             number("%.3g", rows.at(name).ms_sweep) + " | " +
                             number("%.2f", rows.at(name).ms_sweep / rows.at(other).ms_sweep) + " |\n";
        }
        return table;
    };
    if (const std::string far = against(Space::open_far, Space::open); !far.empty())
        out << "\nOne far particle, same run: the lattice in R^d alone and with one particle at 10^6 on every axis "
            << "(ms/sweep; a layout whose cells the far particle widens makes this ratio grow like N):\n\n"
            << "| d | search | kernel | N (lattice) | t(R^d) | t(with the far particle) | ratio |\n"
            << "|--:|---|---|--:|--:|--:|--:|\n"
            << far;
    if (const std::string envelope = against(Space::open_envelope, Space::open); !envelope.empty())
        out << "\nAn envelope, same run: the lattice in R^d alone and with N/10 more particles about it, Gaussian "
            << "with sigma 5 on every axis, and one at 10^6 (ms/sweep; slabs coarsened to fit the envelope made this "
            << "ratio 11, 100 and 390 at N = 10^4, 10^5, 10^6 before stop 56):\n\n"
            << "| d | search | kernel | N (lattice) | t(R^d) | t(with the envelope) | ratio |\n"
            << "|--:|---|---|--:|--:|--:|--:|\n"
            << envelope;
    if (const std::string cluster = against(Space::periodic_cluster, Space::periodic); !cluster.empty())
        out << "\nA cluster in the periodic box, same run: the lattice, and 9 in 10 of its particles drawn into the box's "
            << "middle eighth on every axis (eps dx/4: ~27 neighbours in the cluster, the background ~none; ms/sweep; "
            << "equal cells of side 1/(N^(1/3) + 1) put ~460 of the cluster's particles in each of its cells, which "
            << "made this ratio 4-9 before stop 56):\n\n"
            << "| d | search | kernel | N | t(lattice) | t(cluster) | ratio |\n"
            << "|--:|---|---|--:|--:|--:|--:|\n"
            << cluster;
    if (!skipped.empty()) {
        out << "\nSkipped:\n\n";
        for (const auto& s : skipped) out << "- " << s << "\n";
    }
    out.close();
    std::rename((path + ".tmp").c_str(), path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    const std::string md = mollify::bench::initialize(argc, argv);
    // Precision::fast, as the SPH scenes run (the kernel's rounding is far
    // below any SPH error); the 1D kernels also in Precision::accurate, the
    // cost of nearly correctly rounded kernels in a sweep.
    constexpr auto fast = mollify::Precision::fast;
    using C4_1 = mollify::StaticKernel<tables::wendland_k_2_D1, fast>;
    using C4_3 = mollify::StaticKernel<tables::wendland_k_2_D3, fast>;
    using Combo = mollify::StaticKernel<tables::combo_m_3_base_wendland_k_3_D1, fast>;
    using C4_1_accurate = mollify::StaticKernel<tables::wendland_k_2_D1>;
    using Combo_accurate = mollify::StaticKernel<tables::combo_m_3_base_wendland_k_3_D1>;
    // d = 1, eps = 20 dx; d = 3, eps = 2 dx; N = 10^4, 10^5, 10^6 (3D: 22^3, 46^3, 100^3).
    // 1D through the default search (CellList, Newton's third law) and, the
    // same run, through SortedSweep (particle by particle: the 1D default
    // until stop 54).
    const auto line = {10'000L, 100'000L, 1'000'000L};
    register_sweeps<1, C4_1, sph::CellList<1>>("CellList", "wendland:k=2", 20, line);
    register_sweeps<1, C4_1_accurate, sph::CellList<1>>("CellList", "wendland:k=2 (accurate)", 20, line);
    register_sweeps<1, Combo, sph::CellList<1>>("CellList", "combo:m=3,base=wendland:k=3", 20, line);
    register_sweeps<1, Combo_accurate, sph::CellList<1>>("CellList", "combo:m=3,base=wendland:k=3 (accurate)", 20, line);
    register_sweeps<1, RunTimeC4<1>, sph::CellList<1>>("CellList", "wendland:k=2 (run-time form)", 20, line);
    register_sweeps<1, ZeroKernel<1>, sph::CellList<1>>("CellList", "zero", 20, line);
    register_sweeps<1, C4_1, sph::SortedSweep>("SortedSweep", "wendland:k=2", 20, line);
    register_sweeps<1, RunTimeC4<1>, sph::SortedSweep>("SortedSweep", "wendland:k=2 (run-time form)", 20, line);
    register_sweeps<1, ZeroKernel<1>, sph::SortedSweep>("SortedSweep", "zero", 20, line);
    register_sweeps<1, C4_1, sph::AllPairs<1>>("AllPairs", "wendland:k=2", 20, {1'000, 3'000, 10'000});
    register_sweeps<3, C4_3, sph::CellList<3>>("CellList", "wendland:k=2", 2, {22, 46, 100});
    register_sweeps<3, RunTimeC4<3>, sph::CellList<3>>("CellList", "wendland:k=2 (run-time form)", 2, {22, 46, 100});
    register_sweeps<3, ZeroKernel<3>, sph::CellList<3>>("CellList", "zero", 2, {22, 46, 100});
    register_sweeps<3, C4_3, CellListByParticle<3>>("CellListByParticle", "wendland:k=2", 2, {22, 46});
    // R^3: the lattice alone and with one far particle (CellList::layout).
    register_sweeps<3, C4_3, sph::CellList<3>>("CellList", "wendland:k=2", 2, {22, 46, 100}, Space::open);
    register_sweeps<3, C4_3, sph::CellList<3>>("CellList", "wendland:k=2", 2, {22, 46, 100}, Space::open_far);
    // The periodic box with a cluster (CellList::periodic_layout).
    register_sweeps<3, C4_3, sph::CellList<3>>("CellList", "wendland:k=2", 2, {22, 46, 100}, Space::periodic_cluster);
    register_sweeps<3, C4_3, sph::CellList<3>>("CellList", "wendland:k=2", 2, {22, 46, 100}, Space::open_envelope);
    register_sweeps<3, C4_3, sph::AllPairs<3>>("AllPairs", "wendland:k=2", 2, {10, 14, 22});  // 1000, 2744, 10648
    Collector collector;
    const std::string before = uptime();
    benchmark::RunSpecifiedBenchmarks(&collector);
    const std::string after = uptime();
    if (!md.empty()) write_markdown(md, collector.runs(), collector.skipped(), before, after);
    benchmark::Shutdown();
    return 0;
}
