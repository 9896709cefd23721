// The hard-case points, kept as named data (as CORE-MATH keeps its worst
// cases): where a kernel evaluation can lose digits, and why.
#include "accuracy.hpp"

#include <cmath>
#include <random>

namespace mollify::accuracy {

namespace {

// Smoothing lengths of the sweeps: powers of ten (not powers of two, so
// r/h and (h - r)/h round) and a few exact binary ones.
constexpr double sweep_h[] = {1e-8, 1e-6, 1e-4, 1e-2, 0.1, 0.5, 1, 2, 3, 10, 1e2, 1e4, 1e6, 1e8};

// r/h of the h-sweep: inside, at the interior breakpoints of the cubic
// spline and the combinations (1/3, 1/2, 2/3), at and beyond the edge.
constexpr double sweep_q[] = {0, 1e-3, 0.1, 0.25, 1.0 / 3, 0.5, 2.0 / 3, 0.75, 0.9, 0.99, 0.999999, 1, 1.5};

void edge_points(std::vector<Point>& out) {
    // 1 - r/h = 10^-k, k = 1, 1.5, ..., 15: where (1 - q)^n is the whole value.
    for (int k2 = 2; k2 <= 30; ++k2) {
        const double d = std::pow(10.0, -0.5 * k2);
        out.push_back({1 - d, 1, "edge"});  // h = 1: r the double nearest 1 - 10^-k
        for (double h : {1e-8, 3.0, 1e8}) out.push_back({h * (1 - d), h, "edge"});
    }
    // The last doubles inside, on and just outside the (closed) support.
    for (double h : sweep_h) {
        out.push_back({h, h, "edge"});
        out.push_back({std::nextafter(h, 0.0), h, "edge"});
        out.push_back({std::nextafter(std::nextafter(h, 0.0), 0.0), h, "edge"});
        out.push_back({std::nextafter(h, 2 * h), h, "outside"});
    }
}

void origin_points(std::vector<Point>& out) {
    // r/h = 10^-k, k = 1 .. 300 (every decade; half decades to 1e-20): where
    // singular terms of the closed forms cancel (S/r - 1/r, log r).
    for (int k = 1; k <= 300; ++k) out.push_back({std::pow(10.0, -k), 1, "origin"});
    for (int k2 = 3; k2 <= 39; k2 += 2) out.push_back({std::pow(10.0, -0.5 * k2), 1, "origin"});
    for (double h : {1e-8, 1e8})
        for (int k = 1; k <= 280; k += 7) out.push_back({h * std::pow(10.0, -k), h, "origin"});
    for (double h : sweep_h) out.push_back({0, h, "zero"});
}

void sweep_points(std::vector<Point>& out) {
    for (double h : sweep_h)
        for (double q : sweep_q) out.push_back({q * h, h, "h-sweep"});
    // Interior breakpoints and their neighbouring doubles (h = 1).
    for (double b : {1.0 / 3, 0.5, 2.0 / 3})
        for (double r : {std::nextafter(b, 0.0), b, std::nextafter(b, 1.0)}) out.push_back({r, 1, "break"});
}

void far_points(std::vector<Point>& out) {
    // Potentials outside are the Green's function: r/h up to 1e6.
    for (double h : {1e-8, 1e-2, 1.0, 3.0, 1e2, 1e8})
        for (double q : {1.0 + 1e-9, 1.01, 1.2, 2.0, 10.0, 1e2, 1e3, 1e4, 1e5, 1e6}) out.push_back({q * h, h, "far"});
}

// r/h uniform in [0, 1.2]; h = 1 for a third, log-uniform in [1e-8, 1e8]
// otherwise (std::mt19937_64 is specified exactly; the distributions are
// written out, since std's are not portable).
void uniform_points(std::vector<Point>& out, int count, std::uint64_t seed) {
    std::mt19937_64 gen(seed);
    auto unit = [&] { return static_cast<double>(gen() >> 11) * 0x1p-53; };
    for (int i = 0; i < count; ++i) {
        const double q = 1.2 * unit();
        const double h = i % 3 == 0 ? 1.0 : std::pow(10.0, -8 + 16 * unit());
        out.push_back({q * h, h, "uniform"});
    }
}

}  // namespace

std::vector<Point> hard_points(int uniform_count, std::uint64_t seed) {
    std::vector<Point> out;
    edge_points(out);
    origin_points(out);
    sweep_points(out);
    far_points(out);
    uniform_points(out, uniform_count, seed);
    return out;
}

}  // namespace mollify::accuracy
