/* The loop benchmark's traces and the lab's seeded generator, header-only so that the
 * standalone plan_count.c (public API alone) replays the same traces as bench_loop.c. */
#ifndef HP_BENCH_LOOP_TRACE_H
#define HP_BENCH_LOOP_TRACE_H

#include <headplan/headplan.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* The loop benchmark's rate limit on every bladder of its rate-limited planners [Pa a plan]
 * and the noise of its readings [Pa, uniform within ±]. */
#define SA_LOOP_RATE_PA 500.0
#define SA_LOOP_NOISE_PA 3.0

/* Uniform in [0, 1) from the xorshift state *s (the lab's seeded generator: bench_urand). */
static inline double sa_xorshift(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 0x2545F4914F6CDD1Du) >> 11) / 9007199254740992.0;
}

/* The loop benchmark's correction at cycle j of trace 0 (smooth), 1 (noisy: smooth plus
 * uniform noise of ±0.1 mm, ±0.05 deg) or 2 (step: a new target uniform in ±3 mm, ±2 deg
 * every 300 cycles, held between), in mm and deg; *s is the trace's generator (seeded
 * 0x100b + trace), step_tgt the step trace's current target, kept by the caller. */
static inline void sa_loop_trace(int trace, long j, uint64_t *s, double step_tgt[6],
                                 double mm_deg[6])
{
    const double pi = 3.14159265358979323846;
    for (int i = 0; i < 6; ++i) mm_deg[i] = 0;
    if (trace == 2) {
        if (j % 300 == 0)
            for (int i = 0; i < 6; ++i)
                step_tgt[i] = (2.0 * sa_xorshift(s) - 1.0) * (i < 3 ? 3.0 : 2.0);
        for (int i = 0; i < 6; ++i) mm_deg[i] = step_tgt[i];
        return;
    }
    double ph = 2.0 * pi * (double)j / 200.0;
    mm_deg[0] = 1.0 * sin(2.0 * pi * (double)j / 2000.0);
    mm_deg[1] = 0.8 * sin(ph + 0.3);
    mm_deg[2] = 2.0 * sin(ph);
    mm_deg[3] = 0.6 * sin(ph + 0.1);
    if (trace == 1)
        for (int i = 0; i < 6; ++i)
            mm_deg[i] += (2.0 * sa_xorshift(s) - 1.0) * (i < 3 ? 0.1 : 0.05);
}

/* A trace's number from its name (0 smooth, 1 noisy, 2 step), or -1; and back. */
static inline const char *sa_loop_trace_name(int trace)
{
    static const char *const names[] = {"smooth", "noisy", "step"};
    return trace >= 0 && trace < 3 ? names[trace] : "unknown";
}
static inline int sa_loop_trace_of(const char *name)
{
    for (int t = 0; t < 3; ++t)
        if (strcmp(name, sa_loop_trace_name(t)) == 0) return t;
    return -1;
}

/* A trace walked cycle by cycle: which trace, its generator (sa_loop_trace), its readings'
 * noise's generator (sa_loop_readings) and the step trace's current target. */
typedef struct sa_loop_walk {
    int trace;
    uint64_t seed, noise;
    double step_tgt[6];
} sa_loop_walk;

/* The walk of a trace from its first cycle, with the loop benchmark's seeds. */
static inline void sa_loop_walk_start(sa_loop_walk *w, int trace)
{
    w->trace = trace;
    w->seed = 0x100b + (uint64_t)trace;
    w->noise = 0x5e7 + (uint64_t)trace;
    for (int i = 0; i < 6; ++i) w->step_tgt[i] = 0;
}

/* The walk's correction at cycle j (cycles taken in order from 0) in SI units (m, rad). */
static inline void sa_loop_walk_at(sa_loop_walk *w, long j, double xi[6])
{
    double mm_deg[6];
    sa_loop_trace(w->trace, j, &w->seed, w->step_tgt, mm_deg);
    for (int i = 0; i < 6; ++i) xi[i] = mm_deg[i] * (i < 3 ? 1e-3 : 3.14159265358979323846 / 180.0);
}

/* The readings of an answer's pressures: each within ±SA_LOOP_NOISE_PA, drawn from *noise. */
static inline void sa_loop_readings(const hp_result *res, uint64_t *noise, double *P)
{
    for (int k = 0; k < res->n; ++k)
        P[k] = res->bladders[k].pressure + SA_LOOP_NOISE_PA * (2.0 * sa_xorshift(noise) - 1.0);
}

/* A realtime planner of the loop benchmark's replays (plan_count.c's tail mode,
 * loop_phases.c) at level (0 linear, 1 plane, 2 surface), rate limits on or off, max_time
 * 10 s: the loop benchmark's rate and measured planners' settings. 0, or 65 after printing
 * prog and the planner's message on stderr. */
static inline int sa_loop_planner(const hp_layout *L, int level, int rate, const char *prog,
                                  hp_planner **p)
{
    hp_settings st;
    hp_settings_default(&st);
    st.level = (hp_level)level;
    st.use_rate_limits = rate;
    st.max_time = 10.0;
    hp_diag d = {{0}};
    if (hp_planner_create(L, &st, p, &d) == HP_OK) return 0;
    fprintf(stderr, "%s: %s\n", prog, d.text);
    return 65;
}

/* L0 with every bladder's rate_max SA_LOOP_RATE_PA: the layout of the loop benchmark's
 * planners (a rate-free planner ignores it). */
static inline void sa_loop_layout(const hp_layout *L0, hp_layout *L)
{
    *L = *L0;
    for (int k = 0; k < L->n; ++k) L->bladders[k].rate_max = SA_LOOP_RATE_PA;
}

/* The replays' n planners on sa_loop_layout(L0): p[0] rate-free, the others rate-limited
 * (sa_loop_planner). 0, or its status at the first that fails; the ones made stay in p for
 * the caller to destroy (the rest NULL). */
static inline int sa_loop_planners(const hp_layout *L0, int level, int n, const char *prog,
                                   hp_planner **p)
{
    hp_layout L;
    sa_loop_layout(L0, &L);
    int rc = 0;
    for (int m = 0; m < n; ++m) p[m] = NULL;
    for (int m = 0; m < n && rc == 0; ++m) rc = sa_loop_planner(&L, level, m > 0, prog, &p[m]);
    return rc;
}

#endif
