#include "emit.hpp"

#include "error.hpp"

#include <fstream>
#include <unistd.h>

namespace mollify::gen {

namespace {

// Whether `path` holds exactly `text`: such a file is left alone, so that
// regenerating unchanged tables keeps their timestamps and rebuilds nothing.
bool holds(const std::filesystem::path& path, const std::string& text) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec) || std::filesystem::file_size(path, ec) != text.size() || ec)
        return false;
    std::ifstream f(path, std::ios::binary);
    std::string old(text.size(), '\0');
    return f.read(old.data(), static_cast<std::streamsize>(old.size())) && old == text;
}

}  // namespace

StagedFiles::StagedFiles(std::filesystem::path out) : out_(std::move(out)) {}

StagedFiles::~StagedFiles() {
    if (committed_) return;
    std::error_code ignored;  // a destructor does not throw: what cannot be removed stays
    for (const auto& [rel, tmp] : staged_)
        if (tmp) std::filesystem::remove(*tmp, ignored);
    // The folders made for them, deepest first (a folder sorts before its
    // subfolders), each only if empty.
    for (auto it = made_.rbegin(); it != made_.rend(); ++it) std::filesystem::remove(*it, ignored);
}

void StagedFiles::make_folders(const std::filesystem::path& folder) {
    std::vector<std::filesystem::path> missing;
    for (std::filesystem::path p = folder; !p.empty() && !std::filesystem::exists(p); p = p.parent_path()) {
        missing.push_back(p);
        if (p == p.parent_path()) break;
    }
    std::lock_guard lock(mutex_);  // one thread at a time makes folders, so each is made (and recorded) once
    for (auto it = missing.rbegin(); it != missing.rend(); ++it)
        if (std::filesystem::create_directory(*it)) made_.insert(*it);
}

void StagedFiles::stage(const std::string& rel, const std::string& text) {
    {
        std::lock_guard lock(mutex_);
        if (committed_) fail("internal: " + rel + " staged after the commit");
        if (!staged_.try_emplace(rel).second) fail("internal: " + rel + " staged twice");
    }
    const std::filesystem::path target = out_ / rel;
    std::optional<std::filesystem::path> tmp;
    try {
        if (!holds(target, text)) {
            make_folders(target.parent_path());
            tmp = target.string() + ".tmp." + std::to_string(::getpid());
            std::ofstream f(*tmp, std::ios::binary);
            f << text;
            if (!f.flush()) {
                std::filesystem::remove(*tmp);
                fail("cannot write " + tmp->string());
            }
        }
    } catch (const std::filesystem::filesystem_error& e) {
        fail(std::string("cannot write the tables: ") + e.what());
    }
    std::lock_guard lock(mutex_);
    staged_[rel] = std::move(tmp);
}

std::size_t StagedFiles::commit(const EmitResult& result) {
    for (const auto& [rel, text] : result.files) {
        bool seen;
        {
            std::lock_guard lock(mutex_);
            seen = staged_.count(rel) != 0;
        }
        if (!seen) stage(rel, text);
    }
    std::lock_guard lock(mutex_);
    std::size_t written = 0;
    try {
        for (auto& [rel, tmp] : staged_)
            if (tmp) {
                std::filesystem::rename(*tmp, out_ / rel);
                tmp.reset();
                ++written;
            }
    } catch (const std::filesystem::filesystem_error& e) {  // the temporaries not renamed go with the destructor
        fail(std::string("cannot write the tables: ") + e.what());
    }
    committed_ = true;
    return written;
}

std::size_t write_files(const std::filesystem::path& out, const EmitResult& result) {
    StagedFiles files(out);
    return files.commit(result);
}

}  // namespace mollify::gen
