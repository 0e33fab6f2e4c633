/* headplan-bench: the timing harness. Times batches of evaluations with CLOCK_MONOTONIC so
 * that nanosecond-scale calls are not drowned by the clock's own cost and resolution. */
#ifndef BENCH_LAB_TIMING_H
#define BENCH_LAB_TIMING_H

#include "bench/bench.h"

/* Runs `count` evaluations, the first at input position `first` (the callee wraps positions
 * modulo its number of inputs). */
typedef void (*bench_batch_fn)(void *ctx, long first, long count);

typedef struct bench_timing {
    double median_ns;                  /* median over samples of (batch time / batch) */
    double p99_ns;                     /* 99th percentile, nearest rank, of the same */
    long samples;                      /* timed batches */
    long batch;                        /* evaluations per batch */
    int rounds;                        /* rounds the samples were taken in */
    double round_ns[BENCH_MAX_ROUNDS]; /* median per evaluation of each round's samples */
} bench_timing;

/* One method of a set timed together: its batch function and context in, its timing out. */
typedef struct bench_timed {
    bench_batch_fn fn;
    void *ctx;
    bench_timing out;
} bench_timed;

/* Times n methods so that the host's speed swings hit all of them alike. Every method is
 * first calibrated in turn (batch size doubled until one batch lasts at least
 * o->batch_target_ns, then o->warmup_batches untimed batches) and given its sample count
 * (o->samples, fewer when the method is so slow that they would exceed the per-method budget,
 * never fewer than 21). Then o->rounds × o->round_turns turns: in each, every method in turn
 * (forwards in even turns, backwards in odd ones) times its even share of its batches,
 * after one untimed batch when its batches are short (its caches, evicted by the method
 * before it). The median and p99 are over all of a method's samples; round_ns holds the
 * median of each round's samples (o->round_turns consecutive turns), so that a ratio of two
 * methods can be taken round by round. Each method's batches continue where its previous one
 * stopped, so every input is visited in turn. Allocates every sample buffer before the first
 * turn (none inside the timed loops). Returns 0, or -1 when out of memory. */
int bench_time_set(const bench_options *o, bench_timed *m, int n);

/* One method alone, its batches back to back: bench_time_set with n = 1, one round of one
 * turn (out->rounds = 1). */
int bench_time(const bench_options *o, bench_batch_fn fn, void *ctx, bench_timing *out);

/* Copies a timing into a method's row: median, p99, samples, batch and the rounds' medians. */
void bench_row_set_timing(bench_row *row, const bench_timing *tm);

/* Percentile p in (0, 1] of sorted[0..n-1] by the nearest-rank rule (sorted[ceil(p·n) − 1]);
 * p = 0.5 returns the usual median (mean of the two middle values for even n). */
double bench_percentile(const double *sorted, long n, double p);

/* A seeded permutation of 0..n-1 (xorshift64* + Fisher–Yates): the same seed gives the same
 * order on every machine. */
void bench_shuffle(long *perm, long n, unsigned long seed);

/* CLOCK_MONOTONIC now, in nanoseconds. */
double bench_now_ns(void);

#endif
