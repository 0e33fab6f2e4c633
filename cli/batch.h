/* Internal to the batch subcommand: the rows of a trace, their planned outputs, and the
 * engine that plans a trace block by block (memory flat in the number of rows), with
 * shards in processes that give the same output for any number of jobs. */
#ifndef CLI_BATCH_H
#define CLI_BATCH_H

#include "headplan/headplan.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_trace_plan.h"

#include <stddef.h>

/* A block of input rows of the trace, as columns (the rows are what hp_trace_plan_run
 * plans; bad rows keep their message). */
typedef struct batch_in {
    hp_trace_row *row;  /* line, t, the desired correction (SI); a bad row's line only */
    unsigned char *bad; /* 1: the row could not be read; msg says why */
    char **msg;
} batch_in;

/* One output row: everything the output files show (hp_trace_columns.h), except the
 * measured time, is a deterministic function of (previous good output row, input row). */
typedef struct batch_out {
    int bad;     /* the row could not be read: r is unset */
    hp_result r; /* the planned result */
} batch_out;

/* Plans rows [from, to) in order through the trace plan (hp_trace_plan_run: the state
 * before each row is the previous good output row alone); *state is the row the first plan
 * starts from (NULL: the start of the trace, the nominal answer) and is updated to the last
 * good row planned (a pointer into out). Bad rows pass the state through. Returns HP_OK or
 * the planner's call error. */
hp_error batch_plan_range(hp_trace_plan *tp, const batch_in *in, batch_out *out, size_t from,
                          size_t to, const batch_out **state);

/* 1 when two output rows are equal in every field that the files show (time excluded). */
int batch_same(const batch_out *a, const batch_out *b, int n);

/* Plans a trace block by block; the state (the last good output row) carries across
 * blocks. */
typedef struct batch_engine {
    const hp_layout *L;
    const hp_settings *s;
    int jobs;
    hp_planner *p;         /* in-process: every row when jobs == 1, repairs else */
    hp_trace_plan *tp;     /* over p */
    batch_out last;        /* the last good row so far (when has_last) */
    int has_last;          /* 0: no good row yet: the nominal answer is the state */
    batch_out block_start; /* the state the last block started from ... */
    int has_block_start;   /* ... (0: the start of the trace) */
    size_t repaired;       /* rows re-planned at shard joins, over all blocks */
} batch_engine;

/* Creates the planner; the state is the start of the trace. Returns 0, or 1 after a line
 * on stderr. */
int batch_engine_init(batch_engine *e, const hp_layout *L, const hp_settings *s, int jobs);

/* Plans rows in[0..rows) into out, continuing from the engine's state. With jobs > 1 the
 * block is split into `jobs` processes; shard k > 0 starts from the start of the trace (a
 * guess) and the parent then re-plans each shard's head from the true previous state
 * until a row comes out identical to the guess, from which on the two runs agree (the
 * planner's state is a function of the previous good row alone). The result equals a
 * single sequential run, bit for bit. Returns 0, or non-zero after a line on stderr. */
int batch_engine_run(batch_engine *e, const batch_in *in, batch_out *out, size_t rows);

/* Plans row i of the last block run again from its own previous state, on the engine's
 * planner, and returns the planner's message (why an invalid-input row was refused: since a
 * CLOSEST answer must pass the round trip, that depends on the state, not the row alone). */
const char *batch_engine_reason(batch_engine *e, const batch_in *in, const batch_out *out,
                                size_t i);
void batch_engine_free(batch_engine *e);

#endif
