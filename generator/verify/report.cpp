#include <mollify/verify.hpp>

#include <cmath>
#include <cstdio>

namespace mollify::verify {

bool Report::passed() const { return points > 0 && max_ulps <= bound; }

bool Report::complete() const { return hard_points_compared == hard_points; }

namespace {

std::string format(const char* f, double x) {
    char b[64];
    std::snprintf(b, sizeof b, f, x);
    return b;
}

}  // namespace

std::string Report::to_string() const {
    const std::string unit = float_ulps ? " float ulps" : " ulps";
    std::string s = "verify " + spec + " D=" + std::to_string(dim) + " " + std::string(name(quantity)) + " (convention " +
                    convention + "): " + std::to_string(points) + " points\n";
    const std::string hard = std::to_string(hard_points_compared) + " of " + std::to_string(hard_points);
    s += "  max " + format("%.3g", max_ulps) + unit + ", RMS " + format("%.3g", rms_ulps) + unit + ", bound " +
         format("%.3g", bound) + unit + ": " + (passed() ? "PASSED" : "FAILED") +
         (passed() && !complete() ? " on the given samples only (" + hard + " hard points)" : "") + "\n";
    s += "  hard points: " + hard + " among the samples" +
         (complete() ? "" : " (the verification's samples hold them all; the others were not checked)") + "\n";
    if (!worst.empty()) {
        s += "  worst:                       r                       h                     got                   exact        ulps\n";
        for (const Point& p : worst)
            s += "        " + format("%24.17g", p.r) + format("%24.17g", p.h) + format("%24.17g", p.got) +
                 format("%24.17g", p.exact) + format("%12.3g", p.ulps) + "\n";
    }
    if (diagnosis) s += "  diagnosis (" + std::string(name(diagnosis->kind)) + "): " + diagnosis->text + "\n";
    return s;
}

}  // namespace mollify::verify
