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

hp_error batch_plan_range(hp_planner *p, const batch_in *in, batch_out *out, size_t from,
                          size_t to, double *prev, volatile size_t *progress)
{
    const int n = hp_planner_layout(p)->n;
    for (size_t i = from; i < to; ++i) {
        batch_out *o = &out[i];
        memset(o, 0, sizeof *o);
        if (in[i].bad) {
            o->bad = 1;
        } else {
            /* The state of every plan is set from the previous pressures alone, so any
             * shard that starts from the same pressures continues identically. */
            hp_error e = hp_planner_set_previous(p, prev);
            if (e != HP_OK) return e;
            hp_result r;
            e = hp_plan(p, in[i].correction, &r);
            if (e != HP_OK && r.status != HP_STATUS_INVALID_INPUT) return e;
            o->status = r.status;
            o->raw_code = r.raw_code;
            memcpy(o->achieved, r.achieved, sizeof o->achieved);
            o->pose_error = r.pose_error;
            for (int k = 0; k < n; ++k) {
                o->pressure[k] = r.bladders[k].pressure;
                o->binding[k] = r.bladders[k].binding;
                prev[k] = r.bladders[k].pressure;
            }
            o->iterations = r.iterations;
            o->solve_time = r.solve_time;
        }
        if (progress) *progress += 1;
    }
    return HP_OK;
}

int batch_same(const batch_out *a, const batch_out *b, int n)
{
    if (a->bad != b->bad) return 0;
    if (a->bad) return 1;
    if (a->status != b->status || a->raw_code != b->raw_code ||
        a->iterations != b->iterations)
        return 0;
    if (memcmp(a->achieved, b->achieved, sizeof a->achieved) != 0) return 0;
    if (memcmp(&a->pose_error, &b->pose_error, sizeof a->pose_error) != 0) return 0;
    for (int k = 0; k < n; ++k)
        if (memcmp(&a->pressure[k], &b->pressure[k], sizeof(double)) != 0 ||
            a->binding[k] != b->binding[k])
            return 0;
    return 1;
}

static hp_error nominal_pressures(hp_planner *p, double *prev)
{
    hp_planner_reset(p);
    return hp_planner_nominal_pressures(p, prev);
}

static int make_planner(const hp_layout *L, const hp_settings *s, hp_planner **p)
{
    hp_diag d = {{0}};
    if (hp_planner_create(L, s, p, &d) != HP_OK) {
        fprintf(stderr, "headplan batch: planner: %s\n", d.text);
        return 1;
    }
    return 0;
}

static void sleep_ms(long ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

int batch_run(const hp_layout *L, const hp_settings *s, const batch_in *in, batch_out *out,
              size_t rows, int jobs, void (*progress_cb)(size_t done, size_t total),
              size_t *repaired_rows)
{
    *repaired_rows = 0;
    if (jobs < 1) jobs = 1;
    if ((size_t)jobs > rows) jobs = rows > 0 ? (int)rows : 1;

    /* Outputs and per-job progress live in shared memory so the workers write in place. */
    size_t out_bytes = rows * sizeof *out + 1;
    batch_out *shared = mmap(NULL, out_bytes, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS,
                             -1, 0);
    volatile size_t *progress = mmap(NULL, (size_t)jobs * sizeof(size_t) * 2,
                                     PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (shared == MAP_FAILED || progress == MAP_FAILED) {
        fprintf(stderr, "headplan batch: cannot map shared memory: %s\n", strerror(errno));
        return 1;
    }
    volatile size_t *failed = progress + jobs;
    size_t chunk = (rows + (size_t)jobs - 1) / (size_t)jobs;

    pid_t pids[256];
    int started = 0, rc = 0;
    fflush(NULL);
    for (int k = 0; k < jobs; ++k) {
        size_t from = (size_t)k * chunk, to = from + chunk < rows ? from + chunk : rows;
        progress[k] = 0;
        failed[k] = 0;
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
            double prev[HP_MAX_BLADDERS];
            int bad = make_planner(L, s, &p) || nominal_pressures(p, prev) != HP_OK ||
                      batch_plan_range(p, in, shared, from, to, prev, &progress[k]) != HP_OK;
            if (bad) {
                if (p) fprintf(stderr, "headplan batch: %s\n", hp_planner_error(p));
                failed[k] = 1;
            }
            hp_planner_destroy(p);
            _exit(bad ? 1 : 0);
        }
        pids[started++] = pid;
    }
    /* Wait, reporting progress; a worker that dies by a signal fails the run. */
    int live = started;
    while (live > 0) {
        for (int k = 0; k < started; ++k) {
            if (pids[k] <= 0) continue;
            int st;
            pid_t w = waitpid(pids[k], &st, WNOHANG);
            if (w == pids[k]) {
                if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) {
                    if (WIFSIGNALED(st))
                        fprintf(stderr, "headplan batch: job %d killed by signal %d\n", k,
                                WTERMSIG(st));
                    rc = 1;
                }
                pids[k] = 0;
                --live;
            }
        }
        if (progress_cb) {
            size_t done = 0;
            for (int k = 0; k < jobs; ++k) done += progress[k];
            progress_cb(done, rows);
        }
        if (live > 0) sleep_ms(100);
    }
    for (int k = 0; k < jobs; ++k) rc |= failed[k] ? 1 : 0;

    /* Repair: re-plan each later shard's head from the true previous pressures until a row
     * matches the guess. */
    if (rc == 0 && jobs > 1) {
        hp_planner *p = NULL;
        double prev[HP_MAX_BLADDERS];
        if (make_planner(L, s, &p) || nominal_pressures(p, prev) != HP_OK) rc = 1;
        for (int k = 1; rc == 0 && k < jobs; ++k) {
            size_t from = (size_t)k * chunk, to = from + chunk < rows ? from + chunk : rows;
            /* True state: the pressures after the last good row before this shard. */
            size_t j = from;
            while (j > 0 && shared[j - 1].bad) --j;
            if (j > 0) memcpy(prev, shared[j - 1].pressure, sizeof prev);
            else nominal_pressures(p, prev);
            for (size_t i = from; i < to; ++i) {
                batch_out fresh;
                batch_out tmp[1];
                if (batch_plan_range(p, in + i, tmp, 0, 1, prev, NULL) != HP_OK) {
                    fprintf(stderr, "headplan batch: %s\n", hp_planner_error(p));
                    rc = 1;
                    break;
                }
                fresh = tmp[0];
                int same = batch_same(&fresh, &shared[i], L->n);
                if (!same) {
                    shared[i] = fresh;
                    *repaired_rows += 1;
                }
                /* Equal non-bad rows mean equal state from here on. */
                if (same && !fresh.bad) break;
            }
        }
        hp_planner_destroy(p);
    }
    if (rc == 0) memcpy(out, shared, rows * sizeof *out);
    munmap(shared, out_bytes);
    munmap((void *)progress, (size_t)jobs * sizeof(size_t) * 2);
    return rc;
}
