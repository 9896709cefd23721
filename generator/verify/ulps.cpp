#include "verify/ulps.hpp"

#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mollify::verify::detail {

double ulps(double y, const accuracy::Real& x, double floor, bool single) {
    mpfr_srcptr c = x.backend().data();
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (std::isnan(y) || mpfr_nan_p(c)) return inf;
    const double xd = single ? static_cast<double>(mpfr_get_flt(c, MPFR_RNDN)) : mpfr_get_d(c, MPFR_RNDN);
    if (std::isinf(y) || std::isinf(xd)) return y == xd ? 0 : inf;
    const int precision = single ? 24 : 53, min_exponent = single ? -149 : -1074;
    mpfr_t d;
    mpfr_init2(d, std::max<long>(mpfr_get_prec(c), 64) + 1200);
    // The scale: max(|x|, floor); its exponent e with 2^(e-1) <= scale < 2^e.
    long e = mpfr_zero_p(c) ? std::numeric_limits<long>::min() / 2 : mpfr_get_exp(c);
    if (floor > 0) {
        int fe = 0;
        std::frexp(floor, &fe);
        if (mpfr_zero_p(c) || mpfr_cmpabs(c, (mpfr_set_d(d, floor, MPFR_RNDN), d)) < 0) e = fe;
    }
    const long ulp_exponent = std::max<long>(e - precision, min_exponent);
    mpfr_set_d(d, y, MPFR_RNDN);
    mpfr_sub(d, d, c, MPFR_RNDN);
    mpfr_mul_2si(d, d, -ulp_exponent, MPFR_RNDN);
    const double out = std::abs(mpfr_get_d(d, MPFR_RNDN));
    mpfr_clear(d);
    return out;
}

}  // namespace mollify::verify::detail
