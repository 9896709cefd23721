// Any kernel the grammar expresses, at run time, without recompiling: the
// kernels of the compiled catalogue as they are, every other one generated
// by the exact generator (certified: every certificate proved exactly, or an
// Error), cached on disk as a table file (table_file.hpp) keyed by its
// canonical spec, dimension and the generator's version, and evaluated by
// libmollify's data-driven loops. Link mollify::exact (GMP, MPFR); the
// header itself needs neither.
//
//   const mollify::Kernel w = mollify::exact::kernel("wendland:k=6,l=3", 3);
#pragma once

#include <mollify/dynamic_kernel.hpp>
#include <mollify/precision.hpp>
#include <mollify/table.hpp>

#include <filesystem>
#include <memory>
#include <string_view>

namespace mollify::exact {

struct Options {
    // Where generated tables are kept; empty: default_cache_dir().
    std::filesystem::path cache_dir;
    // false: generate anew and write nothing (a read-only file system).
    bool use_cache = true;
};

// $MOLLIFY_CACHE_DIR, else $XDG_CACHE_HOME/mollify, else $HOME/.cache/mollify,
// else a folder in the system's temporary directory.
std::filesystem::path default_cache_dir();

// The table file of a spec in dimension dim inside a cache folder:
// <cache>/<generator version>/<identifier>.table.
std::filesystem::path cache_file(const std::filesystem::path& cache, std::string_view spec, int dim);

// The table of spec in dim: the compiled one where the catalogue has it,
// else the cached one, else generated now (and cached). Bad specs and
// kernels that do not exist in dim are Errors naming the value, before any
// work.
std::shared_ptr<const table::Kernel> table(std::string_view spec, int dim, const Options& options = {});

// The run-time kernel of that table.
Kernel kernel(std::string_view spec, int dim, Precision precision = Precision::accurate, const Options& options = {});

}  // namespace mollify::exact
