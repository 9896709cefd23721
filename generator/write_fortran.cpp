// --target fortran: one Fortran 2008 module per kernel and dimension,
// fortran/<prefix>.f90 (module mollify_<identifier>, lower case), with the
// kernel's constants as real(c_double) parameters (their bits as BOZ
// literals, exact; the exact value beside each) and bind(C) pure functions
// kernel_<q>(r) (h = 1) and kernel_<q>_h(r, h) = h^p f(r/h) in mollify's
// convention, evaluated in the runtime's Precision::fast form
// (target_code.hpp). Fortran 2008 has no fused multiply-add: the distances
// (a h - r)/h and (r - c h)/h round c h first (as the runtime does without
// an FMA: an absolute error <= c 2^-53, the size of the rounding of q).
#include "fortran_code.hpp"
#include "target.hpp"
#include "target_code.hpp"

#include "error.hpp"
#include "rounding.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <set>

namespace mollify::gen {

// The bits of a double as a Fortran constant: real(z'...', c_double) is the
// double with exactly these bits (F2008 13.7.138).
std::string boz(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "real(z'%016llX', c_double)",
                  static_cast<unsigned long long>(std::bit_cast<std::uint64_t>(x)));
    return buf;
}

// The evaluation helpers of mollify's Precision::fast form
// (include/mollify/detail/evaluate.hpp); a module contains those it uses
// (gfortran -Wall warns of unused private procedures).
const std::vector<Helper>& fortran_helpers() {
    static const std::vector<Helper> all = {
        // a(n) of explicit shape, n given: gfortran -O3 inlines it and
        // unrolls its loop, where an assumed-shape a(:) (a descriptor) left a
        // call and a loop (bench/phantom_kernel_bench.sh, Phantom's flags:
        // its get_kernel of the quintic spline 1.34 -> 1.06x the stock
        // file's time, of the quartic 1.30 -> 1.04x; README, "Phantom's
        // `get_kernel`, stock against mollify's").
        {"horner", {}, R"(
  pure function horner(a, n, v) result(y)
    integer, intent(in) :: n
    real(c_double), intent(in) :: a(n), v
    real(c_double) :: y
    integer :: k
    y = a(n)
    do k = n - 1, 1, -1
      y = y * v + a(k)
    end do
  end function horner
)"},
        {"shifted", {}, R"(
  ! r/h - centre of a Taylor piece, the centre's own rounding c_lo after
  pure function shifted(r, h, centre, centre_lo) result(y)
    real(c_double), intent(in) :: r, h, centre, centre_lo
    real(c_double) :: y
    y = (r - centre * h) / h - centre_lo
  end function shifted
)"},
        {"to_edge", {}, R"(
  ! (a h - r)/h: the distance to a combination's inner radius a
  pure function to_edge(r, h, a) result(y)
    real(c_double), intent(in) :: r, h, a
    real(c_double) :: y
    y = (a * h - r) / h
  end function to_edge
)"},
        {"sqrt_s", {}, R"(
  ! S = sqrt(1 - q^2) from the accurate edge distance e = 1 - q
  pure function sqrt_s(q, e) result(y)
    real(c_double), intent(in) :: q, e
    real(c_double) :: y
    y = sqrt(e * (1.0_c_double + q))
  end function sqrt_s
)"},
        {"arcsech", {"sqrt_s", "c_log1p"}, R"(
  ! arcsech q = log((1 + S)/q): two positive logs near 0, log1p of a small number near 1
  pure function arcsech(q, e) result(y)
    real(c_double), intent(in) :: q, e
    real(c_double) :: y, s
    s = sqrt_s(q, e)
    if (q < 0.5_c_double) then
      y = c_log1p(s) - log(q)
    else
      y = c_log1p((e + s) / q)
    end if
  end function arcsech
)"},
        {"log_q", {"c_log1p"}, R"(
  pure function log_q(q, e) result(y)
    real(c_double), intent(in) :: q, e
    real(c_double) :: y
    if (q < 0.5_c_double) then
      y = log(q)
    else
      y = c_log1p(-e)
    end if
  end function log_q
)"},
        {"times_arcsech", {"arcsech"}, R"(
  ! x arcsech q and x log q where x carries a positive power of q: the limit 0 at q = 0
  pure function times_arcsech(x, q, e) result(y)
    real(c_double), intent(in) :: x, q, e
    real(c_double) :: y
    y = 0.0_c_double
    if (q > 0.0_c_double) y = x * arcsech(q, e)
  end function times_arcsech
)"},
        {"times_log", {"log_q"}, R"(
  pure function times_log(x, q, e) result(y)
    real(c_double), intent(in) :: x, q, e
    real(c_double) :: y
    y = 0.0_c_double
    if (q > 0.0_c_double) y = x * log_q(q, e)
  end function times_log
)"},
        {"at_origin", {}, R"(
  ! a quantity singular at r = 0: its limit (+-inf) where its terms give inf - inf or 0 * inf
  pure function at_origin(x, limit) result(y)
    real(c_double), intent(in) :: x, limit
    real(c_double) :: y
    y = x
    if (ieee_is_nan(x)) y = limit
  end function at_origin
)"},
        {"near_origin", {}, std::string(R"(
  ! f_h(r) = h^p f(r/h) of a quantity singular at r = 0, where r/h < 2^-150: its leading order
  ! h^p q^low (plain + logarithm log q) (the terms beyond it are below 2^-150 of it), with q = m 2^e
  ! and h = mh 2^eh taken apart so that neither q^low nor h^p overflows alone (f(r/h) first
  ! overflows below r/h ~ 1e-100 where f_h is finite for a large h)
  pure function near_origin(r, h, p, low, plain, logarithm) result(y)
    real(c_double), intent(in) :: r, h, plain, logarithm
    integer, intent(in) :: p, low
    real(c_double) :: y, m, mh, f
    integer :: ex, eh
    mh = fraction(h)
    eh = exponent(h)
    m = fraction(r) / mh
    ex = exponent(r) - eh
    ! m in (1/2, 2) as r > 0, so log(m) is finite and logarithm = 0 adds 0 (no real
    ! comparison: gfortran's -Wextra flags one, -Wcompare-reals)
    f = plain + logarithm * (log(m) + real(ex, c_double) * &
      )") + boz(round_to_double(Exact::log_of(Q(2)))) + R"()  ! log(2)
    y = scale(f * m**low * mh**p, ex * low + eh * p)
  end function near_origin
)"},
        {"arcsin", {"sqrt_s"}, R"(
  ! arcsin q as atan2(q, S): asin would magnify the rounding of q by 1/S near q = 1
  pure function arcsin(q, e) result(y)
    real(c_double), intent(in) :: q, e
    real(c_double) :: y
    y = atan2(q, sqrt_s(q, e))
  end function arcsin
)"},
    };
    return all;
}

// The helpers `functions` calls, with those they call, in fortran_helpers'
// order; and whether C's log1p is needed.
std::string used_helpers(const std::string& functions, bool& log1p) {
    std::set<std::string> used;
    for (const Helper& h : fortran_helpers())
        if (uses(functions, h.name)) used.insert(h.name);
    for (bool grown = true; grown;) {
        grown = false;
        for (const Helper& h : fortran_helpers())
            if (used.count(h.name))
                for (const std::string& u : h.uses) grown = used.insert(u).second || grown;
    }
    log1p = used.count("c_log1p") > 0;
    std::string out = "\n  ! The evaluation helpers of mollify's Precision::fast form\n"
                      "  ! (include/mollify/detail/evaluate.hpp).\n";
    for (const Helper& h : fortran_helpers())
        if (used.count(h.name)) out += h.code;
    return out;
}

std::string Literals::operator()(double x) {
    if (x == 0 && !std::signbit(x)) return "0.0_c_double";
    for (std::size_t i = 0; i < values.size(); ++i)
        if (std::bit_cast<std::uint64_t>(values[i]) == std::bit_cast<std::uint64_t>(x)) return "b(" + std::to_string(i) + ")";
    values.push_back(x);
    return "b(" + std::to_string(values.size() - 1) + ")";
}

Syntax fortran_syntax(Literals& literals) {
    Syntax s;
    s.constant = [](std::size_t i) { return "c(" + std::to_string(i) + ")"; };
    s.horner = [](std::size_t first, std::size_t n, const std::string& v) {
        if (n == 1) return "c(" + std::to_string(first) + ")";
        return "horner(c(" + std::to_string(first) + ":" + std::to_string(first + n - 1) + "), " + std::to_string(n) + ", " +
               v + ")";
    };
    s.power = [](const std::string& x, int n) {
        if (n == 1) return x;
        return x + "**" + (n < 0 ? "(" + std::to_string(n) + ")" : std::to_string(n));
    };
    s.literal = [&literals](double x) { return literals(x); };
    s.call = [](const std::string& name, const std::vector<std::string>& args) {
        std::string out = name + "(";
        for (std::size_t i = 0; i < args.size(); ++i) out += (i ? ", " : "") + args[i];
        return out + ")";
    };
    s.log = "log";
    s.infinity = "ieee_value(1.0_c_double, ieee_positive_inf)";
    return s;
}

// A sum of terms over several lines, continued with '&'.
std::string continued(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '\n') out += " &";
        out += c;
    }
    return out;
}

std::string fortran_piece_chain(const CodeQuantity& q, const Syntax& s, const std::string& indent, const std::string& inner) {
    std::string body;
    for (std::size_t p = 0; p < q.inside.size(); ++p) {
        const CodePiece& piece = q.inside[p];
        const bool last = p + 1 == q.inside.size();
        body += indent + "! " + piece.note + "\n";
        if (q.inside.size() > 1)
            body += indent + (last ? std::string("else\n")
                                   : std::string(p == 0 ? "if" : "else if") + " (q < " + s.literal(q.inside[p + 1].lo) + ") then\n");
        body += indent + inner + "y = " + continued(inside_piece(s, q, p)) + "\n";
    }
    if (q.inside.size() > 1) body += indent + "end if\n";
    return body;
}

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// The module's name: the prefix in lower case; beyond Fortran's 63
// characters (F2008 3.2.2; long radii lists of combinations) its first 54
// and 8 hex digits of the FNV-1a hash of the whole, so distinct kernels keep
// distinct modules.
std::string module_name(const std::string& prefix) {
    const std::string name = lower(prefix);
    if (name.size() <= 63) return name;
    std::uint32_t hash = 2166136261u;
    for (char c : name) hash = (hash ^ static_cast<unsigned char>(c)) * 16777619u;
    char tail[16];
    std::snprintf(tail, sizeof tail, "_%08x", static_cast<unsigned>(hash));
    return name.substr(0, 54) + tail;
}

std::string fortran_function(const CodeKernel& k, const CodeQuantity& q, const Syntax& s) {
    const std::string name = "kernel_" + q.name;
    std::string out = "\n  ! " + quantity_description(q.id) + ": f_h(r) = h^(" + std::to_string(q.scale_power) +
                      ") f(r/h)" + (q.log_h_coefficient ? " + log(h)/(2 pi)" : "") + "\n";
    out += "  pure function " + name + "_h(r, h) &\n      bind(C, name=\"" + k.prefix + "_f90_" + q.name + "_h\") result(y)\n";
    out += "    real(c_double), value, intent(in) :: r, h\n    real(c_double) :: y@E@\n";
    out += "    if (.not. (r >= 0.0_c_double) .or. .not. (h > 0.0_c_double) .or. .not. ieee_is_finite(h)) then\n";
    out += "      y = ieee_value(y, ieee_quiet_nan)  ! r >= 0 and a finite h > 0\n      return\n    end if\n";
    if (q.near_origin) {
        const CodeQuantity::NearOrigin& o = *q.near_origin;
        out += "    if (r > 0.0_c_double .and. r < " + s.literal(detail::near_origin_bound) + " * h) then  ! below r/h = 2^-150: h^p q^" +
               std::to_string(o.low) + " (a + b log q),\n      ! a = " + o.plain.exact + ", b = " + o.logarithm.exact + "\n";
        out += "      y = near_origin(r, h, " + std::to_string(q.scale_power) + ", " + std::to_string(o.low) + ", " +
               s.literal(o.plain.value) + ", " + s.literal(o.logarithm.value) + ")\n      return\n    end if\n";
    }
    out += "    if (r > h) then\n      y = " + continued(piece_sum(s, q.exterior, true)) + "\n      return\n    end if\n";
    const std::string body = fortran_piece_chain(q, s, "    ", "  ");
    const std::string code = without_comments(body, "!", "\n");
    const bool q_used = uses(code, "q"), e_used = uses(code, "e");
    out.replace(out.find("@E@"), 3, std::string(q_used ? ", q" : "") + (e_used ? ", e" : ""));
    out += std::string(q_used ? "    q = r / h\n" : "") + (e_used ? "    e = (h - r) / h\n" : "") + body;
    out += "    y = y * h**real(" + std::to_string(q.scale_power) + ", c_double)\n";
    if (q.log_h_coefficient) out += "    y = y + " + s.constant(*q.log_h_coefficient) + " * log(h)\n";
    out += "  end function " + name + "_h\n\n";
    out += "  pure function " + name + "(r) &\n      bind(C, name=\"" + k.prefix + "_f90_" + q.name + "\") result(y)\n";
    out += "    real(c_double), value, intent(in) :: r\n    real(c_double) :: y\n";
    out += "    y = " + name + "_h(r, 1.0_c_double)\n  end function " + name + "\n";
    return out;
}

}  // namespace

TargetFiles write_fortran(const TargetKernel& tk, const std::string& command) {
    const CodeKernel k = code_kernel(tk);
    const std::string module = module_name(k.prefix);
    Literals literals;
    const Syntax s = fortran_syntax(literals);
    std::string functions, names;
    for (const CodeQuantity& q : k.quantities) {
        functions += fortran_function(k, q, s);
        names += "  public :: kernel_" + q.name + ", kernel_" + q.name + "_h\n";
    }
    std::string out = banner(command, "!");
    out += "!\n! " + k.spec + " in D = " + std::to_string(k.dim) + ": " + tk.facts.kernel.source + "\n";
    out += "! mollify's convention: support radius h (q = r/h <= 1), W_h(r) = h^-" + std::to_string(k.dim) +
           " W(r/h), unit mass;\n! " + tk.convention.potential.description +
           ".\n! kernel_<quantity>(r) is h = 1, kernel_<quantity>_h(r, h) any h; r >= 0, h > 0 finite (else NaN).\n"
           "! bind(C) names: " + k.prefix + "_f90_<quantity>[_h]. Evaluated as mollify's Precision::fast.\n"
           "! Each constant is correctly rounded (its bits as a BOZ literal), its exact value beside it.\n";
    out += "module " + module + "\n  use, intrinsic :: iso_c_binding, only: c_double\n";
    out += "  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, ieee_is_finite, ieee_is_nan\n";
    out += "  implicit none\n  private\n  public :: dim, normalisation, c, b\n" + names + "\n";
    bool log1p = false;
    const std::string helpers = used_helpers(functions, log1p);
    if (log1p)
        out += "  interface\n    pure function c_log1p(x) bind(C, name=\"log1p\") result(y)\n      import :: c_double\n"
               "      real(c_double), value, intent(in) :: x\n      real(c_double) :: y\n    end function c_log1p\n"
               "  end interface\n\n";
    out += "  integer, parameter :: dim = " + std::to_string(k.dim) + "\n";
    out += "  real(c_double), parameter :: normalisation = " + boz(k.normalisation.value) + "  ! " + k.normalisation.exact + "\n";
    out += "  ! The coefficients of every piece, in order (quantity, piece, term, power).\n";
    // In parts of at most 200 (a statement has at most 255 continuation lines, F2008 3.3.2.4).
    const std::size_t part = 200, parts = (k.constants.size() + part - 1) / part;
    for (std::size_t j = 0; j < parts; ++j) {
        const std::size_t begin = j * part, end = std::min(k.constants.size(), begin + part);
        out += "  real(c_double), parameter, private :: c_part_" + std::to_string(j) + "(" + std::to_string(end - begin) +
               ") = [ &\n";
        for (std::size_t i = begin; i < end; ++i)
            out += "    " + boz(k.constants[i].value) + (i + 1 < end ? ", &" : " ]") + "  ! [" + std::to_string(i) + "] " +
                   k.constants[i].exact + "\n";
    }
    out += "  real(c_double), parameter :: c(0:" + std::to_string(k.constants.size() - 1) + ") = [ &\n";
    for (std::size_t j = 0; j < parts; ++j) out += "    c_part_" + std::to_string(j) + (j + 1 < parts ? ", &\n" : " ]\n");
    // b: the piece bounds, edges and centres the functions use (collected while writing them).
    out += "  ! Piece bounds, edges and centres, leading orders at 0 (doubles; their exact values in the pieces'\n"
           "  ! and functions' comments).\n";
    out += "  real(c_double), parameter :: b(0:" + std::to_string(static_cast<long>(literals.values.size()) - 1) + ") = [ &\n";
    out += "    real(c_double) ::";
    for (std::size_t i = 0; i < literals.values.size(); ++i) out += (i ? ", &\n    " : " &\n    ") + boz(literals.values[i]);
    out += " ]\n\ncontains\n" + helpers + functions + "\nend module " + module + "\n";
    return {{"fortran/" + k.prefix + ".f90", out}};
}

}  // namespace mollify::gen
