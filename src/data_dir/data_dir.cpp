// mollify::data_dir (data_dir.hpp). MOLLIFY_BIN_TO_DATA is
// the installed layout's path from the executables' folder to mollify's data
// folder (CMAKE_INSTALL_BINDIR to CMAKE_INSTALL_DATADIR/mollify).
#include "data_dir.hpp"

#include <filesystem>
#include <system_error>

namespace mollify {

std::string data_dir(std::string_view name, std::string_view build_tree_folder) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path installed = (self.parent_path() / MOLLIFY_BIN_TO_DATA / name).lexically_normal();
        if (fs::is_directory(installed, ec)) return installed.string();
    }
    return std::string(build_tree_folder);
}

}  // namespace mollify
