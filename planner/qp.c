/* Goldfarb–Idnani dual active-set QP (see qp.h). Notation of the paper: G = L Lᵀ,
 * J = L⁻ᵀ Q, and Jᵀ N = [R; 0] for the matrix N of active constraint normals, so the primal
 * step direction is z = J₂J₂ᵀ n and the dual one r = R⁻¹J₁ᵀ n. Orthogonal updates use the
 * symmetric Givens reflector [[c, s], [s, −c]].
 *
 * Cost (this runs several times per realtime plan): J is stored transposed, Jt = Jᵀ, so an
 * operation on a column of J (a rotation, d = Jᵀn, z = J₂d) walks one contiguous row; Jt,
 * the rows of C (copied) and x are zero-padded to NM columns, so the inner loops have a
 * fixed length the compiler unrolls and vectorises whatever n is. The padding changes no
 * result: a padded term is an exact ±0, and adding ±0 to a sum that starts at +0 leaves
 * it bit-for-bit the same. A row that is the exact negation of the row before it (a lower
 * and an upper limit on the same quantity) reuses that row's norm and product with x. */
#include "planner/qp.h"
#include "common/dense.h"

#include <math.h>
#include <string.h>

#define NM HP_QP_NMAX
#define IDX(i, j) ((i) * NM + (j))

/* uᵀv over the padded length, summed in index order (the pragma only unrolls) */
static double dot(const double *u, const double *v)
{
    double s = 0;
#pragma GCC unroll 6
    for (int i = 0; i < NM; ++i) s += u[i] * v[i];
    return s;
}

/* y += t·v over the padded length */
static void axpy(double *y, double t, const double *v)
{
#pragma GCC unroll 6
    for (int i = 0; i < NM; ++i) y[i] += t * v[i];
}

/* Jt = L⁻¹ for G = L Lᵀ (G n×n with leading dimension n; Jt with leading dimension NM,
 * zero outside its lower n×n triangle). Lg, when not NULL, is the caller's factor of this
 * G (leading dimension n), used instead of factoring again. Returns 0 unless G is positive
 * definite with finite entries. */
static int inverse_cholesky_factor(const double *G, int n, const double *Lg, double *Jt)
{
    memset(Jt, 0, NM * NM * sizeof *Jt);
    /* hp_cholesky reads only the lower triangle, and a NaN or infinity there fails a pivot
     * test (it reaches that pivot's sum of squares), except +inf on the diagonal, which
     * gives an infinite L_jj; the upper triangle is checked here. */
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
            if (!isfinite(G[i * n + j])) return 0;
    if (Lg) {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j <= i; ++j) Jt[IDX(i, j)] = Lg[i * n + j];
    } else if (!hp_cholesky(G, n, n, 0.0, Jt, NM)) {
        return 0;
    }
    /* L⁻¹ row by row, in place: row i of L⁻¹ is (e_i − Σ_{k<i} L_ik·row k of L⁻¹) / L_ii,
     * from row i of L (saved first) and the rows of L⁻¹ above it. */
    for (int i = 0; i < n; ++i) {
        double *row = &Jt[IDX(i, 0)], l[NM], lii = row[i];
        if (!isfinite(lii)) return 0;
        memcpy(l, row, sizeof l);
        memset(row, 0, sizeof l);
        for (int k = 0; k < i; ++k) axpy(row, -l[k], &Jt[IDX(k, 0)]);
        for (int j = 0; j < i; ++j) row[j] /= lii;
        row[i] = 1.0 / lii;
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
static void rotate_rows(double *Jt, int j, double c, double s)
{
    double *r1 = &Jt[IDX(j, 0)], *r2 = &Jt[IDX(j + 1, 0)];
    for (int i = 0; i < NM; ++i) {
        double t1 = r1[i], t2 = r2[i];
        r1[i] = c * t1 + s * t2;
        r2[i] = s * t1 - c * t2;
    }
}

/* Removes active constraint number l (0 <= l < q) and restores R to triangular form. */
static void drop(hp_qp *qp, int *q, int l)
{
    int qq = *q;
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
        rotate_rows(qp->J_, j, c, s);
    }
    *q = qq - 1;
}

/* 1 when row c is exactly the negation of row p (both padded with zeros). For finite
 * doubles c + p rounds to 0 only when the exact sum is 0 (a nonzero exact sum is at least
 * the smallest subnormal in magnitude, which rounds to itself); a NaN or infinity gives a
 * NaN or infinite sum; so the sum of |c_i + p_i| is 0 exactly when every c_i = −p_i. */
static int negates(const double *c, const double *p)
{
    double s = 0;
#pragma GCC unroll 6
    for (int i = 0; i < NM; ++i) s += fabs(c[i] + p[i]);
    return s == 0.0;
}

/* Copies the rows of C into qp->C_ (zero-padded), checks them and b (finite entries, a row
 * norm that does not overflow), fills nrm, marks in twin the rows that are the exact
 * negation of the row before (that row not itself a twin) and in skip the rows of zero
 * norm. Returns 0 on bad input. */
static int load_rows(hp_qp *qp, double *nrm, int *twin, int *skip)
{
    int n = qp->n, m = qp->m;
    memcpy(qp->C_, qp->C, (size_t)m * NM * sizeof *qp->C_);
    if (n < NM)
        for (int j = 0; j < m; ++j)
            for (int i = n; i < NM; ++i) qp->C_[j * NM + i] = 0.0;
    for (int j = 0; j < m; ++j) {
        const double *w = &qp->C_[j * NM];
        if (!isfinite(qp->b[j])) return 0;
        twin[j] = j > 0 && !twin[j - 1] && negates(w, w - NM);
        if (twin[j]) { /* the negation of a checked row: finite */
            nrm[j] = nrm[j - 1];
        } else {
            double s = dot(w, w);
            if (!isfinite(s)) return 0; /* a NaN or infinity in the row, or |row|² overflows */
            nrm[j] = sqrt(s);
        }
        skip[j] = nrm[j] == 0.0;
    }
    return 1;
}

hp_qp_status hp_qp_solve(hp_qp *qp, int max_iter, double feas_tol)
{
    return hp_qp_solve_factored(qp, NULL, max_iter, feas_tol);
}

hp_qp_status hp_qp_solve_factored(hp_qp *qp, const double *Lg, int max_iter, double feas_tol)
{
    int n = qp->n, m = qp->m;
    if (n < 1 || n > NM || m < 0 || m > HP_QP_MMAX || max_iter < 1) return HP_QP_BAD_INPUT;
    double *Jt = qp->J_, *R = qp->R_, *x = qp->x, *u = qp->uA_;
    double nrm[HP_QP_MMAX], a[NM] = {0};
    int twin[HP_QP_MMAX], skip[HP_QP_MMAX]; /* skip: active rows and rows of zero norm */
    for (int i = 0; i < n; ++i) {
        if (!isfinite(qp->a[i])) return HP_QP_BAD_INPUT;
        a[i] = qp->a[i];
    }
    if (!load_rows(qp, nrm, twin, skip)) return HP_QP_BAD_INPUT;
    memset(R, 0, sizeof qp->R_);
    memset(qp->u, 0, sizeof qp->u);
    memset(qp->active, 0, sizeof qp->active);
    qp->iterations = 0;
    if (!inverse_cholesky_factor(qp->G, n, Lg, Jt)) return HP_QP_BAD_INPUT;

    /* x = −G⁻¹a = −J Jᵀ a, column by column of J (rows of Jt) */
    memset(x, 0, sizeof qp->x);
    for (int k = 0; k < n; ++k) axpy(x, -dot(&Jt[IDX(k, 0)], a), &Jt[IDX(k, 0)]);
    /* a row of zero norm holds for every x or for none */
    for (int j = 0; j < m; ++j)
        if (skip[j] && -qp->b[j] < -feas_tol) return HP_QP_INFEASIBLE;
    int q = 0;

    for (;;) {
        /* Step 1: the most violated constraint, measured per unit-norm row. */
        int p = -1;
        double worst = -feas_tol, cx = 0;
        for (int j = 0; j < m; ++j) {
            cx = twin[j] ? -cx : dot(&qp->C_[j * NM], x);
            if (skip[j]) continue;
            double v = (cx - qp->b[j]) / nrm[j];
            if (v < worst) {
                worst = v;
                p = j;
            }
        }
        if (p < 0) break;
        const double *np = &qp->C_[p * NM];
        double up = 0.0;
        for (;;) { /* Step 2 */
            if (++qp->iterations > max_iter) return HP_QP_ITERATION_LIMIT;
            double d[NM], z[NM] = {0}, r[NM] = {0}, dd_all = 0, dd2 = 0;
            for (int k = 0; k < n; ++k) {
                d[k] = dot(&Jt[IDX(k, 0)], np);
                dd_all += d[k] * d[k];
                if (k >= q) dd2 += d[k] * d[k];
            }
            for (int k = q; k < n; ++k) axpy(z, d[k], &Jt[IDX(k, 0)]);
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
                t2 = -(dot(np, x) - qp->b[p]) / dd2; /* zᵀn_p = |J₂ᵀn_p|² */
                if (t2 < 0) t2 = 0;
            }
            if (z_zero && l < 0) return HP_QP_INFEASIBLE;
            if (z_zero) {
                for (int k = 0; k < q; ++k) u[k] -= t1 * r[k];
                up += t1;
                skip[qp->A_[l]] = 0;
                drop(qp, &q, l);
                continue;
            }
            double t = t1 < t2 ? t1 : t2;
            axpy(x, t, z);
            for (int k = 0; k < q; ++k) u[k] -= t * r[k];
            up += t;
            if (t2 <= t1) { /* full step: p joins the active set */
                for (int j = n - 1; j > q; --j) {
                    if (d[j] == 0.0) continue;
                    double c, s;
                    d[j - 1] = givens(d[j - 1], d[j], &c, &s);
                    d[j] = 0.0;
                    rotate_rows(Jt, j - 1, c, s);
                }
                for (int i = 0; i <= q; ++i) R[IDX(i, q)] = d[i];
                qp->A_[q] = p;
                u[q] = up;
                skip[p] = 1;
                ++q;
                break;
            }
            skip[qp->A_[l]] = 0; /* partial step: a blocking multiplier hit zero */
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
