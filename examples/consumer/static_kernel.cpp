// One kernel as a type: the table is a template argument, evaluation is
// straight-line code. Prints W(1/2) of wendland:k=2 in 3D (h = 1) to 17
// significant digits (enough to read the double back exactly).
#include <mollify/static_kernel.hpp>
#include <mollify/tables/wendland.hpp>

#include <cstdio>

int main() {
    using W = mollify::StaticKernel<mollify::tables::wendland_k_2_D3>;
    std::printf("%.17g\n", W::value(0.5, 1.0));
}
