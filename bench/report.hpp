// What the benchmarks share for their Markdown results: a reporter that keeps
// every run (and says which were skipped) while printing as usual, and
// printf-style number formatting.
#pragma once

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mollify::bench {

// Google Benchmark's own flags parsed (and removed from argv); returns FILE
// of the benchmarks' one extra flag --md=FILE (empty if absent).
inline std::string initialize(int& argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    std::string md;
    for (int i = 1; i < argc; ++i)
        if (std::string_view(argv[i]).substr(0, 5) == "--md=") md = argv[i] + 5;
    return md;
}

class Collector : public benchmark::ConsoleReporter {
public:
    // Colours only on a terminal: a reporter passed to RunSpecifiedBenchmarks
    // keeps its own options (--benchmark_color sets only the default one's),
    // and piped into a file or grep the escape codes were in every line.
    Collector() : ConsoleReporter(isatty(fileno(stdout)) ? OO_ColorTabular : OO_Tabular) {}
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& r : runs)
            if (!r.error_occurred)
                runs_.push_back(r);
            else
                skipped_.push_back(r.run_name.function_name + ": " + r.error_message);
        ConsoleReporter::ReportRuns(runs);
    }
    const std::vector<Run>& runs() const { return runs_; }
    const std::vector<std::string>& skipped() const { return skipped_; }

private:
    std::vector<Run> runs_;
    std::vector<std::string> skipped_;
};

inline std::string number(const char* f, double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, x);
    return buf;
}

// Least-squares slope of log t against log N: the alpha of t ~ N^alpha.
inline double slope(const std::vector<std::pair<double, double>>& nt) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double m = static_cast<double>(nt.size());
    for (const auto& [n, t] : nt) {
        const double lx = std::log(n), ly = std::log(t);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

}  // namespace mollify::bench
