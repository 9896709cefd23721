// Verify anyone's kernel (issue 20): evaluate a kernel someone wrote (a C++
// callable, a function in a shared library, a column of a CSV file, Python)
// at the hard points and at seeded uniform points, compare it with the
// exact value (MPFR >= 200 bits from the generator's exact closed forms),
// and say in ulps how far it is, where it is worst and, when the error is
// systematic rather than rounding, why (a constant factor, a support
// convention, a gradient off by q, a wrong sign, another dimension's kernel,
// cancellation near the edge, single precision).
//
// Three steps, so that every front end shares them: samples() gives the
// arguments, the front end evaluates its kernel there however it can (in a
// child process, from a file), compare() judges the values; verify() is the
// three for a C++ callable. Link mollify::exact (GMP, MPFR); this header
// needs neither.
//
//   const auto report = mollify::verify::verify(my_w, "wendland:k=2", 3, mollify::verify::Quantity::value);
//   if (!report.passed()) std::cerr << report.to_string();
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mollify::verify {

// What the callable returns, in the convention's units of (r, h): W_h(r),
// dW_h/dr, the potential phi_h(r) and its derivative dphi_h/dr, and
// (dW_h/dr)/r, the factor of grad W = (W'/r) x that pair loops use, with its
// finite limit at r = 0 (mollify's quantities value, dr, potential,
// dpotential, grad_over_r).
enum class Quantity { value, dr, potential, force, grad_over_r };

// "value", "dr", "potential", "force", "grad_over_r".
std::string_view name(Quantity q);
// The quantity of a name above (also "dpotential" for force); mollify::Error
// naming the bad name and the known ones.
Quantity parse_quantity(std::string_view name);

struct Sample {
    double r, h;
};

// The most uniform points a verification takes (Options::uniform; each is an
// exact MPFR evaluation, ~10^5 a second).
inline constexpr std::size_t max_uniform_points = 100'000'000;

struct Options {
    // How (r, h) and the returned value relate to mollify's kernel
    // (generator/conventions.*): "cpp" or "mollify" (h = support radius H),
    // "phantom" (H = radkern h, phi = -1/r outside), "swift" (h = 2 sigma,
    // H = gamma h; errors in float ulps), "gadget4" (h = Hsml = H, g = -phi),
    // "c", "fortran", "python" (as cpp).
    std::string convention = "cpp";
    // The bound of passed(): the largest error allowed, in ulps of the exact
    // value (the convention's precision).
    double ulps = 4;
    // The uniform points' generator (a fixed algorithm: the same points on
    // every platform).
    std::uint64_t seed = 1;
    // How many uniform points besides the hard ones (at most max_uniform_points).
    std::size_t uniform = 10000;
};

// One evaluation: the arguments, the value given, the exact value (rounded
// to double) and the error in ulps of the exact value.
struct Point {
    double r, h, got, exact, ulps;
};

enum class DiagnosisKind {
    constant_factor,     // got = c * exact, c != 1 (a wrong normalisation)
    support_convention,  // got = W with h scaled: a factor 2, or gamma = H/h of a named convention
    gradient_factor,     // dr off by a factor q = r/H (or r, or 1/q)
    wrong_sign,          // got = -exact
    other_dimension,     // got = the same kernel in dimension D' != D
    edge_cancellation,   // error growing towards the support edge (expanded monomials)
    single_precision,    // errors ~2^29 ulps everywhere: evaluated in float
    not_finite,          // NaN or infinity where the exact value is finite
    unexplained,         // failed, and none of the above fits
};

// "constant factor", "support convention", ...
std::string_view name(DiagnosisKind kind);

struct Diagnosis {
    DiagnosisKind kind;
    std::string text;  // for people: e.g. "normalisation 3/(359 pi), exact 1/(120 pi)"
};

struct Report {
    std::string spec;        // canonical kernel spec
    int dim = 0;
    Quantity quantity = Quantity::value;
    std::string convention;
    double bound = 0;        // Options::ulps
    bool float_ulps = false; // errors in ulps of float (the convention is single precision)
    std::size_t points = 0;  // evaluations compared
    double max_ulps = 0;     // +inf when a value is NaN or infinite
    double rms_ulps = 0;     // over the points with a finite error
    std::vector<Point> worst;  // the largest errors, largest first (at most 5)
    std::optional<Diagnosis> diagnosis;  // when the error is systematic
    // The hard points of samples() (r = 0, the breakpoints, both sides of the
    // support edge, the h sweep: where kernels are most often wrong), and how
    // many of them are among the samples compared, bit for bit. Fewer than
    // all: the verdict holds for the given samples only.
    std::size_t hard_points = 0, hard_points_compared = 0;

    bool passed() const;
    // Every hard point among the samples compared.
    bool complete() const;
    // A table: kernel, quantity, points, max and RMS ulps, the verdict (on
    // the given samples only, where hard points are missing), the hard
    // points compared, the worst arguments and the diagnosis.
    std::string to_string() const;
};

// The arguments to evaluate at, in the convention's (r, h): the hard points
// (r = 0 and tiny r, H (1 - 2^-k) near the edge, the breakpoints of piecewise
// kernels, just inside and outside the edge, h from 1e-300 to 1e300 where the
// quantity is representable) then `uniform` seeded uniform points. Errors
// (mollify::Error) naming an unknown spec, convention or quantity, a
// dimension the kernel or the convention lacks, a quantity the kernel lacks.
std::vector<Sample> samples(std::string_view spec, int dim, Quantity quantity, const Options& options = {});

// The values someone computed at the samples, judged. values[i] belongs to
// samples[i]; the two spans must have the same size (Error otherwise). Any
// samples may be given; the report counts the hard points among them.
Report compare(std::string_view spec, int dim, Quantity quantity, std::span<const Sample> samples,
               std::span<const double> values, const Options& options = {});

// samples(), f at each, compare(). An exception thrown by f propagates.
Report verify(const std::function<double(double r, double h)>& f, std::string_view spec, int dim, Quantity quantity,
              const Options& options = {});

}  // namespace mollify::verify
