/* The real-time backend: the closest reachable pose under ro_lo <= rho(xi) <= ro_hi.
 * Linear level: one convex QP in the commanded pose components (Goldfarb–Idnani, qp.c).
 * Plane/surface levels: SQP — linearise rho at the current pose, solve the same QP with the
 * (convexified) Hessian of the Lagrangian, accept the step on an l1 merit function (second-
 * order correction, backtracking), repeat (at most max_iter steps) — then a feasibility
 * restoration so the radii strictly respect the limits. Everything lives in the state allocated at create: solve allocates nothing,
 * prints nothing, takes no lock, and its time is bounded by max_iter and max_time. */
#define _POSIX_C_SOURCE 200809L
#include "planner/backend_testing.h"
#include "planner/clock.h"
#include "planner/problem_setup.h"
#include "planner/qp.h"
#include "common/dense.h"
#include "common/minmax.h"
#include "common/same_bits.h"
#include "common/units.h"
#include "kinematics/kin_geom.h"

#include <float.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The QP sees limits moved inward by this much (mm) so that rounding in rho(xi) can never
 * put a returned radius outside them; it is 1000× the rounding of rho ~ 30 mm. */
#define RT_MARGIN_MM 1e-11
/* The fewest ticks of the coarse clock max_time must span for the budget to be read on it
 * (budget_clock): one tick is then at most 1 % of the budget. An integer factor, so the
 * boundary is one exact comparison of max_time with ticks × tick. */
#define RT_COARSE_TICKS 100.0
/* A constraint counts as met when violated by less than this (mm per unit-norm row). */
#define RT_FEAS_TOL 1e-12
/* Restoration: re-solves with limits tightened by the measured violation, then bisection. */
#define RT_RESTORE_ROUNDS 3
#define RT_BISECT_STEPS 60
/* The fraction of a stopped step's linearly interpolated reach kept (the radii curve
 * between the segment's ends; a tenth left for that). */
#define RT_LATE_SHRINK 0.9
/* Under a budget an SQP step after the first begins only while this share of the longest
 * step so far still fits before the deadline: a step predicted right then ends at most
 * three quarters of a step late. A trade-off measured on the loop benchmark's deadline rows
 * (docs/control-loop.md, A time budget that holds): without the prediction a step begun
 * just before the deadline ran a whole step past it; with the whole step (1) the budget
 * stopped many plans that would have ended a fraction of a microsecond late, and the plane
 * step trace reached its targets in half as many plans at 3 us. */
#ifndef RT_STEP_FIT /* defined on the compiler's command line for that measurement */
#define RT_STEP_FIT 0.25
#endif
/* SQP steps below this (mm or deg) are taken whole, larger ones by a merit line search:
 * 1000x the default pose tolerance, where the merit's changes (~step²) reach its rounding. */
#define RT_FULL_STEP 1e-6
/* A line-search trial point at most this far (mm or deg) from the point the QP was built
 * at keeps that point's contact Hessians (merit_full): the Lagrangian's Hessian then
 * differs from its own by what the curvature changes over the step, far below the
 * objective's weights, and the Newton rate holds; once, then they are evaluated again. */
#define RT_REUSE_H_STEP 1e-3
/* Sufficient decrease of the merit line search (a fraction of the predicted decrease). */
#define RT_ARMIJO 1e-4
/* Convexification of the Lagrangian's Hessian (build_objective): the largest augmented-
 * Lagrangian weight tried, and the share of the objective's curvature W the convexified
 * matrix must keep in every direction. */
#define RT_AUG_MAX 1e8
#define RT_AUG_MIN 1e-3

typedef struct rt_state {
    hp_qp qp;
    int max_iter;
    double max_time, tolerance;
    clockid_t clk; /* the clock max_time is checked on (budget_clock) */
    double t_end;  /* this solve's deadline on clk: its start + max_time */
    /* This solve stops for time: the clock was read past t_end (rt_late), or the next SQP
     * step was predicted to end too far past it (RT_STEP_FIT). */
    int late;
    /* rho, J and the Hessians at the point the last QP was linearised at; J and H point into
     * Jb and Hb, whose other halves c_J and c_H take the line search's trial evaluation:
     * when that point is accepted the halves swap instead of being copied. */
    double rho[HP_MAX_BLADDERS], *J, *H;
    double Jb[2][HP_MAX_BLADDERS * 6], Hb[2][HP_MAX_BLADDERS * 36];
    double rho_k[HP_MAX_BLADDERS]; /* rho at the point the last QP was linearised at */
    /* This solve's start and, once an evaluation measured it (r0_ok), rho there: the
     * restoration's first anchor is that start, and after a deadline its check (violation)
     * reads these instead of evaluating the model there again. Without a deadline it
     * evaluates: a model that began failing during the solve shows there and the solve
     * ends in a solver error (tests/reliability/test_faults.c, NaN contact after the first
     * QP), where these radii, measured before the failure, would answer. */
    double r0_x[6], r0_rho[HP_MAX_BLADDERS];
    int r0_ok;
    double u[HP_QP_MMAX]; /* multipliers of the last QP: the Lagrangian's curvature */
    int have_u;
    int qps;                              /* QPs solved in this solve (for the test hook) */
    hp_test_rt_counts cnt;                /* this solve's paths (hpi_test_realtime_count) */
    hp_kin_dist_warm sw[HP_MAX_BLADDERS]; /* surface level: the last distances' warm states */
    int act[HP_QP_MMAX];                  /* active set of the previous SQP step's QP */
    int exact; /* the last QP's Hessian was the Lagrangian's own (Newton) */
    /* The Cholesky factor of the QP's G from the convexity test (build_objective), when G
     * was not changed after it, or of G = W (diagonal): the QP solves then do not factor G
     * again. */
    double Lg[HP_QP_NMAX * HP_QP_NMAX];
    int Lg_ok;
    /* The model at the last full step's trial point, evaluated with its derivatives by the
     * line search: when that step is accepted, the next QP is built from it without a
     * second evaluation at the same point. */
    double c_x[6], c_rho[HP_MAX_BLADDERS], *c_J, *c_H;
    int c_ok;
    /* The bladders whose Hessians H and c_H hold (the masks they were evaluated with);
     * whether c_H was evaluated at c_x at all (RT_REUSE_H_STEP), and whether H is one
     * point old (kept over a short step). */
    unsigned char hm[HP_MAX_BLADDERS], c_hm[HP_MAX_BLADDERS];
    int c_h_ok, h_kept;
    /* The model at the nominal pose, where every cold solve builds its first QP: once, at
     * create (the layout's geometry and level do not change after). */
    double z_rho[HP_MAX_BLADDERS], z_J[HP_MAX_BLADDERS * 6];
    hp_kin_dist_warm z_sw[HP_MAX_BLADDERS];
    int z_ok;
    /* The last answer's pose and whether the core starts the next solve from it
     * (warm_point): then its multipliers and distances' multipliers start the next solve. */
    double x_last[6];
    int accepted;
    /* Linear level: the active set of the last plan's QP (lin_k rows; 0: none kept), for n
     * bladders and nv commanded components. In a control loop consecutive plans walking
     * toward a target bind the same rate limits, so it starts the next plan's QP
     * (hpi_qp_solve_warm: one equality solve and a check, or the full solve). */
    int lin_act[HP_QP_MMAX];
    int lin_k, lin_n, lin_nv;
    /* lin_own: the kept set is the last answer's and the next plan starts from that answer
     * or from readings of it (warm_point, rt_reading); lin_pending: lin_own before the last
     * warm_point(0), which a reading then restores. A set_previous_result (warm_point(0)
     * alone) clears it: the next plan's state does not depend on the history. */
    int lin_own, lin_pending;
    /* Fixed for one solve (rt_begin): the commanded components map[0..nv), the factor
     * taking entry (a, b) of an SI Hessian of rho to the QP's units (mm per scaled unit
     * squared), each bladder's margin (rt_margin). */
    int map[6], nv;
    double hsc[HP_QP_NMAX * HP_QP_NMAX];
    double mg[HP_MAX_BLADDERS];
    /* The last QP's rows (qp_at, rt_row_b): each bladder's linearisation constant rho − J·x,
     * its extra tightening, and the second-order correction's shift (soc: line_search) —
     * what rebuilds a row's b when its rate window end is resolved after the QP was built
     * (hp_problem.lazy). */
    double base[HP_MAX_BLADDERS], ext[HP_MAX_BLADDERS], dk[HP_MAX_BLADDERS];
    int soc;
} rt_state;

/* Test-only hook (planner/backend_testing.h), inert unless a test sets it: the contact
 * distances come back NaN while the evaluation reports success — a model failing silently,
 * the worst case — everywhere in this backend (the core's own evaluations are not hooked). */
static atomic_int rt_fault = HP_TEST_FAULT_NONE;

void hpi_test_realtime_fault(int fault) { atomic_store(&rt_fault, fault); }

static double now_s(clockid_t clk);

/* Test-only path counts (backend_testing.h): each solve counts in st->cnt with plain
 * increments and adds them here at its end, only while a test has counting on. */
#define RT_N_COUNTS 12
static atomic_int rt_counting;
static atomic_long rt_counts[RT_N_COUNTS];

void hpi_test_realtime_count(int on)
{
    if (on)
        for (int i = 0; i < RT_N_COUNTS; ++i) atomic_store(&rt_counts[i], 0);
    atomic_store(&rt_counting, on != 0);
}

void hpi_test_realtime_counts(hp_test_rt_counts *out)
{
    long *f[RT_N_COUNTS] = {&out->solves,   &out->qps,      &out->qp_warm,     &out->soc,
                            &out->soc_warm, &out->h_kept,   &out->rho_step,    &out->rho_refused,
                            &out->late,     &out->qp_steps, &out->bisect_kept, &out->bisect_anchor};
    for (int i = 0; i < RT_N_COUNTS; ++i) *f[i] = atomic_load(&rt_counts[i]);
}

static void rt_count_flush(const rt_state *st)
{
    if (!atomic_load_explicit(&rt_counting, memory_order_relaxed)) return;
    const hp_test_rt_counts *c = &st->cnt;
    const long v[RT_N_COUNTS] = {1,           st->qps,     c->qp_warm,     c->soc,
                                 c->soc_warm, c->h_kept,   c->rho_step,    c->rho_refused,
                                 c->late,     c->qp_steps, c->bisect_kept, c->bisect_anchor};
    for (int i = 0; i < RT_N_COUNTS; ++i) atomic_fetch_add(&rt_counts[i], v[i]);
}

/* Test-only (backend_testing.h): the path a solve stopped by time takes to its answer. */
static atomic_int rt_late_path = HP_TEST_LATE_AS_BUILT;

void hpi_test_realtime_late_path(int path) { atomic_store(&rt_late_path, path); }

/* Test-only: one more piece of work (a contact evaluation or a QP) begun after the budget
 * ran out, counted only while a test counts (one relaxed atomic read otherwise). */
static void rt_count_late(rt_state *st)
{
    if (atomic_load_explicit(&rt_counting, memory_order_relaxed) && now_s(st->clk) > st->t_end)
        ++st->cnt.late;
}

static void rt_inject(const rt_state *st, int n, double *rho)
{
    int f = atomic_load(&rt_fault);
    if (f == HP_TEST_FAULT_NAN_CONTACT || (f == HP_TEST_FAULT_NAN_CONTACT_LATE && st->qps > 0))
        for (int k = 0; k < n; ++k) rho[k] = NAN;
}

/* 1 when two QP active sets (HP_QP_MMAX flags) are equal. */
static inline int same_set(const int *a, const int *b)
{
    int d = 0;
    for (int j = 0; j < HP_QP_MMAX; ++j) d |= a[j] ^ b[j];
    return d == 0;
}

/* The budget clock's reading (the test clock when a test set one: hpi_test_plan_clock). */
static double now_s(clockid_t clk) { return hpi_plan_now_on((int)clk); }

/* The clock the time budget is read on: the kernel's coarse monotonic clock when max_time
 * spans at least RT_COARSE_TICKS of its ticks, so the budget holds to 1 % of itself; else
 * the precise one. A solve reads the clock at its start and after every SQP
 * step (four times in a binding surface plan): ~30 ns a read of the precise clock on the
 * virtual machine of docs/benchmarks.md, ~4 ns of the coarse one (a memory read), and the
 * difference ~2 % of the plan. A control loop's budget of a few milliseconds gets the
 * precise clock. */
static clockid_t budget_clock(double max_time)
{
#ifdef CLOCK_MONOTONIC_COARSE
    struct timespec r;
    if (clock_getres(CLOCK_MONOTONIC_COARSE, &r) == 0 &&
        RT_COARSE_TICKS * ((double)r.tv_sec + 1e-9 * (double)r.tv_nsec) <= max_time)
        return CLOCK_MONOTONIC_COARSE;
#endif
    return CLOCK_MONOTONIC;
}

int hpi_test_realtime_coarse_clock(double max_time)
{
    return budget_clock(max_time) != CLOCK_MONOTONIC;
}

/* 1 once this solve stops for time (the clock read past t_end, or a step predicted too
 * long, rt_state.late; from then on without reading the clock again). Read before every QP,
 * every line-search trial, every restoration round and every few bisection steps: the work
 * a solve begins after its deadline is the few evaluations that find a feasible point to
 * stop at. */
static int rt_late(rt_state *st)
{
    if (!st->late && now_s(st->clk) > st->t_end) st->late = 1;
    return st->late;
}

/* rho (mm), J (mm per mm/deg, may be NULL) and, if H is not NULL, the SI Hessians of rho
 * (per m², m·rad, rad²; scaled by the caller) at scaled pose x. The surface level's
 * point-to-ellipsoid distances start from the previous evaluation's in this solve (st->sw,
 * its multipliers moved to x to first order; the bracket keeps any start safe): successive
 * SQP points are close. */
static hp_error rt_contact(rt_state *st, const hp_problem *pb, const double *x, double *rho,
                           double *J, double *H, unsigned char *mask)
{
    /* Hessians only where the last QP's multiplier is not zero: no other enters the
     * Lagrangian (build_objective), and most bladders are off their limits. mask (written
     * when H is asked for) records which. */
    if (H)
        for (int k = 0; k < pb->n; ++k) mask[k] = st->u[2 * k] - st->u[2 * k + 1] != 0.0;
    double xi[6], Jsi[HP_MAX_BLADDERS * 6];
    for (int i = 0; i < 6; ++i) xi[i] = x[i] * hpi_pose_si_per_scaled(i);
    rt_count_late(st);
    hp_error e = hpi_kin_contact_eval_mask(pb->layout, pb->geom, pb->level, xi, st->sw,
                                           H ? mask : NULL, rho, J ? Jsi : NULL, H);
    if (e != HP_OK) return e;
    for (int k = 0; k < pb->n; ++k) {
        rho[k] *= HP_MM_PER_M;
        if (!isfinite(rho[k])) return HP_ERR_DOMAIN;
        if (J)
            for (int i = 0; i < 6; ++i)
                J[k * 6 + i] = Jsi[k * 6 + i] * HP_MM_PER_M * hpi_pose_si_per_scaled(i);
        if (H && mask[k]) { /* the others are not written, and never read (build_objective) */
            /* h − h is +0 for a finite h and NaN for a NaN or an infinity, so the sums are
             * 0 exactly when every entry is finite: one check, no branch per entry. */
            const double *Hk = &H[k * 36];
            double z0 = 0.0, z1 = 0.0;
            for (int i = 0; i < 36; i += 2) {
                z0 += Hk[i] - Hk[i];
                z1 += Hk[i + 1] - Hk[i + 1];
            }
            if (!(z0 + z1 == 0.0)) return HP_ERR_DOMAIN;
        }
    }
    return HP_OK;
}

/* Keeps st->rho as the radii at this solve's start when x is that start (rt_state.r0_x) and
 * none were kept yet. */
static void rt_note_start(rt_state *st, const hp_problem *pb, const double *x)
{
    if (st->r0_ok || !hpi_same_bits(x, st->r0_x, 6)) return;
    memcpy(st->r0_rho, st->rho, (size_t)pb->n * sizeof *st->rho);
    st->r0_ok = 1;
}

/* The margin (mm) by which the QP moves bladder k's limits inward. */
static double rt_margin(const hp_problem *pb, int k)
{
    return hpi_min2(RT_MARGIN_MM, 0.25 * (pb->ro_hi[k] - pb->ro_lo[k]));
}

/* How far inside a rate window end's stand-in (hp_problem.lazy) a radius must lie for the
 * backend's comparisons of it (against the limits and against the limits moved inward by
 * the margin, rt_margin) to decide as the exact bound would: beyond the margin. Closer,
 * the end is resolved first. */
#define RT_LAZY_MARGIN_MM (2.0 * RT_MARGIN_MM)

static void rt_touch(const hp_problem *pb, const double *rho)
{
    /* A failed resolve leaves the stand-in (a tighter limit) and is reported by the core
     * (hp_rate_lazy.failed), as the eager bounds' failure would be. */
    (void)hpi_setup_rate_touch(pb->lazy, rho, pb->n, RT_LAZY_MARGIN_MM);
}

/* Violation (mm, summed) of the limits the QP sees: moved inward by the margin. The merit
 * must measure the same constraints as the QP: against the true limits, the step that
 * moves an active radius the last 1e-11 mm into its margin only costs objective, and near
 * a flat direction of the reduced Hessian that step can be 1e-6 mm long and rejected again
 * and again (a warm-started trace stalled to its iteration limit so). */
static double qp_violation(const rt_state *st, const hp_problem *pb, const double *rho)
{
    double v = 0;
    rt_touch(pb, rho);
    for (int k = 0; k < pb->n; ++k) {
        if (!isfinite(rho[k])) return INFINITY;
        double mg = st->mg[k];
        v += hpi_max2(0.0, hpi_max2(pb->ro_lo[k] + mg - rho[k], rho[k] - (pb->ro_hi[k] - mg)));
    }
    return v;
}

static hp_error rt_create(void **state, const hp_problem *pb, const hp_settings *s, hp_diag *d)
{
    rt_state *st = calloc(1, sizeof *st);
    if (!st) return hp_diag_set(d, HP_ERR_NOMEM, "realtime backend: out of memory");
    st->max_iter = s->max_iter;
    st->max_time = s->max_time;
    st->clk = budget_clock(s->max_time);
    st->tolerance = s->tolerance;
    st->J = st->Jb[0];
    st->c_J = st->Jb[1];
    st->H = st->Hb[0];
    st->c_H = st->Hb[1];
    const double zero[6] = {0};
    hpi_kin_dist_warm_cold(st->sw, HP_MAX_BLADDERS);
    st->z_ok = rt_contact(st, pb, zero, st->z_rho, st->z_J, NULL, NULL) == HP_OK;
    memcpy(st->z_sw, st->sw, sizeof st->z_sw);
    *state = st;
    return HP_OK;
}

static void rt_destroy(void *state) { free(state); }

/* The tables that stay fixed while one solve runs (rt_state: map, nv, hsc, mg). */
static void rt_begin(rt_state *st, const hp_problem *pb)
{
    int nv = 0;
    for (int i = 0; i < 6; ++i)
        if (pb->w[i] > 0) st->map[nv++] = i;
    st->nv = nv;
    /* mm/m · (si/scaled)_a · (si/scaled)_b: one product per entry instead of a division */
    for (int a = 0; a < nv; ++a)
        for (int b = 0; b < nv; ++b)
            st->hsc[a * nv + b] = HP_MM_PER_M * hpi_pose_si_per_scaled(st->map[a]) *
                                  hpi_pose_si_per_scaled(st->map[b]);
    for (int k = 0; k < pb->n; ++k) st->mg[k] = rt_margin(pb, k);
}

static void rt_warm_point(void *state, int accepted)
{
    rt_state *st = state;
    st->accepted = accepted;
    st->lin_pending = accepted ? 0 : st->lin_own;
    st->lin_own = accepted;
}

static void rt_reading(void *state)
{
    rt_state *st = state;
    st->lin_own = st->lin_pending;
}

/* 1 when the symmetric G (nv×nv) is positive definite with every Cholesky pivot above
 * frac × its diagonal entry: far from the answer, large multipliers times the contact
 * curvature make the Lagrangian nearly singular and the Newton step wild. */
static int well_convex(const double *G, int nv, double frac, double *L)
{
    return hpi_cholesky(G, nv, nv, frac, L, nv);
}

/* 1 when G − frac·W is positive definite (W the objective's diagonal weights): every
 * direction keeps at least frac of the objective's own curvature. */
static int above_w(const double *G, const hp_problem *pb, const int *map, int nv, double frac)
{
    double M[HP_QP_NMAX * HP_QP_NMAX], L[HP_QP_NMAX * HP_QP_NMAX] = {0};
    memcpy(M, G, sizeof M);
    for (int v = 0; v < nv; ++v) M[v * nv + v] -= frac * pb->w[map[v]];
    return hpi_cholesky(M, nv, nv, 0.0, L, nv);
}

/* Hessian of the Lagrangian in the commanded variables, W − Σ (u_lo,k − u_hi,k)·∇²rho_k
 * (Newton-SQP: quadratic convergence on the curved levels), written into q->G, and the
 * linear term for the variables x (not the step); q->C and q->b must be built. Far from
 * the answer, or where large multipliers times the contact curvature make it indefinite,
 * the Lagrangian's Hessian is convexified by the augmented-Lagrangian term
 * ½σ·Σ_j (C_j x − b_j)² over the rows j active in the previous QP: it vanishes with its
 * gradient wherever those rows stay active, so it leaves that QP's answer unchanged while
 * adding curvature across the active normals (only the curvature along the active
 * manifold decides the Newton step). σ grows ×10 from 1 until the matrix is safely
 * positive definite; if none does, W alone (safe, linear rate). */
static void build_objective(rt_state *st, const hp_problem *pb, const double *xk, int curved)
{
    hp_qp *q = &st->qp;
    const int *map = st->map, nv = st->nv;
    double Gl[HP_QP_NMAX * HP_QP_NMAX] = {0};
    for (int v = 0; v < nv; ++v) Gl[v * nv + v] = pb->w[map[v]];
    if (curved) {
        /* The lower triangle, mirrored: the contact Hessians are symmetric (the kinematics
         * writes each pair of entries from one value), and so G is exactly. */
        for (int k = 0; k < pb->n; ++k) {
            double lam = st->u[2 * k] - st->u[2 * k + 1];
            if (lam == 0.0) continue;
            const double *Hk = &st->H[k * 36];
            if (nv == 6) { /* all commanded, map the identity: bounds the compiler unrolls */
                for (int a = 0; a < 6; ++a)
                    for (int b = 0; b <= a; ++b)
                        Gl[a * 6 + b] -= lam * Hk[a * 6 + b] * st->hsc[a * 6 + b];
                continue;
            }
            for (int a = 0; a < nv; ++a) {
                const double *Ha = &Hk[map[a] * 6];
                for (int b = 0; b <= a; ++b)
                    Gl[a * nv + b] -= lam * Ha[map[b]] * st->hsc[a * nv + b];
            }
        }
        for (int a = 1; a < nv; ++a)
            for (int b = 0; b < a; ++b) Gl[b * nv + a] = Gl[a * nv + b];
    }
    memcpy(q->G, Gl, sizeof Gl);
    double sigma = 0.0;
    st->exact = curved;
    st->Lg_ok = curved && well_convex(q->G, nv, 0.1, st->Lg);
    if (curved && !st->Lg_ok) {
        int ok = 0;
        for (sigma = 1.0; sigma <= RT_AUG_MAX; sigma *= 10.0) {
            memcpy(q->G, Gl, sizeof Gl);
            for (int j = 0; j < q->m; ++j) {
                if (!(st->u[j] > 0.0)) continue;
                const double *c = &q->C[j * HP_QP_NMAX];
                for (int a = 0; a < nv; ++a)
                    for (int b = 0; b < nv; ++b) q->G[a * nv + b] += sigma * c[a] * c[b];
            }
            if ((ok = above_w(q->G, pb, map, nv, RT_AUG_MIN))) break;
        }
        st->exact = 0;
        if (!ok) { /* keep only W */
            sigma = 0.0;
            memset(Gl, 0, sizeof Gl);
            for (int v = 0; v < nv; ++v) Gl[v * nv + v] = pb->w[map[v]];
            memcpy(q->G, Gl, sizeof Gl);
        }
    }
    if (!curved || (!st->Lg_ok && sigma == 0.0)) {
        /* G = W, diagonal: its Cholesky factor is diag(√w), the very bits hpi_cholesky
         * gives (each pivot w − 0, each entry below it 0/√w), so the QP need not factor */
        memset(st->Lg, 0, sizeof st->Lg);
        for (int v = 0; v < nv; ++v) st->Lg[v * nv + v] = sqrt(pb->w[map[v]]);
        st->Lg_ok = 1;
    }
    /* ½(x − xk)ᵀGl(x − xk) + ∇f(xk)ᵀ(x − xk) in x: a = ∇f(xk) − Gl·xk, plus the
     * augmentation's linear part −σ·Σ_j b_j C_j (its quadratic part is in G). */
    double xm[HP_QP_NMAX];
    for (int v = 0; v < nv; ++v) xm[v] = xk[map[v]];
    for (int a = 0; a < nv; ++a) {
        double g = pb->w[map[a]] * (xm[a] - pb->d[map[a]]);
        for (int b = 0; b < nv; ++b) g -= Gl[a * nv + b] * xm[b];
        if (sigma > 0.0)
            for (int j = 0; j < q->m; ++j)
                if (st->u[j] > 0.0) g -= sigma * q->b[j] * q->C[j * HP_QP_NMAX + a];
        q->a[a] = g;
    }
}

/* Bladder k's two rows' b in the QP from its bounds (read now: a resolved rate window end
 * has its exact bound there), the linearisation's constant, the extra tightening and,
 * after a second-order correction, its shift. */
static void rt_row_b(rt_state *st, const hp_problem *pb, int k)
{
    hp_qp *q = &st->qp;
    double mg = st->mg[k] + st->ext[k], base = st->base[k];
    q->b[2 * k] = pb->ro_lo[k] + mg - base;        /* J x >= lo − base */
    q->b[2 * k + 1] = -(pb->ro_hi[k] - mg - base); /* −J x >= −(hi − base) */
    if (st->soc) {
        q->b[2 * k] -= st->dk[k];
        q->b[2 * k + 1] += st->dk[k];
    }
}

/* The QP's lazy rows (lz[2k], lz[2k+1]: bladder k's window ends still stand-ins); 1 when
 * any is. */
static int lazy_rows(const hp_rate_lazy *z, int n, unsigned char *lz)
{
    int any = 0;
    for (int k = 0; k < n; ++k) {
        lz[2 * k] = z->lo[k];
        lz[2 * k + 1] = z->hi[k];
        any |= z->lo[k] | z->hi[k];
    }
    return any;
}

/* The QP in st->qp solved as hpi_qp_solve_warm solves it, with every rate window end that
 * is still a stand-in (hp_problem.lazy) resolved when the solve needs it (hpi_qp_solve_lazy
 * stops there): the bladder of that row, and every other bladder whose stand-in row the
 * stopped iterate violates (it is likely to be needed next), get their exact bounds and
 * the solve starts again. The solve that runs to its end is the exact bounds' solve, bit
 * for bit. The rows' b must be those of the bounds as they are (qp_at, line_search). */
static hp_qp_status rt_qp(rt_state *st, const hp_problem *pb, const double *Lg, const int *guess,
                          int budget)
{
    hp_qp *q = &st->qp;
    hp_rate_lazy *z = pb->lazy;
    if (!z) {
        hp_qp_status qs = hpi_qp_solve_warm(q, Lg, guess, budget, RT_FEAS_TOL);
        st->cnt.qp_steps += q->gi_steps;
        return qs;
    }
    unsigned char lz[HP_QP_MMAX] = {0};
    int hit = -1;
    /* A guessed row's b enters the warm start's equality solve, which stops on each stand-in
     * among them (and starts again): their exact ends now, in one pass. */
    for (int k = 0; guess && k < pb->n; ++k) {
        unsigned ends = (guess[2 * k] && z->lo[k] ? 1u : 0u) |
                        (guess[2 * k + 1] && z->hi[k] ? 2u : 0u);
        if (!ends) continue;
        if (!hpi_setup_rate_resolve(z, k, ends)) return HP_QP_BAD_INPUT;
        rt_row_b(st, pb, k);
    }
    int any = lazy_rows(z, pb->n, lz);
    hp_qp_status qs = hpi_qp_solve_lazy(q, Lg, guess, any ? lz : NULL, &hit, budget, RT_FEAS_TOL);
    st->cnt.qp_steps += q->gi_steps;
    while (qs == HP_QP_LAZY) {
        /* A stop in the full solve's loop goes on from its iterate once the row is exact
         * (hpi_qp_resume_lazy): only that end is solved. A warm start's stop (in its check
         * of the other rows: resumed there; on a guessed row: started again) solves with it
         * every bladder whose stand-in row the iterate violates: the check, and the full
         * solve a refusal runs from the unconstrained minimum, are likely to stop on them
         * next. Measured with bench/loop_tail.sh on the step trace, both ways in one build
         * (a run-time switch, its check in both figures): p99.9 34 390 instructions a plan,
         * one end at a time 34 884, though of the 75 ends resolved this way beside a hit row
         * over the trace only 6 end in the answer's active set: the further stops one at a
         * time costs exceed those root finds. */
        int resume = q->resumable;
        if (resume == 1) {
            /* The hit row's bladder alone (a stand-in row, so of a bladder with one): the
             * step trace's slowest plans stop here once an end, seven times, and the pass
             * over every bladder cost each stop about 150 instructions. */
            int k = hit / 2;
            if (!hpi_setup_rate_resolve(z, k, hit == 2 * k ? 1u : 2u)) return HP_QP_BAD_INPUT;
            rt_row_b(st, pb, k);
        } else {
            for (int k = 0; k < pb->n; ++k) {
                if (!(z->lo[k] | z->hi[k])) continue;
                unsigned ends = (hit == 2 * k ? 1u : 0u) | (hit == 2 * k + 1 ? 2u : 0u);
                const double *c = &q->C[2 * k * HP_QP_NMAX];
                double cx = 0.0;
                for (int v = 0; v < q->n; ++v) cx += c[v] * q->x[v];
                ends |= (z->lo[k] && cx < q->b[2 * k] ? 1u : 0u) |
                        (z->hi[k] && -cx < q->b[2 * k + 1] ? 2u : 0u);
                if (!ends) continue;
                if (!hpi_setup_rate_resolve(z, k, ends)) return HP_QP_BAD_INPUT;
                rt_row_b(st, pb, k);
            }
        }
        any = lazy_rows(z, pb->n, lz);
        qs = resume ? hpi_qp_resume_lazy(q, any ? lz : NULL, &hit, budget, RT_FEAS_TOL)
                    : hpi_qp_solve_lazy(q, Lg, guess, any ? lz : NULL, &hit, budget, RT_FEAS_TOL);
        st->cnt.qp_steps += q->gi_steps;
    }
    return qs;
}

/* Builds and solves the QP linearised at xk (scaled pose; uncommanded entries 0), with the
 * limits tightened by extra[k] (mm, may be NULL). Writes the new pose into x. guess (may
 * be NULL) is the active set the QP is warm-started from (hpi_qp_solve_warm): successive
 * SQP steps' QPs mostly share theirs, and a wrong guess only costs the attempt. */
static hp_qp_status qp_at(rt_state *st, const hp_problem *pb, const double *xk, const double *extra,
                          const int *guess, double *x, int budget, int *iters)
{
    hp_qp *q = &st->qp;
    const int *map = st->map, nv = st->nv;
    int curved = pb->level != HP_LEVEL_LINEAR && st->have_u;
    int at_zero = !curved && st->z_ok;
    for (int i = 0; i < 6; ++i) at_zero &= xk[i] == 0.0;
    if (st->c_ok && hpi_same_bits(st->c_x, xk, 6)) {
        memcpy(st->rho, st->c_rho, sizeof st->rho);
        /* The trial evaluation's J and Hessians become the current ones (its Hessians are
         * those of the bladders with a multiplier, the same st->u that build_objective
         * reads; the others are not written and never read). A trial that kept the
         * previous point's Hessians (merit_full) leaves H as it is. */
        double *t = st->J;
        st->J = st->c_J;
        st->c_J = t;
        if (st->c_h_ok) {
            t = st->H;
            st->H = st->c_H;
            st->c_H = t;
            memcpy(st->hm, st->c_hm, sizeof st->hm);
        }
        st->h_kept = !st->c_h_ok;
    } else if (at_zero) {
        memcpy(st->rho, st->z_rho, sizeof st->rho);
        memcpy(st->J, st->z_J, sizeof st->z_J);
        memcpy(st->sw, st->z_sw, sizeof st->sw);
        st->h_kept = 1; /* no Hessians at xk: none to keep */
    } else if (rt_contact(st, pb, xk, st->rho, st->J, curved ? st->H : NULL, st->hm) != HP_OK) {
        return HP_QP_BAD_INPUT;
    } else {
        st->h_kept = !curved;
    }
    st->c_ok = 0;
    rt_inject(st, pb->n, st->rho);
    memcpy(st->rho_k, st->rho, sizeof st->rho_k);
    rt_note_start(st, pb, xk);
    q->n = nv;
    q->m = 2 * pb->n;
    q->pairs = pb->n; /* rows 2k, 2k + 1: bladder k's limits, exact negations (below) */
    /* The commanded parts of xk and of J's rows; with all six commanded (the common case)
     * xk and J themselves, read in place: a perf profile put a stalled load of the copies
     * (written just before, read in pairs) at ~8 % of this function's samples, though the
     * plan's time moved by less than an A/B of two builds resolves (~1 %). Otherwise
     * zero-padded copies (the padding is never read by the QP). */
    double xm[HP_QP_NMAX] = {0};
    const double *xv = xk;
    if (nv < 6) {
        for (int v = 0; v < nv; ++v) xm[v] = xk[map[v]];
        xv = xm;
    }
    st->soc = 0;
    for (int k = 0; k < pb->n; ++k) {
        st->ext[k] = extra ? extra[k] : 0.0;
        double base = st->rho[k]; /* rho(xk) − J·xk: the linearisation's constant */
        const double *jr = &st->J[k * 6];
        double *lo = &q->C[(2 * k) * HP_QP_NMAX], *hi = lo + HP_QP_NMAX;
        double jm[HP_QP_NMAX] = {0};
        if (nv < 6) {
            for (int v = 0; v < nv; ++v) jm[v] = jr[map[v]];
            jr = jm;
        }
        for (int v = 0; v < nv; ++v) base -= jr[v] * xv[v];
        for (int v = 0; v < HP_QP_NMAX; ++v) {
            lo[v] = jr[v];
            hi[v] = -jr[v];
        }
        st->base[k] = base;
        rt_row_b(st, pb, k);
    }
    build_objective(st, pb, xk, curved);
    hp_qp_status qs = rt_qp(st, pb, st->Lg_ok ? st->Lg : NULL, guess, budget);
    *iters += q->iterations;
    if (qs == HP_QP_BAD_INPUT && curved) { /* Lagrangian not convex here: plain W */
        build_objective(st, pb, xk, 0);
        qs = rt_qp(st, pb, st->Lg, guess, budget);
        *iters += q->iterations;
    }
    ++st->qps;
    rt_count_late(st);
    if (qs == HP_QP_OPTIMAL) {
        memcpy(st->u, q->u, sizeof st->u);
        st->have_u = 1;
    }
    if (qs == HP_QP_OPTIMAL) {
        for (int i = 0; i < 6; ++i) x[i] = 0.0;
        for (int v = 0; v < nv; ++v) x[map[v]] = q->x[v];
    }
    return qs;
}

/* Largest violation of the true limits by rho(x) (mm); per-bladder violations in viol. */
static double violation(rt_state *st, const hp_problem *pb, const double *x, double *viol)
{
    if (viol) /* every entry is written, even when a non-finite rho ends the scan */
        for (int k = 0; k < pb->n; ++k) viol[k] = 0.0;
    if (st->c_ok && hpi_same_bits(st->c_x, x, 6)) /* the line search's point */
        memcpy(st->rho, st->c_rho, sizeof st->rho);
    else if (st->late && st->r0_ok && hpi_same_bits(st->r0_x, x, 6)) /* the solve's start */
        memcpy(st->rho, st->r0_rho, sizeof st->rho);
    else if (rt_contact(st, pb, x, st->rho, NULL, NULL, NULL) != HP_OK) return INFINITY;
    else {
        rt_inject(st, pb->n, st->rho);
        rt_note_start(st, pb, x);
    }
    rt_touch(pb, st->rho);
    double worst = 0;
    for (int k = 0; k < pb->n; ++k) {
        if (!isfinite(st->rho[k])) return INFINITY; /* a max would drop a NaN */
        double v = hpi_max2(pb->ro_lo[k] - st->rho[k], st->rho[k] - pb->ro_hi[k]);
        v = hpi_max2(v, 0.0);
        if (viol) viol[k] = v;
        worst = hpi_max2(worst, v);
    }
    return worst;
}

/* rho at xk (st->rho) from the last QP's linearisation at xa, rho_k + J·(xk − xa), when
 * the step xa -> xk is so short that its second-order remainder (hpi_kin_contact_step_bound,
 * a bound derived for the layout's geometry, not an estimate) is below one rounding of
 * each radius: then these are the numbers a fresh evaluation would give, to its own
 * rounding, for 48 multiply-adds instead of eight distances. A converged solve's last
 * step (~1e-11 mm or deg) leaves a remainder near 1e-18 mm. Returns 1 only when every
 * radius is also inside its true limits (the restoration, which needs the violations,
 * then has nothing to do); otherwise 0 with st->rho untouched. */
static int rho_by_step(rt_state *st, const hp_problem *pb, const double *xa, const double *xk)
{
    double xia[6], xib[6], dxi[6], ra[HP_MAX_BLADDERS], b[HP_MAX_BLADDERS], r[HP_MAX_BLADDERS];
    hpi_setup_pose_from_scaled(xa, xia);
    hpi_setup_pose_from_scaled(xk, xib);
    for (int i = 0; i < 6; ++i) dxi[i] = xib[i] - xia[i];
    for (int k = 0; k < pb->n; ++k) ra[k] = st->rho_k[k] / HP_MM_PER_M;
    if (hpi_kin_contact_step_bound(pb->layout, pb->geom, pb->level, xia, dxi, ra, b) != HP_OK)
        return 0;
    for (int k = 0; k < pb->n; ++k) {
        double v = st->rho_k[k];
        for (int i = 0; i < 6; ++i) v += st->J[k * 6 + i] * (xk[i] - xa[i]);
        /* comparisons false for a NaN: a failed model never passes */
        if (!(b[k] * HP_MM_PER_M <= DBL_EPSILON * fabs(v))) return 0;
        r[k] = v;
    }
    rt_touch(pb, r);
    for (int k = 0; k < pb->n; ++k)
        if (!(r[k] >= pb->ro_lo[k] && r[k] <= pb->ro_hi[k])) return 0;
    memcpy(st->rho, r, (size_t)pb->n * sizeof *r);
    return 1;
}

/* The model at xa, the last QP's linearisation point, for the core's round trip (problem.h):
 * its distances and, back in SI units, its Jacobian (the scaling's powers of ten cost the
 * entries an ulp or two, far inside the certificate's slack). */
static void lin_point(const rt_state *st, const hp_problem *pb, const double *xa,
                      hp_backend_result *r)
{
    memcpy(r->lin_x, xa, sizeof r->lin_x);
    memcpy(r->lin_rho, st->rho_k, sizeof r->lin_rho);
    for (int k = 0; k < pb->n; ++k)
        for (int i = 0; i < 6; ++i)
            r->lin_J[k * 6 + i] = st->J[k * 6 + i] / (HP_MM_PER_M * hpi_pose_si_per_scaled(i));
    r->has_lin = 1;
}

/* The l1 merit function ½Σw(x − d)² + nu·Σ violation(x) (mm), which the SQP step decreases
 * for nu above the largest multiplier, from the radii rho at x. */
static double merit_of(const rt_state *st, const hp_problem *pb, const double *x, const double *rho,
                       double nu)
{
    double f = 0;
    for (int i = 0; i < 6; ++i) f += 0.5 * pb->w[i] * (x[i] - pb->d[i]) * (x[i] - pb->d[i]);
    return f + nu * qp_violation(st, pb, rho);
}

static double merit(rt_state *st, const hp_problem *pb, const double *x, double nu)
{
    if (rt_contact(st, pb, x, st->rho, NULL, NULL, NULL) != HP_OK) return INFINITY;
    rt_inject(st, pb->n, st->rho);
    return merit_of(st, pb, x, st->rho, nu);
}

/* The merit at a full SQP step's point x, evaluating the model there with the derivatives
 * the next QP needs (kept in st->c_*): near the answer every full step is accepted. */
static double merit_full(rt_state *st, const hp_problem *pb, const double *x, double nu, int want_h)
{
    st->c_ok = 0;
    /* Only the curved levels search lines, and only after a QP, so the Hessians (of the
     * bladders with a multiplier) are wanted unless the caller keeps the current ones. */
    if (rt_contact(st, pb, x, st->c_rho, st->c_J, want_h ? st->c_H : NULL, st->c_hm) != HP_OK)
        return INFINITY;
    memcpy(st->c_x, x, sizeof st->c_x);
    st->c_ok = 1;
    st->c_h_ok = want_h;
    rt_inject(st, pb->n, st->c_rho);
    return merit_of(st, pb, x, st->c_rho, nu);
}

/* 1 when the current Hessians (st->H, evaluated at the point the last QP was built at) may
 * serve at a trial point the step xk -> xn away: a short step, H evaluated there (not kept
 * from further back), and every bladder with a multiplier now among those H holds. */
static int keep_h(const rt_state *st, const hp_problem *pb, const double *xk, const double *xn)
{
    if (st->h_kept) return 0;
    for (int i = 0; i < 6; ++i)
        if (!(fabs(xn[i] - xk[i]) <= RT_REUSE_H_STEP)) return 0;
    for (int k = 0; k < pb->n; ++k)
        if (st->u[2 * k] - st->u[2 * k + 1] != 0.0 && !st->hm[k]) return 0;
    return 1;
}

/* The step xk -> xn of the QP just solved at xk (still in st->qp), globalised on the l1
 * merit function: accepted whole when it decreases the merit enough (Armijo); otherwise a
 * second-order correction — the same QP with each linearised distance shifted by what the
 * linearisation missed at xn, rho(xn) − rho(xk) − J·(xn − xk) — whose answer is accepted on
 * the same test (this keeps full Newton steps near the answer, where the merit can reject
 * them on curved limits: the Maratos effect); otherwise backtracking along the step (at
 * most 30 halvings). Far from the answer a full step can overshoot the curved limits and
 * cycle; every accepted point here lowers the merit. xk becomes the accepted point. */
static int line_search(rt_state *st, const hp_problem *pb, double *xk, const double *xn, int budget,
                       int *iters)
{
    hp_qp *q = &st->qp;
    double nu = 1.0;
    for (int j = 0; j < 2 * pb->n; ++j)
        if (2.0 * st->u[j] > nu) nu = 2.0 * st->u[j]; /* fmax, inline */
    /* rho(xk) is the QP's own linearisation point (st->rho_k): no evaluation here. */
    double phi0 = merit_of(st, pb, xk, st->rho_k, nu), viol0 = qp_violation(st, pb, st->rho_k);
    double slope = 0;
    for (int i = 0; i < 6; ++i) slope += pb->w[i] * (xk[i] - pb->d[i]) * (xn[i] - xk[i]);
    slope -= nu * viol0; /* directional derivative bound of the l1 merit along a QP step */
    slope = fmin(slope, 0.0);
    /* The full step is tried even when the QP ended past the budget: one trial (a contact
     * evaluation) keeps the step the QP paid for. Stopping before it kept xk, and under a
     * budget that a QP outlasts every plan ended where it started: the loop benchmark's
     * step trace at 3 us, every plane and surface plan time-limit, none reaching its
     * target (docs/control-loop.md, A time budget that holds). */
    int kept = keep_h(st, pb, xk, xn);
    st->cnt.h_kept += kept;
    if (merit_full(st, pb, xn, nu, !kept) <= phi0 + RT_ARMIJO * slope) {
        memcpy(xk, xn, 6 * sizeof *xk);
        return 1;
    }
    if (!st->c_ok) /* the model failed at xn: only backtracking can help */
        for (int k = 0; k < pb->n; ++k) st->c_rho[k] = NAN;
    st->c_ok = 0;
    /* Second-order correction: st->c_rho holds rho(xn), st->rho_k and st->J the values at
     * xk the QP was built from; G, a and C are unchanged, only b moves. */
    const int *map = st->map, nv = st->nv;
    for (int k = 0; k < pb->n; ++k) {
        double dk = st->c_rho[k] - st->rho_k[k];
        for (int v = 0; v < nv; ++v) dk -= st->J[k * 6 + map[v]] * (xn[map[v]] - xk[map[v]]);
        st->dk[k] = dk;
    }
    st->soc = 1; /* the rows' b shifted by dk (rt_row_b), from the bounds as they are now */
    for (int k = 0; k < pb->n; ++k) rt_row_b(st, pb, k);
    double xt[6];
    int soc_ok = 1, guess[HP_QP_MMAX]; /* the QP just solved: its active set is the guess */
    memcpy(guess, q->active, sizeof guess);
    for (int k = 0; k < pb->n; ++k) soc_ok &= isfinite(st->c_rho[k]) != 0;
    const double *Lg = st->Lg_ok ? st->Lg : NULL;
    if (rt_late(st)) return 0;
    if (soc_ok && isfinite(phi0) && rt_qp(st, pb, Lg, guess, budget) == HP_QP_OPTIMAL) {
        *iters += q->iterations;
        ++st->cnt.soc;
        st->cnt.soc_warm += q->warm == HP_QP_WARM_ACCEPTED;
        for (int i = 0; i < 6; ++i) xt[i] = 0.0;
        for (int v = 0; v < nv; ++v) xt[map[v]] = q->x[v];
        if (merit(st, pb, xt, nu) <= phi0 + RT_ARMIJO * slope) {
            memcpy(xk, xt, sizeof xt);
            return 0;
        }
    }
    double alpha = 0.5;
    for (int it = 0; it < 30; ++it, alpha *= 0.5) {
        if (rt_late(st)) return 0;
        for (int i = 0; i < 6; ++i) xt[i] = xk[i] + alpha * (xn[i] - xk[i]);
        if (merit(st, pb, xt, nu) <= phi0 + RT_ARMIJO * alpha * slope) break;
    }
    memcpy(xk, xt, sizeof xt);
    return 0;
}

static hp_status qp_status_map(hp_qp_status qs)
{
    switch (qs) {
    case HP_QP_OPTIMAL: return HP_STATUS_CLOSEST;
    case HP_QP_INFEASIBLE: return HP_STATUS_INFEASIBLE_START;
    case HP_QP_ITERATION_LIMIT: return HP_STATUS_ITERATION_LIMIT;
    default: return HP_STATUS_SOLVER_ERROR;
    }
}

static hp_error rt_solve(void *state, const hp_problem *pb, const double *x0, double *x,
                         hp_backend_result *r, hp_diag *d)
{
    rt_state *st = state;
    double t0 = now_s(st->clk), xk[6], xn[6];
    st->t_end = t0 + st->max_time;
    st->late = 0;
    r->iterations = 0;
    r->converged = 0;
    r->raw_code = 0;
    r->has_rho = 0;
    r->has_lin = 0;
    for (int i = 0; i < 6; ++i) xk[i] = (pb->w[i] > 0 && x0 && isfinite(x0[i])) ? x0[i] : 0.0;
    if (pb->level == HP_LEVEL_LINEAR)
        for (int i = 0; i < 6; ++i) xk[i] = 0.0;
    memcpy(st->r0_x, xk, sizeof st->r0_x);
    st->r0_ok = 0;

    int iters = 0, sqp = 0;
    double prev_step = INFINITY;
    /* Started at this backend's own last answer (the core said so, and x0 is that pose):
     * the first QP is a Newton step with that answer's multipliers, and the distances start
     * from theirs; along a trace the answer moves little and its active set rarely. */
    int warm = st->accepted && st->have_u && pb->level != HP_LEVEL_LINEAR && x0 &&
               hpi_same_bits(x0, st->x_last, 6);
    int lin_own = st->lin_own;
    st->accepted = 0;
    st->lin_own = 0; /* until the core accepts this answer (warm_point) */
    if (!warm) {
        st->have_u = 0;
        hpi_kin_dist_warm_cold(st->sw, HP_MAX_BLADDERS); /* a cold first distance */
    }
    st->qps = 0;
    memset(&st->cnt, 0, sizeof st->cnt); /* its solves and qps fields stay unused here */
    st->c_ok = 0;
    st->h_kept = 1;
    rt_begin(st, pb);
    int whole_prev = 0, exact_prev = 0, short_last = 0;
    double xa[6];
    hp_qp_status qs = HP_QP_OPTIMAL;
    hp_status st_out = HP_STATUS_CLOSEST;
    /* The stopping steps scale with the pose tolerance, but no further than RT_FULL_STEP:
     * a stop after a longer, line-searched step leaves the curved limits violated by its
     * linearisation error (~½κ·step², above RT_MARGIN_MM from ~1e-5 mm on), which the
     * restoration then tightens into a point not proven closest: ITERATION_LIMIT after a
     * handful of steps whenever the tolerance is clinical (0.05 to 0.5 mm). */
    const double stop_tol = fmin(st->tolerance, RT_FULL_STEP);
    double t_step = t0, longest = 0.0; /* the last SQP step's start; the longest step */
    for (;;) {
        /* The previous step's active set as the guess; none for a cold solve's first QP
         * (st->act is then the last solve's, for another target: measured on the default
         * scene's binding targets, right 2 times in 37). */
        const int *guess = sqp > 0 || warm ? st->act : NULL;
        /* Linear level: the last plan's active set, when this plan starts from that answer
         * or a reading of it (in a loop walking toward a target, consecutive plans bind the
         * same rate limits). Counted on the loop's step trace (tests/planner/
         * test_rate_window.c, test_binding_walk_warm): accepted in 155 QPs of 240 plans. */
        if (pb->level == HP_LEVEL_LINEAR && lin_own && st->lin_k > 0 && st->lin_n == pb->n &&
            st->lin_nv == st->nv)
            guess = st->lin_act;
        /* Out of time (before the first QP too: a budget shorter than the solve's set-up),
         * or a step like the longest so far would end past the budget: stop at the current
         * iterate, which the restoration below makes feasible or replaces by the warm
         * start or the nominal pose. A step begun near the deadline ran on past it by a
         * whole QP and its trial, the largest part of a stopped plan's overshoot. */
        const double t = now_s(st->clk); /* nothing in the loop sets late and goes on */
        if (sqp > 0) longest = fmax(longest, t - t_step);
        t_step = t;
        if (t + RT_STEP_FIT * longest > st->t_end) {
            st->late = 1;
            st_out = HP_STATUS_TIME_LIMIT;
            r->converged = 0;
            break;
        }
        qs = qp_at(st, pb, xk, NULL, guess, xn, st->max_iter, &iters);
        ++sqp;
        st->cnt.qp_warm += st->qp.warm == HP_QP_WARM_ACCEPTED;
        if (qs != HP_QP_OPTIMAL && sqp > 1) {
            /* A linearisation far from the answer can be empty or degenerate: keep the last
             * iterate, let the restoration make it feasible, and say it is not optimal. */
            qs = HP_QP_OPTIMAL;
            st_out = HP_STATUS_ITERATION_LIMIT;
            r->converged = 0;
            break;
        }
        if (qs != HP_QP_OPTIMAL) break;
        double step = 0;
        for (int i = 0; i < 6; ++i) {
            double s = fabs(xn[i] - xk[i]);
            if (s > step) step = s; /* fmax, inline */
        }
        if (pb->level == HP_LEVEL_LINEAR) {
            st->lin_k = 0;
            for (int j = 0; j < st->qp.m; ++j) st->lin_k += st->qp.active[j] != 0;
            memcpy(st->lin_act, st->qp.active, sizeof st->lin_act);
            st->lin_n = pb->n;
            st->lin_nv = st->nv;
            memcpy(xk, xn, sizeof xk);
            r->converged = 1;
            break;
        }
        /* Steps far below any clinical size (at the rounding floor of the merit) are taken
         * whole; every other one is globalised. */
        int whole = 1;
        short_last = step <= RT_FULL_STEP;
        if (!short_last) whole = line_search(st, pb, xk, xn, st->max_iter, &iters);
        else {
            memcpy(xa, xk, sizeof xa); /* where rho_k and J were evaluated */
            memcpy(xk, xn, sizeof xk);
        }
        if (st->late) { /* the line search stopped for time: no convergence test */
            st_out = HP_STATUS_TIME_LIMIT;
            r->converged = 0;
            break;
        }
        int same_active = same_set(st->act, st->qp.active);
        memcpy(st->act, st->qp.active, sizeof st->act);
        /* The accepted point inside the true limits: measured when the line search
         * evaluated it, else a step below RT_FULL_STEP, whose linearisation error ½κ·step²
         * (κ <= ~0.1 mm per mm² or deg²) is far below the margin. What a longer step leaves
         * of the curved limits' violation does not follow the pose's Newton rate and can
         * exceed the margin (a stop there was restored and labelled iteration-limit). */
        int measured = st->c_ok && hpi_same_bits(st->c_x, xk, 6);
        int inside = measured || step <= RT_FULL_STEP;
        if (measured) rt_touch(pb, st->c_rho);
        for (int k = 0; measured && inside && k < pb->n; ++k)
            inside = st->c_rho[k] >= pb->ro_lo[k] && st->c_rho[k] <= pb->ro_hi[k];
        /* Converged when the step is far below the pose tolerance, or below a tenth of it
         * and no longer shrinking (Newton steps that stall have hit the rounding floor), or
         * when Newton's quadratic rate predicts it: the last two QPs were exact Newton steps
         * (the Lagrangian's own Hessian, not convexified) on the same active set, both taken
         * whole, the second at most 1 % of the first, the next step extrapolated at the
         * quadratic rate, step·(step/prev)², below 1e-3 of the tolerance and a tenth of the
         * margin, and the accepted point measured inside the limits. Those are the
         * conditions under which Newton-SQP converges quadratically near a regular
         * solution; the QP saved would only confirm digits far below the tolerance. */
        double next = step * (step / prev_step) * (step / prev_step);
        if (step <= 1e-3 * stop_tol || (step <= 0.1 * stop_tol && step >= 0.5 * prev_step) ||
            (whole && whole_prev && same_active && inside && st->exact && exact_prev &&
             step <= 0.01 * prev_step && next <= fmin(1e-3 * stop_tol, 0.1 * RT_MARGIN_MM))) {
            r->converged = 1;
            break;
        }
        prev_step = step;
        whole_prev = whole;
        exact_prev = st->exact;
        if (sqp >= st->max_iter) {
            st_out = HP_STATUS_ITERATION_LIMIT;
            break;
        }
    }
    r->raw_code = (int)qs;
    r->iterations = iters;
    if (qs != HP_QP_OPTIMAL) {
        r->status = qp_status_map(qs);
        rt_count_flush(st);
        return hp_diag_set(d, HP_ERR_SOLVER, "realtime QP: %s",
                           qs == HP_QP_INFEASIBLE        ? "the limits cannot all hold at once"
                           : qs == HP_QP_ITERATION_LIMIT ? "iteration budget exhausted"
                                                         : "bad numbers in the problem");
    }

    /* Feasibility restoration (only the nonlinear levels can need it). */
    double viol[HP_MAX_BLADDERS], extra[HP_MAX_BLADDERS] = {0};
    double anchor[6] = {0}; /* the bisection's feasible end (have), when v > 0 below */
    int have = 0;
    /* rho(xk): after a short last step, from that step's linearisation (rho_by_step). */
    double v = 0.0;
    if (short_last && rho_by_step(st, pb, xa, xk)) {
        for (int k = 0; k < pb->n; ++k) viol[k] = 0.0;
        ++st->cnt.rho_step;
        lin_point(st, pb, xa, r);
    } else {
        st->cnt.rho_refused += short_last;
        v = violation(st, pb, xk, viol);
    }
    int rho_at_xk = v == 0.0; /* st->rho holds rho(xk) until a restoration moves on */
    /* rho(xk) and rho(anchor) kept for a stop by time: a step fraction from them (below) */
    double rho_x[HP_MAX_BLADDERS], rho_a[HP_MAX_BLADDERS];
    int have_rho_x = v > 0 && isfinite(v), rho_fresh = 0;
    if (have_rho_x) memcpy(rho_x, st->rho, sizeof rho_x);
    /* Restoration tightens finite violations; a non-finite one has nothing to tighten. Out
     * of time it is left to the bisection below, unless that has no feasible anchor. */
    int round = 0;
    for (int heed_clock = 1; heed_clock >= 0; --heed_clock) {
        for (; v > 0 && isfinite(v) && round < RT_RESTORE_ROUNDS && !(heed_clock && rt_late(st));
             ++round) {
            for (int k = 0; k < pb->n; ++k) extra[k] += 2.0 * viol[k];
            if (qp_at(st, pb, xk, extra, st->act, xn, st->max_iter, &iters) != HP_QP_OPTIMAL) break;
            double vn = violation(st, pb, xn, viol);
            if (vn < v) {
                memcpy(xk, xn, sizeof xk);
                v = vn;
                memcpy(rho_x, st->rho, sizeof rho_x);
            }
            r->converged = 0; /* a tightened answer is feasible but not proven closest */
        }
        if (!(v > 0) || !heed_clock) break;
        /* Bisection toward a feasible anchor: the warm start, else the nominal pose. */
        if (x0) {
            for (int i = 0; i < 6; ++i) anchor[i] = pb->w[i] > 0 && isfinite(x0[i]) ? x0[i] : 0;
            have = violation(st, pb, anchor, NULL) == 0;
        }
        if (!have) {
            memset(anchor, 0, sizeof anchor);
            have = violation(st, pb, anchor, NULL) == 0;
        }
        if (have) memcpy(rho_a, st->rho, sizeof rho_a);
        /* Neither is feasible (a reading at a limit, a start the windows moved off): the
         * rounds the clock cut short are the last chance before the safe output, so they
         * run whatever the clock (at most RT_RESTORE_ROUNDS in all). */
        if (have) break;
    }
    if (v > 0) {
        if (!have) {
            r->status = HP_STATUS_SOLVER_ERROR;
            rt_count_flush(st);
            return hp_diag_set(d, HP_ERR_SOLVER,
                               "realtime SQP: no feasible point found for the restoration");
        }
        double lo = 0, hi = 1, xt[6];
        /* Stopped by time: the fraction of the segment anchor -> xk at which each violated
         * radius, interpolated linearly between its two ends, meets its limit, the least of
         * them shrunk by RT_LATE_SHRINK for the curvature, tried first: one contact
         * evaluation where the bisection's three find the fraction to an eighth. Kept only
         * when that point is inside every limit (measured, not interpolated); else the
         * bisection below it. Without a stop by time the bisection alone, as always. */
        int path = st->late ? atomic_load_explicit(&rt_late_path, memory_order_relaxed)
                            : HP_TEST_LATE_AS_BUILT;
        if (st->late && have_rho_x && path == HP_TEST_LATE_AS_BUILT) {
            double t = 1.0;
            for (int k = 0; k < pb->n; ++k) {
                double den = rho_x[k] - rho_a[k];
                if (rho_x[k] > pb->ro_hi[k]) t = fmin(t, (pb->ro_hi[k] - rho_a[k]) / den);
                else if (rho_x[k] < pb->ro_lo[k]) t = fmin(t, (pb->ro_lo[k] - rho_a[k]) / den);
            }
            t *= RT_LATE_SHRINK;
            if (t > 0 && t < 1) {
                for (int i = 0; i < 6; ++i) xt[i] = anchor[i] + t * (xk[i] - anchor[i]);
                if (violation(st, pb, xt, NULL) == 0) {
                    lo = t;
                    rho_fresh = 1; /* st->rho is rho of that point, the answer below */
                } else {
                    hi = t;
                }
            }
        }
        const int steps = path == HP_TEST_LATE_ANCHOR ? 0 : RT_BISECT_STEPS;
        for (int it = 0; it < steps && !rho_fresh; ++it) {
            /* Every 4 steps (each a contact evaluation) the clock, first after three: lo is
             * feasible at every step, so stopping anywhere is safe, and three steps find the
             * feasible fraction of a step the budget cut to within an eighth (stopping at
             * once kept none of it: the anchor, where the plan started). */
            if (it % 4 == 3 && rt_late(st)) break;
            double mid = 0.5 * (lo + hi);
            for (int i = 0; i < 6; ++i) xt[i] = anchor[i] + mid * (xk[i] - anchor[i]);
            if (violation(st, pb, xt, NULL) == 0) {
                lo = mid;
                memcpy(rho_a, st->rho, sizeof rho_a); /* rho at the feasible end */
            } else {
                hi = mid;
            }
        }
        for (int i = 0; i < 6; ++i) xk[i] = anchor[i] + lo * (xk[i] - anchor[i]);
        /* The feasible end's radii, measured at these very bits (the same expression; at lo
         * = 0 the anchor's, the same value): the answer's, without evaluating there again. */
        if (!rho_fresh) {
            memcpy(st->rho, rho_a, sizeof rho_a);
            rho_fresh = 1;
            ++*(lo > 0 ? &st->cnt.bisect_kept : &st->cnt.bisect_anchor);
        }
        r->converged = 0;
    }
    r->iterations = iters;
    if (st->late) { /* the budget stopped some step: the answer is the feasible point reached */
        st_out = HP_STATUS_TIME_LIMIT;
        r->converged = 0;
    }
    if (!r->converged && st_out == HP_STATUS_CLOSEST && pb->level != HP_LEVEL_LINEAR)
        st_out = HP_STATUS_ITERATION_LIMIT;
    r->status = st_out;
    /* Pose and the inner radii that keep contact with it (rho(xk) is in st->rho when the
     * answer is the point the violation was measured at). */
    if (!((rho_at_xk && isfinite(v)) || rho_fresh) &&
        rt_contact(st, pb, xk, st->rho, NULL, NULL, NULL) != HP_OK) {
        r->status = HP_STATUS_SOLVER_ERROR;
        rt_count_flush(st);
        return hp_diag_set(d, HP_ERR_SOLVER, "realtime: contact model failed at the answer");
    }
    rt_inject(st, pb->n, st->rho);
    for (int i = 0; i < 6; ++i) x[i] = xk[i];
    memcpy(st->x_last, xk, sizeof st->x_last);
    memcpy(r->rho, st->rho, sizeof r->rho);
    r->has_rho = 1;
    for (int k = 0; k < pb->n; ++k) r->has_rho &= isfinite(st->rho[k]) != 0;
    /* With the distances handed back the core derives every radius from them (problem.h):
     * inverting the volume law here too would cost eight root finds a plan for nothing. */
    for (int k = 0; k < pb->n; ++k) {
        double ri = NAN;
        if (!r->has_rho &&
            hp_iab_ri(&pb->layout->bladders[k].iab, st->rho[k] / HP_MM_PER_M, &ri) != HP_OK)
            ri = NAN;
        x[6 + k] = ri * HP_MM_PER_M;
    }
    rt_count_flush(st);
    return HP_OK;
}

/* The load level's HOLD with its own bounded SQP tie-breaker (load_solve.c); no solver code
 * of its own, so raw is left alone. */
static hpi_load_solve_status rt_load_hold(const hp_load_model *M, const double xi[6],
                                          const double *lo, const double *hi, const double *target,
                                          const double *start, int max_iter, int stiffness,
                                          double *P, double *F, int *iterations, int *raw)
{
    (void)stiffness; /* not in caps: hp_planner_create refuses it */
    (void)raw;
    return hpi_load_hold(M, xi, lo, hi, target, start, max_iter, P, F, iterations);
}

const hp_backend_ops hpi_backend_realtime_ops = {
    .name = "realtime",
    .caps = HP_BACKEND_CERTIFIES | HP_BACKEND_THREAD_SAFE | HP_BACKEND_REAL_TIME |
            HP_BACKEND_WARM_STARTS | HP_BACKEND_LOAD | HP_BACKEND_LAZY_RATE,
    .load_hold = rt_load_hold,
    .load_hold_keep = hpi_load_hold_keep,
    .create = rt_create,
    .solve = rt_solve,
    .destroy = rt_destroy,
    .warm_point = rt_warm_point,
    .reading = rt_reading,
};
