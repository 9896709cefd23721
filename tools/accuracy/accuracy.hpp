// Measuring the double-precision runtime against the exact values: the one
// place that defines the exact reference, the ulp error (SLEEF's countULP),
// the hard-case points and the naive evaluation forms compared against.
// Used by tests/accuracy_test.cpp (bounds asserted), tools/stability_report
// (the report) and bench/kernel_bench.cpp (speed against error).
//
// Links the exact generator core (GMP/MPFR); the runtime itself never does.
// The reference itself lives in the exact library (generator/verify/
// reference.hpp), where the verification of anyone's kernel uses it too.
#pragma once

#include "verify/reference.hpp"

#include <mollify/kernel.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mollify::accuracy {

// Points (r, h) where kernels are hard to evaluate, kept as named data
// (CORE-MATH style): 1 - r/h from 1e-1 down to 1e-15, r/h from 1e-1 down to
// 1e-300 and exactly 0, h from 1e-8 to 1e8, plus seeded uniform points.
struct Point {
    double r, h;
    const char* why;  // "edge", "origin", "zero", "h-sweep", "uniform", "far" ...
};
std::vector<Point> hard_points(int uniform_count, std::uint64_t seed);

// Statistics of one (kernel, quantity, evaluation form) over a point set.
struct Stats {
    double max_ulp = 0, rms_ulp = 0;       // over points with |exact| >= 1e-10 max
    double max_scaled = 0;                  // over points with |exact| <  1e-10 max, in ulps of the max
    Point worst{0, 0, ""};                  // argument of max_ulp
    long points = 0, tiny_points = 0;
};

}  // namespace mollify::accuracy
