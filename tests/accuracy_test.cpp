// The runtime measured against the exact values (issue 3): every kernel of
// mollify::tables::all_kernels, every quantity it has, at >= 10,000 points
// (tools/accuracy hard_points: support edge 1 - r/h = 1e-1 .. 1e-15, r/h =
// 1e-1 .. 1e-300 and 0, h = 1e-8 .. 1e8, r/h up to 1e6, uniform r/h in
// [0, 1.2]), through the run-time batch API mollify::kernel(spec, dim)
// .evaluate; for a few kernels also the compile-time StaticKernel and its
// vector forms (gradient, hessian, pair, potential_gradient).
//
// Metric (SLEEF's tester): the error in ulps of the exact value
// (accuracy::ulp_error) where |exact| >= 1e-10 max |f_h|; below that, in
// ulps of max |f_h| (accuracy::scaled_error). Per (family, quantity) a
// bound is asserted; the table `bounds` below says why each is what it is.
// The output lists, per family, dimension and quantity, the max ulp and its
// argument.
//
// MOLLIFY_ACCURACY_POINTS=N overrides the number of uniform points (default
// 10,000; the hard points come on top), for quick local runs; CI measures
// the default. The sanitizer build of .ci/run does not build this suite.
#include "accuracy/accuracy.hpp"

#include <mollify/kernel.hpp>
#include <mollify/tables/catalogue.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace acc = mollify::accuracy;
namespace table = mollify::table;
using mollify::QuantityId;
using acc::Real;

namespace {

constexpr int default_uniform_points = 10000;
constexpr double tiny_fraction = 1e-10;

int uniform_points() {
    if (const char* n = std::getenv("MOLLIFY_ACCURACY_POINTS")) return std::max(1, std::atoi(n));
    return default_uniform_points;
}

const std::vector<acc::Point>& points() {
    static const std::vector<acc::Point> p = acc::hard_points(uniform_points(), 20240611);
    return p;
}

// ---------------------------------------------------------------------------
// Families and their bounds.

enum class Family { anderson2, anderson_high, wendland, missing, combo, classic };
constexpr const char* family_names[] = {"mollifier (order 2)", "mollifier (order 4, 6)", "wendland",
                                        "wendland-missing", "combo", "classic"};

Family family_of(const std::string& spec) {
    if (spec.rfind("mollifier", 0) == 0) return spec.find("order") == std::string::npos ? Family::anderson2 : Family::anderson_high;
    if (spec.rfind("wendland-missing", 0) == 0) return Family::missing;
    if (spec.rfind("wendland", 0) == 0) return Family::wendland;
    if (spec.rfind("combo", 0) == 0) return Family::combo;
    return Family::classic;
}

// Bounds in ulps, three per (family, quantity):
//  local:  error in ulps of max(|exact|, sum |terms| of the emitted form)
//          -- asserted everywhere;
//  ulp:    error in ulps of the exact value -- asserted where the quantity
//          has no interior sign change (infinity: not asserted, see below);
//  scaled: tiny values (|exact| < 1e-10 max |f_h|), in ulps of max |f_h|.
struct Bound {
    double local, ulp, scaled;
};

constexpr double none = std::numeric_limits<double>::infinity();

// Why the bounds are what they are (measured maxima: the [accuracy] lines
// of the test output):
//  - 32 ulp (polynomial kernels, W and its derivatives), not 4: h is drawn
//    log-uniformly, so r/h and (h - r)/h are rounded (~1 ulp each), and the
//    factored (1 - q)^n, (1 - q^2)^n multiplies that by n: n = 14 for
//    wendland:k=4,l=4, 2 x 11 for mollifier:M=9,order=6 (measured max 25 ulp,
//    all at uniform points with such h; not yet separated from the
//    evaluation error by a power-of-two-h run).
//  - 128 local for combos: each term is factored at its own radius a_j
//    (emitted as a double: 1/3 and 2/3 are rounded), and the distance
//    a_j h - r is formed from the rounded h (measured 92 local ulp,
//    combo:m=3 hess_radial in 1D with an awkward h).
//  - ulp = none for d2r and the Laplacian of every polynomial family, and
//    for everything of the high-order families (mollifier order 4, 6;
//    combos): they change sign inside the support, where the relative
//    error measures the condition number (up to 1e9 ulp measured), not the
//    evaluation; the local bound (ulps of the emitted form's sum of |terms|)
//    is asserted instead. Likewise the potentials (2D: phi(r/h) + c log h
//    crosses 0; 3D/1D: Green's function + remainder cancel near the edge).
//  - 512 local for the classic d2r/Laplacian: the cubic spline's W'' and
//    3D Laplacian vanish exactly at its breakpoint r/h = 1/2, and the runtime
//    forms 1/2 - q from the rounded q (not from h/2 - r), so near the root the
//    error is ~ulp(q)/(1/2 - q) (measured 271 local ulp at r/h = 0.4987).
//  - wendland-missing: 32 local (measured 21); the raw ulp bound is 2^30 and
//    is a known defect, not a goal: the emitted closed form S P + arcsech Q
//    cancels in the middle range r/h ~ 0.3 .. 0.8 (measured up to 7e8 ulp,
//    1.6e-7 relative, wendland-missing:k=2,l=2 in 3D at r/h = 0.81), between
//    the exact series pieces at r = 0 and at the edge, which are accurate.
//    Taylor pieces in the middle are the missing piece of work.
//  - potentials: 16 local (measured max 9.3: Green's function plus factored
//    remainder, and the 2D c log h term).
Bound bound(Family f, QuantityId q) {
    const bool potential = static_cast<int>(q) >= static_cast<int>(QuantityId::potential);
    const bool root = q == QuantityId::d2r || q == QuantityId::laplacian;
    if (f == Family::missing) return {32, potential ? none : 0x1p30, 2};
    if (potential) return {16, none, 2};
    switch (f) {
        case Family::anderson2:
        case Family::wendland: return {32, root ? none : 32, 2};
        case Family::anderson_high: return {32, none, 2};
        case Family::combo: return {128, none, 2};
        case Family::classic: return {root ? 512.0 : 16.0, root ? none : 16, 2};
        case Family::missing: break;
    }
    return {8, 8, 2};
}

// ---------------------------------------------------------------------------
// The local scale: sum of |terms| of the emitted form at the point (long
// double: r^-4 terms at r/h = 1e-300 overflow a double). Where the terms
// cancel (near an interior root, or where a 2D potential phi(r/h) + c log h
// crosses 0) the relative error measures the condition number of the value,
// not the evaluation; the error in ulps of this scale measures the latter.

long double basis_magnitude(const table::Term& t, long double q, long double e) {
    const long double s = std::sqrt(e * (1 + q));
    switch (t.basis) {
        case table::Basis::one: return 1;
        case table::Basis::sqrt_power: return std::pow(s, static_cast<long double>(t.s_power));
        case table::Basis::arcsech: return std::abs(std::log1p((e + s) / q));
        case table::Basis::log: return std::abs(q < 0.5L ? std::log(q) : std::log1p(-e));
        case table::Basis::arcsin: return std::abs(std::asin(q));
    }
    return 0;
}

long double piece_magnitude(const table::Piece& p, long double q, long double e) {
    long double sum = 0;
    for (int i = 0; i < p.nterms; ++i) {
        const table::Term& t = p.terms[i];
        const long double v = t.var == table::Var::r ? q : q * q;
        long double poly = 0;
        for (int k = t.n; k-- > 0;) poly = poly * v + std::abs(static_cast<long double>(t.c[k]));
        long double x = poly * std::pow(q, static_cast<long double>(t.low));
        const long double to_edge = t.edge == 1.0 ? e : t.edge - q;
        const long double edge = t.var == table::Var::r ? to_edge : to_edge * (t.edge + q);
        if (t.edge_power != 0) x *= std::pow(std::abs(edge), static_cast<long double>(t.edge_power));
        sum += x * basis_magnitude(t, q, e);
    }
    return sum;
}

long double emitted_magnitude(const table::Kernel& k, QuantityId id, double r, double h) {
    const table::Quantity& tq = k.quantities[static_cast<int>(id)];
    if (r > h) return piece_magnitude(tq.pieces[tq.npieces - 1], r, 1.0L - r);
    const long double q = static_cast<long double>(r) / h, e = (static_cast<long double>(h) - r) / h;
    int p = 0;
    while (p + 2 < tq.npieces && !(q < tq.pieces[p].hi)) ++p;
    long double m = piece_magnitude(tq.pieces[p], q, e) *
                    std::pow(static_cast<long double>(h), mollify::detail::scale_power(id, k.dim));
    if (id == QuantityId::potential && k.dim == 2) m += std::abs(std::log(static_cast<long double>(h))) / (2 * M_PI);
    return m;
}

// |y - x| in ulps of max(|x|, local) (ulp as in accuracy::ulp_error).
double local_error(double y, const Real& x, long double local) {
    mpfr_srcptr c = x.backend().data();
    if (!std::isfinite(y) || !mpfr_number_p(c) || !(local > 0) || !std::isfinite(local)) return acc::ulp_error(y, x);
    mpfr_t d, m;
    mpfr_init2(d, mpfr_get_prec(c) + 1100);
    mpfr_init2(m, 64);
    mpfr_set_d(d, y, MPFR_RNDN);
    mpfr_sub(d, d, c, MPFR_RNDN);
    mpfr_abs(d, d, MPFR_RNDN);
    mpfr_set_ld(m, local, MPFR_RNDN);
    if (mpfr_cmpabs(c, m) > 0) mpfr_abs(m, c, MPFR_RNDN);
    mpfr_set_ui_2exp(m, 1, std::max(mpfr_get_exp(m) - 53, -1074L), MPFR_RNDN);  // 2^(e-1) <= max < 2^e
    mpfr_div(d, d, m, MPFR_RNDN);
    const double out = mpfr_get_d(d, MPFR_RNDN);
    mpfr_clear(d);
    mpfr_clear(m);
    return out;
}

// ---------------------------------------------------------------------------
// Statistics.

struct Measured {
    acc::Stats s;
    double max_local = 0;  // error in ulps of max(|exact|, sum |terms| of the emitted form)
    acc::Point worst_local{0, 0, ""};
    std::string local_kernel;
    long overflow = 0;
    std::string kernel;  // of the worst point, for family summaries
    std::string worst_scaled_at;
};

void add(Measured& m, double y, const Real& exact, double scale, long double local, const acc::Point& p,
         const std::string& who) {
    const double l = local_error(y, exact, local);
    if (!(l <= m.max_local)) {
        m.max_local = l;
        m.worst_local = p;
        m.local_kernel = who;
    }
    const double x = std::abs(static_cast<double>(exact));
    if (x >= tiny_fraction * scale) {
        const double u = acc::ulp_error(y, exact);
        ++m.s.points;
        m.s.rms_ulp += u * u;
        if (!(u <= m.s.max_ulp)) {
            m.s.max_ulp = u;
            m.s.worst = p;
            m.kernel = who;
        }
    } else {
        const double u = acc::scaled_error(y, exact, scale);
        ++m.s.tiny_points;
        if (!(u <= m.s.max_scaled)) {
            m.s.max_scaled = u;
            char buf[160];
            std::snprintf(buf, sizeof buf, "%s r=%.17g h=%.17g (%s)", who.c_str(), p.r, p.h, p.why);
            m.worst_scaled_at = buf;
        }
    }
}

void merge(Measured& into, const Measured& m) {
    into.overflow += m.overflow;
    if (!(m.max_local <= into.max_local)) {
        into.max_local = m.max_local;
        into.worst_local = m.worst_local;
        into.local_kernel = m.local_kernel;
    }
    into.s.points += m.s.points;
    into.s.tiny_points += m.s.tiny_points;
    into.s.rms_ulp += m.s.rms_ulp;
    if (!(m.s.max_ulp <= into.s.max_ulp)) {
        into.s.max_ulp = m.s.max_ulp;
        into.s.worst = m.s.worst;
        into.kernel = m.kernel;
    }
    if (!(m.s.max_scaled <= into.s.max_scaled)) {
        into.s.max_scaled = m.s.max_scaled;
        into.worst_scaled_at = m.worst_scaled_at;
    }
}

std::string describe(const Measured& m) {
    char buf[1000];
    const double rms = m.s.points ? std::sqrt(m.s.rms_ulp / static_cast<double>(m.s.points)) : 0;
    std::snprintf(buf, sizeof buf,
                  "max %9.3g ulp (rms %.2g) at %s r=%.17g h=%.17g (%s) | local: max %.3g ulp at %s r=%.17g h=%.17g (%s)"
                  " | tiny: max %.3g ulp of max (%ld pts) %s | %ld overflow pts",
                  m.s.max_ulp, rms, m.kernel.c_str(), m.s.worst.r, m.s.worst.h, m.s.worst.why, m.max_local,
                  m.local_kernel.c_str(), m.worst_local.r, m.worst_local.h, m.worst_local.why, m.s.max_scaled,
                  m.s.tiny_points, m.worst_scaled_at.c_str(), m.overflow);
    return buf;
}

// max |f_h| over the support: h^p max |f|, plus |c log h| for a 2D potential.
double scale_at(const acc::Reference& ref, QuantityId q, double h) {
    double s = ref.max_abs(q) * std::pow(h, mollify::detail::scale_power(q, ref.dim()));
    if (q == QuantityId::potential && ref.dim() == 2) s += std::abs(std::log(h)) / (2 * M_PI);
    return s;
}

// ---------------------------------------------------------------------------
// The run-time batch API against the reference, one kernel and quantity.

// The runtime at every point, through Kernel::evaluate, one batch per h.
std::vector<double> runtime_values(const mollify::Kernel& k, QuantityId q, const std::vector<acc::Point>& pts) {
    std::vector<std::size_t> order(pts.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return pts[a].h < pts[b].h; });
    std::vector<double> y(pts.size());
    for (std::size_t i = 0; i < order.size();) {
        std::size_t j = i;
        std::vector<double> r, out;
        while (j < order.size() && pts[order[j]].h == pts[order[i]].h) r.push_back(pts[order[j++]].r);
        out.resize(r.size());
        k.evaluate(q, r, pts[order[i]].h, out);
        for (std::size_t m = i; m < j; ++m) y[order[m]] = out[m - i];
        i = j;
    }
    return y;
}

// The runtime evaluates f(r/h) in double, then scales by h^p: where f(r/h)
// itself is beyond DBL_MAX (kernels singular at 0 -- viscosity, spiky's
// W'/r -- at r/h < 1e-100) it returns inf even if f_h is finite. Such points
// are counted, not measured (a documented limit of the runtime).
bool unscaled_overflows(const Real& exact, QuantityId q, int dim, const acc::Point& p) {
    if (p.r > p.h) return false;
    const Real scale = boost::multiprecision::pow(Real(p.h, 40), mollify::detail::scale_power(q, dim));
    return boost::multiprecision::abs(exact / scale) > Real(std::numeric_limits<double>::max());
}

Measured measure_kernel(const table::Kernel& t, const acc::Reference& ref, QuantityId q) {
    const mollify::Kernel k = mollify::kernel(t.spec, t.dim);
    const auto& pts = points();
    const std::vector<double> y = runtime_values(k, q, pts);
    const std::string who = std::string(t.spec) + " D" + std::to_string(t.dim);
    Measured m;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const Real exact = ref.value(q, pts[i].r, pts[i].h);
        if (unscaled_overflows(exact, q, t.dim, pts[i])) {
            ++m.overflow;
            continue;
        }
        add(m, y[i], exact, scale_at(ref, q, pts[i].h), emitted_magnitude(t, q, pts[i].r, pts[i].h), pts[i], who);
    }
    return m;
}

// Every kernel of one family and dimension.
void check_family(Family family, int dim) {
    std::map<int, Measured> summary;  // per quantity
    int kernels = 0;
    for (const table::Kernel* t : mollify::tables::all_kernels) {
        if (t->dim != dim || family_of(t->spec) != family) continue;
        ++kernels;
        const acc::Reference ref(t->spec, t->dim);
        for (int qi = 0; qi < table::quantity_count; ++qi) {
            const auto q = static_cast<QuantityId>(qi);
            if (!ref.has(q)) continue;
            const Measured m = measure_kernel(*t, ref, q);
            const Bound b = bound(family, q);
            EXPECT_LE(m.max_local, b.local) << t->spec << " D" << dim << " " << mollify::quantity_names[qi] << ": "
                                             << describe(m);
            EXPECT_LE(m.s.max_ulp, b.ulp) << t->spec << " D" << dim << " " << mollify::quantity_names[qi] << ": "
                                           << describe(m);
            EXPECT_LE(m.s.max_scaled, b.scaled) << t->spec << " D" << dim << " " << mollify::quantity_names[qi]
                                                << ": " << describe(m) << " tiny worst " << m.worst_scaled_at;
            merge(summary[qi], m);
        }
    }
    ASSERT_GT(kernels, 0);
    for (const auto& [qi, m] : summary)
        std::printf("[accuracy] %-22s D%d %-21s %s\n", family_names[static_cast<int>(family)], dim,
                    mollify::quantity_names[qi], describe(m).c_str());
    std::fflush(stdout);
}

std::string test_name(const ::testing::TestParamInfo<std::tuple<Family, int>>& info) {
    static const char* const n[] = {"Anderson2", "AndersonHigh", "Wendland", "Missing", "Combo", "Classic"};
    return std::string(n[static_cast<int>(std::get<0>(info.param))]) + "_D" + std::to_string(std::get<1>(info.param));
}

class Families : public ::testing::TestWithParam<std::tuple<Family, int>> {};

TEST_P(Families, RuntimeMatchesExactValues) {
    ASSERT_GE(points().size(), static_cast<std::size_t>(std::min(uniform_points(), default_uniform_points)));
    check_family(std::get<0>(GetParam()), std::get<1>(GetParam()));
}

INSTANTIATE_TEST_SUITE_P(All, Families,
                         ::testing::Combine(::testing::Values(Family::anderson2, Family::anderson_high,
                                                              Family::wendland, Family::missing, Family::combo,
                                                              Family::classic),
                                            ::testing::Values(1, 2, 3)),
                         test_name);

}  // namespace

// ---------------------------------------------------------------------------
// The vector forms of the compile-time StaticKernel (what SPH and Poisson
// codes call: pair, gradient, Hessian, potential gradient) at random double
// displacements x against the exact values at the exact |x| (MPFR, 400 bits).
// The runtime rounds |x| once (sqrt of a rounded sum of squares); a result
// exact for r' within 2 ulp(r) of r is as good as the input allows, so the
// tolerance is B ulp of the exact value plus |d(component)/dr| * 2 ulp(r)
// (the condition of the component with respect to r: large only where
// (1 - r/h)^n makes it steep relative to its size, near the edge).

namespace vector_forms {

constexpr int samples = 4000;
// W and grad W: measured <= 12.3 ulp (wendland:k=4,l=4, the edge factor's
// n = 8 times the half ulp of 1 - q, plus the squarings of the power).
constexpr double bound_ulps = 16;
// grad phi: measured up to 63 ulp for wendland:k=4,l=4 in 2D at r/h ~ 0.5,
// where the emitted interior polynomial of phi'/r (degree 16, alternating
// signs) cancels; the radial test above sees the same (raw ulps of
// dpotential_over_r). An emission limit, not the evaluation (local <= 8).
constexpr double potential_bound_ulps = 128;

struct Worst {
    double ulps = 0;
    std::string at;
};

Real exact_r(const double* x, int dim) {
    Real s(0, 400);
    for (int c = 0; c < dim; ++c) s += Real(x[c], 400) * Real(x[c], 400);
    return boost::multiprecision::sqrt(s);
}

double ulp_of(double x) { return std::ldexp(1.0, x == 0 ? -1074 : std::max(std::ilogb(x) - 52, -1074)); }

// |y - exact| / (ulp(exact) + |slope| 2 ulp(r)): SLEEF ulps with the r-rounding allowance.
double error(double y, const Real& exact, const Real& slope, double r) {
    const double allowance = std::abs(static_cast<double>(slope)) * 2 * ulp_of(r);
    const Real diff = boost::multiprecision::abs(Real(y, 400) - exact);
    return static_cast<double>(diff) / (ulp_of(std::abs(static_cast<double>(exact))) + allowance);
}

template <const table::Kernel& K>
void check_vector_forms(double h, unsigned seed) {
    using W = mollify::StaticKernel<K>;
    constexpr int D = W::dim;
    const acc::Reference ref(K.spec, D);
    const mollify::Smoothing s = W::smoothing(h);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.05 * h, 1.05 * h);
    Worst worst_value, worst_grad, worst_pot;
    const Real H(h, 400);
    for (int i = 0; i < samples; ++i) {
        mollify::Vector<D> x;
        for (double& c : x) c = u(rng);
        if (i == 0) x.fill(0.0);
        const Real r = exact_r(x.data(), D);
        const double rd = static_cast<double>(r);
        if (rd == 0 || rd > h) continue;
        const auto pair = W::pair(x, s);
        const Real w = ref.value(QuantityId::value, r, H), dw = ref.value(QuantityId::dr, r, H);
        const Real g = ref.value(QuantityId::grad_over_r, r, H), dg = ref.value(QuantityId::hess_radial, r, H) * r;
        auto note = [&](Worst& wst, double e, const char* what) {
            if (e > wst.ulps) {
                char buf[200];
                std::snprintf(buf, sizeof buf, "%s at |x|=%.17g h=%.17g", what, rd, h);
                wst = {e, buf};
            }
        };
        note(worst_value, error(pair.value, w, dw, rd), "pair W");
        for (int c = 0; c < D; ++c) {
            const Real gx = g * Real(x[c], 400);
            note(worst_grad, error(pair.gradient[c], gx, dg * Real(x[c], 400), rd), "pair grad W");
        }
        if constexpr (K.has_potential) {
            const auto e = W::potential_gradient(x, s);
            const Real pg = ref.value(QuantityId::dpotential_over_r, r, H);
            const Real dpg = ref.value(QuantityId::potential_hess_radial, r, H) * r;
            for (int c = 0; c < D; ++c)
                note(worst_pot, error(e[c], pg * Real(x[c], 400), dpg * Real(x[c], 400), rd), "potential gradient");
        }
    }
    std::printf("[accuracy] vector %-40s D%d h=%-8g W %.3g ulp (%s) | grad %.3g ulp (%s) | grad phi %.3g ulp (%s)\n",
                K.spec, D, h, worst_value.ulps, worst_value.at.c_str(), worst_grad.ulps, worst_grad.at.c_str(),
                worst_pot.ulps, worst_pot.at.c_str());
    EXPECT_LE(worst_value.ulps, bound_ulps) << K.spec << " D" << D << " " << worst_value.at;
    EXPECT_LE(worst_grad.ulps, bound_ulps) << K.spec << " D" << D << " " << worst_grad.at;
    EXPECT_LE(worst_pot.ulps, potential_bound_ulps) << K.spec << " D" << D << " " << worst_pot.at;
}

}  // namespace vector_forms

// Wendland C4 (the SPH workhorse), Wendland k = 4, l = 4 and the mollifier
// M = 9 (the highest powers of the edge factor), in 2D and 3D, at a
// power-of-two h and at awkward ones. Kernels whose W or W'/r change sign
// (high orders, combos) are measured radially above with the local metric;
// here a root would make the relative error meaningless.
TEST(VectorForms, PairGradientAndPotentialGradientMatchExactValues) {
    namespace t = mollify::tables;
    for (const double h : {1.0, 0.37, 3e-7, 2.5e6}) {
        vector_forms::check_vector_forms<t::wendland_k_2_D3>(h, 1);
        vector_forms::check_vector_forms<t::wendland_k_4_l_4_D2>(h, 2);
        vector_forms::check_vector_forms<t::mollifier_M_9_D3>(h, 3);
        vector_forms::check_vector_forms<t::mollifier_M_4_D2>(h, 4);
    }
}
