// The C++ writer: one header of constexpr tables per kernel and dimension
// (table.hpp's format, designated initialisers, every coefficient a
// correctly rounded hex-float with its exact value beside it) and the list
// of them all (catalogue.hpp declares it, src/catalogue.cpp defines it).
// Header paths: kernel_header.
#pragma once

#include "emit_metadata.hpp"
#include "emit_round.hpp"

#include <optional>

#include <string>
#include <vector>

namespace mollify::gen {

// The header of kernel `spec` in dimension `dim`, relative to generated/.
std::string kernel_header(const std::string& spec, int dim);
// Its contents: banner, #include <mollify/table.hpp>, then the tables of
// the kernel: namespace detail_<id> with its arrays, then
// `inline constexpr table::Kernel <id>`. `tables`: the ten quantities
// (emit_round.hpp) in table::QuantityId order.
std::string kernel_file(const std::string& command, const KernelFacts& k,
                        const std::vector<std::optional<std::vector<RoundedPiece>>>& tables);
std::string catalogue_header(const std::string& command);
// `headers` and `ids` in catalogue order.
std::string catalogue_source(const std::string& command, const std::vector<std::string>& headers,
                             const std::vector<std::string>& ids);

}  // namespace mollify::gen
