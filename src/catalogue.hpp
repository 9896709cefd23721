// The kernels compiled into libmollify, in catalogue order: the one place
// the run-time form gets them from (today the emitted constexpr array of
// generated/mollify/tables/catalogue.hpp; later its compiled source).
#pragma once

#include <mollify/table.hpp>

#include <span>

namespace mollify::detail {

std::span<const table::Kernel* const> catalogue();

}  // namespace mollify::detail
