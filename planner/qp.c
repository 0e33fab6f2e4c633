/* Goldfarb–Idnani dual active-set QP (see qp.h). Notation of the paper: G = L Lᵀ,
 * J = L⁻ᵀ Q, and Jᵀ N = [R; 0] for the matrix N of active constraint normals, so the primal
 * step direction is z = J₂J₂ᵀ n and the dual one r = R⁻¹J₁ᵀ n. Orthogonal updates use the
 * symmetric Givens reflector [[c, s], [s, −c]]. */
#include "planner/qp.h"
#include "common/dense.h"

#include <math.h>
#include <string.h>

#define NM HP_QP_NMAX
#define IDX(i, j) ((i) * NM + (j))

static int cholesky_inverse_transpose(const double *G, int n, double *J)
{
    double L[NM * NM] = {0}, Li[NM * NM] = {0};
    if (!hp_cholesky(G, n, n, 0.0, L, NM)) return 0;
    for (int j = 0; j < n; ++j) { /* Li = L⁻¹, lower triangular, column by column */
        Li[IDX(j, j)] = 1.0 / L[IDX(j, j)];
        for (int i = j + 1; i < n; ++i) {
            double t = 0;
            for (int k = j; k < i; ++k) t -= L[IDX(i, k)] * Li[IDX(k, j)];
            Li[IDX(i, j)] = t / L[IDX(i, i)];
        }
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) J[IDX(i, j)] = Li[IDX(j, i)];
    return 1;
}

static void rotate_cols(double *M, int rows, int j, double c, double s)
{
    for (int i = 0; i < rows; ++i) {
        double t1 = M[IDX(i, j)], t2 = M[IDX(i, j + 1)];
        M[IDX(i, j)] = c * t1 + s * t2;
        M[IDX(i, j + 1)] = s * t1 - c * t2;
    }
}

/* Removes active constraint number l (0 <= l < q) and restores R to triangular form. */
static void drop(hp_qp *qp, int *q, int l)
{
    int n = qp->n, qq = *q;
    double *R = qp->R_;
    for (int k = l; k < qq - 1; ++k) {
        qp->A_[k] = qp->A_[k + 1];
        qp->uA_[k] = qp->uA_[k + 1];
        for (int i = 0; i < qq; ++i) R[IDX(i, k)] = R[IDX(i, k + 1)];
    }
    for (int i = 0; i < qq; ++i) R[IDX(i, qq - 1)] = 0.0;
    for (int j = l; j < qq - 1; ++j) {
        double a = R[IDX(j, j)], bb = R[IDX(j + 1, j)];
        if (bb == 0.0) continue;
        double h = hypot(a, bb), c = a / h, s = bb / h;
        for (int k = j; k < qq - 1; ++k) {
            double t1 = R[IDX(j, k)], t2 = R[IDX(j + 1, k)];
            R[IDX(j, k)] = c * t1 + s * t2;
            R[IDX(j + 1, k)] = s * t1 - c * t2;
        }
        R[IDX(j + 1, j)] = 0.0;
        rotate_cols(qp->J_, n, j, c, s);
    }
    *q = qq - 1;
}

hp_qp_status hp_qp_solve(hp_qp *qp, int max_iter, double feas_tol)
{
    int n = qp->n, m = qp->m;
    if (n < 1 || n > NM || m < 0 || m > HP_QP_MMAX || max_iter < 1) return HP_QP_BAD_INPUT;
    for (int i = 0; i < n * n; ++i)
        if (!isfinite(qp->G[i])) return HP_QP_BAD_INPUT;
    for (int j = 0; j < m; ++j) {
        if (!isfinite(qp->b[j])) return HP_QP_BAD_INPUT;
        for (int i = 0; i < n; ++i)
            if (!isfinite(qp->C[j * NM + i])) return HP_QP_BAD_INPUT;
    }
    double *J = qp->J_, *R = qp->R_, *x = qp->x, *u = qp->uA_;
    memset(R, 0, sizeof qp->R_);
    memset(qp->u, 0, sizeof qp->u);
    memset(qp->active, 0, sizeof qp->active);
    qp->iterations = 0;
    if (!cholesky_inverse_transpose(qp->G, n, J)) return HP_QP_BAD_INPUT;

    double nrm[HP_QP_MMAX];
    for (int j = 0; j < m; ++j) {
        double s = 0;
        for (int i = 0; i < n; ++i) s += qp->C[j * NM + i] * qp->C[j * NM + i];
        nrm[j] = sqrt(s);
    }
    /* x = −G⁻¹a = −J Jᵀ a */
    double Jta[NM];
    for (int k = 0; k < n; ++k) {
        Jta[k] = 0;
        for (int i = 0; i < n; ++i) Jta[k] += J[IDX(i, k)] * qp->a[i];
    }
    for (int i = 0; i < n; ++i) {
        x[i] = 0;
        for (int k = 0; k < n; ++k) x[i] -= J[IDX(i, k)] * Jta[k];
    }
    int q = 0, in_active[HP_QP_MMAX] = {0};

    for (;;) {
        /* Step 1: the most violated constraint, measured per unit-norm row. */
        int p = -1;
        double worst = -feas_tol;
        for (int j = 0; j < m; ++j) {
            if (in_active[j]) continue;
            double s = -qp->b[j];
            for (int i = 0; i < n; ++i) s += qp->C[j * NM + i] * x[i];
            if (nrm[j] == 0.0) {
                if (s < -feas_tol) return HP_QP_INFEASIBLE;
                continue;
            }
            if (s / nrm[j] < worst) {
                worst = s / nrm[j];
                p = j;
            }
        }
        if (p < 0) break;
        const double *np = &qp->C[p * NM];
        double up = 0.0;
        for (;;) { /* Step 2 */
            if (++qp->iterations > max_iter) return HP_QP_ITERATION_LIMIT;
            double d[NM], z[NM], r[NM], dd_all = 0, dd2 = 0;
            for (int k = 0; k < n; ++k) {
                d[k] = 0;
                for (int i = 0; i < n; ++i) d[k] += J[IDX(i, k)] * np[i];
                dd_all += d[k] * d[k];
                if (k >= q) dd2 += d[k] * d[k];
            }
            for (int i = 0; i < n; ++i) {
                z[i] = 0;
                for (int k = q; k < n; ++k) z[i] += J[IDX(i, k)] * d[k];
            }
            for (int k = q - 1; k >= 0; --k) {
                double t = d[k];
                for (int j = k + 1; j < q; ++j) t -= R[IDX(k, j)] * r[j];
                r[k] = t / R[IDX(k, k)];
            }
            double t1 = INFINITY;
            int l = -1;
            for (int k = 0; k < q; ++k)
                if (r[k] > 0 && u[k] / r[k] < t1) {
                    t1 = u[k] / r[k];
                    l = k;
                }
            /* n_p lies in the span of the active normals when J₂ᵀn_p vanishes. */
            int z_zero = !(dd2 > 1e-24 * dd_all) || q == n;
            double t2 = INFINITY;
            if (!z_zero) {
                double sp = -qp->b[p];
                for (int i = 0; i < n; ++i) sp += np[i] * x[i];
                t2 = -sp / dd2; /* zᵀn_p = |J₂ᵀn_p|² */
                if (t2 < 0) t2 = 0;
            }
            if (z_zero && l < 0) return HP_QP_INFEASIBLE;
            if (z_zero) {
                for (int k = 0; k < q; ++k) u[k] -= t1 * r[k];
                up += t1;
                in_active[qp->A_[l]] = 0;
                drop(qp, &q, l);
                continue;
            }
            double t = t1 < t2 ? t1 : t2;
            for (int i = 0; i < n; ++i) x[i] += t * z[i];
            for (int k = 0; k < q; ++k) u[k] -= t * r[k];
            up += t;
            if (t2 <= t1) { /* full step: p joins the active set */
                for (int j = n - 1; j > q; --j) {
                    if (d[j] == 0.0) continue;
                    double h = hypot(d[j - 1], d[j]), c = d[j - 1] / h, s = d[j] / h;
                    d[j - 1] = h;
                    d[j] = 0.0;
                    rotate_cols(J, n, j - 1, c, s);
                }
                for (int i = 0; i <= q; ++i) R[IDX(i, q)] = d[i];
                qp->A_[q] = p;
                u[q] = up;
                in_active[p] = 1;
                ++q;
                break;
            }
            in_active[qp->A_[l]] = 0; /* partial step: a blocking multiplier hit zero */
            drop(qp, &q, l);
        }
    }
    for (int k = 0; k < q; ++k) {
        qp->u[qp->A_[k]] = u[k];
        qp->active[qp->A_[k]] = 1;
    }
    for (int i = 0; i < n; ++i)
        if (!isfinite(x[i])) return HP_QP_BAD_INPUT;
    return HP_QP_OPTIMAL;
}
