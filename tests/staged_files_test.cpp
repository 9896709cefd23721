// StagedFiles (generator/emit.hpp): emit's files written all or none. Each
// kernel's file is staged while the others are still being rendered, so a
// failure after some were staged must leave the output as it was: old files
// intact, no temporaries, no folders made for files that were never placed.
#include "command.hpp"
#include "emit.hpp"
#include "error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using mollify::gen::EmitResult;
using mollify::gen::StagedFiles;
using mollify::testing::slurp;

namespace {

fs::path scratch(const std::string& name) {
    const fs::path p = fs::temp_directory_path() / ("mollify-staged-test-" + std::to_string(::getpid()) + "-" + name);
    fs::remove_all(p);
    return p;
}

// Every path under `root`, files and folders, relative to it.
std::vector<std::string> tree(const fs::path& root) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(root)) out.push_back(fs::relative(e.path(), root).string());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST(StagedFiles, NothingCommittedLeavesTheOutputAsItWas) {
    const fs::path out = scratch("abandoned");
    fs::create_directories(out / "a");
    { std::ofstream(out / "a/old.hpp") << "old\n"; }
    const auto before = tree(out);
    {
        StagedFiles files(out);
        files.stage("a/old.hpp", "new\n");         // a changed file
        files.stage("a/b/c/fresh.hpp", "fresh\n");  // in folders that do not exist yet
        files.stage("d/e.hpp", "e\n");
        EXPECT_TRUE(fs::exists(out / "a/b/c"));  // the temporaries are there, beside their places
    }  // destroyed without its commit: a later kernel failed
    EXPECT_EQ(tree(out), before);
    EXPECT_EQ(slurp(out / "a/old.hpp"), "old\n");
    fs::remove_all(out);
    {
        StagedFiles files(out);  // the output folder itself made, then removed again
        files.stage("x/y.hpp", "y\n");
    }
    EXPECT_FALSE(fs::exists(out));
}

TEST(StagedFiles, CommitPlacesEveryFileAndLeavesNoTemporary) {
    const fs::path out = scratch("committed");
    fs::create_directories(out);
    { std::ofstream(out / "same.hpp") << "same\n"; }
    const auto old = fs::file_time_type::clock::now() - std::chrono::hours(24 * 365);
    fs::last_write_time(out / "same.hpp", old);
    EmitResult r;
    r.files = {{"same.hpp", "same\n"}, {"k/one.hpp", "one\n"}, {"k/two.hpp", "two\n"}, {"catalogue.json", "{}\n"}};
    std::size_t written = 0;
    {
        StagedFiles files(out);
        // Staged from several threads at once, as emit's workers do.
        std::vector<std::thread> workers;
        workers.emplace_back([&] { files.stage("k/one.hpp", "one\n"); });
        workers.emplace_back([&] { files.stage("k/two.hpp", "two\n"); });
        workers.emplace_back([&] { files.stage("same.hpp", "same\n"); });
        for (auto& w : workers) w.join();
        written = files.commit(r);  // stages catalogue.json, the one not staged yet
    }
    EXPECT_EQ(written, 3u);  // same.hpp unchanged: not rewritten
    EXPECT_EQ(tree(out), (std::vector<std::string>{"catalogue.json", "k", "k/one.hpp", "k/two.hpp", "same.hpp"}));
    EXPECT_EQ(slurp(out / "k/two.hpp"), "two\n");
    EXPECT_EQ(slurp(out / "catalogue.json"), "{}\n");
    EXPECT_TRUE(fs::last_write_time(out / "same.hpp") == old);
    fs::remove_all(out);
}

TEST(StagedFiles, APathStagedTwiceIsAnError) {
    const fs::path out = scratch("twice");
    StagedFiles files(out);
    files.stage("k.hpp", "1\n");
    try {
        files.stage("k.hpp", "2\n");
        FAIL() << "staged twice without an error";
    } catch (const mollify::gen::Error& e) {
        EXPECT_NE(std::string(e.what()).find("k.hpp"), std::string::npos) << e.what();
    }
}
