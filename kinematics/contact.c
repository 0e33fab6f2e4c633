/* Contact distances at three fidelity levels with exact first and second derivatives.
 *
 * Surface and plane both evaluate a function f of the back-transformed bladder centre
 * c' = Rᵀ(c − pivot − t) + pivot (the centre seen from the head's own frame): the exact
 * distance of c' to the nominal head (surface), or nᵀ(c' − p) for the nominal tangent
 * plane (plane; equal to n(ξ)ᵀ(c − p(ξ)) with n(ξ) = R n, p(ξ) = pivot + R(p − pivot) + t).
 * Chain rule: J = ∇fᵀ C, H = Cᵀ ∇²f C + Σ_m ∂f/∂c'_m ∂²c'_m, C = ∂c'/∂ξ. */
#include "kin_internal.h"
#include "kin_geom.h"

#include <math.h>
#include <string.h>

/* c' and its first derivatives at pose xi for the centre whose arm is c − pivot
 * (hp_geom.arm); u = c − pivot − t, evaluated left to right as before, so the same bits.
 * ∂c'/∂t = −Rᵀ needs no storage; Cr = ∂c'/∂θ (3×3). */
typedef struct backmap {
    double cp[3], u[3];
    double Cr[3][3];
} backmap;

/* R with its derivatives in roll (hpi_kin_rotation_roll); every other derivative is a
 * signed copy of their entries, used where it is needed. */
typedef struct rotd {
    double R[9], Dr[9], Drr[9];
} rotd;

/* The columns of Cr use the structure of the rotation derivatives (hpi_kin_rotation_derivs):
 * ∂R/∂pitch = R·[e_x]× has the columns 0, R₂, −R₁, so its column of Cr is (0, w₂, −w₁)
 * with w = Rᵀu; ∂R/∂yaw = [e_z]×·R has the rows −R₁, R₀, 0, so its column is
 * R₀ᵀ·u₁ − R₁ᵀ·u₀ entrywise. Each is the sum the full 3-term product forms, less its exact
 * zero terms and with an exact negation moved out: the same bits (up to the sign of a zero)
 * for 15 products instead of 27. */
static void back_transform(const hp_layout *L, const double arm[3], const double xi[6],
                           const rotd *rd, int derivs, backmap *bm)
{
    const double *R = rd->R, *D = rd->Dr;
    double *u = bm->u, w[3];
    for (int i = 0; i < 3; ++i) u[i] = arm[i] - xi[i];
    for (int m = 0; m < 3; ++m) {
        w[m] = R[m] * u[0] + R[3 + m] * u[1] + R[6 + m] * u[2];
        bm->cp[m] = w[m] + L->pivot[m];
    }
    if (!derivs) return; /* distances only: Cr is never read */
    for (int m = 0; m < 3; ++m) {
        bm->Cr[m][1] = D[m] * u[0] + D[3 + m] * u[1] + D[6 + m] * u[2];
        bm->Cr[m][2] = -R[3 + m] * u[0] + R[m] * u[1];
    }
    bm->Cr[0][0] = 0.0;
    bm->Cr[1][0] = w[2];
    bm->Cr[2][0] = -w[1];
}

/* H = Cᵀ ∇²f C + Σ_m g_m ∂²c'_m (6×6, row-major, symmetric). The second derivatives of
 * c' = Rᵀu + pivot are sparse: none between translations, −∂_b R[a][m] between translation
 * a and rotation b, (∂²_ab Rᵀ u)_m between rotations. Contracted with g they are the
 * vectors ∂_b R g and the numbers uᵀ ∂²_ab R g, so the 3×6×6 array of ∂²c' is never
 * formed. Of the nine derivative matrices only ∂R/∂roll and ∂²R/∂roll² are not signed
 * copies of entries of R or of each other (hpi_kin_rotation_roll): with the pitch factor
 * [e_x]× on the right and the yaw factor [e_z]× on the left, every other contraction is a
 * two-term sum or a signed copy of Rg = R·g, Dg = ∂R/∂roll·g or P = ∂R/∂pitch·g, each the
 * sum the full 3-term contraction forms less its exact zero terms (the same bits, up to
 * the sign of a zero). hf NULL: f is linear in c' (the plane level), only the second
 * term. */
static void contact_hessian(const rotd *rd, const backmap *bm, const double g[3],
                            const double Rg[3], const double hf[9], double *restrict H)
{
    const double *u = bm->u, *R = rd->R, *Dr = rd->Dr, *Drr = rd->Drr;
#define HS(i, j) H[(i)*6 + (j)]
    if (hf) {
        /* The columns of C = ∂c'/∂ξ = [−Rᵀ | Cr]: c_i = −(row i of R), c_{3+i} = column i of
         * Cr; hc_i = ∇²f · c_i. The pitch column's first entry is an exact zero
         * (back_transform), so its products are left out of both sums. The upper triangle
         * is written straight into H (no zeroed 6×6 and copy), the lower one mirrored. */
        double C[6][3], hC[6][3];
        for (int i = 0; i < 3; ++i)
            for (int m = 0; m < 3; ++m) {
                C[i][m] = -R[i * 3 + m];
                C[3 + i][m] = bm->Cr[m][i];
            }
        for (int i = 0; i < 6; ++i)
            for (int a = 0; a < 3; ++a)
                hC[i][a] = i == 3 ? hf[a * 3 + 1] * C[3][1] + hf[a * 3 + 2] * C[3][2]
                                  : hf[a * 3] * C[i][0] + hf[a * 3 + 1] * C[i][1] +
                                        hf[a * 3 + 2] * C[i][2];
        for (int i = 0; i < 6; ++i)
            for (int j = i; j < 6; ++j)
                HS(i, j) = i == 3 ? C[3][1] * hC[j][1] + C[3][2] * hC[j][2]
                                  : C[i][0] * hC[j][0] + C[i][1] * hC[j][1] + C[i][2] * hC[j][2];
    } else {
        for (int i = 0; i < 6; ++i)
            for (int j = i; j < 6; ++j) HS(i, j) = 0.0;
    }
    double P[3], Dg[3], q00[3], q01[3], q11[3];
    for (int a = 0; a < 3; ++a) {
        const double *r = R + 3 * a, *d = Dr + 3 * a, *dd = Drr + 3 * a;
        P[a] = r[2] * g[1] - r[1] * g[2]; /* ∂R/∂pitch = R·[e_x]×: row (0, R_a2, −R_a1) */
        Dg[a] = d[0] * g[0] + d[1] * g[1] + d[2] * g[2];
        q00[a] = -(r[1] * g[1] + r[2] * g[2]); /* ∂²/∂pitch²: row (0, −R_a1, −R_a2) */
        q01[a] = d[2] * g[1] - d[1] * g[2];    /* ∂²/∂pitch∂roll = ∂R/∂roll·[e_x]× */
        q11[a] = dd[0] * g[0] + dd[1] * g[1] + dd[2] * g[2];
    }
    for (int a = 0; a < 3; ++a) {
        HS(a, 3) -= P[a];
        HS(a, 4) -= Dg[a];
    }
    /* ∂R/∂yaw = [e_z]×·R: rows −R₁, R₀, 0; so the yaw contractions of R, ∂R/∂pitch and
     * ∂R/∂roll are (−Rg₁, Rg₀, 0), (−P₁, P₀, 0), (−Dg₁, Dg₀, 0), and ∂²/∂yaw² gives
     * (−Rg₀, −Rg₁, 0); a zero term is left out (it adds nothing to a sum). */
    HS(0, 5) -= -Rg[1];
    HS(1, 5) -= Rg[0];
    HS(3, 3) += u[0] * q00[0] + u[1] * q00[1] + u[2] * q00[2];
    HS(3, 4) += u[0] * q01[0] + u[1] * q01[1] + u[2] * q01[2];
    HS(4, 4) += u[0] * q11[0] + u[1] * q11[1] + u[2] * q11[2];
    HS(3, 5) += u[0] * -P[1] + u[1] * P[0];
    HS(4, 5) += u[0] * -Dg[1] + u[1] * Dg[0];
    HS(5, 5) += u[0] * -Rg[0] + u[1] * -Rg[1];
    for (int i = 1; i < 6; ++i)
        for (int j = 0; j < i; ++j) HS(i, j) = HS(j, i);
#undef HS
}

/* Bounds of hpi_kin_contact_inside: stop at the first bladder outside them. */
typedef struct contact_stop {
    const double *lo, *hi;
    double scale;
    int inside;
} contact_stop;

/* 1 (and stop->inside = 0) when distance f of bladder k, times stop->scale, is outside
 * [lo[k], hi[k]] or not a number. */
static int outside(contact_stop *stop, int k, double f)
{
    double v = f * stop->scale;
    if (v >= stop->lo[k] && v <= stop->hi[k]) return 0;
    stop->inside = 0;
    return 1;
}

/* The bladder the linear level predicts furthest outside stop's bounds at xi: the largest
 * max(lo[k] − v, v − hi[k]) with v = ρ_lin,k · scale (the scaling of outside()), the lowest
 * index on a tie; 0 when none is a number above −∞. A target beyond reach usually has one
 * bladder far outside, which the linear level already sees: evaluating it first stops the
 * direct chain after one exact distance instead of several. Six multiply-adds a bladder
 * (the rows are hp_geom's, derived once); the order changes what is evaluated, never the
 * verdict. */
static int predicted_worst(const hp_geom *G, int n, const double xi[6], const contact_stop *stop)
{
    int worst = 0;
    double most = -INFINITY;
    for (int k = 0; k < n; ++k) {
        double v = hpi_geom_linear(G, k, xi) * stop->scale;
        double below = stop->lo[k] - v, above = v - stop->hi[k];
        double over = below > above ? below : above;
        if (over > most) {
            most = over;
            worst = k;
        }
    }
    return worst;
}

static void fill_nan(int n, double *rho, double *J, double *H)
{
    for (int k = 0; k < n; ++k) {
        if (rho) rho[k] = NAN;
        if (J)
            for (int i = 0; i < 6; ++i) J[k * 6 + i] = NAN;
        if (H)
            for (int i = 0; i < 36; ++i) H[k * 36 + i] = NAN;
    }
}

hp_error hpi_contact_eval_g(const hp_layout *L, const hp_geom *G, hp_level level,
                            const double xi[6], double *rho, double *J, double *H)
{
    return hpi_kin_contact_eval_warm(L, G, level, xi, NULL, rho, J, H);
}

hp_error hpi_kin_contact_eval_warm(const hp_layout *L, const hp_geom *G, hp_level level,
                                   const double xi[6], hp_kin_dist_warm *warm, double *rho,
                                   double *J, double *H)
{
    return hpi_kin_contact_eval_mask(L, G, level, xi, warm, NULL, rho, J, H);
}

/* The checks every evaluation starts with: L, G, xi not NULL (HP_ERR_NULL), a concrete
 * level, a finite pose (else HP_ERR_INVALID with the outputs given filled with NaN). */
static hp_error eval_args(const hp_layout *L, const hp_geom *G, hp_level level, const double xi[6],
                          double *rho, double *J, double *H)
{
    if (!L || !G || !xi) return HP_ERR_NULL;
    if (!hp_level_is_geometry(level)) return HP_ERR_INVALID;
    for (int i = 0; i < 6; ++i)
        if (!isfinite(xi[i])) {
            fill_nan(L->n, rho, J, H);
            return HP_ERR_INVALID;
        }
    return HP_OK;
}

/* Distance f of bladder k at pose xi (plane or surface level) and its gradient g in c',
 * with the back transform bm it was computed from (derivs: also ∂c'/∂θ). hf (surface
 * level, may be NULL): ∇²f; w: the distance's warm state (may be NULL). The distance
 * error of hpi_kin_head_distance_k, nothing written elsewhere. */
static inline hp_error bladder_distance(const hp_layout *L, const hp_geom *G, hp_level level,
                                        const double xi[6], const rotd *rd, int derivs, int k,
                                        hp_kin_dist_warm *w, backmap *bm, double *f, double g[3],
                                        double *hf)
{
    back_transform(L, G->arm[k], xi, rd, derivs, bm);
    if (level == HP_LEVEL_SURFACE)
        return hpi_kin_head_distance_k(&G->head, &G->headk, bm->cp, w, f, g, hf, NULL);
    const double *n = G->normal[k], *p = G->contact[k];
    *f = n[0] * (bm->cp[0] - p[0]) + n[1] * (bm->cp[1] - p[1]) + n[2] * (bm->cp[2] - p[2]);
    memcpy(g, n, 3 * sizeof *g);
    return HP_OK;
}

/* Bladder k's row of the Jacobian from its distance's gradient g (in c') and the back
 * transform bm (computed with derivs): the translation columns −R·g (∂c'/∂t = −Rᵀ), the
 * rotation columns gᵀ∂c'/∂θ. Rg = R·g is returned for the Hessian's contractions. */
static inline void jacobian_row(const rotd *rd, const backmap *bm, const double g[3], double Rg[3],
                                double *Jk)
{
    const double *R = rd->R;
    Rg[0] = g[0] * R[0] + g[1] * R[1] + g[2] * R[2];
    Rg[1] = g[0] * R[3] + g[1] * R[4] + g[2] * R[5];
    Rg[2] = g[0] * R[6] + g[1] * R[7] + g[2] * R[8];
    if (Jk)
        for (int i = 0; i < 3; ++i) {
            Jk[i] = -Rg[i];
            Jk[3 + i] = g[0] * bm->Cr[0][i] + g[1] * bm->Cr[1][i] + g[2] * bm->Cr[2][i];
        }
}

/* Bladder k's Jacobian row (J may be NULL) and Hessian (H may be NULL: not wanted) from its
 * distance's gradient g and, at the surface level, the distance's own Hessian hf (NULL at
 * the plane level). */
static inline void derivative_rows(const rotd *rd, const backmap *bm, const double g[3],
                                   const double *hf, int k, double *J, double *H)
{
    if (!J && !H) return;
    /* R·g: the translation columns of J negated, and three of the Hessian's contractions. */
    double Rg[3];
    jacobian_row(rd, bm, g, Rg, J ? J + 6 * k : NULL);
    if (H) contact_hessian(rd, bm, g, Rg, hf, H + k * 36);
}

/* The direct chain's evaluation (hpi_kin_contact_inside): distances only, stopping at the
 * first bladder outside stop's bounds (stop->inside = 0). At the linear level in index
 * order (the evaluation is the prediction); at the plane level too (a plane distance costs
 * about what the prediction would); at the surface level the bladder the linear level
 * predicts furthest outside (predicted_worst) first, then the others in index order. A
 * function of its own, so that the full evaluation pays nothing for the order. */
static hp_error inside_eval(const hp_layout *L, const hp_geom *G, hp_level level,
                            const double xi[6], double *rho, double *J, contact_stop *stop)
{
    hp_error e = eval_args(L, G, level, xi, rho, J, NULL);
    if (e) return e;
    if (level == HP_LEVEL_LINEAR) {
        for (int k = 0; k < L->n; ++k) {
            rho[k] = hpi_geom_linear(G, k, xi);
            if (J) memcpy(J + 6 * k, G->row[k], sizeof G->row[k]);
            if (outside(stop, k, rho[k])) break;
        }
        return HP_OK;
    }
    rotd rd;
    int derivs = J != NULL;
    hpi_kin_rotation_roll(xi + 3, rd.R, derivs ? rd.Dr : NULL, NULL);
    /* j = −1: the predicted bladder (surface level); j = 0..n−1: the others, index order. */
    int first = level == HP_LEVEL_SURFACE ? predicted_worst(G, L->n, xi, stop) : -1;
    for (int j = first < 0 ? 0 : -1; j < L->n; ++j) {
        int k = j < 0 ? first : j;
        if (j >= 0 && k == first) continue; /* evaluated first */
        backmap bm;
        double g[3], Rg[3];
        e = bladder_distance(L, G, level, xi, &rd, derivs, k, NULL, &bm, &rho[k], g, NULL);
        if (e) {
            fill_nan(L->n, rho, J, NULL);
            return e;
        }
        if (J) jacobian_row(&rd, &bm, g, Rg, J + 6 * k);
        if (outside(stop, k, rho[k])) break;
    }
    return HP_OK;
}

static hp_error contact_eval(const hp_layout *L, const hp_geom *G, hp_level level,
                             const double xi[6], hp_kin_dist_warm *warm, const unsigned char *hmask,
                             double *rho, double *J, double *H);

hp_error hpi_kin_contact_eval_mask(const hp_layout *L, const hp_geom *G, hp_level level,
                                   const double xi[6], hp_kin_dist_warm *warm,
                                   const unsigned char *hmask, double *rho, double *J, double *H)
{
    return contact_eval(L, G, level, xi, warm, hmask, rho, J, H);
}

hp_error hpi_kin_contact_inside(const hp_layout *L, const hp_geom *G, hp_level level,
                                const double xi[6], double scale, const double *lo,
                                const double *hi, double *rho, double *J, int *inside)
{
    if (!lo || !hi || !rho || !inside) return HP_ERR_NULL;
    contact_stop stop = {lo, hi, scale, 1};
    *inside = 0;
    hp_error e = inside_eval(L, G, level, xi, rho, J, &stop);
    if (e == HP_OK) *inside = stop.inside;
    return e;
}

/* The evaluation itself. */
static hp_error contact_eval(const hp_layout *L, const hp_geom *G, hp_level level,
                             const double xi[6], hp_kin_dist_warm *warm, const unsigned char *hmask,
                             double *rho, double *J, double *H)
{
    hp_error e = eval_args(L, G, level, xi, rho, J, H);
    if (e) return e;
    if (level == HP_LEVEL_LINEAR) {
        for (int k = 0; k < L->n; ++k) {
            if (rho) rho[k] = hpi_geom_linear(G, k, xi);
            if (J) memcpy(J + 6 * k, G->row[k], sizeof G->row[k]);
            if (H)
                for (int i = 0; i < 36; ++i) H[k * 36 + i] = 0.0;
        }
        return HP_OK;
    }
    /* The second derivatives of the rotation only when some bladder's Hessian is wanted. */
    int any_h = 0;
    if (H)
        for (int k = 0; k < L->n; ++k) any_h |= !hmask || hmask[k];
    rotd rd;
    /* Distances alone (the end of a solve, a line search's trial, the direct chain) need
     * neither the rotation's derivatives nor ∂c'/∂θ. */
    int derivs = J || H;
    hpi_kin_rotation_roll(xi + 3, rd.R, derivs ? rd.Dr : NULL, any_h ? rd.Drr : NULL);
    /* At the surface level, in passes: every bladder's back transform, then the distances
     * with their root finds side by side (hpi_kin_head_distances: a step of each bladder's
     * chain of divisions and square roots in turn, so the processor overlaps the chains),
     * then the derivative rows. The same bits as one bladder after another; binding
     * surface plans ~3 % faster for the passes, ~2 % more for the root finds side by
     * side. A plane distance is a dot product with nothing to overlap: one pass. */
    if (level == HP_LEVEL_SURFACE) {
        backmap bm[HP_MAX_BLADDERS];
        double g[HP_MAX_BLADDERS][3], hf[HP_MAX_BLADDERS][9];
        double cp[HP_MAX_BLADDERS][3], f[HP_MAX_BLADDERS];
        unsigned char want[HP_MAX_BLADDERS];
        int bad;
        for (int k = 0; k < L->n; ++k) {
            back_transform(L, G->arm[k], xi, &rd, derivs, &bm[k]);
            memcpy(cp[k], bm[k].cp, sizeof cp[k]);
            want[k] = H && (!hmask || hmask[k]);
        }
        e = hpi_kin_head_distances(&G->head, &G->headk, L->n, (const double(*)[3])cp, warm, f, g,
                                   H ? hf : NULL, want, &bad);
        if (e) {
            fill_nan(L->n, rho, J, H);
            return e;
        }
        if (rho) memcpy(rho, f, sizeof(double) * (size_t)L->n);
        if (J || H)
            for (int k = 0; k < L->n; ++k)
                derivative_rows(&rd, &bm[k], g[k], hf[k], k, J, want[k] ? H : NULL);
        return HP_OK;
    }
    for (int k = 0; k < L->n; ++k) { /* the plane level: no Hessian of its own */
        backmap bm;
        double f, g[3];
        e = bladder_distance(L, G, level, xi, &rd, derivs, k, NULL, &bm, &f, g, NULL);
        if (e) {
            fill_nan(L->n, rho, J, H);
            return e;
        }
        if (rho) rho[k] = f;
        derivative_rows(&rd, &bm, g, NULL, k, J, H && (!hmask || hmask[k]) ? H : NULL);
    }
    return HP_OK;
}

hp_error hp_contact_eval(const hp_layout *L, hp_level level, const double xi[6], double *rho,
                         double *J, double *H)
{
    if (!L || !xi) return HP_ERR_NULL;
    hp_geom G;
    if (hpi_geom_derive(L, &G, NULL) != HP_OK) {
        if (L->n >= 1 && L->n <= HP_MAX_BLADDERS) fill_nan(L->n, rho, J, H);
        return HP_ERR_INVALID;
    }
    return hpi_contact_eval_g(L, &G, level, xi, rho, J, H);
}
