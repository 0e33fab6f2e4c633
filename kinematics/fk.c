/* Forward contact kinematics: the pose whose contact distances best fit measured outer
 * radii, by Levenberg–Marquardt with Marquardt's column scaling. Each step is a damped
 * least-squares solve: by the normal equations where their column-scaled matrix is
 * provably well conditioned (hpi_kin_damped_normal), else by QR (hpi_kin_damped_qr; Eigen's
 * pivoting QR in linalg_eigen.cpp where that fails), so an ill-conditioned Jacobian (a
 * pitch column with a small lever arm, a distant pivot) never has its conditioning
 * squared. */
#include "kin_internal.h"
#include "fit_internal.h"
#include "kin_geom.h"
#include "linalg.h"
#include "common/dense.h"

#include <math.h>
#include <string.h>

#define FK_MAX_ITERS 200
/* A step whose effect on every radius is below this [m] ends the iteration: 1e-15 m is a
 * few ulps of a 30 mm radius, the resolution of the residual itself. */
#define FK_STEP_TOL 1e-15
#define FK_LAMBDA_MAX 1e12

/* Stacked Householder QR (fit_internal.h). The damping rows give the system full column
 * rank, where QR without pivoting is backward stable, so the fit's small system needs
 * neither pivoting nor Eigen's dynamic-size machinery. */
int hpi_kin_damped_qr(int n, int nf, const double *J, const double *r, const double *D,
                      double lambda, double *dx)
{
    enum { MR = HP_MAX_BLADDERS + 6 };
    double A[MR][6], b[MR];
    double sl = sqrt(lambda);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < nf; ++j) A[i][j] = J[i * nf + j];
        b[i] = -r[i];
    }
    for (int i = 0; i < nf; ++i) {
        for (int j = 0; j < nf; ++j) A[n + i][j] = i == j ? sl * D[j] : 0.0;
        b[n + i] = 0.0;
    }
    for (int j = 0; j < nf; ++j) {
        /* Rows below n + j are still zero in the columns from j on (damping row n + i has
         * only its diagonal until column i's reflection reaches it): skipping them changes
         * no bit and saves a third of the work. */
        const int m = n + j + 1;
        double nrm = 0.0;
        for (int i = j; i < m; ++i) nrm += A[i][j] * A[i][j];
        nrm = sqrt(nrm);
        if (!(nrm > 0) || !isfinite(nrm)) return -1;
        double alpha = A[j][j] > 0 ? -nrm : nrm;
        double v0 = A[j][j] - alpha; /* v = (v0, A[j+1..][j]) */
        double vv = v0 * v0;
        for (int i = j + 1; i < m; ++i) vv += A[i][j] * A[i][j];
        if (vv > 0) {
            for (int k = j + 1; k < nf; ++k) {
                double sdot = v0 * A[j][k];
                for (int i = j + 1; i < m; ++i) sdot += A[i][j] * A[i][k];
                double f = 2.0 * sdot / vv;
                A[j][k] -= f * v0;
                for (int i = j + 1; i < m; ++i) A[i][k] -= f * A[i][j];
            }
            double sdot = v0 * b[j];
            for (int i = j + 1; i < m; ++i) sdot += A[i][j] * b[i];
            double f = 2.0 * sdot / vv;
            b[j] -= f * v0;
            for (int i = j + 1; i < m; ++i) b[i] -= f * A[i][j];
        }
        A[j][j] = alpha;
    }
    for (int j = nf - 1; j >= 0; --j) {
        double v = b[j];
        for (int k = j + 1; k < nf; ++k) v -= A[j][k] * dx[k];
        dx[j] = v / A[j][j];
        if (!isfinite(dx[j])) return -1;
    }
    return 0;
}

/* Jᵀ J and −Jᵀ r of a fit's Jacobian J (n×nf) and residual r, zero-padded to 6 columns so
 * that the loops have a fixed length the compiler unrolls (a padded entry is an exact
 * zero). Each entry of the lower triangle is summed over the rows in index order from +0,
 * so A_jj is bit for bit the fit's squared column norm; the upper triangle is its mirror. */
typedef struct fk_gram {
    double A[6][6];
    double g[6];
} fk_gram;

static void gram_of(int n, int nf, const double *J, const double *r, fk_gram *q)
{
    /* Local sums (no aliasing with J and r for the compiler to fear), copied out once. */
    double A[6][6], g[6];
    memset(A, 0, sizeof A);
    memset(g, 0, sizeof g);
    for (int i = 0; i < n; ++i) {
        double a[6] = {0};
        for (int j = 0; j < nf; ++j) a[j] = J[i * nf + j];
#pragma GCC unroll 6
        for (int j = 0; j < 6; ++j) {
#pragma GCC unroll 6
            for (int k = 0; k < 6; ++k)
                if (k <= j) A[j][k] += a[j] * a[k];
            g[j] -= a[j] * r[i];
        }
    }
    for (int j = 0; j < 6; ++j)
        for (int k = j + 1; k < 6; ++k) A[j][k] = A[k][j];
    memcpy(q->A, A, sizeof A);
    memcpy(q->g, g, sizeof g);
}

/* gram_of for a fit whose Jacobian Jr (n×nf, the columns col[] of st->J) is the start's:
 * JᵀJ is copied from st->A's sub-block (the same sums of the same products in the same
 * order) and only −Jᵀr, which depends on the target, is summed. */
static void gram_from_start(int n, int nf, const int *col, const hp_kin_fit_start *st,
                            const double *Jr, const double *r, fk_gram *q)
{
    if (nf == 6) {
        memcpy(q->A, st->A, sizeof q->A); /* col is 0..5 */
    } else {
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k) q->A[j][k] = j < nf && k < nf ? st->A[col[j]][col[k]] : 0.0;
    }
    /* −Jᵀr summed from +0 over the rows in order, as gram_of sums it (its padded entries
     * stay +0); all six columns free is the common case, with a loop of fixed length. */
    double g[6] = {0};
    if (nf == 6) {
        for (int i = 0; i < n; ++i)
#pragma GCC unroll 6
            for (int j = 0; j < 6; ++j) g[j] -= Jr[i * 6 + j] * r[i];
    } else {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < nf; ++j) g[j] -= Jr[i * nf + j] * r[i];
    }
    memcpy(q->g, g, sizeof g);
}

/* The damped step from the normal equations of q (see hpi_kin_damped_normal). */
static int normal_step(const fk_gram *q, int nf, const double *D, double lambda, double *dx)
{
    double A[6][6], g[6], d[6];
    memcpy(A, q->A, sizeof A);
    for (int j = 0; j < nf; ++j) {
        A[j][j] += lambda * D[j] * D[j];
        if (!(A[j][j] > 0) || !isfinite(A[j][j])) return -1;
        d[j] = 1.0 / sqrt(A[j][j]);
    }
    for (int j = nf; j < 6; ++j) d[j] = 0.0;
        /* Scaled to unit diagonal (fixed-length loops; the padded part is never read). */
#pragma GCC unroll 6
    for (int j = 0; j < 6; ++j) {
#pragma GCC unroll 6
        for (int k = 0; k < 6; ++k) A[j][k] *= d[j] * d[k];
        A[j][j] = 1.0;
        g[j] = q->g[j] * d[j];
    }
    if (!hpi_cholesky(&A[0][0], 6, nf, 0.0, &A[0][0], 6)) return -1;
    /* trace = nf (unit diagonal) */
    if (!(nf * hpi_cholesky_inv_frob2(&A[0][0], 6, nf) <= HP_KIN_NORMAL_MAX_COND)) return -1;
    hpi_cholesky_solve(&A[0][0], 6, nf, g);
    for (int j = 0; j < nf; ++j) {
        dx[j] = g[j] * d[j];
        if (!isfinite(dx[j])) return -1;
    }
    return 0;
}

/* Normal equations, scaled to unit diagonal, by Cholesky (fit_internal.h). Accepted only
 * under the condition bound HP_KIN_NORMAL_MAX_COND. */
int hpi_kin_damped_normal(int n, int nf, const double *J, const double *r, const double *D,
                          double lambda, double *dx)
{
    fk_gram q;
    gram_of(n, nf, J, r, &q);
    return normal_step(&q, nf, D, lambda, dx);
}

/* The damped step by the cheapest exact method that is accurate for this J (q: its normal
 * equations). */
static int damped_step(int n, int nf, const double *J, const double *r, const fk_gram *q,
                       const double *D, double lambda, double *dx)
{
    if (normal_step(q, nf, D, lambda, dx) == 0) return 0;
    return hpi_kin_damped_qr(n, nf, J, r, D, lambda, dx);
}

static double sumsq(int n, const double *v)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += v[i] * v[i];
    return s;
}

/* Residual r = rho(xi) − ro and, if Jr is not NULL, its Jacobian in the nf free columns
 * listed in col[]; sw: the surface level's distances' warm states (in/out). */
static hp_error residual(const hp_layout *L, const hp_geom *G, hp_level level, const double *ro,
                         const double xi[6], int nf, const int *col, hp_kin_dist_warm *sw,
                         double *r, double *Jr)
{
    double rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6];
    /* All six columns free (col is then 0..5): the model writes the Jacobian in place. */
    int all = nf == 6;
    hp_error err = hpi_kin_contact_eval_warm(L, G, level, xi, sw, rho, Jr ? (all ? Jr : J) : NULL,
                                             NULL);
    if (err) return err;
    for (int k = 0; k < L->n; ++k) {
        r[k] = rho[k] - ro[k];
        if (Jr && !all)
            for (int j = 0; j < nf; ++j) Jr[k * nf + j] = J[k * 6 + col[j]];
    }
    return HP_OK;
}

hp_error hpi_kin_fit_start_at(const hp_layout *L, const hp_geom *G, hp_level level,
                              const double x0[6], hp_kin_fit_start *st)
{
    hpi_kin_dist_warm_cold(st->w, HP_MAX_BLADDERS);
    hp_error err = hpi_kin_contact_eval_warm(L, G, level, x0, st->w, st->rho, st->J, NULL);
    if (err) return err;
    fk_gram q;
    gram_of(L->n, 6, st->J, st->rho, &q); /* its −Jᵀr is not used */
    memcpy(st->A, q.A, sizeof q.A);
    return HP_OK;
}

/* 1 when the fit has provably arrived at near (see hpi_kin_fit): x within near->tol/4 of
 * near->pose and the undamped Gauss–Newton step at x (its Jacobian Jr, residual r) below
 * near->tol/4 in every free component. */
static int arrived(int n, int nf, const int *col, const double *x, const double *Jr,
                   const double *r, const fk_gram *q, const hp_kin_fit_near *near)
{
    for (int j = 0; j < nf; ++j)
        if (!(fabs(x[col[j]] - near->pose[col[j]]) <= 0.25 * near->tol[col[j]])) return 0;
    double D[6], h[6];
    for (int j = 0; j < nf; ++j) D[j] = 0.0;
    if (damped_step(n, nf, Jr, r, q, D, 0.0, h) != 0) return 0;
    for (int j = 0; j < nf; ++j)
        if (!(fabs(h[j]) <= 0.25 * near->tol[col[j]])) return 0;
    return 1;
}

/* What a fit's trial certificates share: the anchor's Jacobian in the free columns and its
 * normal matrix (formed as the fit forms its own, gram_of), and the bound σ̂ derived from
 * it; formed at the first try, once a fit. */
typedef struct trial_cache {
    int have;
    fk_gram q;
    hp_kin_trial_cache c;
} trial_cache;

/* hpi_kin_fit_certified_trial with the anchor's normal matrix in the free columns. */
static int certified_trial(const hp_layout *L, const hp_geom *G, hp_level level, int nf,
                           const int *col, const double *xt, double cost, double lambda_next,
                           const double *target, int iters_left, const hp_kin_fit_near *near,
                           trial_cache *tc)
{
    int n = L->n;
    if (!tc->have) {
        double Ja[HP_MAX_BLADDERS * 6], r0[HP_MAX_BLADDERS] = {0};
        const double *J = near->anchor_J;
        if (nf < 6) {
            for (int k = 0; k < n; ++k)
                for (int j = 0; j < nf; ++j) Ja[k * nf + j] = near->anchor_J[k * 6 + col[j]];
            J = Ja;
        }
        gram_of(n, nf, J, r0, &tc->q);
        tc->c.ready = 0;
        tc->have = 1;
    }
    return hpi_kin_fit_certified_trial(L, G, level, nf, col, xt, &tc->q.A[0][0], cost, lambda_next,
                                       target, iters_left, near, &tc->c);
}

hp_error hpi_kin_fit(const hp_layout *L, const hp_geom *G, hp_level level, const double *target,
                     const int free_[6], const double x0[6], const hp_kin_fit_start *st,
                     const hp_kin_fit_near *near, double xi[6], double *residual_rms, int *iters)
{
    if (!L || !G || !target || !free_ || !x0 || !xi) return HP_ERR_NULL;
    if (!hp_level_is_geometry(level)) return HP_ERR_INVALID;
    for (int k = 0; k < L->n; ++k)
        if (!isfinite(target[k])) return HP_ERR_INVALID;
    for (int i = 0; i < 6; ++i)
        if (free_[i] && !isfinite(x0[i])) return HP_ERR_INVALID;
    int n = L->n, col[6], nf = 0;
    for (int i = 0; i < 6; ++i)
        if (free_[i]) col[nf++] = i;
    double x[6];
    for (int i = 0; i < 6; ++i) x[i] = free_[i] ? x0[i] : 0.0;
    if (nf == 0) {
        memcpy(xi, x, sizeof x);
        return HP_OK;
    }
    /* Successive iterates are close: each bladder's distance starts from its state at the
     * last evaluation. */
    hp_kin_dist_warm sw[HP_MAX_BLADDERS];
    double r[HP_MAX_BLADDERS], Jr[HP_MAX_BLADDERS * 6], rt[HP_MAX_BLADDERS];
    double Jt[HP_MAX_BLADDERS * 6];
    hp_error err = HP_OK;
    if (st) {
        for (int k = 0; k < n; ++k) {
            sw[k] = st->w[k];
            r[k] = st->rho[k] - target[k];
            for (int j = 0; j < nf; ++j) Jr[k * nf + j] = st->J[k * 6 + col[j]];
        }
    } else {
        hpi_kin_dist_warm_cold(sw, n);
        err = residual(L, G, level, target, x, nf, col, sw, r, Jr);
    }
    if (err) return err;
    /* The linear model's fit is a linear least-squares problem: an undamped first step
     * solves it, and the second (a rounding-level correction) ends the iteration. The
     * curved levels start damped, as Levenberg–Marquardt should from a far start. */
    double cost = sumsq(n, r), lambda = level == HP_LEVEL_LINEAR ? 1e-15 : 1e-3;
    int it = 0, done = 0, have_gram = 0, certified = 0;
    fk_gram gram;
    trial_cache tcache;
    tcache.have = 0;
    if (st) {
        gram_from_start(n, nf, col, st, Jr, r, &gram);
        have_gram = 1;
    }
    while (!done && it < FK_MAX_ITERS) {
        ++it;
        double D[6], dx[6], xt[6];
        /* The normal equations of each new Jacobian, once: their diagonal is the squared
         * column norms (Marquardt's scales), and they serve every damping tried there. */
        if (!have_gram) {
            gram_of(n, nf, Jr, r, &gram);
            have_gram = 1;
        }
        for (int j = 0; j < nf; ++j) {
            double s = gram.A[j][j];
            D[j] = s > 0 ? sqrt(s) : 1.0;
        }
        if (cost == 0.0) break;
        /* The early stops leave the full fit its steps at the rounding floor
         * (HP_KIN_FIT_STOP_MARGIN): an answer it reaches only after its budget is none. */
        if (near && it > 1 && it + HP_KIN_FIT_STOP_MARGIN <= FK_MAX_ITERS &&
            arrived(n, nf, col, x, Jr, r, &gram, near)) {
            done = 1;
            break;
        }
        /* With the anchor's Jacobian the proof is tried at each trial instead (below): a
         * step closer, and before the evaluation it would save. */
        if (near && it > 1 && !near->anchor_J &&
            hpi_kin_fit_certified(L, G, level, nf, col, x, &gram.A[0][0], r, lambda, target,
                                  FK_MAX_ITERS - it, near)) {
            certified = 1;
            break;
        }
        if (damped_step(n, nf, Jr, r, &gram, D, lambda, dx) != 0 &&
            hpi_kin_damped_lstsq(n, nf, Jr, r, D, lambda, dx) != 0)
            return HP_ERR_NO_CONVERGENCE;
        double stepsize = 0.0;
        for (int j = 0; j < nf; ++j) stepsize = fmax(stepsize, fabs(D[j] * dx[j]));
        memcpy(xt, x, sizeof xt);
        for (int j = 0; j < nf; ++j) xt[col[j]] += dx[j];
        /* A trial, before it is evaluated: with the anchor's Jacobian the proof may already
         * hold (it then also proves the trial accepted, after which the damping is a tenth
         * and the step too long to end the fit). From a far start it fails at the first
         * trial and holds at the second, which then costs no evaluation of the model. */
        if (near && near->has_anchor && near->anchor_J && stepsize > FK_STEP_TOL &&
            certified_trial(L, G, level, nf, col, xt, cost, fmax(lambda * 0.1, 1e-15), target,
                            FK_MAX_ITERS - it, near, &tcache)) {
            certified = 1;
            break;
        }
        /* The trial's Jacobian comes with its distances (most steps are accepted, and it
         * costs far less than a second evaluation at the accepted point). A rejected
         * trial's multipliers still warm-start the next one: the bracket makes any start
         * safe. */
        err = residual(L, G, level, target, xt, nf, col, sw, rt, Jt);
        double ct = err == HP_OK ? sumsq(n, rt) : INFINITY;
        if (ct <= cost) {
            memcpy(x, xt, sizeof x);
            cost = ct;
            memcpy(r, rt, sizeof(double) * (size_t)n);
            memcpy(Jr, Jt, sizeof(double) * (size_t)(n * nf));
            have_gram = 0;
            lambda = fmax(lambda * 0.1, 1e-15);
            if (stepsize <= FK_STEP_TOL) done = 1;
        } else {
            lambda *= 10.0;
            /* No descent at any damping: the fit is at its minimum to rounding. */
            if (lambda > FK_LAMBDA_MAX || stepsize <= FK_STEP_TOL) done = 1;
        }
    }
    if (certified) {
        /* The rest of the fit provably ends within tol/4 of near->pose: report the anchor,
         * a pose within a few 1e-10 of where it ends, and its residual. */
        for (int j = 0; j < nf; ++j) x[col[j]] = near->anchor[col[j]];
        cost = 0.0;
        for (int k = 0; k < n; ++k) {
            double d = near->anchor_rho[k] - target[k];
            cost += d * d;
        }
        done = 1;
    }
    if (!done && cost != 0.0) return HP_ERR_NO_CONVERGENCE;
    memcpy(xi, x, sizeof x);
    if (residual_rms) *residual_rms = sqrt(cost / n);
    if (iters) *iters = it;
    return HP_OK;
}

hp_error hpi_contact_fit_g(const hp_layout *L, const hp_geom *G, hp_level level,
                           const double *target, const int free_[6], const double x0[6],
                           double xi[6], double *residual_rms, int *iters)
{
    return hpi_kin_fit(L, G, level, target, free_, x0, NULL, NULL, xi, residual_rms, iters);
}

hp_error hpi_contact_fk_g(const hp_layout *L, const hp_geom *G, hp_level level, const double *ro,
                          const double *xi0, double xi[6], double *residual_rms, int *iters)
{
    if (!L || !G || !ro || !xi) return HP_ERR_NULL;
    if (!hp_level_is_geometry(level)) return HP_ERR_INVALID;
    int n = L->n;
    int dof = L->head.shape == HP_HEAD_SPHERE ? 3 : 6;
    if (n < dof) return HP_ERR_INVALID;
    for (int k = 0; k < n; ++k)
        if (!(ro[k] > 0) || !isfinite(ro[k])) return HP_ERR_INVALID;
    double x[6] = {0};
    if (xi0) {
        for (int i = 0; i < 6; ++i) {
            if (!isfinite(xi0[i])) return HP_ERR_INVALID;
            x[i] = xi0[i];
        }
    }
    int free_[6];
    for (int i = 0; i < 6; ++i) free_[i] = i < dof;
    return hpi_contact_fit_g(L, G, level, ro, free_, x, xi, residual_rms, iters);
}

hp_error hp_contact_fit(const hp_layout *L, hp_level level, const double *target,
                        const int free_[6], const double x0[6], double xi[6], double *residual_rms,
                        int *iters)
{
    if (!L || !target || !free_ || !x0 || !xi) return HP_ERR_NULL;
    hp_geom G;
    if (hpi_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hpi_contact_fit_g(L, &G, level, target, free_, x0, xi, residual_rms, iters);
}

hp_error hp_contact_fk(const hp_layout *L, hp_level level, const double *ro, const double *xi0,
                       double xi[6], double *residual_rms, int *iters)
{
    if (!L || !ro || !xi) return HP_ERR_NULL;
    hp_geom G;
    if (hpi_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hpi_contact_fk_g(L, &G, level, ro, xi0, xi, residual_rms, iters);
}
