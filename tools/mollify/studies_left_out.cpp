// The studies' experiments in a mollify command configured with
// -DMOLLIFY_STUDIES=OFF (CMakeLists.txt: CI's sanitizer build): the registry
// still names them (scenes parse and list as everywhere), and running one
// is an error saying how to get it, before anything is written.
#include "experiment.hpp"

namespace mollify::app {

namespace {

[[noreturn]] void left_out(const Scene& scene) {
    scene.reject("scene.experiment",
                 "not compiled into this mollify (configured with -DMOLLIFY_STUDIES=OFF; build with -DMOLLIFY_STUDIES=ON to run it)");
}

}  // namespace

void run_franz(const Scene& scene, Output&) { left_out(scene); }
void run_belley(const Scene& scene, Output&) { left_out(scene); }

}  // namespace mollify::app
