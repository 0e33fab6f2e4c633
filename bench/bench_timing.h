/* headplan-bench: the timing harness. Times batches of evaluations with CLOCK_MONOTONIC so
 * that nanosecond-scale calls are not drowned by the clock's own cost and resolution. */
#ifndef BENCH_LAB_TIMING_H
#define BENCH_LAB_TIMING_H

#include "bench/bench.h"

/* Runs `count` evaluations, the first at input position `first` (the callee wraps positions
 * modulo its number of inputs). */
typedef void (*bench_batch_fn)(void *ctx, long first, long count);

typedef struct bench_timing {
    double median_ns; /* median over samples of (batch time / batch) */
    double p99_ns;    /* 99th percentile, nearest rank, of the same */
    long samples;     /* timed batches */
    long batch;       /* evaluations per batch */
} bench_timing;

/* Calibrates the batch size so one batch lasts at least o->batch_target_ns, runs
 * o->warmup_batches untimed batches, then times o->samples batches (fewer when the method is
 * so slow that they would exceed the per-method budget, never fewer than 21). Consecutive
 * batches continue where the previous one stopped, so every input is visited in turn.
 * Allocates a sample buffer; returns 0, or -1 when out of memory. */
int bench_time(const bench_options *o, bench_batch_fn fn, void *ctx,
                  bench_timing *out);

/* Percentile p in (0, 1] of sorted[0..n-1] by the nearest-rank rule (sorted[ceil(p·n) − 1]);
 * p = 0.5 returns the usual median (mean of the two middle values for even n). */
double bench_percentile(const double *sorted, long n, double p);

/* A seeded permutation of 0..n-1 (xorshift64* + Fisher–Yates): the same seed gives the same
 * order on every machine. */
void bench_shuffle(long *perm, long n, unsigned long seed);

/* CLOCK_MONOTONIC now, in nanoseconds. */
double bench_now_ns(void);

#endif
