// The --target machinery of `mollify-gen emit` (issue 19): one writer per
// target, each in its own file (write_c.cpp, write_fortran.cpp,
// write_python.cpp, write_phantom.cpp, write_swift.cpp, write_gadget4.cpp), all fed the same
// planned and rounded tables (emit_plan, emit_round) and the target's
// convention (conventions.hpp). A new target is a writer function and one
// line in target.cpp's list.
#pragma once

#include "conventions.hpp"
#include "emit_metadata.hpp"
#include "emit_round.hpp"

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace mollify::gen {

// The ten quantities of one kernel, rounded, in table::QuantityId order
// (nullopt: a potential the kernel does not have).
using Tables = std::vector<std::optional<std::vector<RoundedPiece>>>;

// The planned, checked and rounded tables of a kernel (emit.cpp), as every
// writer gets them.
Tables rounded_tables(const KernelFacts& f);

// What a writer gets for one kernel in one dimension.
struct TargetKernel {
    const KernelFacts& facts;
    const Tables& tables;
    const Convention& convention;
    // --allow-negative-lobes: a target that clamps the kernel's sign (SWIFT)
    // writes a kernel it cannot prove W >= 0, W' <= 0 for, without the clamps.
    bool allow_negative_lobes = false;
};

// Paths relative to --out -> contents, each beginning with banner(command, ...).
using TargetFiles = std::map<std::string, std::string>;

struct Target {
    std::string name;
    std::function<TargetFiles(const TargetKernel&, const std::string& command)> write;
};

// The writer of target `name`; Error naming it and the known ones. ("cpp",
// mollify's own tables, is emit.cpp's render_catalogue, not a Target.)
const Target& target(const std::string& name);

// The writers (write_<target>.cpp).
TargetFiles write_c(const TargetKernel& k, const std::string& command);
TargetFiles write_fortran(const TargetKernel& k, const std::string& command);
TargetFiles write_python(const TargetKernel& k, const std::string& command);
TargetFiles write_phantom(const TargetKernel& k, const std::string& command);
TargetFiles write_gadget4(const TargetKernel& k, const std::string& command);
TargetFiles write_swift(const TargetKernel& k, const std::string& command);
// SWIFT's kernel_gravity.h alone; Error in D != 3 or for a kernel without a
// Poisson potential (write_swift then writes kernel_hydro.h alone).
TargetFiles write_swift_gravity(const TargetKernel& k, const std::string& command);

}  // namespace mollify::gen
