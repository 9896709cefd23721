// One part of the run-time kernel registry compiled once (CMake target
// mollify::registry): the batch functions of every MOLLIFY_REGISTRY_PARTS-th
// emitted table from MOLLIFY_REGISTRY_PART on, so that programs looking
// kernels up by spec string (mollify::kernel) do not each spend minutes
// compiling them, and the parts compile in parallel.
#define MOLLIFY_DEFINE_REGISTRY
#include <mollify/dynamic_kernel.hpp>

#if !defined(MOLLIFY_PRECOMPILED_REGISTRY) || !defined(MOLLIFY_REGISTRY_PART) || !defined(MOLLIFY_REGISTRY_PARTS)
#error "src/registry.cpp is built by the CMake target mollify::registry, once per MOLLIFY_REGISTRY_PART"
#endif

namespace mollify::detail {
template std::span<const KernelOps> registry_slice<MOLLIFY_REGISTRY_PART, MOLLIFY_REGISTRY_PARTS>();
}  // namespace mollify::detail
