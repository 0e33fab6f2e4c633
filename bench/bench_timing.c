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
/* A method whose batch lasts less than this runs one untimed batch before its share of a
 * turn: the method before it evicted its caches, which matters at microseconds and not at
 * the milliseconds of an Ipopt plan (where the extra batch would only cost time). */
#define WARM_TURN_NS 1e5

void bench_options_default(bench_options *o, int quick, unsigned long seed)
{
    o->quick = quick;
    o->seed = seed;
    o->loop_level = -1;
    o->loop_backend = -1;
    o->loop_budget_us = BENCH_LOOP_BUDGET_US;
    /* 10 µs batches: clock_gettime costs ~20 ns through the vDSO, so the clock is < 1 % of
     * a batch; quick mode only needs the rows, not stable numbers. */
    o->samples = quick ? 101 : 20001;
    o->warmup_batches = quick ? 5 : 200;
    o->batch_target_ns = quick ? 2e3 : 1e4;
    /* 7 rounds of 9 turns: in a full planner run a turn lasts ~0.2 s, so a slow spell of
     * the host (seconds here) falls on every method rather than on one method's whole
     * window; at least 3 samples per round with the 21-sample floor. */
    o->rounds = 7;
    o->round_turns = 9;
    o->scene = NULL;
    o->scenarios = NULL;
    o->python = NULL;
    o->peer_script = NULL;
    o->out_dir = NULL;
    o->repeat = 1;
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

/* Calibration of one method: doubles the batch until it lasts the target (the first call
 * also pays for cold caches, so the size is then set from the last, warm, measurement), runs
 * the warm-up, and picks the sample count under the per-method budget. */
static void calibrate(const bench_options *o, bench_timed *m, long *pos)
{
    long batch = 1;
    double per_call = 0;
    for (;;) {
        double t0 = bench_now_ns();
        m->fn(m->ctx, *pos, batch);
        double dt = bench_now_ns() - t0;
        *pos += batch;
        per_call = dt / (double)batch;
        if (dt >= o->batch_target_ns || batch >= MAX_BATCH) break;
        batch *= 2;
    }
    if (per_call > 0) {
        double want = ceil(o->batch_target_ns / per_call);
        batch = want < 1 ? 1 : want > (double)MAX_BATCH ? MAX_BATCH : (long)want;
    }
    for (long w = 0; w < o->warmup_batches; ++w, *pos += batch) m->fn(m->ctx, *pos, batch);

    double budget = o->quick ? BUDGET_NS_QUICK : BUDGET_NS_FULL;
    long samples = o->samples;
    double est = per_call * (double)batch;
    if (est > 0 && est * (double)samples > budget) {
        samples = (long)(budget / est);
        if (samples < MIN_SAMPLES) samples = MIN_SAMPLES;
    }
    m->out.samples = samples;
    m->out.batch = batch;
    m->out.median_ns = est; /* the batch's calibrated duration, until the turns measure */
}

/* First sample of turn j of T when a method has s in all: floor(s·j/T), so that the turns
 * share the samples evenly and round r (turns r·steps .. r·steps + steps − 1) holds samples
 * floor(s·r/R) .. floor(s·(r+1)/R) − 1. */
static long turn_start(long s, long j, long T) { return (long)((double)s * (double)j / (double)T); }

int bench_time_set(const bench_options *o, bench_timed *m, int n)
{
    int R = o->rounds < 1 ? 1 : o->rounds > BENCH_MAX_ROUNDS ? BENCH_MAX_ROUNDS : o->rounds;
    long steps = o->round_turns < 1 ? 1 : o->round_turns, T = R * steps;
    long *pos = calloc((size_t)n, sizeof *pos);
    double **t = calloc((size_t)n, sizeof *t);
    int rc = pos && t ? 0 : -1;
    for (int i = 0; i < n && rc == 0; ++i) {
        calibrate(o, &m[i], &pos[i]);
        if (!(t[i] = malloc((size_t)m[i].out.samples * sizeof **t))) rc = -1;
    }
    /* The turns: every method in turn times its share; the order alternates (forwards,
     * backwards) so no method always follows the same one. */
    for (long j = 0; j < T && rc == 0; ++j)
        for (int q = 0; q < n; ++q) {
            bench_timed *mi = &m[j % 2 ? n - 1 - q : q];
            long *pi = &pos[mi - m];
            double *ti = t[mi - m];
            long batch = mi->out.batch, k0 = turn_start(mi->out.samples, j, T),
                 k1 = turn_start(mi->out.samples, j + 1, T);
            if (k1 > k0 && mi->out.median_ns < WARM_TURN_NS) {
                mi->fn(mi->ctx, *pi, batch); /* untimed: caches the method before evicted */
                *pi += batch;
            }
            for (long k = k0; k < k1; ++k, *pi += batch) {
                double t0 = bench_now_ns();
                mi->fn(mi->ctx, *pi, batch);
                ti[k] = (bench_now_ns() - t0) / (double)batch;
            }
        }
    for (int i = 0; i < n && rc == 0; ++i) {
        bench_timing *out = &m[i].out;
        out->rounds = R;
        for (int r = 0; r < R; ++r) {
            long k0 = turn_start(out->samples, r * steps, T),
                 k1 = turn_start(out->samples, (r + 1) * steps, T);
            qsort(t[i] + k0, (size_t)(k1 - k0), sizeof **t, cmp_double);
            out->round_ns[r] = bench_percentile(t[i] + k0, k1 - k0, 0.5);
        }
        qsort(t[i], (size_t)out->samples, sizeof **t, cmp_double);
        out->median_ns = bench_percentile(t[i], out->samples, 0.5);
        out->p99_ns = bench_percentile(t[i], out->samples, 0.99);
    }
    for (int i = 0; t && i < n; ++i) free(t[i]);
    free(t);
    free(pos);
    return rc;
}

int bench_time(const bench_options *o, bench_batch_fn fn, void *ctx, bench_timing *out)
{
    /* Alone, a method has nobody to take turns with: one round of one turn, i.e. its
     * batches back to back as before rounds existed. */
    bench_options alone = *o;
    alone.rounds = alone.round_turns = 1;
    bench_timed m = {.fn = fn, .ctx = ctx};
    int rc = bench_time_set(&alone, &m, 1);
    *out = m.out;
    return rc;
}

void bench_row_set_timing(bench_row *row, const bench_timing *tm)
{
    row->median_ns = tm->median_ns;
    row->p99_ns = tm->p99_ns;
    row->samples = tm->samples;
    row->batch = tm->batch;
    row->rounds = tm->rounds;
    for (int r = 0; r < tm->rounds; ++r) row->round_ns[r] = tm->round_ns[r];
}

double bench_round_ratio(const double *a, const double *b, int rounds)
{
    double q[BENCH_MAX_ROUNDS];
    if (rounds < 1 || rounds > BENCH_MAX_ROUNDS) return NAN;
    for (int r = 0; r < rounds; ++r) {
        q[r] = a[r] / b[r];
        if (!(q[r] > 0) || !isfinite(q[r])) return NAN;
    }
    qsort(q, (size_t)rounds, sizeof *q, cmp_double);
    return bench_percentile(q, rounds, 0.5);
}
