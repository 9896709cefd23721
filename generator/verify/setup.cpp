#include "verify/setup.hpp"

#include "error.hpp"

#include <mollify/smoothing.hpp>
#include <mollify/spec.hpp>

#include <cmath>
#include <deque>
#include <limits>
#include <mutex>
#include <utility>

namespace mollify::verify::detail {

namespace {

constexpr unsigned digits = 100;  // ~330 bits: beyond the reference's 200

// "mollify" is another name of mollify's own convention, the target cpp.
const gen::Convention& find_convention(const std::string& name) {
    if (name == "mollify") return find_convention("cpp");
    std::string known = "mollify";
    for (const gen::Convention& c : gen::conventions()) {
        if (c.target == name) return c;
        known += ", " + c.target;
    }
    fail("unknown convention '" + name + "' (known: " + known + ")");
}

table::QuantityId quantity_id(Quantity q) {
    switch (q) {
        case Quantity::value: return table::QuantityId::value;
        case Quantity::dr: return table::QuantityId::dr;
        case Quantity::potential: return table::QuantityId::potential;
        case Quantity::force: return table::QuantityId::dpotential;
        case Quantity::grad_over_r: return table::QuantityId::grad_over_r;
    }
    fail("unknown verify::Quantity " + std::to_string(static_cast<int>(q)));
}

Real to_real(const gen::Q& q) {
    Real x(0, digits);
    mpfr_set_q(x.backend().data(), q.backend().data(), MPFR_RNDN);
    return x;
}

// H / h of the convention, squared (exact).
gen::Q support_square(const gen::Convention& c, const gen::ExactKernel& k) {
    switch (c.support) {
        case gen::SupportRule::support:
        case gen::SupportRule::fixed_multiple: {
            const gen::Q m = gen::support_multiple(c, k);
            return m * m;
        }
        case gen::SupportRule::twice_sigma: return gen::swift_gamma(k).square;
    }
    fail("convention " + c.target + ": unknown support rule");
}

}  // namespace

std::shared_ptr<const accuracy::Reference> reference(const std::string& spec, int dim) {
    static std::mutex mutex;
    static std::deque<std::pair<std::string, std::shared_ptr<const accuracy::Reference>>> kept;
    const std::string key = spec + "|" + std::to_string(dim);
    {
        const std::lock_guard lock(mutex);
        for (const auto& [k, r] : kept)
            if (k == key) return r;
    }
    auto r = std::make_shared<const accuracy::Reference>(spec, dim);
    const std::lock_guard lock(mutex);
    kept.emplace_back(key, r);
    if (kept.size() > 8) kept.pop_front();
    return r;
}

Setup setup(std::string_view spec, int dim, Quantity quantity, const Options& options) {
    Setup s;
    s.spec = spec_string(parse_spec(spec));
    if (dim < 1 || dim > 3) fail("dimension " + std::to_string(dim) + " is not 1, 2 or 3");
    s.dim = dim;
    s.quantity = quantity;
    s.id = quantity_id(quantity);
    s.convention = &find_convention(options.convention);
    bool has_dim = false;
    for (int d : s.convention->dims) has_dim = has_dim || d == dim;
    if (!has_dim) fail("convention " + s.convention->target + " has no kernels in D = " + std::to_string(dim));
    if (!(options.ulps >= 0)) fail("the bound in ulps must be a number >= 0, not " + std::to_string(options.ulps));
    // (each point an exact MPFR evaluation, ~10^5 a second: 10^8 take ~20 minutes; more ran out of memory unnamed)
    if (options.uniform > max_uniform_points)
        fail(std::to_string(options.uniform) + " uniform points: at most " + std::to_string(max_uniform_points) +
             " (each is an exact evaluation)");
    s.reference = reference(s.spec, dim);
    const gen::ExactKernel& k = s.reference->kernel();
    if (!s.reference->has(s.id))
        fail(s.spec + " in D = " + std::to_string(dim) + " has no " + std::string(name(quantity)) +
             (k.claims.no_potential.empty() ? "" : " (" + k.claims.no_potential + ")"));
    s.support_square = support_square(*s.convention, k);
    s.support_scale = sqrt(to_real(s.support_square));
    s.value_scale = gen::Exact(gen::Q(1));
    if (table::is_potential(s.id)) {
        const gen::Exact c = gen::potential_scale(*s.convention);
        if (!(c == gen::Exact(gen::Q(1))) && dim != 3)
            fail("convention " + s.convention->target + " scales its potential in D = 3 only (" +
                 s.convention->potential.description + "), not in D = " + std::to_string(dim));
        s.value_scale = c;
    }
    s.value_scale_real = Real(s.value_scale.evaluate(digits * 4).first, digits);
    s.single = s.convention->precision == gen::FloatFormat::binary32;
    s.power = mollify::detail::scale_power(s.id, dim);
    return s;
}

Real support_of(const Setup& s, double h) {
    Real H(h, digits);
    H *= s.support_scale;
    return H;
}

Real exact_with(const Setup& s, const accuracy::Reference& ref, double r, const Real& H) {
    Real R(r, digits);
    Real v = ref.value(s.id, R, H);
    v *= s.value_scale_real;
    return v;
}

Real exact(const Setup& s, double r, double h) { return exact_with(s, *s.reference, r, support_of(s, h)); }

double magnitude(const Setup& s, double h) {
    const double H = h * static_cast<double>(s.support_scale);
    double m = s.reference->max_abs(s.id) * std::pow(H, s.power);
    if (s.id == table::QuantityId::potential && s.dim == 2) m += std::abs(std::log(H)) / (2 * M_PI);
    return m * std::abs(static_cast<double>(s.value_scale_real));
}

}  // namespace mollify::verify::detail
