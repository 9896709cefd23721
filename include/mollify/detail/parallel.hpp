// OpenMP where the translation unit is compiled with it (-fopenmp), plain
// serial loops otherwise: the pragmas are spelled through _Pragma so that a
// build without OpenMP gets no -Wunknown-pragmas (an error under -Werror).
#pragma once

#if defined(_OPENMP)
#include <omp.h>
#define MOLLIFY_PRAGMA(x) _Pragma(#x)
#define MOLLIFY_PARALLEL_FOR(clauses) MOLLIFY_PRAGMA(omp parallel for clauses)
#define MOLLIFY_SIMD MOLLIFY_PRAGMA(omp simd)
#define MOLLIFY_SIMD_SUM(x) MOLLIFY_PRAGMA(omp simd reduction(+ : x))
#else
#define MOLLIFY_PARALLEL_FOR(clauses)
#define MOLLIFY_SIMD
#define MOLLIFY_SIMD_SUM(x)
#endif

namespace mollify::detail {

inline int thread_count() {
#if defined(_OPENMP)
    return omp_get_max_threads();
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

}  // namespace mollify::detail
