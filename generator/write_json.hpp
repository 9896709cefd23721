// catalogue.json: every exact value of every emitted kernel as "p/q"
// strings (pieces of all ten quantities, normalisation, moments, a
// combination's radii and weights, Anderson's alpha, certificates).
#pragma once

#include "emit_metadata.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace mollify::gen {

nlohmann::ordered_json kernel_json(const KernelFacts& k);

// A kernel's entry as catalogue.json prints it within its "kernels" array
// (nlohmann's dump, indented to that depth): made by each kernel's worker,
// so that the 2.6 MB file is not printed on one core after them all.
std::string kernel_entry(const KernelFacts& k);

// The whole file: the kernels' entries (kernel_entry) in catalogue order.
std::string catalogue_json(const std::string& command, const std::vector<std::string>& entries);

}  // namespace mollify::gen
