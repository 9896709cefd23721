// mollify::Kernel, the run-time form: the checks of the public API, then
// the data-driven loops (src/evaluator.cpp) on the kernel's plan.
#include <mollify/tables/catalogue.hpp>
#include "evaluator.hpp"
#include "plan.hpp"

#include <mollify/dynamic_kernel.hpp>

#include <mutex>
#include <vector>

namespace mollify {
namespace {

void check_precision(Precision precision) {
    if (precision != Precision::accurate && precision != Precision::fast)
        fail("precision " + std::to_string(static_cast<int>(precision)) + " does not exist");
}

// The plans of the catalogue's kernels, made once each on first use.
std::shared_ptr<const detail::Plan> catalogue_plan(std::size_t index) {
    static std::mutex mutex;
    static std::vector<std::shared_ptr<const detail::Plan>> plans(tables::all_kernels.size());
    const std::lock_guard lock(mutex);
    if (!plans[index]) plans[index] = detail::make_plan(*tables::all_kernels[index], nullptr);
    return plans[index];
}

}  // namespace

Kernel::Kernel(std::shared_ptr<const detail::Plan> plan, Precision precision)
    : plan_(std::move(plan)), precision_(precision) {
    check_precision(precision);
}

namespace {

// A catalogue table's plan is made once and shared.
std::shared_ptr<const detail::Plan> plan_of(const table::Kernel& table) {
    const auto all = tables::all_kernels;
    for (std::size_t i = 0; i < all.size(); ++i)
        if (all[i] == &table) return catalogue_plan(i);
    return detail::make_plan(table, nullptr);
}

}  // namespace

Kernel::Kernel(const table::Kernel& table, Precision precision) : Kernel(plan_of(table), precision) {}

Kernel::Kernel(std::shared_ptr<const table::Kernel> table, Precision precision)
    : Kernel(table ? detail::make_plan(*table, table) : throw Error("a null table given to mollify::Kernel"), precision) {}

Kernel Kernel::with(Precision precision) const { return Kernel(plan_, precision); }

const table::Kernel& Kernel::table() const { return *plan_->table; }
std::string_view Kernel::spec() const { return plan_->table->spec; }
int Kernel::dim() const { return plan_->table->dim; }
bool Kernel::has_potential() const { return plan_->table->has_potential; }

void Kernel::require(QuantityId q, const Smoothing& s) const {
    if (s.dim() != dim())
        fail("a smoothing length made for D = " + std::to_string(s.dim()) + " used with " + std::string(spec()) +
             " in D = " + std::to_string(dim()));
    if (static_cast<int>(q) < 0 || static_cast<int>(q) >= table::quantity_count)
        fail("quantity " + std::to_string(static_cast<int>(q)) + " does not exist");
    if (static_cast<int>(q) >= static_cast<int>(QuantityId::potential) && !has_potential())
        fail("kernel " + std::string(spec()) + " has no potential in D = " + std::to_string(dim()));
    if (!plan_->quantities[static_cast<std::size_t>(q)].present)
        fail("kernel " + std::string(spec()) + " has no " + quantity_names[static_cast<int>(q)] +
             " in D = " + std::to_string(dim()));
}

double Kernel::operator()(QuantityId q, double r, double h) const {
    const Smoothing& s = Smoothing::reused(h, dim(), q);
    require(q, s);
    return detail::evaluator().at_radius(*plan_, precision_, q, r, s);
}

void Kernel::evaluate(QuantityId q, std::span<const double> r, const Smoothing& s, std::span<double> out) const {
    require(q, s);
    detail::check_sizes(r.size(), out.size(), "evaluate");
    detail::evaluator().evaluate(*plan_, precision_, q, r.data(), out.data(), r.size(), s);
}

void Kernel::pairs(std::span<const std::span<const double>> x, const Smoothing& s, std::span<double> w,
                   std::span<const std::span<double>> grad) const {
    require(QuantityId::value, s);
    require(QuantityId::grad_over_r, s);
    const auto d = static_cast<std::size_t>(dim());
    detail::check_sizes(d, x.size(), "pairs: components of x");
    detail::check_sizes(d, grad.size(), "pairs: components of grad");
    const std::size_t n = x[0].size();
    detail::check_sizes(n, w.size(), "pairs (values)");
    for (std::size_t c = 0; c < d; ++c) {
        detail::check_sizes(n, x[c].size(), "pairs: point components");
        detail::check_sizes(n, grad[c].size(), "pairs (gradient)");
    }
    detail::evaluator().pairs(*plan_, precision_, x.data(), s, w.data(), grad.data(), n);
}

Kernel kernel(std::string_view spec, int dim, Precision precision) {
    if (dim < 1 || dim > 3) fail("dimension " + std::to_string(dim) + " is not 1, 2 or 3");
    check_precision(precision);
    const std::string key = spec_string(parse_spec(spec));
    bool other_dim = false;
    const auto all = tables::all_kernels;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (key != all[i]->spec) continue;
        if (all[i]->dim == dim) return Kernel(*all[i], precision);
        other_dim = true;
    }
    if (other_dim)
        fail("kernel " + key + " is not defined in D = " + std::to_string(dim) + " (its tables exist for other dimensions)");
    fail("kernel " + key + " is not compiled into libmollify: generate it at run time with mollify::exact::kernel (link "
         "mollify::exact), or as a table file with: mollify-gen emit --format data --only '" + key + "'");
}

Kernel kernel(const table::Kernel& table, Precision precision) { return Kernel(table, precision); }
Kernel kernel(std::shared_ptr<const table::Kernel> table, Precision precision) {
    return Kernel(std::move(table), precision);
}

}  // namespace mollify
