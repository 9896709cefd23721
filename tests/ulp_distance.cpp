// ulp_distance EXACT COMPUTED BOUND: |COMPUTED - EXACT| in units in the last
// place of EXACT, printed; exit status 0 within BOUND, 1 beyond it, 2 on bad
// input. ulp as in tools/accuracy (SLEEF's countULP): 2^(e-52) for
// 2^e <= |EXACT| < 2^(e+1). EXACT (a decimal of `mollify-gen value`) is read
// in MPFR at 256 bits and the difference taken there, so the distance is
// exact to far below any bound worth stating. tests/install_test.sh uses it
// on the installed package's values.
#include <mpfr.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace {

bool read(const char* text, double& out) {
    char* end = nullptr;
    out = std::strtod(text, &end);
    return end != text && *end == '\0' && std::isfinite(out);
}

}  // namespace

int main(int argc, char** argv) {
    mpfr_t exact, d;
    mpfr_inits2(256, exact, d, static_cast<mpfr_ptr>(nullptr));
    double computed = 0, bound = 0;
    if (argc != 4 || mpfr_set_str(exact, argv[1], 10, MPFR_RNDN) != 0 || !mpfr_regular_p(exact) ||
        !read(argv[2], computed) || !read(argv[3], bound)) {
        std::fprintf(stderr, "usage: ulp_distance EXACT COMPUTED BOUND (finite decimals, EXACT not 0): got '%s'\n",
                     argc > 1 ? argv[1] : "");
        return 2;
    }
    // exact = m 2^E with 1/2 <= |m| < 1, so 2^(E-1) <= |exact| < 2^E: ulp = 2^(E-53).
    const long e = mpfr_get_exp(exact);
    mpfr_set_d(d, computed, MPFR_RNDN);  // exact: a double in 256 bits
    mpfr_sub(d, d, exact, MPFR_RNDN);
    mpfr_mul_2si(d, d, 53 - e, MPFR_RNDN);
    const double distance = std::fabs(mpfr_get_d(d, MPFR_RNDN));
    mpfr_clears(exact, d, static_cast<mpfr_ptr>(nullptr));
    std::printf("%s is %.4f ulp from %s (bound %s)\n", argv[2], distance, argv[1], argv[3]);
    return distance <= bound ? 0 : 1;
}
