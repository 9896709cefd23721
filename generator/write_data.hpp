// The data writer (mollify-gen emit --format data): one text file per
// kernel and dimension, everything its table::Kernel holds; the format is
// documented at the top of write_data.cpp.
#pragma once

#include "emit_metadata.hpp"
#include "emit_round.hpp"
#include "write_cpp.hpp"

#include <optional>
#include <string>
#include <vector>

namespace mollify::gen {

// `tables`: the ten quantities in table::QuantityId order.
std::string kernel_data(const KernelFacts& k, const std::vector<std::optional<std::vector<RoundedPiece>>>& tables);

// Relative to the output folder: kernel_header's path, .table for .hpp
// (mollify/tables/wendland/k_2_D3.table).
std::string kernel_data_path(const std::string& spec, int dim);

}  // namespace mollify::gen
