/* SWIFT's softened pair gravity timed as its particle-particle loop takes
 * it, built once with SWIFT's stock src/kernel_gravity.h and once with
 * mollify's (`mollify-gen emit --target swift`), with SWIFT's GCC flags
 * (bench/swift_gravity_bench.sh). The loop is ours, written after the shape
 * of SWIFT's runner_dopair_grav_pp_full (src/runner_doiact_grav.c) and
 * runner_iact_grav_pp_full (src/gravity/MultiSoftening/gravity_iact.h):
 * for each target i, every source j of a cache of structure-of-arrays floats,
 * the separation (wrapped by nearestf where `periodic`, a run-time flag, as
 * SWIFT's), the softening max(H_i, H_j), Newtonian gravity for r >= H, else
 * kernel_grav_force_eval and kernel_grav_pot_eval at u = r/H, and the sums of
 * acceleration and potential. GCC vectorises such a loop only when it can
 * unswitch it on `periodic` and if-convert the softened branch, which a long
 * kernel function (the double plan's Taylor pieces) prevented (stop 90).
 * NSOURCE sources uniform in a unit box, their softening H in [0.1, 0.3]
 * (a quarter of the pairs softened), NTARGET targets among them; prints the
 * least ns a pair of 7 timings of SWEEPS sweeps, and the sums of the
 * potential and of |a| over one sweep (in double) to compare the headers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "kernel_gravity.h"

#define NSOURCE 4096
#define NTARGET 64
#define RUNS 7

static float xs[NSOURCE] __attribute__((aligned(64))), ys[NSOURCE] __attribute__((aligned(64))),
    zs[NSOURCE] __attribute__((aligned(64))), ms[NSOURCE] __attribute__((aligned(64))),
    hs[NSOURCE] __attribute__((aligned(64)));

static double seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static float nearest(float d, float box) { return d > 0.5f * box ? d - box : (d < -0.5f * box ? d + box : d); }

/* One target against every source: acceleration and potential sums. */
static inline __attribute__((always_inline)) void target(int i, int periodic, float box, float *out) {
  const float xi = xs[i], yi = ys[i], zi = zs[i], hi = hs[i];
  float ax = 0.f, ay = 0.f, az = 0.f, pot = 0.f;
  int j;
  for (j = 0; j < NSOURCE; ++j) {
    float dx = xs[j] - xi, dy = ys[j] - yi, dz = zs[j] - zi;
    if (periodic) {
      dx = nearest(dx, box);
      dy = nearest(dy, box);
      dz = nearest(dz, box);
    }
    const float r2 = dx * dx + dy * dy + dz * dz;
    const float h = hi > hs[j] ? hi : hs[j];
    const float h_inv = 1.f / h, h_inv3 = h_inv * h_inv * h_inv;
    const float r_inv = 1.f / sqrtf(r2 + 1e-30f);
    float f, p;
    if (r2 >= h * h) {
      f = ms[j] * r_inv * r_inv * r_inv;
      p = -ms[j] * r_inv;
    } else {
      const float ui = r2 * r_inv * h_inv;
      f = ms[j] * h_inv3 * kernel_grav_force_eval(ui);
      p = ms[j] * h_inv * kernel_grav_pot_eval(ui);
    }
    ax += f * dx;
    ay += f * dy;
    az += f * dz;
    pot += p;
  }
  out[0] = ax;
  out[1] = ay;
  out[2] = az;
  out[3] = pot;
}

static double sweep(int sweeps, int periodic, double *sum_pot, double *sum_a) {
  double keep = 0;
  int s, i;
  for (s = 0; s < sweeps; ++s)
    for (i = 0; i < NTARGET; ++i) {
      float o[4];
      target(i * (NSOURCE / NTARGET), periodic, 1.f, o);
      keep += (double)o[0] + (double)o[3];
      if (s == 0) {
        *sum_pot += o[3];
        *sum_a += sqrt((double)o[0] * o[0] + (double)o[1] * o[1] + (double)o[2] * o[2]);
      }
    }
  return keep;
}

int main(int argc, char **argv) {
  int sweeps = 200, i, r, periodic = 0;
  double keep = 0, best = 1e300, sum_pot = 0, sum_a = 0;
  if (argc > 1) {
    char *end;
    const long s = strtol(argv[1], &end, 10);
    if (*end != '\0' || s < 1 || s > 1000000) {
      fprintf(stderr, "swift_grav_pp: SWEEPS must be a positive integer, not '%s'\n", argv[1]);
      return 2;
    }
    sweeps = (int)s;
  }
  /* the flag comes from outside, as SWIFT's does: the compiler cannot fold it */
  periodic = getenv("SWIFT_GRAV_PP_PERIODIC") != NULL;
  for (i = 0; i < NSOURCE; ++i) {
    const double a = (double)i * 0.6180339887498949, b = (double)i * 0.7548776662466927,
                 c = (double)i * 0.5698402909980532, d = (double)i * 0.4142135623730950;
    xs[i] = (float)(a - (double)(long)a);
    ys[i] = (float)(b - (double)(long)b);
    zs[i] = (float)(c - (double)(long)c);
    hs[i] = (float)(0.1 + 0.2 * (d - (double)(long)d));
    ms[i] = 1.f / NSOURCE;
  }
  for (r = 0; r < RUNS; ++r) {
    double p = 0, a = 0;
    const double t0 = seconds();
    keep += sweep(sweeps, periodic, &p, &a);
    const double t = (seconds() - t0) / ((double)sweeps * NSOURCE * NTARGET) * 1e9;
    if (t < best) best = t;
    sum_pot = p;
    sum_a = a;
  }
  if (keep != keep) return 1; /* the timed sums are used (a NaN fails) */
  printf("ns_pair %.4f sum_w %.17e sum_a %.17e\n", best, sum_pot, sum_a);
  return 0;
}
