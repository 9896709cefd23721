// The errata of Anderson 2014 (seed 000): Table 1's sigma and c0, the
// exponent method's gamma and alpha_j, Theorem 1's sigma formula, the second
// moment, the radii combinations (8)-(10), and the formulas for B_delta,
// phi_delta and its derivatives (§4, Appendix B).
#include "errata_checker.hpp"

#include "anderson.hpp"
#include "error.hpp"
#include "spec.hpp"
#include "vandermonde.hpp"

#include <functional>

namespace mollify::gen::errata {

namespace {

// Anderson's omega_N: 1, 2 pi, 4 pi (his §2; the core uses omega_1 = 2).
Exact omega_anderson(int dim) { return dim == 1 ? Exact(Q(1)) : sphere_measure(dim); }

std::string mollifier_spec(int M, int order = 2) {
    return "mollifier:M=" + std::to_string(M) + (order == 2 ? "" : ",order=" + std::to_string(order));
}

Q rational_or_fail(const Exact& x, const std::string& what) {
    if (!x.is_rational()) fail("internal: " + what + " is not rational: " + x.to_string());
    return x.rational();
}

}  // namespace

Q Checker::table1_sigma(int dim, int M) {
    return rational_or_fail(kernel(mollifier_spec(M), dim).W.at(Q(0)) * omega_anderson(dim), "sigma");
}

// ---------------------------------------------------------------------------
// Table 1 and the exponent method

void Checker::anderson_sigma(const Entry& e) { scalar(e, table1_sigma(e.param("D"), e.param("M"))); }

void Checker::anderson_c0(const Entry& e) {
    const int D = e.param("D");
    const std::string spec = mollifier_spec(e.param("M"));
    const ExactKernel& k = kernel(spec, D);
    const Quantities& qs = quantities(spec, D);
    if (!qs.potential) fail("internal: no potential for " + spec);
    // phi = normalisation * v_N + const inside, v_N(1) = 0, c0 = v_N(0).
    const Exact c0 = (qs.potential->at(Q(0)) - qs.potential->at(Q(1))) * k.normalisation.inverse();
    scalar(e, rational_or_fail(c0, "c0"));
}

namespace {

// Tables 3-8 are fourth and sixth order; anything else is a bad transcription.
ExponentMethod tabulated_exponent_method(const Entry& e) {
    const int M = e.param("M"), order = e.param("order"), D = e.param("D");
    if (M < 1 || M > max_mollifier_M || (order != 4 && order != 6) || D < 1 || D > 3)
        e.bad("params (D = " + std::to_string(D) + ", M = " + std::to_string(M) + ", order = " + std::to_string(order) +
              ") are outside Tables 3-8 (D 1..3, order 4 or 6)");
    return exponent_method(M, order, D);
}

}  // namespace

void Checker::anderson_gamma(const Entry& e) {
    const ExponentMethod m = tabulated_exponent_method(e);
    const Exact gamma = m.normalisation * omega_anderson(e.param("D"));
    scalar(e, rational_or_fail(gamma, "gamma"));
}

void Checker::anderson_alpha(const Entry& e) {
    const ExponentMethod m = tabulated_exponent_method(e);
    const int j = e.param("j");
    if (j < 1 || j >= static_cast<int>(m.alpha.size()))
        e.bad("params.j = " + std::to_string(j) + " is outside 1.." + std::to_string(m.alpha.size() - 1));
    scalar(e, m.alpha[static_cast<std::size_t>(j)]);
}

void Checker::anderson_sigma_formula(const Entry& e) {
    const int D = e.param("D");
    const Q exact = table1_sigma(D, e.param("M"));
    const Q printed = e.rational(e.printed(), "printed");
    std::string remark;
    if (printed != exact && D == 1 && printed == 2 * exact)
        remark = "Theorem 1's formula assumes omega_1 = 2; with the paper's omega_1 = 1 (§2) it is off by a factor 2";
    scalar(e, exact, remark);
}

void Checker::anderson_second_moment(const Entry& e) {
    const int D = e.param("D");
    const ExactKernel& k = kernel(mollifier_spec(e.param("M")), D);
    // int B x_i^2 = int B |x|^2 / D, delta = 1
    const Q m2 = rational_or_fail(radial_moment(k, 2) * Q(1, D), "second moment");
    const Q printed = e.rational(e.printed(), "value", "printed");
    const int dp = e.integer(e.printed(), "delta_power", "printed");
    e.compare(printed == m2, "", short_string(printed), short_string(m2),
              printed == m2 ? "" : factor_remark(printed / m2));
    // Scaling B_delta(x) = delta^-D B(x/delta) multiplies the second moment by delta^2.
    e.compare(dp == 2, "power of delta", delta_string(dp), delta_string(2));
}

// ---------------------------------------------------------------------------
// Radii combinations, eqs. (8)-(10): sum_j w_j B_{a_j}, a_j = j/K

namespace {

std::string b_of(const Q& weight, const Q& scale) {
    return short_string(weight) + " * B(" + short_string(scale) + " r)";
}

// x as the base of a power: "3", "(3/2)".
std::string power_base(const Q& x) { return is_integer(x) ? short_string(x) : "(" + short_string(x) + ")"; }

// The printed term t against the member w B_a(r) = w a^-N B(r/a) of radius a:
// its weight, then its argument.
void compare_radius_member(const Entry& e, const std::string& part, const ScaledTerm& t, const Q& a, const Q& w) {
    e.compare(t.weight == w, part + ", weight", short_string(t.weight), short_string(w),
              factor_remark(w != 0 ? std::optional<Q>(t.weight / w) : std::nullopt));
    const Q inv = Q(1) / a;
    const std::string member = "B_{" + short_string(a) + "}(r)";
    const std::string exact = short_string(w) + " * " + member + " = " + short_string(w) + " * " + power_base(inv) +
                              "^N * B(" + short_string(inv) + " r)";
    e.compare(t.scale == inv, part + ", argument", b_of(t.weight, t.scale), exact,
              "B(" + short_string(t.scale) + " r) is " + member + " only after rescaling: " + member + " = " +
                  power_base(inv) + "^N B(" + short_string(inv) +
                  " r); the weights give unit mass and vanishing moments only for the radius-" + short_string(a) +
                  " member");
}

}  // namespace

void Checker::anderson_radii_combination(const Entry& e) {
    const int order = e.param("order");
    if (order < 4 || order % 2 != 0 || order / 2 > max_combo_m) e.bad("params.order must be even and at least 4");
    const std::vector<Q> radii = equidistant_radii(order / 2);  // a_j = j/K, eq. (8)
    const std::vector<Q> w = vandermonde_weights(radii);
    const std::vector<ScaledTerm> printed = read_scaled_terms(e, "argument_scale");  // weight * B(scale r)
    // The member of radius a is B_a(r) = a^-N B(r/a): argument scale 1/a. A
    // printed scale s is matched with the radius 1/s, else with the radius s
    // (the argument read as the radius).
    Pairing pairing(printed.size(), radii.size());
    pairing.pair([&](std::size_t i, std::size_t j) { return printed[i].scale > 0 && radii[j] * printed[i].scale == 1; });
    pairing.pair([&](std::size_t i, std::size_t j) { return printed[i].scale > 0 && radii[j] == printed[i].scale; });
    for (std::size_t i = 0; i < printed.size(); ++i) {
        const std::string part = "term " + b_of(printed[i].weight, printed[i].scale);
        if (const auto j = pairing.match[i])
            compare_radius_member(e, part, printed[i], radii[*j], w[*j]);
        else
            e.compare(false, part, b_of(printed[i].weight, printed[i].scale), "no such term",
                      "no radius j/" + std::to_string(order / 2) + " has argument scale " + short_string(printed[i].scale));
    }
    for (std::size_t j = 0; j < radii.size(); ++j)
        if (!pairing.used[j])
            e.compare(false, "term of radius " + short_string(radii[j]), "missing",
                      short_string(w[j]) + " * B_{" + short_string(radii[j]) + "}(r)");
}

// ---------------------------------------------------------------------------
// B_delta, phi_delta and its derivatives, Anderson §4 and Appendix B

namespace {

// What those formulas print: prefactor * delta^delta_power * [sum_n c_n v^n],
// v = 1-(r/delta)^2 for the kernel and r/delta for the potential.
struct PrintedFormula {
    const Entry& e;
    Exact prefactor;
    int delta_power;
    std::string variable;
    int D;
    std::function<Q()> sigma;  // Table 1's sigma_{M(D)}, for the remarks

    std::string var_power(int n) const { return "(" + variable + ")^" + std::to_string(n); }

    // The printed bracket coefficients times the printed prefactor.
    Coefficients scaled(const std::map<int, Q>& bracket) const {
        Coefficients c;
        for (const auto& [n, v] : bracket) add_coefficient(c, n, prefactor * v);
        return c;
    }

    // The printed bracket coefficient and the exact one relative to the
    // printed prefactor, when that is rational.
    std::string bracket_remark(const Exact& p, const Exact& x) const {
        std::vector<std::string> r;
        const auto pb = p.is_zero() ? std::optional<Q>(Q(0)) : ratio(p, prefactor);
        const auto xb = x.is_zero() ? std::optional<Q>(Q(0)) : ratio(x, prefactor);
        if (pb && xb) r.push_back("bracket coefficient printed " + short_string(*pb) + ", exact " + short_string(*xb));
        if (!p.is_zero() && !x.is_zero()) {
            const auto f = ratio(p, x);
            r.push_back(factor_remark(f));
            // A stray sigma in a printed denominator, e.g. (2 sigma k).
            const Q s = sigma();
            if (f && *f == 1 / s)
                r.push_back("consistent with a spurious factor 1/sigma_{M(" + std::to_string(D) +
                            ")} = 1/" + short_string(s) + " in the printed coefficient");
        }
        return join(r, "; ");
    }

    // The printed bracket against the exact coefficients of the same powers.
    template <class Label>
    void compare_bracket(const std::map<int, Q>& printed, const Coefficients& exact, Label label) const {
        std::set<int> keys;
        for (const auto& [n, v] : printed) keys.insert(n);
        compare_coefficients(e, scaled(printed), exact, keys, label,
                             [&](int, const Exact& p, const Exact& x) { return bracket_remark(p, x); });
    }

    void compare_delta(const std::string& part, int exact_dp) const {
        e.compare(delta_power == exact_dp, part, delta_string(delta_power), delta_string(exact_dp),
                  delta_power == exact_dp ? ""
                                          : "printed " + delta_string(delta_power) + ", exact " + delta_string(exact_dp));
    }
};

PrintedFormula read_formula(const Entry& e, int D, std::function<Q()> sigma) {
    const json& pr = e.printed();
    const json& pre = e.need(pr, "prefactor", "printed");
    const Exact prefactor = Exact::pi_power(e.rational(pre, "value", "printed.prefactor"),
                                            e.integer(pre, "pi_power", "printed.prefactor"));
    const int delta_power = e.integer(pre, "delta_power", "printed.prefactor");
    const std::string variable = e.text(pr, "variable", "printed");
    const std::string expected = e.quantity == "anderson.kernel" ? "1-(r/delta)^2" : "r/delta";
    if (variable != expected) e.bad("printed.variable must be \"" + expected + "\" for " + e.quantity);
    return PrintedFormula{e, prefactor, delta_power, variable, D, std::move(sigma)};
}

const ClosedForm& single_piece(const Radial& f, const char* what, const std::string& spec) {
    if (f.pieces.size() != 1) fail(std::string("internal: ") + what + " of " + spec + " has several pieces");
    return f.pieces[0];
}

// B_delta(r) = delta^-D B(r/delta); B as a polynomial in u = 1 - s^2.
void check_kernel_formula(const PrintedFormula& f, const ExactKernel& k, const std::string& spec) {
    Laurent p;
    Atom factor;
    if (!single_piece(k.W, "kernel", spec).single_polynomial(&p, &factor)) fail("internal: kernel is not a polynomial");
    const std::vector<Q> u = p.even_part_in_square().taylor_at(Q(1));
    Coefficients exact;
    for (std::size_t i = 0; i < u.size(); ++i) add_coefficient(exact, static_cast<int>(i), exact_from(u[i], factor));
    const auto printed = f.e.coefficient_map(f.e.printed(), "coefficients", "printed");
    f.compare_bracket(printed, exact, [&](int n) { return "coefficient of " + f.var_power(n); });
    f.compare_delta("power of delta", -f.D);
}

// The additive part of phi_delta: c [* delta^p] [* log(delta)].
struct Additive {
    Exact c;
    int delta_power;
    bool log;
    bool operator==(const Additive& o) const { return c == o.c && delta_power == o.delta_power && log == o.log; }
    std::string str() const {
        return c.to_string() + (delta_power != 0 ? " * " + delta_string(delta_power) : "") + (log ? " * log(delta)" : "");
    }
};

// The additive term is the Green's function at r = delta: delta^(2-D) phi(1),
// plus g log(delta) in D = 2 (g the log r coefficient of the Green's function).
void check_additive_term(const PrintedFormula& f, const Radial& potential, const Exact& phi1) {
    std::vector<Additive> exact;
    if (!phi1.is_zero()) exact.push_back({phi1, 2 - f.D, false});
    for (const auto& [key, p] : potential.outside.terms())
        if (key.basis == Basis::log) exact.push_back({exact_from(p.coefficient(0), key.factor), 0, true});
    const Entry& e = f.e;
    const json& add = e.need(e.printed(), "additive", "printed");
    const Additive printed{
        Exact::pi_power(e.rational(add, "value", "printed.additive"), e.integer(add, "pi_power", "printed.additive")),
        e.integer(add, "delta_power", "printed.additive"), e.boolean(add, "log_delta", "printed.additive")};
    std::vector<std::string> exact_strings;
    for (const auto& a : exact) exact_strings.push_back(a.str());
    const bool same = exact.size() == 1 && exact[0] == printed;
    std::string remark;
    if (!same && exact.size() == 1 && exact[0].delta_power == printed.delta_power && exact[0].log == printed.log &&
        exact[0].c == -printed.c)
        remark = "sign differs: continuity with the exterior potential at r = delta needs " + exact[0].str();
    e.compare(same, "additive term", printed.str(), join(exact_strings, " + "), remark);
}

// phi_delta(r) = delta^(2-D) phi(r/delta) + [D = 2] g log(delta). Anderson's
// bracket vanishes at r = delta; the rest is the additive term.
void check_potential_formula(const PrintedFormula& f, const Radial& potential, const std::string& spec) {
    const Exact phi1 = potential.at(Q(1));
    Coefficients exact = coefficients(single_piece(potential, "potential", spec));
    add_coefficient(exact, 0, -phi1);
    const auto printed = f.e.coefficient_map(f.e.printed(), "coefficients", "printed");
    f.compare_bracket(printed, exact, [&](int n) { return "coefficient of " + f.var_power(n); });
    f.compare_delta("power of delta", 2 - f.D);
    check_additive_term(f, potential, phi1);
}

// d phi_delta / dx_i = delta^-D (phi'/s)(s) x_i, s = r/delta.
void check_gradient_formula(const PrintedFormula& f, const Quantities& qs, const std::string& spec) {
    const Coefficients exact = coefficients(single_piece(*qs.dpotential_over_r, "potential gradient", spec));
    const auto printed = f.e.coefficient_map(f.e.printed(), "coefficients", "printed");
    f.compare_bracket(printed, exact, [&](int n) { return "coefficient of " + f.var_power(n) + " x_i"; });
    f.compare_delta("power of delta", -f.D);
}

// Hessian: delta^-D [delta^-2 H(s) x_i x_j + (phi'/s)(s) eps_ij].
void check_hessian_formula(const PrintedFormula& f, const Quantities& qs, const std::string& spec) {
    const Coefficients xx = coefficients(single_piece(*qs.potential_hess_radial, "potential Hessian", spec));
    const Coefficients dij = coefficients(single_piece(*qs.dpotential_over_r, "potential gradient", spec));
    const auto printed_xx = f.e.coefficient_map(f.e.printed(), "xixj", "printed");
    const auto printed_dij = f.e.coefficient_map(f.e.printed(), "delta_ij", "printed");
    f.compare_bracket(printed_xx, xx, [&](int n) { return "x_i x_j coefficient of " + f.var_power(n); });
    f.compare_delta("x_i x_j term, power of delta", -f.D - 2);
    f.compare_bracket(printed_dij, dij, [&](int n) { return "epsilon_ij coefficient of " + f.var_power(n); });
    f.compare_delta("epsilon_ij term, power of delta", -f.D);
}

}  // namespace

void Checker::anderson_formula(const Entry& e) {
    const int D = e.param("D"), M = e.param("M"), order = e.param("order");
    const std::string spec = mollifier_spec(M, order);
    const ExactKernel& k = kernel(spec, D);
    const PrintedFormula f = read_formula(e, D, [this, D, M] { return table1_sigma(D, M); });
    if (e.quantity == "anderson.kernel") {
        check_kernel_formula(f, k, spec);
        return;
    }
    const Quantities& qs = quantities(spec, D);
    if (!qs.potential) fail("internal: no potential for " + spec);
    if (e.quantity == "anderson.potential") check_potential_formula(f, *qs.potential, spec);
    else if (e.quantity == "anderson.potential_gradient") check_gradient_formula(f, qs, spec);
    else check_hessian_formula(f, qs, spec);
}

}  // namespace mollify::gen::errata
