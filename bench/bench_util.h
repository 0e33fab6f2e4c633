/* headplan-bench: helpers shared by the stability, peers and levels families — scene
 * loading, the planner's radius bounds recomputed through the public API, the checks of an
 * answer through the exact model, and seeded random numbers. */
#ifndef BENCH_LAB_UTIL_H
#define BENCH_LAB_UTIL_H

#include "bench/bench.h"
#include "headplan/hp_planner.h"
#include "common/units.h"
#include "headplan/hp_scene.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define BENCH_PI HP_PI

/* Loads a layout scene; on failure one line on stderr and CLI_EXIT_NOINPUT or
 * CLI_EXIT_DATAERR (not a layout). */
int bench_load_layout(const char *path, hp_scene *scene);

/* Creates a planner; on failure one line on stderr naming the settings, CLI_EXIT_SOFTWARE. */
int bench_planner_new(const hp_layout *L, const hp_settings *s, hp_planner **p);

/* Every bladder's inner-radius bounds [m] and the pressures there [Pa]: the planner's own
 * envelope (hpi_bladder_envelope: pressure, stretch, stress and limit-point limits).
 * Returns 0, or -1 when a bladder has no valid interval. */
typedef struct bench_bounds {
    double ri_lo[HP_MAX_BLADDERS], ri_hi[HP_MAX_BLADDERS];
    double p_lo[HP_MAX_BLADDERS], p_hi[HP_MAX_BLADDERS];
} bench_bounds;
int bench_bounds_of(const hp_layout *L, bench_bounds *b);

/* The pose the head takes under r's pressures at `level`: bladder FK (pressure -> ri), the
 * volume law (-> ro) and the contact FK from r->achieved. ro_out (n, [m]) may be NULL.
 * Returns HP_OK or the first failing call's code. */
hp_error bench_round_trip(const hp_layout *L, hp_level level, const hp_result *r, double xi[6],
                          double *ro_out);

/* Largest axis difference, mm (translation) or degrees (rotation), over the axes with
 * commanded[i] != 0 (commanded NULL: all six). */
double bench_pose_diff(const double a[6], const double b[6], const int *commanded);

/* Weighted distance sqrt(Σ (a−b)²) in mm and degrees (1 mm ≙ 1°) over commanded axes. */
double bench_pose_dist(const double a[6], const double b[6], const int *commanded);

/* Worst pressure or stretch limit violation of r, as a fraction of the limit's span. */
double bench_limit_violation(const hp_layout *L, const hp_result *r);

/* Worst contact-equality violation max_k |ro_k(P_k) − rho_k(achieved)| [mm] at `level`:
 * the outer radii the returned pressures really give (bladder FK, volume law) against the
 * contact distances of the pose the method claims. NaN when a model call fails. */
double bench_contact_violation(const hp_layout *L, hp_level level, const hp_result *r);

/* The timed body shared by the planner and peers families: plans targets[perm[pos]] from a
 * reset planner, `count` times, walking the seeded permutation from `first`. */
typedef struct bench_plan_ctx {
    hp_planner *p;
    const double (*targets)[6];
    long n;
    const long *perm; /* order of the targets; NULL: in order */
    double sink;      /* keeps the compiler from dropping the plans */
    int warm;         /* 1: a trace, each plan continuing from the previous answer (no reset) */
} bench_plan_ctx;
void bench_plan_batch(void *ctx, long first, long count);

/* A scene file's stem with its NUL: a file name (NAME_MAX, 255 bytes on Linux) without
 * ".yaml" always fits. */
#define BENCH_STEM_MAX 256

/* One scene of a catalogue walk: fills row from the scene at path (stem: its file name
 * without .yaml, whole: shorter than BENCH_STEM_MAX). Returns 0 (row kept), 1 (scene
 * skipped) or an exit status. */
typedef int (*bench_scene_fn)(const bench_options *o, const char *path, const char *stem,
                              void *row);

/* The catalogue walk shared by the levels and load families: run on every .yaml file of
 * o->scenarios in name order (at most 64 files), rows of row_size bytes filled in that
 * order, at most max_rows kept; *nrows gets how many. Returns 0, the first exit status run
 * returned, or CLI_EXIT_NOINPUT after one line on stderr when the folder cannot be read. */
/* 0 when dir opens as a folder (the scene catalogue bench_each_scene walks), else
 * CLI_EXIT_NOINPUT after one line naming --scenarios: the command line checks it before it
 * creates the output folder. */
int bench_catalogue_readable(const char *dir);

int bench_each_scene(const bench_options *o, bench_scene_fn run, void *rows, size_t row_size,
                     int max_rows, int *nrows);

/* Writes DIR/NAME (bench_save) as the CSV header line then row(arg, i, f) for i < n; the
 * writer every catalogue family shares. Returns bench_save's status. */
typedef void (*bench_csv_row_fn)(const void *arg, int i, FILE *f);
int bench_save_csv(const char *dir, const char *name, const char *header, bench_csv_row_fn row,
                   const void *arg, int n);

/* xorshift64* in [0, 1); the same seed gives the same numbers on every machine. */
double bench_urand(uint64_t *s);

/* A random unit vector in 6-D (Gaussian by Box–Muller, normalised). */
void bench_unit6(uint64_t *s, double u[6]);

/* mm/deg <-> SI for a pose. */
void bench_to_si(const double mm_deg[6], double xi[6]);

#endif
