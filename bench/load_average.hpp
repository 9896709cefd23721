// The machine's load as /proc/loadavg gives it (1, 5 and 15 minute averages,
// runnable/total tasks, last pid): what a benchmark prints before and after
// its run, so a shared machine's state stands beside its ratios.
#pragma once

#include <fstream>
#include <string>

namespace mollify::bench {

inline std::string load_average() {
    std::ifstream in("/proc/loadavg");
    std::string s;
    std::getline(in, s);
    return s;
}

}  // namespace mollify::bench
