// A scene's output folder, written atomically: every file goes into a fresh
// staging directory beside the destination (DEST.tmp-XXXXXX); commit()
// renames it over DEST (the old DEST is removed only after the new one is
// complete), and an Output destroyed without commit() (an error, an
// exception) removes its staging directory, so a failed run never leaves a
// half-written folder and never destroys the previous complete one.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace mollify::app {

// A table of strings: written as CSV (data) and as a Markdown table (summary).
struct Table {
    std::vector<std::string> columns;
    std::vector<std::vector<std::string>> rows;

    void add(std::vector<std::string> row);  // Error if row.size() != columns.size()
    std::string csv() const;                 // RFC 4180 quoting where needed
    std::string markdown() const;
};

// A double as text: %.*g with `digits` significant digits ("nan"/"inf" kept
// visible, never silently formatted as numbers).
std::string format(double x, int digits = 4);

// Writes `content` to `file` atomically: a temporary file beside it, fsync,
// rename (a failure leaves no file and names the cause).
void write_atomically(const std::filesystem::path& file, std::string_view content);

class Output {
public:
    explicit Output(std::filesystem::path destination);
    Output(const Output&) = delete;
    Output& operator=(const Output&) = delete;
    ~Output();

    const std::filesystem::path& destination() const;
    const std::filesystem::path& staging() const;  // where files are written until commit()

    // A file NAME (relative, no "..") in the staging directory.
    void write(const std::string& name, std::string_view content);
    void csv(const std::string& name, const Table& table);
    // Runs gnuplot in the staging directory on `script` (which reads the CSV
    // files written so far, e.g. plot 'rates.csv' using 1:2), after
    // "set terminal pngcairo size W,H; set output 'NAME'; set datafile separator ',';
    // set key autotitle columnheader" (the CSV header row titles the curves;
    // gnuplot's messages name the script "PNG.gp" and its own line numbers).
    // Error (naming the PNG and gnuplot's stderr) if gnuplot fails or is missing;
    // gnuplot's warnings (exit status 0) are copied to stderr.
    void plot(const std::string& png, std::string_view script, int width = 900, int height = 600);

    // The Markdown summary (summary.md), appended to by the experiment.
    std::string& summary();

    // Writes summary.md, then atomically replaces the destination.
    void commit();

private:
    std::filesystem::path destination_;
    std::filesystem::path staging_;
    std::string summary_;
    bool committed_ = false;
    bool created_parent_ = false;  // removed again (if empty) when not committed
};

// Progress on stderr: "[stage] done/total detail", rewritten in place when
// stderr is a terminal (at most ~10 updates a second), else one line per
// call at most once a second. The call with done == total is always shown
// (and ends the in-place line). Cheap enough to call per step; thread-safe
// (a call made while another thread is printing is skipped).
void progress(std::string_view stage, std::size_t done, std::size_t total, std::string_view detail = {});
// Clears an unfinished in-place progress line (before other stderr output).
void progress_clear();

}  // namespace mollify::app
