// One kernel as a type: the table is a template argument, evaluation is
// straight-line code. Prints W(1/2) of wendland:k=2 in 3D (h = 1) to 17
// significant digits (enough to read the double back exactly).
#include "wendland_c4.hpp"

#include <cstdio>

int main() { std::printf("%.17g\n", WendlandC4::value(0.5, 1.0)); }
