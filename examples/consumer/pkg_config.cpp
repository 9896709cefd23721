// Built without CMake, against the pkg-config file:
//
//   c++ -std=c++20 -O2 pkg_config.cpp $(pkg-config --cflags --libs mollify)
//
// The spec grammar's parser is compiled in libmollify, the kernel is a
// table header. Prints the spec as libmollify spells it and W(1/2) of
// wendland:k=2 in 3D (h = 1) to 17 significant digits.
#include "wendland_c4.hpp"

#include <mollify/spec.hpp>

#include <cstdio>

int main() {
    const mollify::Spec spec = mollify::parse_spec("wendland:k=2");
    std::printf("%s %.17g\n", mollify::spec_string(spec).c_str(), WendlandC4::value(0.5, 1.0));
}
