/* Timing harness of headplan-bench (see bench_timing.h). */
#define _POSIX_C_SOURCE 200809L
#include "bench/bench_timing.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <time.h>

/* A single method may take at most about this long to time, so that slow methods (the
 * planner's milliseconds) do not stretch a run; fast ones hit the sample count first. */
#define BUDGET_NS_FULL 0.6e9
#define BUDGET_NS_QUICK 0.03e9
#define MIN_SAMPLES 21
#define MAX_BATCH (1L << 24)

void bench_options_default(bench_options *o, int quick, unsigned long seed)
{
    o->quick = quick;
    o->seed = seed;
    /* 10 µs batches: clock_gettime costs ~20 ns through the vDSO, so the clock is < 1 % of
     * a batch; quick mode only needs the rows, not stable numbers. */
    o->samples = quick ? 101 : 20001;
    o->warmup_batches = quick ? 5 : 200;
    o->batch_target_ns = quick ? 2e3 : 1e4;
    o->scene = NULL;
    o->scenarios = NULL;
    o->python = NULL;
    o->peer_script = NULL;
    o->out_dir = NULL;
}

double bench_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double bench_percentile(const double *sorted, long n, double p)
{
    if (n <= 0) return NAN;
    if (p == 0.5) return (n % 2) ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
    long k = (long)ceil(p * (double)n) - 1;
    if (k < 0) k = 0;
    if (k >= n) k = n - 1;
    return sorted[k];
}

void bench_shuffle(long *perm, long n, unsigned long seed)
{
    uint64_t s = (uint64_t)seed * 0x9E3779B97F4A7C15u + 0x2545F4914F6CDD1Du;
    for (long i = 0; i < n; ++i) perm[i] = i;
    for (long i = n - 1; i > 0; --i) {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        uint64_t r = s * 0x2545F4914F6CDD1Du;
        long j = (long)((r >> 11) % (uint64_t)(i + 1));
        long t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
}

int bench_time(const bench_options *o, bench_batch_fn fn, void *ctx,
                  bench_timing *out)
{
    long pos = 0;
    /* Calibration: double the batch until it lasts the target. The first call also pays
     * for cold caches, so it is repeated once at the final size. */
    long batch = 1;
    double per_call = 0;
    for (;;) {
        double t0 = bench_now_ns();
        fn(ctx, pos, batch);
        double dt = bench_now_ns() - t0;
        pos += batch;
        per_call = dt / (double)batch;
        if (dt >= o->batch_target_ns || batch >= MAX_BATCH) break;
        batch *= 2;
    }
    if (per_call > 0) {
        double want = ceil(o->batch_target_ns / per_call);
        batch = want < 1 ? 1 : want > (double)MAX_BATCH ? MAX_BATCH : (long)want;
    }
    for (long w = 0; w < o->warmup_batches; ++w, pos += batch) fn(ctx, pos, batch);

    double budget = o->quick ? BUDGET_NS_QUICK : BUDGET_NS_FULL;
    long samples = o->samples;
    double est = per_call * (double)batch;
    if (est > 0 && est * (double)samples > budget) {
        samples = (long)(budget / est);
        if (samples < MIN_SAMPLES) samples = MIN_SAMPLES;
    }
    double *t = malloc((size_t)samples * sizeof *t);
    if (!t) return -1;
    for (long k = 0; k < samples; ++k, pos += batch) {
        double t0 = bench_now_ns();
        fn(ctx, pos, batch);
        t[k] = (bench_now_ns() - t0) / (double)batch;
    }
    qsort(t, (size_t)samples, sizeof *t, cmp_double);
    out->median_ns = bench_percentile(t, samples, 0.5);
    out->p99_ns = bench_percentile(t, samples, 0.99);
    out->samples = samples;
    out->batch = batch;
    free(t);
    return 0;
}
