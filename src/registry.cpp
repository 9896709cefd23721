// The run-time kernel registry compiled once (CMake target mollify::registry):
// every emitted table's batch functions, so that programs looking kernels up
// by spec string (mollify::kernel) do not each spend a minute compiling them.
#define MOLLIFY_DEFINE_REGISTRY
#include <mollify/dynamic_kernel.hpp>

#ifndef MOLLIFY_PRECOMPILED_REGISTRY
#error "src/registry.cpp is built with MOLLIFY_PRECOMPILED_REGISTRY (CMake target mollify::registry)"
#endif

namespace mollify::detail {
template const KernelOps* find_ops<void>(std::string_view, int, bool&);
}  // namespace mollify::detail
