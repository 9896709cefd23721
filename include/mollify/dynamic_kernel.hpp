// The run-time form of a kernel, chosen by a spec string (a scene file, a
// command line) or given as a table: an opaque handle to a plan of the
// table (src/plan.hpp), evaluated by libmollify's data-driven loops
// (src/evaluator.cpp), compiled for generic x86-64, x86-64-v3 and -v4 and chosen
// at load time. No table is compiled into the caller.
//
//   const mollify::Kernel w = mollify::kernel("wendland:k=2", 3);
//   w.evaluate(mollify::QuantityId::value, r, h, out);   // spans
//   w.pairs({dx, dy, dz}, h, values, {gx, gy, gz});
//   const mollify::Kernel f = w.with(mollify::Precision::fast);  // or kernel(spec, 3, Precision::fast)
#pragma once

#include <mollify/kernel_concept.hpp>
#include <mollify/spec.hpp>
#include <mollify/static_kernel.hpp>

#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace mollify {

namespace detail {
struct Plan;
}  // namespace detail

class Kernel {
public:
    // The kernel of a table that outlives it (the compiled-in catalogue), or
    // of one it shares (a table loaded at run time).
    explicit Kernel(const table::Kernel& table, Precision precision = Precision::accurate);
    explicit Kernel(std::shared_ptr<const table::Kernel> table, Precision precision = Precision::accurate);

    // The same kernel (the same plan) evaluated at another Precision.
    Kernel with(Precision precision) const;
    Precision precision() const { return precision_; }

    const table::Kernel& table() const;
    std::string_view spec() const;
    int dim() const;
    bool has_potential() const;
    Smoothing smoothing(double h) const { return Smoothing(h, dim()); }

    // f_h at n radii (checked: finite r >= 0; h checked by Smoothing). The
    // radii are checked a chunk at a time as they are evaluated: on a bad
    // one, an Error naming it; out then holds the values of the chunks
    // before and unspecified values in the bad one's chunk.
    void evaluate(QuantityId q, std::span<const double> r, const Smoothing& s, std::span<double> out) const;
    void evaluate(QuantityId q, std::span<const double> r, double h, std::span<double> out) const {
        evaluate(q, r, smoothing(h), out);
    }

    // f_h at one radius, checked (r, h, q present): evaluate's operations for
    // a batch of one, without the batch around them; h's Smoothing reused
    // from this thread's last call with the same h, for a new h only q's
    // scale made (Smoothing::reused(h, dim, q)).
    double operator()(QuantityId q, double r, double h) const;
    double value(double r, double h) const { return (*this)(QuantityId::value, r, h); }
    double potential(double r, double h) const { return (*this)(QuantityId::potential, r, h); }

    // W_h and grad W_h at n displacements; x and grad hold dim() spans
    // (checked as evaluate's radii: finite, chunk by chunk).
    void pairs(std::span<const std::span<const double>> x, const Smoothing& s, std::span<double> w,
               std::span<const std::span<double>> grad) const;

private:
    Kernel(std::shared_ptr<const detail::Plan> plan, Precision precision);
    void require(QuantityId q, const Smoothing& s) const;

    std::shared_ptr<const detail::Plan> plan_;
    Precision precision_;
};

static_assert(RadialKernel<Kernel>);

// The kernel of a spec (any spelling of the grammar, include/mollify/spec.hpp)
// in dimension dim, from the catalogue compiled into libmollify.
Kernel kernel(std::string_view spec, int dim, Precision precision = Precision::accurate);

// The kernel of a table: one that outlives the Kernel, or one loaded at run time.
Kernel kernel(const table::Kernel& table, Precision precision = Precision::accurate);
Kernel kernel(std::shared_ptr<const table::Kernel> table, Precision precision = Precision::accurate);

// The instruction set of the run-time form's loops: "x86-64-v4" (AVX-512,
// chosen where the CPU has it), "x86-64-v3" (AVX2 + FMA) or "generic". use_isa forces one (tests
// check both; the environment variable MOLLIFY_ISA does the same at load
// time); it fails naming an ISA that is unknown or that the CPU lacks.
std::string_view isa();
void use_isa(std::string_view name);

// The quantity named as in the tables ("value", "dr", ..., "potential").
inline QuantityId quantity(std::string_view name) {
    for (int q = 0; q < table::quantity_count; ++q)
        if (name == quantity_names[q]) return static_cast<QuantityId>(q);
    std::string known;
    for (int q = 0; q < table::quantity_count; ++q) known += (q ? ", " : "") + std::string(quantity_names[q]);
    fail("unknown quantity '" + std::string(name) + "' (known: " + known + ")");
}

}  // namespace mollify
