// evaluate_foreign: fork, the child dlopens and evaluates, one pipe back
// (foreign_function.hpp describes the protocol).
#include "foreign_function.hpp"

#include <mollify/error.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <string_view>

#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace mollify::app {

namespace {

// Record tags: the child's messages to the parent.
constexpr char ready = 'R';            // library opened, symbol found
constexpr char value = 'V';            // 8 bytes: the next argument's value
constexpr char cannot_open = 'O';      // text: dlerror() of dlopen
constexpr char no_symbol = 'S';        // text: dlerror() of dlsym
constexpr char threw = 'X';            // text: what() of the exception that escaped f

using Kernel = double (*)(double, double);

std::string shortest(double x) {
    char buf[32];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

// ---- the child ---------------------------------------------------------

// write(2) all of it; the parent gone (EPIPE) ends the child.
void send(int fd, const void* data, std::size_t n) {
    const char* p = static_cast<const char*>(data);
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) ::_exit(3);
        p += w;
        n -= static_cast<std::size_t>(w);
    }
}

void send_tag(int fd, char tag) { send(fd, &tag, 1); }

void send_text(int fd, char tag, std::string_view text) {
    const auto n = static_cast<std::uint32_t>(std::min<std::size_t>(text.size(), 4000));
    send_tag(fd, tag);
    send(fd, &n, sizeof n);
    send(fd, text.data(), n);
}

// The user's code sees a plain process: default handlers for the signals a
// crash raises (a sanitizer's handlers would turn the signal into an exit
// status), no core file per crash, its printing on stderr (stdout is
// mollify's table), and it dies with mollify.
void isolate(pid_t parent) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(3);
    const rlimit no_core{0, 0};
    ::setrlimit(RLIMIT_CORE, &no_core);
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGPIPE}) ::signal(sig, SIG_DFL);
    ::dup2(STDERR_FILENO, STDOUT_FILENO);
}

// A path to an existing file as an absolute path: dlopen searches the
// library path for a name without '/', so "libmine.so" in the working
// directory would not be found.
std::string dlopen_name(const std::filesystem::path& library) {
    std::error_code ec;
    if (library.native().find('/') == std::string::npos && std::filesystem::is_regular_file(library, ec))
        return std::filesystem::absolute(library, ec).string();
    return library.string();
}

[[noreturn]] void child(int fd, pid_t parent, const ForeignFunction& f, std::span<const double> r,
                        std::span<const double> h) {
    isolate(parent);
    void* lib = ::dlopen(dlopen_name(f.library).c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        const char* e = ::dlerror();
        send_text(fd, cannot_open, e ? e : "unknown error");
        ::_exit(0);
    }
    ::dlerror();
    void* symbol = ::dlsym(lib, f.symbol.c_str());
    if (const char* e = ::dlerror(); e || !symbol) {
        send_text(fd, no_symbol, e ? e : "the symbol is null");
        ::_exit(0);
    }
    send_tag(fd, ready);
    const auto kernel = reinterpret_cast<Kernel>(symbol);
    for (std::size_t i = 0; i < r.size(); ++i) {
        double v;
        try {
            v = kernel(r[i], h[i]);
        } catch (const std::exception& e) {
            send_text(fd, threw, e.what());
            ::_exit(0);
        } catch (...) {
            send_text(fd, threw, "");
            ::_exit(0);
        }
        char record[1 + sizeof v];
        record[0] = value;
        std::memcpy(record + 1, &v, sizeof v);
        send(fd, record, sizeof record);
    }
    ::_exit(0);
}

// ---- the parent --------------------------------------------------------

// The child process: killed and reaped however the parent leaves.
class Child {
public:
    explicit Child(pid_t pid) : pid_(pid) {}
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    ~Child() {
        if (pid_ > 0) {
            ::kill(pid_, SIGKILL);
            reap();
        }
    }
    // Its wait status once it has exited (after the pipe's end of file).
    int reap() {
        int status = 0;
        while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
        pid_ = -1;
        return status;
    }
    void kill() {
        ::kill(pid_, SIGKILL);
        reap();
    }

private:
    pid_t pid_;
};

class Fd {
public:
    explicit Fd(int fd) : fd_(fd) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() { close(); }
    int get() const { return fd_; }
    void close() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }

private:
    int fd_;
};

enum class Read { data, end_of_file, timed_out };

// Appends what the pipe has to `buffer`, waiting at most `timeout`.
Read read_some(int fd, std::string& buffer, std::chrono::milliseconds timeout) {
    pollfd p{fd, POLLIN, 0};
    int ready_count;
    do {
        ready_count = ::poll(&p, 1, static_cast<int>(timeout.count()));
    } while (ready_count < 0 && errno == EINTR);
    if (ready_count < 0) fail(std::string("poll on the child's pipe failed: ") + std::strerror(errno));
    if (ready_count == 0) return Read::timed_out;
    char chunk[65536];
    ssize_t n;
    do {
        n = ::read(fd, chunk, sizeof chunk);
    } while (n < 0 && errno == EINTR);
    if (n < 0) fail(std::string("reading the child's pipe failed: ") + std::strerror(errno));
    if (n == 0) return Read::end_of_file;
    buffer.append(chunk, static_cast<std::size_t>(n));
    return Read::data;
}

// How the child ended, for "SYMBOL crashed with SIGSEGV at ...".
std::string ending(int status) {
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        const char* abbrev = ::sigabbrev_np(sig);
        return std::string("crashed with ") + (abbrev ? std::string("SIG") + abbrev : "signal " + std::to_string(sig));
    }
    if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status)) + " (called exit or stop)";
    return "ended abnormally";
}

// The evaluation's state as the parent sees it.
class Session {
public:
    Session(const ForeignFunction& f, std::span<const double> r, std::span<const double> h)
        : f_(f), r_(r), h_(h) {}

    bool done() const { return values_.size() == r_.size(); }
    std::vector<double> take() { return std::move(values_); }

    // Where the child is: "at r=..., h=..." or "while loading LIBRARY".
    std::string where() const {
        if (!ready_) return "while loading " + f_.library.string();
        const std::size_t i = values_.size();
        if (i == r_.size()) return "after its last argument";
        return "at r=" + shortest(r_[i]) + ", h=" + shortest(h_[i]);
    }

    // Consumes the complete records at the front of `buffer`; an error record
    // or a non-finite value throws.
    void consume(std::string& buffer) {
        std::size_t at = 0;
        while (at < buffer.size()) {
            const char tag = buffer[at];
            if (tag == ready) {
                ready_ = true;
                at += 1;
            } else if (tag == value) {
                double v;
                if (buffer.size() - at < 1 + sizeof v) break;
                std::memcpy(&v, buffer.data() + at + 1, sizeof v);
                if (done()) fail("the child process evaluating " + f_.symbol + " sent more values than arguments");
                if (!std::isfinite(v))
                    fail(f_.symbol + " returned " + shortest(v) + " " + where() + " (a kernel value is finite)");
                values_.push_back(v);
                at += 1 + sizeof v;
            } else {
                std::uint32_t n;
                if (buffer.size() - at < 1 + sizeof n) break;
                std::memcpy(&n, buffer.data() + at + 1, sizeof n);
                if (buffer.size() - at < 1 + sizeof n + n) break;
                fail_with(tag, buffer.substr(at + 1 + sizeof n, n));
            }
        }
        buffer.erase(0, at);
    }

private:
    [[noreturn]] void fail_with(char tag, const std::string& text) const {
        if (tag == cannot_open) fail("cannot open library " + f_.library.string() + ": " + text);
        if (tag == no_symbol)
            fail("no symbol " + f_.symbol + " in " + f_.library.string() + ": " + text +
                 " (a C-ABI function double " + f_.symbol + "(double r, double h); from C++ declare it extern \"C\", "
                 "from Fortran bind(C, name='" + f_.symbol + "'))");
        if (tag == threw)
            fail(f_.symbol + " threw an exception" + (text.empty() ? "" : " (" + text + ")") + " " + where());
        fail("the child process evaluating " + f_.symbol + " sent a record mollify does not know");
    }

    const ForeignFunction& f_;
    std::span<const double> r_, h_;
    bool ready_ = false;
    std::vector<double> values_;
};

std::string seconds(std::chrono::milliseconds t) { return shortest(static_cast<double>(t.count()) / 1000) + " s"; }

}  // namespace

std::vector<double> evaluate_foreign(const ForeignFunction& f, std::span<const double> r, std::span<const double> h,
                                     std::chrono::milliseconds timeout) {
    if (r.size() != h.size()) fail("evaluate_foreign: " + std::to_string(r.size()) + " values of r, " +
                                   std::to_string(h.size()) + " of h");
    if (f.symbol.empty()) fail("the symbol name is empty");
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) fail(std::string("cannot create a pipe: ") + std::strerror(errno));
    Fd in(fds[0]), out(fds[1]);
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) fail(std::string("cannot fork a process for ") + f.symbol + ": " + std::strerror(errno));
    if (pid == 0) {
        ::close(fds[0]);
        child(fds[1], parent, f, r, h);
    }
    Child process(pid);
    out.close();
    Session session(f, r, h);
    std::string buffer;
    for (;;) {
        const Read got = read_some(in.get(), buffer, timeout);
        if (got == Read::timed_out) {
            const std::string where = session.where();
            process.kill();
            fail(f.symbol + " did not return within " + seconds(timeout) + " " + where +
                 " (an endless loop? --timeout sets the limit)");
        }
        if (got == Read::end_of_file) break;
        session.consume(buffer);
    }
    const int status = process.reap();
    if (!session.done()) fail(f.symbol + " " + ending(status) + " " + session.where());
    if (!buffer.empty()) fail("the child process evaluating " + f.symbol + " ended inside a record");
    return session.take();
}

}  // namespace mollify::app
