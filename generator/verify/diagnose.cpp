// Diagnosis of a systematic error: the values are fitted by c T(exact) for a
// few transformations T a published kernel bug amounts to (none: a constant
// factor or the sign; h scaled: a support convention; another dimension's
// kernel; dW/dr times q or r, or divided by them), c by the median ratio;
// a transformation fits when 95 % of the residuals |got - c T| are below a
// tolerance relative to the largest value (2^-34: far above double rounding,
// expanded monomials' cancellation included; 2^-19 for values that are
// floats). A constant is then recognised as p/q pi^k and checked against the
// exact values in ulps. What no transformation explains is single precision
// (the values are floats), cancellation near the edge (the failures lie near
// r = H), or unexplained.
#include "verify/compared.hpp"

#include "verify/recognise.hpp"
#include "verify/ulps.hpp"

#include "conventions.hpp"
#include "error.hpp"
#include "number.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

namespace mollify::verify::detail {

namespace {

constexpr std::size_t max_fit_points = 2000;

std::string number(double x, int digits = 6) {
    char b[64];
    std::snprintf(b, sizeof b, "%.*g", digits, x);
    return b;
}

struct Fit {
    double c = 1, residual = std::numeric_limits<double>::infinity();
};

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return std::numeric_limits<double>::infinity();
    const auto k = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
}

// The indices the fits use: every point when there are few, else every k-th.
std::vector<std::size_t> subset(std::size_t n) {
    std::vector<std::size_t> out;
    const std::size_t step = std::max<std::size_t>(1, n / max_fit_points);
    for (std::size_t i = 0; i < n; i += step) out.push_back(i);
    return out;
}

// got ~ c y: c the median ratio where y is not tiny (>= 1e-3 of the
// quantity's magnitude m at that h), the residuals |got - c y| / m.
Fit fit(const std::vector<double>& got, const std::vector<double>& y, const std::vector<double>& m) {
    std::vector<double> ratios;
    for (std::size_t i = 0; i < got.size(); ++i)
        if (std::isfinite(got[i]) && std::isfinite(y[i]) && std::abs(y[i]) >= 1e-3 * m[i] && y[i] != 0)
            ratios.push_back(got[i] / y[i]);
    if (ratios.size() < 10) return {};
    Fit f;
    f.c = percentile(ratios, 0.5);
    std::vector<double> residuals;
    for (std::size_t i = 0; i < got.size(); ++i) {
        if (!std::isfinite(got[i])) continue;
        residuals.push_back(std::isfinite(y[i]) ? std::abs(got[i] - f.c * y[i]) / m[i]
                                                : std::numeric_limits<double>::infinity());
    }
    f.residual = percentile(residuals, 0.95);
    return f;
}

struct Candidate {
    DiagnosisKind kind;
    std::string what;  // the transformation, for people
    std::vector<double> y;
    Fit fit;
};

// c recognised and checked: 95 % of the points within max(4 bound, 16) ulps of c exact.
std::optional<gen::Exact> exact_factor(const Setup& s, const std::vector<Compared>& pts,
                                       const std::vector<std::size_t>& idx, double c, bool floats, double bound) {
    // Float values give c to ~2^-24: denominators <= 100 (rationals p/q pi^k
    // near 1 are ~3e-4 apart, so a match within 2^-21 is unlikely to be
    // chance); doubles give c to ~2^-52, checked in ulps below.
    const auto e = recognise(c, floats ? 0x1p-21 : 1e-13, floats ? 100 : 100000);
    if (!e) return std::nullopt;
    const Real v(e->evaluate(400).first, 100);
    std::vector<double> errors;
    for (std::size_t i : idx) {
        if (!std::isfinite(pts[i].got)) continue;
        const Real x = pts[i].exact * v;
        errors.push_back(ulps(pts[i].got, x, pts[i].floor * std::abs(c), s.single || floats));
    }
    return percentile(errors, 0.95) <= std::max(4 * bound, 16.0) ? e : std::nullopt;
}

// "W_h(0) = ... h^-D, exact ... h^-D" where both are exact.
std::string normalisation_text(const Setup& s, const std::optional<gen::Exact>& factor) {
    if (s.quantity != Quantity::value || !factor || s.convention->support == gen::SupportRule::twice_sigma) return "";
    try {
        const gen::ExactKernel& k = s.reference->kernel();
        const gen::Exact w0 = gen::value_at(k.W.pieces.front(), gen::Q(0)) *
                              gen::pow(gen::support_multiple(*s.convention, k), -s.dim);
        if (w0.is_zero()) return "";
        const std::string h = " h^-" + std::to_string(s.dim);
        return ": W_h(0) = " + pretty(w0 * *factor) + h + ", exact " + pretty(w0) + h;
    } catch (const Error&) {
        return "";
    }
}

Diagnosis constant_diagnosis(const Setup& s, const std::vector<Compared>& pts, const std::vector<std::size_t>& idx,
                             double c, bool floats, double bound) {
    if (c == 0)  // "normalisation off by the factor 0" said nothing useful
        return {DiagnosisKind::constant_factor,
                "constant factor 0: got = 0 where the exact value is not (nothing computed, or h far from the "
                "convention's)"};
    const auto e = exact_factor(s, pts, idx, c, floats, bound);
    const std::string f = e ? pretty(*e) : number(c, floats ? 8 : 17);
    if ((e && *e == gen::Exact(gen::Q(-1))) || (!e && std::abs(c + 1) <= 0x1p-40))
        return {DiagnosisKind::wrong_sign, "wrong sign: got = -exact everywhere"};
    std::string text = "constant factor: got = " + f + " x exact everywhere" +
                       (std::abs(c - 1) < 0.01 ? " (relative deviation " + number(c - 1, 3) + ")" : "");
    if (s.quantity == Quantity::value) text = "normalisation off by the factor " + f + normalisation_text(s, e);
    if (table::is_potential(s.id) && e) {
        for (const gen::Convention& other : gen::conventions()) {
            if (other.target == s.convention->target) continue;
            if (gen::potential_scale(other) * s.value_scale.inverse() == *e) {
                text += "; that is the potential convention of " + other.target + " (" + other.potential.description + ")";
                break;
            }
        }
    }
    if (!e) text += " (not a small rational or pi multiple)";
    return {DiagnosisKind::constant_factor, text};
}

// The kernel with its support scaled by a: a^-? folded into c.
struct Scaling {
    double a;
    std::string name;
};

std::vector<Scaling> scalings(const Setup& s) {
    // 2/3, 3/2, 4/5, 5/4: radkern 2 against Phantom's stock 3 and 2.5 (its quintic and quartic splines)
    std::vector<Scaling> out{{2, "2"},         {0.5, "1/2"},       {3, "3"},     {1.0 / 3, "1/3"},
                             {2.0 / 3, "2/3"}, {1.5, "3/2"},       {0.8, "4/5"}, {1.25, "5/4"}};
    try {
        const gen::DerivedConstant g = gen::swift_gamma(s.reference->kernel());
        const std::string gn = number(g.value, 7);
        out.push_back({g.value, "gamma = " + gn + " (SWIFT's kernel_gamma = H/(2 sigma) of this kernel)"});
        out.push_back({1 / g.value, "1/gamma, gamma = " + gn + " (SWIFT's kernel_gamma)"});
        out.push_back({g.value / 2, "gamma/2 = " + number(g.value / 2, 7) + " (SWIFT's h = 2 sigma against q in [0, 2))"});
    } catch (const Error&) {
    }
    return out;
}

std::string support_text(const Setup& s, const Scaling& sc, double c, const std::string& factor) {
    std::string t = "support convention: got = the kernel with support " + sc.name + " x H (H = the support radius of convention " +
                    s.convention->target + " at your h)";
    if (sc.a == 2) t += ": your h is half the support (q = r/h in [0, 2), Phantom's radkern 2; --convention phantom)";
    if (sc.a == 0.5) t += ": your support is h/2 (or your h is twice the convention's)";
    if (sc.a == 2.0 / 3 || sc.a == 0.8 || sc.a == 1.5 || sc.a == 1.25)
        t += ": a radkern of 2 against 3 or 2.5, or the reverse (Phantom's stock quintic and quartic splines have 3 and 2.5, "
             "its other kernels 2; --convention phantom takes Phantom's own for each kernel)";
    if (sc.name.rfind("gamma =", 0) == 0) t += ": your h is SWIFT's h = 2 sigma (--convention swift)";
    if (std::abs(c - 1) > 1e-9) t += ", times " + factor + " (its normalisation not rescaled)";
    return t;
}

std::optional<Diagnosis> transformations(const Setup& s, const std::vector<Compared>& pts,
                                         const std::vector<std::size_t>& idx, bool floats, double bound) {
    const double tol = floats ? 0x1p-19 : 0x1p-34;
    std::vector<double> got, identity, m;
    for (std::size_t i : idx) {
        got.push_back(pts[i].got);
        identity.push_back(pts[i].exact_d);
        m.push_back(pts[i].magnitude);
    }
    const Fit id = fit(got, identity, m);
    if (id.residual <= tol) {
        const double significant = std::max(bound, 1.0) * (floats ? 0x1p-22 : 0x1p-50);
        if (std::abs(id.c - 1) <= significant) return std::nullopt;  // rounding, not a factor
        return constant_diagnosis(s, pts, idx, id.c, floats, bound);
    }
    std::vector<Candidate> candidates;
    auto values = [&](const std::function<double(const Compared&)>& f) {
        std::vector<double> y;
        for (std::size_t i : idx) {
            try {
                y.push_back(f(pts[i]));
            } catch (const Error&) {
                y.push_back(std::numeric_limits<double>::quiet_NaN());
            }
        }
        return y;
    };
    std::vector<Scaling> scs = scalings(s);
    for (std::size_t j = 0; j < scs.size(); ++j) {
        const double a = scs[j].a;
        candidates.push_back({DiagnosisKind::support_convention, std::to_string(j), values([&](const Compared& p) {
                                  Real H = support_of(s, p.h);
                                  H *= a;
                                  return static_cast<double>(exact_with(s, *s.reference, p.r, H));
                              }),
                              {}});
    }
    for (int d = 1; d <= 3; ++d) {
        if (d == s.dim) continue;
        std::shared_ptr<const accuracy::Reference> other;
        try {
            other = reference(s.spec, d);
        } catch (const Error&) {
            continue;
        }
        if (!other->has(s.id)) continue;
        candidates.push_back({DiagnosisKind::other_dimension, std::to_string(d), values([&](const Compared& p) {
                                  return static_cast<double>(exact_with(s, *other, p.r, support_of(s, p.h)));
                              }),
                              {}});
    }
    // A derivative off by a factor of q, r or h (dW/dq for dW/dr, W' for W'/r, ...).
    using Factor = std::pair<const char*, double (*)(const Compared&)>;
    std::vector<Factor> factors;
    if (s.quantity == Quantity::dr)
        factors = {{"times q = r/H (a factor q too many)", [](const Compared& p) { return p.exact_d * p.q; }},
                   {"divided by q = r/H (a factor q missing)", [](const Compared& p) { return p.exact_d / p.q; }},
                   {"times r (a factor r too many)", [](const Compared& p) { return p.exact_d * p.r; }},
                   {"divided by r (a factor r missing: W'/r instead of W')", [](const Compared& p) { return p.exact_d / p.r; }},
                   {"times h (dW/dq, not dW/dr: the factor 1/h missing)", [](const Compared& p) { return p.exact_d * p.h; }},
                   {"divided by h (a factor 1/h too many)", [](const Compared& p) { return p.exact_d / p.h; }}};
    if (s.quantity == Quantity::grad_over_r)
        factors = {{"times r (dW/dr, not W'/r: the division by r missing)", [](const Compared& p) { return p.exact_d * p.r; }},
                   {"divided by r (W'/r^2: divided by r twice)", [](const Compared& p) { return p.exact_d / p.r; }},
                   {"times h (dW/dq / r, not dW/dr / r: the factor 1/h missing)", [](const Compared& p) { return p.exact_d * p.h; }},
                   {"divided by h (a factor 1/h too many)", [](const Compared& p) { return p.exact_d / p.h; }}};
    for (const auto& [what, f] : factors) candidates.push_back({DiagnosisKind::gradient_factor, what, values(f), {}});
    const Candidate* best = nullptr;
    for (Candidate& c : candidates) {
        c.fit = fit(got, c.y, m);
        if (c.fit.residual <= tol && (!best || c.fit.residual < best->fit.residual)) best = &c;
    }
    if (!best) return std::nullopt;
    const double c = best->fit.c;
    const std::string factor = std::abs(c - 1) > 1e-9 ? number(c, 10) : "1";
    switch (best->kind) {
        case DiagnosisKind::support_convention:
            return Diagnosis{best->kind, support_text(s, scs[std::stoul(best->what)], c, factor)};
        case DiagnosisKind::other_dimension:
            return Diagnosis{best->kind, "kernel of another dimension: got = " + s.spec + " in D = " + best->what +
                                             (factor == "1" ? "" : " times " + factor) + ", not D = " + std::to_string(s.dim) +
                                             " (its normalisation, and for Wendland kernels its exponent, depend on D)"};
        default:
            return Diagnosis{best->kind, "gradient off by a factor: got = dW/dr " + best->what +
                                             (factor == "1" ? "" : ", times " + factor)};
    }
}

// The residual of got = c exact (the fit of no transformation).
double identity_residual(const std::vector<Compared>& pts, const std::vector<std::size_t>& idx) {
    std::vector<double> got, y, m;
    for (std::size_t i : idx) {
        got.push_back(pts[i].got);
        y.push_back(pts[i].exact_d);
        m.push_back(pts[i].magnitude);
    }
    return fit(got, y, m).residual;
}

// Most nonzero values are exactly floats.
bool values_are_floats(const std::vector<Compared>& pts, std::string* count) {
    std::size_t nonzero = 0, floats = 0;
    for (const Compared& p : pts) {
        if (!std::isfinite(p.got) || p.got == 0) continue;
        ++nonzero;
        if (static_cast<double>(static_cast<float>(p.got)) == p.got) ++floats;
    }
    *count = std::to_string(floats) + " of " + std::to_string(nonzero);
    return nonzero >= 10 && static_cast<double>(floats) >= 0.95 * static_cast<double>(nonzero);
}

// The error grows towards r = H: the worst inside lies within 0.1 H of the
// edge and is 10 times the worst for r < H/2. Expanded monomials: the terms
// of sum c_k q^k cancel to (1 - q)^n, at q = 1 - d they are O(1) against a
// value O(d^n). The textbook factored form too: 1 - q formed from a rounded
// q = r/h carries a relative error ulp(q)/(1 - q), n times in (1 - q)^n
// (a Wendland C4 written so is off by ~200 ulps at r/H = 1 - 2^-8).
std::optional<Diagnosis> edge(const std::vector<Compared>& pts, double bound) {
    const double limits[] = {0.5, 0.9, 0.99, 0.999};
    double below[4] = {0, 0, 0, 0}, worst = 0, worst_q = 0;
    for (const Compared& p : pts) {
        if (p.q >= 1 || !std::isfinite(p.ulps)) continue;
        for (int j = 0; j < 4; ++j)
            if (p.q < limits[j]) below[j] = std::max(below[j], p.ulps);
        if (p.ulps > worst) worst = p.ulps, worst_q = p.q;
    }
    if (worst_q < 0.9 || worst < 10 * std::max(below[0], bound)) return std::nullopt;
    std::string growth;
    for (int j = 0; j < 4; ++j) growth += (j ? ", " : "") + number(below[j], 3) + " for r/H < " + number(limits[j], 3);
    return Diagnosis{DiagnosisKind::edge_cancellation,
                     "error grows towards the support edge (max ulps " + growth + "), worst " + number(worst, 3) +
                         " ulps at r/H = 1 - " + number(1 - worst_q, 3) +
                         ": expanded monomials cancel there, or 1 - q is formed from a rounded q = r/h; keep the edge factor "
                         "(1 - q)^n with 1 - q = (h - r)/h (exact where r and h are within a factor 2)"};
}

}  // namespace

std::optional<Diagnosis> diagnose(const Setup& s, const std::vector<Compared>& points, double bound) {
    double max = 0;
    for (const Compared& p : points) max = std::max(max, p.ulps);
    if (points.empty() || max <= bound) return std::nullopt;
    std::string count;
    const bool floats = values_are_floats(points, &count);
    for (const Compared& p : points)
        if (!floats && !std::isfinite(p.got) && std::isfinite(p.exact_d))
            return Diagnosis{DiagnosisKind::not_finite, std::string(std::isnan(p.got) ? "NaN" : "infinity") + " at r = " +
                                                            number(p.r, 17) + ", h = " + number(p.h, 17) + " (exact " +
                                                            number(p.exact_d, 17) + ")"};
    const std::vector<std::size_t> idx = subset(points.size());
    if (auto d = transformations(s, points, idx, floats, bound)) return d;
    std::vector<double> e;
    for (const Compared& p : points) e.push_back(p.ulps);
    const double median = percentile(e, 0.5);
    const std::string size = number(median, 3) + " ulps (2^" + number(std::log2(std::max(median, 1.0)), 3) +
                             "; half a float ulp is 2^28 double ulps)";
    if (floats && !s.single)
        return Diagnosis{DiagnosisKind::single_precision,
                         "single precision: " + count + " nonzero values are exactly floats, median error " + size +
                             ": evaluate in double, or verify with a float convention (swift)"};
    // Float arithmetic inside, a double result (e.g. w(q) in float times h^-D
    // in double): errors of float rounding (2^-24 relative, 2^29 ulps) at
    // most points, and the values within float rounding of the exact ones.
    if (!s.single && median >= 0x1p20 && identity_residual(points, idx) <= 0x1p-19)
        return Diagnosis{DiagnosisKind::single_precision,
                         "single precision inside: median error " + size +
                             " everywhere, the values within float rounding of the exact ones: part of the evaluation is in float"};
    if (auto d = edge(points, bound)) return d;
    const Compared* worst = &points.front();
    for (const Compared& p : points)
        if (p.ulps > worst->ulps) worst = &p;
    return Diagnosis{DiagnosisKind::unexplained, "no systematic pattern recognised (not a constant factor, support convention, "
                                                 "gradient factor, sign, dimension, float evaluation or edge cancellation); worst " +
                                                     number(worst->ulps, 3) + (s.single ? " float" : "") + " ulps at r = " + number(worst->r, 17) +
                                                     ", h = " + number(worst->h, 17)};
}

}  // namespace mollify::verify::detail
