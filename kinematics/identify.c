/* What the contact model can tell apart (hp_identifiable in hp_contact.h): the rank of
 * the contact Jacobian in a dimensionless head-centred frame, the commanded pose components,
 * the unobservable motions, the rotation and translation range, and the commanded part of a
 * desired correction. */
#include "kin_internal.h"
#include "kin_geom.h"
#include "common/units.h"
#include "linalg.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define ID_PI HP_PI

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Row k of the Jacobian in the head-centred frame, made dimensionless: the translation of
 * the head centre (m/m) and the rotation about it times the length ell (m/(rad·m)). Written
 * from the geometry directly (not from the pivot-frame Jacobian), so no far pivot cancels
 * digits: a sphere's rotation columns are exactly zero. */
static void centred_row(const hp_geom *G, int k, double ell, double row[6])
{
    const double *n = G->normal[k];
    double lv[3], m[3];
    for (int i = 0; i < 3; ++i) lv[i] = G->contact[k][i] - G->head.center[i];
    cross3(lv, n, m);
    for (int i = 0; i < 3; ++i) {
        row[i] = -n[i];
        row[3 + i] = -m[i] / ell;
    }
}

/* Column j of the map from pose coordinates about the pivot to the dimensionless centred
 * coordinates: a translation moves the centre by itself; a rotation ω_j about the pivot
 * moves the centre by ω_j e_j × w (w = centre − pivot) and turns it by ω_j (times ell). */
static void pivot_column(const hp_layout *L, int j, double ell, double col[6])
{
    memset(col, 0, 6 * sizeof *col);
    if (j < 3) {
        col[j] = 1.0;
        return;
    }
    double e[3] = {0, 0, 0}, w[3], t[3];
    e[j - 3] = 1.0;
    for (int i = 0; i < 3; ++i) w[i] = L->head.center[i] - L->pivot[i];
    cross3(e, w, t);
    for (int i = 0; i < 3; ++i) col[i] = t[i] / ell;
    col[j] = 1.0;
}

/* Rank of Jc (n×6) on the span of the pivot columns selected by keep[] (dimensionless),
 * relative to the largest singular value. The kept columns are first made orthonormal (Gram
 * –Schmidt, twice): a far pivot makes them nearly parallel (1 km: a turn's own part is 1e-4
 * of its column, the rest a translation) and Jc times them directly would square that ratio
 * in the singular values; the span, which is all the rank depends on, is well conditioned.
 * With every translation kept it is exactly the span of the same components about the head
 * centre. Jc's columns are not normalised: a sphere's rotation about its centre has a column
 * of rounding noise (~1e-17) that must stay negligible. */
static int subset_rank(int n, const double *Jc, const double A[6][6], const int keep[6])
{
    double Q[6][6], M[HP_MAX_BLADDERS * 6], sv[6], V[36];
    int c = 0;
    for (int j = 0; j < 6; ++j) {
        if (!keep[j]) continue;
        double q[6];
        memcpy(q, A[j], sizeof q);
        for (int pass = 0; pass < 2; ++pass)
            for (int m = 0; m < c; ++m) {
                double d = 0.0;
                for (int i = 0; i < 6; ++i) d += Q[m][i] * q[i];
                for (int i = 0; i < 6; ++i) q[i] -= d * Q[m][i];
            }
        double nq = 0.0;
        for (int i = 0; i < 6; ++i) nq += q[i] * q[i];
        nq = sqrt(nq);
        if (!(nq > 0)) continue; /* A is invertible: does not happen */
        for (int i = 0; i < 6; ++i) Q[c][i] = q[i] / nq;
        ++c;
    }
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < 6; ++j) {
            double v = 0.0;
            if (j < c)
                for (int i = 0; i < 6; ++i) v += Jc[k * 6 + i] * Q[j][i];
            M[k * 6 + j] = v;
        }
    if (hpi_kin_svd6(n, M, sv, V) != 0) return -1;
    int r = 0;
    for (int j = 0; j < 6; ++j) r += sv[j] > HP_IDENT_RANK_TOL * sv[0];
    return r;
}

static void describe_symmetry(const hp_head *h, int centre_only, char *out, size_t size)
{
    const double *a = h->semi_axes;
    static const char *const ax[3] = {"X", "Y", "Z"};
    if (centre_only) {
        snprintf(out, size,
                 "every rotation about its centre (only the centre's motion is "
                 "observable)");
        return;
    }
    for (int i = 0; i < 3; ++i) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        if (a[j] == a[k]) {
            snprintf(out, size,
                     "every turn about its %s axis and half-turns about every axis "
                     "across it",
                     ax[i]);
            return;
        }
    }
    snprintf(out, size, "half-turns about its X, Y and Z axes");
}

hp_error hpi_layout_identify_g(const hp_layout *L, const hp_geom *G, hp_identifiable *out)
{
    if (!L || !G || !out) return HP_ERR_NULL;
    memset(out, 0, sizeof *out);
    const double *a = G->head.semi_axes;
    double ell = fmax(a[0], fmax(a[1], a[2]));
    out->length = ell;
    out->centre_only = a[0] == a[1] && a[1] == a[2];
    int n = L->n;
    double Jc[HP_MAX_BLADDERS * 6], sv[6], V[36];
    for (int k = 0; k < n; ++k) centred_row(G, k, ell, Jc + 6 * k);
    if (hpi_kin_svd6(n, Jc, sv, V) != 0) return HP_ERR_NO_CONVERGENCE;
    if (!(sv[0] > 0)) return HP_ERR_INVALID;
    int rank = 0;
    for (int j = 0; j < 6; ++j) {
        out->rel_sv[j] = sv[j] / sv[0];
        rank += out->rel_sv[j] > HP_IDENT_RANK_TOL;
    }
    out->rank = rank;
    out->n_null = 6 - rank;
    /* Unobservable motions: right singular vectors past the rank, from centred coordinates
     * (translation t_c, ell·ω) back to pose coordinates about the pivot:
     * ω = v_r / ell, t = t_c − ω × w. */
    double w[3];
    for (int i = 0; i < 3; ++i) w[i] = L->head.center[i] - L->pivot[i];
    for (int m = 0; m < out->n_null; ++m) {
        double tc[3], om[3], oxw[3];
        for (int i = 0; i < 3; ++i) {
            tc[i] = V[i * 6 + rank + m];
            om[i] = V[(3 + i) * 6 + rank + m] / ell;
        }
        cross3(om, w, oxw);
        for (int i = 0; i < 3; ++i) {
            out->null_space[m][i] = tc[i] - oxw[i];
            out->null_space[m][3 + i] = om[i];
        }
    }
    /* Commanded components: drop rotations, then translations, while the rest keep the
     * rank (the sphere's rotations are the natural unobservable ones). */
    double A[6][6];
    for (int j = 0; j < 6; ++j) pivot_column(L, j, ell, A[j]);
    for (int j = 0; j < 6; ++j) out->commanded[j] = 1;
    static const int order[6] = {HP_YAW, HP_ROLL, HP_PITCH, HP_Z, HP_Y, HP_X};
    int dropped = 0;
    for (int t = 0; t < 6 && dropped < out->n_null; ++t) {
        out->commanded[order[t]] = 0;
        int r = subset_rank(n, Jc, (const double(*)[6])A, out->commanded);
        if (r < 0) return HP_ERR_NO_CONVERGENCE;
        if (r == rank) ++dropped;
        else out->commanded[order[t]] = 1;
    }
    out->rot_limit = out->centre_only ? ID_PI : 0.5 * ID_PI;
    out->trans_limit = fmin(a[0], fmin(a[1], a[2]));
    describe_symmetry(&G->head, out->centre_only, out->symmetry, sizeof out->symmetry);
    return HP_OK;
}

double hp_pose_rotation_angle(const double xi[6])
{
    double R[9];
    hpi_kin_rotation_derivs(xi + 3, R, NULL, NULL);
    /* atan2 of |axis·sin| and cos: accurate at every angle, unlike acos near 0 and pi. */
    double s = 0.5 * hypot(hypot(R[7] - R[5], R[2] - R[6]), R[3] - R[1]);
    double c = 0.5 * (R[0] + R[4] + R[8] - 1.0);
    return atan2(s, c);
}

/* Solves the m×m system M a = b (m <= 6) by Gaussian elimination with partial pivoting;
 * returns 0 when M is singular. */
static int solve_small(int m, double M[6][6], double b[6], double x[6])
{
    for (int c = 0; c < m; ++c) {
        int piv = c;
        for (int r = c + 1; r < m; ++r)
            if (fabs(M[r][c]) > fabs(M[piv][c])) piv = r;
        if (!(fabs(M[piv][c]) > 0)) return 0;
        for (int j = 0; j < m; ++j) {
            double t = M[c][j];
            M[c][j] = M[piv][j];
            M[piv][j] = t;
        }
        double t = b[c];
        b[c] = b[piv];
        b[piv] = t;
        for (int r = c + 1; r < m; ++r) {
            double f = M[r][c] / M[c][c];
            for (int j = c; j < m; ++j) M[r][j] -= f * M[c][j];
            b[r] -= f * b[c];
        }
    }
    for (int c = m - 1; c >= 0; --c) {
        double s = b[c];
        for (int j = c + 1; j < m; ++j) s -= M[c][j] * x[j];
        x[c] = s / M[c][c];
    }
    return 1;
}

hp_error hpi_pose_commanded_part_g(const hp_layout *L, const hp_geom *G, const hp_identifiable *id,
                                   hp_level level, const double xd[6], double xc[6])
{
    if (!L || !G || !id || !xd || !xc) return HP_ERR_NULL;
    for (int i = 0; i < 6; ++i)
        if (!isfinite(xd[i])) return HP_ERR_INVALID;
    if (id->n_null == 0) {
        memcpy(xc, xd, 6 * sizeof *xc);
        return HP_OK;
    }
    int trans_only = id->commanded[0] && id->commanded[1] && id->commanded[2] &&
                     !id->commanded[3] && !id->commanded[4] && !id->commanded[5];
    if (id->centre_only && trans_only) {
        /* Exact: the head centre moves to pivot + R(h − pivot) + t under xd; the same
         * centre motion as a pure translation. R = I exactly at zero rotation, so a
         * translation-only xd comes back bit for bit. */
        double R[9], w[3];
        hpi_kin_rotation_derivs(xd + 3, R, NULL, NULL);
        for (int i = 0; i < 3; ++i) w[i] = L->head.center[i] - L->pivot[i];
        for (int i = 0; i < 3; ++i) {
            double Rw = R[i * 3] * w[0] + R[i * 3 + 1] * w[1] + R[i * 3 + 2] * w[2];
            xc[i] = xd[i] + (Rw - w[i]);
            xc[3 + i] = 0.0;
        }
        return HP_OK;
    }
    /* Linear projection along the unobservable motions: xc = xd − Σ a_m N_m with the
     * dropped components zero; exact for the linear model, the start of the fit. */
    int U[6], nu = 0;
    for (int i = 0; i < 6; ++i)
        if (!id->commanded[i]) U[nu++] = i;
    double M[6][6], b[6], coef[6] = {0};
    for (int u = 0; u < nu; ++u) {
        b[u] = xd[U[u]];
        for (int m = 0; m < id->n_null; ++m) M[u][m] = id->null_space[m][U[u]];
    }
    double x0[6];
    memcpy(x0, xd, sizeof x0);
    if (nu == id->n_null && solve_small(nu, M, b, coef))
        for (int m = 0; m < id->n_null; ++m)
            for (int i = 0; i < 6; ++i) x0[i] -= coef[m] * id->null_space[m][i];
    for (int u = 0; u < nu; ++u) x0[U[u]] = 0.0;
    int zero = 1;
    for (int u = 0; u < nu; ++u) zero &= xd[U[u]] == 0.0;
    if (zero || level == HP_LEVEL_LINEAR) {
        /* Nothing to remove (xd is its own commanded part, bit for bit), or the linear
         * model, where the projection is already exact. */
        memcpy(xc, zero ? xd : x0, 6 * sizeof *xc);
        return HP_OK;
    }
    double rho[HP_MAX_BLADDERS];
    hp_error e = hpi_contact_eval_g(L, G, level, xd, rho, NULL, NULL);
    if (e != HP_OK) return e;
    return hpi_contact_fit_g(L, G, level, rho, id->commanded, x0, xc, NULL, NULL);
}

hp_error hp_layout_identify(const hp_layout *L, hp_identifiable *out)
{
    if (!L || !out) return HP_ERR_NULL;
    hp_geom G;
    if (hpi_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hpi_layout_identify_g(L, &G, out);
}

hp_error hp_pose_commanded_part(const hp_layout *L, const hp_identifiable *id, hp_level level,
                                const double xd[6], double xc[6])
{
    if (!L || !id || !xd || !xc) return HP_ERR_NULL;
    hp_geom G;
    if (hpi_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    return hpi_pose_commanded_part_g(L, &G, id, level, xd, xc);
}
