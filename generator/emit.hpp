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
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
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

// Called with a kernel's file (path relative to the output, text) as soon as
// it is rendered, on the thread that rendered it.
using FileReady = std::function<void(const std::string& path, const std::string& text)>;

// `command` is printed in every banner ("mollify-gen emit --only ..."): it
// names the content, never the output directory. `ready`, where given, sees
// each kernel's file while the others are still being rendered (the
// catalogue's own files are only in the result).
EmitResult render_catalogue(const std::vector<CatalogueEntry>& entries, const std::string& command,
                            EmitFormat format = EmitFormat::cpp, const FileReady& ready = {});

// --target NAME (target.hpp; not cpp): each kernel's files as the target's
// writer makes them, for its convention (conventions.hpp); Error for a
// dimension the target does not take.
EmitResult render_target(const std::vector<CatalogueEntry>& entries, const std::string& command,
                         const std::string& target, bool allow_negative_lobes = false);

// Files written all or none: each file whose content differs from the one at
// its place is written to a temporary beside it (stage: on any thread, as
// soon as its text is ready), and commit renames them all into place;
// destroyed before its commit, it removes its temporaries, so a failure
// leaves the old files intact. Unchanged files keep their timestamps;
// directories are created as needed.
class StagedFiles {
public:
    explicit StagedFiles(std::filesystem::path out);
    StagedFiles(const StagedFiles&) = delete;
    StagedFiles& operator=(const StagedFiles&) = delete;
    ~StagedFiles();

    // `rel`, relative to the output; each path once.
    void stage(const std::string& rel, const std::string& text);
    // Stages the result's files not staged yet, then renames every staged
    // file into place. Returns how many files it wrote.
    std::size_t commit(const EmitResult& result);

private:
    void make_folders(const std::filesystem::path& folder);

    std::filesystem::path out_;
    std::mutex mutex_;
    std::set<std::filesystem::path> made_;  // the folders this made (removed again where nothing is committed)
    std::map<std::string, std::optional<std::filesystem::path>> staged_;  // path -> its temporary (none: unchanged)
    bool committed_ = false;
};

// Every file of `result`, staged and committed (StagedFiles). Returns how
// many files it wrote.
std::size_t write_files(const std::filesystem::path& out, const EmitResult& result);

}  // namespace mollify::gen
