// The catalogue's tables as data, in their own translation unit: the only
// unit of libmollify that parses the emitted headers.
#include "catalogue.hpp"

#include <mollify/tables/catalogue.hpp>

namespace mollify::detail {

std::span<const table::Kernel* const> catalogue() { return tables::all_kernels; }

}  // namespace mollify::detail
