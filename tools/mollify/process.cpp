#include "process.hpp"

#include <mollify/error.hpp>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace mollify::app {

namespace {

// A temporary file, removed with this object; the child writes into it
// (files rather than pipes: two pipes read one after the other could
// deadlock when the child fills the other).
class Capture {
public:
    Capture() {
        path_ = (fs::temp_directory_path() / "mollify-capture-XXXXXX").string();
        fd_ = ::mkstemp(path_.data());
        if (fd_ < 0) fail("cannot create a temporary file " + path_ + ": " + std::strerror(errno));
    }
    ~Capture() {
        ::close(fd_);
        ::unlink(path_.c_str());
    }
    Capture(const Capture&) = delete;
    Capture& operator=(const Capture&) = delete;
    int fd() const { return fd_; }
    std::string text() const {
        std::ifstream in(path_, std::ios::binary);
        std::ostringstream s;
        s << in.rdbuf();
        return s.str();
    }

private:
    std::string path_;
    int fd_ = -1;
};

}  // namespace

ProcessResult run_process(const std::string& program, const std::vector<std::string>& args, const fs::path& dir,
                          const std::string& missing_hint) {
    Capture out, err;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, out.fd(), 1);
    posix_spawn_file_actions_adddup2(&actions, err.fd(), 2);
    if (!dir.empty()) posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
    std::vector<std::string> words{program};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int rc = ::posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc == ENOENT) fail(program + " is not installed or not built" + (missing_hint.empty() ? "" : " (" + missing_hint + ")"));
    if (rc != 0) fail("cannot run " + program + ": " + std::strerror(rc));
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    ProcessResult r;
    r.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = out.text();
    r.err = err.text();
    return r;
}

}  // namespace mollify::app
