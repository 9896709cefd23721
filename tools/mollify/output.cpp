// The atomic output folder, tables, number formatting, gnuplot, progress.
#include "output.hpp"
#include "process.hpp"

#include <mollify/error.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <mutex>

#include <fcntl.h>
#include <stdio.h>  // renameat2 (glibc >= 2.28)
#include <sys/stat.h>
#include <unistd.h>

extern char** environ;

namespace fs = std::filesystem;

namespace mollify::app {

namespace {

std::string errno_text(int e) { return std::strerror(e); }

// "a/b.csv": relative, no "..", no ".", no empty components, no absolute path.
void check_name(const std::string& name) {
    const fs::path p(name);
    bool ok = !name.empty() && p.is_relative() && name.back() != '/';
    for (const auto& part : p) ok = ok && !part.empty() && part != "." && part != "..";
    if (!ok) fail("output file name '" + name + "' must be a relative path without '.' or '..' components");
}

std::string csv_field(const std::string& f) {
    if (f.find_first_of(",\"\r\n") == std::string::npos) return f;
    std::string q = "\"";
    for (char c : f) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string markdown_cell(const std::string& f) {
    std::string m;
    for (char c : f) {
        if (c == '|') m += "\\|";
        else if (c == '\n' || c == '\r') m += ' ';
        else m += c;
    }
    return m;
}

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s;
}

}  // namespace

void write_atomically(const fs::path& file, std::string_view content) {
    std::string tmp = file.string() + ".tmp-XXXXXX";
    const int fd = ::mkstemp(tmp.data());
    if (fd < 0) fail("cannot create " + tmp + ": " + errno_text(errno));
    std::size_t done = 0;
    while (done < content.size()) {
        const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int e = errno;
            ::close(fd);
            ::unlink(tmp.c_str());
            fail("cannot write " + file.string() + ": " + errno_text(e));
        }
        done += static_cast<std::size_t>(n);
    }
    ::fchmod(fd, 0644);  // mkstemp makes 0600; these are ordinary result files
    if (::fsync(fd) != 0 || ::close(fd) != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        fail("cannot write " + file.string() + ": " + errno_text(e));
    }
    if (::rename(tmp.c_str(), file.c_str()) != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        fail("cannot rename " + tmp + " to " + file.string() + ": " + errno_text(e));
    }
}


// ---------------------------------------------------------------- Table

void Table::add(std::vector<std::string> row) {
    if (row.size() != columns.size())
        fail("table row has " + std::to_string(row.size()) + " cells, the table has " + std::to_string(columns.size()) +
             " columns");
    rows.push_back(std::move(row));
}

std::string Table::csv() const {
    std::string s;
    auto line = [&](const std::vector<std::string>& r) {
        for (std::size_t i = 0; i < r.size(); ++i) s += (i ? "," : "") + csv_field(r[i]);
        s += "\n";
    };
    line(columns);
    for (const auto& r : rows) line(r);
    return s;
}

std::string Table::markdown() const {
    std::string s;
    auto line = [&](const std::vector<std::string>& r) {
        s += "|";
        for (const auto& c : r) s += " " + markdown_cell(c) + " |";
        s += "\n";
    };
    line(columns);
    s += "|";
    for (std::size_t i = 0; i < columns.size(); ++i) s += "---|";
    s += "\n";
    for (const auto& r : rows) line(r);
    return s;
}

std::string format(double x, int digits) {
    if (std::isnan(x)) return "nan";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    digits = std::clamp(digits, 1, 17);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, x);
    return buf;
}

// ---------------------------------------------------------------- Output

Output::Output(fs::path destination) {
    if (!destination.has_filename()) destination = destination.parent_path();  // "out/x/" -> "out/x"
    const std::string leaf = destination.filename().string();
    if (leaf.empty() || leaf == "." || leaf == "..")
        fail("output folder '" + destination.string() + "' must name a folder (not '.' or '..')");
    destination = destination.lexically_normal();
    std::error_code ec;
    const auto st = fs::symlink_status(destination, ec);
    if (fs::exists(st) && !fs::is_directory(st))
        fail("output folder " + destination.string() + " exists and is not a folder; not replacing it");
    const fs::path parent = destination.has_parent_path() ? destination.parent_path() : fs::path(".");
    created_parent_ = fs::create_directories(parent, ec);
    if (ec) fail("cannot create " + parent.string() + ": " + ec.message());
    std::string tmp = (parent / (leaf + ".tmp-XXXXXX")).string();
    if (!::mkdtemp(tmp.data())) fail("cannot create a staging folder beside " + destination.string() + ": " + errno_text(errno));
    ::chmod(tmp.c_str(), 0755);  // mkdtemp makes 0700; the result is an ordinary folder
    destination_ = std::move(destination);
    staging_ = tmp;
}

Output::~Output() {
    if (committed_) return;
    std::error_code ec;
    fs::remove_all(staging_, ec);  // best effort: a destructor must not throw
    if (created_parent_) fs::remove(staging_.parent_path(), ec);  // only if empty
}

const fs::path& Output::destination() const { return destination_; }
const fs::path& Output::staging() const { return staging_; }
std::string& Output::summary() { return summary_; }

void Output::write(const std::string& name, std::string_view content) {
    if (committed_) fail("output " + destination_.string() + " is already committed; cannot write " + name);
    check_name(name);
    const fs::path file = staging_ / name;
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    if (ec) fail("cannot create " + file.parent_path().string() + ": " + ec.message());
    write_atomically(file, content);
}

void Output::csv(const std::string& name, const Table& table) { write(name, table.csv()); }

void Output::plot(const std::string& png, std::string_view script, int width, int height) {
    if (committed_) fail("output " + destination_.string() + " is already committed; cannot plot " + png);
    check_name(png);
    if (png.find('\'') != std::string::npos) fail("plot name '" + png + "' must not contain a quote");
    if (width < 16 || height < 16 || width > 20000 || height > 20000)
        fail("plot " + png + ": size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 16..20000");
    std::error_code ec;
    fs::create_directories((staging_ / png).parent_path(), ec);

    // gnuplot runs the preamble (-e) and then the script from a file, which
    // its messages name ("NAME.png.gp" line 3: ...) and which is removed
    // afterwards; the PNG is written under a temporary name and renamed when
    // gnuplot succeeds.
    const std::string tmp_png = png + ".tmp-" + std::to_string(::getpid()) + ".png";
    const std::string script_name = png + ".gp";
    const fs::path script_file = staging_ / script_name;
    if (fs::exists(script_file, ec)) fail("plot " + png + ": " + script_name + " exists in the output already");
    write_atomically(script_file, script);
    const std::string preamble = "set terminal pngcairo size " + std::to_string(width) + "," + std::to_string(height) +
                                 "; set output '" + tmp_png +
                                 "'; set datafile separator ','; set key autotitle columnheader";

    ProcessResult r;
    try {
        r = run_process("gnuplot", {"-e", preamble, script_name}, staging_,
                        "run tools/install-deps.sh, which installs gnuplot-nox");
    } catch (const Error& e) {
        fs::remove(script_file, ec);
        fail("plot " + png + ": " + e.what());
    }
    const std::string err = trim(r.err);
    fs::remove(script_file, ec);
    const fs::path produced = staging_ / tmp_png;
    const bool ok = r.ok() && fs::file_size(produced, ec) > 0 && !ec;
    if (!ok) {
        fs::remove(produced, ec);
        std::string why = r.exit_status >= 0 ? "exit status " + std::to_string(r.exit_status) : "killed by a signal";
        if (r.ok()) why = "no image written";
        fail("plot " + png + ": gnuplot failed (" + why + ")" + (err.empty() ? "" : ":\n" + err));
    }
    if (!err.empty()) std::cerr << "mollify: gnuplot warnings for " << png << ":\n" << err << "\n";
    fs::rename(produced, staging_ / png);
}

void Output::commit() {
    if (committed_) fail("output " + destination_.string() + " is already committed");
    write("summary.md", summary_);
    // Where the kernel can swap the two folders in one step (Linux
    // renameat2 RENAME_EXCHANGE), DEST never disappears; otherwise the old
    // DEST is renamed aside first. The old folder is removed last.
    const std::string dest = destination_.string(), stage = staging_.string();
    std::error_code ec;
    fs::path old;
    const bool exists = fs::exists(fs::symlink_status(destination_));
    if (exists && !fs::is_directory(fs::symlink_status(destination_)))
        fail("output folder " + dest + " exists and is not a folder; not replacing it (the run is in " + stage + ")");
    if (!exists) {
        if (::rename(stage.c_str(), dest.c_str()) != 0)
            fail("cannot rename " + stage + " to " + dest + ": " + errno_text(errno));
    } else if (::renameat2(AT_FDCWD, stage.c_str(), AT_FDCWD, dest.c_str(), RENAME_EXCHANGE) == 0) {
        old = staging_;  // now holds the previous DEST
    } else {
        std::string aside = dest + ".old-XXXXXX";
        if (!::mkdtemp(aside.data())) fail("cannot create a folder beside " + dest + ": " + errno_text(errno));
        if (::rename(dest.c_str(), aside.c_str()) != 0) {  // replaces the empty folder `aside`
            const int e = errno;
            ::rmdir(aside.c_str());
            fail("cannot move the previous " + dest + " aside: " + errno_text(e));
        }
        if (::rename(stage.c_str(), dest.c_str()) != 0) {
            const int e = errno;
            ::rename(aside.c_str(), dest.c_str());  // put the previous folder back
            fail("cannot rename " + stage + " to " + dest + ": " + errno_text(e));
        }
        old = aside;
    }
    committed_ = true;
    if (!old.empty()) {
        fs::remove_all(old, ec);
        if (ec) std::cerr << "mollify: warning: could not remove the previous output " << old.string() << ": " << ec.message() << "\n";
    }
}

// ---------------------------------------------------------------- progress

namespace {

struct Progress {
    std::mutex mutex;
    std::chrono::steady_clock::time_point last{};
    std::size_t width = 0;  // length of the in-place line on a terminal (0: none)
    int tty = -1;
};

Progress& progress_state() {
    static Progress p;
    return p;
}

}  // namespace

void progress(std::string_view stage, std::size_t done, std::size_t total, std::string_view detail) {
    Progress& p = progress_state();
    const bool final = done >= total;
    std::unique_lock lock(p.mutex, std::defer_lock);
    if (final) lock.lock();
    else if (!lock.try_lock()) return;  // another thread is reporting: skip, it is only progress
    if (p.tty < 0) p.tty = ::isatty(STDERR_FILENO) ? 1 : 0;
    const auto now = std::chrono::steady_clock::now();
    // ~10 Hz on a terminal; 1 line a second into a log file; always the last call.
    const auto interval = p.tty ? std::chrono::milliseconds(100) : std::chrono::milliseconds(1000);
    if (!final && p.last != std::chrono::steady_clock::time_point{} && now - p.last < interval) return;
    p.last = final ? std::chrono::steady_clock::time_point{} : now;
    std::string line = "[" + std::string(stage) + "] " + std::to_string(done) + "/" + std::to_string(total);
    if (!detail.empty()) line += " " + std::string(detail);
    if (p.tty) {
        const std::size_t pad = p.width > line.size() ? p.width - line.size() : 0;
        std::cerr << "\r" << line << std::string(pad, ' ');
        if (final) {
            std::cerr << "\n";
            p.width = 0;
        } else {
            p.width = line.size();
        }
    } else {
        std::cerr << line << "\n";
    }
    std::cerr.flush();
}

void progress_clear() {
    Progress& p = progress_state();
    std::lock_guard lock(p.mutex);
    if (p.width == 0) return;
    std::cerr << "\r" << std::string(p.width, ' ') << "\r";
    std::cerr.flush();
    p.width = 0;
}

}  // namespace mollify::app
