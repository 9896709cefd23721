// The run-time form of a kernel, chosen by a spec string (a scene file, a
// command line): a pointer to the emitted table and to the batch functions
// of its StaticKernel, instantiated for every emitted table at both
// Precisions. A batch costs one indirect call more than the compile-time
// form; nothing else differs.
//
//   const mollify::Kernel w = mollify::kernel("wendland:k=2", 3);
//   w.evaluate(mollify::QuantityId::value, r, h, out);   // spans
//   w.pairs({dx, dy, dz}, h, values, {gx, gy, gz});
//   const mollify::Kernel f = w.with(mollify::Precision::fast);  // or kernel(spec, 3, Precision::fast)
#pragma once

#include <mollify/spec.hpp>
#include <mollify/static_kernel.hpp>
// Programs linking the precompiled registry (MOLLIFY_PRECOMPILED_REGISTRY)
// do not parse the emitted tables here (11 MB of headers, ~30 s per
// translation unit); src/registry.cpp defines MOLLIFY_DEFINE_REGISTRY.
#if !defined(MOLLIFY_PRECOMPILED_REGISTRY) || defined(MOLLIFY_DEFINE_REGISTRY)
#define MOLLIFY_REGISTRY_DEFINED_HERE
#include <mollify/tables/catalogue.hpp>
#endif

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace mollify {
namespace detail {
inline namespace MOLLIFY_ISA {

using BatchFunction = void (*)(const double* r, double* out, std::size_t n, const Smoothing& s);
using PairsFunction = void (*)(const std::span<const double>* x, const Smoothing& s, double* w,
                               const std::span<double>* grad, std::size_t n);

// The batch functions of one kernel at one Precision.
struct PrecisionOps {
    std::array<BatchFunction, table::quantity_count> batch;
    PairsFunction pairs;
};

struct KernelOps {
    const table::Kernel* table;
    std::array<PrecisionOps, 2> precision;  // indexed by Precision
};

#ifdef MOLLIFY_REGISTRY_DEFINED_HERE
template <const table::Kernel& K, Precision Pr, int Q>
void batch(const double* r, double* out, std::size_t n, const Smoothing& s) {
    StaticKernel<K, Pr>::template evaluate_unchecked<static_cast<QuantityId>(Q)>(r, out, n, s);
}

template <const table::Kernel& K, Precision Pr>
void pairs(const std::span<const double>* x, const Smoothing& s, double* w, const std::span<double>* grad,
           std::size_t n) {
    constexpr int D = K.dim;
    Points<D> in;
    PointsOut<D> out;
    for (int c = 0; c < D; ++c) {
        in[c] = x[c];
        out[c] = grad[c];
    }
    StaticKernel<K, Pr>::pairs_unchecked(in, s, w, out, n);
}

template <const table::Kernel& K, Precision Pr, std::size_t... Q>
constexpr PrecisionOps precision_ops(std::index_sequence<Q...>) {
    return {{&batch<K, Pr, static_cast<int>(Q)>...}, &pairs<K, Pr>};
}

template <const table::Kernel& K>
constexpr KernelOps ops_of() {
    constexpr auto quantities = std::make_index_sequence<table::quantity_count>{};
    static_assert(static_cast<int>(Precision::accurate) == 0 && static_cast<int>(Precision::fast) == 1);
    return {&K, {precision_ops<K, Precision::accurate>(quantities), precision_ops<K, Precision::fast>(quantities)}};
}

// Kernels Part, Part + Parts, Part + 2 Parts, ... of the catalogue: the
// precompiled registry is compiled as Parts translation units (src/registry.cpp
// once per part: in parallel, and in a fraction of the memory of one).
template <std::size_t Part, std::size_t Parts, std::size_t... J>
constexpr auto slice_of(std::index_sequence<J...>) {
    return std::array<KernelOps, sizeof...(J)>{
        ops_of<*tables::all_kernels[Part + J * Parts]>()...};
}

// Instantiated only where a kernel is looked up by name (a variable
// template), so code using only StaticKernel does not compile all tables.
template <std::size_t Part, std::size_t Parts>
inline constexpr auto slice_table =
    slice_of<Part, Parts>(std::make_index_sequence<(std::size(tables::all_kernels) + Parts - 1 - Part) / Parts>{});

template <std::size_t Part, std::size_t Parts>
std::span<const KernelOps> registry_slice() {
    return slice_table<Part, Parts>;
}
#else
// Defined (explicitly instantiated) in src/registry.cpp, one part per
// translation unit.
template <std::size_t Part, std::size_t Parts>
std::span<const KernelOps> registry_slice();
#endif

// The number of parts of the registry: MOLLIFY_REGISTRY_PARTS translation
// units of the precompiled registry (CMake target mollify::registry), else
// one, instantiated where kernels are looked up.
#ifdef MOLLIFY_PRECOMPILED_REGISTRY
inline constexpr std::size_t registry_parts = MOLLIFY_REGISTRY_PARTS;
#else
inline constexpr std::size_t registry_parts = 1;
#endif

inline const KernelOps* find_in(std::span<const KernelOps> slice, std::string_view key, int dim, bool& other_dim) {
    for (const KernelOps& ops : slice) {
        if (key != ops.table->spec) continue;
        if (ops.table->dim == dim) return &ops;
        other_dim = true;
    }
    return nullptr;
}

template <std::size_t... Part>
const KernelOps* find_in_parts(std::string_view key, int dim, bool& other_dim, std::index_sequence<Part...>) {
    const KernelOps* found = nullptr;
    ((found = found ? found : find_in(registry_slice<Part, registry_parts>(), key, dim, other_dim)), ...);
    return found;
}

// The registry entry of a canonical spec in dimension dim, or nullptr
// (other_dim says whether the spec exists in another dimension). A template
// so that only translation units that look kernels up by name instantiate
// the registry.
template <class = void>
const KernelOps* find_ops(std::string_view key, int dim, bool& other_dim) {
    other_dim = false;
    return find_in_parts(key, dim, other_dim, std::make_index_sequence<registry_parts>{});
}

}  // namespace MOLLIFY_ISA
}  // namespace detail

inline namespace MOLLIFY_ISA {

class Kernel {
public:
    explicit Kernel(const detail::KernelOps& ops, Precision precision = Precision::accurate)
        : ops_(&ops), precision_(precision) {
        if (precision != Precision::accurate && precision != Precision::fast)
            fail("precision " + std::to_string(static_cast<int>(precision)) + " does not exist");
    }

    // The same kernel evaluated at another Precision (both are compiled in).
    Kernel with(Precision precision) const { return Kernel(*ops_, precision); }
    Precision precision() const { return precision_; }

    const table::Kernel& table() const { return *ops_->table; }
    std::string_view spec() const { return ops_->table->spec; }
    int dim() const { return ops_->table->dim; }
    bool has_potential() const { return ops_->table->has_potential; }
    Smoothing smoothing(double h) const { return Smoothing(h, dim()); }

    // f_h at n radii (checked: finite r >= 0; h checked by Smoothing).
    void evaluate(QuantityId q, std::span<const double> r, const Smoothing& s, std::span<double> out) const {
        require(q, s);
        detail::check_sizes(r.size(), out.size(), "evaluate");
        detail::check_radii(r);
        ops().batch[static_cast<int>(q)](r.data(), out.data(), r.size(), s);
    }
    void evaluate(QuantityId q, std::span<const double> r, double h, std::span<double> out) const {
        evaluate(q, r, smoothing(h), out);
    }

    double operator()(QuantityId q, double r, double h) const {
        double out = 0;
        evaluate(q, std::span<const double>(&r, 1), h, std::span<double>(&out, 1));
        return out;
    }
    double value(double r, double h) const { return (*this)(QuantityId::value, r, h); }
    double potential(double r, double h) const { return (*this)(QuantityId::potential, r, h); }

    // W_h and grad W_h at n displacements; x and grad hold dim() spans.
    void pairs(std::span<const std::span<const double>> x, const Smoothing& s, std::span<double> w,
               std::span<const std::span<double>> grad) const {
        require(QuantityId::value, s);
        const auto d = static_cast<std::size_t>(dim());
        detail::check_sizes(d, x.size(), "pairs: components of x");
        detail::check_sizes(d, grad.size(), "pairs: components of grad");
        const std::size_t n = x[0].size();
        detail::check_sizes(n, w.size(), "pairs (values)");
        for (std::size_t c = 0; c < d; ++c) {
            detail::check_sizes(n, x[c].size(), "pairs: point components");
            detail::check_sizes(n, grad[c].size(), "pairs (gradient)");
            detail::check_coordinates(x[c], static_cast<int>(c));
        }
        ops().pairs(x.data(), s, w.data(), grad.data(), n);
    }

private:
    const detail::PrecisionOps& ops() const { return ops_->precision[static_cast<int>(precision_)]; }

    void require(QuantityId q, const Smoothing& s) const {
        if (s.dim() != dim())
            fail("a smoothing length made for D = " + std::to_string(s.dim()) + " used with " + std::string(spec()) +
                 " in D = " + std::to_string(dim()));
        if (static_cast<int>(q) < 0 || static_cast<int>(q) >= table::quantity_count)
            fail("quantity " + std::to_string(static_cast<int>(q)) + " does not exist");
        if (static_cast<int>(q) >= static_cast<int>(QuantityId::potential) && !has_potential())
            fail("kernel " + std::string(spec()) + " has no potential in D = " + std::to_string(dim()));
    }

    const detail::KernelOps* ops_;
    Precision precision_;
};

// The kernel of a spec (any spelling of the grammar, include/mollify/spec.hpp)
// in dimension dim, from the emitted tables on the include path. (A template
// for the reason find_ops is one.)
template <class = void>
Kernel kernel(std::string_view spec, int dim, Precision precision = Precision::accurate) {
    if (dim < 1 || dim > 3) fail("dimension " + std::to_string(dim) + " is not 1, 2 or 3");
    const std::string key = spec_string(parse_spec(spec));
    bool other_dim = false;
    if (const detail::KernelOps* ops = detail::find_ops<>(key, dim, other_dim)) return Kernel(*ops, precision);
    if (other_dim)
        fail("kernel " + key + " is not defined in D = " + std::to_string(dim) + " (its tables exist for other dimensions)");
    fail("kernel " + key + " is not in the emitted tables; emit it with: mollify-gen emit --only '" + key + "'");
}

// The quantity named as in the tables ("value", "dr", ..., "potential").
inline QuantityId quantity(std::string_view name) {
    for (int q = 0; q < table::quantity_count; ++q)
        if (name == quantity_names[q]) return static_cast<QuantityId>(q);
    fail("unknown quantity '" + std::string(name) + "'");
}

}  // namespace MOLLIFY_ISA
}  // namespace mollify
