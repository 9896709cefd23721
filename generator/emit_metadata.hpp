// What the writers need of one kernel, derived once from its exact object
// (the kernel, its quantities, a combination's terms and theirs, its
// certificates), and what every generated file says of its origin.
#pragma once

#include "catalogue.hpp"
#include "certificate.hpp"
#include "kernel.hpp"
#include "quantities.hpp"

#include <string>
#include <vector>

namespace mollify::gen {

struct KernelFacts {
    ExactKernel kernel;
    Quantities quantities;
    std::string spec;  // canonical
    std::string id;    // its C++ symbol, identifier(spec, dim)
    std::vector<ComboTerm> terms;  // a combination's w_j psi_{a_j} (else empty)
    std::vector<Quantities> term_quantities;
    std::vector<Certificate> certificates;
};

KernelFacts kernel_facts(const CatalogueEntry& e);

// Quantity i (table::QuantityId order) of the kernel; nullptr for a
// potential of a kernel without one.
const Radial* quantity_of(const KernelFacts& k, int i);
// A combination's quantity i term by term, w_j f_j (Franz (4.17)); empty
// for other kernels.
std::vector<Radial> parts_of(const KernelFacts& k, int i);
// A combination's multipole factors E_0..E_max_order (softening.hpp) term by
// term, element n the w_j E_n of every term (E_n is linear in the kernel);
// empty lists for other kernels. Planned as one merged sum, GADGET-4's
// fac_n of the m = 3 combinations were up to ~1.7e4 double ulps off (stop 90).
std::vector<std::vector<Radial>> multipole_factor_parts(const KernelFacts& k, int max_order);

// `text` with every character but letters and digits written '_'.
std::string sanitized(const std::string& text);
// The C++ symbol of a kernel: sanitized(spec)_D<dim>.
std::string identifier(const std::string& spec, int dim);

// The banner of every generated file, its lines starting with `comment`:
// the generator's version and the command that wrote it.
std::string banner(const std::string& command, const std::string& comment);
std::string generator_version();

}  // namespace mollify::gen
