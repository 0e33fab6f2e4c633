/* Goldfarb–Idnani dual active-set QP (see qp.h). Notation of the paper: G = L Lᵀ,
 * J = L⁻ᵀ Q, and Jᵀ N = [R; 0] for the matrix N of active constraint normals, so the primal
 * step direction is z = J₂J₂ᵀ n and the dual one r = R⁻¹J₁ᵀ n. Orthogonal updates use the
 * symmetric Givens reflector [[c, s], [s, −c]].
 *
 * Cost (this runs several times per realtime plan): J is stored transposed, Jt = Jᵀ, so
 * every operation on a column of J (the rotations, d = Jᵀn, z = J₂d) walks one contiguous
 * row; the initial Jt = L⁻¹ is lower triangular and the products with it skip its zeros
 * until the first rotation fills it (skipping an exact zero term leaves a sum bit-for-bit
 * the same); a row that is the exact negation of the row before it (a lower and an upper
 * limit on the same quantity) reuses that row's norm and product with x. */
#include "planner/qp.h"
#include "common/dense.h"

#include <math.h>
#include <string.h>

#define NM HP_QP_NMAX
#define IDX(i, j) ((i) * NM + (j))

/* Jt = L⁻¹ for G = L Lᵀ (Jt row-major, leading dimension NM, strict upper part zero).
 * Returns 0 unless G is positive definite with finite entries. */
static int inverse_cholesky_factor(const double *G, int n, double *Jt)
{
    memset(Jt, 0, NM * NM * sizeof *Jt);
    /* hp_cholesky reads only the lower triangle, and a NaN or infinity there fails a pivot
     * test (it reaches that pivot's sum of squares), except +inf on the diagonal, which
     * gives an infinite L_jj; the upper triangle is checked here. */
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            if (!isfinite(G[i * n + j])) return 0;
    if (!hp_cholesky(G, n, n, 0.0, Jt, NM)) return 0;
    /* L⁻¹ column by column, in place: column j of L⁻¹ needs the entries L_ik (k >= j) of
     * rows not yet overwritten and the entries of L⁻¹ already computed in column j. */
    for (int j = 0; j < n; ++j) {
        if (!isfinite(Jt[IDX(j, j)])) return 0;
        Jt[IDX(j, j)] = 1.0 / Jt[IDX(j, j)];
        for (int i = j + 1; i < n; ++i) {
            double t = 0;
            for (int k = j; k < i; ++k) t -= Jt[IDX(i, k)] * Jt[IDX(k, j)];
            Jt[IDX(i, j)] = t / Jt[IDX(i, i)];
        }
    }
    return 1;
}

/* The reflector zeroing b against a: c = a/h, s = b/h, returns h = |(a, b)| (b != 0).
 * sqrt(a² + b²) is within about one ulp of hypot wherever the squares can neither overflow
 * nor become subnormal, which 1e-150 < h < 1e150 guarantees; outside, hypot. */
static double givens(double a, double b, double *c, double *s)
{
    double h = sqrt(a * a + b * b);
    if (!(h > 1e-150 && h < 1e150)) h = hypot(a, b);
    *c = a / h;
    *s = b / h;
    return h;
}

/* Applies the reflector to rows j and j + 1 of Jt (columns j, j + 1 of J). */
static void rotate_rows(double *Jt, int n, int j, double c, double s)
{
    double *r1 = &Jt[IDX(j, 0)], *r2 = &Jt[IDX(j + 1, 0)];
    for (int i = 0; i < n; ++i) {
        double t1 = r1[i], t2 = r2[i];
        r1[i] = c * t1 + s * t2;
        r2[i] = s * t1 - c * t2;
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
        double a = R[IDX(j, j)], bb = R[IDX(j + 1, j)], c, s;
        if (bb == 0.0) continue;
        givens(a, bb, &c, &s);
        for (int k = j; k < qq - 1; ++k) {
            double t1 = R[IDX(j, k)], t2 = R[IDX(j + 1, k)];
            R[IDX(j, k)] = c * t1 + s * t2;
            R[IDX(j + 1, k)] = s * t1 - c * t2;
        }
        R[IDX(j + 1, j)] = 0.0;
        rotate_rows(qp->J_, n, j, c, s);
    }
    *q = qq - 1;
}

/* Checks the rows of C and b (finite entries, a row norm that does not overflow), fills
 * nrm, and marks in twin the rows that are the exact negation of the row before (that row
 * not itself a twin). Returns 0 on bad input. */
static int check_rows(const hp_qp *qp, double *nrm, int *twin)
{
    int n = qp->n;
    for (int j = 0; j < qp->m; ++j) {
        const double *c = &qp->C[j * NM];
        if (!isfinite(qp->b[j])) return 0;
        twin[j] = j > 0 && !twin[j - 1];
        for (int i = 0; i < n && twin[j]; ++i) twin[j] = c[i] == -c[i - NM];
        if (twin[j]) { /* equal to a finite row: finite */
            nrm[j] = nrm[j - 1];
            continue;
        }
        double s = 0;
        for (int i = 0; i < n; ++i) s += c[i] * c[i];
        if (!isfinite(s)) return 0; /* a NaN or infinity in the row, or |row|² overflows */
        nrm[j] = sqrt(s);
    }
    return 1;
}

hp_qp_status hp_qp_solve(hp_qp *qp, int max_iter, double feas_tol)
{
    int n = qp->n, m = qp->m;
    if (n < 1 || n > NM || m < 0 || m > HP_QP_MMAX || max_iter < 1) return HP_QP_BAD_INPUT;
    double *Jt = qp->J_, *R = qp->R_, *x = qp->x, *u = qp->uA_;
    double nrm[HP_QP_MMAX];
    int twin[HP_QP_MMAX];
    for (int i = 0; i < n; ++i)
        if (!isfinite(qp->a[i])) return HP_QP_BAD_INPUT;
    if (!check_rows(qp, nrm, twin)) return HP_QP_BAD_INPUT;
    memset(R, 0, sizeof qp->R_);
    memset(qp->u, 0, sizeof qp->u);
    memset(qp->active, 0, sizeof qp->active);
    qp->iterations = 0;
    if (!inverse_cholesky_factor(qp->G, n, Jt)) return HP_QP_BAD_INPUT;

    /* x = −G⁻¹a = −J Jᵀ a, with J = Jtᵀ upper triangular */
    double Jta[NM];
    for (int k = 0; k < n; ++k) {
        Jta[k] = 0;
        for (int i = 0; i <= k; ++i) Jta[k] += Jt[IDX(k, i)] * qp->a[i];
    }
    for (int i = 0; i < n; ++i) {
        x[i] = 0;
        for (int k = i; k < n; ++k) x[i] -= Jt[IDX(k, i)] * Jta[k];
    }
    int q = 0, in_active[HP_QP_MMAX] = {0}, tri = 1; /* tri: Jt still lower triangular */

    for (;;) {
        /* Step 1: the most violated constraint, measured per unit-norm row. */
        int p = -1;
        double worst = -feas_tol, cx = 0;
        for (int j = 0; j < m; ++j) {
            if (twin[j]) {
                cx = -cx;
            } else {
                cx = 0;
                for (int i = 0; i < n; ++i) cx += qp->C[j * NM + i] * x[i];
            }
            if (in_active[j]) continue;
            double s = cx - qp->b[j];
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
            double d[NM], z[NM] = {0}, r[NM], dd_all = 0, dd2 = 0;
            for (int k = 0; k < n; ++k) {
                const double *jk = &Jt[IDX(k, 0)];
                int len = tri ? k + 1 : n;
                d[k] = 0;
                for (int i = 0; i < len; ++i) d[k] += jk[i] * np[i];
                dd_all += d[k] * d[k];
                if (k >= q) dd2 += d[k] * d[k];
            }
            for (int k = q; k < n; ++k) {
                const double *jk = &Jt[IDX(k, 0)];
                int len = tri ? k + 1 : n;
                for (int i = 0; i < len; ++i) z[i] += jk[i] * d[k];
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
                tri = 0;
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
                    double c, s;
                    d[j - 1] = givens(d[j - 1], d[j], &c, &s);
                    d[j] = 0.0;
                    tri = 0;
                    rotate_rows(Jt, n, j - 1, c, s);
                }
                for (int i = 0; i <= q; ++i) R[IDX(i, q)] = d[i];
                qp->A_[q] = p;
                u[q] = up;
                in_active[p] = 1;
                ++q;
                break;
            }
            in_active[qp->A_[l]] = 0; /* partial step: a blocking multiplier hit zero */
            tri = 0;
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
