/* headplan-bench: the shared method table. Every family of methods (the bladder IK now, the
 * planner later) fills rows of the same shape; cmd_bench.c writes them as CSV, draws the
 * chart and prints the summary without knowing which family they came from. */
#ifndef BENCH_LAB_H
#define BENCH_LAB_H

#include <stddef.h>

/* The lab's command line (bench_cmd.c): argc/argv as main gets them; returns the exit
 * status. */
int bench_run_cli(int argc, char **argv);

/* Errors smaller than this (including exact zeros) are drawn at this value on the log-scale
 * chart; the CSV keeps the true value. */
#define BENCH_ERROR_FLOOR 1e-17

/* Most rounds the timing protocol may use (bench_timing.h). */
#define BENCH_MAX_ROUNDS 15

/* The loop family's deadline planner: its default time budget and the largest
 * --loop-budget-us takes [us]. */
#define BENCH_LOOP_BUDGET_US 20.0
#define BENCH_LOOP_BUDGET_MAX_US 1e6

/* How hard to measure. */
typedef struct bench_options {
    int quick;               /* 1: a test run: few samples; the IK's accuracy still on every
                               input, the planner's on fewer targets */
    unsigned long seed;      /* order in which timed batches walk the inputs */
    long samples;            /* timed batches per method */
    long warmup_batches;     /* untimed batches first */
    int rounds;              /* methods timed together report a median per round (1..
                               BENCH_MAX_ROUNDS) for per-round ratios */
    int round_turns;         /* each round is this many turns; in a turn every method times
                               its share, so a slow spell of the host hits them all */
    double batch_target_ns;  /* a batch lasts at least this long (clock resolution/overhead) */
    const char *scene;       /* the layout scene of the planner and peers families */
    const char *scenarios;   /* the scenario catalogue folder (stability, levels) */
    const char *python;      /* the Python with SciPy (peers) */
    const char *peer_script; /* bench/scipy_peer.py (peers) */
    const char *out_dir;     /* the output folder (peers writes its exchange files there) */
    int repeat;              /* loop: each trace run this many times, its cycles pooled */
    int loop_level;          /* loop: the one hp_level it runs (-1: linear, plane, surface) */
    int loop_backend;        /* loop: the one hp_backend it runs (-1: realtime, SLSQP) */
    double loop_budget_us;   /* loop: the deadline planner's max_time [us] */
} bench_options;

/* Fills the sampling settings for a full (quick = 0) or quick run; the paths NULL. */
void bench_options_default(bench_options *o, int quick, unsigned long seed);

/* One method's measurements: one CSV row. Text fields never hold commas or quotes. */
typedef struct bench_row {
    char method[48];          /* unique name, e.g. "gl-ref-16" */
    char family[16];          /* "ik", "planner" */
    char variant[32];         /* the chart's series, e.g. "gauss-reference" */
    char parameter[24];       /* what varies along the series: order, tolerance, level... */
    char input_set[16];       /* which inputs it ran on; only rows on the same inputs compete
                           for the Pareto front ("grid", "binding", "reachable") */
    double median_ns;         /* median time per evaluation over the timed batches [ns] */
    double p99_ns;            /* 99th percentile (nearest rank) of the same [ns] */
    double max_error;         /* IK: max relative error vs the __float128 reference;
                           planner: max pose error [mm or deg] */
    char worst[64];           /* where max_error occurred, "key=value;key=value" */
    double max_violation;     /* worst constraint violation; NaN = not applicable */
    double model_error;       /* planner: max pose difference between the exact-model round trip
                           and the method's own claim [mm or deg]; NaN = not applicable */
    long failures;            /* inputs on which the method returned an error or failed status */
    long inputs;              /* inputs the accuracy was measured on */
    long samples;             /* timed batches */
    long batch;               /* evaluations per timed batch */
    double ratio_to_baseline; /* median_ns / the family baseline's median_ns */
    int pareto;               /* 1 when no row on the same input set is both faster (or as fast)
                           and more accurate (or as accurate) */
    int rounds;               /* timing rounds (0: not timed in rounds) */
    double round_ns[BENCH_MAX_ROUNDS]; /* median time per evaluation in each round [ns] */
    double round_ratio; /* median over rounds of round_ns / the baseline's round_ns: the
                           ratio with the host's slow spells cancelled; NaN = not measured */
} bench_row;

/* A growable list of rows (cmd_bench.c owns it). */
typedef struct bench_table {
    bench_row *rows;
    size_t n, cap;
    const char *baseline; /* method name of the row the ratios divide by; the chart's thick
                             front is that of the baseline's input set */
} bench_table;

/* The median over rounds of a[r] / b[r], r < rounds: the ratio of two methods timed in the
 * same rounds, in which a slow spell of the host that falls into one round cancels. NaN when
 * rounds < 1 or a ratio is not a positive finite number. */
double bench_round_ratio(const double *a, const double *b, int rounds);

/* Appends a zeroed row (max_violation NaN) and returns it; NULL when out of memory. */
bench_row *bench_table_add(bench_table *t);
/* Fills ratio_to_baseline and round_ratio (NaN when the baseline row is missing or, for
 * round_ratio, was not timed in the same rounds) and the pareto flags. */
void bench_table_finish(bench_table *t);
void bench_table_free(bench_table *t);

/* A family of methods: runs every method on the family's inputs and appends one row each.
 * Progress goes to stderr, nothing to stdout. Returns 0, or a process exit status. */
typedef int (*bench_family_fn)(const bench_options *o, bench_table *t);

/* The bladder IK: closed form, Gauss–Legendre (both forms, orders 2..64), adaptive
 * Gauss–Kronrod (both forms, tolerances 1e-4..1e-13); baseline the closed form. */
int bench_ik(const bench_options *o, bench_table *t);

/* The planner: fast path per level; backend × level × tolerance on targets where a limit
 * binds; accuracy through the exact surface model against Ipopt at a tight tolerance;
 * baseline Ipopt at the surface level, tolerance 1e-9. Needs o->scene. */
int bench_planner(const bench_options *o, bench_table *t);

/* A family that writes its own files into dir (CSV, charts) and prints its summary on
 * stdout, for results that are not one row per method. Returns 0 or an exit status. */
typedef int (*bench_files_fn)(const bench_options *o, const char *dir);

/* Stability where methods fail: every backend × level on correction sizes 0.01..1000 along
 * seeded random 6-D directions, on the default, soft-material and near-degenerate layouts
 * and from bad warm starts; success rate, iterations, violations, and every silent wrong
 * answer. Writes DIR/stability.csv, stability_wrong.csv, stability.gp/.png/.svg. */
int bench_stability(const bench_options *o, const char *dir);

/* The peers on the same NLP (linear contact level, binding targets of o->scene): SciPy
 * SLSQP (o->python, o->peer_script) and Ipopt with a limited-memory Hessian, against Ipopt
 * with the exact Hessian (the baseline) and headplan's own backends. Rows of the table. */
int bench_peers(const bench_options *o, bench_table *t);

/* Model no more than a scene needs: for every layout scene of the catalogue, the level
 * `auto` picks, each level's error bound, median time per plan and pose error against the
 * exact surface answer. Writes DIR/levels.csv. */
int bench_levels(const bench_options *o, const char *dir);
/* The load level on the catalogue's load scenes: time per plan of the kinematic planner and
 * of the load planner on each backend, and the sag error of the kinematic plan measured
 * through the forward statics. Writes DIR/load.csv (bench/bench_load.c). */
int bench_load(const bench_options *o, const char *dir);
/* The control loop as it is run: traces planned cycle by cycle with rate limits, measured
 * pressures fed back and a deadline, against the same plan without rate limits, per level
 * and backend (realtime, nlopt-slsqp). Writes DIR/loop.csv (bench/bench_loop.c). Needs
 * o->scene. */
int bench_loop(const bench_options *o, const char *dir);
/* Each level's pose error against the finite-element reference: every level's pressures on
 * the catalogue's layout scenes (their corrections and a seeded clinical sweep) rested under
 * the head's weight with the contact law fitted to the CalculiX tables, against the pose the
 * plan claims, with the law's own error band. Writes DIR/fidelity.csv
 * (bench/bench_fidelity.c). */
int bench_fidelity(const bench_options *o, const char *dir);

#endif
