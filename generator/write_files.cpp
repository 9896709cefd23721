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

std::size_t write_files(const std::filesystem::path& out, const EmitResult& result) {
    // Every changed file goes to a temporary beside its target first; only
    // when all are written are they renamed into place, so a failure leaves
    // the old tables intact.
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> staged;
    auto discard = [&] {
        for (const auto& [tmp, target] : staged) std::filesystem::remove(tmp);
    };
    try {
        for (const auto& [rel, text] : result.files) {
            const std::filesystem::path target = out / rel;
            if (holds(target, text)) continue;
            std::filesystem::create_directories(target.parent_path());
            const std::filesystem::path tmp = target.string() + ".tmp." + std::to_string(::getpid());
            staged.emplace_back(tmp, target);
            std::ofstream f(tmp, std::ios::binary);
            f << text;
            if (!f.flush()) fail("cannot write " + tmp.string());
        }
    } catch (const std::filesystem::filesystem_error& e) {
        discard();
        fail(std::string("cannot write the tables: ") + e.what());
    } catch (...) {
        discard();
        throw;
    }
    for (const auto& [tmp, target] : staged) std::filesystem::rename(tmp, target);
    return staged.size();
}

}  // namespace mollify::gen
