// The member API both kernel forms share: mollify::StaticKernel<table, Pr>
// (the table a template argument, the hot loops types) and mollify::Kernel
// (the run-time form from table data). Solvers and studies take either
// through this concept, with no adapter (issue 18).
#pragma once

#include <mollify/smoothing.hpp>
#include <mollify/table.hpp>

#include <concepts>
#include <span>
#include <string_view>

namespace mollify {

template <class K>
concept RadialKernel = requires(const K& k, QuantityId q, double r, double h, std::span<const double> radii,
                                const Smoothing& s, std::span<double> out, std::span<const std::span<const double>> x,
                                std::span<const std::span<double>> grad) {
    { k.dim() } -> std::convertible_to<int>;
    { k.spec() } -> std::convertible_to<std::string_view>;
    { k.table() } -> std::same_as<const table::Kernel&>;
    { k.has_potential() } -> std::convertible_to<bool>;
    { k.smoothing(h) } -> std::same_as<Smoothing>;
    // f_h at the radii (checked), the quantity chosen at run time.
    k.evaluate(q, radii, s, out);
    // W_h and grad W_h at displacements; x and grad hold dim() spans.
    k.pairs(x, s, out, grad);
    { k(q, r, h) } -> std::convertible_to<double>;
    { k.value(r, h) } -> std::convertible_to<double>;
};

}  // namespace mollify
