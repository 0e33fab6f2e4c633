/* Helpers shared by the Ipopt and NLopt backends: problem checks, starting point, clipping,
 * and a first-order optimality test for results a solver could not certify. */
#include "planner/backend_common.h"
#include "common/units.h"
#include "common/dense.h"

#include <float.h>
#include <math.h>
#include <string.h>

hp_error hpi_backend_check_problem(const hp_problem *pb, hp_diag *d)
{
    if (!pb || !pb->layout || !pb->geom) return hp_diag_set(d, HP_ERR_NULL, "problem: NULL");
    if (pb->n < 1 || pb->n > HP_MAX_BLADDERS || pb->n != pb->layout->n || pb->nx != 6 + pb->n)
        return hp_diag_set(d, HP_ERR_INVALID, "problem: n = %d, nx = %d do not match the layout",
                           pb->n, pb->nx);
    if (pb->level == HP_LEVEL_AUTO)
        return hp_diag_set(d, HP_ERR_INVALID, "problem: level must be resolved, not auto");
    for (int i = 0; i < 6; i++) {
        if (!isfinite(pb->d[i]))
            return hp_diag_set(d, HP_ERR_INVALID, "problem: desired[%d] is not finite", i);
        if (!(pb->w[i] >= 0.0) || !isfinite(pb->w[i]))
            return hp_diag_set(d, HP_ERR_INVALID, "problem: weight[%d] must be >= 0", i);
    }
    if (!(pb->mu >= 0.0) || !isfinite(pb->mu))
        return hp_diag_set(d, HP_ERR_INVALID, "problem: mu must be finite and >= 0");
    for (int k = 0; k < pb->n; k++) {
        const char *name = pb->layout->bladders[k].name;
        if (!isfinite(pb->ri_lo[k]) || !isfinite(pb->ri_hi[k]) || !(pb->ri_lo[k] > 0.0))
            return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: ri bounds not finite and > 0", name);
        if (!isfinite(pb->p_prev[k]))
            return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: previous pressure not finite", name);
        if (!(pb->ri_lo[k] <= pb->ri_hi[k]))
            return hp_diag_set(d, HP_ERR_DOMAIN,
                               "bladder %s: ri bounds empty (%.17g > %.17g mm): limits "
                               "cannot all hold",
                               name, pb->ri_lo[k], pb->ri_hi[k]);
    }
    return HP_OK;
}

void hpi_backend_clip(const hp_problem *pb, double *x)
{
    for (int k = 0; k < pb->n; k++) {
        double *r = &x[6 + k];
        if (*r < pb->ri_lo[k]) *r = pb->ri_lo[k];
        if (*r > pb->ri_hi[k]) *r = pb->ri_hi[k];
    }
}

hp_error hpi_backend_default_start(const hp_problem *pb, double *x)
{
    double xi[6], rho[HP_MAX_BLADDERS];
    for (int i = 0; i < 6; i++) {
        x[i] = pb->d[i];
        xi[i] = pb->d[i] * (i < 3 ? 1e-3 : HP_RAD_PER_DEG);
    }
    hp_error e = hpi_contact_eval_g(pb->layout, pb->geom, pb->level, xi, rho, NULL, NULL);
    if (e != HP_OK) return e;
    for (int k = 0; k < pb->n; k++) {
        double ri;
        if (hp_iab_ri(&pb->layout->bladders[k].iab, rho[k], &ri) == HP_OK && isfinite(ri))
            x[6 + k] = ri * 1e3;
        else x[6 + k] = pb->ri_lo[k];
    }
    hpi_backend_clip(pb, x);
    return HP_OK;
}

hp_error hpi_backend_start(const hp_problem *pb, const double *x0, double *x)
{
    if (!x0) return hpi_backend_default_start(pb, x);
    for (int i = 0; i < pb->nx; i++) {
        if (!isfinite(x0[i])) return HP_ERR_INVALID;
        x[i] = x0[i];
    }
    hpi_backend_clip(pb, x);
    return HP_OK;
}

/* Solves A y = b in place for symmetric positive definite A (m×m, overwritten by its
 * factor); 0 when not SPD. */
static int cholesky_solve(double *A, double *b, int m)
{
    if (!hpi_cholesky(A, m, m, 0.0, A, m)) return 0;
    hpi_cholesky_solve(A, m, m, b);
    return 1;
}

/* When the active contacts' pose gradients are linearly dependent (four bladders binding
 * on a sphere's three translations, say), their multipliers are not unique and the minimum-
 * norm ones can carry a wrong sign while others of the right sign cancel the gradient as
 * well: the first-order conditions ask only that some exist. Searches for them: the
 * multipliers of the active radii, each held on its right side (z_k >= 0 at a lower bound,
 * <= 0 at an upper one), that minimise the pose rows of the Lagrangian's gradient, by
 * projected coordinate descent on that convex least-squares problem (at most 8 unknowns,
 * 6 rows). b0 is the gradient with the free radii's multipliers in. Replaces m_out's
 * stationarity, wrong sign (then 0) and bound multipliers when its residual is below
 * max(stationarity, wrong sign) of the minimum-norm ones. Allocates nothing. */
static void signed_multipliers(const hp_problem *pb, const double *g, const double *jac,
                               const int free_[6], const double b0[6], const int *lo, const int *hi,
                               const int *act, int m, hp_kkt_measure *m_out)
{
    const int nx = pb->nx;
    double lam[HP_MAX_BLADDERS], bnd[HP_MAX_BLADDERS], aa[HP_MAX_BLADDERS], r[6];
    int sgn[HP_MAX_BLADDERS]; /* +1: lam >= bnd, −1: lam <= bnd, 0: free */
    for (int i = 0; i < 6; i++) r[i] = free_[i] ? b0[i] : 0.0;
    for (int p = 0; p < m; p++) {
        int k = act[p];
        double ro1 = jac[k * nx + 6 + k];
        bnd[p] = -g[6 + k] / ro1; /* z_k = g_{6+k} + lam·ro1 changes sign here */
        sgn[p] = lo[k] && !hi[k] ? 1 : hi[k] && !lo[k] ? -1 : 0;
        lam[p] = bnd[p];
        aa[p] = 0.0;
        for (int i = 0; i < 6; i++)
            if (free_[i]) {
                aa[p] += jac[k * nx + i] * jac[k * nx + i];
                r[i] += lam[p] * jac[k * nx + i];
            }
    }
    for (int sweep = 0; sweep < 4000; sweep++) {
        double moved = 0.0;
        for (int p = 0; p < m; p++) {
            if (!(aa[p] > 0.0)) continue;
            const double *a = &jac[act[p] * nx];
            double ar = 0.0;
            for (int i = 0; i < 6; i++)
                if (free_[i]) ar += a[i] * r[i];
            double v = lam[p] - ar / aa[p];
            if (sgn[p] > 0 && v < bnd[p]) v = bnd[p];
            if (sgn[p] < 0 && v > bnd[p]) v = bnd[p];
            double dv = v - lam[p];
            if (dv == 0.0) continue;
            for (int i = 0; i < 6; i++)
                if (free_[i]) r[i] += dv * a[i];
            lam[p] = v;
            moved = fmax(moved, fabs(dv) * sqrt(aa[p]));
        }
        if (!(moved > 1e-3 * DBL_EPSILON * (1.0 + m_out->grad_max))) break;
    }
    double stat = 0.0;
    for (int i = 0; i < 6; i++)
        if (free_[i]) stat = fmax(stat, fabs(r[i]));
    if (!(stat < fmax(m_out->stationarity, m_out->wrong_sign))) return;
    m_out->stationarity = stat;
    m_out->wrong_sign = 0.0;
    for (int p = 0; p < m; p++) {
        int k = act[p];
        m_out->bound_mult[k] = g[6 + k] + lam[p] * jac[k * nx + 6 + k];
    }
}

hp_error hpi_backend_kkt_measure(const hp_problem *pb, const double *x, hp_kkt_measure *m_out)
{
    const int n = pb->n, nx = pb->nx;
    double f, g[HP_PROBLEM_NX_MAX], c[HP_MAX_BLADDERS];
    double jac[HP_MAX_BLADDERS * HP_PROBLEM_NX_MAX];
    hp_error e = hpi_problem_objective(pb, x, &f, g, NULL);
    if (e != HP_OK) return e;
    e = hpi_problem_constraints(pb, x, c, jac, NULL, NULL);
    if (e != HP_OK) return e;
    m_out->grad_max = 0.0;
    m_out->feasibility = 0.0;
    m_out->stationarity = HUGE_VAL;
    m_out->wrong_sign = HUGE_VAL;
    m_out->in_bounds = 1;
    for (int i = 0; i < nx; i++) m_out->grad_max = fmax(m_out->grad_max, fabs(g[i]));
    /* A bound counts as active within the one binding threshold of the planner (mm): far
     * below any physical meaning of ri and far above the 1e-14 mm rounding of ri near
     * 30 mm. */
    const double btol = HP_BINDING_TOL_MM;

    int lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    for (int k = 0; k < n; k++) {
        m_out->feasibility = fmax(m_out->feasibility, fabs(c[k]));
        double r = x[6 + k];
        if (!(r >= pb->ri_lo[k] && r <= pb->ri_hi[k])) m_out->in_bounds = 0;
        lo[k] = r - pb->ri_lo[k] <= btol;
        hi[k] = pb->ri_hi[k] - r <= btol;
    }
    /* A free ri_k fixes its contact multiplier: g_{6+k} + λ_k·ro'_k = 0 (ro' = jac[k][6+k] > 0).
     * The active ones take the least-squares (ridge-regularised, minimum-norm) values that
     * best cancel the pose rows of the Lagrangian's gradient. */
    /* A pose component of weight 0 is not commanded: the backends hold it fixed at 0, so
     * its row of the Lagrangian's gradient carries a bound multiplier, not a condition. */
    int free_[6];
    for (int i = 0; i < 6; i++) free_[i] = pb->w[i] > 0.0;
    double lam[HP_MAX_BLADDERS] = {0};
    double b[6];
    for (int i = 0; i < 6; i++) b[i] = g[i];
    int act[HP_MAX_BLADDERS], m = 0;
    for (int k = 0; k < n; k++) {
        if (lo[k] || hi[k]) {
            act[m++] = k;
            continue;
        }
        lam[k] = -g[6 + k] / jac[k * nx + 6 + k];
        for (int i = 0; i < 6; i++) b[i] += lam[k] * jac[k * nx + i];
    }
    double b0[6];
    for (int i = 0; i < 6; i++) b0[i] = b[i];
    if (m > 0) {
        double A[HP_MAX_BLADDERS * HP_MAX_BLADDERS], rhs[HP_MAX_BLADDERS];
        double tr = 0.0;
        for (int p = 0; p < m; p++) {
            for (int q = 0; q < m; q++) {
                double s = 0.0;
                for (int i = 0; i < 6; i++)
                    if (free_[i]) s += jac[act[p] * nx + i] * jac[act[q] * nx + i];
                A[p * m + q] = s;
            }
            tr += A[p * m + p];
            double s = 0.0;
            for (int i = 0; i < 6; i++)
                if (free_[i]) s += jac[act[p] * nx + i] * b[i];
            rhs[p] = -s;
        }
        for (int p = 0; p < m; p++) A[p * m + p] += 1e-12 * (tr > 0.0 ? tr : 1.0);
        if (!cholesky_solve(A, rhs, m)) return HP_OK; /* measures stay +inf */
        for (int p = 0; p < m; p++) {
            int k = act[p];
            lam[k] = rhs[p];
            for (int i = 0; i < 6; i++) b[i] += lam[k] * jac[k * nx + i];
        }
    }
    m_out->stationarity = 0.0;
    for (int i = 0; i < 6; i++)
        if (free_[i]) m_out->stationarity = fmax(m_out->stationarity, fabs(b[i]));
    m_out->wrong_sign = 0.0;
    for (int k = 0; k < n; k++) m_out->bound_mult[k] = 0.0;
    for (int p = 0; p < m; p++) {
        int k = act[p];
        /* Bound multiplier z = ∂L/∂ri_k: >= 0 at a lower bound, <= 0 at an upper one. */
        double z = g[6 + k] + lam[k] * jac[k * nx + 6 + k];
        m_out->bound_mult[k] = z;
        if (lo[k] && !hi[k]) m_out->wrong_sign = fmax(m_out->wrong_sign, -z);
        if (hi[k] && !lo[k]) m_out->wrong_sign = fmax(m_out->wrong_sign, z);
    }
    if (m_out->wrong_sign > 0.0) signed_multipliers(pb, g, jac, free_, b0, lo, hi, act, m, m_out);
    return HP_OK;
}

int hpi_backend_kkt_ok(const hp_problem *pb, const double *x, double feas_tol)
{
    hp_kkt_measure m;
    if (hpi_backend_kkt_measure(pb, x, &m) != HP_OK) return 0;
    const double stat_tol = 1e-6 * (1.0 + m.grad_max);
    return m.in_bounds && m.feasibility <= feas_tol && m.stationarity <= stat_tol &&
           m.wrong_sign <= stat_tol;
}

hp_error hpi_backend_begin(const char *name, const hp_problem *pb, int n, int nx, const double *x0,
                           double *xs, hp_backend_result *r, int *go, hp_diag *d)
{
    *go = 0;
    r->status = HP_STATUS_SOLVER_ERROR;
    r->raw_code = 0;
    r->iterations = 0;
    r->converged = 0;
    if (pb->n != n || pb->nx != nx)
        return hp_diag_set(d, HP_ERR_INVALID, "%s: problem size changed since create", name);
    hp_error e = hpi_backend_check_problem(pb, d);
    if (e == HP_ERR_DOMAIN) {
        r->status = HP_STATUS_INFEASIBLE_START;
        return HP_OK;
    }
    if (e != HP_OK) return e;
    e = hpi_backend_start(pb, x0, xs);
    if (e != HP_OK) return hp_diag_set(d, e, "%s: starting point not finite or not valid", name);
    *go = 1;
    return HP_OK;
}

int hpi_backend_first_order_ok(const hp_problem *pb, const double *x, double tolerance)
{
    hp_kkt_measure m;
    if (hpi_backend_kkt_measure(pb, x, &m) != HP_OK) return 0;
    /* Loose on purpose: SLSQP's answers stop up to ~1e-5 mm/deg short and its multipliers
     * are not exact, while a stalled start point misses stationarity by O(1) of the
     * gradient; 1e-3 of the gradient's scale separates the two. */
    double feas = 10.0 * tolerance > 1e-6 ? 10.0 * tolerance : 1e-6;
    double stat = 1e-3 * (1.0 + m.grad_max);
    return m.in_bounds && m.feasibility <= feas && m.stationarity <= stat && m.wrong_sign <= stat;
}
