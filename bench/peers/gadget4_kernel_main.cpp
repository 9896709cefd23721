// GADGET-4's kernel_main(u, hinv3, hinv4, &wk, &dwk, mode), both values
// (COMPUTE_WK_AND_DWK), timed as its SPH loops call it: built once with
// GADGET-4's stock src/sph/kernel.h and once with mollify's header
// (`mollify-gen emit --target gadget4`, which defines kernel_main the same
// way), with GADGET-4's flags (bench/gadget4_kernel_bench.sh): 4096 u
// spread over [0, 1) by the golden ratio, the function inlined into a loop
// and called once a point through a function the compiler may not inline.
// Built with EXPLICIT_VECTORIZATION (GADGET-4's Config.sh option; Vec4d
// from its vectorclass), also kernel_main_vector on four u at once, as its
// density and hydro loops call it (src/sph/density.cc, hydra.cc).
// Prints the least ns a point of 7 timings of SWEEPS sweeps for each, and
// the sums of wk and dwk over one sweep (h = 1) to compare the two headers.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#ifdef EXPLICIT_VECTORIZATION
#include "vectorclass/vectorclass.h"
#endif
#ifndef NUMDIMS
#define NUMDIMS 3  // GADGET-4's src/data/constants.h without ONEDIMS or TWODIMS
#endif
#include KERNEL_HEADER

namespace {

constexpr int n = 4096, runs = 7;
double u[n];

__attribute__((noinline)) void main_call(double x, double *wk, double *dwk) {
  kernel_main(x, 1.0, 1.0, wk, dwk, COMPUTE_WK_AND_DWK);
}
inline __attribute__((always_inline)) void main_inlined(double x, double *wk, double *dwk) {
  kernel_main(x, 1.0, 1.0, wk, dwk, COMPUTE_WK_AND_DWK);
}

double seconds() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// The sweeps with f, a constant at each use: inlined into the loop, or a call a point.
template <void (*F)(double, double *, double *)>
double sweeps_of(int sweeps) {
  double sw = 0, sg = 0;
  for (int s = 0; s < sweeps; ++s)
    for (int i = 0; i < n; ++i) {
      double wk, dwk;
      F(u[i], &wk, &dwk);
      sw += wk;
      sg += dwk;
    }
  return sw + sg;
}

#ifdef EXPLICIT_VECTORIZATION
// kernel_main_vector over the u four at a time (NORM in the hinv3 and hinv4
// it is passed, as GADGET-4's loops pass them: h = 1).
double vector_sweeps(int sweeps) {
  Vec4d sum(0.0);
  for (int s = 0; s < sweeps; ++s)
    for (int i = 0; i < n; i += 4) {
      Vec4d x, wk, dwk;
      x.load(u + i);
      kernel_main_vector(x, Vec4d(NORM), Vec4d(NORM), &wk, &dwk);
      sum += wk + dwk;
    }
  return horizontal_add(sum);
}
#endif

double best_ns(double (*sweep)(int), int sweeps, double &keep) {
  double best = 1e300;
  for (int r = 0; r < runs; ++r) {
    const double t0 = seconds();
    keep += sweep(sweeps);
    const double t = (seconds() - t0) / (double(sweeps) * n) * 1e9;
    if (t < best) best = t;
  }
  return best;
}

}  // namespace

int main(int argc, char **argv) {
  int sweeps = 20000;
  if (argc > 1) {
    char *end;
    const long s = strtol(argv[1], &end, 10);
    if (*end != '\0' || s < 1 || s > 100000000) {
      fprintf(stderr, "gadget4_kernel_main: SWEEPS must be a positive integer, not '%s'\n", argv[1]);
      return 2;
    }
    sweeps = int(s);
  }
  double sum_w = 0, sum_dw = 0, keep = 0;
  for (int i = 0; i < n; ++i) {
    const double f = i * 0.6180339887498949;
    u[i] = f - floor(f);
  }
  for (int i = 0; i < n; ++i) {
    double wk, dwk;
    main_call(u[i], &wk, &dwk);
    sum_w += wk;
    sum_dw += dwk;
  }
  const double inlined = best_ns(sweeps_of<main_inlined>, sweeps, keep);
  const double called = best_ns(sweeps_of<main_call>, sweeps, keep);
#ifdef EXPLICIT_VECTORIZATION
  const double vector = best_ns(vector_sweeps, sweeps, keep);
#else
  const double vector = 0;
#endif
  if (keep != keep) return 1;  // the timed sums are used (a NaN fails)
  printf("ns_inlined %.3f ns_called %.3f ns_vector %.3f sum_w %.17e sum_dw %.17e\n", inlined, called, vector, sum_w, sum_dw);
  return 0;
}
