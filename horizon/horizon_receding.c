/* The receding-horizon planner: at every row, the next N rows under a predicted desired pose,
 * solved in a workspace allocated at create; the first row is applied through hp_plan.
 *
 * The horizon problem is the offline one (hp_horizon.h) over N rows, with the radii
 * eliminated (ro_k = ρ_k(ξ); ri and P follow on the stable branch):
 *   minimise  Σ_j Σ_i w_i (z_j,i − d_j,i)² + smooth Σ_j,k u_j,k²          z_j scaled (mm, deg)
 *   s.t.      ro_lo_k <= ρ_k(z_j) <= ro_hi_k,   |u_j,k| <= Δ_j,k / 1 kPa
 * with u_j,k = (P_j,k − P_j−1,k) / 1 kPa (row 0 against the pressures held now). It is
 * solved by a primal-dual interior-point method (slacks s and multipliers λ for the 4·n·N
 * inequalities, started inside, fraction-to-the-boundary steps, centring σ = RH_SIGMA), with
 * the constraints linearised at every iterate (exact contact Jacobians, dP/dro of the bladder
 * model) and a Gauss–Newton Hessian of the objective. Eliminating s and λ leaves the normal
 * matrix H + Σ_i (λ_i/s_i) ∇c_i ∇c_iᵀ, block tridiagonal (row j couples only with j ± 1
 * through the rate and smoothness terms), so each step is a block Cholesky in O(N · 6³): no
 * dense 6N × 6N matrix. At most rh_max_iter iterations (fewer once converged, none begun
 * after half the planner's max_time), started from the previous call's plan
 * shifted by one row. The iterate need not be feasible: the applied first row goes through
 * hp_plan (realtime backend, this row's rate limits), which keeps every limit exactly.
 * Uncommanded pose components are pulled to 0 with unit weight, as the planner holds them. */
#define _POSIX_C_SOURCE 200809L
#include "horizon/horizon_internal.h"
#include "planner/problem_setup.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define RH_SIGMA 0.1      /* centring: the next barrier weight is this times the mean s·λ */
#define RH_BOUNDARY 0.995 /* fraction-to-the-boundary of a step */
#define RH_S_MIN 1e-3     /* smallest starting slack (mm or kPa) */
#define RH_MU0 1e-3       /* starting complementarity s·λ */
#define RH_GAP_TOL 1e-10  /* stop when the mean s·λ is below this ... */
#define RH_STEP_TOL 1e-9  /* ... and the last step moved no pose by more (mm or degrees) */
#define RH_NC 4           /* inequalities per bladder and row: ro >= lo, ro <= hi, ±u <= Δ */

struct hp_horizon_rh {
    hp_planner *p;
    const hp_layout *L; /* the planner's validated copy */
    const hp_geom *G;   /* and its contact geometry */
    hp_settings s;
    hp_horizon_settings hs;
    hp_level level;
    int n, N;
    int commanded[6];
    double w[6]; /* pose weights (1 where not commanded) */
    double ro_lo[HP_MAX_BLADDERS], ro_hi[HP_MAX_BLADDERS]; /* [mm] static box */
    double rate_scene[HP_MAX_BLADDERS]; /* [Pa] the scene's per-row limits (the planner's
                                           copy holds the last row's allowance) */
    double p_now[HP_MAX_BLADDERS];      /* pressures the bladders hold [Pa] */
    double last_t;
    int started;
    int hist_n; /* commanded parts of the desired poses, kept for the
                                        velocity prediction */
    double hist_t[HP_HORIZON_MAX], hist_d[HP_HORIZON_MAX][6];
    double z[HP_HORIZON_MAX * 6], zt[HP_HORIZON_MAX * 6], dz[HP_HORIZON_MAX * 6];
    double d[HP_HORIZON_MAX * 6];
    double delta[HP_HORIZON_MAX * HP_MAX_BLADDERS];
    double rho[HP_HORIZON_MAX * HP_MAX_BLADDERS], J[HP_HORIZON_MAX * HP_MAX_BLADDERS * 6];
    double P[HP_HORIZON_MAX * HP_MAX_BLADDERS], dP[HP_HORIZON_MAX * HP_MAX_BLADDERS];
    double g[HP_HORIZON_MAX * 6];
    double A[HP_HORIZON_MAX * 36], B[HP_HORIZON_MAX * 36]; /* diagonal / sub-diagonal blocks */
    hp_result applied;     /* the last applied answer (its pose starts a cold plan) */
    int budget_stopped;    /* the last call's horizon solve stopped at its time budget */
    char why[HP_DIAG_MAX]; /* ... and what it says about it */
    double c[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS];   /* constraint values (>= 0 wanted) */
    double sl[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS];  /* slacks */
    double lam[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS]; /* multipliers */
    double ds[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS];
    double dl[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS];
};

/* P [Pa] and dP/dro [Pa/mm] at outer radius ro (mm), ro held inside the box. */
static int press_of_ro(const hp_horizon_rh *rh, int k, double ro, double *P, double *dP)
{
    const hp_iab *b = &rh->L->bladders[k].iab;
    double rc = fmin(fmax(ro, rh->ro_lo[k]), rh->ro_hi[k]) / HP_MM_PER_M, ri, dPdri;
    if (hp_iab_ri(b, rc, &ri) != HP_OK || hp_iab_ik_derivs(b, ri, P, &dPdri, NULL) != HP_OK)
        return 0;
    /* Outside the box the value is held (the box constraints pull the iterate back), so is
     * its slope. */
    *dP = (ro < rh->ro_lo[k] || ro > rh->ro_hi[k]) ? 0.0
                                                   : dPdri / HP_MM_PER_M * (rc / ri) * (rc / ri);
    return isfinite(*P) && isfinite(*dP);
}

/* Contact distances, Jacobians, pressures and the constraint values c (index
 * RH_NC·(n·j + k) + 0..3: ro − lo, hi − ro, Δ − u, Δ + u; without a rate limit the last two
 * are a large constant) of every row at z. 0 on failure. */
static int evaluate(hp_horizon_rh *rh, const double *z)
{
    const int n = rh->n;
    for (int j = 0; j < rh->N; ++j) {
        if (hpi_setup_contact_scaled(rh->L, rh->G, rh->level, z + 6 * j, rh->rho + n * j,
                                     rh->J + 6 * n * j) != HP_OK)
            return 0;
        for (int k = 0; k < n; ++k) {
            double ro = rh->rho[n * j + k], *c = rh->c + RH_NC * (n * j + k);
            if (!press_of_ro(rh, k, ro, &rh->P[n * j + k], &rh->dP[n * j + k])) return 0;
            double prev = j ? rh->P[n * (j - 1) + k] : rh->p_now[k];
            double u = (rh->P[n * j + k] - prev) * 1e-3, D = rh->delta[n * j + k] * 1e-3;
            if (!isfinite(D)) D = 1e6, u = 0;
            c[0] = ro - rh->ro_lo[k];
            c[1] = rh->ro_hi[k] - ro;
            c[2] = D - u;
            c[3] = D + u;
        }
    }
    return 1;
}

/* Adds c·a·bᵀ into the 6×6 block M. */
static void add_outer(double *M, double c, const double *a, const double *b)
{
    for (int r = 0; r < 6; ++r)
        for (int q = 0; q < 6; ++q) M[6 * r + q] += c * a[r] * b[q];
}

/* ∇u_j,k on row j (a) and on row j − 1 (b, zero for j = 0). */
static void rate_grad(const hp_horizon_rh *rh, int j, int k, double *a, double *b)
{
    const int n = rh->n;
    for (int i = 0; i < 6; ++i) {
        a[i] = rh->dP[n * j + k] * 1e-3 * rh->J[6 * (n * j + k) + i];
        b[i] = j ? -rh->dP[n * (j - 1) + k] * 1e-3 * rh->J[6 * (n * (j - 1) + k) + i] : 0.0;
    }
}

/* The reduced Newton system at the point evaluate() last saw, for barrier weight mu:
 *   (H + Σ_i (λ_i/s_i) ∇c_i∇c_iᵀ) dz = −g,  g = ∇f − Σ_i ∇c_i (mu − λ_i (c_i − s_i)) / s_i,
 * H the Gauss–Newton Hessian of the objective (halved, like g's objective part), in the
 * blocks A (diagonal), B (sub-diagonal) and g. */
static void normal_equations(hp_horizon_rh *rh, const double *z, double mu)
{
    const int n = rh->n, N = rh->N;
    memset(rh->A, 0, sizeof(double) * 36 * (size_t)N);
    memset(rh->B, 0, sizeof(double) * 36 * (size_t)N);
    memset(rh->g, 0, sizeof(double) * 6 * (size_t)N);
    for (int j = 0; j < N; ++j) {
        double *A = rh->A + 36 * j, *g = rh->g + 6 * j;
        for (int i = 0; i < 6; ++i) {
            A[7 * i] += 2.0 * rh->w[i];
            g[i] += 2.0 * rh->w[i] * (z[6 * j + i] - rh->d[6 * j + i]);
        }
        for (int k = 0; k < n; ++k) {
            const double *Jk = rh->J + 6 * (n * j + k);
            const int o = RH_NC * (n * j + k);
            double q[RH_NC], wt[RH_NC];
            for (int c = 0; c < RH_NC; ++c) {
                wt[c] = rh->lam[o + c] / rh->sl[o + c];
                q[c] = (mu - rh->lam[o + c] * (rh->c[o + c] - rh->sl[o + c])) / rh->sl[o + c];
            }
            /* box: ∇c0 = J, ∇c1 = −J */
            add_outer(A, wt[0] + wt[1], Jk, Jk);
            for (int i = 0; i < 6; ++i) g[i] -= (q[0] - q[1]) * Jk[i];
            /* rate (∇c2 = −∇u, ∇c3 = ∇u) and smoothness smooth·u² */
            double a[6], b[6];
            rate_grad(rh, j, k, a, b);
            double prev = j ? rh->P[n * (j - 1) + k] : rh->p_now[k];
            double u = (rh->P[n * j + k] - prev) * 1e-3;
            int lim = isfinite(rh->delta[n * j + k]);
            double cw = 2.0 * rh->hs.smooth + (lim ? wt[2] + wt[3] : 0.0);
            double ge = 2.0 * rh->hs.smooth * u - (lim ? q[3] - q[2] : 0.0);
            if (cw == 0.0 && ge == 0.0) continue;
            add_outer(A, cw, a, a);
            for (int i = 0; i < 6; ++i) g[i] += ge * a[i];
            if (j) {
                add_outer(rh->A + 36 * (j - 1), cw, b, b);
                add_outer(rh->B + 36 * j, cw, a, b);
                for (int i = 0; i < 6; ++i) rh->g[6 * (j - 1) + i] += ge * b[i];
            }
        }
    }
}

/* In-place Cholesky of a symmetric positive definite 6×6 block (lower triangle kept). */
static int chol6(double *M)
{
    for (int c = 0; c < 6; ++c) {
        double s = M[7 * c];
        for (int q = 0; q < c; ++q) s -= M[6 * c + q] * M[6 * c + q];
        if (!(s > 0)) return 0;
        M[7 * c] = sqrt(s);
        for (int r = c + 1; r < 6; ++r) {
            double t = M[6 * r + c];
            for (int q = 0; q < c; ++q) t -= M[6 * r + q] * M[6 * c + q];
            M[6 * r + c] = t / M[7 * c];
        }
    }
    return 1;
}

/* x := L⁻¹ x (trans 0) or L⁻ᵀ x (trans 1) for a 6×6 Cholesky factor L. */
static void tri6(const double *L, double *x, int trans)
{
    if (!trans) {
        for (int r = 0; r < 6; ++r) {
            for (int q = 0; q < r; ++q) x[r] -= L[6 * r + q] * x[q];
            x[r] /= L[7 * r];
        }
    } else {
        for (int r = 5; r >= 0; --r) {
            for (int q = r + 1; q < 6; ++q) x[r] -= L[6 * q + r] * x[q];
            x[r] /= L[7 * r];
        }
    }
}

/* Solves the block-tridiagonal system (A, B) dz = −g by block Cholesky; A and B are
 * overwritten by the factors (A_j → L_jj, B_j → L_j,j−1). */
static int solve_banded(hp_horizon_rh *rh)
{
    const int N = rh->N;
    for (int j = 0; j < N; ++j) {
        double *A = rh->A + 36 * j;
        if (j) {
            double *Bj = rh->B + 36 * j;
            const double *Lp = rh->A + 36 * (j - 1);
            for (int r = 0; r < 6; ++r) tri6(Lp, Bj + 6 * r, 0); /* row r of B L⁻ᵀ */
            for (int r = 0; r < 6; ++r)
                for (int q = 0; q <= r; ++q) {
                    double s = 0;
                    for (int i = 0; i < 6; ++i) s += Bj[6 * r + i] * Bj[6 * q + i];
                    A[6 * r + q] -= s;
                }
        }
        for (int r = 0; r < 6; ++r)
            for (int q = r + 1; q < 6; ++q) A[6 * r + q] = A[6 * q + r];
        if (!chol6(A)) return 0;
    }
    double *y = rh->dz;
    for (int j = 0; j < N; ++j) {
        for (int i = 0; i < 6; ++i) y[6 * j + i] = -rh->g[6 * j + i];
        if (j)
            for (int r = 0; r < 6; ++r)
                for (int q = 0; q < 6; ++q)
                    y[6 * j + r] -= rh->B[36 * j + 6 * r + q] * y[6 * (j - 1) + q];
        tri6(rh->A + 36 * j, y + 6 * j, 0);
    }
    for (int j = N - 1; j >= 0; --j) {
        if (j + 1 < N)
            for (int r = 0; r < 6; ++r)
                for (int q = 0; q < 6; ++q)
                    y[6 * j + r] -= rh->B[36 * (j + 1) + 6 * q + r] * y[6 * (j + 1) + q];
        tri6(rh->A + 36 * j, y + 6 * j, 1);
    }
    for (int i = 0; i < 6 * N; ++i)
        if (!isfinite(y[i])) return 0;
    return 1;
}

/* Largest step in (0, 1] keeping v + α dv >= (1 − RH_BOUNDARY) v. */
static double to_boundary(const double *v, const double *dv, int m)
{
    double alpha = 1.0;
    for (int i = 0; i < m; ++i)
        if (dv[i] < 0) alpha = fmin(alpha, -RH_BOUNDARY * v[i] / dv[i]);
    return alpha;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* At most rh_max_iter primal-dual interior-point iterations from rh->z, and none started
 * after the planner's max_time (half of it: hp_plan gets the rest). Returns how many ran when
 * the time budget stopped it before it converged or used them all, else -1: its plan then
 * depends on the machine's speed, and the row says so. A budget below a nanosecond (the
 * clock's resolution) stops it before the first iteration, always. */
static int interior_point(hp_horizon_rh *rh)
{
    const int n = rh->n, m = RH_NC * n * rh->N;
    const double budget = 0.5 * rh->s.max_time, t_end = now_s() + budget;
    if (!evaluate(rh, rh->z)) return -1;
    for (int i = 0; i < m; ++i) {
        rh->sl[i] = fmax(rh->c[i], RH_S_MIN);
        rh->lam[i] = RH_MU0 / rh->sl[i];
    }
    for (int it = 0; it < rh->hs.rh_max_iter; ++it) {
        if (budget < 1e-9 || now_s() >= t_end) return it;
        double gap = 0;
        for (int i = 0; i < m; ++i) gap += rh->sl[i] * rh->lam[i];
        double mu = RH_SIGMA * gap / m;
        normal_equations(rh, rh->z, mu);
        if (!solve_banded(rh)) return -1;
        /* ds = ∇cᵀdz + (c − s), dλ = (mu − sλ − λ ds)/s */
        for (int j = 0; j < rh->N; ++j)
            for (int k = 0; k < n; ++k) {
                const int o = RH_NC * (n * j + k);
                const double *Jk = rh->J + 6 * (n * j + k), *dzj = rh->dz + 6 * j;
                double a[6], b[6], dr = 0, du = 0;
                rate_grad(rh, j, k, a, b);
                for (int i = 0; i < 6; ++i) {
                    dr += Jk[i] * dzj[i];
                    du += a[i] * dzj[i] + (j ? b[i] * rh->dz[6 * (j - 1) + i] : 0.0);
                }
                if (!isfinite(rh->delta[n * j + k])) du = 0;
                const double dc[RH_NC] = {dr, -dr, -du, du};
                for (int c = 0; c < RH_NC; ++c) {
                    rh->ds[o + c] = dc[c] + rh->c[o + c] - rh->sl[o + c];
                    rh->dl[o + c] = (mu - rh->sl[o + c] * rh->lam[o + c] -
                                     rh->lam[o + c] * rh->ds[o + c]) /
                                    rh->sl[o + c];
                }
            }
        double ap = to_boundary(rh->sl, rh->ds, m), ad = to_boundary(rh->lam, rh->dl, m);
        for (int i = 0; i < 6 * rh->N; ++i) rh->zt[i] = rh->z[i] + ap * rh->dz[i];
        if (!evaluate(rh, rh->zt)) {
            evaluate(rh, rh->z); /* keep the last point that evaluated */
            return -1;
        }
        memcpy(rh->z, rh->zt, sizeof(double) * 6 * (size_t)rh->N);
        double step = 0;
        for (int i = 0; i < 6 * rh->N; ++i) step = fmax(step, fabs(ap * rh->dz[i]));
        gap = 0;
        for (int i = 0; i < m; ++i) {
            rh->sl[i] += ap * rh->ds[i];
            rh->lam[i] += ad * rh->dl[i];
            gap += rh->sl[i] * rh->lam[i];
        }
        if (gap / m < RH_GAP_TOL && step < RH_STEP_TOL) return -1;
    }
    return -1;
}

/* The predicted desired poses of rows 0..N−1 and their rate limits (row 0: dt0). */
static void predict(hp_horizon_rh *rh, double dt0)
{
    const int h = rh->hist_n - 1; /* index of the newest entry */
    double v[6] = {0}, dtp = dt0;
    int m = h < rh->hs.velocity_rows - 1 ? h : rh->hs.velocity_rows - 1;
    if (m >= 1) {
        double span = rh->hist_t[h] - rh->hist_t[h - m];
        dtp = span / m;
        if (rh->hs.prediction == HP_PREDICT_VELOCITY)
            for (int i = 0; i < 6; ++i) v[i] = (rh->hist_d[h][i] - rh->hist_d[h - m][i]) / span;
    }
    for (int j = 0; j < rh->N; ++j) {
        for (int i = 0; i < 6; ++i) {
            double s = i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD;
            rh->d[6 * j + i] = rh->commanded[i] ? (rh->hist_d[h][i] + v[i] * dtp * j) * s : 0.0;
        }
        hpi_horizon_row_rates(rh->rate_scene, rh->n, &rh->hs, j ? dtp : dt0, rh->delta + rh->n * j);
    }
}

hp_error hp_horizon_rh_create(const hp_layout *L, const hp_settings *settings,
                              const hp_horizon_settings *hs, const double *p_start,
                              hp_horizon_rh **out, hp_diag *d)
{
    if (out) *out = NULL;
    if (!L || !out) return hp_diag_set(d, HP_ERR_NULL, "receding: NULL argument");
    hp_horizon_rh *rh = calloc(1, sizeof *rh);
    if (!rh) return hp_diag_set(d, HP_ERR_NOMEM, "receding: out of memory");
    if (settings) rh->s = *settings;
    else hp_settings_default(&rh->s);
    rh->s.backend = HP_BACKEND_REALTIME;
    if (hs) rh->hs = *hs;
    else hp_horizon_settings_default(&rh->hs);
    hp_error e = hp_horizon_settings_validate(&rh->hs, d);
    if (e == HP_OK) e = hp_planner_create(L, &rh->s, &rh->p, d);
    if (e == HP_OK && hp_planner_level(rh->p) == HP_LEVEL_LOAD)
        e = hpi_horizon_load_refused("receding", d);
    if (e != HP_OK) goto fail;
    rh->L = hp_planner_layout(rh->p);
    rh->G = hpi_planner_geom(rh->p);
    rh->level = hp_planner_level(rh->p);
    rh->n = rh->L->n;
    rh->N = rh->hs.horizon;
    hpi_horizon_scene_rates(rh->L, rh->rate_scene);
    hp_static_bounds sb;
    hp_problem pb;
    memset(&pb, 0, sizeof pb);
    memcpy(rh->commanded, hp_planner_identifiable(rh->p)->commanded, sizeof rh->commanded);
    if ((e = hpi_setup_static_bounds(rh->L, &sb, d)) != HP_OK ||
        (e = hpi_setup_cycle_bounds(rh->L, &sb, NULL, 0, &pb, NULL, NULL, d)) != HP_OK)
        goto fail;
    for (int k = 0; k < rh->n; ++k) {
        rh->ro_lo[k] = pb.ro_lo[k];
        rh->ro_hi[k] = pb.ro_hi[k];
    }
    for (int i = 0; i < 6; ++i) {
        double w = hpi_horizon_weight(&rh->s, rh->commanded, i);
        rh->w[i] = w > 0 ? w : 1.0;
    }
    if (p_start) memcpy(rh->p_now, p_start, sizeof(double) * (size_t)rh->n);
    else if ((e = hp_horizon_nominal_pressures(rh->L, rh->p_now, d)) != HP_OK) goto fail;
    if ((e = hp_planner_set_previous(rh->p, rh->p_now)) != HP_OK) {
        hp_diag_set(d, e, "start pressures: %s", hp_planner_error(rh->p));
        goto fail;
    }
    /* The pose the start pressures hold: where a cold plan starts. */
    double ro[HP_MAX_BLADDERS];
    for (int k = 0; k < rh->n && e == HP_OK; ++k) {
        double ri;
        e = hp_iab_fk_limit(&rh->L->bladders[k].iab, &sb.limit[k], rh->p_now[k], &ri);
        if (e == HP_OK) e = hp_iab_ro(&rh->L->bladders[k].iab, ri, &ro[k]);
    }
    /* In the commanded components, as the planner's set_previous fits them: a layout that
     * cannot observe all six (five bladders) has no fit in all six. */
    const double zero[6] = {0};
    if (e == HP_OK)
        e = hp_contact_fit(rh->L, rh->level, ro, rh->commanded, zero, rh->applied.achieved, NULL,
                           NULL);
    if (e != HP_OK) {
        hp_diag_set(d, e, "start pressures: no pose holds them (%s)", hp_error_message(e));
        goto fail;
    }
    *out = rh;
    return HP_OK;
fail:
    hp_horizon_rh_destroy(rh);
    return e;
}

void hp_horizon_rh_destroy(hp_horizon_rh *rh)
{
    if (!rh) return;
    hp_planner_destroy(rh->p);
    free(rh);
}

hp_error hp_horizon_rh_step(hp_horizon_rh *rh, double t, const double desired[6], hp_result *result)
{
    if (!rh || !desired || !result) return HP_ERR_NULL;
    if (!isfinite(t) || (rh->started && !(t > rh->last_t))) return HP_ERR_INVALID;
    double dt0 = rh->started ? t - rh->last_t : rh->hs.start_interval_s;
    int finite = 1;
    for (int i = 0; i < 6; ++i) finite = finite && isfinite(desired[i]);
    double target[6], xc[6];
    rh->budget_stopped = 0;
    memcpy(target, desired, sizeof target);
    memcpy(xc, desired, sizeof xc);
    /* The horizon plans the commanded part of each desired pose (what hp_plan aims at): the
     * raw components of a pose with a part the layout cannot observe are another pose. */
    if (finite && hp_pose_commanded_part(rh->L, hp_planner_identifiable(rh->p), rh->level, desired,
                                         xc) != HP_OK)
        finite = 0; /* hp_plan refuses such a row itself */
    if (finite) {
        if (rh->hist_n == HP_HORIZON_MAX) {
            memmove(rh->hist_t, rh->hist_t + 1, sizeof(double) * (HP_HORIZON_MAX - 1));
            memmove(rh->hist_d, rh->hist_d + 1, sizeof(double) * 6 * (HP_HORIZON_MAX - 1));
            rh->hist_n--;
        }
        rh->hist_t[rh->hist_n] = t;
        memcpy(rh->hist_d[rh->hist_n], xc, sizeof rh->hist_d[0]);
        rh->hist_n++;
        predict(rh, dt0);
        if (!rh->started) {
            /* the pose the start pressures hold, over the whole horizon */
            for (int j = 0; j < rh->N; ++j)
                for (int i = 0; i < 6; ++i)
                    rh->z[6 * j + i] = rh->applied.achieved[i] *
                                       (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD);
        }
        int done = interior_point(rh);
        rh->budget_stopped = done >= 0;
        if (done >= 0)
            snprintf(rh->why, sizeof rh->why,
                     "time-limit: the receding horizon's solve stopped at its time budget (half "
                     "of solver.max_time_s = %g s) after %d of at most %d iterations; the row "
                     "depends on the machine's speed",
                     rh->s.max_time, done, rh->hs.rh_max_iter);
        int aim_desired = 1;
        for (int i = 0; i < 6; ++i) {
            double s = i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD;
            target[i] = rh->commanded[i] ? rh->z[i] / s : 0.0;
            aim_desired &= !rh->commanded[i] || fabs(rh->z[i] - xc[i] * s) <= HP_HORIZON_AIM_TOL;
        }
        if (aim_desired) memcpy(target, desired, sizeof target);
    }
    double delta[HP_MAX_BLADDERS];
    hpi_horizon_row_rates(rh->rate_scene, rh->n, &rh->hs, dt0, delta);
    hp_error e = hp_planner_set_rate_max(rh->p, delta);
    if (e == HP_OK) e = hp_plan(rh->p, target, result);
    if (e != HP_OK) return e;
    rh->started = 1;
    rh->last_t = t;
    for (int k = 0; k < rh->n; ++k) rh->p_now[k] = result->bladders[k].pressure;
    rh->applied = *result;
    /* The row's own desired pose, error and label, not the planned target's: a row off its
     * desired pose is held there by a limit (now, or on the rows planned ahead). */
    memcpy(result->desired, desired, sizeof result->desired);
    if (result->status == HP_STATUS_REACHED || result->status == HP_STATUS_CLOSEST ||
        result->status == HP_STATUS_UNCOMMANDED) {
        result->status = hpi_horizon_label(rh->commanded, desired, xc, result->achieved,
                                           rh->s.tolerance, &result->pose_error);
        for (int i = 0; i < 6; ++i) result->uncommanded[i] = desired[i] - xc[i];
        /* A plan the time budget cut short is not reproducible: labelled as batch labels a
         * row its budget stopped (the pressures are hp_plan's, inside every limit). */
        if (rh->budget_stopped) result->status = HP_STATUS_TIME_LIMIT;
    }
    /* Shift the plan by one row and start the next call from it (the new last row repeats
     * the old one); with N = 1 the applied pose is the start. */
    if (rh->N > 1) {
        memmove(rh->z, rh->z + 6, sizeof(double) * 6 * (size_t)(rh->N - 1));
    } else {
        for (int i = 0; i < 6; ++i)
            rh->z[i] = result->achieved[i] * (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD);
    }
    return HP_OK;
}

const char *hpi_horizon_rh_reason(const hp_horizon_rh *rh)
{
    if (rh->budget_stopped) return rh->why;
    const char *e = hp_planner_error(rh->p);
    return *e ? e : hp_planner_note(rh->p);
}

/* The receding-horizon plan of a whole trace: one hp_horizon_rh_step per row. */
hp_error hp_horizon_receding(const hp_layout *L, const hp_settings *settings,
                             const hp_horizon_settings *hs, const hp_trace_row *rows, size_t T,
                             const double *p_start, hp_horizon_row *out, hp_diag *d)
{
    if (!L || (T && (!rows || !out))) return hp_diag_set(d, HP_ERR_NULL, "receding: NULL argument");
    hp_horizon_rh *rh = NULL;
    hp_error e = hpi_horizon_check_rows_at(L, rows, T, d);
    if (e != HP_OK) return e;
    e = hp_horizon_rh_create(L, settings, hs, p_start, &rh, d);
    if (e != HP_OK) return e;
    if (d) d->text[0] = '\0';
    int refused = 0;
    for (size_t t = 0; t < T; ++t) {
        hp_result r;
        e = hp_horizon_rh_step(rh, rows[t].t, rows[t].correction, &r);
        if (e != HP_OK) {
            hp_diag_set(d, e, "line %ld: t_s: not after the previous row", rows[t].line);
            break;
        }
        hpi_horizon_note_refusal(d, &refused, &r, rows[t].line, hpi_horizon_rh_reason(rh));
        hpi_horizon_row_from_result(rows + t, &r, L->n, out + t);
    }
    hp_horizon_rh_destroy(rh);
    return e;
}
