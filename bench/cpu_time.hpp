// Process CPU seconds (all threads): the per-core figure of a one-thread
// benchmark, robust to the load of a shared machine.
#pragma once

#include <ctime>

namespace mollify::bench {

inline double cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace mollify::bench
