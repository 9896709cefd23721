// Emission, the last step of the pipeline: one C++ header of constexpr
// tables per kernel and dimension (mollify/tables/<family>/<parameters>_D<d>.hpp,
// the rule in emit.cpp's kernel_header), the list of them all
// (mollify/tables/catalogue.hpp declares it, src/catalogue.cpp defines it,
// compiled once into the mollify library) and catalogue.json with every
// exact value as "p/q" strings; or, with EmitFormat::data, one table file
// per kernel and dimension (write_data.cpp). Pure text generation over the
// exact kernels; changed files are written atomically, unchanged ones left alone.
#pragma once

#include "catalogue.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mollify::gen {

struct EmitResult {
    std::map<std::string, std::string> files;  // relative path -> contents
    int kernels = 0;
    int certificates = 0;
    std::vector<std::string> failed_certificates;
};

// cpp: the C++ headers, the catalogue's list and catalogue.json (generated/);
// data: one table file per kernel and dimension (write_data.cpp), nothing else.
enum class EmitFormat { cpp, data };

// `command` is printed in every banner ("mollify-gen emit --only ..."): it
// names the content, never the output directory.
EmitResult render_catalogue(const std::vector<CatalogueEntry>& entries, const std::string& command,
                            EmitFormat format = EmitFormat::cpp);

// --target NAME (target.hpp; not cpp): each kernel's files as the target's
// writer makes them, for its convention (conventions.hpp); Error for a
// dimension the target does not take.
EmitResult render_target(const std::vector<CatalogueEntry>& entries, const std::string& command,
                         const std::string& target, bool allow_negative_lobes = false);

// Writes every file whose content differs from the one at its place
// (temporary file, then rename; unchanged files keep their timestamps);
// creates directories.
// Returns how many files it wrote.
std::size_t write_files(const std::filesystem::path& out, const EmitResult& result);

}  // namespace mollify::gen
