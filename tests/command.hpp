// Running a built command as a user would (tests of mollify-gen and mollify):
// its exit status, stdout and stderr.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>

namespace mollify::testing {

struct Outcome {
    int status;
    std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

// Runs the shell command `command`, its output captured in two files named
// `capture`.stdout and `capture`.stderr (removed afterwards).
inline Outcome run_command(const std::string& command, const std::filesystem::path& capture) {
    const std::filesystem::path out = capture.string() + ".stdout", err = capture.string() + ".stderr";
    const int raw = std::system((command + " >'" + out.string() + "' 2>'" + err.string() + "'").c_str());
    Outcome r{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(out), slurp(err)};
    std::filesystem::remove(out);
    std::filesystem::remove(err);
    return r;
}

}  // namespace mollify::testing
