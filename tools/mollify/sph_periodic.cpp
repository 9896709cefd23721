// A periodic SPH case in 2D or 3D with a visible result: Franz's scheme
// (3.24)-(3.26) on the box [0, 1)^D, particles on the lattice, a Gaussian
// density bump at rest in the middle of a uniform background. The bump
// spreads as a pressure wave (p = rho^2/2, sound speed sqrt(rho)) that
// crosses the periodic boundaries and interferes with its images; the
// density at the particles is drawn at the requested times (in 3D: the
// particles of the slab around z = 1/2). Energy (Franz 2.18/3.7) and
// momentum are recorded at every snapshot.
#include "experiment.hpp"
#include <mollify/exact.hpp>
#include <mollify/kernel.hpp>

#include <mollify/sph.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace mollify::app {
namespace {

template <int D>
struct Setup {
    sph::State<D> state;
    std::vector<double> mass;
};

template <int D>
Setup<D> lattice(long n, double amplitude, double width, double velocity) {
    Setup<D> s;
    const double h = 1.0 / static_cast<double>(n);
    std::array<long, D> idx{};
    for (;;) {
        double r2 = 0;
        std::array<double, D> x;
        for (int c = 0; c < D; ++c) {
            x[c] = (static_cast<double>(idx[c]) + 0.5) * h;
            r2 += (x[c] - 0.5) * (x[c] - 0.5);
        }
        const double rho0 = 1 + amplitude * std::exp(-r2 / (width * width));
        for (int c = 0; c < D; ++c) {
            s.state.x[c].push_back(x[c]);
            // A uniform drift along x: Galilean invariance made visible (the
            // wave pattern moves, its shape does not change).
            s.state.u[c].push_back(c == 0 ? velocity : 0.0);
        }
        s.mass.push_back(std::pow(h, D) * rho0);
        int c = 0;
        while (c < D && ++idx[c] == n) idx[c++] = 0;
        if (c == D) break;
    }
    return s;
}

template <int D>
void run(const Scene& scene, Output& out) {
    const std::string spec = scene.string("sph_periodic.kernel");
    const long n = scene.integer("sph_periodic.particles_per_side");
    if (n < 4 || n > (D == 2 ? 2000 : 150))
        scene.reject("sph_periodic.particles_per_side", std::to_string(n) + " is outside 4.." + (D == 2 ? "2000" : "150"));
    const double ratio = scene.positive("sph_periodic.eps_over_h");
    const double eps = ratio / static_cast<double>(n);
    if (ratio < 1.5) scene.reject("sph_periodic.eps_over_h", format(ratio, 4) + " is too small: eps would not reach the neighbouring particles (needs >= 1.5 lattice spacings)");
    if (!(2 * eps < 1)) scene.reject("sph_periodic.eps_over_h", "eps = " + format(eps, 4) + " is not below half the box");
    const double amplitude = scene.number("sph_periodic.amplitude", 0.5);
    const double width = scene.positive("sph_periodic.width");
    const double drift = scene.number("sph_periodic.drift", 0.0);
    if (!(amplitude > -1)) scene.reject("sph_periodic.amplitude", format(amplitude, 4) + " would make the density non-positive");
    std::vector<double> times = scene.numbers("sph_periodic.snapshots");
    std::sort(times.begin(), times.end());
    if (times.empty() || !(times.front() >= 0)) scene.reject("sph_periodic.snapshots", "needs times >= 0");
    const double cfl = scene.number("sph_periodic.cfl", 0.1);
    if (!(cfl > 0 && cfl <= 1)) scene.reject("sph_periodic.cfl", format(cfl, 6) + " is not in (0, 1]");
    const sph::Integrator method = checked(scene, "sph_periodic.integrator", [&] { return sph::integrator(scene.string("sph_periodic.integrator", "leapfrog")); });

    const Precision precision = scene_precision(scene, "sph_periodic.precision");
    const Kernel kernel = mollify::exact::kernel(spec, D, precision);
    Setup<D> s = lattice<D>(n, amplitude, width, drift);
    const auto domain = sph::Domain<D>::periodic(1.0);
    sph::BarotropicEuler<D, Kernel> system(kernel, eps, domain, s.mass);
    sph::TimeStepper<D, decltype(system)> stepper(system, method);
    std::vector<double> rho;
    system.density(s.state.x, rho);
    const double dt_max = sph::cfl_step<D>(s.state, rho, eps, cfl);
    // At the first step's size: a huge amplitude (a sound speed to match) or
    // a far snapshot would otherwise run for ever.
    check_step_count(scene, "sph_periodic.snapshots", times.back() / dt_max,
                     "t = " + format(times.back()) + " in steps dt <= " + format(dt_max, 3) + " (amplitude " +
                         format(amplitude, 3) + ", CFL " + format(cfl, 2) + ")");

    Table history{{"t", "kinetic", "potential", "energy", "relative_drift", "momentum_x", "min_rho", "max_rho"}, {}};
    const auto start = std::chrono::steady_clock::now();
    double t = 0, e0 = 0;
    std::size_t steps = 0;
    std::string plots;
    for (std::size_t k = 0; k < times.size(); ++k) {
        while (t < times[k]) {  // steps of at most dt_max, landing on the snapshot time
            const double left = times[k] - t;
            const double dt = left / std::ceil(left / dt_max);
            stepper.step(s.state, dt);
            t += dt;
            ++steps;
            if (std::abs(times[k] - t) < 1e-12) t = times[k];
            progress("sph-periodic", k, times.size(), "t = " + format(t, 3));
        }
        system.density(s.state.x, rho);
        const double ek = system.kinetic_energy(s.state.u), ep = system.potential_energy(rho);
        if (k == 0) e0 = ek + ep;
        double px = 0;
        for (std::size_t j = 0; j < s.mass.size(); ++j) px += s.mass[j] * s.state.u[0][j];
        const auto [lo, hi] = std::minmax_element(rho.begin(), rho.end());
        history.add({format(t, 6), format(ek, 10), format(ep, 10), format(ek + ep, 12), format((ek + ep - e0) / e0, 3),
                     format(px, 6), format(*lo, 6), format(*hi, 6)});
        Table snap{{"x", "y", "rho", "speed"}, {}};
        for (std::size_t j = 0; j < s.mass.size(); ++j) {
            if (D == 3 && std::abs(s.state.x[D - 1][j] - 0.5) > 0.5 / static_cast<double>(n)) continue;
            double v2 = 0;
            for (int c = 0; c < D; ++c) v2 += s.state.u[c][j] * s.state.u[c][j];
            snap.add({format(s.state.x[0][j], 6), format(s.state.x[1][j], 6), format(rho[j], 6), format(std::sqrt(v2), 4)});
        }
        const std::string name = "snapshot_" + std::to_string(k);
        out.csv(name + ".csv", snap);
        out.plot(name + ".png",
                 "set size square; set xrange [0:1]; set yrange [0:1]; set palette rgb 33,13,10; "
                 "set cblabel 'density'; set title 'SPH density, t = " + format(t, 3) + " (" + spec + ", " +
                     std::to_string(s.mass.size()) + " particles)'\n"
                     "plot '" + name + ".csv' using 1:2:3 with points pt 7 ps 0.35 palette notitle\n",
                 700, 640);
        plots += "![t = " + format(t, 3) + "](" + name + ".png)\n";
    }
    progress("sph-periodic", times.size(), times.size());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.csv("history.csv", history);

    std::string& md = out.summary();
    md += "# " + scene.title() + "\n\n";
    md += "Franz's SPH scheme for p = ρ²/2 on the periodic box [0, 1)^" + std::to_string(D) + " with " + spec + " (Precision::" + std::string(name(precision)) + "), " +
          std::to_string(s.mass.size()) + " particles (" + std::to_string(n) + " per side), ε = " + format(ratio, 3) +
          " lattice spacings, " + sph::name(method) + ", Δt ≤ " + format(dt_max, 3) + " (CFL " + format(cfl, 2) + "), " +
          std::to_string(steps) + " steps, " + format(static_cast<double>(system.interactions()) / wall, 3) +
          " particle–neighbour interactions per second, " + format(wall, 3) + " s.\n\n";
    md += "Initial density 1 + " + format(amplitude, 3) + "·exp(−|x − c|²/" + format(width, 3) +
          "²) at rest (plus a drift " + format(drift, 3) + " along x): the bump spreads as a pressure wave through the periodic boundaries.\n\n";
    md += history.markdown() + "\n" + plots;
}

}  // namespace

void run_sph_periodic(const Scene& scene, Output& out) {
    scene.only("sph_periodic", {"dim", "kernel", "particles_per_side", "eps_over_h", "amplitude", "width", "drift",
                                "snapshots", "cfl", "integrator", "precision"});
    const long dim = scene.integer("sph_periodic.dim", 2);
    if (dim == 2)
        run<2>(scene, out);
    else if (dim == 3)
        run<3>(scene, out);
    else
        scene.reject("sph_periodic.dim", std::to_string(dim) + " is not 2 or 3");
}

}  // namespace mollify::app
