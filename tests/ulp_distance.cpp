// ulp_distance EXACT COMPUTED BOUND: |COMPUTED - EXACT| in units in the last
// place of a double at EXACT (the spacing of doubles in EXACT's binade),
// printed; exit status 0 within BOUND, 1 beyond it, 2 on bad input.
// EXACT is read in long double (64-bit significand): its own rounding is
// 2^-11 ulp of a double at most, far below any bound worth stating.
// tests/install_test.sh uses it on the installed package's values.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

bool read(const char* text, long double& out) {
    char* end = nullptr;
    out = std::strtold(text, &end);
    return end != text && *end == '\0' && std::isfinite(out);
}

}  // namespace

int main(int argc, char** argv) {
    long double exact = 0, computed = 0, bound = 0;
    if (argc != 4 || !read(argv[1], exact) || !read(argv[2], computed) || !read(argv[3], bound) || exact == 0) {
        std::fprintf(stderr, "usage: ulp_distance EXACT COMPUTED BOUND (finite decimals, EXACT not 0); got %d arguments\n",
                     argc - 1);
        return 2;
    }
    // COMPUTED is a double printed with 17 digits: read back, it is that double.
    const long double x = static_cast<double>(computed);
    const long double ulp = std::ldexp(1.0L, std::ilogb(exact) - 52);
    const long double distance = std::fabs(x - exact) / ulp;
    std::printf("%s is %.4Lf ulp from %s (bound %s)\n", argv[2], distance, argv[1], argv[3]);
    return distance <= bound ? 0 : 1;
}
