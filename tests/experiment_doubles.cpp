// Test doubles for the experiments' entry points (tools/mollify/experiment.hpp),
// linked only into scene_test: it tests the app library (scenes, output,
// the registry of experiments) without linking the experiments themselves
// and the run-time kernels they use. Running one is an Error, so a test that
// reaches an experiment by mistake fails loudly.
#include "experiment.hpp"

#include <mollify/error.hpp>

#include <string>

namespace mollify::app {

namespace {

[[noreturn]] void not_linked(const std::string& name) {
    fail("test double: experiment " + name + " is not linked into scene_test");
}

}  // namespace

void run_franz(const Scene&, Output&) { not_linked("franz"); }
void run_belley(const Scene&, Output&) { not_linked("belley"); }
void run_sph_periodic(const Scene&, Output&) { not_linked("sph-periodic"); }
void run_poisson_free(const Scene&, Output&) { not_linked("poisson-free"); }
void run_poisson_periodic(const Scene&, Output&) { not_linked("poisson-periodic"); }
void run_vortex_sheet(const Scene&, Output&) { not_linked("vortex-sheet"); }
void run_kernel_values(const Scene&, Output&) { not_linked("kernel-values"); }

}  // namespace mollify::app
