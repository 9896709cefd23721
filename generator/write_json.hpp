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

// The whole file: the kernels' entries in catalogue order.
std::string catalogue_json(const std::string& command, const std::vector<nlohmann::ordered_json>& kernels);

}  // namespace mollify::gen
