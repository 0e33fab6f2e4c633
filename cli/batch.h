/* Internal to the batch subcommand: the rows of a trace, their planned outputs, and the
 * sharded run that gives the same output for any number of jobs. */
#ifndef HP_CLI_BATCH_H
#define HP_CLI_BATCH_H

#include "headplan/headplan.h"
#include "headplan/hp_planner.h"

#include <stddef.h>

/* One input row of the trace, read before any planning (bad rows keep their message). */
typedef struct batch_in {
    long line;
    double t;
    double correction[6]; /* SI */
    int bad;              /* 1: the row could not be read; msg says why */
    char *msg;
} batch_in;

/* One output row: everything the output files show, except the per-row time, is a
 * deterministic function of (previous pressures, input row). */
typedef struct batch_out {
    int bad;
    hp_status status;
    int raw_code;
    double achieved[6];
    double pose_error;
    double pressure[HP_MAX_BLADDERS];
    unsigned binding[HP_MAX_BLADDERS];
    int iterations;
    double solve_time; /* [s]: a measurement, excluded from comparisons */
} batch_out;

/* Plans rows [from, to) in order with one planner, starting from previous pressures
 * prev (n values, updated to the last row's pressures). Bad rows pass the state through.
 * progress (may be NULL) is incremented after every row. Returns HP_OK or the planner's
 * call error. */
hp_error batch_plan_range(hp_planner *p, const batch_in *in, batch_out *out, size_t from,
                          size_t to, double *prev, volatile size_t *progress);

/* 1 when two output rows are equal in every field that the files show (time excluded). */
int batch_same(const batch_out *a, const batch_out *b, int n);

/* Runs the whole trace with `jobs` processes. Shard k > 0 starts from the nominal pressures
 * (a guess); afterwards the parent re-plans each shard's head from the true previous
 * pressures until a row comes out identical to the guess, from which on the two runs agree
 * (the planner's state is a function of the previous pressures alone). The result equals a
 * single sequential run, bit for bit. progress_cb (may be NULL) is called about ten times a
 * second with rows done. Returns 0, or non-zero after printing why to stderr. */
int batch_run(const hp_layout *L, const hp_settings *s, const batch_in *in, batch_out *out,
              size_t rows, int jobs, void (*progress_cb)(size_t done, size_t total),
              size_t *repaired_rows);

#endif
