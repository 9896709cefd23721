// OpenMP where the translation unit is compiled with it (-fopenmp), plain
// serial loops otherwise: the pragmas are spelled through _Pragma so that a
// build without OpenMP gets no -Wunknown-pragmas (an error under -Werror).
#pragma once

#if defined(_OPENMP)
#include <omp.h>
#define MOLLIFY_PRAGMA(x) _Pragma(#x)
#define MOLLIFY_PARALLEL_FOR(clauses) MOLLIFY_PRAGMA(omp parallel for clauses)
#define MOLLIFY_PARALLEL(clauses) MOLLIFY_PRAGMA(omp parallel clauses)
#define MOLLIFY_FOR(clauses) MOLLIFY_PRAGMA(omp for clauses)
#define MOLLIFY_SIMD MOLLIFY_PRAGMA(omp simd)
#define MOLLIFY_SIMD_SUM(x) MOLLIFY_PRAGMA(omp simd reduction(+ : x))
#else
#define MOLLIFY_PARALLEL_FOR(clauses)
#define MOLLIFY_PARALLEL(clauses)
#define MOLLIFY_FOR(clauses)
#define MOLLIFY_SIMD
#define MOLLIFY_SIMD_SUM(x)
#endif

#include <thread>

namespace mollify::detail {

inline int thread_count() {
#if defined(_OPENMP)
    return omp_get_max_threads();
#else
    return 1;
#endif
}

// The threads of the enclosing parallel region (1 outside one).
inline int team_size() {
#if defined(_OPENMP)
    return omp_get_num_threads();
#else
    return 1;
#endif
}

inline int thread_index() {
#if defined(_OPENMP)
    return omp_get_thread_num();
#else
    return 0;
#endif
}

// The pause hint of a busy wait (leaves a sibling hyperthread the core).
inline void cpu_pause() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

// Waits until done(), for waits of one thread's short serial step: busy
// with the pause hint, then yielding the core (~50 us on), where threads
// outnumber cores and the awaited thread may need this one's.
template <class Done>
void spin_until(Done&& done) {
    for (int k = 0; !done(); ++k) {
        if (k < 4096) cpu_pause();
        else std::this_thread::yield();
    }
}

}  // namespace mollify::detail
