// Running another program (gnuplot, mollify-gen, mollify-stability,
// kernel_bench) and collecting what it printed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mollify::app {

struct ProcessResult {
    int exit_status = -1;  // -1: killed by a signal
    std::string out, err;  // its stdout and stderr
    bool ok() const { return exit_status == 0; }
};

// Runs `program` (a path, or a name looked up on PATH) with `args`, stdin
// from /dev/null, in `dir` (empty: the current folder); waits for it. An
// Error naming the program if it cannot be started (with `missing_hint`
// when it does not exist); a nonzero exit status is the caller's to judge.
ProcessResult run_process(const std::string& program, const std::vector<std::string>& args,
                          const std::filesystem::path& dir = {}, const std::string& missing_hint = {});

}  // namespace mollify::app
