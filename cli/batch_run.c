/* The sharded batch run (see batch.h). Workers are processes, not threads: Ipopt with
 * Debian's MUMPS must not run in two threads of one process. */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS */
#include "cli/batch.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* The state before a row: the previous good row's output (its answer, or the safe output
 * it carried), or, with row NULL, the start of the trace (the nominal answer). A function of
 * that row alone, so equal rows mean equal states. */
static hp_error set_state(hp_trace_plan *tp, const batch_out *row)
{
    return hp_trace_plan_set_state(tp, row ? &row->r : NULL);
}

/* The sink of batch_plan_range: row `from + i` of out from its result. */
typedef struct range_ctx {
    batch_out *out;
    const batch_out *last;
} range_ctx;

static hp_error put_row(void *ctx, size_t i, const hp_result *r)
{
    range_ctx *c = ctx;
    batch_out *o = &c->out[i];
    o->bad = 0;
    o->r = *r;
    c->last = o;
    return HP_OK;
}

hp_error batch_plan_range(hp_trace_plan *tp, const batch_in *in, batch_out *out, size_t from,
                          size_t to, const batch_out **state)
{
    /* The state of every plan is the previous good row alone, so any shard that starts
     * from an equal row continues identically. */
    hp_error e = set_state(tp, *state);
    if (e != HP_OK) return e;
    for (size_t i = from; i < to; ++i)
        if (in->bad[i]) {
            memset(&out[i], 0, sizeof out[i]);
            out[i].bad = 1;
        }
    range_ctx c = {out + from, *state};
    e = hp_trace_plan_run(tp, in->row + from, in->bad + from, to - from, put_row, &c, NULL, NULL);
    *state = c.last;
    return e;
}

int batch_same(const batch_out *a, const batch_out *b, int n)
{
    if (a->bad != b->bad) return 0;
    if (a->bad) return 1;
    /* Every column the files show, bit for bit (NaN equal to NaN), the measured ones left
     * out; and, unscaled, what the next row's state is made of (hp_trace_plan_set_state:
     * the pose and the bladders' radii and pressures), and the raw code. */
    if (a->r.raw_code != b->r.raw_code ||
        memcmp(a->r.achieved, b->r.achieved, sizeof a->r.achieved) != 0)
        return 0;
    for (int k = 0; k < n; ++k)
        if (memcmp(&a->r.bladders[k].ri, &b->r.bladders[k].ri, sizeof(double)) != 0 ||
            memcmp(&a->r.bladders[k].ro, &b->r.bladders[k].ro, sizeof(double)) != 0 ||
            memcmp(&a->r.bladders[k].pressure, &b->r.bladders[k].pressure, sizeof(double)) != 0)
            return 0;
    size_t nc;
    const hp_column *c = hp_columns(&nc);
    double va[HP_COLUMN_WIDTH_MAX], vb[HP_COLUMN_WIDTH_MAX];
    for (size_t j = 0; j < nc; ++j) {
        if (!c[j].in_rows || c[j].measured || c[j].source != HP_COLUMN_FROM_RESULT) continue;
        int w = hp_column_values(&c[j], n, NULL, &a->r, va);
        hp_column_values(&c[j], n, NULL, &b->r, vb);
        if (memcmp(va, vb, (size_t)w * sizeof va[0]) != 0) return 0;
    }
    return 1;
}

/* A planner and the trace plan over it (rates: the planner's own per-plan limits). */
static int make_planner(const hp_layout *L, const hp_settings *s, hp_planner **p,
                        hp_trace_plan **tp)
{
    hp_diag d = {{0}};
    if (hp_planner_create(L, s, p, &d) != HP_OK) {
        fprintf(stderr, "headplan batch: planner: %s\n", d.text);
        return 1;
    }
    if (hp_trace_plan_create(*p, NULL, tp, &d) != HP_OK) {
        fprintf(stderr, "headplan batch: %s\n", d.text);
        return 1;
    }
    return 0;
}

int batch_engine_init(batch_engine *e, const hp_layout *L, const hp_settings *s, int jobs)
{
    memset(e, 0, sizeof *e);
    e->L = L;
    e->s = s;
    e->jobs = jobs < 1 ? 1 : jobs;
    return make_planner(L, s, &e->p, &e->tp);
}

void batch_engine_free(batch_engine *e)
{
    hp_trace_plan_destroy(e->tp);
    e->tp = NULL;
    hp_planner_destroy(e->p);
    e->p = NULL;
}

/* The state after row i-1 of this block: the last good row before it, else the state the
 * block started from (NULL: the start of the trace). */
static const batch_out *state_before(const batch_out *out, size_t i, const batch_out *start)
{
    size_t j = i;
    while (j > 0 && out[j - 1].bad) --j;
    return j > 0 ? &out[j - 1] : start;
}

/* Row i alone into fresh[0], from state st, on the engine's planner. */
static hp_error replan(batch_engine *e, const batch_in *in, size_t i, batch_out *fresh,
                       const batch_out *st)
{
    batch_in one = {in->row + i, in->bad + i, in->msg + i};
    return batch_plan_range(e->tp, &one, fresh, 0, 1, &st);
}

/* Keeps the state after a block for the next one. */
static void keep_state(batch_engine *e, const batch_out *last)
{
    if (last && last != &e->last) e->last = *last;
    e->has_last = last != NULL;
}

int batch_engine_run(batch_engine *e, const batch_in *in, batch_out *out, size_t rows)
{
    const int n = e->L->n;
    int jobs = e->jobs;
    e->block_start = e->last;
    e->has_block_start = e->has_last;
    const batch_out *start = e->has_last ? &e->last : NULL;
    if ((size_t)jobs > rows) jobs = rows > 0 ? (int)rows : 1;
    if (jobs == 1) {
        const batch_out *st = start;
        if (batch_plan_range(e->tp, in, out, 0, rows, &st) != HP_OK) {
            fprintf(stderr, "headplan batch: %s\n", hp_planner_error(e->p));
            return 1;
        }
        keep_state(e, st);
        return 0;
    }

    /* Outputs live in shared memory so the workers write in place. */
    size_t out_bytes = rows * sizeof *out + 1;
    batch_out *shared = mmap(NULL, out_bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS,
                             -1, 0);
    if (shared == MAP_FAILED) {
        fprintf(stderr, "headplan batch: cannot map shared memory: %s\n", strerror(errno));
        return 1;
    }
    size_t chunk = (rows + (size_t)jobs - 1) / (size_t)jobs;

    pid_t pids[256];
    int started = 0, rc = 0;
    fflush(NULL);
    for (int k = 0; k < jobs; ++k) {
        size_t from = (size_t)k * chunk, to = from + chunk < rows ? from + chunk : rows;
        pid_t pid = fork();
        if (pid < 0) {
            fprintf(stderr, "headplan batch: fork: %s\n", strerror(errno));
            rc = 1;
            break;
        }
        if (pid == 0) {
            /* A worker must not outlive a killed parent (Linux). */
            prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (getppid() == 1) _exit(1);
            hp_planner *p = NULL;
            hp_trace_plan *tp = NULL;
            /* Shard 0 starts from the true state, the others from the start of the trace
             * (a guess the parent repairs). */
            const batch_out *st = k == 0 ? start : NULL;
            int bad = make_planner(e->L, e->s, &p, &tp);
            bad = bad || batch_plan_range(tp, in, shared, from, to, &st) != HP_OK;
            if (bad && p) fprintf(stderr, "headplan batch: %s\n", hp_planner_error(p));
            hp_trace_plan_destroy(tp);
            hp_planner_destroy(p);
            _exit(bad ? 1 : 0);
        }
        pids[started++] = pid;
    }
    /* A worker that fails or dies by a signal fails the run. */
    for (int k = 0; k < started; ++k) {
        int st;
        while (waitpid(pids[k], &st, 0) < 0 && errno == EINTR) {}
        if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) {
            if (WIFSIGNALED(st))
                fprintf(stderr, "headplan batch: job %d killed by signal %d\n", k, WTERMSIG(st));
            rc = 1;
        }
    }

    /* Repair: re-plan each later shard's head from the true previous state until a row
     * matches the guess. */
    for (int k = 1; rc == 0 && k < jobs; ++k) {
        size_t from = (size_t)k * chunk, to = from + chunk < rows ? from + chunk : rows;
        for (size_t i = from; i < to; ++i) {
            batch_out fresh[1];
            const batch_out *st = state_before(shared, i, start);
            if (replan(e, in, i, fresh, st) != HP_OK) {
                fprintf(stderr, "headplan batch: %s\n", hp_planner_error(e->p));
                rc = 1;
                break;
            }
            int same = batch_same(&fresh[0], &shared[i], n);
            if (!same) {
                shared[i] = fresh[0];
                e->repaired += 1;
            }
            /* Equal non-bad rows mean equal state from here on. */
            if (same && !fresh[0].bad) break;
        }
    }
    if (rc == 0) {
        memcpy(out, shared, rows * sizeof *out);
        keep_state(e, state_before(out, rows, start));
    }
    munmap(shared, out_bytes);
    return rc;
}

const char *batch_engine_reason(batch_engine *e, const batch_in *in, const batch_out *out, size_t i)
{
    batch_out fresh[1];
    const batch_out *st = state_before(out, i, e->has_block_start ? &e->block_start : NULL);
    if (replan(e, in, i, fresh, st) != HP_OK || !*hp_planner_error(e->p))
        return "invalid correction";
    return hp_planner_error(e->p);
}
