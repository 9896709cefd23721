// The kernel of static_kernel.cpp and pkg_config.cpp as a type: Wendland's
// C4 (wendland:k=2) in 3D. A StaticKernel user includes the one table
// header of the kernel it uses.
#pragma once

#include <mollify/static_kernel.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>

using WendlandC4 = mollify::StaticKernel<mollify::tables::wendland_k_2_D3>;
