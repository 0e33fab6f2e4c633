/* The receding-horizon planner: at every row, the next N rows under a predicted desired pose,
 * solved in a workspace allocated at create; the first row is applied through hp_plan.
 *
 * The horizon problem is the offline one (hp_horizon.h) over N rows, with the radii
 * eliminated (ro_k = ρ_k(ξ); ri and P follow on the stable branch):
 *   minimise  Σ_j Σ_i w_i (z_j,i − d_j,i)² + smooth Σ_j,k u_j,k²          z_j scaled (mm, deg)
 *   s.t.      ro_lo_k <= ρ_k(z_j) <= ro_hi_k,   |u_j,k| <= Δ_j,k / 1 kPa
 * with u_j,k = (P_j,k − P_j−1,k) / 1 kPa (row 0 against the pressures held now). It is
 * solved by a primal-dual interior-point method (slacks s and multipliers λ for the 4·n·N
 * inequalities, started inside, fraction-to-the-boundary steps), with the constraints
 * linearised at every iterate (exact contact Jacobians, dP/dro of the bladder model) and a
 * Gauss–Newton Hessian of the objective. Eliminating s and λ leaves the normal matrix
 * H + Σ_i (λ_i/s_i) ∇c_i ∇c_iᵀ, block tridiagonal (row j couples only with j ± 1 through the
 * rate and smoothness terms), so each step is a block Cholesky in O(N · 6³): no dense 6N × 6N
 * matrix. Each iteration is Mehrotra's predictor–corrector (one factorisation, two solves),
 * and a call starts from the previous call's plan and multipliers shifted by one row: on the
 * horizon traces 3–5 iterations a call where a fixed centring from cold multipliers took
 * 11–14 (tests/horizon/test_rh_solve.c); each row's contact distances start from the row's
 * last evaluation, shifted with it (one root-find step a distance, 2.5 from the bracket). At
 * most rh_max_iter iterations, aimed to end within four fifths of the planner's max_time from
 * the call's start (none after the first begun that this call's longest would carry past
 * it). The iterate
 * need not be feasible: the applied first row goes through hp_plan (realtime backend, this
 * row's rate limits), which keeps every limit exactly. Uncommanded pose components are
 * pulled to 0 with unit weight, as the planner holds them. */
#define _POSIX_C_SOURCE 200809L
#include "horizon/horizon_internal.h"
#include "iab/iab_internal.h"
#include "planner/clock.h"
#include "planner/problem_setup.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RH_SIGMA 0.1      /* centring: the next barrier weight is this times the mean s·λ */
#define RH_BOUNDARY 0.995 /* fraction-to-the-boundary of a step */
#define RH_S_MIN 1e-3     /* smallest starting slack (mm or kPa) */
#define RH_MU0 1e-3       /* starting complementarity s·λ */
#define RH_WARM_S 1e-2    /* smallest slack of a warm start (mm or kPa) */
#define RH_WARM_MU 1e-3   /* smallest s·λ of a warm start */
#define RH_GAP_TOL 1e-10  /* stop when the mean s·λ is below this ... */
#define RH_STEP_TOL 1e-9  /* ... and the last step moved no pose by more (mm or degrees) */
/* ... or, with the same gap, the first row (the one applied) is estimated within
 * RH_LEFT_FIRST of where it converges and the last step moved no row by more than
 * RH_STEP_REST (mm or degrees). Near the end the pose converges linearly (the Gauss–Newton
 * matrix leaves out the constraints' curvature), so the distance left is estimated from the
 * contraction of the first row's last two steps. 1e-7 is a tenth of the distance at which
 * the applied row aims at the desired pose itself (HP_HORIZON_AIM_TOL); the later rows only
 * start the next call, which corrects them. Against the reference solve the applied rows
 * agree to 2.2e-7 mm/deg on the horizon traces (tests/horizon/test_rh_solve.c). */
#define RH_LEFT_FIRST 1e-7
#define RH_STEP_REST 1e-3
/* The reference solve of the tests (hpi_horizon_rh_reference): cold, to these. */
#define RH_REF_MAX_ITER 100
#define RH_REF_GAP_TOL 1e-13
#define RH_REF_STEP_TOL 1e-11
/* The share of the settings' max_time, from the call's start, within which the interior
 * point aims to end; the applied row's hp_plan runs after it (a few microseconds at N = 10,
 * a twentieth of a 100 µs budget, under its own max_time). Half left the solve two
 * iterations at 100 µs, and tracked worse (docs/horizon.md, A deadline). */
#define RH_SOLVE_SHARE 0.8
/* Rows of desired poses kept for the predictions: the velocity's at most HP_HORIZON_MAX,
 * the periodic fit's two periods and the crossings before them (12.8 s at 10 Hz, three
 * breathing cycles of 4 s). */
#define RH_HIST 128
#define RH_NC 4 /* inequalities per bladder and row: ro >= lo, ro <= hi, ±u <= Δ */

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
    hp_iab_s S[HP_MAX_BLADDERS];        /* the bladders validated once, at create */
    double rate_scene[HP_MAX_BLADDERS]; /* [Pa] the scene's per-row limits (the planner's
                                           copy holds the last row's allowance) */
    double p_now[HP_MAX_BLADDERS];      /* pressures the bladders hold [Pa] */
    double last_t;
    int started;
    int hist_n; /* commanded parts of the desired poses, kept for the predictions */
    double hist_t[RH_HIST], hist_d[RH_HIST][6];
    double z[HP_HORIZON_MAX * 6], zt[HP_HORIZON_MAX * 6], dz[HP_HORIZON_MAX * 6];
    double d[HP_HORIZON_MAX * 6];
    double delta[HP_HORIZON_MAX * HP_MAX_BLADDERS];
    double rho[HP_HORIZON_MAX * HP_MAX_BLADDERS], J[HP_HORIZON_MAX * HP_MAX_BLADDERS * 6];
    double P[HP_HORIZON_MAX * HP_MAX_BLADDERS], dP[HP_HORIZON_MAX * HP_MAX_BLADDERS];
    /* ∇u_j,k = α_j,k J_j,k − α_j−1,k J_j−1,k with α = (dP/dro) / 1 kPa: every gradient of
     * a bladder's constraints lies along its contact Jacobian, so the normal matrix, its
     * right-hand side and the slack steps are sums of scalars times J (one outer product per
     * bladder and row, not three). */
    double alpha[HP_HORIZON_MAX * HP_MAX_BLADDERS];
    /* The surface level's root-find state of each bladder and row at the last pose its row
     * was evaluated at: the next evaluation of the row starts from it (an iterate moves a
     * row little), in fewer steps to the same distance to rounding. Shifted with the rows,
     * so that a call starts each row from that row's own pose; unshifted, the neighbouring
     * row's pose served as well on the horizon traces (1.00–1.01 steps a distance either
     * way), so the tests hold the states kept across calls, not the shift. The reference
     * solve of the tests starts every distance from its bracket. */
    hp_kin_dist_warm dw[HP_HORIZON_MAX * HP_MAX_BLADDERS];
    double wk[HP_HORIZON_MAX * HP_MAX_BLADDERS]; /* per bladder and row, within one step */
    double g[HP_HORIZON_MAX * 6];
    double A[HP_HORIZON_MAX * 36], B[HP_HORIZON_MAX * 36]; /* diagonal / sub-diagonal blocks */
    hp_result applied;     /* the last applied answer (its pose starts a cold plan) */
    int budget_stopped;    /* the last call's horizon solve stopped at its time budget */
    double t_call;         /* [s] CLOCK_MONOTONIC at the call's start: its budget's origin */
    char why[HP_DIAG_MAX]; /* ... and what it says about it */
    double c[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS];   /* constraint values (>= 0 wanted) */
    double sl[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS];  /* slacks */
    double lam[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS]; /* multipliers */
    double ds[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS];
    double dl[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS];
    double tgt[RH_NC * HP_HORIZON_MAX * HP_MAX_BLADDERS]; /* complementarity targets */
    int warm;        /* sl and lam hold the previous call's answer, shifted by one row */
    int geom_ok;     /* rho, J, P, dP and du are those of every row of z */
    long iterations; /* interior-point iterations of every call so far (tests) */
    unsigned long dist_steps, dists; /* ellipsoid distances' root-find steps, and count (tests) */
    int reference;                   /* solve every call cold to a tight tolerance (tests) */
};

/* P [Pa] and dP/dro [Pa/mm] at outer radius ro (mm), ro held inside the box. */
static int press_of_ro(const hp_horizon_rh *rh, int k, double ro, double *P, double *dP)
{
    const hp_iab_s *b = &rh->S[k];
    double rc = ro < rh->ro_lo[k] ? rh->ro_lo[k] : ro > rh->ro_hi[k] ? rh->ro_hi[k] : ro;
    rc /= HP_MM_PER_M;
    double ri, ris, dPdri;
    /* hp_iab_ri, then hp_iab_ik and its slope on the bladder validated at create, with the
     * outer radius the pressure needs taken from rc (one Newton step of the cube root
     * instead of a cube root: the same bits but within 1e-7 ulp of a rounding midpoint). */
    if (hpi_iab_s_ri_m(b, rc, &ri) != HP_OK || hpi_iab_s_radius(b, ri, &ris) != HP_OK ||
        hpi_iab_s_ik_near_m(b, ri, rc, P) != HP_OK ||
        hpi_iab_s_slopes(b, ris, rc * b->scale, &dPdri, NULL) != HP_OK)
        return 0;
    dPdri *= b->scale;
    /* Outside the box the value is held (the box constraints pull the iterate back), so is
     * its slope. */
    *dP = (ro < rh->ro_lo[k] || ro > rh->ro_hi[k]) ? 0.0
                                                   : dPdri / HP_MM_PER_M * (rc / ri) * (rc / ri);
    return isfinite(*P) && isfinite(*dP);
}

/* Contact distances, Jacobians, pressures and dP/dro (α) of row j at its pose zj: what a
 * row's pose alone decides. 0 on failure. */
static int row_geometry(hp_horizon_rh *rh, int j, const double *zj)
{
    const int n = rh->n;
    hp_kin_dist_warm *w = rh->dw + n * j;
    if (rh->reference) hpi_kin_dist_warm_cold(w, n); /* every distance from its bracket */
    if (hpi_setup_contact_scaled_warm(rh->L, rh->G, rh->level, zj, w, rh->rho + n * j,
                                      rh->J + 6 * n * j) != HP_OK)
        return 0;
    rh->dists += (unsigned long)n; /* counted with their steps: a failed row adds neither */
    for (int k = 0; k < n; ++k) rh->dist_steps += (unsigned long)w[k].evals;
    for (int k = 0; k < n; ++k) {
        const int o = n * j + k;
        if (!press_of_ro(rh, k, rh->rho[o], &rh->P[o], &rh->dP[o])) return 0;
        rh->alpha[o] = rh->dP[o] * 1e-3;
    }
    return 1;
}

/* The constraint values c (index RH_NC·(n·j + k) + 0..3: ro − lo, hi − ro, Δ − u, Δ + u;
 * without a rate limit the last two are a large constant) of every row, from the rows'
 * geometry, the pressures held now and the allowances. */
static void constraints(hp_horizon_rh *rh)
{
    const int n = rh->n;
    for (int j = 0; j < rh->N; ++j)
        for (int k = 0; k < n; ++k) {
            double ro = rh->rho[n * j + k], *c = rh->c + RH_NC * (n * j + k);
            double prev = j ? rh->P[n * (j - 1) + k] : rh->p_now[k];
            double u = (rh->P[n * j + k] - prev) * 1e-3, D = rh->delta[n * j + k] * 1e-3;
            if (!isfinite(D)) D = 1e6, u = 0;
            c[0] = ro - rh->ro_lo[k];
            c[1] = rh->ro_hi[k] - ro;
            c[2] = D - u;
            c[3] = D + u;
        }
}

/* The geometry of every row at z and the constraint values. 0 on failure, and the geometry
 * then matches no pose (rh->geom_ok cleared). */
static int evaluate(hp_horizon_rh *rh, const double *z)
{
    rh->geom_ok = 0;
    for (int j = 0; j < rh->N; ++j)
        if (!row_geometry(rh, j, z + 6 * j)) return 0;
    constraints(rh);
    return 1;
}

/* Adds c·a·bᵀ into the 6×6 block M. restrict (here and below): a block is never one of the
 * vectors (the blocks and the Jacobians are separate arrays), which lets the compiler vectorise
 * the rows: 6 % fewer instructions a call at N = 10, the same bits. */
static void add_outer(double *restrict M, double c, const double *restrict a,
                      const double *restrict b)
{
    for (int r = 0; r < 6; ++r)
        for (int q = 0; q < 6; ++q) M[6 * r + q] += c * a[r] * b[q];
}

/* Adds c·a·aᵀ into the lower triangle of the symmetric 6×6 block M: the factorisation reads
 * nothing else, so the upper half is not formed. */
static void add_outer_lower(double *restrict M, double c, const double *restrict a)
{
    for (int r = 0; r < 6; ++r)
        for (int q = 0; q <= r; ++q) M[6 * r + q] += c * a[r] * a[q];
}

/* The matrix of the reduced Newton system at the point evaluate() last saw:
 *   H + Σ_i (λ_i/s_i) ∇c_i∇c_iᵀ,
 * H the Gauss–Newton Hessian of the objective (halved, like the gradient's objective part),
 * in the blocks A (diagonal, lower triangles) and B (sub-diagonal). It depends on the
 * iterate alone, so both solves of an iteration (predictor and corrector) share one
 * factorisation. A bladder's box rows (∇c = ±J) and its rate rows (∇u, along J of two
 * consecutive rows) fold into one weight per row's J Jᵀ and one per J_j J_j−1ᵀ. */
static void normal_matrix(hp_horizon_rh *rh)
{
    const int n = rh->n, N = rh->N;
    double *cw = rh->wk; /* weight of ∇u∇uᵀ: smoothness, and the rate rows when limited */
    for (int o = 0; o < n * N; ++o) {
        const double *lam = rh->lam + RH_NC * o, *sl = rh->sl + RH_NC * o;
        cw[o] = 2.0 * rh->hs.smooth +
                (isfinite(rh->delta[o]) ? lam[2] / sl[2] + lam[3] / sl[3] : 0.0);
    }
    memset(rh->B, 0, sizeof(double) * 36 * (size_t)N);
    for (int j = 0; j < N; ++j) {
        double *A = rh->A + 36 * j;
        memset(A, 0, sizeof(double) * 36);
        for (int i = 0; i < 6; ++i) A[7 * i] = 2.0 * rh->w[i];
        for (int k = 0; k < n; ++k) {
            const int o = n * j + k;
            const double *lam = rh->lam + RH_NC * o, *sl = rh->sl + RH_NC * o, a = rh->alpha[o];
            double W = lam[0] / sl[0] + lam[1] / sl[1] +
                       (cw[o] + (j + 1 < N ? cw[o + n] : 0.0)) * a * a;
            add_outer_lower(A, W, rh->J + 6 * o);
            if (j)
                add_outer(rh->B + 36 * j, -cw[o] * a * rh->alpha[o - n], rh->J + 6 * o,
                          rh->J + 6 * (o - n));
        }
    }
}

/* The right-hand side g of the reduced Newton system (H + Σ_i (λ_i/s_i) ∇c_i∇c_iᵀ) dz = −g
 * for complementarity targets t_i (rh->tgt: s_i λ_i → t_i):
 *   g = ∇f − Σ_i ∇c_i (t_i − λ_i (c_i − s_i)) / s_i. */
static void normal_rhs(hp_horizon_rh *rh, const double *z)
{
    const int n = rh->n, N = rh->N;
    double *ge = rh->wk; /* the coefficient of ∇u: smoothness and the rate rows */
    for (int j = 0; j < N; ++j)
        for (int k = 0; k < n; ++k) {
            const int o = n * j + k, b = RH_NC * o;
            double prev = j ? rh->P[o - n] : rh->p_now[k];
            double u = (rh->P[o] - prev) * 1e-3;
            ge[o] = 2.0 * rh->hs.smooth * u;
            if (isfinite(rh->delta[o]))
                ge[o] -= (rh->tgt[b + 3] - rh->lam[b + 3] * (rh->c[b + 3] - rh->sl[b + 3])) /
                             rh->sl[b + 3] -
                         (rh->tgt[b + 2] - rh->lam[b + 2] * (rh->c[b + 2] - rh->sl[b + 2])) /
                             rh->sl[b + 2];
        }
    for (int j = 0; j < N; ++j) {
        double *g = rh->g + 6 * j;
        for (int i = 0; i < 6; ++i) g[i] = 2.0 * rh->w[i] * (z[6 * j + i] - rh->d[6 * j + i]);
        for (int k = 0; k < n; ++k) {
            const int o = n * j + k, b = RH_NC * o;
            double q0 = (rh->tgt[b] - rh->lam[b] * (rh->c[b] - rh->sl[b])) / rh->sl[b];
            double q1 = (rh->tgt[b + 1] - rh->lam[b + 1] * (rh->c[b + 1] - rh->sl[b + 1])) /
                        rh->sl[b + 1];
            double gam = q1 - q0 + (ge[o] - (j + 1 < N ? ge[o + n] : 0.0)) * rh->alpha[o];
            const double *Jk = rh->J + 6 * o;
            for (int i = 0; i < 6; ++i) g[i] += gam * Jk[i];
        }
    }
}

/* In-place Cholesky of a symmetric positive definite 6×6 block (lower triangle read and
 * kept). */
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

/* Block Cholesky of the block-tridiagonal matrix (A, B): A_j → L_jj, B_j → L_j,j−1. */
static int factor_banded(hp_horizon_rh *rh)
{
    for (int j = 0; j < rh->N; ++j) {
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
        if (!chol6(A)) return 0;
    }
    return 1;
}

/* dz = −(L Lᵀ)⁻¹ g with the factors of factor_banded. */
static int solve_banded(hp_horizon_rh *rh)
{
    const int N = rh->N;
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

/* The slack and multiplier steps of a pose step dz for the targets rh->tgt:
 *   ds = ∇cᵀdz + (c − s),  dλ = (t − sλ − λ ds)/s. */
static void slack_steps(hp_horizon_rh *rh)
{
    const int n = rh->n;
    double *dr = rh->wk; /* J_j,k · dz_j: the step of the contact distance */
    for (int j = 0; j < rh->N; ++j)
        for (int k = 0; k < n; ++k) {
            const int o = n * j + k, b = RH_NC * o;
            const double *Jk = rh->J + 6 * o, *dzj = rh->dz + 6 * j;
            double r = 0;
            for (int i = 0; i < 6; ++i) r += Jk[i] * dzj[i];
            dr[o] = r;
            double du = 0;
            if (isfinite(rh->delta[o]))
                du = rh->alpha[o] * r - (j ? rh->alpha[o - n] * dr[o - n] : 0.0);
            const double dc[RH_NC] = {r, -r, -du, du};
            for (int c = 0; c < RH_NC; ++c) {
                rh->ds[b + c] = dc[c] + rh->c[b + c] - rh->sl[b + c];
                rh->dl[b + c] = (rh->tgt[b + c] - rh->sl[b + c] * rh->lam[b + c] -
                                 rh->lam[b + c] * rh->ds[b + c]) /
                                rh->sl[b + c];
            }
        }
}

/* Largest step in (0, 1] keeping v + α dv >= (1 − tau) v. Every quotient is formed and the
 * ones of dv >= 0 discarded by a select, in RH_LANES running minima: no branch on the sign
 * of dv, which the processor cannot predict (half the rows' steps are negative), and the
 * lanes vectorise. A minimum does not depend on the order it is taken in: the same value as
 * a scan in row order, and the same bits but for a zero minimum reached as both +0 and −0
 * (a v <= −0), which slacks and multipliers kept positive never give. */
#define RH_LANES 4
static double to_boundary(const double *v, const double *dv, int m, double tau)
{
    double lane[RH_LANES] = {1.0, 1.0, 1.0, 1.0};
    int i = 0;
    for (; i + RH_LANES <= m; i += RH_LANES)
        for (int l = 0; l < RH_LANES; ++l) {
            double q = -tau * v[i + l] / dv[i + l];
            lane[l] = dv[i + l] < 0 && q < lane[l] ? q : lane[l];
        }
    for (; i < m; ++i) {
        double q = -tau * v[i] / dv[i];
        lane[0] = dv[i] < 0 && q < lane[0] ? q : lane[0];
    }
    double alpha = lane[0];
    for (int l = 1; l < RH_LANES; ++l) alpha = lane[l] < alpha ? lane[l] : alpha;
    return alpha;
}

/* The slacks and multipliers an interior-point solve starts from, at the point evaluate()
 * last saw. Cold: s = max(c, RH_S_MIN), s·λ = RH_MU0. Warm (the previous call's answer,
 * shifted by one row): its multipliers, with every slack at least RH_WARM_S and every
 * product s·λ at least RH_WARM_MU, so that a constraint the new row's data makes active or
 * inactive is not pinned at the boundary by the old answer. */
static void start_point(hp_horizon_rh *rh, int m, int warm)
{
    for (int i = 0; i < m; ++i) {
        rh->sl[i] = fmax(rh->c[i], warm ? RH_WARM_S : RH_S_MIN);
        rh->lam[i] = warm ? fmax(rh->lam[i], RH_WARM_MU / rh->sl[i]) : RH_MU0 / rh->sl[i];
    }
}

/* At most rh_max_iter primal-dual interior-point iterations from rh->z, aimed to end within
 * RH_SOLVE_SHARE of the planner's max_time from the call's start (hp_plan runs after it):
 * the first iteration begins while that share lasts, each later one only if the longest of
 * this call's iterations so far would end within it. An iteration is one evaluation of the N
 * rows, one factorisation and two solves, about the same work each time, so a call mostly
 * ends within its share rather than one whole iteration past it. It can still pass it by up
 * to one iteration: a first iteration begun just before the end (every call makes one, or
 * its plan would never follow a new target), an iteration longer than the longest before
 * it, a stall of the host. The estimate is this call's own, so a preempted iteration in one
 * call does not starve the next. Each iteration is
 * Mehrotra's predictor–corrector: one factorisation, an affine step (targets 0) that gives
 * the centring σ = (μ_aff/μ)³, and the corrected step (targets σμ − ds_aff·dλ_aff); the
 * reference solve of the tests takes the plain step (targets RH_SIGMA·μ) from a cold start.
 * Returns how many ran when the time budget stopped it before it converged or used them all,
 * else -1: its plan then depends on the machine's speed, and the row says so. A budget below
 * a nanosecond (the clock's resolution) stops it before the first iteration, always. */
static int interior_point(hp_horizon_rh *rh)
{
    const int n = rh->n, m = RH_NC * n * rh->N;
    const double budget = RH_SOLVE_SHARE * rh->s.max_time, t_end = rh->t_call + budget;
    const int max_iter = rh->reference ? RH_REF_MAX_ITER : rh->hs.rh_max_iter;
    const double gap_tol = rh->reference ? RH_REF_GAP_TOL : RH_GAP_TOL;
    const double step_tol = rh->reference ? RH_REF_STEP_TOL : RH_STEP_TOL;
    const int warm = rh->warm && !rh->reference;
    rh->warm = 0; /* until the slacks and multipliers are a solve's again */
    /* The geometry of the shifted plan is the last call's, shifted with it: only the
     * constraint values change (the pressures held now, the allowances). */
    if (rh->geom_ok) constraints(rh);
    else if (!(rh->geom_ok = evaluate(rh, rh->z))) return -1;
    start_point(rh, m, warm);
    double prev0 = INFINITY, longest = 0.0;
    for (int it = 0; it < max_iter; ++it) {
        const double t_it = hpi_plan_now();
        if (budget < 1e-9 || t_it + longest >= t_end) return it;
        rh->iterations++;
        double gap = 0;
        for (int i = 0; i < m; ++i) gap += rh->sl[i] * rh->lam[i];
        const double mu = gap / m;
        normal_matrix(rh);
        if (!factor_banded(rh)) return -1;
        double sigma = RH_SIGMA;
        if (!rh->reference) {
            for (int i = 0; i < m; ++i) rh->tgt[i] = 0.0;
            normal_rhs(rh, rh->z);
            if (!solve_banded(rh)) return -1;
            slack_steps(rh);
            double ap = to_boundary(rh->sl, rh->ds, m, 1.0),
                   ad = to_boundary(rh->lam, rh->dl, m, 1.0);
            double aff = 0;
            for (int i = 0; i < m; ++i)
                aff += (rh->sl[i] + ap * rh->ds[i]) * (rh->lam[i] + ad * rh->dl[i]);
            double r = fmin(aff / m / mu, 1.0);
            sigma = r * r * r;
        }
        for (int i = 0; i < m; ++i)
            rh->tgt[i] = sigma * mu - (rh->reference ? 0.0 : rh->ds[i] * rh->dl[i]);
        normal_rhs(rh, rh->z);
        if (!solve_banded(rh)) return -1;
        slack_steps(rh);
        /* Fraction to the boundary: RH_BOUNDARY, nearer 1 as μ vanishes (1 − μ, as Ipopt's
         * τ), so that the last steps are whole Newton steps: a fixed 0.995 leaves 0.5 % of
         * every step to the next iteration, and the step test then waits for it. */
        const double tau = rh->reference ? RH_BOUNDARY : fmax(RH_BOUNDARY, 1.0 - mu);
        double ap = to_boundary(rh->sl, rh->ds, m, tau), ad = to_boundary(rh->lam, rh->dl, m, tau);
        for (int i = 0; i < 6 * rh->N; ++i) rh->zt[i] = rh->z[i] + ap * rh->dz[i];
        if (!evaluate(rh, rh->zt)) {
            rh->geom_ok = evaluate(rh, rh->z); /* keep the last point that evaluated */
            return -1;
        }
        memcpy(rh->z, rh->zt, sizeof(double) * 6 * (size_t)rh->N);
        rh->geom_ok = 1;
        double step = 0, step0 = 0;
        for (int i = 0; i < 6 * rh->N; ++i) step = fmax(step, fabs(ap * rh->dz[i]));
        for (int i = 0; i < 6; ++i) step0 = fmax(step0, fabs(ap * rh->dz[i]));
        gap = 0;
        for (int i = 0; i < m; ++i) {
            rh->sl[i] += ap * rh->ds[i];
            rh->lam[i] += ad * rh->dl[i];
            gap += rh->sl[i] * rh->lam[i];
        }
        rh->warm = 1;
        /* The first row's distance to where it converges, from the contraction θ of its
         * last two steps: step0 · θ / (1 − θ). */
        double theta = step0 / prev0, left0 = theta < 1 ? step0 * theta / (1 - theta) : INFINITY;
        prev0 = step0;
        if (gap / m < gap_tol &&
            (step < step_tol || (!rh->reference && left0 < RH_LEFT_FIRST && step < RH_STEP_REST)))
            return -1;
        longest = fmax(longest, hpi_plan_now() - t_it);
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
        if (rh->hs.prediction != HP_PREDICT_HOLD)
            for (int i = 0; i < 6; ++i) v[i] = (rh->hist_d[h][i] - rh->hist_d[h - m][i]) / span;
    }
    /* The periodic fit of each commanded component, anchored at the latest desired pose:
     * row j is that pose plus the fit's change over j intervals. */
    hpi_periodic fit[6];
    int periodic[6] = {0};
    if (rh->hs.prediction == HP_PREDICT_PERIODIC)
        for (int i = 0; i < 6; ++i)
            periodic[i] = rh->commanded[i] &&
                          hpi_horizon_periodic_fit(rh->hist_t, &rh->hist_d[0][i], 6, rh->hist_n,
                                                   &fit[i]);
    const double t_now = rh->hist_t[h];
    for (int j = 0; j < rh->N; ++j) {
        for (int i = 0; i < 6; ++i) {
            double s = i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD;
            double ahead = periodic[i] ? hpi_horizon_periodic_at(&fit[i], t_now + dtp * j) -
                                             hpi_horizon_periodic_at(&fit[i], t_now)
                                       : v[i] * dtp * j;
            rh->d[6 * j + i] = rh->commanded[i] ? (rh->hist_d[h][i] + ahead) * s : 0.0;
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
    hpi_kin_dist_warm_cold(rh->dw, HP_HORIZON_MAX * HP_MAX_BLADDERS);
    for (int k = 0; k < rh->n && e == HP_OK; ++k)
        e = hpi_iab_scaled_init(&rh->L->bladders[k].iab, &rh->S[k], d);
    if (e != HP_OK) goto fail;
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
    rh->t_call = hpi_plan_now(); /* the prediction's fit counts against the budget too */
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
        if (rh->hist_n == RH_HIST) {
            memmove(rh->hist_t, rh->hist_t + 1, sizeof(double) * (RH_HIST - 1));
            memmove(rh->hist_d, rh->hist_d + 1, sizeof(double) * 6 * (RH_HIST - 1));
            rh->hist_n--;
        }
        rh->hist_t[rh->hist_n] = t;
        memcpy(rh->hist_d[rh->hist_n], xc, sizeof rh->hist_d[0]);
        rh->hist_n++;
        predict(rh, dt0);
        if (!rh->started) {
            /* the pose the start pressures hold, over the whole horizon */
            rh->geom_ok = 0;
            for (int j = 0; j < rh->N; ++j)
                for (int i = 0; i < 6; ++i)
                    rh->z[6 * j + i] = rh->applied.achieved[i] *
                                       (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD);
        }
        int done = interior_point(rh);
        rh->budget_stopped = done >= 0;
        if (done >= 0)
            snprintf(rh->why, sizeof rh->why,
                     "time-limit: the receding horizon's solve stopped at its time budget (%g of "
                     "solver.max_time_s = %g s) after %d of at most %d iterations; the row "
                     "depends on the machine's speed",
                     RH_SOLVE_SHARE, rh->s.max_time, done, rh->hs.rh_max_iter);
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
        const size_t row = RH_NC * (size_t)rh->n, rest = row * (size_t)(rh->N - 1);
        const size_t n = (size_t)rh->n, N1 = (size_t)(rh->N - 1);
        memmove(rh->z, rh->z + 6, sizeof(double) * 6 * N1);
        memmove(rh->sl, rh->sl + row, sizeof(double) * rest);
        memmove(rh->lam, rh->lam + row, sizeof(double) * rest);
        /* The last row keeps its pose, and so its geometry. */
        memmove(rh->rho, rh->rho + n, sizeof(double) * n * N1);
        memmove(rh->P, rh->P + n, sizeof(double) * n * N1);
        memmove(rh->dP, rh->dP + n, sizeof(double) * n * N1);
        memmove(rh->J, rh->J + 6 * n, sizeof(double) * 6 * n * N1);
        memmove(rh->alpha, rh->alpha + n, sizeof(double) * n * N1);
        memmove(rh->dw, rh->dw + n, sizeof rh->dw[0] * n * N1);
    } else {
        rh->geom_ok = 0;
        for (int i = 0; i < 6; ++i)
            rh->z[i] = result->achieved[i] * (i < 3 ? HP_MM_PER_M : HP_DEG_PER_RAD);
    }
    return HP_OK;
}

long hpi_horizon_rh_iterations(const hp_horizon_rh *rh) { return rh->iterations; }

double hpi_horizon_rh_dist_steps(const hp_horizon_rh *rh)
{
    return rh->dists ? (double)rh->dist_steps / (double)rh->dists : 0.0;
}

void hpi_horizon_rh_reference(hp_horizon_rh *rh) { rh->reference = 1; }

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
