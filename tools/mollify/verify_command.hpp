// `mollify verify`: someone's kernel against the exact one (issue 20, item 4;
// README, "Verify your kernel from any language").
//
//   mollify verify SPEC --dim D --library libmine.so --symbol my_w [options]
//   mollify verify SPEC --dim D --samples FILE.csv [options]
//
// The library's `double my_w(double r, double h)` runs in a child process
// (foreign_function.hpp) at mollify::verify::samples(); a CSV brings its own
// (r, h, value) rows (samples_csv.hpp). mollify::verify::compare judges them.
// Exit status: 0 within --ulps, 1 outside (the report says why), 2 bad input
// (a bad spec, library, symbol, CSV row; a crash, hang, NaN of the function).
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace mollify::app {

struct VerifyOptions {
    std::string spec;
    int dim = 0;
    std::string library, symbol;  // --library, --symbol
    std::string samples;          // --samples FILE.csv
    std::string arguments;        // --write-arguments FILE.csv: the sample arguments, to evaluate elsewhere
    std::string quantity = "value";
    std::string convention = "cpp";
    double ulps = 4;
    std::uint64_t seed = 1;
    std::size_t points = 10000;
    double timeout = 10;  // seconds one evaluation may take
};

// Adds the subcommand to `app`, its options bound to `options`.
CLI::App* add_verify_command(CLI::App& app, VerifyOptions& options);

// Runs it: prints the report and the verdict; returns the exit status.
int run_verify(const VerifyOptions& options);

}  // namespace mollify::app
