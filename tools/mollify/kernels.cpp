// The one translation unit of the app that instantiates every emitted table
// (mollify::kernel, ~1 min to compile).
#include "kernels.hpp"

namespace mollify::app {

Kernel find_kernel(std::string_view spec, int dim) { return kernel(spec, dim); }

}  // namespace mollify::app
