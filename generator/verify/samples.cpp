// Where a kernel is hard to evaluate, as data: r = 0 and tiny r (singular
// terms cancel), H (1 - 2^-k) (the edge factor (1 - q)^n is the whole
// value; expanded monomials cancel), the interior breakpoints of piecewise
// kernels and their neighbouring doubles (the wrong piece, a kink), the last
// doubles inside and the first outside the support, h from 1e-300 to 1e300
// wherever the quantity is representable, the far field of a potential,
// then seeded uniform points.
#include "verify/setup.hpp"

#include <mollify/smoothing.hpp>

#include <cmath>
#include <limits>
#include <random>

namespace mollify::verify {

namespace {

using detail::Setup;

// Smoothing lengths of the sweep (in the convention's h): decades, and
// ones that are not powers of two (so that r/h rounds).
constexpr double sweep_h[] = {1e-300, 1e-200, 1e-100, 1e-30, 1e-10, 1e-3, 0.3, 1, 3, 1e3, 1e10, 1e30, 1e100, 1e200, 1e300};

// r/H of the sweep (H the support radius).
constexpr double sweep_q[] = {0, 1e-5, 0.1, 0.25, 1.0 / 3, 0.5, 2.0 / 3, 0.75, 0.9, 0.99, 1 - 0x1p-20, 1, 1.5};

// The quantity at this h is a normal number of the convention's format,
// with room for the shape (2^16 either side), and so is every power h^p of
// the kernel's quantities (smoothing.hpp, scale_power): mollify's runtime
// refuses an h where one is not (detail/failures.hpp).
bool representable(const Setup& s, double h) {
    const int emax = s.single ? 127 : 1023, emin = s.single ? -126 : -1022;
    auto normal = [&](double m) { return std::isfinite(m) && m > 0 && std::ilogb(m) < emax - 16 && std::ilogb(m) > emin + 16; };
    const double H = static_cast<double>(detail::support_of(s, h));
    for (int i = 0; i < table::quantity_count; ++i) {
        const int p = mollify::detail::scale_power(static_cast<table::QuantityId>(i), s.dim);
        if (p != 0 && !normal(std::pow(H, p))) return false;
    }
    return normal(detail::magnitude(s, h));
}

double support_d(const Setup& s, double h) { return static_cast<double>(detail::support_of(s, h)); }

void add(std::vector<Sample>& out, double q, double h, const Setup& s) { out.push_back({q * support_d(s, h), h}); }

void origin_points(std::vector<Sample>& out, const Setup& s) {
    for (double h : {1.0, 0.3}) {
        out.push_back({0, h});
        out.push_back({std::numeric_limits<double>::denorm_min(), h});
        for (int k : {1, 2, 4, 8, 16, 26, 30, 40, 53, 60, 100, 300, 1000}) add(out, std::ldexp(1.0, -k), h, s);
    }
}

void edge_points(std::vector<Sample>& out, const Setup& s) {
    for (double h : {1.0, 0.3, 7.0}) {
        for (int k = 1; k <= 53; ++k) add(out, 1 - std::ldexp(1.0, -k), h, s);
        const double H = support_d(s, h);
        for (double r : {H, std::nextafter(H, 0.0), std::nextafter(std::nextafter(H, 0.0), 0.0),
                         std::nextafter(H, 2 * H), 1.5 * H, 2 * H})
            out.push_back({r, h});
    }
}

void breakpoint_points(std::vector<Sample>& out, const Setup& s) {
    const auto& breaks = s.reference->kernel().W.breaks;
    for (std::size_t i = 1; i + 1 < breaks.size(); ++i) {
        const double b = static_cast<double>(breaks[i]);
        for (double h : {1.0, 0.3})
            for (double q : {std::nextafter(b, 0.0), b, std::nextafter(b, 2.0)}) add(out, q, h, s);
    }
}

void sweep_points(std::vector<Sample>& out, const Setup& s) {
    for (double h : sweep_h) {
        if (!representable(s, h)) continue;
        for (double q : sweep_q) add(out, q, h, s);
    }
}

void far_points(std::vector<Sample>& out, const Setup& s) {
    if (!table::is_potential(s.id)) return;
    for (double h : {1.0, 0.3})
        for (double q : {1 + 0x1p-30, 2.0, 10.0, 1e3, 1e6}) add(out, q, h, s);
}

// r/H uniform in [0, 1.1]; h = 1 for half, log-uniform in [1e-3, 1e3]
// otherwise. std::mt19937_64 is specified exactly and the conversions are
// written out (std's distributions are not portable), so a seed gives the
// same points everywhere.
void uniform_points(std::vector<Sample>& out, const Setup& s, std::size_t count, std::uint64_t seed) {
    std::mt19937_64 gen(seed);
    auto unit = [&] { return static_cast<double>(gen() >> 11) * 0x1p-53; };
    for (std::size_t i = 0; i < count; ++i) {
        const double q = 1.1 * unit();
        const double h = i % 2 == 0 ? 1.0 : std::pow(10.0, -3 + 6 * unit());
        add(out, q, h, s);
    }
}

}  // namespace

std::vector<Sample> detail::hard_samples(const Setup& s) {
    std::vector<Sample> out;
    origin_points(out, s);
    edge_points(out, s);
    breakpoint_points(out, s);
    sweep_points(out, s);
    far_points(out, s);
    return out;
}

std::vector<Sample> samples(std::string_view spec, int dim, Quantity quantity, const Options& options) {
    const Setup s = detail::setup(spec, dim, quantity, options);
    std::vector<Sample> out = detail::hard_samples(s);
    uniform_points(out, s, options.uniform, options.seed);
    return out;
}

}  // namespace mollify::verify
