/* Forward statics of the load model: where the head rests under given pressures, and how
 * firmly it is held there (stiffness, stability, compliance, sag). */
#include "headplan/hp_load.h"
#include "common/units.h"
#include "load_internal.h"
#include "kin_internal.h"
#include "linalg.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define REST_MAX_ITERS 100
#define REST_STEP_CAP 5.0   /* mm or degrees per Newton step */
#define REST_STEP_TOL 1e-12 /* mm or degrees: below this the rest is found */
#define REST_BOX_MM 100.0   /* a rest further than this is no rest of a held head */
#define REST_BOX_DEG 60.0

double hpi_load_unit(int i) { return i < 3 ? 1e-3 : HP_RAD_PER_DEG; }

int hpi_load_cholesky(int n, double *A)
{
    for (int j = 0; j < n; ++j) {
        double d = A[j * n + j];
        for (int k = 0; k < j; ++k) d -= A[j * n + k] * A[j * n + k];
        if (!(d > 0) || !isfinite(d)) return -1;
        d = sqrt(d);
        A[j * n + j] = d;
        for (int i = j + 1; i < n; ++i) {
            double s = A[i * n + j];
            for (int k = 0; k < j; ++k) s -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = s / d;
        }
    }
    return 0;
}

void hpi_load_cholesky_solve(int n, const double *Lf, double *b)
{
    for (int i = 0; i < n; ++i) {
        double s = b[i];
        for (int k = 0; k < i; ++k) s -= Lf[i * n + k] * b[k];
        b[i] = s / Lf[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
        double s = b[i];
        for (int k = i + 1; k < n; ++k) s -= Lf[k * n + i] * b[k];
        b[i] = s / Lf[i * n + i];
    }
}

/* K in mm/degree units (energy per unit²), symmetrised. */
static void scaled_stiffness(const double *K, double *Ks)
{
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            Ks[i * 6 + j] = 0.5 * (K[i * 6 + j] + K[j * 6 + i]) * hpi_load_unit(i) *
                            hpi_load_unit(j);
}

static const char *const AXIS_WORDS[6] = {
    "lateral (x)", "longitudinal (y)", "vertical (z)", "pitch", "roll", "yaw"};

static void describe(const double v[6], char *out, size_t len)
{
    int d = 0;
    for (int i = 1; i < 6; ++i)
        if (fabs(v[i]) > fabs(v[d])) d = i;
    int n = snprintf(out, len, "%s", AXIS_WORDS[d]);
    const char *sep = " with some ";
    for (int i = 0; i < 6 && n > 0 && (size_t)n < len; ++i) {
        if (i == d || fabs(v[i]) < 0.3) continue;
        n += snprintf(out + n, len - (size_t)n, "%s%s", sep, AXIS_WORDS[i]);
        sep = " and ";
    }
}

static void holding_from_K(const hp_load_model *M, const double *K, hp_load_holding *h)
{
    memcpy(h->K, K, sizeof h->K);
    double Ks[36], F[36];
    scaled_stiffness(K, Ks);
    memcpy(F, Ks, sizeof F);
    h->stable = hpi_load_cholesky(6, F) == 0;
    for (int i = 0; i < 6; ++i) {
        if (h->stable) {
            double e[6] = {0};
            e[i] = 1.0;
            hpi_load_cholesky_solve(6, F, e);           /* column i of Ks⁻¹ */
            h->compliance[i] = e[i] * hpi_load_unit(i); /* (K⁻¹)_ii / unit: mm/N, deg/(N·m) */
        } else {
            h->compliance[i] = INFINITY;
        }
    }
    /* Along a unit direction of Ks with eigenvalue lam a generalized force F (N or N·m)
     * moves the head by F·unit/lam units: the compliance is unit/lam. */
    double sv[6], V[36];
    if (hpi_kin_svd6(6, Ks, sv, V) == 0) {
        for (int i = 0; i < 6; ++i) h->weakest[i] = V[i * 6 + 5];
        int d = 0;
        for (int i = 1; i < 6; ++i)
            if (fabs(h->weakest[i]) > fabs(h->weakest[d])) d = i;
        if (h->weakest[d] < 0)
            for (int i = 0; i < 6; ++i) h->weakest[i] = -h->weakest[i];
        h->weakest_is_rotation = d >= 3;
        h->weakest_compliance = h->stable && sv[5] > 0 ? hpi_load_unit(d) / sv[5] : INFINITY;
        describe(h->weakest, h->weakest_words, sizeof h->weakest_words);
    } else {
        for (int i = 0; i < 6; ++i) h->weakest[i] = NAN;
        h->weakest_compliance = INFINITY;
        snprintf(h->weakest_words, sizeof h->weakest_words, "unknown");
    }
    double g = 0.0, kg = 0.0;
    for (int a = 0; a < 3; ++a) g += M->spec.gravity[a] * M->spec.gravity[a];
    g = sqrt(g);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            kg += M->spec.gravity[a] / g * 0.5 * (K[a * 6 + b] + K[b * 6 + a]) *
                  M->spec.gravity[b] / g;
    h->k_gravity = kg;
    h->sag = kg > 0 ? M->spec.mass * g / kg : INFINITY;
}

hp_error hp_load_holding_at(const hp_load_model *M, const double xi[6], const double *P,
                            hp_load_holding *out)
{
    if (!out) return HP_ERR_NULL;
    double Q[6], dQ[36];
    hp_error err = hp_load_eval(M, xi, P, Q, dQ, NULL, NULL, NULL);
    if (err) return err;
    for (int i = 0; i < 36; ++i) dQ[i] = -dQ[i];
    holding_from_K(M, dQ, out);
    return HP_OK;
}

/* Newton step in scaled units: (Ks + tau·I) ds = Qs, with the smallest Levenberg shift
 * tau that makes the matrix positive definite. */
static void newton_step(const double *K, const double Q[6], double ds[6])
{
    double Ks[36], F[36], Qs[6], dmax = 0.0;
    scaled_stiffness(K, Ks);
    for (int i = 0; i < 6; ++i) {
        Qs[i] = Q[i] * hpi_load_unit(i);
        dmax = fmax(dmax, fabs(Ks[i * 6 + i]));
    }
    double tau = 0.0;
    for (int attempt = 0; attempt < 40; ++attempt) {
        memcpy(F, Ks, sizeof F);
        for (int i = 0; i < 6; ++i) F[i * 6 + i] += tau;
        if (hpi_load_cholesky(6, F) == 0) break;
        tau = tau == 0.0 ? fmax(1e-6 * dmax, 1e-9) : 10.0 * tau;
    }
    memcpy(ds, Qs, sizeof Qs);
    hpi_load_cholesky_solve(6, F, ds);
    double big = 0.0;
    for (int i = 0; i < 6; ++i) big = fmax(big, fabs(ds[i]));
    if (!(big <= REST_STEP_CAP))
        for (int i = 0; i < 6; ++i) ds[i] *= REST_STEP_CAP / big;
    if (!isfinite(big))
        for (int i = 0; i < 6; ++i) ds[i] = 0.0;
}

hp_error hp_load_rest(const hp_load_model *M, const double *P, const double *xi0, double xi[6],
                      hp_load_rest_info *info)
{
    if (!M || !P || !xi) return HP_ERR_NULL;
    double x[6] = {0};
    if (xi0) memcpy(x, xi0, sizeof x);
    for (int i = 0; i < 6; ++i)
        if (!isfinite(x[i])) return HP_ERR_INVALID;
    for (int k = 0; k < M->layout.n; ++k)
        if (!isfinite(P[k])) return HP_ERR_INVALID;
    double ro[HP_MAX_BLADDERS];
    hp_error err = hpi_load_radii(M, P, ro, NULL);
    if (err) return err;
    double Q[6], dQ[36], K[36], E;
    if ((err = hpi_load_eval_radii(M, x, P, ro, NULL, 0, Q, dQ, NULL, NULL, &E))) return err;
    int it = 0, done = 0;
    while (!done) {
        if (it >= REST_MAX_ITERS) return HP_ERR_NO_CONVERGENCE;
        ++it;
        for (int i = 0; i < 36; ++i) K[i] = -dQ[i];
        double ds[6], slope = 0.0, big = 0.0;
        newton_step(K, Q, ds);
        for (int i = 0; i < 6; ++i) {
            slope -= Q[i] * hpi_load_unit(i) * ds[i]; /* dPi along ds, <= 0 */
            big = fmax(big, fabs(ds[i]));
        }
        if (big <= REST_STEP_TOL) break;
        /* Near the rest (small steps) Newton is quadratic and Pi's changes drown in rounding:
         * take the full step. Further out, Armijo backtracking on Pi. */
        int full = big < 1e-4;
        double t = 1.0, xn[6], Qn[6], dQn[36], En = 0.0;
        for (int tries = 0;; ++tries) {
            /* Every length down to 2^-50 of the step leaving the domain: x lies on its edge
             * (a bladder centre on the head surface) and the descent goes through the
             * panel. That is no rest of the model, whereas no decrease at any length inside
             * the domain is rounding level: x is the rest. */
            if (tries > 50 && err == HP_ERR_DOMAIN) return HP_ERR_NO_CONVERGENCE;
            if (tries > 50) {
                done = 1;
                break;
            }
            for (int i = 0; i < 6; ++i) xn[i] = x[i] + t * ds[i] * hpi_load_unit(i);
            err = hpi_load_eval_radii(M, xn, P, ro, NULL, 0, Qn, dQn, NULL, NULL, &En);
            if (err == HP_OK && (full || En <= E + 1e-4 * t * slope)) break;
            if (err != HP_OK && err != HP_ERR_DOMAIN) return err;
            t *= 0.5;
        }
        if (done) break;
        memcpy(x, xn, sizeof x);
        memcpy(Q, Qn, sizeof Q);
        memcpy(dQ, dQn, sizeof dQ);
        E = En;
        for (int i = 0; i < 6; ++i)
            if (!(fabs(x[i]) / hpi_load_unit(i) <= (i < 3 ? REST_BOX_MM : REST_BOX_DEG)))
                return HP_ERR_NO_CONVERGENCE; /* falls: nothing holds it */
        if (full && big * t <= REST_STEP_TOL) break;
    }
    /* A descent that stopped without a decrease at any step length inside the domain
     * (pressed against a panel's edge, where every longer step leaves it) is no rest unless
     * the generalized force vanishes there: 1e-6 N (moment rows per 1°/1 mm) is far above
     * a converged rest's rounding (1e-9 N) and far below any force that moves the head. */
    for (int i = 0; i < 6; ++i)
        if (!(fabs(Q[i]) * (i < 3 ? 1.0 : hpi_load_unit(i) / 1e-3) <= 1e-6))
            return HP_ERR_NO_CONVERGENCE;
    memcpy(xi, x, sizeof x);
    if (info) {
        memset(info, 0, sizeof *info);
        info->iterations = it;
        for (int i = 0; i < 36; ++i) K[i] = -dQ[i];
        holding_from_K(M, K, &info->holding);
        for (int i = 0; i < 6; ++i) info->q_norm = fmax(info->q_norm, fabs(Q[i]));
        double f[3], m[3];
        if ((err = hp_load_newton_euler(M, x, P, f, m))) return err;
        info->residual_force = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
        info->residual_moment = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        /* Where the head rests is only as good as the contact law there: flag a rest that
         * indents a carrying bladder beyond the range the law was checked on. */
        double ratio[HP_MAX_BLADDERS];
        if ((err = hp_load_indentation(M, x, P, ratio))) return err;
        for (int k = 0; k < M->layout.n; ++k) info->indent_max = fmax(info->indent_max, ratio[k]);
        info->beyond_indent = info->indent_max > HP_LOAD_INDENT_MAX;
    }
    return HP_OK;
}
