// --target phantom: a complete kernel_<id>.f90, Phantom's `module kernel`
// (../shared/peers.md, "Phantom": every symbol Phantom uses, q = r/h,
// support radkern h, W = cnormk w(q)/h^3, phi = -1/q outside for
// G = m = h = 1, fsoft = dphi/dq, dphidh = -phi - q dphi/dq).
//
// The kernel. mollify's kernel W_1 (unit mass, support 1) scaled to support
// H = radkern h is W = W_1(q/radkern) / (radkern h)^3, so Phantom's
// cnormk w(q) = W_1(q/radkern) / radkern^3. With W_1 = N s (s the kernel's
// unnormalised shape, N its normalisation): w(q) = s(q/radkern)/s(0) and
// cnormk = N s(0) / radkern^3 (w(0) = 1; s as it is where s(0) is not a nonzero rational), which is Phantom's own split (the cubic spline
// gives its w and cnormk = 1/pi; Wendland C2 its (1 - q/2)^4 (2q + 1) and
// 21/(16 pi)). radkern R = 2 for every kernel (the convention's support_in_h,
// Phantom's choice for the cubic and Wendland kernels; a power of two, so
// x = q/radkern is exact) but those Phantom ships with another (its quartic
// 5/2, quintic 3: conventions.hpp, support_multiple; x is then rounded
// once). Every function is one of mollify's factored tables in x on [0, 1]
// (Precision::fast), a Radial derived here exactly:
//   w = s(x), dw/dq = s'(x)/R, q^2 w = R^2 x^2 s(x),
//   phi(q) = G(x)/R with G = 4 pi phi_1 (-1/x outside; Delta phi_1 = W_1),
//   dphi/dq = G'(x)/R^2, dphidh = -phi - q dphi/dq = -(G + x G')/R,
//   gsoft = q d/dq(fsoft/q) = q phi'' - phi' = (x G'' - G')/R^2 (Phantom's
//     kernel_grad_soft: -3/q^2 outside).
// Constants, exact then correctly rounded: cnormk = 1/(4 pi int_0^R w q^2 dq),
// cnormk_drag = 1/(4 pi int_0^R q^4 w dq), wab0 = w(0), gradh0 = -3 w(0),
// dphidh0 = dphidh(0), av_factor = int q^4 w' / int q^3 w' (Meru & Bate
// 2012, eq. B21, as Phantom's scripts/kernels.py get_avdiss), hfact_default
// = phantom_hfact (conventions.hpp: equal standard deviation in units of the
// particle spacing as Phantom's cubic at 1.2).
#include "fortran_code.hpp"
#include "target.hpp"
#include "target_code.hpp"

#include "emit_round.hpp"
#include "error.hpp"
#include "rounding.hpp"

#include <cctype>
#include <cmath>
#include <optional>

namespace mollify::gen {

namespace {

// One function of x = q/radkern on [0, 1], and outside.
struct UnitFunction {
    std::string name;     // the private module function u_<name>(x)
    std::string meaning;  // for its comment
    Radial f;
    bool potential_like;  // nonzero outside / at the edge (emit_plan.hpp)
};

Radial x_times(const Radial& f, const Q& c, int power) { return f.times(Laurent::monomial(c, power)); }

// Phantom's split of W into cnormk w: w(0) = 1 (its stock kernels), where
// the shape's value at 0 is a nonzero rational; else the shape as it is.
std::optional<Q> rational_at_zero(const ExactKernel& k) {
    if (!k.shape.form_at(Q(0)).is_elementary()) return std::nullopt;
    try {
        const Exact s0 = k.shape.at(Q(0));
        if (s0.is_rational() && s0.rational() != 0) return s0.rational();
    } catch (const Error&) {  // singular at 0 (the viscosity kernel's 1/r)
    }
    return std::nullopt;
}
Q shape_scale(const ExactKernel& k) {
    const std::optional<Q> s0 = rational_at_zero(k);
    return s0 ? Q(1) / *s0 : Q(1);
}
Radial phantom_shape(const ExactKernel& k) { return k.shape * Exact(shape_scale(k)); }

// The functions of x = q/R on [0, 1], R = radkern: q = R x, d/dq = (1/R) d/dx.
std::vector<UnitFunction> unit_functions(const KernelFacts& facts, const Q& R) {
    const ExactKernel& k = facts.kernel;
    const Radial* phi1 = quantity_of(facts, static_cast<int>(table::QuantityId::potential));
    if (!phi1) fail("--target phantom: " + facts.spec + " has no Poisson potential (Phantom's kernel_softening needs one)");
    const Radial s = phantom_shape(k);
    const Radial G = *phi1 * sphere_measure(3);
    const Radial dG = G.derivative();
    const std::string r = short_string(R), r2 = short_string(R * R);
    return {
        {"w", "w(q) = s(x)", s, false},
        {"grkern", "dw/dq = s'(x)/" + r, s.derivative() * Exact(Q(1) / R), false},
        {"drag", "q^2 w(q) = " + r2 + " x^2 s(x)", x_times(s, R * R, 2), false},
        {"phi", "phi(q) = G(x)/" + r + ", G = 4 pi phi_1", G * Exact(Q(1) / R), true},
        {"fsoft", "dphi/dq = G'(x)/" + r2, dG * Exact(Q(1) / (R * R)), true},
        {"dphidh", "-phi - q dphi/dq = -(G + x G')/" + r, (G + x_times(dG, Q(1), 1)) * Exact(Q(-1) / R), false},
        {"gsoft", "q phi'' - phi' = (x G'' - G')/" + r2, (x_times(dG.derivative(), Q(1), 1) - dG) * Exact(Q(1) / (R * R)),
         true},
    };
}

// A constant and its exact value for the comment, correctly rounded
// (rounding.hpp: exact for rationals, Ziv's loop with a rigorous error bound
// for pi and logarithms, an Error where that cannot decide).
struct Constant {
    double value;
    std::string exact;
};

Constant constant(const Exact& x) { return {round_to_double(x), x.to_string()}; }

// f(0) times scale; a missing Wendland function's S and arcsech are singular
// at 0 (0 * inf), its value there the exact limit (series.hpp).
Constant at_zero(const Radial& f, const Q& scale) { return constant(value_at(f.form_at(Q(0)), Q(0)) * scale); }

// a/b, correctly rounded: exact where both are rational or b is q pi^e;
// else (a sum with logarithms: the missing Wendland functions) Ziv's loop
// on the quotient's enclosure (rounding.hpp).
Constant ratio(const Exact& a, const Exact& b) {
    if (b.is_zero()) fail("--target phantom: a zero denominator (" + a.to_string() + " / 0)");
    if (a.is_rational() && b.is_rational()) return constant(Exact(a.rational() / b.rational()));
    if (b.terms().size() == 1 && b.terms().begin()->first.log_of == 1) return constant(a * b.inverse());
    return {round_quotient_to_double(a, b),
            "(" + a.to_string() + ") / (" + b.to_string() + ") = " + decimal_quotient(a, b, 21) + " (correctly rounded)"};
}

// A real parameter: its bits, the exact value beside it.
std::string parameter(const std::string& name, const Constant& c) {
    return " real, parameter, public :: " + name + " = " + boz(c.value) + "  ! " + c.exact + "\n";
}
std::string parameter(const std::string& name, const Exact& x) { return parameter(name, constant(x)); }

// One private function of x in the runtime's fast form (write_fortran.cpp's pieces).
std::string unit_function(const UnitFunction& u, const CodeQuantity& q, const Syntax& s) {
    const std::string name = "u_" + u.name;
    std::string out = "\n ! " + u.meaning + ", x = q/radkern\n";
    out += " pure function " + name + "(q) result(y)\n  real(c_double), intent(in) :: q\n  real(c_double) :: y@E@\n";
    const std::string body = fortran_piece_chain(q, s, "  ", " ");
    const std::string outside = piece_sum(s, q.exterior, true);
    const std::string code = without_comments(body, "!", "\n");
    const bool r_used = uses(code, "r") || uses(outside, "r"), h_used = uses(code, "h"), e_used = uses(code, "e");
    out.replace(out.find("@E@"), 3, std::string(r_used ? ", r" : "") + (h_used ? ", h" : "") + (e_used ? ", e" : ""));
    out += std::string(r_used ? "  r = q\n" : "") + (h_used ? "  h = 1.0_c_double\n" : "");
    out += "  if (q > 1.0_c_double) then\n   y = " + continued(outside) + "\n   return\n  end if\n";
    out += std::string(e_used ? "  e = 1.0_c_double - q\n" : "") + body;
    out += " end function " + name + "\n";
    return out;
}

// Phantom's public procedures (peers.md's list), each a call of the u_ functions at x = q/radkern.
std::string public_procedures() {
    return R"(
 pure subroutine get_kernel(q2,q,wkern,grkern)
  real, intent(in)  :: q2,q
  real, intent(out) :: wkern,grkern
  wkern  = u_w(q/radkern)
  grkern = u_grkern(q/radkern)
 end subroutine get_kernel

 pure elemental real function wkern(q2,q)
  real, intent(in) :: q2,q
  wkern = u_w(q/radkern)
 end function wkern

 pure elemental real function grkern(q2,q)
  real, intent(in) :: q2,q
  grkern = u_grkern(q/radkern)
 end function grkern

 pure subroutine get_kernel_grav1(q2,q,wkern,grkern,dphidh)
  real, intent(in)  :: q2,q
  real, intent(out) :: wkern,grkern,dphidh
  wkern  = u_w(q/radkern)
  grkern = u_grkern(q/radkern)
  dphidh = u_dphidh(q/radkern)
 end subroutine get_kernel_grav1

 ! potensoft = phi(q), -1/q for q >= radkern; fsoft = dphi/dq, 1/q^2 outside
 pure subroutine kernel_softening(q2,q,potensoft,fsoft)
  real, intent(in)  :: q2,q
  real, intent(out) :: potensoft,fsoft
  potensoft = u_phi(q/radkern)
  fsoft     = u_fsoft(q/radkern)
 end subroutine kernel_softening

 ! gsoft = q d/dq (fsoft/q) = q phi'' - phi' (-3/q^2 outside), as Phantom's stock kernels
 pure subroutine kernel_grad_soft(q2,q,gsoft)
  real, intent(in)  :: q2,q
  real, intent(out) :: gsoft
  gsoft = u_gsoft(q/radkern)
 end subroutine kernel_grad_soft

 ! the double hump q^2 w(q), normalised by cnormk_drag
 pure elemental real function wkern_drag(q2,q)
  real, intent(in) :: q2,q
  wkern_drag = u_drag(q/radkern)
 end function wkern_drag
)";
}

}  // namespace

TargetFiles write_phantom(const TargetKernel& tk, const std::string& command) {
    const KernelFacts& facts = tk.facts;
    const ExactKernel& k = facts.kernel;
    if (k.dim != 3)
        fail("--target phantom: Phantom is 3D only; " + facts.spec + " was asked in D = " + std::to_string(k.dim) +
             " (use --dim 3)");
    const Q radkern = support_multiple(tk.convention, k);
    const bool exact_x = radkern == Q(2);  // a power of two: q/radkern exact

    const std::vector<UnitFunction> functions = unit_functions(facts, radkern);
    std::vector<std::vector<RoundedPiece>> rounded;
    for (const UnitFunction& u : functions) {
        auto r = rounded_quantity(&u.f, u.potential_like, {});
        if (!r) fail("internal: --target phantom: " + u.name + " of " + facts.spec + " did not round");
        rounded.push_back(std::move(*r));
    }
    std::vector<CodeConstant> constants;
    Literals literals;
    const Syntax s = fortran_syntax(literals);
    std::string body;
    for (std::size_t i = 0; i < functions.size(); ++i)
        body += unit_function(functions[i], code_quantity(functions[i].name, rounded[i], constants), s);

    // Exact constants (file comment above).
    const Radial w = phantom_shape(k);
    const Exact four_pi = sphere_measure(3);
    const Exact r5 = Exact(radkern * radkern * radkern * radkern * radkern);
    // = 1/(4 pi int_0^radkern w q^2 dq); with w(0) = 1 the convention's separate_normalisation (conventions.hpp)
    const bool unit = rational_at_zero(k).has_value();
    const Exact cnormk = unit ? separate_normalisation(tk.convention, k)
                             : k.normalisation * (Q(1) / (radkern * radkern * radkern));
    const Exact m4 = radial_integral(w, 4);  // the 3D second moment / 4 pi
    if (m4.is_zero() || (m4.is_rational() && m4.rational() < 0))
        fail("--target phantom: " + facts.spec + " has second moment " + m4.to_string() +
             " <= 0 (a higher-order kernel): Phantom's cnormk_drag (the double hump q^2 w) and hfact_default need a "
             "positive one");
    const Constant cnormk_drag = ratio(Exact(Q(1)), four_pi * r5 * radial_integral(w, 4));
    const Constant wab0 = at_zero(w, Q(1)), gradh0 = at_zero(w, Q(-3));
    const Constant dphidh0 = at_zero(functions[5].f, Q(1));
    const Exact av_num = radial_integral(w.derivative(), 4), av_den = radial_integral(w.derivative(), 3);
    if (av_den.is_zero())  // a step kernel (box): w' = 0 inside, its jump at the edge is no function
        fail("--target phantom: " + facts.spec + " has w' = 0 inside its support (a step kernel): Phantom's grkern "
             "and av_factor = int q^4 w' dq / int q^3 w' dq (Meru & Bate 2012, eq. B21; here 0/0) need a "
             "differentiable kernel");
    const Constant av_factor = ratio(av_num * radkern, av_den);
    const DerivedConstant hfact = phantom_hfact(k);

    std::string name = facts.spec;
    std::string out = banner(command, "!");
    out += "!\n! Phantom's kernel module (src/main/kernel_<NAME>.f90, KERNEL=<NAME>) for " + facts.spec + ":\n! " +
           k.source + "\n";
    out += "! q = r/h, support radkern h, W = cnormk w(q)/h^3, |grad W| = cnormk grkern/h^4 (3D only).\n"
           "! w(q) = s(q/radkern)/s(0), s the kernel's shape on support 1; cnormk = N s(0)/radkern^3 (N: s's\n"
           "! unit-mass normalisation). " +
           std::string(exact_x ? "radkern = 2 for every kernel (Phantom's choice for the cubic and Wendland kernels):\n"
                                 "! a power of two, so q/radkern is exact."
                               : "radkern = " + short_string(radkern) + ", Phantom's own for this kernel (its stock " +
                                     "kernel file), so h means\n! what it means there; q/radkern is rounded once.") +
           " phi is the kernel's exact Poisson potential (mollify's, times\n"
           "! 4 pi, scaled to support radkern): phi = -1/q outside, dphidh = -phi - q dphi/dq.\n"
           "! hfact_default: " + hfact.rule + ";\n!   hfact_default^2 = " + short_string(hfact.square) + " exactly.\n"
           "! av_factor = int q^4 w' dq / int q^3 w' dq (Meru & Bate 2012, eq. B21).\n"
           "! Evaluated as mollify's Precision::fast; every constant correctly rounded, its exact value beside it.\n"
           "! Compile with Phantom's -fdefault-real-8 (real is c_double).\n";
    out += "module kernel\n use, intrinsic :: iso_c_binding, only: c_double\n implicit none\n private\n";
    out += " character(len=*), parameter, public :: kernelname = '" + name + "'\n";
    out += parameter("radkern", Exact(radkern)) + parameter("radkern2", Exact(radkern * radkern));
    out += parameter("cnormk", cnormk) + parameter("wab0", wab0) + parameter("gradh0", gradh0);
    out += parameter("dphidh0", dphidh0) + parameter("cnormk_drag", cnormk_drag);
    out += " real, parameter, public :: hfact_default = " + boz(hfact.value) + "  ! " + sqrt_text(hfact.square) + "\n";
    out += parameter("av_factor", av_factor);
    out += " public :: get_kernel, get_kernel_grav1, wkern, grkern, kernel_softening, kernel_grad_soft, wkern_drag\n";
    bool log1p = false;
    const std::string helpers = used_helpers(body, log1p);
    if (log1p)
        out += " interface\n  pure function c_log1p(x) bind(C, name=\"log1p\") result(y)\n   import :: c_double\n"
               "   real(c_double), value, intent(in) :: x\n   real(c_double) :: y\n  end function c_log1p\n"
               " end interface\n";
    out += " ! The coefficients of every piece, in order (function, piece, term, power).\n";
    const std::size_t part = 200, parts = (constants.size() + part - 1) / part;
    for (std::size_t j = 0; j < parts; ++j) {
        const std::size_t begin = j * part, end = std::min(constants.size(), begin + part);
        out += " real(c_double), parameter :: c_part_" + std::to_string(j) + "(" + std::to_string(end - begin) + ") = [ &\n";
        for (std::size_t i = begin; i < end; ++i)
            out += "  " + boz(constants[i].value) + (i + 1 < end ? ", &" : " ]") + "  ! [" + std::to_string(i) + "] " +
                   constants[i].exact + "\n";
    }
    out += " real(c_double), parameter :: c(0:" + std::to_string(constants.size() - 1) + ") = [ &\n";
    for (std::size_t j = 0; j < parts; ++j) out += "  c_part_" + std::to_string(j) + (j + 1 < parts ? ", &\n" : " ]\n");
    out += " ! Piece bounds, edges and centres (doubles; their exact values in the pieces' comments).\n";
    if (literals.values.empty()) literals.values.push_back(0.0);
    out += " real(c_double), parameter :: b(0:" + std::to_string(literals.values.size() - 1) + ") = [ &\n  real(c_double) ::";
    for (std::size_t i = 0; i < literals.values.size(); ++i) out += (i ? ", &\n  " : " &\n  ") + boz(literals.values[i]);
    out += " ]\n\ncontains\n" + public_procedures() + helpers + body + "\nend module kernel\n";
    return {{"phantom/kernel_" + facts.id + ".f90", out}};
}

}  // namespace mollify::gen
