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

/* c' and its first derivatives at pose xi for centre c; u = c − pivot − t. ∂c'/∂t = −Rᵀ
 * needs no storage; Cr = ∂c'/∂θ (3×3). */
typedef struct backmap {
    double cp[3], u[3];
    double Cr[3][3];
} backmap;

typedef struct rotd {
    double R[9], dR[3][9], d2R[3][3][9];
} rotd;

/* The columns of Cr use the structure of the rotation derivatives (hp_kin_rotation_derivs):
 * ∂R/∂pitch = R·[e_x]× has the columns 0, R₂, −R₁, so its column of Cr is (0, w₂, −w₁)
 * with w = Rᵀu; ∂R/∂yaw = [e_z]×·R has the rows −R₁, R₀, 0, so its column is
 * R₀ᵀ·u₁ − R₁ᵀ·u₀ entrywise. Each is the sum the full 3-term product forms, less its exact
 * zero terms and with an exact negation moved out: the same bits (up to the sign of a zero)
 * for 15 products instead of 27. */
static void back_transform(const hp_layout *L, const double c[3], const double xi[6],
                           const rotd *rd, backmap *bm)
{
    const double *R = rd->R, *D = rd->dR[1];
    double *u = bm->u, w[3];
    for (int i = 0; i < 3; ++i) u[i] = c[i] - L->pivot[i] - xi[i];
    for (int m = 0; m < 3; ++m) {
        w[m] = R[m] * u[0] + R[3 + m] * u[1] + R[6 + m] * u[2];
        bm->cp[m] = w[m] + L->pivot[m];
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
 * formed. hf NULL: f is linear in c' (the plane level), only the second term. */
static void contact_hessian(const rotd *rd, const backmap *bm, const double g[3],
                            const double hf[9], double *H)
{
    const double *u = bm->u;
    double Hs[6][6] = {{0}};
    if (hf) {
        double C[3][6], hC[3][6]; /* C = ∂c'/∂ξ, hC = ∇²f · C */
        for (int m = 0; m < 3; ++m)
            for (int i = 0; i < 3; ++i) {
                C[m][i] = -rd->R[i * 3 + m];
                C[m][3 + i] = bm->Cr[m][i];
            }
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < 6; ++i)
                hC[a][i] = hf[a * 3] * C[0][i] + hf[a * 3 + 1] * C[1][i] + hf[a * 3 + 2] * C[2][i];
        for (int i = 0; i < 6; ++i)
            for (int j = i; j < 6; ++j)
                Hs[i][j] = C[0][i] * hC[0][j] + C[1][i] * hC[1][j] + C[2][i] * hC[2][j];
    }
    for (int b = 0; b < 3; ++b) {
        const double *D = rd->dR[b];
        for (int a = 0; a < 3; ++a)
            Hs[a][3 + b] -= D[a * 3] * g[0] + D[a * 3 + 1] * g[1] + D[a * 3 + 2] * g[2];
        for (int a = 0; a <= b; ++a) {
            const double *Q = rd->d2R[a][b];
            double qg[3];
            for (int l = 0; l < 3; ++l) qg[l] = Q[l * 3] * g[0] + Q[l * 3 + 1] * g[1] + Q[l * 3 + 2] * g[2];
            Hs[3 + a][3 + b] += u[0] * qg[0] + u[1] * qg[1] + u[2] * qg[2];
        }
    }
    for (int i = 0; i < 6; ++i)
        for (int j = i; j < 6; ++j) {
            H[i * 6 + j] = Hs[i][j];
            H[j * 6 + i] = Hs[i][j];
        }
}

static void linear_row(const hp_layout *L, const hp_geom *G, int k, double row[6])
{
    const double *n = G->normal[k];
    double lv[3];
    for (int i = 0; i < 3; ++i) lv[i] = G->contact[k][i] - L->pivot[i];
    row[0] = -n[0];
    row[1] = -n[1];
    row[2] = -n[2];
    row[3] = -(lv[1] * n[2] - lv[2] * n[1]);
    row[4] = -(lv[2] * n[0] - lv[0] * n[2]);
    row[5] = -(lv[0] * n[1] - lv[1] * n[0]);
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

hp_error hp_contact_eval_g(const hp_layout *L, const hp_geom *G, hp_level level,
                           const double xi[6], double *rho, double *J, double *H)
{
    return hp_kin_contact_eval_warm(L, G, level, xi, NULL, rho, J, H);
}

hp_error hp_kin_contact_eval_warm(const hp_layout *L, const hp_geom *G, hp_level level,
                                  const double xi[6], double *s_warm, double *rho, double *J,
                                  double *H)
{
    return hp_kin_contact_eval_mask(L, G, level, xi, s_warm, NULL, rho, J, H);
}

hp_error hp_kin_contact_eval_mask(const hp_layout *L, const hp_geom *G, hp_level level,
                                  const double xi[6], double *s_warm, const unsigned char *hmask,
                                  double *rho, double *J, double *H)
{
    if (!L || !G || !xi) return HP_ERR_NULL;
    if (level != HP_LEVEL_LINEAR && level != HP_LEVEL_PLANE && level != HP_LEVEL_SURFACE)
        return HP_ERR_INVALID;
    for (int i = 0; i < 6; ++i)
        if (!isfinite(xi[i])) {
            fill_nan(L->n, rho, J, H);
            return HP_ERR_INVALID;
        }
    if (level == HP_LEVEL_LINEAR) {
        for (int k = 0; k < L->n; ++k) {
            double row[6], v = G->rho0[k];
            linear_row(L, G, k, row);
            for (int i = 0; i < 6; ++i) v += row[i] * xi[i];
            if (rho) rho[k] = v;
            if (J) memcpy(J + 6 * k, row, sizeof row);
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
    hp_kin_rotation_derivs(xi + 3, rd.R, rd.dR, any_h ? rd.d2R : NULL);
    for (int k = 0; k < L->n; ++k) {
        int want_h = H && (!hmask || hmask[k]);
        if (H && !want_h)
            for (int i = 0; i < 36; ++i) H[k * 36 + i] = 0.0;
        backmap bm;
        back_transform(L, L->bladders[k].center, xi, &rd, &bm);
        double f, g[3], hf[9];
        if (level == HP_LEVEL_SURFACE) {
            hp_error err = hp_kin_head_distance_k(&G->head, &G->headk, bm.cp, s_warm ? &s_warm[k] : NULL,
                                                     &f, g, want_h ? hf : NULL, NULL);
            if (err) {
                fill_nan(L->n, rho, J, H);
                return err;
            }
        } else {
            const double *n = G->normal[k], *p = G->contact[k];
            f = n[0] * (bm.cp[0] - p[0]) + n[1] * (bm.cp[1] - p[1]) + n[2] * (bm.cp[2] - p[2]);
            memcpy(g, n, sizeof g);
        }
        if (rho) rho[k] = f;
        if (J) {
            const double *R = rd.R;
            for (int i = 0; i < 3; ++i) {
                J[k * 6 + i] = g[0] * -R[i * 3] + g[1] * -R[i * 3 + 1] + g[2] * -R[i * 3 + 2];
                J[k * 6 + 3 + i] = g[0] * bm.Cr[0][i] + g[1] * bm.Cr[1][i] + g[2] * bm.Cr[2][i];
            }
        }
        if (want_h)
            contact_hessian(&rd, &bm, g, level == HP_LEVEL_SURFACE ? hf : NULL, H + k * 36);
    }
    return HP_OK;
}

hp_error hp_contact_eval(const hp_layout *L, hp_level level, const double xi[6],
                         double *rho, double *J, double *H)
{
    if (!L || !xi) return HP_ERR_NULL;
    hp_geom G;
    if (hp_geom_derive(L, &G, NULL) != HP_OK) {
        if (L->n >= 1 && L->n <= HP_MAX_BLADDERS) fill_nan(L->n, rho, J, H);
        return HP_ERR_INVALID;
    }
    return hp_contact_eval_g(L, &G, level, xi, rho, J, H);
}
