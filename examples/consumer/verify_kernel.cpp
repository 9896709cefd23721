// Verify a kernel against the exact one (mollify::exact, <mollify/verify.hpp>):
// here mollify's own run-time Wendland C4 in 3D stands for "your kernel";
// prints the report and exits 0 only when it is within 1 ulp.
#include <mollify/kernel.hpp>
#include <mollify/verify.hpp>

#include <iostream>

int main() {
    const mollify::Kernel w = mollify::kernel("wendland:k=2", 3);
    mollify::verify::Options options;
    options.ulps = 1;
    const auto report = mollify::verify::verify([&](double r, double h) { return w.value(r, h); }, "wendland:k=2", 3,
                                                mollify::verify::Quantity::value, options);
    std::cout << report.to_string();
    return report.passed() ? 0 : 1;
}
