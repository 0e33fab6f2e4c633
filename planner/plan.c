/* hp_plan: validate -> direct chain -> solve -> accept -> label, each a step of its own.
 * Every answer passes the checks of hp_planner.h before it is returned; anything else is
 * labelled and carries the safe output. Allocation-free (messages via plan_text.c). */
#include "planner/planner_internal.h"
#include "iab/iab_internal.h"
#include "common/unconst.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

static const char *const pose_names[6] = {"x", "y", "z", "pitch", "roll", "yaw"};

/* One plan's working state, passed between the steps. */
typedef struct plan_ctx {
    double t0;       /* hp_plan's start [s] */
    double xc[6];    /* the commanded part of the desired correction (SI) */
    double unc[6];   /* the rest: what the layout cannot observe (SI) */
    const double *x; /* the answer's scaled point (pose, radii) */
    int direct;      /* 1: the direct chain answered, no backend ran */
    int converged;   /* the backend claims a (local) optimum */
    hp_status st;    /* the backend's status */
    int raw, iters;  /* the backend's raw code and iterations */
    double clamp_mm; /* largest radius moved back into its limits */
    /* The distances at c->x [mm]: the direct chain's, or the backend's own (has_rho). */
    double rho[HP_MAX_BLADDERS];
    int has_rho;
    /* The backend's last linearisation point, a rounding-level step from c->x, with the
     * model there (hp_backend_result's lin_*): the round trip's anchor with a Jacobian. */
    int has_lin;
    double lin_x[6], lin_rho[HP_MAX_BLADDERS], lin_J[HP_MAX_BLADDERS * 6];
    int held;          /* every bladder's window is a point: the previous answer, held */
    int warm;          /* the backend started from the previous answer */
    int unconfirmed;   /* label refused a CLOSEST answer its round trip did not confirm */
    int rate_deferred; /* the bounds are the static ones; the rate bounds are not solved yet */
} plan_ctx;

/* The safe output: the previous valid answer, labelled with a failure status (the message
 * is already in p->err). */
static hp_error fail_safe(hp_planner *p, hp_result *res, hp_status st, const plan_ctx *c)
{
    /* A reading's answer, derived now (or dropped, said after the cause in p->err). */
    (void)hpi_plan_measured_derive(p);
    double desired[6];
    memcpy(desired, res->desired, sizeof desired);
    *res = p->prev;
    memcpy(res->desired, desired, sizeof desired);
    res->status = st;
    res->raw_code = c ? c->raw : res->raw_code;
    res->iterations = c ? c->iters : 0;
    res->pose_error = INFINITY;
    for (int i = 0; i < 6; ++i) res->uncommanded[i] = 0.0;
    for (int k = 0; k < res->n; ++k) res->bladders[k].binding = 0;
    p->note[0] = '\0';
    p->note_pending = 0;
    res->solve_time = hpi_plan_now() - (c ? c->t0 : res->solve_time);
    return HP_OK;
}

/* The previous answer's radii and pose, for a step that starts from them: a reading of
 * set_measured is derived here when pending. Returns 1, or 0 with res labelled (the
 * reading has no radius or pose: dropped, the safe output the answer before it). */
static int previous_ready(hp_planner *p, hp_result *res, plan_ctx *c)
{
    if (hpi_plan_measured_derive(p) == HP_OK) return 1;
    hpi_text_add(p->err, "; holding the previous pressures");
    fail_safe(p, res, HP_STATUS_INVALID_INPUT, c);
    return 0;
}

/* The previous answer as a solve's start (x_prev): a pending reading is derived only when
 * that answer is no feasible start for the reading's windows (hpi_plan_measured_start_ok).
 * Otherwise the last plan's pose and radii, already known, start the solve: the reading's
 * own answer would only be another start, and the answer reached from either passes the
 * same checks (limits and rate windows exact, the round trip). Returns 1, or 0 with res
 * labelled as previous_ready. */
static int start_ready(hp_planner *p, hp_result *res, plan_ctx *c)
{
    return hpi_plan_measured_start_ok(p) || previous_ready(p, res, c);
}

/* "STATUS: the BACKEND backend did not converge within solver.max_iter = N iterations" (or
 * max_time_s = T s): the budget that stopped it, so that a caller knows what to raise; the
 * command line, batch and Python all print this one text. */
static void add_budget(const hp_planner *p, char *buf, hp_status st)
{
    hpi_text_set(buf, hp_status_name(st));
    hpi_text_add(buf, ": the ");
    hpi_text_add(buf, hp_backend_name(p->s.backend));
    hpi_text_add(buf, " backend did not converge within solver.");
    if (st == HP_STATUS_TIME_LIMIT) {
        /* The fewest decimals that give the budget back (0.05 as "0.05"), at most 9. */
        int dec = 0;
        double scale = 1.0;
        while (dec < 9 && fabs(nearbyint(p->s.max_time * scale) - p->s.max_time * scale) >
                              1e-9 * p->s.max_time * scale) {
            ++dec;
            scale *= 10.0;
        }
        hpi_text_add(buf, "max_time_s = ");
        hpi_text_add_num(buf, p->s.max_time, dec);
        hpi_text_add(buf, " s");
    } else {
        hpi_text_add(buf, "max_iter = ");
        hpi_text_add_int(buf, p->s.max_iter);
        hpi_text_add(buf, " iterations");
    }
}

/* "BACKEND: STATUS (raw code N)" into p->err, the start of every backend failure; for a
 * budget that ran out, add_budget's text in place of "BACKEND: STATUS". */
static void err_backend(hp_planner *p, hp_status st, int raw)
{
    if (st == HP_STATUS_ITERATION_LIMIT || st == HP_STATUS_TIME_LIMIT) {
        add_budget(p, p->err, st);
    } else {
        hpi_text_set(p->err, p->ops->name);
        hpi_text_add(p->err, ": ");
        hpi_text_add(p->err, hp_status_name(st));
    }
    hpi_text_add(p->err, " (raw code ");
    hpi_text_add_int(p->err, raw);
    hpi_text_add(p->err, ")");
}

/* The plan's label when this cycle's rate bounds cannot be solved (safe output). */
static int rate_failed(hp_planner *p, hp_result *res, plan_ctx *c)
{
    hpi_text_set(p->err, "the rate limits leave no radius inside the pressure and stretch "
                         "limits");
    fail_safe(p, res, HP_STATUS_INFEASIBLE_START, c);
    return 0;
}

/* 1 when this plan's rate windows are those of the last plan that set rate bounds, bit for
 * bit (the same centres p_prev and limits), and they become the last ones. */
static int same_windows(hp_planner *p)
{
    int same = p->rate_last_ok;
    for (int k = 0; k < p->L.n; ++k) {
        double P = p->pb.p_prev[k], rate = p->L.bladders[k].rate_max;
        same &= memcmp(&P, &p->rate_last_P[k], sizeof P) == 0 &&
                memcmp(&rate, &p->rate_last_rate[k], sizeof rate) == 0;
        p->rate_last_P[k] = P;
        p->rate_last_rate[k] = rate;
    }
    p->rate_last_ok = 1;
    return same;
}

/* The plan's bounds, and with marks its stand-in marks, into m (to_kept), or back. Whole
 * arrays, HP_MAX_BLADDERS long: copies of a size known at compile time are a few vector
 * moves each, where copies of n bladders' were library calls (about 100 instructions more
 * a copy). */
static void copy_bounds(hp_planner *p, hp_rate_kept *m, int to_kept, int marks)
{
    hp_problem *pb = &p->pb;
    hp_rate_lazy *z = &p->rate_lazy;
#define HP_KEPT_COPY(kept, plan)                                                                   \
    memcpy(to_kept ? (void *)(kept) : (void *)(plan), to_kept ? (void *)(plan) : (void *)(kept),   \
           sizeof(kept))
    HP_KEPT_COPY(m->ri_lo, pb->ri_lo);
    HP_KEPT_COPY(m->ri_hi, pb->ri_hi);
    HP_KEPT_COPY(m->ro_lo, pb->ro_lo);
    HP_KEPT_COPY(m->ro_hi, pb->ro_hi);
    HP_KEPT_COPY(m->ri_lo_si, pb->ri_lo_si);
    HP_KEPT_COPY(m->ri_hi_si, pb->ri_hi_si);
    HP_KEPT_COPY(m->lo_flags, p->lo_flags);
    HP_KEPT_COPY(m->hi_flags, p->hi_flags);
    if (marks) {
        HP_KEPT_COPY(m->lo, z->lo);
        HP_KEPT_COPY(m->hi, z->hi);
    }
#undef HP_KEPT_COPY
}

/* The plan's bounds and stand-in marks into p->rate_kept (to_kept), or back from it. */
static void copy_kept(hp_planner *p, int to_kept) { copy_bounds(p, &p->rate_kept, to_kept, 1); }

/* After a plan that set its bounds with stand-ins: those bounds as the plan left them, for
 * the next plan with the same windows (rate_bounds). Ends it resolved are exact, the others
 * still stand-ins strictly inside theirs, so they are a valid lazy start for the same
 * windows; not when a resolve failed (that plan failed, and so will the next). Kept only
 * when the next plan's centres, this answer's pressures, are this plan's (a held answer):
 * a plan that moved, or a measured reading, sets other windows, and copying for them cost
 * every such plan 170 instructions. */
static void keep_rate_bounds(hp_planner *p)
{
    if (!p->rate_live) return;
    p->rate_live = 0;
    int held = !p->rate_lazy.failed;
    for (int k = 0; k < p->L.n && held; ++k)
        held = memcmp(&p->pb.p_prev[k], &p->rate_last_P[k], sizeof p->rate_last_P[k]) == 0;
    p->rate_kept_ok = held;
    if (held) copy_kept(p, 1);
}

/* This cycle's bounds: the static ones intersected with the rate windows around the
 * previous pressures. For a backend that resolves window ends itself
 * (HP_BACKEND_LAZY_RATE) the ends are stand-ins until a point of the plan comes near one
 * (problem_setup.h, hp_rate_lazy; p->pb.lazy); for the others every end is solved here.
 * Returns 1, or 0 with res labelled (safe output). */
static int rate_bounds(hp_planner *p, hp_result *res, plan_ctx *c)
{
    c->rate_deferred = 0;
    hp_error e = HP_OK;
    p->pb.lazy = NULL;
    int lazy = hpi_setup_rate_lazy() && (p->ops->caps & HP_BACKEND_LAZY_RATE);
    hp_rate_lazy *z = &p->rate_lazy;
    /* Windows that are the last plan's, bit for bit (a plan holding its answer): that
     * plan's bounds as it left them (keep_rate_bounds), the ends it needed exact and the
     * others its stand-ins, and one stand-in more made exact. Setting them up again would
     * cost more, and solving every end it never needed at once (15 on the loop benchmark's
     * step trace) made the first held plan the slowest of the trace; one a plan, a hold
     * of a few plans has them all when the target moves (a step from a held answer comes
     * near most ends). The eager bounds of such windows come from the memo (no solve after
     * the first). */
    int same = same_windows(p);
    p->rate_live = 0;
    if (lazy && same && p->rate_kept_ok) {
        copy_kept(p, 0);
        z->failed = 0;
        p->rate_live = 1;
        for (int k = 0; k < p->L.n; ++k)
            if (z->lo[k] || z->hi[k]) {
                if (!hpi_setup_rate_resolve(z, k, z->lo[k] ? 1u : 2u)) e = HP_ERR_INVALID;
                break;
            }
    } else if (lazy) {
        p->rate_kept_ok = 0;
        *z = (hp_rate_lazy){.L = &p->L,
                            .b = &p->sb,
                            .memo = &p->rate_memo,
                            .stand = &p->rate_stand,
                            .pb = &p->pb,
                            .lo_flags = p->lo_flags,
                            .hi_flags = p->hi_flags};
        e = hpi_setup_cycle_bounds_lazy(z, NULL);
        p->rate_live = e == HP_OK;
    } else {
        p->rate_kept_ok = 0;
        e = hpi_setup_cycle_bounds_memo(&p->L, &p->sb, p->pb.p_prev, p->s.use_rate_limits,
                                        &p->rate_memo, &p->pb, p->lo_flags, p->hi_flags, NULL);
    }
    if (p->rate_live && hpi_setup_rate_pending(z)) p->pb.lazy = z;
    return e == HP_OK ? 1 : rate_failed(p, res, c);
}

/* Before the plan's answer is taken from its point: every window end still a stand-in that
 * the answer's radii (c->rho) do not lie clearly inside (twice the binding tolerance, so
 * that the binding flags and the radius clamps decide as with the exact bound) is
 * resolved, every one when the radii are not known. Returns 1, or 0 with res labelled
 * when a resolved end (here or in the backend) had no stable radius. */
static int rate_settle(hp_planner *p, hp_result *res, plan_ctx *c)
{
    hp_rate_lazy *z = p->pb.lazy;
    if (!z) return 1;
    if (c->direct || c->has_rho) {
        hpi_setup_rate_touch(z, c->rho, p->L.n, 2.0 * HP_BINDING_TOL_MM);
    } else {
        for (int k = 0; k < p->L.n; ++k) hpi_setup_rate_resolve(z, k, 3u);
    }
    return z->failed ? rate_failed(p, res, c) : 1;
}

/* Step 1: the request. Checks desired (finite, in range, identifiable), splits it into the
 * commanded part and the rest, and sets this cycle's bounds. Returns 1 to go on, else 0
 * with res labelled (safe output). */
static int validate(hp_planner *p, const double desired[6], hp_result *res, plan_ctx *c)
{
    for (int i = 0; i < 6; ++i) res->desired[i] = desired[i];
    if (!hpi_plan_desired_ok(&p->id, desired, p->err)) {
        fail_safe(p, res, HP_STATUS_INVALID_INPUT, c);
        return 0;
    }
    /* The commanded part: what the layout can observe of the desired correction, in the
     * commanded components; the rest is reported, never silently dropped. */
    if (hpi_pose_commanded_part_g(&p->L, &p->G, &p->id, p->level, desired, c->xc) != HP_OK) {
        hpi_text_set(p->err, "desired: the contact model cannot evaluate this correction (a "
                             "bladder centre would lie deep inside the head)");
        fail_safe(p, res, HP_STATUS_INVALID_INPUT, c);
        return 0;
    }
    for (int i = 0; i < 6; ++i) c->unc[i] = desired[i] - c->xc[i];
    hp_problem *pb = &p->pb;
    pb->lazy = NULL;
    hpi_plan_to_scaled(c->xc, pb->d);
    for (int i = 0; i < 6; ++i)
        if (!p->commanded[i]) pb->d[i] = 0.0;
    /* Without a rate limit the bounds are those create set (rate_free). With one, the
     * static bounds first: most plans of a control loop end in the direct chain with every
     * pressure well inside its rate window, and then the rate limits' radius bounds (two
     * pressure -> radius solves a bladder) change nothing (rate_bounds). */
    if (p->rate_free) return 1;
    /* The windows, once a plan (the start check, the bounds and the answer read them). */
    hpi_setup_rate_windows(&p->L, pb);
    if (!hpi_setup_rate_lazy()) return rate_bounds(p, res, c);
    /* The static bounds from the image the first plan took of them: the same bits, copied
     * in a few vector moves where setting them up bladder by bladder cost each plan 283
     * instructions (callgrind, the loop benchmark's step trace; with the copy the
     * rate-limited median there is 155 lower, 12 559 -> 12 404, bench/loop_tail.sh). A
     * set-up that failed (a volume law that gave no outer radius) is not kept: the next
     * plan sets them up again. */
    if (p->static_kept_ok) {
        copy_bounds(p, &p->static_kept, 0, 0);
    } else if (hpi_setup_cycle_bounds(&p->L, &p->sb, NULL, 0, pb, p->lo_flags, p->hi_flags, NULL) ==
               HP_OK) {
        copy_bounds(p, &p->static_kept, 1, 0);
        p->static_kept_ok = 1;
    }
    c->rate_deferred = 1;
    return 1;
}

/* Step 2: the direct chain. 1 when every limit holds at the commanded part itself: then it
 * is the exact answer and no solver runs. */
static int direct_chain(hp_planner *p, plan_ctx *c)
{
    const hp_problem *pb = &p->pb;
    int inside = 0;
    /* The Jacobian only where a round trip follows (the linear level skips it). */
    double *J = p->level == HP_LEVEL_LINEAR ? NULL : p->chain_J;
    return hpi_setup_contact_inside(&p->L, &p->G, p->level, pb->d, pb->ro_lo, pb->ro_hi, c->rho, J,
                                    &inside) == HP_OK &&
           inside;
}

static atomic_int look_mode; /* hpi_test_plan_look */
void hpi_test_plan_look(int mode) { atomic_store(&look_mode, mode); }

/* 1 when the previous answer did not reach its target (held back by the rate windows, on
 * the walk toward a target after a jump), or the commanded target (p->pb.d) lies more than
 * HP_TARGET_FAR (mm, deg) from that answer's pose in some component (a jump). Otherwise (a
 * breathing trace moves by 0.3 mm a plan or less) the direct answer's pressures are rarely
 * beyond a rate window. Only a cost choice: whatever it says, the plan's answer is the
 * same. */
#define HP_TARGET_FAR 0.5
static int target_far(const hp_planner *p)
{
    if (p->prev.status != HP_STATUS_REACHED && p->prev.status != HP_STATUS_UNCOMMANDED) return 1;
    double a[6];
    hpi_plan_to_scaled(p->prev.achieved, a);
    for (int i = 0; i < 6; ++i)
        if (fabs(p->pb.d[i] - a[i]) > HP_TARGET_FAR) return 1;
    return 0;
}

/* Step 3a: 1 when the rate limits leave every bladder a window of outer radii no wider than
 * HP_BINDING_TOL_MM (a limit of about 1 mPa per plan or less): any answer binds every
 * bladder, and holding the previous pressures, around which the windows are centred, is
 * one. No backend resolves such windows (n contact equalities in 6 pose unknowns, each
 * to within the window: Ipopt's restoration and the realtime QP find no feasible point,
 * NLopt's answers hold no pose), so none runs. */
static int rate_pinned(const hp_planner *p)
{
    if (p->rate_free) return 0;
    for (int k = 0; k < p->L.n; ++k)
        if (!(p->pb.ro_hi[k] - p->pb.ro_lo[k] <= HP_BINDING_TOL_MM)) return 0;
    return 1;
}

/* Step 3b: the answer of a pinned plan: the previous answer's pose and outer radii, which
 * accept turns into pressures inside this cycle's windows (the previous ones, to within
 * the allowance) and label calls reached or closest (binding the rate limits) after the
 * round trip every answer passes. Pressures that hold no pose (hp_planner_set_previous
 * takes any inside the limits; its pose is a least-squares fit) are held by no answer
 * either: refused as accept refuses clamped radii, by the residual HP_CLAMP_RESID_MM.
 * Returns 1 with c set, or 0 with res labelled (safe output). */
static int hold(hp_planner *p, hp_result *res, plan_ctx *c)
{
    if (!previous_ready(p, res, c)) return 0;
    double rho[HP_MAX_BLADDERS], ss = 0.0;
    if (hpi_setup_contact_scaled(&p->L, &p->G, p->level, p->x_prev, rho, NULL) != HP_OK)
        ss = INFINITY;
    for (int k = 0; k < p->L.n; ++k) {
        c->rho[k] = p->prev.bladders[k].ro * HP_MM_PER_M;
        ss += (rho[k] - c->rho[k]) * (rho[k] - c->rho[k]);
    }
    double resid = sqrt(ss / p->L.n);
    if (!(resid <= HP_CLAMP_RESID_MM)) {
        hpi_text_set(p->err, "the rate limits hold every bladder at its previous pressure, and "
                             "those pressures hold no pose at the ");
        hpi_text_add(p->err, hp_level_name(p->level));
        hpi_text_add(p->err, " level (contact residual ");
        hpi_text_add_num(p->err, resid, 9);
        hpi_text_add(p->err, " mm RMS); holding the previous pressures");
        fail_safe(p, res, HP_STATUS_INFEASIBLE_START, c);
        return 0;
    }
    memcpy(p->x_work, p->x_prev, sizeof(double) * (size_t)p->pb.nx);
    c->x = p->x_work;
    c->has_rho = 1;
    c->has_lin = 0;
    c->converged = 1;
    c->st = HP_STATUS_REACHED;
    c->raw = 0;
    c->iters = 0;
    return 1;
}

/* Step 3: the backend, through its table, from the previous answer (warm) or a cold point.
 * Returns 1 with c->x set, or 0 with res labelled (the backend failed: safe output). */
static int solve(hp_planner *p, hp_result *res, plan_ctx *c, int cold)
{
    hp_backend_result br = {.status = HP_STATUS_SOLVER_ERROR};
    const double *x0 = p->x_prev;
    double xcold[HP_PROBLEM_NX_MAX];
    if (!p->s.warm_start || cold) {
        for (int i = 0; i < 6; ++i) xcold[i] = 0.0;
        for (int k = 0; k < p->L.n; ++k) xcold[6 + k] = p->L.bladders[k].iab.Ri * HP_MM_PER_M;
        x0 = xcold;
    }
    c->warm = x0 == p->x_prev;
    if (c->warm && !start_ready(p, res, c)) return 0;
    p->diag.text[0] = '\0';
    hp_error e = p->ops->solve(p->bstate, &p->pb, x0, p->x_work, &br, &p->diag);
    if (br.status == HP_STATUS_INFEASIBLE_START && x0 != p->x_prev) {
        /* A cold start's first linearisation can be empty (rate windows far from the
         * nominal pose) while the program is feasible: the previous answer meets this
         * cycle's rate windows, which are centred on its pressures. Try from there before
         * calling the limits contradictory. */
        if (!start_ready(p, res, c)) return 0;
        hp_backend_result b2 = {.status = HP_STATUS_SOLVER_ERROR};
        p->diag.text[0] = '\0';
        e = p->ops->solve(p->bstate, &p->pb, p->x_prev, p->x_work, &b2, &p->diag);
        b2.iterations += br.iterations;
        br = b2;
    }
    c->raw = br.raw_code;
    c->iters = br.iterations;
    /* A backend may also report a failure through its status with HP_OK (Ipopt and NLopt do
     * for a failed solve, handing back their start point): that point is no answer, so it
     * must not be relabelled as an iteration limit. */
    if (e != HP_OK || br.status == HP_STATUS_SOLVER_ERROR ||
        br.status == HP_STATUS_INFEASIBLE_START || br.status == HP_STATUS_INVALID_INPUT) {
        /* The backend's own label, except that a failed call never claims success. */
        hp_status fs = br.status;
        if (fs == HP_STATUS_REACHED || fs == HP_STATUS_CLOSEST || fs == HP_STATUS_UNCOMMANDED ||
            (int)fs < 0 || fs >= HP_STATUS_COUNT_)
            fs = HP_STATUS_SOLVER_ERROR;
        err_backend(p, fs, br.raw_code);
        if (e != HP_OK && p->diag.text[0]) {
            hpi_text_add(p->err, ": ");
            hpi_text_add(p->err, p->diag.text);
        }
        hpi_text_add(p->err, "; holding the previous pressures");
        fail_safe(p, res, fs, c);
        return 0;
    }
    double x_backend[6];
    memcpy(x_backend, p->x_work, sizeof x_backend);
    for (int i = 0; i < 6; ++i)
        if (!p->commanded[i]) p->x_work[i] = 0.0;
    c->x = p->x_work;
    c->converged = br.converged;
    c->st = br.status;
    c->has_rho = br.has_rho;
    for (int i = 0; i < 6; ++i) c->has_rho &= p->commanded[i] || x_backend[i] == 0.0;
    if (c->has_rho) memcpy(c->rho, br.rho, sizeof c->rho);
    /* Only in the fit's space (the components not commanded at the nominal pose's 0). */
    c->has_lin = c->has_rho && br.has_lin;
    for (int i = 0; i < 6; ++i) c->has_lin &= p->commanded[i] || br.lin_x[i] == 0.0;
    if (c->has_lin) {
        memcpy(c->lin_x, br.lin_x, sizeof c->lin_x);
        memcpy(c->lin_rho, br.lin_rho, sizeof c->lin_rho);
        memcpy(c->lin_J, br.lin_J, sizeof c->lin_J);
    }
    return 1;
}

/* Step 4: the answer at the point c->x: radii and pressures inside this cycle's limits; a
 * backend's radii moved back into their limits hold a slightly different pose, found by
 * forward contact kinematics (not real time). Returns 1, or 0 with res labelled. */
static int accept(hp_planner *p, hp_result *r, plan_ctx *c)
{
    /* The direct chain's answer is the pose it just evaluated, and a backend may hand back
     * its distances at its answer: no second evaluation. */
    if (!hpi_plan_answer_from_pose(p, c->x, c->direct || c->has_rho ? c->rho : NULL,
                                   c->direct && c->rate_deferred, r, &c->clamp_mm)) {
        hpi_text_set(p->err, "the answer was not finite or left a limit: holding the previous "
                             "pressures");
        fail_safe(p, r, HP_STATUS_SOLVER_ERROR, c);
        return 0;
    }
    if (!(c->clamp_mm > 1e-9)) return 1;
    double ro[HP_MAX_BLADDERS], xi[6], resid, xs[6];
    for (int k = 0; k < p->L.n; ++k) ro[k] = r->bladders[k].ro;
    hpi_plan_from_scaled(c->x, xs);
    /* Radii that no pose holds (a backend that stopped at an infeasible point, e.g. under
     * rate limits that cannot all hold) are no answer: the fitted pose would not be where
     * the head goes. */
    if (hpi_contact_fk_g(&p->L, &p->G, p->level, ro, xs, xi, &resid, NULL) != HP_OK ||
        !(resid * HP_MM_PER_M <= HP_CLAMP_RESID_MM)) {
        /* A budget that ran out before a feasible iterate keeps its label. */
        hp_status fs = (c->st == HP_STATUS_ITERATION_LIMIT || c->st == HP_STATUS_TIME_LIMIT)
                           ? c->st
                           : HP_STATUS_SOLVER_ERROR;
        err_backend(p, fs, c->raw);
        hpi_text_add(p->err, ": the backend's radii, clamped into the limits, hold no pose; "
                             "holding the previous pressures");
        fail_safe(p, r, fs, c);
        return 0;
    }
    for (int i = 0; i < 6; ++i) r->achieved[i] = p->commanded[i] ? xi[i] : 0.0;
    c->converged = 0;
    return 1;
}

/* Whether a backend's claimed optimum x (scaled, full program) meets the first-order
 * optimality conditions: contacts within max(10·tolerance, 1e-6) mm, radii inside their
 * bounds, stationarity and multiplier signs within 1e-3 of the gradient's scale. A backend
 * that certifies its own optimum (HP_BACKEND_CERTIFIES: Ipopt's KKT test, the realtime QP's
 * multiplier signs) is not re-checked; NLopt's stopping tests (XTOL, FTOL) say nothing
 * about optimality. The check uses the minimum-norm multipliers, so at a degenerate vertex
 * it can refuse a true optimum: then the answer is labelled solver-error, never wrong. */
static int closest_verified(const hp_planner *p, const double *x)
{
    if (p->ops->caps & HP_BACKEND_CERTIFIES) return 1;
    return hpi_backend_first_order_ok(&p->pb, x, p->s.tolerance);
}

/* 1 when the strict round trip of answer r gives back achieved, its achieved pose
 * (r->achieved; not the commanded target c->xc, from which a REACHED answer may lie up to the
 * tolerance), to HP_IDENT_FK_TOL: its pressures -> stable radii -> outer radii -> forward
 * contact kinematics in the commanded components started from the NOMINAL pose. t says
 * where the fit ended (hp_plan_trip). On a near-degenerate layout the fit from the nominal
 * pose can end at another pose with the same distances, or stall in a second local fit;
 * then the answer is not identified by this layout. Allocates nothing. */
int hpi_plan_round_trip(const hp_planner *p, const hp_result *r, const double achieved[6],
                        const hp_plan_anchor *anchor, hp_plan_trip *t)
{
    t->worst = 0.0;
    t->gap_mm = 0.0;
    memcpy(t->end, achieved, sizeof t->end);
    /* The linear model is linear in the pose and the commanded columns have full column
     * rank (hp_layout_identify keeps exactly `rank` of them): the least-squares fit is
     * unique, so the fit from the nominal pose is the commanded part itself, to rounding.
     * The check would cost ~50 us of a ~10 us plan and could not fail. */
    if (p->level == HP_LEVEL_LINEAR) return 1;
    double ro[HP_MAX_BLADDERS], xf[6], a[6], b[6];
    for (int k = 0; k < p->L.n; ++k) {
        double ri;
        /* Started at the answer's own stable radius: the root of its pressure is unique on
         * the stable branch, so the start changes the steps, never what is verified. */
        if (hpi_iab_s_fk_limit_warm_ro(&p->sb.iab_s[k], &p->sb.limit[k], r->bladders[k].pressure,
                                       r->bladders[k].ri, &ri, &ro[k]) != HP_OK)
            ro[k] = r->bladders[k].ro;
    }
    double resid = INFINITY;
    /* The fit may stop once it has provably arrived at achieved (hpi_kin_fit): the last two or
     * three of its ~5 steps only polish digits far below HP_IDENT_FK_TOL. A fit that heads
     * anywhere else runs to its end exactly as before. */
    hp_kin_fit_near near;
    for (int i = 0; i < 6; ++i) {
        near.pose[i] = achieved[i];
        near.tol[i] = HP_IDENT_FK_TOL / (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD);
    }
    /* The answer's point and the distances evaluated there (the direct chain's, or the
     * backend's own), and for the direct chain its Jacobian there: with them the fit may
     * stop as soon as a certificate proves where it ends (hpi_kin_fit_certified), with the
     * Jacobian usually before it evaluates its first step. */
    near.has_anchor = anchor != NULL;
    near.anchor_J = anchor ? anchor->J : NULL;
    near.anchor_J_err = anchor ? anchor->J_err : 0.0;
    if (anchor) {
        hpi_plan_from_scaled(anchor->x, near.anchor);
        for (int k = 0; k < p->L.n; ++k) near.anchor_rho[k] = anchor->rho_mm[k] / HP_MM_PER_M;
    }
    hp_error e = hpi_plan_fit_from_nominal(p, ro, p->commanded, &near, xf, &resid);
    hpi_plan_to_scaled(achieved, a);
    hpi_plan_to_scaled(xf, b);
    double w = e == HP_OK ? 0.0 : INFINITY;
    for (int i = 0; i < 6; ++i) w = fmax(w, fabs(a[i] - b[i]));
    t->worst = w;
    memcpy(t->end, xf, sizeof t->end);
    if (w <= HP_IDENT_FK_TOL) return 1;
    if (w <= HP_IDENT_SAME && resid * HP_MM_PER_M <= HP_IDENT_FIT_MM) return 1;
    /* A refusal names the pose only after checking it: the distances there, evaluated
     * afresh (not the fit's residual, an RMS), against the answer's outer radii. */
    double rho[HP_MAX_BLADDERS];
    t->gap_mm = INFINITY;
    if (e == HP_OK && hpi_contact_eval_g(&p->L, &p->G, p->level, xf, rho, NULL, NULL) == HP_OK) {
        t->gap_mm = 0.0;
        for (int k = 0; k < p->L.n; ++k)
            t->gap_mm = fmax(t->gap_mm, fabs(rho[k] - ro[k]) * HP_MM_PER_M);
        if (!isfinite(t->gap_mm)) t->gap_mm = INFINITY;
    }
    return 0;
}

/* hpi_plan_round_trip of answer r from plan c, with its message in p->err when it fails. */
static int recovered_from_nominal(hp_planner *p, const hp_result *r, const double achieved[6],
                                  const plan_ctx *c)
{
    hp_plan_anchor an = {c->x, c->rho, c->direct ? p->chain_J : NULL, 0.0};
    if (!c->direct && c->has_lin) {
        /* The backend's Jacobian is a rounding-level step old: its drift to c->x bounded. */
        double xa[6], rho_m[HP_MAX_BLADDERS], d2 = 0.0;
        hpi_plan_from_scaled(c->lin_x, xa);
        for (int k = 0; k < p->L.n; ++k) rho_m[k] = c->lin_rho[k] / HP_MM_PER_M;
        for (int i = 0; i < 6; ++i) d2 += (c->x[i] - c->lin_x[i]) * (c->x[i] - c->lin_x[i]);
        an.J = c->lin_J;
        an.J_err = hpi_kin_jacobian_drift(&p->L, &p->G, p->level, xa, rho_m, c->lin_J,
                                          sqrt(d2) * (1.0 + 1e-12));
    }
    hp_plan_trip t;
    if (hpi_plan_round_trip(p, r, achieved, c->direct || c->has_rho ? &an : NULL, &t)) return 1;
    hpi_text_set(p->err, r->status == HP_STATUS_CLOSEST
                             ? "desired: its closest reachable pose lies outside the identifiable "
                               "range of this layout at the "
                             : "desired: outside the identifiable range of this layout at the ");
    hpi_text_add(p->err, hp_level_name(p->level));
    hpi_text_add(p->err, " level: ");
    hpi_plan_trip_text(p->err, &t);
    return 0;
}

/* 1 when some bladder of r sits on a limit (HP_BINDING_TOL_MM). */
static int binds_any(const hp_result *r)
{
    for (int k = 0; k < r->n; ++k)
        if (r->bladders[k].binding) return 1;
    return 0;
}

/* 1 when some component of the part not commanded exceeds the pose tolerance (mm, deg). */
static int uncommanded_beyond(const hp_planner *p, const double unc[6])
{
    double u[6];
    hpi_plan_to_scaled(unc, u);
    for (int i = 0; i < 6; ++i)
        if (fabs(u[i]) > p->s.tolerance) return 1;
    return 0;
}

/* Names the components of the part not commanded beyond the tolerance, with values. */
static void add_uncommanded(const hp_planner *p, char *buf, const double unc[6])
{
    double u[6];
    hpi_plan_to_scaled(unc, u);
    hpi_text_add(buf, "not commanded (the layout cannot observe it):");
    int first = 1;
    for (int i = 0; i < 6; ++i) {
        if (!(fabs(u[i]) > p->s.tolerance)) continue;
        hpi_text_add(buf, first ? " " : ", ");
        hpi_text_add(buf, pose_names[i]);
        hpi_text_add(buf, " ");
        hpi_text_add_num(buf, u[i], 6);
        hpi_text_add(buf, i < 3 ? " mm" : " deg");
        first = 0;
    }
}

/* "STATUS: binding BLADDER LIMIT..., ..." (or "none") into buf, from each bladder's
 * HP_BIND_* flags. */
static void add_binding(const hp_planner *p, char *buf, hp_status st, const unsigned *binding)
{
    hpi_text_set(buf, hp_status_name(st));
    hpi_text_add(buf, ": binding");
    int any = 0;
    for (int k = 0; k < p->L.n; ++k) {
        if (!binding[k]) continue;
        hpi_text_add(buf, any ? ", " : " ");
        hpi_text_add(buf, p->L.bladders[k].name);
        for (int b = 0; b < HP_BIND_COUNT; ++b)
            if (binding[k] & (1u << b)) {
                hpi_text_add(buf, " ");
                hpi_text_add(buf, hp_binding_name(1u << b));
            }
        any = 1;
    }
    if (!any) hpi_text_add(buf, " none");
}

/* A CLOSEST answer's note: its binding limits, and when the backend solved from one start
 * only (p->note_local) that the answer is a local optimum another start may improve on. */
static void add_closest(const hp_planner *p, char *buf, const unsigned *binding)
{
    add_binding(p, buf, HP_STATUS_CLOSEST, binding);
    if (!p->note_local) return;
    hpi_text_add(buf, "; a local optimum: the ");
    hpi_text_add(buf, p->ops->name);
    hpi_text_add(buf, " backend made no restarts, and another start may end closer");
}

/* Step 5: the label. REACHED / UNCOMMANDED when the commanded part is met and the strict
 * round trip confirms it; CLOSEST when a certified or verified optimum binds a limit and
 * the same round trip confirms its pose;
 * ITERATION_LIMIT / TIME_LIMIT for a budget's last feasible iterate. Returns 1, or 0 with
 * res labelled (a claim the checks refute: safe output). */
static int label(hp_planner *p, hp_result *r, plan_ctx *c)
{
    int unc_any = uncommanded_beyond(p, c->unc);
    /* No answer leaves the identifiable range: a pose there is one the layout cannot tell
     * from another (a five-direction layout's closest answers reached 107 mm, beyond the
     * head's smallest semi-axis). A converged answer there is refused, as a desired pose
     * there is (a warm solve's is first tried again from the nominal pose); a budget's
     * iterate there is no usable iterate. */
    int budget = !(r->pose_error <= p->s.tolerance) && !c->converged;
    if (!hpi_plan_range_ok(&p->id, r->achieved,
                           budget ? "the last iterate's" : "desired: its closest reachable pose's",
                           p->err)) {
        if (budget) {
            char why[HP_DIAG_MAX];
            hpi_text_set(why, p->err);
            hp_status fs = c->st == HP_STATUS_TIME_LIMIT ? HP_STATUS_TIME_LIMIT
                                                         : HP_STATUS_ITERATION_LIMIT;
            add_budget(p, p->err, fs);
            hpi_text_add(p->err, "; ");
            hpi_text_add(p->err, why);
            hpi_text_add(p->err, "; holding the previous pressures");
            fail_safe(p, r, fs, c);
            return 0;
        }
        c->unconfirmed = 1;
        fail_safe(p, r, HP_STATUS_INVALID_INPUT, c);
        return 0;
    }
    if (r->pose_error <= p->s.tolerance) {
        r->status = unc_any ? HP_STATUS_UNCOMMANDED : HP_STATUS_REACHED;
        /* What is verified is the answer's own pose: with a tolerance above the round
         * trip's HP_IDENT_FK_TOL a REACHED answer may lie up to the tolerance from c->xc, and
         * the fit then rightly ends there, not at c->xc; that is no second pose. */
        if (!recovered_from_nominal(p, r, r->achieved, c)) {
            fail_safe(p, r, HP_STATUS_INVALID_INPUT, c);
            return 0;
        }
    } else if (c->converged && !c->held && !closest_verified(p, c->x)) {
        /* A backend that claims an optimum the first-order conditions refute (NLopt SLSQP
         * far beyond reach handed back its start point with XTOL_REACHED) gives no answer:
         * label it and hold, never report it as the closest correction. */
        err_backend(p, HP_STATUS_SOLVER_ERROR, c->raw);
        hpi_text_add(p->err, ": its claimed optimum fails the first-order (KKT) check; "
                             "holding the previous pressures");
        fail_safe(p, r, HP_STATUS_SOLVER_ERROR, c);
        return 0;
    } else if (c->converged && !binds_any(r)) {
        /* Nothing binds, so the first-order conditions say the optimum is the target: a
         * claimed optimum short of it is not the closest (Ipopt stops its interior point a
         * few 1e-6 mm inside a bound when the remaining pose error is tiny, because its
         * complementarity test scales with the multiplier). Label it, never CLOSEST. */
        err_backend(p, HP_STATUS_SOLVER_ERROR, c->raw);
        hpi_text_add(p->err, ": its claimed optimum binds no limit (none within ");
        hpi_text_add_num(p->err, HP_BINDING_TOL_MM * 1e6, 0);
        hpi_text_add(p->err, " nm), so it is not the closest; holding the previous pressures");
        fail_safe(p, r, HP_STATUS_SOLVER_ERROR, c);
        return 0;
    } else if (c->converged) {
        /* The answer's pose is a claim about where these pressures hold the head, so it is
         * verified as a reached one is: at the edge of a near-degenerate layout's
         * identifiable range the closest pose can be one of two with the same contact
         * distances, and the fit from the nominal pose (the forward model hp_planner_set_
         * previous and every reached answer use) ends at the other. */
        r->status = HP_STATUS_CLOSEST;
        /* A backend's own answer (not the direct chain's, not a hold): one start's optimum
         * unless the backend restarted. */
        unsigned caps = p->ops->caps;
        p->note_local = !c->direct && !c->held && (caps & HP_BACKEND_ONE_START) &&
                        !((caps & HP_BACKEND_RESTARTS) && p->s.restarts > 0);
        if (!recovered_from_nominal(p, r, r->achieved, c)) {
            c->unconfirmed = 1;
            fail_safe(p, r, HP_STATUS_INVALID_INPUT, c);
            return 0;
        }
    } else {
        r->status = (c->st == HP_STATUS_TIME_LIMIT) ? HP_STATUS_TIME_LIMIT
                                                    : HP_STATUS_ITERATION_LIMIT;
    }
    /* The two text channels: an answer explains itself in the note, a budget that ran out
     * is a failure to finish (error). */
    if (r->status == HP_STATUS_UNCOMMANDED) {
        hpi_text_set(p->note, "uncommanded: the commanded part is reached; ");
        add_uncommanded(p, p->note, c->unc);
    } else if (r->status != HP_STATUS_REACHED) {
        unsigned binding[HP_MAX_BLADDERS];
        for (int k = 0; k < p->L.n; ++k) binding[k] = r->bladders[k].binding;
        if (r->status == HP_STATUS_CLOSEST && !unc_any) { /* written when asked for */
            memcpy(p->note_binding, binding, sizeof binding);
            p->note_pending = 1;
            return 1;
        }
        char *buf = r->status == HP_STATUS_CLOSEST ? p->note : p->err;
        if (r->status == HP_STATUS_CLOSEST) add_closest(p, buf, binding);
        else add_budget(p, buf, r->status);
        if (unc_any) {
            hpi_text_add(buf, "; ");
            add_uncommanded(p, buf, c->unc);
        }
    }
    return 1;
}

void hpi_plan_note_flush(hp_planner *p)
{
    if (!p->note_pending) return;
    p->note_pending = 0;
    add_closest(p, p->note, p->note_binding);
    if (p->load) hpi_load_level_note(p->load, p->note);
}

static hp_error plan_once(hp_planner *p, const double desired[6], hp_result *res)
{
    plan_ctx c = {.t0 = hpi_plan_now(), .st = HP_STATUS_REACHED, .converged = 1};
    if (!p) return HP_ERR_NULL;
    if (!res) {
        hpi_text_set(p->err, "result: NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) {
        memset(res, 0, sizeof *res);
        res->status = HP_STATUS_SOLVER_ERROR;
        return HP_ERR_STATE;
    }
    p->err[0] = '\0';
    p->note[0] = '\0';
    p->note_pending = 0;
    p->note_local = 0;
    if (p->load) {
        /* The load level's plan; a CLOSEST answer's note names its binding limits as the
         * contact levels' does (composed when asked for, hp_planner_note). */
        hp_error e = hpi_load_level_plan(p->load, desired, res);
        if (e == HP_OK && res->status == HP_STATUS_CLOSEST) {
            for (int k = 0; k < res->n; ++k) p->note_binding[k] = res->bladders[k].binding;
            p->note_pending = 1;
        }
        return e;
    }
    if (!desired) {
        for (int i = 0; i < 6; ++i) res->desired[i] = NAN;
        hpi_text_set(p->err, "desired: NULL");
        fail_safe(p, res, HP_STATUS_INVALID_INPUT, &c);
        return HP_ERR_NULL;
    }
    if (!validate(p, desired, res, &c)) return HP_OK;

    c.direct = direct_chain(p, &c);
    /* Outside the static bounds the exact ones are tighter: no direct answer either. */
    if (c.rate_deferred && !c.direct && !rate_bounds(p, res, &c)) return HP_OK;
    c.held = !c.direct && rate_pinned(p);
    /* A second pass only after a warm solve's CLOSEST answer that the round trip from the
     * nominal pose does not confirm: local optima depend on the start, and the backend
     * started from the nominal pose, where the round trip starts too, may find one it
     * confirms. Without it a warm and a cold planner given the same previous pressures
     * could answer the same request differently. */
    for (int pass = 0;; ++pass) {
        res->backend = p->s.backend;
        res->level = p->level;
        res->n = p->L.n;
        res->raw_code = 0;
        res->iterations = 0;
        for (int i = 0; i < 6; ++i) res->commanded[i] = p->commanded[i];
        memcpy(res->uncommanded, c.unc, sizeof c.unc);
        c.x = p->pb.d;
        c.unconfirmed = 0;
        int iters0 = c.iters;
        int ok = c.held ? hold(p, res, &c) : c.direct || solve(p, res, &c, pass > 0);
        /* A window end the backend resolved without a radius fails the plan as the eager
         * bounds would have, before any solve. */
        if (!ok && p->pb.lazy && p->rate_lazy.failed) rate_failed(p, res, &c);
        if (!ok || !rate_settle(p, res, &c)) return HP_OK;
        c.iters += pass > 0 ? iters0 : 0;
        res->raw_code = c.raw;
        res->iterations = c.iters;
        /* A direct answer (deferred bounds: the direct chain answered) that the rate
         * windows discard for certain is not built (after a target jump the ramp's plans
         * skip about 4 000 instructions each). The discard below reads nothing of it but
         * the radii c.rho, and its rows are no memo for the next plan, which skips it again
         * or tests radii nearer the window. Looked for only after an answer the windows
         * held back, or toward a target far from the previous answer's pose (target_far):
         * the look costs about 930 instructions, which a breathing trace's plans, whose
         * answers stay inside their windows, paid for nothing (median 6 460 -> 7 382 on
         * the smooth trace). */
        int look = 0;
        if (c.rate_deferred) {
            int mode = atomic_load_explicit(&look_mode, memory_order_relaxed);
            look = mode ? mode > 0 : target_far(p);
        }
        int left = look && hpi_plan_direct_left(p, c.rho);
        if (!left && !accept(p, res, &c)) return HP_OK;
        if (c.rate_deferred) {
            /* A direct answer inside the static bounds: the plan's own unless a pressure
             * comes near a rate window's end. Then the exact bounds, and the plan again. */
            if (!left && hpi_setup_rate_clear(&p->L, &p->sb, &p->pb, res->bladders)) {
                c.rate_deferred = 0;
                /* Kept where a walk the windows held back ends (look): the plans holding
                 * its target test the same direct answer (hp_answer_memo), and no discarded
                 * one of the walk left its rows (on the loop benchmark's step trace each
                 * such hold plan cost 3 268 instructions more without them). */
                if (look) hpi_plan_answer_keep(p, c.rho, res);
            } else {
                /* Its rows, for the next plan toward the same target (hp_answer_memo). */
                if (!left) hpi_plan_answer_keep(p, c.rho, res);
                if (!rate_bounds(p, res, &c)) return HP_OK;
                /* The direct chain's radii (c.rho, every bladder's: it answered) decide its
                 * test against the stand-ins as against the exact bounds once the ends
                 * they come near are resolved; none when a radius lies beyond an exact
                 * end for certain (the test fails either way, and the solver resolves
                 * only the ends its answer needs). */
                if (!hpi_setup_rate_surely_out(p->pb.lazy, c.rho, p->L.n, 2.0 * HP_BINDING_TOL_MM))
                    hpi_setup_rate_touch(p->pb.lazy, c.rho, p->L.n, 2.0 * HP_BINDING_TOL_MM);
                if (p->pb.lazy && p->rate_lazy.failed) {
                    rate_failed(p, res, &c);
                    return HP_OK;
                }
                c.direct = direct_chain(p, &c);
                c.held = !c.direct && rate_pinned(p);
                c.clamp_mm = 0;
                --pass;
                continue;
            }
        }
        double a[6];
        hpi_plan_to_scaled(res->achieved, a);
        res->pose_error = 0;
        for (int i = 0; i < 6; ++i)
            if (p->commanded[i]) res->pose_error = fmax(res->pose_error, fabs(a[i] - p->pb.d[i]));
        if (label(p, res, &c)) break;
        if (!(c.unconfirmed && c.warm && pass == 0)) return HP_OK;
        p->err[0] = '\0';
        c.converged = 1;
        c.st = HP_STATUS_REACHED;
        c.clamp_mm = 0;
        c.has_rho = 0;
        c.has_lin = 0;
    }

    hpi_plan_set_previous_answer(p, res);
    /* A backend's own answer, unmoved, is the next start: tell the backend (warm start with
     * its multipliers). */
    if (!c.direct && !c.held && c.clamp_mm == 0) {
        /* The backend's own point; radii it left out (has_rho: NAN) stay the answer's. */
        memcpy(p->x_prev, p->x_work, 6 * sizeof *p->x_work);
        for (int k = 0; k < p->L.n; ++k)
            if (isfinite(p->x_work[6 + k])) p->x_prev[6 + k] = p->x_work[6 + k];
        if (p->ops->warm_point) p->ops->warm_point(p->bstate, 1);
    }
    res->solve_time = hpi_plan_now() - c.t0;
    p->prev.solve_time = res->solve_time;
    return HP_OK;
}

hp_error hp_plan(hp_planner *p, const double desired[6], hp_result *res)
{
    hp_error e = plan_once(p, desired, res);
    if (p) keep_rate_bounds(p);
    return e;
}

/* The three texts of the last plan live beside it: the failure's, the answer's, either. */
const char *hp_planner_error(const hp_planner *p) { return p ? p->err : "planner is NULL"; }

const char *hp_planner_note(const hp_planner *p)
{
    if (!p) return "";
    /* The planner is the caller's own, never a const object: the pending text is written
     * here (hpi_plan_note_flush), as hp_plan would have. */
    if (p->note_pending) hpi_plan_note_flush(hpi_unconst(p));
    return p->note;
}

const char *hp_planner_message(const hp_planner *p)
{
    if (!p) return hp_planner_error(p);
    /* A failure clears the note and an answer clears the error, so at most one is set. */
    return *p->err ? p->err : hp_planner_note(p);
}
