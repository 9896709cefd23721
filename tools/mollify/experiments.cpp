// The registry of experiments a scene can name.
#include "experiment.hpp"

#include <array>

namespace mollify::app {

namespace {

constexpr std::array registry = {
    Experiment{"franz", "Franz's convergence study: weakly compressible SPH against the Burgers reference, rates over epsilon",
               run_franz},
    Experiment{"belley", "Belley's estimation study: SPH, trapezoidal and Simpson sums of f, f', f'' on random points",
               run_belley},
    Experiment{"sph-periodic", "SPH on a periodic box in 2D, with a density/velocity picture", run_sph_periodic},
    Experiment{"poisson-free", "free-space particle Poisson solvers (direct, treecode) against exact values: time against error",
               run_poisson_free},
    Experiment{"poisson-periodic", "periodic FFT Poisson solver (FD and pseudospectral symbols, charge assignment), 1D BVP",
               run_poisson_periodic},
    Experiment{"vortex-sheet", "2D vortex blobs: periodic vortex sheet roll-up, algebraic and compact mollifiers",
               run_vortex_sheet},
    Experiment{"kernel-values", "any kernel of the grammar tabulated at given radii (generated exactly where not compiled in)",
               run_kernel_values},
};

}  // namespace

std::span<const Experiment> experiments() { return registry; }

const Experiment& find_experiment(const Scene& scene) {
    const std::string name = scene.experiment();
    for (const Experiment& e : registry)
        if (e.name == name) return e;
    std::string known;
    for (const Experiment& e : registry) known += (known.empty() ? "" : ", ") + std::string(e.name);
    scene.reject("scene.experiment", "unknown experiment (known: " + known + ")");
}

}  // namespace mollify::app
