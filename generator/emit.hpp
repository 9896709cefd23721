// Emission, the last step of the pipeline: C++ headers of constexpr tables
// (one per table family, FFTW-genfft style, plus an index) and
// catalogue.json with every exact value as "p/q" strings. Pure text
// generation over the exact kernels; files are written atomically.
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

// `command` is printed in every banner ("mollify-gen emit --only ..."): it
// names the content, never the output directory.
EmitResult render_catalogue(const std::vector<CatalogueEntry>& entries, const std::string& command);

// Writes every file (temporary file, then rename); creates directories.
void write_files(const std::filesystem::path& out, const EmitResult& result);

}  // namespace mollify::gen
