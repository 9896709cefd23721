// Out of line so that the hot headers (static_kernel.hpp, smoothing.hpp)
// build no strings: see include/mollify/detail/failures.hpp.
#include <mollify/detail/failures.hpp>
#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>
#include <mollify/table.hpp>

#include <string>

namespace mollify::detail {

void fail_dimension(int dim) { fail("dimension " + std::to_string(dim) + " is not 1, 2 or 3"); }

void fail_smoothing_length(double h) {
    fail("smoothing length h = " + show(h) + " is not a positive finite number");
}

void fail_smoothing_range(double h, int dim, int power, int quantity) {
    fail("smoothing length h = " + show(h) + " is out of range in D = " + std::to_string(dim) + ": h^" +
         std::to_string(power) + " (for " + table::quantity_names[quantity] + ") is outside [2^-900, 2^900]");
}

void fail_radius(double r) { fail("radius r = " + show(r) + " is not a finite number >= 0"); }

void fail_coordinate(double x, int component) {
    fail("coordinate x[" + std::to_string(component) + "] = " + show(x) + " is not finite");
}

void fail_sizes(std::size_t in, std::size_t out, const char* what) {
    fail(std::string(what) + ": " + std::to_string(in) + " inputs but room for " + std::to_string(out) + " outputs");
}

void fail_missing_quantity(const char* spec, int quantity, int dim) {
    fail(std::string("kernel ") + spec + " has no " + table::quantity_names[quantity] + " in D = " + std::to_string(dim));
}

void fail_no_potential(const char* spec, int dim) {
    fail(std::string("kernel ") + spec + " has no potential in D = " + std::to_string(dim));
}

void fail_smoothing_dimension(int smoothing_dim, const char* spec, int dim) {
    fail("a smoothing length made for D = " + std::to_string(smoothing_dim) + " used with " + spec + " in D = " +
         std::to_string(dim));
}

void fail_quantity(int quantity) {
    fail("quantity number " + std::to_string(quantity) + " is not one of the " + std::to_string(table::quantity_count) +
         " in the tables");
}

}  // namespace mollify::detail
