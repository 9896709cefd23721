// An exact value from the generator's library: W(1/2) of wendland:k=2 in 3D
// (a rational multiple of 1/pi), correctly rounded to 40 significant digits,
// as `mollify-gen value wendland:k=2 --dim 3 --r 1/2` prints it.
#include <mollify/exact/closed_form.hpp>
#include <mollify/exact/kernel.hpp>
#include <mollify/exact/number.hpp>
#include <mollify/exact/quantities.hpp>
#include <mollify/exact/rounding.hpp>
#include <mollify/exact/spec.hpp>

#include <iostream>

int main() {
    namespace gen = mollify::gen;
    const auto kernel = gen::make_kernel(gen::parse_spec("wendland:k=2"), 3);
    const auto quantities = gen::derive_quantities(kernel);
    const gen::Q r = gen::parse_rational("1/2", "r");
    std::cout << gen::decimal(gen::value_at(gen::quantity(kernel, quantities, "value").form_at(r), r), 40) << "\n";
}
