// The work of Precision::accurate against Precision::fast (issue 21, goal 3):
// one batch of W + grad W (StaticKernel::pairs_unchecked, 3D, 4096 points
// inside the support) evaluated `repetitions` times for one kernel and one
// precision. bench/precision_cost.sh runs it under callgrind and divides the
// instructions of `batches` by the evaluations: instructions per evaluation,
// a count that does not depend on the machine's load. Built for x86-64-v3
// (AVX2 + FMA), which valgrind executes (it has no AVX-512).
//
//   precision_cost wendland|combo fast|accurate
#include <mollify/kernel.hpp>
#include <mollify/tables/combo/m_3_base_wendland_k_2_D3.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>

#include <cstdio>
#include <random>
#include <string_view>
#include <vector>

namespace {

constexpr std::size_t points = 4096;
constexpr int repetitions = 100;

template <class W>
[[gnu::noinline]] void batches(const mollify::Points<3>& x, const mollify::Smoothing& s, double* w,
                               const mollify::PointsOut<3>& grad) {
    for (int i = 0; i < repetitions; ++i) W::pairs_unchecked(x, s, w, grad, points);
}

template <const mollify::table::Kernel& K>
double run(bool fast) {
    std::mt19937_64 random(1);
    std::uniform_real_distribution<double> component(-0.57, 0.57);  // |x| <= 0.99 h: inside
    std::vector<double> x0(points), x1(points), x2(points), w(points), g0(points), g1(points), g2(points);
    for (std::size_t i = 0; i < points; ++i) x0[i] = component(random), x1[i] = component(random), x2[i] = component(random);
    const mollify::Points<3> x{x0, x1, x2};
    const mollify::PointsOut<3> grad{g0, g1, g2};
    const mollify::Smoothing s(1.0, 3);
    if (fast) batches<mollify::StaticKernel<K, mollify::Precision::fast>>(x, s, w.data(), grad);
    else batches<mollify::StaticKernel<K, mollify::Precision::accurate>>(x, s, w.data(), grad);
    double sum = 0;
    for (std::size_t i = 0; i < points; ++i) sum += w[i] + g0[i];
    return sum;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string_view kernel = argc == 3 ? argv[1] : "", precision = argc == 3 ? argv[2] : "";
    if ((kernel != "wendland" && kernel != "combo") || (precision != "fast" && precision != "accurate")) {
        std::fprintf(stderr, "usage: precision_cost wendland|combo fast|accurate (got %d arguments)\n", argc - 1);
        return 2;
    }
    const bool fast = precision == "fast";
    const double sum = kernel == "wendland" ? run<mollify::tables::wendland_k_2_D3>(fast)
                                            : run<mollify::tables::combo_m_3_base_wendland_k_2_D3>(fast);
    std::printf("evaluations %zu checksum %.17g\n", points * repetitions, sum);
}
