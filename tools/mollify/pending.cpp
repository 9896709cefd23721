// Stubs for the experiments whose source file does not exist yet: CMake
// defines MOLLIFY_HAVE_FRANZ etc. for each of franz.cpp, belley.cpp,
// sph_periodic.cpp, poisson_free.cpp, poisson_periodic.cpp, vortex_sheet.cpp it compiles into the app, so the build links at every
// stage. Compiled without any of them, this is mollify_app_stubs (tests).
#include "experiment.hpp"

#include <mollify/error.hpp>

namespace mollify::app {

#ifndef MOLLIFY_HAVE_FRANZ
void run_franz(const Scene&, Output&) { fail("experiment franz is not built yet"); }
#endif
#ifndef MOLLIFY_HAVE_BELLEY
void run_belley(const Scene&, Output&) { fail("experiment belley is not built yet"); }
#endif
#ifndef MOLLIFY_HAVE_SPH_PERIODIC
void run_sph_periodic(const Scene&, Output&) { fail("experiment sph-periodic is not built yet"); }
#endif
#ifndef MOLLIFY_HAVE_POISSON_FREE
void run_poisson_free(const Scene&, Output&) { fail("experiment poisson-free is not built yet"); }
#endif
#ifndef MOLLIFY_HAVE_POISSON_PERIODIC
void run_poisson_periodic(const Scene&, Output&) { fail("experiment poisson-periodic is not built yet"); }
#endif
#ifndef MOLLIFY_HAVE_VORTEX_SHEET
void run_vortex_sheet(const Scene&, Output&) { fail("experiment vortex-sheet is not built yet"); }
#endif

}  // namespace mollify::app
