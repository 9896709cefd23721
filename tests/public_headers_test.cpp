// The public runtime's headers (include/mollify/) and the emitted tables
// (generated/) include neither Eigen nor Boost: the mollify target declares
// no such dependency for its users (issue 18). Study code that needs Eigen
// lives in tools/studies/ (target mollify_studies).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// "file:line: text" for every #include of a header under a forbidden prefix.
std::vector<std::string> forbidden_includes(const fs::path& root) {
    const std::vector<std::string> prefixes = {"<boost/", "\"boost/", "<Eigen/", "\"Eigen/", "<eigen3/", "\"eigen3/"};
    std::vector<std::string> found;
    for (const auto& entry : fs::recursive_directory_iterator(root)) {
        if (!entry.is_regular_file()) continue;
        const std::string ext = entry.path().extension().string();
        if (ext != ".hpp" && ext != ".h") continue;
        std::ifstream in(entry.path());
        int number = 0;
        for (std::string line; std::getline(in, line);) {
            ++number;
            const auto hash = line.find_first_not_of(" \t");
            if (hash == std::string::npos || line[hash] != '#' || line.find("include") == std::string::npos) continue;
            for (const std::string& p : prefixes)
                if (line.find(p) != std::string::npos)
                    found.push_back(entry.path().string() + ":" + std::to_string(number) + ": " + line);
        }
    }
    return found;
}

std::size_t header_count(const fs::path& root) {
    std::size_t n = 0;
    for (const auto& entry : fs::recursive_directory_iterator(root))
        n += entry.is_regular_file() && entry.path().extension() == ".hpp";
    return n;
}

}  // namespace

TEST(PublicHeaders, IncludeNeitherEigenNorBoost) {
    for (const char* dir : {MOLLIFY_INCLUDE_DIR, MOLLIFY_GENERATED_DIR}) {
        // The scan reads files: an empty or wrong folder would pass vacuously.
        ASSERT_GT(header_count(dir), 0u) << dir;
        const std::vector<std::string> found = forbidden_includes(dir);
        std::string list;
        for (const std::string& f : found) list += f + "\n";
        EXPECT_TRUE(found.empty()) << list;
    }
}

// The scan can fail: the study headers do include Eigen.
TEST(PublicHeaders, ScanFindsTheStudiesEigen) {
    const std::vector<std::string> found = forbidden_includes(MOLLIFY_STUDIES_DIR);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_NE(found[0].find("convergence.hpp"), std::string::npos) << found[0];
    EXPECT_NE(found[0].find("<Eigen/Dense>"), std::string::npos) << found[0];
}
