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
 * and an upper limit on the same quantity) reuses that row's norm and product with x; the
 * caller may declare such pairs (hp_qp.pairs) so they are not compared on every call. The
 * factor of G is read in place (the caller's, or hpi_cholesky's), lower triangle only; the
 * substitutions with it are unrolled for n = NM and keep their vector in registers, and the
 * square root of a row's norm is taken only where a division by it is (a violated row).
 * Every one of these is arranged to give the bits of the plain formulation. */
#include "planner/qp.h"
#include "common/dense.h"
#include "common/same_bits.h"

#include <math.h>
#include <string.h>

#define NM HP_QP_NMAX
#define IDX(i, j) ((i)*NM + (j))

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

/* The lower Cholesky factor of G = L Lᵀ: *L and its leading dimension *ldl. Lg, when not
 * NULL, is the caller's factor of this G (leading dimension n), used in place (no copy:
 * every reader of the factor reads its lower triangle only); else G (n×n, leading
 * dimension n) is factored into Lw (leading dimension NM, lower triangle written).
 * Returns 0 unless G is positive definite with finite entries. */
static int cholesky_factor(const double *G, int n, const double *Lg, double *Lw, const double **L,
                           int *ldl)
{
    /* hpi_cholesky reads only the lower triangle, and a NaN or infinity there fails a pivot
     * test (it reaches that pivot's sum of squares), except +inf on the diagonal, which
     * gives an infinite L_jj; the upper triangle and that diagonal are checked by one sum:
     * g − g is +0 for a finite g and NaN otherwise, so z is 0 exactly when every entry is
     * finite (one test at the end, no branch per entry). */
    double z = 0.0;
    for (int i = 1; i < n; ++i)
        for (int j = 0; j < i; ++j) z += G[j * n + i] - G[j * n + i];
    if (Lg) {
        *L = Lg;
        *ldl = n;
    } else {
        if (!hpi_cholesky(G, n, n, 0.0, Lw, NM)) return 0;
        *L = Lw;
        *ldl = NM;
    }
    for (int i = 0; i < n; ++i) z += (*L)[i * *ldl + i] - (*L)[i * *ldl + i]; /* an infinite L_jj */
    return z == 0.0;
}

/* Jt = L⁻¹ (leading dimension NM, zero outside its lower n×n triangle; rows >= n are never
 * read) from the factor of cholesky_factor: row i of L⁻¹ is
 * (e_i − Σ_{k<i} L_ik·row k of L⁻¹) / L_ii, from the rows of L⁻¹ above it. */
static void invert_factor(const double *L, int ldl, int n, double *Jt)
{
    for (int i = 0; i < n; ++i) {
        double *row = &Jt[IDX(i, 0)], lii = L[i * ldl + i];
        memset(row, 0, NM * sizeof *row);
        for (int k = 0; k < i; ++k) axpy(row, -L[i * ldl + k], &Jt[IDX(k, 0)]);
        for (int j = 0; j < i; ++j) row[j] /= lii;
        row[i] = 1.0 / lii;
    }
}

/* 1 when the factor L (order n, leading dimension ldl; its lower triangle, all that
 * invert_factor reads) is the one whose inverse qp keeps (hp_qp.ck_). */
static int same_factor(const hp_qp *qp, const double *L, int ldl, int n)
{
    if (qp->ck_ < 1 || qp->ckn_ != n) return 0;
    if (ldl == NM) /* the n rows whole, as kept: one run of a loop that vectorises */
        return hpi_same_bits(L, qp->ckL_, n * NM);
    int same = 1;
    for (int i = 0; i < n; ++i) same &= hpi_same_bits(&L[i * ldl], &qp->ckL_[i * NM], i + 1);
    return same;
}

/* R zeroed and Jᵀ = L⁻¹ (invert_factor) in qp, the start of every Goldfarb–Idnani set-up:
 * the kept inverse when L is the factor it was formed from (the same function of the same
 * bits), else formed and kept. */
static void setup_inverse(hp_qp *qp, const double *L, int ldl, int n)
{
    double *R = qp->R_;
    /* row by row: a small memset compiles to a few stores, this one whole to a string
     * store with a slow start */
    for (int i = 0; i < NM; ++i) memset(&R[IDX(i, 0)], 0, NM * sizeof *R);
    if (same_factor(qp, L, ldl, n)) {
        memcpy(qp->J_, qp->ckJ0_, sizeof qp->J_);
        return;
    }
    invert_factor(L, ldl, n, qp->J_);
    if (ldl == NM) /* whole rows, above the diagonal too: same_factor compares them so */
        memcpy(qp->ckL_, L, (size_t)n * NM * sizeof *L);
    else
        for (int i = 0; i < n; ++i)
            for (int j = 0; j <= i; ++j) qp->ckL_[i * NM + j] = L[i * ldl + j];
    qp->ckn_ = n;
    memcpy(qp->ckJ0_, qp->J_, sizeof qp->J_);
    qp->ck_ = 1;
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

/* What load_rows found among the rows of zero norm: that there is one (only then does the
 * lazy solve look for a lazy one among them, a loop over every row otherwise run each solve),
 * and that one is violated whatever x is (the QP is empty). */
enum { ROWS_ZERO = 1, ROWS_EMPTY = 2 };

/* Row j's zero-norm verdict (ROWS_*) when its norm is zero and its b is bj */
static inline int zero_row(double bj, double feas_tol)
{
    return ROWS_ZERO | (-bj < -feas_tol ? ROWS_EMPTY : 0);
}

/* One row's checks: |w|² finite (a NaN or infinity in the row, or an overflowing norm,
 * fails), its squared norm, whether it is skipped (zero norm) and violated whatever x is. */
static int load_row(const hp_qp *qp, const double *w, int j, double feas_tol, double *nrm2,
                    int *skip, int *rows)
{
    double s = dot(w, w);
    if (!isfinite(s) || !isfinite(qp->b[j])) return 0;
    nrm2[j] = s;
    skip[j] = s == 0.0;
    if (skip[j]) *rows |= zero_row(qp->b[j], feas_tol);
    return 1;
}

/* The rows of C zero-padded to NM columns: C itself when n = NM (every column is read), else a copy
 * in qp->C_. Checks them and b (finite entries, a row norm that does not overflow), fills nrm2 with
 * the squared row norms, marks in twin the rows that are the exact negation of the row before (that
 * row not itself a twin): the odd rows of the qp->pairs declared pairs without comparing, the rows
 * after them by comparison; marks in skip the rows of zero norm; *rows (ROWS_*) says whether there
 * is such a row and whether one is violated beyond feas_tol (it holds for every x or for none).
 * Sets the outputs u and active to 0 on the way (scalar stores the loop hides; a memset of them
 * costs a string store's start-up). One pass over the rows. Returns the rows, NULL on bad input. */
static const double *load_rows(hp_qp *qp, double feas_tol, double *nrm2, int *twin, int *skip,
                               int *rows)
{
    int n = qp->n, m = qp->m, p2 = 2 * qp->pairs;
    const double *Cr = qp->C;
    if (n < NM) {
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < NM; ++i) qp->C_[j * NM + i] = i < n ? qp->C[j * NM + i] : 0.0;
        Cr = qp->C_;
    }
    *rows = 0;
    for (int j = 0; j < p2; j += 2) { /* declared pairs: the twin's norm is its partner's */
        if (!load_row(qp, &Cr[j * NM], j, feas_tol, nrm2, skip, rows) || !isfinite(qp->b[j + 1]))
            return NULL;
        nrm2[j + 1] = nrm2[j];
        skip[j + 1] = skip[j];
        if (skip[j]) *rows |= zero_row(qp->b[j + 1], feas_tol);
        twin[j] = 0;
        twin[j + 1] = 1;
        qp->u[j] = qp->u[j + 1] = 0.0;
        qp->active[j] = qp->active[j + 1] = 0;
    }
    for (int j = p2; j < m; ++j) {
        const double *w = &Cr[j * NM];
        twin[j] = j > 0 && !twin[j - 1] && negates(w, w - NM);
        qp->u[j] = 0.0;
        qp->active[j] = 0;
        if (!twin[j]) {
            if (!load_row(qp, w, j, feas_tol, nrm2, skip, rows)) return NULL;
            continue;
        }
        /* the negation of a checked row: finite, the same norm */
        if (!isfinite(qp->b[j])) return NULL;
        nrm2[j] = nrm2[j - 1];
        skip[j] = skip[j - 1];
        if (skip[j]) *rows |= zero_row(qp->b[j], feas_tol);
    }
    return Cr;
}

/* Row j's violation test of most_violated: r = C_j x − b_j, nrm2 = |C_j|². A row with
 * r >= 0 cannot be below a negative −feas_tol: its square root and division are skipped
 * (same answer, fewer operations: the norm is taken only for the rows that need it, and
 * it is the same bits wherever it is taken). */
static inline void violation(double r, double nrm2, int skip, int j, double *worst, int *p)
{
    if (skip || (!(r < 0.0) && *worst < 0.0)) return;
    double v = r / sqrt(nrm2);
    if (v < *worst) {
        *worst = v;
        *p = j;
    }
}

/* The most violated row at x, measured per unit-norm row (the violation (C_j x − b_j)/|C_j|
 * below −feas_tol), ignoring the rows marked in skip; −1 when none is. A twin row reuses
 * the product of the row before it, negated: a declared pair (qp->pairs) is tested as one
 * product and two rows, the rows after the pairs one by one. keep (may be NULL) receives
 * every row's product C_j x; kept (may be NULL) gives them instead of x: the products a
 * scan at this x kept, so the same bits, and the row picked is the same whatever b_j
 * changed since (each r = C_j x − b_j is formed again). Both NULL: the plain scan. */
static inline int scan_rows(hp_qp *qp, const double *Cr, const double *x, const double *nrm2,
                            const int *twin, const int *skip, double feas_tol, double *keep,
                            const double *kept)
{
    int p = -1, p2 = 2 * qp->pairs;
    double worst = -feas_tol, cx = 0;
    qp->scans += !kept;
    for (int j = 0; j < p2; j += 2) {
        cx = kept ? kept[j] : dot(&Cr[j * NM], x);
        if (keep) keep[j] = cx;
        violation(cx - qp->b[j], nrm2[j], skip[j], j, &worst, &p);
        violation(-cx - qp->b[j + 1], nrm2[j + 1], skip[j + 1], j + 1, &worst, &p);
    }
    for (int j = p2; j < qp->m; ++j) {
        cx = kept ? kept[j] : twin[j] ? -cx : dot(&Cr[j * NM], x);
        if (keep) keep[j] = cx;
        violation(cx - qp->b[j], nrm2[j], skip[j], j, &worst, &p);
    }
    return p;
}

static int most_violated(hp_qp *qp, const double *Cr, const double *x, const double *nrm2,
                         const int *twin, const int *skip, double feas_tol)
{
    return scan_rows(qp, Cr, x, nrm2, twin, skip, feas_tol, NULL, NULL);
}

/* most_violated in a solve that can stop on a stand-in row (lazy given) or that resumes one
 * (qp->cxk_: the scan before the stop kept the products at this x, which a resume leaves
 * as it was): the first scan after the stop takes the products kept, and a scan that can
 * stop keeps them. They are read only at the x they were formed at: every scan clears
 * cxk_, a stop alone sets it, and a stop leaves x where the scan was (a resume, which may
 * stop again on another stand-in at that x, then reads them again). */
static int most_violated_lazy(hp_qp *qp, const double *Cr, const double *x, const double *nrm2,
                              const int *twin, const int *skip, double feas_tol,
                              const unsigned char *lazy)
{
    int kept = qp->cxk_;
    qp->cxk_ = 0;
    if (kept) return scan_rows(qp, Cr, x, nrm2, twin, skip, feas_tol, NULL, qp->cx_);
    if (lazy) return scan_rows(qp, Cr, x, nrm2, twin, skip, feas_tol, qp->cx_, NULL);
    return most_violated(qp, Cr, x, nrm2, twin, skip, feas_tol);
}

/* y = L⁻¹v by forward substitution (L, ldl from cholesky_factor, its lower triangle read;
 * y zero-padded to NM), v[i] − Σ_{k<i} L_ik y_k summed from +0 in index order: the bits of
 * the zero-padded dot product this replaces (its extra terms are L_ik·0 = ±0, and a sum
 * that starts at +0 is never −0, so adding them changes nothing). Written for any n and
 * instantiated for n = NM (the realtime backend's case), where the loops unroll completely
 * and y stays in registers until the stores at the end. */
static inline void forward_subst_n(const double *L, int ldl, int n, const double *v, double *y)
{
    double t[NM];
#pragma GCC unroll 6
    for (int i = 0; i < n; ++i) {
        double s = 0;
#pragma GCC unroll 6
        for (int k = 0; k < i; ++k) s += L[i * ldl + k] * t[k];
        t[i] = (v[i] - s) / L[i * ldl + i];
    }
#pragma GCC unroll 6
    for (int i = 0; i < NM; ++i) y[i] = i < n ? t[i] : 0.0;
}

static void forward_subst(const double *L, int ldl, int n, const double *v, double *y)
{
    if (n == NM) forward_subst_n(L, NM, NM, v, y);
    else forward_subst_n(L, ldl, n, v, y);
}

/* x = L⁻ᵀy by back substitution, row by row of L (y is overwritten): x_i = y_i/L_ii, then
 * y_j += −x_i·L_ij for j < i — the same operations as the zero-padded axpy it replaces on
 * the entries it reads again. Instantiated like forward_subst; x zero-padded to NM. */
static inline void back_subst_n(const double *L, int ldl, int n, double *y, double *x)
{
    double t[NM], r[NM];
#pragma GCC unroll 6
    for (int i = 0; i < n; ++i) t[i] = y[i];
#pragma GCC unroll 6
    for (int i = n - 1; i >= 0; --i) {
        r[i] = t[i] / L[i * ldl + i];
#pragma GCC unroll 6
        for (int j = 0; j < i; ++j) t[j] += -r[i] * L[i * ldl + j];
    }
#pragma GCC unroll 6
    for (int i = 0; i < NM; ++i) x[i] = i < n ? r[i] : 0.0;
}

static void back_subst(const double *L, int ldl, int n, double *y, double *x)
{
    if (n == NM) back_subst_n(L, NM, NM, y, x);
    else back_subst_n(L, ldl, n, y, x);
}

/* The scaled Gram matrix S of the k normalised columns Mt (row c at Mt + c·NM), its
 * Cholesky factor Rs (leading dimension k) and the test (a) of warm_solve: 1 when every
 * pivot is positive and κ₂(S) <= trace(S)·‖Rs⁻¹‖_F² <= HP_QP_WARM_KAPPA. */
static int gram_factor(const double *Mt, int k, double *S, double *Rs)
{
    double trace = 0;
    for (int c = 0; c < k; ++c) {
        for (int e = 0; e <= c; ++e) S[c * k + e] = dot(&Mt[c * NM], &Mt[e * NM]);
        trace += S[c * k + c];
    }
    return k == 0 || (hpi_cholesky(S, k, k, 0.0, Rs, k) &&
                      trace * hpi_cholesky_inv_frob2(Rs, k, k) <= HP_QP_WARM_KAPPA);
}

/* The warm start (qp.h, hpi_qp_solve_warm): the equality-constrained QP on the guessed rows,
 * accepted as the answer only when it is the answer. With x = L⁻ᵀ(w + M u), w = −L⁻¹a and
 * the columns M_c = L⁻¹C_cᵀ of the k guessed rows, stationarity G x + a = Σ C_cᵀu_c holds
 * for any u, and the guessed rows hold as equalities when (MᵀM) u = b_A − Mᵀw. The Gram
 * matrix is formed of the normalised columns M_c/|M_c| (unit diagonal: the scaling makes
 * its condition number the smallest diagonal scaling can reach, within a factor k, and the
 * solve is invariant to it) and factored S = R Rᵀ. Accepted when (a) every pivot of S is
 * positive and κ₂(S) <= trace(S)·‖R⁻¹‖_F² <= HP_QP_WARM_KAPPA, (b) every u_c >= 0, (c)
 * every other row passes the same per-unit-norm test GI stops on. (a)+(b)+(c) are the KKT
 * conditions of the full QP, which for G positive definite characterise its unique minimum;
 * (a) also bounds the rounding (qp.h): the computed u solves (S + E) u = r with |E| ~ kε|S|,
 * so u carries κ(S)·kε; but stationarity holds for any u, so an error δu moves x only by
 * L⁻ᵀM δu, and |M δu| <= |E||u|/σ_min(M) — a factor √κ(S), as in the full solve's QR.
 *
 * warm_solve does (a) and (b): it writes x (the full solve overwrites it on a refusal) and
 * keeps the guessed rows (qp->wa_, qp->wk_), their scaled multipliers (qp->wu_) and column
 * norms (qp->wd_) for warm_check, which does (c) and writes the outputs u and active on
 * acceptance. Split so that a stop in (c) on a stand-in row resumes at (c): the equality
 * solve reads only the guessed rows' b, none of them a stand-in, so it would give the same
 * bits again. warm_solve returns HP_QP_WARM_ACCEPTED when (a) and (b) hold. When (b) fails
 * it drops the row of the most negative scaled multiplier and solves the smaller system
 * again (a principal submatrix of S: its condition is no worse, (a) is tested again all
 * the same), until every multiplier is >= 0: HP_QP_WARM_SIGN with the rows kept in
 * qp->wa_, qp->wk_ (wk_ 0: none kept, a NaN multiplier, or a refusal before the sign) and
 * their point in x, the dual-feasible start of warm_gi. */
static hp_qp_warm warm_solve(hp_qp *qp, const double *L, int ldl, const double *Cr, const int *A,
                             int k, const double *a, const int *twin, const int *skip, int max_iter,
                             const unsigned char *lazy, int *hit)
{
    int n = qp->n;
    qp->wk_ = 0;
    if (lazy) /* a guessed row's b enters the equality solve: it must be exact */
        for (int c = 0; c < k; ++c)
            if (lazy[A[c]]) {
                *hit = A[c];
                return HP_QP_WARM_NONE;
            }
    if (k > n || k > max_iter) return HP_QP_WARM_SHAPE;
    for (int c = 0; c < k; ++c) {
        int j = A[c];
        /* a twin pair's rows are exact negations: both active would leave no interior */
        if (skip[j] || (twin[j] && c > 0 && A[c - 1] == j - 1)) return HP_QP_WARM_SHAPE;
    }
    double w[NM], Mt[NM * NM], S[NM * NM], Rs[NM * NM], y[NM];
    double *D = qp->wd_, *us = qp->wu_;
    forward_subst(L, ldl, n, a, w);
    for (int i = 0; i < n; ++i) w[i] = -w[i];
    for (int c = 0; c < k; ++c) {
        double *mc = &Mt[c * NM];
        forward_subst(L, ldl, n, &Cr[A[c] * NM], mc);
        double d2 = dot(mc, mc); /* D_c in (0, inf) exactly when D_c² is, NaN failing */
        if (!(d2 > 0.0 && d2 < INFINITY)) return HP_QP_WARM_CONDITION;
        D[c] = sqrt(d2);
        double inv = 1.0 / D[c];
        for (int i = 0; i < NM; ++i) mc[i] *= inv;
    }
    int *wa = qp->wa_;
    memcpy(wa, A, (size_t)k * sizeof *A);
    hp_qp_warm verdict = HP_QP_WARM_ACCEPTED;
    for (;;) {
        if (!gram_factor(Mt, k, S, Rs)) /* (a); after a drop, of a principal submatrix */
            return verdict == HP_QP_WARM_ACCEPTED ? HP_QP_WARM_CONDITION : verdict;
        /* scaled multipliers us_c = |M_c|·u_c: S us = (b_c − M_cᵀw)/|M_c| */
        for (int c = 0; c < k; ++c) us[c] = qp->b[wa[c]] / D[c] - dot(&Mt[c * NM], w);
        if (k > 0) hpi_cholesky_solve(Rs, k, k, us);
        qp->warm_solved = 1;
        int neg = -1;
        for (int c = 0; c < k; ++c) {
            if (us[c] != us[c]) return HP_QP_WARM_SIGN; /* NaN: nothing to keep */
            if (us[c] < 0.0 && (neg < 0 || us[c] < us[neg])) neg = c;
        }
        if (neg < 0) break;
        /* the most negative (scaled) multiplier's row leaves; none left: the full solve,
         * whose start is that (empty) set's optimum */
        verdict = HP_QP_WARM_SIGN;
        if (--k == 0) return verdict;
        for (int c = neg; c < k; ++c) {
            wa[c] = wa[c + 1];
            D[c] = D[c + 1];
            memcpy(&Mt[c * NM], &Mt[(c + 1) * NM], NM * sizeof *Mt);
        }
    }
    memcpy(y, w, sizeof y);
    for (int c = 0; c < k; ++c) axpy(y, us[c], &Mt[c * NM]);
    back_subst(L, ldl, n, y, qp->x); /* the output x (the full solve overwrites it on refusal) */
    qp->wk_ = k;
    return verdict;
}

/* (c) of the warm start on warm_solve's x and kept rows: no other row violated beyond
 * feas_tol, as the full solve measures it; then the outputs u, active and iterations. A
 * stand-in row as the most violated one: HP_QP_WARM_NONE with *hit = that row. */
static hp_qp_warm warm_check(hp_qp *qp, const double *Cr, const double *nrm2, const int *twin,
                             int *skip, double feas_tol, const unsigned char *lazy, int *hit)
{
    const int *A = qp->wa_, k = qp->wk_;
    /* the guessed rows hold as equalities: skipped in the test (restored after; they were
     * 0, a skipped row having been refused by warm_solve) */
    for (int c = 0; c < k; ++c) skip[A[c]] = 1;
    int viol = most_violated_lazy(qp, Cr, qp->x, nrm2, twin, skip, feas_tol, lazy);
    for (int c = 0; c < k; ++c) skip[A[c]] = 0;
    if (viol >= 0 && lazy && lazy[viol]) {
        *hit = viol;
        qp->cxk_ = 1;
        return HP_QP_WARM_NONE;
    }
    if (viol >= 0) return HP_QP_WARM_VIOLATED;
    for (int c = 0; c < k; ++c) {
        qp->u[A[c]] = qp->wu_[c] / qp->wd_[c];
        qp->active[A[c]] = 1;
    }
    qp->iterations = k;
    return HP_QP_WARM_ACCEPTED;
}

/* The cold entries take a q whose problem alone was filled: nothing kept is read. */
hp_qp_status hpi_qp_solve(hp_qp *qp, int max_iter, double feas_tol)
{
    qp->ck_ = 0;
    return hpi_qp_solve_warm(qp, NULL, NULL, max_iter, feas_tol);
}

hp_qp_status hpi_qp_solve_factored(hp_qp *qp, const double *Lg, int max_iter, double feas_tol)
{
    qp->ck_ = 0;
    return hpi_qp_solve_warm(qp, Lg, NULL, max_iter, feas_tol);
}

hp_qp_status hpi_qp_solve_warm(hp_qp *qp, const double *Lg, const int *guess, int max_iter,
                               double feas_tol)
{
    return hpi_qp_solve_lazy(qp, Lg, guess, NULL, NULL, max_iter, feas_tol);
}

/* Row p joins the active set as number q, d = Jᵀn_p: the reflectors zero d below entry q
 * (rotating the columns of J with them) and d's first q + 1 entries become column q of R. */
static void add_active(hp_qp *qp, int q, double *d, int p)
{
    for (int j = qp->n - 1; j > q; --j) {
        if (d[j] == 0.0) continue;
        double c, s;
        d[j - 1] = givens(d[j - 1], d[j], &c, &s);
        d[j] = 0.0;
        rotate_rows(qp->J_, j - 1, c, s);
    }
    for (int i = 0; i <= q; ++i) qp->R_[IDX(i, q)] = d[i];
    qp->A_[q] = p;
    qp->skip_[p] = 1;
}

/* The Goldfarb–Idnani loop of hpi_qp_solve_lazy from the state in qp (x, Jᵀ, R, the active
 * set A_ of size q_ with multipliers uA_, the row state nrm2_, twin_, skip_): adds the most
 * violated row until none is. A stand-in row picked stops it (HP_QP_LAZY, resumable). */
static hp_qp_status gi_loop(hp_qp *qp, const double *Cr, const unsigned char *lazy, int *hit,
                            int max_iter, double feas_tol)
{
    int n = qp->n;
    double *Jt = qp->J_, *R = qp->R_, *x = qp->x, *u = qp->uA_, *nrm2 = qp->nrm2_;
    int *twin = qp->twin_, *skip = qp->skip_;
    int q = qp->q_;

    for (;;) {
        /* Step 1: the most violated constraint. */
        int p = most_violated_lazy(qp, Cr, x, nrm2, twin, skip, feas_tol, lazy);
        if (p < 0) break;
        if (lazy && lazy[p]) {
            *hit = p;
            qp->q_ = q;
            qp->resumable = 1;
            qp->cxk_ = 1;
            return HP_QP_LAZY;
        }
        const double *np = &Cr[p * NM];
        double up = 0.0;
        for (;;) { /* Step 2 */
            ++qp->gi_steps;
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
                add_active(qp, q, d, p);
                u[q] = up;
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

/* The full Goldfarb–Idnani solve from the unconstrained minimum, with the rows as
 * load_rows left them (no active row) and L, ldl from cholesky_factor. */
static hp_qp_status full_solve(hp_qp *qp, const double *L, int ldl, const double *Cr,
                               const unsigned char *lazy, int *hit, int max_iter, double feas_tol)
{
    int n = qp->n;
    double *Jt = qp->J_, *x = qp->x, a[NM] = {0};
    for (int i = 0; i < n; ++i) a[i] = qp->a[i]; /* checked finite by hpi_qp_solve_lazy */
    setup_inverse(qp, L, ldl, n);

    /* x = −G⁻¹a = −J Jᵀ a, column by column of J (rows of Jt) */
    memset(x, 0, sizeof qp->x);
    for (int k = 0; k < n; ++k) axpy(x, -dot(&Jt[IDX(k, 0)], a), &Jt[IDX(k, 0)]);
    qp->q_ = 0;
    qp->kept_ = 0;
    return gi_loop(qp, Cr, lazy, hit, max_iter, feas_tol);
}

/* The status qs of the loop; when it started from a warm start's kept rows (qp->kept_) and
 * found the QP empty, the full solve's verdict instead. From a degenerate vertex (rows
 * meeting at a point, one violated only by rounding) the loop can find a row dependent on
 * the kept ones that no multiplier lets in, where the full solve, through other rows,
 * finds the answer; an empty verdict is rare and final, so it is checked from scratch. */
static hp_qp_status kept_verdict(hp_qp *qp, hp_qp_status qs, const double *Cr,
                                 const unsigned char *lazy, int *hit, int max_iter, double feas_tol)
{
    if (qs != HP_QP_INFEASIBLE || !qp->kept_) return qs;
    qp->kept_ = 0;
    for (int j = 0; j < qp->m; ++j) qp->skip_[j] = qp->nrm2_[j] == 0.0; /* as load_rows left them */
    qp->iterations = 0;
    return full_solve(qp, qp->L_, NM, Cr, lazy, hit, max_iter, feas_tol);
}

/* The Goldfarb–Idnani solve started from the warm start's kept rows (qp->wa_, qp->wk_,
 * none a stand-in) and warm_solve's x, the minimum with those rows as equalities, and
 * their multipliers, all >= 0: a dual-feasible start, from which the loop reaches the
 * same unique minimum as from the unconstrained one (G positive definite), in fewer adds
 * when the rows kept are rows of the answer. J and R are those of adding the kept rows in
 * order (the factorisation of the add step, without its step: x is already there); each
 * kept row counts as one add step, as in an accepted warm start. */
static hp_qp_status warm_gi(hp_qp *qp, const double *L, int ldl, const double *Cr,
                            const unsigned char *lazy, int *hit, int max_iter, double feas_tol)
{
    int n = qp->n, k = qp->wk_;
    /* Jᵀ and R after the adds of the kept rows depend on the factor and on those rows (in
     * order) alone: kept from the last warm_gi when every one is the same bits (a ramp of
     * the rate limits keeps the same rows from plan to plan; hp_qp.ck_). */
    int same = qp->ck_ == 2 && qp->ckk_ == k && same_factor(qp, L, ldl, n);
    for (int c = 0; same && c < k; ++c)
        same = qp->cka_[c] == qp->wa_[c] &&
               hpi_same_bits(&qp->ckC_[c * NM], &Cr[qp->wa_[c] * NM], NM);
    if (same) {
        memcpy(qp->J_, qp->ckJ_, sizeof qp->J_);
        memcpy(qp->R_, qp->ckR_, sizeof qp->R_);
        for (int c = 0; c < k; ++c) { /* add_active's bookkeeping */
            qp->A_[c] = qp->wa_[c];
            qp->skip_[qp->wa_[c]] = 1;
        }
    } else {
        setup_inverse(qp, L, ldl, n);
        for (int c = 0; c < k; ++c) {
            int p = qp->wa_[c];
            double d[NM];
            for (int i = 0; i < n; ++i) d[i] = dot(&qp->J_[IDX(i, 0)], &Cr[p * NM]);
            add_active(qp, c, d, p);
            qp->cka_[c] = p;
            memcpy(&qp->ckC_[c * NM], &Cr[p * NM], NM * sizeof *Cr);
        }
        qp->ckk_ = k;
        memcpy(qp->ckJ_, qp->J_, sizeof qp->J_);
        memcpy(qp->ckR_, qp->R_, sizeof qp->R_);
        qp->ck_ = 2;
    }
    for (int c = 0; c < k; ++c) qp->uA_[c] = qp->wu_[c] / qp->wd_[c];
    qp->q_ = k;
    qp->iterations = k;
    if (L != qp->L_) /* for kept_verdict's full solve after a resume */
        for (int i = 0; i < n; ++i)
            for (int j = 0; j <= i; ++j) qp->L_[i * NM + j] = L[i * ldl + j];
    qp->kept_ = 1;
    return kept_verdict(qp, gi_loop(qp, Cr, lazy, hit, max_iter, feas_tol), Cr, lazy, hit, max_iter,
                        feas_tol);
}

/* After warm_solve's (a) and (b) held: its check (c), the answer when it holds, else the
 * full solve. A stop in the check (a stand-in row the most violated) is resumable
 * (resumable 2): the factor of G is kept in qp->L_ (leading dimension NM, the same
 * entries) for the full solve a refusal after the resume runs. */
static hp_qp_status warm_finish(hp_qp *qp, const double *L, int ldl, const double *Cr,
                                const unsigned char *lazy, int *hit, int max_iter, double feas_tol)
{
    qp->warm = warm_check(qp, Cr, qp->nrm2_, qp->twin_, qp->skip_, feas_tol, lazy, hit);
    if (*hit >= 0) {
        if (L != qp->L_)
            for (int i = 0; i < qp->n; ++i)
                for (int j = 0; j <= i; ++j) qp->L_[i * NM + j] = L[i * ldl + j];
        qp->resumable = 2;
        return HP_QP_LAZY;
    }
    if (qp->warm == HP_QP_WARM_ACCEPTED) {
        for (int i = 0; i < qp->n; ++i)
            if (!isfinite(qp->x[i])) return HP_QP_BAD_INPUT;
        return HP_QP_OPTIMAL;
    }
    if (qp->wk_ > 0) /* (a) and (b) hold: a dual-feasible start */
        return warm_gi(qp, L, ldl, Cr, lazy, hit, max_iter, feas_tol);
    return full_solve(qp, L, ldl, Cr, lazy, hit, max_iter, feas_tol);
}

hp_qp_status hpi_qp_solve_lazy(hp_qp *qp, const double *Lg, const int *guess,
                               const unsigned char *lazy, int *hit, int max_iter, double feas_tol)
{
    int n = qp->n, m = qp->m, hit_row = -1;
    if (!hit) hit = &hit_row;
    *hit = -1;
    qp->warm = HP_QP_WARM_NONE;
    qp->resumable = 0;
    qp->warm_solved = 0;
    qp->gi_steps = 0;
    qp->scans = 0;
    qp->kept_ = 0;
    qp->cxk_ = 0;
    if (n < 1 || n > NM || m < 0 || m > HP_QP_MMAX || max_iter < 1 || qp->pairs < 0 ||
        qp->pairs > m / 2)
        return HP_QP_BAD_INPUT;
    double *nrm2 = qp->nrm2_, a[NM] = {0};
    int *twin = qp->twin_, *skip = qp->skip_; /* skip: active rows and rows of zero norm */
    /* the guessed rows in index order, read before the outputs (guess may be qp->active) */
    int ga[HP_QP_MMAX], gk = 0;
    if (guess)
        for (int j = 0; j < m; ++j) {
            ga[gk] = j; /* gk <= j < m */
            gk += guess[j] != 0;
        }
    for (int i = 0; i < n; ++i) {
        if (!isfinite(qp->a[i])) return HP_QP_BAD_INPUT;
        a[i] = qp->a[i];
    }
    int rows;
    const double *Cr = load_rows(qp, feas_tol, nrm2, twin, skip, &rows);
    if (!Cr) return HP_QP_BAD_INPUT;
    qp->iterations = 0;
    const double *L;
    int ldl;
    if (!cholesky_factor(qp->G, n, Lg, qp->L_, &L, &ldl)) return HP_QP_BAD_INPUT;
    if (lazy && (rows & ROWS_ZERO)) /* a row of zero norm: its b alone decides emptiness */
        for (int j = 0; j < m; ++j)
            if (lazy[j] && skip[j]) {
                *hit = j;
                return HP_QP_LAZY;
            }
    if (rows & ROWS_EMPTY) return HP_QP_INFEASIBLE; /* a row of zero norm that no x satisfies */
    if (guess) {
        qp->warm = warm_solve(qp, L, ldl, Cr, ga, gk, a, twin, skip, max_iter, lazy, hit);
        if (*hit >= 0) return HP_QP_LAZY; /* before the equality solve: start again */
        if (qp->warm == HP_QP_WARM_ACCEPTED)
            return warm_finish(qp, L, ldl, Cr, lazy, hit, max_iter, feas_tol);
        if (qp->warm == HP_QP_WARM_SIGN && qp->wk_ > 0)
            return warm_gi(qp, L, ldl, Cr, lazy, hit, max_iter, feas_tol);
    }
    return full_solve(qp, L, ldl, Cr, lazy, hit, max_iter, feas_tol);
}

hp_qp_status hpi_qp_resume_lazy(hp_qp *qp, const unsigned char *lazy, int *hit, int max_iter,
                                double feas_tol)
{
    int hit_row = -1;
    if (!hit) hit = &hit_row;
    *hit = -1;
    int resumable = qp->resumable;
    if (!resumable) return HP_QP_BAD_INPUT;
    qp->resumable = 0;
    qp->warm_solved = 0;
    qp->gi_steps = 0;
    qp->scans = 0;
    /* load_rows's choice of rows: C itself at full width, else its padded copy (which
     * the stopped solve wrote and nothing since has changed) */
    const double *Cr = qp->n < NM ? qp->C_ : qp->C;
    /* A row's b made exact must still be a number: b − b is +0 for a finite b and NaN
     * otherwise, so the sum is 0 exactly when every b is finite (no branch per row). */
    double zb = 0.0;
    for (int j = 0; j < qp->m; ++j) zb += qp->b[j] - qp->b[j];
    if (!(zb == 0.0)) return HP_QP_BAD_INPUT;
    if (resumable == 2) /* stopped in the warm start's check, the factor kept in L_ */
        return warm_finish(qp, qp->L_, NM, Cr, lazy, hit, max_iter, feas_tol);
    return kept_verdict(qp, gi_loop(qp, Cr, lazy, hit, max_iter, feas_tol), Cr, lazy, hit, max_iter,
                        feas_tol);
}
