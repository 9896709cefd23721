// The run-time kernel lookup, compiled once (kernels.cpp): mollify::kernel()
// instantiates every emitted table, ~1 min of compile time per translation
// unit, so the app's experiments call this instead.
#pragma once

#include <mollify/dynamic_kernel.hpp>

#include <string_view>

namespace mollify::app {

Kernel find_kernel(std::string_view spec, int dim);

}  // namespace mollify::app
