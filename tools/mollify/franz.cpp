// Franz's convergence study (thesis §6.2): SPH for the 1D Euler equations
// with p = rho^2/2 against the quasi-analytical Burgers solution, on R
// (h = eps^2, Table 6.2) or on T (h = eps^2/10, Table 6.4), for extended
// Wendland kernels psi_{1,k,l} and their Vandermonde combinations of order
// 2m; errors Q_kin, Q_pot at t_end, rates by least squares over eps, beside
// the thesis' printed rates.
#include "experiment.hpp"
#include <mollify/exact.hpp>
#include <mollify/kernel.hpp>

#include <mollify/sph.hpp>
#include "studies/convergence.hpp"
#include "studies/franz_cases.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

namespace mollify::app {
namespace {

using sph::State;

struct KernelChoice {
    std::string spec;
    int k = -1, l = -1, m = -1;  // -1: a kernel named explicitly, not from the (k, l, m) grid
    std::string label() const {
        if (k < 0) return spec;
        return "k=" + std::to_string(k) + " l=" + std::to_string(l) + " m=" + std::to_string(m);
    }
};

// psi_{1,k,l} (m = 1) or its combination of order 2m on radii j/m (Franz 4.17).
std::string grid_spec(int k, int l, int m) {
    std::string base = "wendland:k=" + std::to_string(k) + (l ? ",l=" + std::to_string(l) : "");
    return m == 1 ? base : "combo:m=" + std::to_string(m) + ",base=" + base;
}

struct Settings {
    sph::FranzCase problem = sph::franz_torus();
    std::vector<KernelChoice> kernels;
    std::vector<double> eps;
    double t_end = 0.8, cfl = 0.05;
    sph::Integrator integrator = sph::Integrator::rk4;
    std::vector<std::size_t> dt_check;  // kernels re-run at the smallest eps with dt/2
    Precision precision = Precision::accurate;
    std::vector<std::size_t> precision_check;  // kernels re-run at the smallest eps at the other precision
    std::string printed_file, printed_table;
    std::vector<std::size_t> plot_kernels;  // time-vs-error plot
};

// The canonical spelling of a spec the scene gives under `key`.
std::string canonical(const Scene& scene, std::string_view key, const std::string& spec) {
    return checked(scene, key, [&] { return spec_string(parse_spec(spec)); });
}

// The scene's kernels named under `key` (any spelling), as indices into
// s.kernels: checked before any run, so a typo costs no study.
std::vector<std::size_t> named_kernels(const Scene& scene, const Settings& s, std::string_view key) {
    std::vector<std::size_t> out;
    for (const std::string& spec : scene.strings(key)) {
        const std::string c = canonical(scene, key, spec);
        const auto it = std::find_if(s.kernels.begin(), s.kernels.end(), [&](const KernelChoice& k) { return k.spec == c; });
        if (it == s.kernels.end()) scene.reject(key, "kernel '" + spec + "' is not among the scene's kernels");
        out.push_back(static_cast<std::size_t>(it - s.kernels.begin()));
    }
    return out;
}

Settings read(const Scene& scene) {
    scene.only("franz", {"case", "k", "l", "m", "kernels", "epsilon", "t_end", "cfl", "integrator", "dt_check",
                         "printed", "printed_table", "spacing_factor", "time_vs_error", "precision", "precision_check"});
    Settings s;
    const std::string c = scene.string("franz.case");
    if (c == "line")
        s.problem = sph::franz_line();
    else if (c == "torus")
        s.problem = sph::franz_torus();
    else
        scene.reject("franz.case", "'" + c + "' is not line or torus");
    if (scene.has("franz.spacing_factor")) s.problem.spacing_factor = scene.positive("franz.spacing_factor");
    if (scene.has("franz.k"))
        for (long k : scene.integers("franz.k"))
            for (long l : scene.integers("franz.l"))
                for (long m : scene.integers("franz.m")) {
                    if (k < 0 || k > 12 || l < 0 || l > 12 || m < 1 || m > 12)
                        scene.reject("franz.k", "(k, l, m) = (" + std::to_string(k) + ", " + std::to_string(l) + ", " +
                                                    std::to_string(m) + ") is outside k, l = 0..12, m = 1..12");
                    s.kernels.push_back({canonical(scene, "franz.k", grid_spec(int(k), int(l), int(m))), int(k), int(l), int(m)});
                }
    if (scene.has("franz.kernels"))
        for (const std::string& spec : scene.strings("franz.kernels"))
            s.kernels.push_back({canonical(scene, "franz.kernels", spec)});
    if (s.kernels.empty()) scene.reject("franz.k", "no kernels: give k, l, m lists or a kernels list");
    s.eps = scene.numbers("franz.epsilon");
    if (s.eps.size() < 2) scene.reject("franz.epsilon", "a rate needs at least two values of eps");
    for (double e : s.eps)
        if (!(e > 0) || !std::isfinite(e)) scene.reject("franz.epsilon", "eps = " + format(e, 17) + " is not positive");
    std::sort(s.eps.begin(), s.eps.end(), std::greater<>());
    if (const auto twice = std::adjacent_find(s.eps.begin(), s.eps.end()); twice != s.eps.end())
        scene.reject("franz.epsilon", "eps = " + format(*twice, 17) + " is given twice (the rates are fits over distinct eps)");
    for (double e : s.eps) {
        const double h = s.problem.spacing(e);
        if (!(e >= 2 * h))
            scene.reject("franz.epsilon", "eps = " + format(e, 6) + " is too small for the particle spacing h = " +
                                              format(h, 6) + ": the kernel must reach at least two neighbours (eps/h = " +
                                              format(e / h, 3) + " < 2)");
        if (s.problem.domain.is_periodic() && !(2 * e < s.problem.domain.length()))
            scene.reject("franz.epsilon", "eps = " + format(e, 6) + " is not below half the torus length");
    }
    s.t_end = scene.number("franz.t_end", 0.8);
    if (!(s.t_end > 0) || !(s.t_end < s.problem.solution.blow_up_time()))
        scene.reject("franz.t_end", "t_end = " + format(s.t_end, 6) + " is not in (0, " +
                                        format(s.problem.solution.blow_up_time(), 6) + "), where the exact solution exists");
    s.cfl = scene.number("franz.cfl", 0.05);
    if (!(s.cfl > 0 && s.cfl <= 1)) scene.reject("franz.cfl", "cfl = " + format(s.cfl, 6) + " is not in (0, 1]");
    s.integrator = checked(scene, "franz.integrator", [&] { return sph::integrator(scene.string("franz.integrator", "rk4")); });
    s.dt_check = scene.has("franz.dt_check") ? named_kernels(scene, s, "franz.dt_check") : std::vector<std::size_t>{0};
    s.precision = scene_precision(scene, "franz.precision");
    if (scene.has("franz.precision_check")) s.precision_check = named_kernels(scene, s, "franz.precision_check");
    s.printed_file = scene.string("franz.printed", "");
    s.printed_table = scene.string("franz.printed_table", "");
    if (scene.has("franz.time_vs_error")) s.plot_kernels = named_kernels(scene, s, "franz.time_vs_error");
    return s;
}

struct Run {
    double eps = 0, h = 0, dt = 0, wall = 0, cpu = 0, energy_drift = 0, mass_change = 0;
    std::size_t particles = 0, steps = 0, interactions = 0;
    sph::EnergyError q;
};

// One SPH run to t_end with step dt_scale times the CFL step.
Run simulate(const Settings& s, const Kernel& kernel, double eps, double dt_scale) {
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();  // the process's CPU time: robust to other load on the machine
    Run r;
    r.eps = eps;
    r.h = s.problem.spacing(eps);
    sph::Lattice lat = sph::lattice(s.problem, r.h);
    sph::BarotropicEuler<1, Kernel> system(kernel, eps, s.problem.domain, lat.mass);
    std::vector<double> rho;
    system.density(lat.state.x, rho);
    const double e0 = system.kinetic_energy(lat.state.u) + system.potential_energy(rho);
    double mass0 = 0;
    for (double m : lat.mass) mass0 += m;
    const double dt_cfl = sph::cfl_step<1>(lat.state, rho, eps, s.cfl) * dt_scale;
    r.steps = static_cast<std::size_t>(std::ceil(s.t_end / dt_cfl));
    r.dt = s.t_end / static_cast<double>(r.steps);
    sph::TimeStepper<1, decltype(system)> stepper(system, s.integrator);
    for (std::size_t n = 0; n < r.steps; ++n) stepper.step(lat.state, r.dt);
    system.density(lat.state.x, rho);
    const double e1 = system.kinetic_energy(lat.state.u) + system.potential_energy(rho);
    double mass1 = 0;
    for (double m : system.mass()) mass1 += m;
    r.energy_drift = (e1 - e0) / e0;
    r.mass_change = mass1 - mass0;
    const auto& sol = s.problem.solution;
    const auto& x = lat.state.x[0];
    r.q = sph::energy_error<1>(
        lat.state, rho, lat.mass, [&](std::size_t j) { return Vector<1>{sol.velocity(x[j], s.t_end)}; },
        [&](std::size_t j) { return sol.density(x[j], s.t_end); });
    r.particles = lat.mass.size();
    r.interactions = system.interactions();
    r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    return r;
}

// A printed rate, and the eps it was fitted on where a mark (a, b, c) says
// the thesis left some out (Table 6.2/6.4 captions); empty: all of them.
struct Printed {
    double kin = NAN, pot = NAN;
    std::string kin_mark, pot_mark;
    std::vector<double> kin_eps, pot_eps;
};

std::map<std::tuple<int, int, int>, Printed> printed_rates(const Scene& scene, const Settings& s) {
    std::map<std::tuple<int, int, int>, Printed> out;
    if (s.printed_file.empty()) return out;
    const std::filesystem::path file = std::filesystem::path(scene.origin()).parent_path() / s.printed_file;
    std::ifstream in(file);
    if (!in) scene.reject("franz.printed", "cannot read " + file.string());
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(in);
        const auto& table = doc.at("tables").at(s.printed_table);
        for (const auto& row : table.at("rates")) {
            Printed p{row.at("kin").get<double>(), row.at("pot").get<double>(), "", "", {}, {}};
            if (!row.at("kin_mark").is_null()) {
                p.kin_mark = row.at("kin_mark").get<std::string>();
                p.kin_eps = table.at("marks").at(p.kin_mark).get<std::vector<double>>();
            }
            if (!row.at("pot_mark").is_null()) {
                p.pot_mark = row.at("pot_mark").get<std::string>();
                p.pot_eps = table.at("marks").at(p.pot_mark).get<std::vector<double>>();
            }
            out[{row.at("k").get<int>(), row.at("l").get<int>(), row.at("m").get<int>()}] = p;
        }
    } catch (const nlohmann::json::exception& e) {
        scene.reject("franz.printed_table", file.string() + " table '" + s.printed_table + "': " + e.what());
    }
    return out;
}

// The rate fitted on the runs whose eps is in `only` (all runs if empty);
// NaN if fewer than two remain. Printed eps are rounded (0.0884 for
// 1/sqrt(128)), hence the relative match.
double rate_on(const std::vector<Run>& runs, const std::vector<double>& only, bool kinetic) {
    std::vector<double> e, q;
    for (const Run& r : runs) {
        const bool in = only.empty() || std::any_of(only.begin(), only.end(), [&](double x) {
                            return std::abs(x - r.eps) <= 1e-3 * r.eps;
                        });
        if (!in) continue;
        e.push_back(r.eps);
        q.push_back(kinetic ? r.q.kinetic : r.q.potential);
    }
    return e.size() < 2 ? NAN : sph::convergence_rate(e, q).rate;
}

std::string marked(double v, const std::string& mark) {
    if (std::isnan(v)) return "";
    std::ostringstream o;
    o.setf(std::ios::fixed);
    o.precision(2);
    o << v << (mark.empty() ? "" : " (" + mark + ")");
    return o.str();
}

std::string fixed(double v, int digits = 2) {
    std::ostringstream o;
    o.setf(std::ios::fixed);
    o.precision(digits);
    o << v;
    return o.str();
}

// One gnuplot line per kernel of the table `file` (blank-line separated blocks).
std::string per_kernel_plot(const std::string& file, const std::vector<std::string>& titles, const std::string& using_) {
    std::string s = "plot ";
    for (std::size_t i = 0; i < titles.size(); ++i) {
        if (i) s += ", ";
        s += "'" + file + "' index " + std::to_string(i) + " using " + using_ + " with linespoints title '" + titles[i] + "'";
    }
    return s + "\n";
}

// Per kernel drawn in the time-against-error plot: the CPU time of the
// cheapest run reaching each Q_kin target (which kernel gets there fastest).
Table cost_table(const Settings& s, const std::vector<std::vector<Run>>& runs, const std::vector<std::size_t>& chosen) {
    constexpr double targets[] = {1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
    Table t{{"kernel"}, {}};
    for (double q : targets) t.columns.push_back("Q_kin ≤ " + format(q, 1) + " [s]");
    for (const std::size_t i : chosen) {
        std::vector<std::string> row{s.kernels[i].spec};
        for (double q : targets) {
            double best = INFINITY;
            for (const Run& r : runs[i])
                if (r.q.kinetic <= q) best = std::min(best, r.cpu);
            row.push_back(std::isfinite(best) ? format(best, 3) : "–");
        }
        t.add(row);
    }
    return t;
}
}  // namespace

void run_franz(const Scene& scene, Output& out) {
    const Settings s = read(scene);
    const auto printed = printed_rates(scene, s);
    std::vector<Kernel> kernels;
    for (const KernelChoice& k : s.kernels) kernels.push_back(mollify::exact::kernel(k.spec, 1, s.precision));  // all checked before any run

    // Runs, cheapest first within each kernel (largest eps first).
    std::vector<std::vector<Run>> runs(s.kernels.size());
    Table errors{{"kernel", "k", "l", "m", "eps", "h", "particles", "steps", "dt", "Q_kin", "Q_pot", "energy_drift",
                  "mass_change", "wall_s", "cpu_s", "interactions"},
                 {}};
    const std::size_t total = s.kernels.size() * s.eps.size();
    std::size_t done = 0;
    for (std::size_t i = 0; i < s.kernels.size(); ++i)
        for (double e : s.eps) {
            progress("franz " + s.problem.name, done, total, s.kernels[i].spec + " eps=" + format(e, 4));
            const Run r = simulate(s, kernels[i], e, 1.0);
            runs[i].push_back(r);
            const KernelChoice& k = s.kernels[i];
            errors.add({k.spec, std::to_string(k.k), std::to_string(k.l), std::to_string(k.m), format(e, 6), format(r.h, 6),
                        std::to_string(r.particles), std::to_string(r.steps), format(r.dt, 6), format(r.q.kinetic, 6),
                        format(r.q.potential, 6), format(r.energy_drift, 3), format(r.mass_change, 3), format(r.wall, 4),
                        format(r.cpu, 4), std::to_string(r.interactions)});
            ++done;
        }
    progress("franz " + s.problem.name, total, total);
    out.csv("errors.csv", errors);

    // Time-step check: the smallest eps again with dt/2.
    Table dt_table{{"kernel", "eps", "dt", "Q_kin", "Q_kin(dt/2)", "relative change", "energy drift", "energy drift(dt/2)"}, {}};
    for (const std::size_t i : s.dt_check) {
        const std::string& spec = s.kernels[i].spec;
        progress("franz dt/2 check", 0, 1, spec);
        const Run& a = runs[i].back();
        const Run b = simulate(s, kernels[i], a.eps, 0.5);
        dt_table.add({spec, format(a.eps, 4), format(a.dt, 3), format(a.q.kinetic, 4), format(b.q.kinetic, 4),
                      format(std::abs(b.q.kinetic - a.q.kinetic) / a.q.kinetic, 2), format(a.energy_drift, 2),
                      format(b.energy_drift, 2)});
    }
    out.csv("dt_check.csv", dt_table);

    // Precision check: the smallest eps again with the kernel evaluated at
    // the other Precision. The SPH error dwarfs the kernel's rounding
    // (~1e-15 relative against Q >= 1e-12), so the change must be tiny.
    const Precision other = s.precision == Precision::fast ? Precision::accurate : Precision::fast;
    Table precision_table{{"kernel", "eps", "Q_kin (" + std::string(name(s.precision)) + ")",
                           "Q_kin (" + std::string(name(other)) + ")", "relative change kin", "relative change pot",
                           "cpu_s (" + std::string(name(s.precision)) + ")", "cpu_s (" + std::string(name(other)) + ")"},
                          {}};
    for (const std::size_t i : s.precision_check) {
        const std::string& spec = s.kernels[i].spec;
        progress("franz precision check", 0, 1, spec);
        const Run& a = runs[i].back();
        const Run b = simulate(s, kernels[i].with(other), a.eps, 1.0);
        precision_table.add({spec, format(a.eps, 4), format(a.q.kinetic, 6), format(b.q.kinetic, 6),
                             format(std::abs(b.q.kinetic - a.q.kinetic) / a.q.kinetic, 2),
                             format(std::abs(b.q.potential - a.q.potential) / a.q.potential, 2), format(a.cpu, 3),
                             format(b.cpu, 3)});
    }
    out.csv("precision_check.csv", precision_table);

    // Rates by least squares over all eps, beside the printed ones.
    // Ours over all eps, and over the thesis' own eps where it fitted on a
    // subset (marked rates); the difference is taken like for like.
    Table rates{{"kernel", "k", "l", "m", "a_ana", "rate_kin", "thesis_eps_kin", "printed_kin", "rate_pot", "thesis_eps_pot",
                 "printed_pot", "diff_kin", "diff_pot", "fit_residual_kin"},
                {}};
    std::size_t big = 0, compared = 0;
    for (std::size_t i = 0; i < s.kernels.size(); ++i) {
        std::vector<double> e, qk;
        for (const Run& r : runs[i]) {
            e.push_back(r.eps);
            qk.push_back(r.q.kinetic);
        }
        const KernelChoice& k = s.kernels[i];
        const auto p = printed.find({k.k, k.l, k.m});
        const Printed pr = p == printed.end() ? Printed{} : p->second;
        sph::Rate rk;
        double rp = NAN, sk = NAN, sp = NAN;
        try {  // an error Q of 0 (a t_end too short to move anything) or not finite leaves no rate to fit
            rk = sph::convergence_rate(e, qk);
            rp = rate_on(runs[i], {}, false);
            if (!pr.kin_eps.empty()) sk = rate_on(runs[i], pr.kin_eps, true);
            if (!pr.pot_eps.empty()) sp = rate_on(runs[i], pr.pot_eps, false);
        } catch (const Error& error) {
            scene.reject("franz.t_end", "the rates of " + k.spec + " over eps: " + error.what() + " (no error to fit a rate to at this t_end)");
        }
        const double dk = (std::isnan(sk) ? rk.rate : sk) - pr.kin, dp = (std::isnan(sp) ? rp : sp) - pr.pot;
        if (!std::isnan(pr.kin)) {
            ++compared;
            if (std::abs(dk) > 0.5 || std::abs(dp) > 0.5) ++big;
        }
        const std::string ana = k.k < 0 ? "" : k.l == 0 ? "-" : std::to_string(2 * std::min(k.k, k.m));
        auto opt = [](double v) { return std::isnan(v) ? std::string() : fixed(v); };
        rates.add({k.spec, k.k < 0 ? "" : std::to_string(k.k), k.k < 0 ? "" : std::to_string(k.l),
                   k.k < 0 ? "" : std::to_string(k.m), ana, fixed(rk.rate), opt(sk), marked(pr.kin, pr.kin_mark), fixed(rp),
                   opt(sp), marked(pr.pot, pr.pot_mark), opt(dk), opt(dp), fixed(rk.residual, 3)});
    }
    out.csv("rates.csv", rates);

    // Plots: Q_kin against eps (one line per kernel), CPU time against Q_kin
    // (the process's CPU time over all threads: comparable between kernels
    // even when other work shares the machine).
    std::string blocks, titles_csv;
    std::vector<std::string> titles;
    for (std::size_t i = 0; i < s.kernels.size(); ++i) {
        titles.push_back(s.kernels[i].label());
        for (const Run& r : runs[i])
            blocks += format(r.eps, 6) + "," + format(r.q.kinetic, 6) + "," + format(r.q.potential, 6) + "," +
                      format(r.cpu, 4) + "\n";
        blocks += "\n\n";
    }
    out.write("errors_by_kernel.dat", blocks);
    out.plot("q_kin.png",
             "set key noautotitle; set logscale xy; set format y '10^{%L}'; set xlabel 'ε'; set ylabel 'Q_{kin}(t_{end})'; set key outside right; set title 'Franz " +
                 s.problem.name + ": Q_{kin} against ε'\n" + per_kernel_plot("errors_by_kernel.dat", titles, "1:2"),
             1100, 700);
    std::vector<std::size_t> chosen = s.plot_kernels;
    if (chosen.empty())
        for (std::size_t i = 0; i < s.kernels.size(); ++i) chosen.push_back(i);
    std::string tv = "set key noautotitle; set logscale xy; set format x '10^{%L}'; set xlabel 'Q_{kin}(t_{end})'; set ylabel 'CPU time [s], all threads'; set key outside right; "
                     "set title 'Franz " + s.problem.name + ": CPU time against error (lower left is better)'\nplot ";
    bool first = true;
    for (const std::size_t i : chosen) {
        tv += std::string(first ? "" : ", ") + "'errors_by_kernel.dat' index " + std::to_string(i) +
              " using 2:4 with linespoints title '" + s.kernels[i].label() + "'";
        first = false;
    }
    out.plot("time_vs_error.png", tv + "\n", 1100, 700);

    // Summary.
    double wall = 0, cpu = 0;
    for (const auto& rs : runs)
        for (const Run& r : rs) wall += r.wall, cpu += r.cpu;
    std::string& md = out.summary();
    md += "# " + scene.title() + "\n\n";
    md += "SPH for the 1D Euler equations with p = ρ²/2 (Franz eqs. 3.4–3.6) on " +
          std::string(s.problem.domain.is_periodic() ? "the torus T = [0, 1)" : "R") + ", particle spacing h = " +
          format(s.problem.spacing_factor, 3) + "·ε², " + sph::name(s.integrator) + " with a constant step " +
          format(s.cfl, 3) + "·ε/(max √ρ + velocity spread), compared at t = " + format(s.t_end, 3) +
          " with the quasi-analytical Burgers solution (Thm. 6.2–6.3, Newton to 1e-14).\n\n";
    md += "ε range used for every rate: ";
    for (std::size_t j = 0; j < s.eps.size(); ++j) md += (j ? ", " : "") + format(s.eps[j], 4);
    md += " (least squares over all of them). " + std::to_string(s.kernels.size()) + " kernels, " +
          std::to_string(total) + " runs, " + format(wall, 3) + " s wall (" + format(cpu, 3) + " s CPU) of runs on this machine.\n\n";
    md += "## Rates a in Q ~ ε^a, ours beside the thesis' (" + (s.printed_table.empty() ? "none" : "Table " + s.printed_table) +
          ")\n\n`rate_*`: least squares over all our ε; `thesis_eps_*`: over the ε the thesis used for a marked rate "
          "(a, b, c: see its caption); `diff_*`: ours minus printed, like for like.\n\n" + rates.markdown() + "\n";
    if (compared)
        md += std::to_string(big) + " of " + std::to_string(compared) +
              " kernels differ from the printed rate by more than 0.5 (kin or pot).\n\n";
    md += "## Cost of an error level\n\n" + cost_table(s, runs, chosen).markdown() +
          "\nCPU time (all threads) of the cheapest measured run whose Q_kin(t_end) is at most the target; "
          "– where no run reached it. Figure: time_vs_error.png.\n\n";
    md += "## Time step: the smallest ε again with Δt/2\n\n" + dt_table.markdown() + "\n";
    md += "Kernels evaluated with Precision::" + std::string(name(s.precision)) + ".";
    if (!s.precision_check.empty())
        md += " The smallest ε again with Precision::" + std::string(name(other)) +
              " (the kernel's rounding against the SPH error):\n\n" + precision_table.markdown();
    md += "\n";
    md += "Mass is conserved exactly (constant particle masses; `mass_change` in errors.csv is 0); the energy "
          "(Franz 2.18 with 3.7) drift of each run is in errors.csv beside its Δt.\n\n";
    md += "Files: errors.csv (every run), rates.csv, dt_check.csv, precision_check.csv, q_kin.png, time_vs_error.png.\n\n";
    md += "Corrected printing errors of the thesis used here: the bump of §6.2.1 is centred at x = 1/2 "
          "(printed exp(1/(4x²−1)), singular inside its own support), and c0 has (4 − 2√3) where "
          "(4 − √3) is printed (which gives min f' = −4.23, not the stated −1, and a blow-up at t = 0.236).\n";
}

}  // namespace mollify::app
