// The translation unit of bench/compile_cost.sh: a short program summing a
// kernel over points. Compiled twice: with MOLLIFY_TABLE_HEADER (one
// StaticKernel, its table header) and without (the same program with a
// Gaussian in its place: the baseline without mollify).
#include <array>
#include <cmath>
#include <cstdio>
#include <span>

#ifdef MOLLIFY_TABLE_HEADER
#include <mollify/static_kernel.hpp>
#include MOLLIFY_TABLE_HEADER

using W = mollify::StaticKernel<mollify::tables::wendland_k_2_D3>;
double kernel(double r) { return W::value(r, 1.0); }
#else
double kernel(double r) { return std::exp(-r * r); }
#endif

int main(int argc, char**) {
    std::array<double, 64> r{};
    for (std::size_t i = 0; i < r.size(); ++i) r[i] = static_cast<double>(i + static_cast<std::size_t>(argc)) / 64.0;
    double sum = 0;
    for (double x : std::span<const double>(r)) sum += kernel(x);
    std::printf("%.17g\n", sum);
}
