/* SWIFT's kernel_deval(u, &W, &dW_dx) timed as SWIFT's hydro loops call it,
 * built once with SWIFT's stock src/kernel_hydro.h and once with mollify's
 * (`mollify-gen emit --target swift`), with SWIFT's GCC flags
 * (bench/swift_kernel_bench.sh): 4096 u spread over [0, kernel_gamma) by the
 * golden ratio, two ways: a loop over the points with the function inlined
 * (as in SWIFT's pair loops; the compiler may vectorise it), and one call a
 * point through a function the compiler may not inline (a scalar call).
 * Built with WITH_VECTORIZATION (and SWIFT's vector.h), also a third way: the
 * SIMD function kernel_deval_1_vec on VEC_SIZE points at a time, as SWIFT's
 * hand-vectorised GADGET-2 SPH loops call it (SWIFT's stock file has it for
 * Wendland C2 and the cubic spline only; without it ns_vector is nan).
 * Prints the least ns a point of 7 timings of SWEEPS sweeps for each, and the
 * sums of W and dW/dx over one sweep (in double) to compare the two headers'
 * values. */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "kernel_hydro.h"

#define N 4096
#define RUNS 7

static float u[N] __attribute__((aligned(64))); /* vec_load's alignment */

__attribute__((noinline)) static void deval_call(float x, float *w, float *dw) { kernel_deval(x, w, dw); }

static double seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The sweeps with f, a constant at each use: kernel_deval itself (inlined
 * into the loop) or deval_call (a call a point). */
static inline __attribute__((always_inline)) double sweeps_of(void (*f)(float, float *, float *), int sweeps) {
  float sw = 0.f, sg = 0.f;
  int s, i;
  for (s = 0; s < sweeps; ++s)
    for (i = 0; i < N; ++i) {
      float w, dw;
      f(u[i], &w, &dw);
      sw += w;
      sg += dw;
    }
  return (double)sw + (double)sg;
}

static double sweep_inlined(int sweeps) { return sweeps_of(kernel_deval, sweeps); }
static double sweep_called(int sweeps) { return sweeps_of(deval_call, sweeps); }

#if defined(WITH_VECTORIZATION)
static double sweep_vector(int sweeps) {
  vector sw, sg;
  double t = 0;
  int s, i, k;
  sw.v = vec_setzero();
  sg.v = vec_setzero();
  for (s = 0; s < sweeps; ++s)
    for (i = 0; i < N; i += VEC_SIZE) {
      vector x, w, dw;
      x.v = vec_load(&u[i]);
      kernel_deval_1_vec(&x, &w, &dw);
      sw.v = vec_add(sw.v, w.v);
      sg.v = vec_add(sg.v, dw.v);
    }
  for (k = 0; k < VEC_SIZE; ++k) t += (double)sw.f[k] + (double)sg.f[k];
  return t;
}
#endif

static double best_ns(double (*sweep)(int), int sweeps, double *keep) {
  double best = 1e300;
  int r;
  for (r = 0; r < RUNS; ++r) {
    const double t0 = seconds();
    *keep += sweep(sweeps);
    const double t = (seconds() - t0) / ((double)sweeps * N) * 1e9;
    if (t < best) best = t;
  }
  return best;
}

int main(int argc, char **argv) {
  int sweeps = 20000, i;
  double keep = 0, sum_w = 0, sum_dw = 0;
  if (argc > 1) {
    char *end;
    const long s = strtol(argv[1], &end, 10);
    if (*end != '\0' || s < 1 || s > 100000000) {
      fprintf(stderr, "swift_kernel_deval: SWEEPS must be a positive integer, not '%s'\n", argv[1]);
      return 2;
    }
    sweeps = (int)s;
  }
  for (i = 0; i < N; ++i) {
    const double f = (double)i * 0.6180339887498949;
    u[i] = (float)((double)kernel_gamma * (f - (double)(long)f));
  }
  for (i = 0; i < N; ++i) {
    float w, dw;
    kernel_deval(u[i], &w, &dw);
    sum_w += w;
    sum_dw += dw;
  }
  {
    const double inlined = best_ns(sweep_inlined, sweeps, &keep);
    const double called = best_ns(sweep_called, sweeps, &keep);
#if defined(WITH_VECTORIZATION)
    const double vectorised = best_ns(sweep_vector, sweeps, &keep);
#else
    const double vectorised = 0.0 / 0.0; /* no SIMD function in this header */
#endif
    if (keep != keep) return 1; /* the timed sums are used (a NaN fails) */
    printf("ns_inlined %.3f ns_called %.3f ns_vector %.3f sum_w %.17e sum_dw %.17e\n", inlined, called, vectorised, sum_w,
           sum_dw);
  }
  return 0;
}
