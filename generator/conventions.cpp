#include "conventions.hpp"

#include "error.hpp"
#include "potential.hpp"
#include "rounding.hpp"

#include <cmath>
#include <limits>

namespace mollify::gen {

namespace {

using table::QuantityId;

const std::vector<QuantityId> all_quantities = {
    QuantityId::value,     QuantityId::dr,         QuantityId::d2r,
    QuantityId::laplacian, QuantityId::grad_over_r, QuantityId::hess_radial,
    QuantityId::potential, QuantityId::dpotential, QuantityId::dpotential_over_r,
    QuantityId::potential_hess_radial};

// The coefficient c of c / r, mollify's 3D Green's function: G(1).
Exact mollify_green_3d() { return value_at(green_function(3), Q(1)); }

// mollify's own convention (README, "Conventions"): support 1, W_h = h^-D W(r/h),
// unit mass, Delta phi = W with the Green's function -1/(4 pi r) outside in 3D.
Convention generic(const std::string& target, const std::string& code, const std::string& file) {
    return {target,
            code,
            {file},
            {1, 2, 3},
            FloatFormat::binary64,
            SupportRule::support,
            Q(1),
            NormalisationRule::folded,
            all_quantities,
            {true, mollify_green_3d(),
             "Delta phi = W; the free-space Green's function outside the support (3D -1/(4 pi r), 2D log(r)/(2 pi), "
             "1D r/2); 2D inside: phi(r/h) + log(h)/(2 pi)"},
            "grad W = (W'/r) x; every quantity f_h(r) = h^p f(r/h) (p: W -D, each r-derivative -1, phi 2 - D)",
            false,
            "",
            {}};
}


std::vector<Convention> make_conventions() {
    std::vector<Convention> out;
    out.push_back(generic("cpp", "mollify's runtime (constexpr tables, include/mollify/table.hpp)",
                          "mollify/tables/<family>/<parameters>_D<d>.hpp"));
    out.push_back(generic("c", "plain C99: static inline functions in one header", "c/<id>.h"));
    out.push_back(generic("fortran", "Fortran 2008: a module of bind(C) pure functions", "fortran/<id>.f90"));
    out.push_back(generic("python", "Python 3 with NumPy: vectorised functions", "python/<id>.py"));

    // ../shared/peers.md, "Phantom": module kernel, q = r/h, support radkern h,
    // W = cnormk w(q)/h^3, phi = -1/q outside (G = m = h = 1), fsoft = dphi/dq.
    out.push_back({"phantom",
                   "Phantom (danieljprice/phantom, src/main/kernel_<NAME>.f90, 3D, double)",
                   {"kernel_<name>.f90"},
                   {3},
                   FloatFormat::binary64,
                   SupportRule::fixed_multiple,
                   Q(2),  // radkern: 2 for Phantom's cubic and Wendland kernels and every other kernel here
                   NormalisationRule::separate_constant,
                   {QuantityId::value, QuantityId::dr, QuantityId::potential, QuantityId::dpotential},
                   {true, Exact(Q(-1)), "potensoft = phi(q), -1/q for q >= radkern; dphidh = -phi - q dphi/dq"},
                   "grkern = dw/dq; |grad W| = cnormk grkern / h^4; fsoft = dphi/dq (1/q^2 outside)",
                   false,
                   "hfact_default: phantom_hfact (conventions.hpp)",
                   // its stock kernel_quartic.f90 and kernel_quintic.f90 (peers.md, "Phantom")
                   {{Family::quartic_spline, Q(5, 2)}, {Family::quintic_spline, Q(3)}}});
    // ../shared/peers.md, "SWIFT": u = r/h, H = gamma h, x = u/gamma,
    // W(u) = C gamma^-d w(x), float; gravity: Wendland C2 with H = 3 epsilon.
    out.push_back({"swift",
                   "SWIFT (SWIFTSIM/SWIFT, src/kernel_hydro.h and src/kernel_gravity.h, float)",
                   {"kernel_hydro.h", "kernel_gravity.h"},
                   {1, 2, 3},
                   FloatFormat::binary32,
                   SupportRule::twice_sigma,
                   Q(0),
                   NormalisationRule::separate_constant,
                   {QuantityId::value, QuantityId::dr, QuantityId::potential, QuantityId::dpotential},
                   {true, Exact(Q(-1)),
                    "kernel_grav_pot_eval(u) = phi H / m for u = r/H < 1; D_soft_1 = -W, D_soft_(n+1) = D_soft_n' - (n-1) "
                    "D_soft_n / u"},
                   "dW/du = C gamma^-(d+1) dw/dx; kernel_grav_force_eval: f = m W_f / H^3 times the separation",
                   true,
                   "kernel_gamma: swift_gamma (conventions.hpp)",
                   {}});
    // ../shared/peers.md, "GADGET-4": Hsml = H, u = r/H, wk = NORM hinv3 w(u),
    // dwk = NORM hinv4 w'(u); g-factors: g = 1/r outside.
    out.push_back({"gadget4",
                   "GADGET-4 (src/sph/kernel.h, double; softening g-factors of the multipole tree)",
                   {"kernel.h"},
                   {1, 2, 3},
                   FloatFormat::binary64,
                   SupportRule::support,
                   Q(1),
                   NormalisationRule::separate_constant,
                   {QuantityId::value, QuantityId::dr, QuantityId::potential, QuantityId::dpotential},
                   {true, Exact(Q(1)), "g(r) = -phi: 1/r outside the support, derivatives g', g'' - g'/r, ... up to fac5"},
                   "dwk = NORM hinv4 w'(u) (dW/dr, negative for a decreasing kernel)",
                   false,
                   "",
                   {}});
    return out;
}

// x's nearest double (or float): the candidate from MPFR, corrected until x
// lies strictly between the squares of its neighbouring midpoints (exact
// comparisons of rationals; a tie goes to the even neighbour).
template <class F>
F sqrt_rounded(const Q& x) {
    if (x < 0) fail("the square root of the negative " + short_string(x));
    if (x == 0) return F(0);
    Real y(0, 200);
    mpfr_set_q(y.backend().data(), x.backend().data(), MPFR_RNDN);
    y = sqrt(y);
    F d = static_cast<F>(static_cast<double>(y));
    for (int step = 0; step < 4; ++step) {
        const Q lo = (Q(d) + Q(std::nextafter(d, F(0)))) / 2;
        const Q hi = (Q(d) + Q(std::nextafter(d, std::numeric_limits<F>::infinity()))) / 2;
        if (x < lo * lo) d = std::nextafter(d, F(0));
        else if (x > hi * hi) d = std::nextafter(d, std::numeric_limits<F>::infinity());
        else return d;  // a tie (x = midpoint^2) is impossible but for exactly representable rationals
    }
    fail("internal: the square root of " + short_string(x) + " did not round");
}

}  // namespace

const std::vector<Convention>& conventions() {
    static const std::vector<Convention> all = make_conventions();
    return all;
}

const Convention& convention(const std::string& target) {
    std::string known;
    for (const Convention& c : conventions()) {
        if (c.target == target) return c;
        known += (known.empty() ? "" : ", ") + c.target;
    }
    fail("--target " + target + " is not a target (" + known + ")");
}

double sqrt_to_double(const Q& x) { return sqrt_rounded<double>(x); }
float sqrt_to_float(const Q& x) { return sqrt_rounded<float>(x); }

std::string sqrt_text(const Q& x) {
    using boost::multiprecision::mpz_int;
    const mpz_int n = numerator(x), d = denominator(x);
    const mpz_int rn = sqrt(n), rd = sqrt(d);
    if (x >= 0 && rn * rn == n && rd * rd == d) return short_string(Q(rn, rd));
    return "sqrt(" + short_string(x) + ")";
}

Q variance(const ExactKernel& k) {
    const Exact m2 = radial_moment(k, 2);
    if (!m2.is_rational())
        fail("the second moment of " + spec_string(k.spec) + " in D = " + std::to_string(k.dim) + " is not rational (" +
             m2.to_string() + "): no exact square root for its width");
    return m2.rational() / Q(k.dim);
}

DerivedConstant swift_gamma(const ExactKernel& k) {
    const Q s = variance(k);
    if (s <= 0)
        fail("the variance of " + spec_string(k.spec) + " in D = " + std::to_string(k.dim) + " is " + short_string(s) +
             " <= 0: SWIFT's gamma = H/(2 sigma) needs a positive one");
    const Q g2 = Q(1) / (Q(4) * s);
    return {"kernel_gamma", g2, sqrt_to_double(g2), sqrt_to_float(g2),
            "gamma = H/(2 sigma), sigma^2 = (1/D) int |x|^2 W (exact) = " + short_string(s) + " H^2"};
}

DerivedConstant phantom_hfact(const ExactKernel& k) {
    // Phantom's own hfact_default for the kernels it ships (peers.md, "Phantom":
    // its kernel_<NAME>.f90): a file that replaces one keeps its h, as radkern.
    struct Stock {
        const char* spec;
        Q hfact;
        const char* file;
    };
    static const Stock stock[] = {
        {"cubic-spline", Q(6, 5), "kernel_cubic.f90"},         {"quartic-spline", Q(11, 10), "kernel_quartic.f90"},
        {"quintic-spline", Q(1), "kernel_quintic.f90"},        {"wendland:k=1", Q(13, 10), "kernel_WendlandC2.f90"},
        {"wendland:k=2", Q(3, 2), "kernel_WendlandC4.f90"},    {"wendland:k=3", Q(8, 5), "kernel_WendlandC6.f90"},
    };
    for (const Stock& st : stock)
        if (k.dim == 3 && k.spec == parse_spec(st.spec))
            return {"hfact_default", st.hfact * st.hfact, sqrt_to_double(st.hfact * st.hfact), sqrt_to_float(st.hfact * st.hfact),
                    "hfact = " + short_string(st.hfact) + ", Phantom's own in its " + st.file +
                        " (the file replaces it with the same h, as radkern)"};
    const Convention& p = convention("phantom");
    // Phantom's stock cubic spline: radkern 2, hfact 1.2 (peers.md, Phantom).
    const Q reference_hfact = Q(6) / Q(5), reference_radkern = Q(2);
    const ExactKernel cubic = make_kernel(parse_spec("cubic-spline"), k.dim);
    const Q s = variance(k), sc = variance(cubic);
    const Q radkern = support_multiple(p, k);
    const Q h2 = reference_hfact * reference_hfact * reference_radkern * reference_radkern * sc / (radkern * radkern * s);
    const std::string rule = "hfact = 1.2 (2 sigma_cubic) / (radkern sigma), sigma^2 = (1/D) int |x|^2 W on support 1: " +
                             short_string(s) + " (cubic " + short_string(sc) + ")";
    // Phantom's checksetup refuses hfact < 1 (src/main/checksetup.f90): its floor
    if (h2 < Q(1)) return {"hfact_default", Q(1), 1.0, 1.0f, rule + " would give sqrt(" + short_string(h2) + ") < 1, Phantom's floor: 1"};
    return {"hfact_default", h2, sqrt_to_double(h2), sqrt_to_float(h2), rule};
}

Exact separate_normalisation(const Convention& c, const ExactKernel& k) {
    if (c.normalisation != NormalisationRule::separate_constant)
        fail("--target " + c.target + " folds the normalisation into its tables");
    Exact w0;
    try {
        w0 = value_at(k.W.pieces.front(), Q(0));
    } catch (const Error& e) {
        fail("--target " + c.target + ": W(0) of " + spec_string(k.spec) + " is not finite (" + e.what() + ")");
    }
    if (w0.is_zero())
        fail("--target " + c.target + ": W(0) = 0 for " + spec_string(k.spec) + ", no constant in front of w/w(0)");
    if (c.support == SupportRule::twice_sigma) return w0;
    return w0 * pow(support_multiple(c, k), -k.dim);
}

Q support_multiple(const Convention& c, const ExactKernel& k) {
    if (c.support == SupportRule::twice_sigma) fail("internal: support_multiple of --target " + c.target + " (gamma per kernel)");
    for (const auto& [family, multiple] : c.own_multiples)
        if (k.spec.family == family) return multiple;
    return c.support_in_h;
}

Exact potential_scale(const Convention& c) {
    return c.potential.green_coefficient_3d * mollify_green_3d().inverse();
}

}  // namespace mollify::gen
