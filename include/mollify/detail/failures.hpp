// The runtime's checks fail through these, compiled in libmollify
// (src/failures.cpp): a header every StaticKernel unit parses builds no
// message and so includes no <string> (issue 18's compile-cost goal). Each
// throws mollify::Error naming the bad value.
#pragma once

#include <cstddef>

namespace mollify::detail {

[[noreturn]] void fail_dimension(int dim);
[[noreturn]] void fail_smoothing_length(double h);
[[noreturn]] void fail_smoothing_range(double h, int dim, int power, int quantity);
[[noreturn]] void fail_radius(double r);
[[noreturn]] void fail_coordinate(double x, int component);
[[noreturn]] void fail_sizes(std::size_t in, std::size_t out, const char* what);
[[noreturn]] void fail_missing_quantity(const char* spec, int quantity, int dim);
[[noreturn]] void fail_no_potential(const char* spec, int dim);
[[noreturn]] void fail_smoothing_dimension(int smoothing_dim, const char* spec, int dim);
[[noreturn]] void fail_quantity(int quantity);

}  // namespace mollify::detail
