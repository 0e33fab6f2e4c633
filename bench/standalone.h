/* What the standalone bench programs share (plan_count.c, plan_ab_inproc.c, horizon_bench.c):
 * each is one file built on the public API alone (bench/plan_ab.sh compiles the first two
 * by themselves, against another commit's library too), so these are static inline here,
 * not in bench_util.c. The target generator is the one both plan programs must draw the
 * same targets from. */
#ifndef HP_BENCH_STANDALONE_H
#define HP_BENCH_STANDALONE_H

#include <stdint.h>
#include <stdlib.h>
#include <time.h>

/* Wall-clock seconds (CLOCK_MONOTONIC). */
static inline double sa_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* qsort's comparison of doubles, ascending. */
static inline int sa_by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of v[0..n-1], n >= 1 (sorted in place; the mean of the middle two for even n). */
static inline double sa_median(double *v, size_t n)
{
    qsort(v, n, sizeof *v, sa_by_value);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Uniform in [0, 1) from a 64-bit LCG seeded 12345: the same sequence on every machine. */
static inline double sa_urand(void)
{
    static uint64_t rng = 12345;
    rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* n targets uniform in ±mm mm and ±deg deg per axis (SI), the next draws of sa_urand. */
static inline void sa_targets(double mm, double deg, int n, double (*t)[6])
{
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 6; ++i) {
            double u = 2 * sa_urand() - 1;
            t[k][i] = i < 3 ? u * mm * 1e-3 : u * deg * 3.14159265358979323846 / 180;
        }
}

/* A whole number of decimal digits (at most 9), or -1 for anything else (a sign, a space,
 * an empty string). */
static inline long sa_whole(const char *a)
{
    long v = 0;
    int k = 0;
    for (; a[k] >= '0' && a[k] <= '9' && k < 9; ++k) v = 10 * v + (a[k] - '0');
    return k > 0 && a[k] == '\0' ? v : -1;
}

#endif
