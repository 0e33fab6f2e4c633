/* The offline horizon plan: every row of a trace (or of a window of it) in one sparse NLP on
 * Ipopt's C interface, with exact first and second derivatives.
 *
 * Variables, row after row: x_t = [ξ_t (mm, deg), ri_t (mm)], nx = 6 + n per row.
 * Constraints of row t (2n, in this order):
 *   contact   ro(ri_t,k) − ρ_k(ξ_t) = 0                        [mm] (problem_eval.c)
 *   rate      (P(ri_t,k) − P(ri_t−1,k)) / 1 kPa in ±(Δ_t,k − margin)/1 kPa
 *             (row 0 against the window's start pressures)
 * Bounds: ri in the static pressure/stretch/stable-branch box of problem_setup.c (so every
 * pressure limit holds exactly), uncommanded pose components fixed at 0.
 * Objective: Σ_t Σ_i w_i (ξ_t,i − d_t,i)² + smooth Σ_t,k ((P_t,k − P_t−1,k) / 1 kPa)².
 *
 * Sparsity, handed to Ipopt as such (never a dense matrix over the whole trace):
 *   Jacobian: a contact row touches its row's six pose columns and its own ri; a rate row
 *   touches ri_t,k and ri_t−1,k.
 *   Hessian of the Lagrangian (lower triangle): per row the dense 6×6 pose block, the ri
 *   diagonal, and the (ri_t,k, ri_t−1,k) entry of the smoothness term — block-banded. */
#include "common/unconst.h"
#include "horizon/horizon_internal.h"
#include "planner/ipopt_shared.h"
#include "planner/planner_internal.h"
#include "planner/problem_setup.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define IPOPT_INF 1e19
/* A row counts as REACHED when its pose error is at most this (mm or degrees): the offline
 * solve meets the contact equality and optimality to Ipopt's tolerance, not to 1e-9. */
#define OFFLINE_REACHED_TOL 1e-6
/* Largest contact residual |ro(ri) − ρ(ξ)| an answer may keep [mm]. */
#define OFFLINE_CONTACT_TOL 1e-6

typedef struct nlp {
    hp_problem pb; /* one row's problem: layout, level, weights, box (mm) */
    int n, nx;
    int T;                      /* rows in this window */
    const hp_trace_row *rows;   /* this window's rows */
    double *xc;                 /* T×6: commanded part of each row's desired pose (SI), the
                                   pose the row aims at, as hp_plan aims at it */
    const double *delta;        /* T×n rate limits [Pa] */
    double p0[HP_MAX_BLADDERS]; /* pressures before the window's first row [Pa] */
    double smooth;
    double *P, *dP, *d2P; /* T×n: IK, per mm, per mm² at the current x */
    double *h, *jac;      /* nx×nx and n×nx per-row scratch */
    int iters;
    int failed;
} nlp;

/* Sets pb.d to the commanded part of row t's desired correction (scaled; 0 where not
 * commanded). */
static void set_row(nlp *q, int t)
{
    for (int i = 0; i < 6; ++i)
        q->pb.d[i] = q->pb.w[i] > 0 ? q->xc[6 * t + i] * hpi_pose_scaled_per_si(i) : 0.0;
}

/* P, dP/dri, d²P/dri² of every bladder of every row at x (mm units). */
static int eval_pressures(nlp *q, const double *x)
{
    for (int t = 0; t < q->T; ++t)
        for (int k = 0; k < q->n; ++k) {
            size_t j = (size_t)t * (size_t)q->n + (size_t)k;
            double P, dP, d2P;
            const hp_iab *b = &q->pb.layout->bladders[k].iab;
            if (hp_iab_ik_derivs(b, x[(size_t)t * (size_t)q->nx + 6 + (size_t)k] * 1e-3, &P, &dP,
                                 &d2P) != HP_OK ||
                !isfinite(P))
                return 0;
            q->P[j] = P;
            q->dP[j] = dP * 1e-3;
            q->d2P[j] = d2P * 1e-6;
        }
    return 1;
}

/* Pressure of bladder k before row t [Pa]. */
static double prev_p(const nlp *q, int t, int k)
{
    return t ? q->P[(size_t)(t - 1) * (size_t)q->n + (size_t)k] : q->p0[k];
}

static Bool eval_f(Index nv, Number *x, Bool new_x, Number *f, UserDataPtr u)
{
    (void)nv, (void)new_x;
    nlp *q = u;
    if (!eval_pressures(q, x)) return FALSE;
    double sum = 0;
    for (int t = 0; t < q->T; ++t) {
        double ft;
        set_row(q, t);
        if (hpi_problem_objective(&q->pb, x + (size_t)t * (size_t)q->nx, &ft, NULL, NULL) != HP_OK)
            return FALSE;
        sum += ft;
        for (int k = 0; k < q->n; ++k) {
            double du = (q->P[(size_t)t * (size_t)q->n + (size_t)k] - prev_p(q, t, k)) * 1e-3;
            sum += q->smooth * du * du;
        }
    }
    *f = sum;
    return isfinite(sum);
}

static Bool eval_grad_f(Index nv, Number *x, Bool new_x, Number *g, UserDataPtr u)
{
    (void)nv, (void)new_x;
    nlp *q = u;
    if (!eval_pressures(q, x)) return FALSE;
    for (int t = 0; t < q->T; ++t) {
        double ft;
        size_t base = (size_t)t * (size_t)q->nx;
        set_row(q, t);
        if (hpi_problem_objective(&q->pb, x + base, &ft, g + base, NULL) != HP_OK) return FALSE;
    }
    for (int t = 0; t < q->T; ++t)
        for (int k = 0; k < q->n; ++k) {
            size_t j = (size_t)t * (size_t)q->n + (size_t)k;
            double du = (q->P[j] - prev_p(q, t, k)) * 1e-3;
            g[(size_t)t * (size_t)q->nx + 6 + (size_t)k] += 2.0 * q->smooth * du * q->dP[j] * 1e-3;
            if (t > 0)
                g[(size_t)(t - 1) * (size_t)q->nx + 6 + (size_t)k] -= 2.0 * q->smooth * du *
                                                                      q->dP[j - (size_t)q->n] *
                                                                      1e-3;
        }
    return TRUE;
}

static Bool eval_g(Index nv, Number *x, Bool new_x, Index m, Number *g, UserDataPtr u)
{
    (void)nv, (void)new_x, (void)m;
    nlp *q = u;
    if (!eval_pressures(q, x)) return FALSE;
    for (int t = 0; t < q->T; ++t) {
        size_t c0 = (size_t)t * 2u * (size_t)q->n;
        if (hpi_problem_constraints(&q->pb, x + (size_t)t * (size_t)q->nx, g + c0, NULL, NULL,
                                    NULL) != HP_OK)
            return FALSE;
        for (int k = 0; k < q->n; ++k)
            g[c0 + (size_t)q->n + (size_t)k] = (q->P[(size_t)t * (size_t)q->n + (size_t)k] -
                                                prev_p(q, t, k)) *
                                               1e-3;
    }
    return TRUE;
}

static Bool eval_jac_g(Index nv, Number *x, Bool new_x, Index m, Index nele, Index *iRow,
                       Index *jCol, Number *v, UserDataPtr u)
{
    (void)nv, (void)new_x, (void)m, (void)nele;
    nlp *q = u;
    const int n = q->n, nx = q->nx;
    if (!v) {
        /* Ipopt asks for the structure with both index arrays; anything else is refused. */
        if (!iRow || !jCol) return FALSE;
        Index e = 0;
        for (int t = 0; t < q->T; ++t) {
            Index c0 = t * 2 * n, x0 = t * nx;
            for (int k = 0; k < n; ++k) {
                for (int i = 0; i < 6; ++i, ++e) iRow[e] = c0 + k, jCol[e] = x0 + i;
                iRow[e] = c0 + k, jCol[e] = x0 + 6 + k, ++e;
            }
            for (int k = 0; k < n; ++k) {
                iRow[e] = c0 + n + k, jCol[e] = x0 + 6 + k, ++e;
                if (t > 0) iRow[e] = c0 + n + k, jCol[e] = x0 - nx + 6 + k, ++e;
            }
        }
        return TRUE;
    }
    if (!eval_pressures(q, x)) return FALSE;
    size_t e = 0;
    for (int t = 0; t < q->T; ++t) {
        if (hpi_problem_constraints(&q->pb, x + (size_t)t * (size_t)nx, NULL, q->jac, NULL, NULL) !=
            HP_OK)
            return FALSE;
        for (int k = 0; k < n; ++k) {
            for (int i = 0; i < 6; ++i) v[e++] = q->jac[k * nx + i];
            v[e++] = q->jac[k * nx + 6 + k];
        }
        for (int k = 0; k < n; ++k) {
            size_t j = (size_t)t * (size_t)n + (size_t)k;
            v[e++] = q->dP[j] * 1e-3;
            if (t > 0) v[e++] = -q->dP[j - (size_t)n] * 1e-3;
        }
    }
    return TRUE;
}

static Bool eval_h(Index nv, Number *x, Bool new_x, Number of, Index m, Number *lambda,
                   Bool new_lambda, Index nele, Index *iRow, Index *jCol, Number *v, UserDataPtr u)
{
    (void)nv, (void)new_x, (void)m, (void)new_lambda, (void)nele;
    nlp *q = u;
    const int n = q->n, nx = q->nx;
    if (!v) {
        if (!iRow || !jCol) return FALSE; /* as in eval_jac_g */
        Index e = 0;
        for (int t = 0; t < q->T; ++t) {
            Index x0 = t * nx;
            for (int i = 0; i < 6; ++i)
                for (int j = 0; j <= i; ++j, ++e) iRow[e] = x0 + i, jCol[e] = x0 + j;
            for (int k = 0; k < n; ++k, ++e) iRow[e] = x0 + 6 + k, jCol[e] = x0 + 6 + k;
            if (t > 0)
                for (int k = 0; k < n; ++k, ++e) iRow[e] = x0 + 6 + k, jCol[e] = x0 - nx + 6 + k;
        }
        return TRUE;
    }
    if (!eval_pressures(q, x)) return FALSE;
    const double s2 = 2.0 * q->smooth * of;
    size_t e = 0;
    for (int t = 0; t < q->T; ++t) {
        double ft;
        const double *xt = x + (size_t)t * (size_t)nx;
        const double *lc = lambda + (size_t)t * 2u * (size_t)n;
        set_row(q, t);
        if (hpi_problem_objective(&q->pb, xt, &ft, NULL, q->h) != HP_OK) return FALSE;
        for (int i = 0; i < nx * nx; ++i) q->h[i] *= of;
        if (hpi_problem_constraints(&q->pb, xt, NULL, NULL, lc, q->h) != HP_OK) return FALSE;
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j <= i; ++j) v[e++] = q->h[i * nx + j];
        for (int k = 0; k < n; ++k) {
            size_t j = (size_t)t * (size_t)n + (size_t)k;
            double dPk = q->dP[j] * 1e-3, d2Pk = q->d2P[j] * 1e-3;
            double hv = q->h[(6 + k) * nx + 6 + k];
            /* rate row of this row (+P_t) and of the next row (−P_t) */
            hv += lc[n + k] * d2Pk;
            double du = (q->P[j] - prev_p(q, t, k)) * 1e-3;
            hv += s2 * (dPk * dPk + du * d2Pk);
            if (t + 1 < q->T) {
                size_t jn = j + (size_t)n;
                double dun = (q->P[jn] - q->P[j]) * 1e-3;
                hv -= lambda[(size_t)(t + 1) * 2u * (size_t)n + (size_t)n + (size_t)k] * d2Pk;
                hv += s2 * (dPk * dPk - dun * d2Pk);
            }
            v[e++] = hv;
        }
        if (t > 0)
            for (int k = 0; k < n; ++k) {
                size_t j = (size_t)t * (size_t)n + (size_t)k;
                v[e++] = -s2 * (q->dP[j] * 1e-3) * (q->dP[j - (size_t)n] * 1e-3);
            }
    }
    return TRUE;
}

static Bool intermediate(Index alg_mod, Index iter, Number obj, Number inf_pr, Number inf_du,
                         Number mu, Number d_norm, Number reg, Number alpha_du, Number alpha_pr,
                         Index ls, UserDataPtr u)
{
    (void)alg_mod, (void)obj, (void)inf_pr, (void)inf_du, (void)mu, (void)d_norm, (void)reg;
    (void)alpha_du, (void)alpha_pr, (void)ls;
    ((nlp *)u)->iters = iter;
    return TRUE;
}

/* Everything a whole offline plan shares between its windows. */
typedef struct offline_ctx {
    const hp_layout *L; /* the planner's validated copy */
    hp_problem pb;      /* weights, level, static box (mm) */
    hp_static_bounds sb;
    const hp_horizon_settings *hs;
    const hp_settings *s;
    hp_planner *p; /* for the strict round trip of every row's answer */
} offline_ctx;

/* The commanded part of every row's desired pose into xc (T×6, SI). */
static hp_error commanded_parts(const offline_ctx *c, const hp_trace_row *rows, int T, double *xc,
                                hp_diag *d)
{
    for (int t = 0; t < T; ++t) {
        hp_error e = hp_pose_commanded_part(c->L, hp_planner_identifiable(c->p), c->pb.level,
                                            rows[t].correction, xc + 6 * t);
        if (e != HP_OK)
            return hp_diag_set(d, HP_ERR_INVALID, "offline: line %ld: commanded part: %s",
                               rows[t].line, hp_error_message(e));
    }
    return HP_OK;
}

/* The planner (for its validated layout and geometry, level and the greedy start) and everything the
 * windows share. *p is the caller's to destroy, also on failure. */
static hp_error ctx_build(const hp_layout *L, const hp_settings *settings,
                          const hp_horizon_settings *hs, hp_settings *s, hp_planner **p,
                          offline_ctx *c, hp_diag *d)
{
    if (settings) *s = *settings;
    else hp_settings_default(s);
    s->backend = HP_BACKEND_REALTIME; /* the start plan; the NLP itself is Ipopt's */
    *p = NULL;
    memset(c, 0, sizeof *c);
    hp_error e = hp_planner_create(L, s, p, d);
    if (e == HP_OK && hp_planner_level(*p) == HP_LEVEL_LOAD)
        e = hpi_horizon_load_refused("offline", d);
    if (e != HP_OK) return e;
    c->L = hp_planner_layout(*p);
    c->p = *p;
    c->hs = hs;
    c->s = s;
    int commanded[6];
    memcpy(commanded, hp_planner_identifiable(*p)->commanded, sizeof commanded);
    if ((e = hpi_setup_static_bounds(c->L, &c->sb, d)) != HP_OK) return e;
    c->pb.layout = c->L;
    c->pb.geom = hpi_planner_geom(*p);
    c->pb.level = hp_planner_level(*p);
    c->pb.n = c->L->n;
    c->pb.nx = 6 + c->L->n;
    c->pb.mu = 0.0;
    for (int i = 0; i < 6; ++i) c->pb.w[i] = hpi_horizon_weight(s, commanded, i);
    return hpi_setup_cycle_bounds(c->L, &c->sb, NULL, 0, &c->pb, NULL, NULL, d);
}

/* Doubles one window's NLP needs (nlp_init's buf). */
static size_t nlp_doubles(int T, int n)
{
    const size_t nx = 6 + (size_t)n, NV = (size_t)T * nx, NC = (size_t)T * 2u * (size_t)n;
    return 3 * (size_t)T * (size_t)n + 6 * (size_t)T + nx * nx + (size_t)n * nx + 3 * NV + 2 * NC;
}

/* One window's NLP on top of buf (nlp_doubles(T, n) doubles; x, bounds follow q->jac). */
static void nlp_init(nlp *q, const offline_ctx *c, const hp_trace_row *rows, const double *delta,
                     int T, const double *p0, double *buf)
{
    const int n = c->L->n, nx = 6 + n;
    memset(q, 0, sizeof *q);
    q->pb = c->pb;
    q->n = n;
    q->nx = nx;
    q->T = T;
    q->rows = rows;
    q->delta = delta;
    q->smooth = c->hs->smooth;
    memcpy(q->p0, p0, sizeof(double) * (size_t)n);
    q->P = buf;
    q->dP = q->P + (size_t)T * (size_t)n;
    q->d2P = q->dP + (size_t)T * (size_t)n;
    q->xc = q->d2P + (size_t)T * (size_t)n;
    q->h = q->xc + 6 * (size_t)T;
    q->jac = q->h + (size_t)nx * (size_t)nx;
}

/* Solves rows [0, T) of `rows` from pressures p0, starting at the plan `start`; writes out.
 * Caller frees nothing: every buffer is freed here. */
static hp_error solve_window(const offline_ctx *c, const hp_trace_row *rows, const double *delta,
                             int T, const double *p0, const hp_horizon_row *start,
                             hp_horizon_row *out, hp_horizon_info *info, hp_diag *d)
{
    const int n = c->L->n, nx = 6 + n;
    const size_t NV = (size_t)T * (size_t)nx, NC = (size_t)T * 2u * (size_t)n;
    nlp q;
    double *buf = malloc(sizeof(double) * nlp_doubles(T, n));
    if (!buf) return hp_diag_set(d, HP_ERR_NOMEM, "offline: out of memory (%d rows)", T);
    nlp_init(&q, c, rows, delta, T, p0, buf);
    hp_error ce = commanded_parts(c, rows, T, q.xc, d);
    if (ce != HP_OK) {
        free(buf);
        return ce;
    }
    double *x = q.jac + (size_t)n * (size_t)nx, *xl = x + NV, *xu = xl + NV;
    double *gl = xu + NV, *gu = gl + NC;

    for (int t = 0; t < T; ++t) {
        size_t b = (size_t)t * (size_t)nx;
        for (int i = 0; i < 6; ++i) {
            double lim = c->pb.w[i] > 0 ? IPOPT_INF : 0.0;
            xl[b + (size_t)i] = -lim;
            xu[b + (size_t)i] = lim;
            x[b + (size_t)i] = c->pb.w[i] > 0 ? start[t].achieved[i] * hpi_pose_scaled_per_si(i)
                                              : 0.0;
        }
        for (int k = 0; k < n; ++k) {
            size_t j = b + 6 + (size_t)k;
            xl[j] = c->pb.ri_lo[k];
            xu[j] = c->pb.ri_hi[k];
            x[j] = fmin(fmax(start[t].ri[k] * HP_MM_PER_M, xl[j]), xu[j]);
        }
        size_t c0 = (size_t)t * 2u * (size_t)n;
        for (int k = 0; k < n; ++k) {
            gl[c0 + (size_t)k] = gu[c0 + (size_t)k] = 0.0;
            double D = delta[(size_t)t * (size_t)n + (size_t)k];
            double lim = D <= HP_HORIZON_HOLD_PA ? 0.0 /* held: see below */
                         : isfinite(D)           ? (D - HP_HORIZON_RATE_MARGIN) * 1e-3
                                                 : IPOPT_INF;
            gl[c0 + (size_t)n + (size_t)k] = -lim;
            gu[c0 + (size_t)n + (size_t)k] = lim;
        }
    }
    /* Every allowance of the window below HP_HORIZON_HOLD_PA: every pressure is held, so the
     * plan is fixed and needs no NLP (posed to Ipopt, its equalities outnumber its free
     * variables): every row is the pose the held pressures hold, from the nominal pose. */
    int all_held = 1;
    for (size_t j = 0; j < (size_t)T * (size_t)n; ++j) all_held &= delta[j] <= HP_HORIZON_HOLD_PA;
    if (all_held) {
        double ro[HP_MAX_BLADDERS], xi[6];
        hp_error he = HP_OK;
        for (int k = 0; k < n && he == HP_OK; ++k) {
            const hp_iab *b = &c->L->bladders[k].iab;
            double ri = NAN;
            he = hp_iab_fk_limit(b, &c->sb.limit[k], p0[k], &ri);
            if (he == HP_OK) he = hp_iab_ro(b, ri, &ro[k]);
            for (int t = 0; t < T; ++t)
                x[(size_t)t * (size_t)nx + 6 + (size_t)k] = ri * HP_MM_PER_M;
        }
        if (he == HP_OK)
            he = hpi_plan_fit_from_nominal(c->p, ro, hp_planner_identifiable(c->p)->commanded, NULL,
                                           xi, NULL);
        if (he != HP_OK) {
            free(buf);
            return hp_diag_set(d, HP_ERR_SOLVER,
                               "offline: line %ld: no pose holds the held pressures (%s)",
                               rows[0].line, hp_error_message(he));
        }
        for (int t = 0; t < T; ++t)
            for (int i = 0; i < 6; ++i)
                x[(size_t)t * (size_t)nx + (size_t)i] = c->pb.w[i] > 0
                                                            ? xi[i] * hpi_pose_scaled_per_si(i)
                                                            : 0.0;
    }
    Index nnz_j = T * 7 * n + T * 2 * n - n;
    Index nnz_h = T * (21 + n) + (T - 1) * n;
    hp_error e = HP_OK;
    enum ApplicationReturnStatus rc = Internal_Error;
    hpi_ipopt_lock();
    IpoptProblem app = all_held
                           ? NULL
                           : CreateIpoptProblem((Index)NV, xl, xu, (Index)NC, gl, gu, nnz_j, nnz_h,
                                                0, eval_f, eval_g, eval_grad_f, eval_jac_g, eval_h);
    if (all_held) rc = Solve_Succeeded;
    else if (!app) e = hp_diag_set(d, HP_ERR_SOLVER, "offline: CreateIpoptProblem failed");
    if (e == HP_OK && app)
        e = hpi_ipopt_base_options(app, c->hs->offline_tol, c->hs->offline_max_iter,
                                   c->hs->offline_max_time, d);
    if (e == HP_OK && app && !SetIntermediateCallback(app, intermediate))
        e = hp_diag_set(d, HP_ERR_SOLVER, "offline: SetIntermediateCallback failed");
    if (e == HP_OK && app) {
        double obj;
        rc = IpoptSolve(app, x, NULL, &obj, NULL, NULL, NULL, &q);
    }
    if (app) FreeIpoptProblem(app);
    hpi_ipopt_unlock();
    if (info) {
        info->windows += 1;
        info->iterations += q.iters;
    }
    if (e == HP_OK && rc != Solve_Succeeded && rc != Solved_To_Acceptable_Level) {
        if (info) info->raw_code = (int)rc;
        e = hp_diag_set(d, HP_ERR_SOLVER,
                        "offline: Ipopt stopped with status %d on the window of lines %ld..%ld",
                        (int)rc, rows[0].line, rows[T - 1].line);
    }
    /* The answer, checked against every limit before it is handed out. */
    for (int t = 0; t < T && e == HP_OK; ++t) {
        hp_horizon_row *o = &out[t];
        const double *xt = x + (size_t)t * (size_t)nx;
        double rho[HP_MAX_BLADDERS];
        o->t = rows[t].t;
        memcpy(o->desired, rows[t].correction, sizeof o->desired);
        double err;
        for (int i = 0; i < 6; ++i) o->achieved[i] = xt[i] / hpi_pose_scaled_per_si(i);
        /* hp_plan's labels, to the offline solve's own accuracy where it is coarser */
        o->status = hpi_horizon_label(hp_planner_identifiable(c->p)->commanded, o->desired,
                                      q.xc + 6 * t, o->achieved,
                                      fmax(c->s->tolerance, OFFLINE_REACHED_TOL), &err);
        if (hpi_setup_contact_scaled(c->L, c->pb.geom, c->pb.level, xt, rho, NULL) != HP_OK) {
            e = hp_diag_set(d, HP_ERR_SOLVER, "offline: line %ld: contact model failed",
                            rows[t].line);
            break;
        }
        /* The row's bladders as an answer, for the round trip below. */
        hp_result rr;
        rr.n = n;
        for (int k = 0; k < n && e == HP_OK; ++k) {
            const hp_bladder *B = &c->L->bladders[k];
            double ri = fmin(fmax(xt[6 + k], c->pb.ri_lo[k]), c->pb.ri_hi[k]) / HP_MM_PER_M;
            double ro, P;
            hp_error he = HP_OK;
            if (delta[(size_t)t * (size_t)n + (size_t)k] <= HP_HORIZON_HOLD_PA) {
                /* Held: the previous row's pressure and radius, exactly (row 0: the start
                 * pressure and its stable radius). */
                if (t) ri = out[t - 1].ri[k];
                else he = hp_iab_fk_limit(&B->iab, &c->sb.limit[k], p0[k], &ri);
            }
            if (he != HP_OK || hp_iab_ro(&B->iab, ri, &ro) != HP_OK ||
                hp_iab_ik(&B->iab, ri, &P) != HP_OK ||
                !(fabs(ro * HP_MM_PER_M - rho[k]) <= OFFLINE_CONTACT_TOL) ||
                !(P >= B->p_min && P <= B->p_max)) {
                e = hp_diag_set(d, HP_ERR_SOLVER,
                                "offline: line %ld: bladder %s: the solver's answer breaks the "
                                "contact or a pressure limit",
                                rows[t].line, B->name);
                break;
            }
            double prev = t ? out[t - 1].pressure[k] : p0[k];
            if (delta[(size_t)t * (size_t)n + (size_t)k] <= HP_HORIZON_HOLD_PA) P = prev;
            if (!(fabs(P - prev) <= delta[(size_t)t * (size_t)n + (size_t)k])) {
                e = hp_diag_set(d, HP_ERR_SOLVER,
                                "offline: line %ld: bladder %s: the solver's answer breaks the "
                                "rate limit (%.9g Pa > %.9g Pa)",
                                rows[t].line, B->name, fabs(P - prev),
                                delta[(size_t)t * (size_t)n + (size_t)k]);
                break;
            }
            o->ri[k] = rr.bladders[k].ri = ri;
            o->pressure[k] = rr.bladders[k].pressure = P;
            rr.bladders[k].ro = ro;
        }
        /* The row's pose is a claim about where its pressures hold the head: the same strict
         * round trip as hp_plan's answers (from the nominal pose), so offline never states a
         * pose that the forward model puts elsewhere. */
        hp_plan_trip trip;
        /* INVALID, as hp_plan refuses such an answer (INVALID_INPUT): the trace asks for a
         * pose this layout cannot identify, not the solver failing. */
        if (e == HP_OK && !hpi_plan_round_trip(c->p, &rr, o->achieved, NULL, &trip)) {
            char why[HP_DIAG_MAX];
            why[0] = '\0';
            hpi_plan_trip_text(why, &trip);
            e = hp_diag_set(d, HP_ERR_INVALID,
                            "offline: line %ld: the planned pose is not where its pressures "
                            "hold the head: %s",
                            rows[t].line, why);
        }
    }
    free(buf);
    return e;
}

void hp_horizon_offline_windows(const hp_horizon_settings *hs, size_t T, int *window, int *overlap)
{
    *window = hs->window;
    *overlap = hs->overlap;
    if (hs->window == 0 && T > HP_HORIZON_WHOLE_MAX) {
        *window = HP_HORIZON_AUTO_WINDOW;
        *overlap = HP_HORIZON_AUTO_OVERLAP;
    }
}

hp_error hp_horizon_offline(const hp_layout *L, const hp_settings *settings,
                            const hp_horizon_settings *hs, const hp_trace_row *rows, size_t T,
                            const double *p_start, hp_horizon_row *out, hp_horizon_info *info,
                            hp_diag *d)
{
    if (!L || !hs || (T && (!rows || !out)))
        return hp_diag_set(d, HP_ERR_NULL, "offline: NULL argument");
    if (info) memset(info, 0, sizeof *info);
    hp_error e = hp_horizon_settings_validate(hs, d);
    if (e != HP_OK || T == 0) return e;
    int window, overlap;
    hp_horizon_offline_windows(hs, T, &window, &overlap);
    if (T > (size_t)(1 << 20) && (window == 0 || (size_t)window >= T))
        return hp_diag_set(d, HP_ERR_INVALID, "offline: %zu rows in one NLP; window the trace", T);
    hp_settings s;
    hp_planner *p = NULL;
    offline_ctx c;
    double start[HP_MAX_BLADDERS];
    double *delta = NULL;
    hp_horizon_row *greedy = NULL;
    if ((e = ctx_build(L, settings, hs, &s, &p, &c, d)) != HP_OK) goto done;
    const int n = c.L->n;
    if (p_start) memcpy(start, p_start, sizeof(double) * (size_t)n);
    else if ((e = hp_horizon_nominal_pressures(c.L, start, d)) != HP_OK) goto done;

    delta = malloc(sizeof(double) * T * (size_t)n);
    greedy = malloc(sizeof *greedy * T);
    if (!delta || !greedy) {
        e = hp_diag_set(d, HP_ERR_NOMEM, "offline: out of memory (%zu rows)", T);
        goto done;
    }
    if ((e = hp_horizon_rates(c.L, hs, rows, T, delta, d)) != HP_OK) goto done;
    if ((e = hp_horizon_greedy(c.L, &s, hs, rows, T, start, greedy, d)) != HP_OK) goto done;

    size_t a = 0;
    while (a < T) {
        size_t b = window > 0 ? a + (size_t)window : T;
        if (b > T) b = T;
        size_t commit = b == T ? T : b - (size_t)overlap;
        if (info && (int)(b - a) > info->largest_window) info->largest_window = (int)(b - a);
        const double *p0 = a ? out[a - 1].pressure : start;
        e = solve_window(&c, rows + a, delta + a * (size_t)n, (int)(b - a), p0, greedy + a, out + a,
                         info, d);
        if (e != HP_OK) goto done;
        a = commit;
    }
    if (info) {
        hp_horizon_metrics m;
        if (hp_horizon_measure(out, T, n, start, &s, hs, 1.0, 1.0, &m) == HP_OK)
            info->cost = m.cost;
    }
done:
    free(delta);
    free(greedy);
    hp_planner_destroy(p);
    return e;
}

hp_error hpi_horizon_nlp_dense(const hp_layout *L, const hp_settings *settings,
                               const hp_horizon_settings *hs, const hp_trace_row *rows, int T,
                               const double *p0, const double *x, double obj_factor,
                               const double *lambda, double *f, double *grad, double *g,
                               double *jac, double *hess)
{
    hp_settings s;
    hp_planner *p = NULL;
    offline_ctx c;
    hp_error e = ctx_build(L, settings, hs, &s, &p, &c, NULL);
    const int n = L->n, nx = 6 + n, NV = T * nx, NC = T * 2 * n;
    const size_t cap = (size_t)T * (size_t)(21 + 9 * n);
    double *delta = malloc(sizeof(double) * (size_t)T * (size_t)n);
    double *buf = malloc(sizeof(double) * nlp_doubles(T, n));
    Index *iR = malloc(sizeof(Index) * cap), *jC = malloc(sizeof(Index) * cap);
    double *v = malloc(sizeof(double) * cap);
    if (e == HP_OK && (!delta || !buf || !iR || !jC || !v)) e = HP_ERR_NOMEM;
    if (e == HP_OK) e = hp_horizon_rates(c.L, hs, rows, (size_t)T, delta, NULL);
    nlp q;
    if (e == HP_OK) {
        nlp_init(&q, &c, rows, delta, T, p0, buf);
        e = commanded_parts(&c, rows, T, q.xc, NULL);
    }
    if (e == HP_OK) {
        double *xx = hpi_unconst(x); /* Ipopt's callbacks take non-const pointers */
        double *ll = hpi_unconst(lambda);
        Index nj = T * 7 * n + T * 2 * n - n, nh = T * (21 + n) + (T - 1) * n;
        if (!eval_f(NV, xx, 1, f, &q) || !eval_grad_f(NV, xx, 1, grad, &q) ||
            !eval_g(NV, xx, 1, NC, g, &q) || !eval_jac_g(NV, xx, 1, NC, nj, iR, jC, NULL, &q) ||
            !eval_jac_g(NV, xx, 1, NC, nj, NULL, NULL, v, &q))
            e = HP_ERR_DOMAIN;
        if (e == HP_OK) {
            memset(jac, 0, sizeof(double) * (size_t)NC * (size_t)NV);
            for (Index i = 0; i < nj; ++i) jac[(size_t)iR[i] * (size_t)NV + (size_t)jC[i]] += v[i];
            if (!eval_h(NV, xx, 1, obj_factor, NC, ll, 1, nh, iR, jC, NULL, &q) ||
                !eval_h(NV, xx, 1, obj_factor, NC, ll, 1, nh, NULL, NULL, v, &q))
                e = HP_ERR_DOMAIN;
        }
        if (e == HP_OK) {
            memset(hess, 0, sizeof(double) * (size_t)NV * (size_t)NV);
            for (Index i = 0; i < nh; ++i) {
                if (iR[i] < jC[i]) e = HP_ERR_INVALID; /* not the lower triangle */
                hess[(size_t)iR[i] * (size_t)NV + (size_t)jC[i]] += v[i];
            }
        }
    }
    free(delta);
    free(buf);
    free(iR);
    free(jC);
    free(v);
    hp_planner_destroy(p);
    return e;
}
