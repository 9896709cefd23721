// `mollify report`: the verification report (README, "The report"). Runs
// the sections below in turn, each into its own folder of the report, and
// writes report/index.md atomically with the figures beside it. A section
// that fails is reported in its place; the others still run.
#pragma once

#include "output.hpp"
#include "scene.hpp"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace mollify::app {

struct ReportOptions {
    std::filesystem::path out = "report";   // the report folder
    std::filesystem::path scenes;           // a folder like scenes/ to read the scenes from; empty: the embedded ones
    std::vector<std::string> only;          // section ids to run (empty: all)
};

// Runs the report; returns the exit status (0: every section passed, 1: not).
int run_report(const ReportOptions& options);

// What a section needs from the report.
struct ReportContext {
    std::filesystem::path tools;      // folder of mollify-gen, mollify-stability, kernel_bench
    std::filesystem::path generated;  // the checked-in tables (generated/) to compare with
    std::filesystem::path scenes;     // as ReportOptions::scenes
};

// What a section gives the index: its Markdown (links relative to the
// report folder) and whether everything it checks passed.
struct SectionResult {
    std::string markdown;
    std::vector<std::string> failures;  // each one line; empty: passed
};

struct Section {
    std::string_view id;     // its folder in the report, and --only
    std::string_view title;  // the heading in index.md
    void (*run)(const ReportContext&, Output&, SectionResult&);
    std::string_view reads = {};  // a section whose output it links (run before it)
};

// The sections, in the order of index.md (report_*.cpp, one per file).
void report_exactness(const ReportContext&, Output&, SectionResult&);
void report_accuracy(const ReportContext&, Output&, SectionResult&);
void report_speed(const ReportContext&, Output&, SectionResult&);
void report_studies(const ReportContext&, Output&, SectionResult&);
void report_figures(const ReportContext&, Output&, SectionResult&);

// Helpers shared by the sections (report.cpp).
// The scene NAME relative to scenes/ (e.g. "report/franz_torus.toml"): from
// ReportContext::scenes when set, else the copy compiled into mollify.
Scene report_scene(const ReportContext& ctx, std::string_view name);
// Runs a scene's experiment into the folder `sub` of `out` (atomically, as
// `mollify run` does); returns the experiment's summary.md text.
std::string run_scene_in(const Scene& scene, Output& out, const std::string& sub);
// A file's whole text (empty if it cannot be read).
std::string read_text(const std::filesystem::path& file);
// The part of a Markdown text under the first heading line starting with
// `heading` (e.g. "## Rates"), up to the next heading of the same or a
// higher level; empty if there is none.
std::string markdown_section(const std::string& markdown, std::string_view heading);

}  // namespace mollify::app
