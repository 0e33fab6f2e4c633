/* The minimum-holding-stiffness tie-breaker of HOLD (load_solve.h).
 *
 * At a fixed pose the holding stiffness is a sum of each bladder's own terms:
 *     K(P) = K_grav + sum_k (a_k(P_k)·J_k J_kᵀ − F_k(P_k)·H_k),
 * (the contact branch of −dQ/dxi, docs/load.md), a_k = −dF_k/drho_k the contact law's own
 * normal stiffness (2·pi·rho_k·P_k for the cap law; not linear in P for the fitted law), so
 * dK/dP_k = a_k'·J_k J_kᵀ − F_k'·H_k and d²K/dP_k² = a_k''·J_k J_kᵀ − F_k''·H_k (and no
 * mixed terms), every derivative along P through ro(P). The objective is the
 * smallest eigenvalue of K in mm/degree units (as hp_load_holding reports it), made smooth by
 * the soft minimum −(1/beta)·log sum_i exp(−beta·lambda_i) = −(1/beta)·log tr exp(−beta·K),
 * a spectral function of K with exact first and second derivatives (Daleckii–Krein), which
 * is within log(6)/beta of the true minimum and needs no positive definite start. A small
 * least-squeeze term keeps the answer unique where the soft minimum is flat. No allocation. */
#include "planner/load_solve.h"
#include "common/units.h"
#include "kinematics/linalg.h"
#include "kinematics/load_internal.h"
#include "common/test_count.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

/* Stiffness in mm/degree units and N/mm: K·unit_i·unit_j·1e3 (1 mm weighs as 1°). */
static double kscale(int i, int j) { return hpi_load_unit(i) * hpi_load_unit(j) * 1e3; }

hp_error hpi_load_stiff_init(hp_load_stiff *S, const hp_load_model *M, const double xi[6],
                             const double *target)
{
    const int n = M->layout.n;
    double rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6], H[HP_MAX_BLADDERS * 36];
    double Q[6], dQ[36];
    hp_error err = hpi_contact_eval_g(&M->layout, &M->geom, M->level, xi, rho, J, H);
    if (err) return err;
    hpi_load_gravity(M, xi, Q, dQ, NULL);
    memset(S, 0, sizeof *S);
    S->M = M;
    S->n = n;
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            S->K0[i * 6 + j] = -0.5 * (dQ[i * 6 + j] + dQ[j * 6 + i]) * kscale(i, j);
    for (int k = 0; k < n; ++k) {
        S->rho[k] = rho[k];
        for (int i = 0; i < 6; ++i)
            for (int j = 0; j < 6; ++j) {
                S->JJ[k][i * 6 + j] = J[6 * k + i] * J[6 * k + j] * kscale(i, j);
                S->H[k][i * 6 + j] = 0.5 * (H[k * 36 + i * 6 + j] + H[k * 36 + j * 6 + i]) *
                                     kscale(i, j);
            }
    }
    S->target = target;
    S->beta = HP_LOAD_STIFF_BETA;
    S->squeeze = HP_LOAD_STIFF_SQUEEZE;
    return HP_OK;
}

/* The holding stiffness [N/mm, mm/degree units] when the nv bladders idx[] carry forces F
 * with normal stiffnesses a, the others nothing. */
static void stiff_at(const hp_load_stiff *S, int nv, const int *idx, const double *F,
                     const double *a, double K[36])
{
    memcpy(K, S->K0, 36 * sizeof *K);
    for (int j = 0; j < nv; ++j)
        for (int q = 0; q < 36; ++q) K[q] += a[j] * S->JJ[idx[j]][q] - F[j] * S->H[idx[j]][q];
}

static atomic_ulong n_eigen;

void hpi_test_eigen_counts(unsigned long *eigen) { *eigen = atomic_load(&n_eigen); }

int hpi_load_stiff_lambda_at(const hp_load_stiff *S, int nv, const int *idx, const double *F,
                             const double *a, double *lam)
{
    double K[36], l[6], V[36];
    stiff_at(S, nv, idx, F, a, K);
    hpi_count(&n_eigen, 1);
    if (hpi_kin_symeig6(K, l, V) != 0) return -1;
    *lam = l[0];
    return 0;
}

int hpi_load_stiff_above(const hp_load_stiff *S, int nv, const int *idx, const double *F,
                         const double *a, double margin)
{
    double K[36];
    stiff_at(S, nv, idx, F, a, K);
    for (int i = 0; i < 6; ++i) K[i * 6 + i] -= margin;
    for (int q = 0; q < 36; ++q)
        if (!isfinite(K[q])) return -1;
    return hpi_load_cholesky(6, K) == 0;
}

int hpi_load_stiff_lambda_min(const double K[36], double *lam)
{
    double Ks[36], l[6], V[36];
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            Ks[i * 6 + j] = 0.5 * (K[i * 6 + j] + K[j * 6 + i]) * kscale(i, j);
    hpi_count(&n_eigen, 1);
    if (hpi_kin_symeig6(Ks, l, V) != 0) return -1;
    *lam = l[0];
    return 0;
}

/* g'[a, b]: the divided difference of g'(l) = −beta·exp(−beta·(l − l0)) (with its limit
 * g''(a) when a == b); expm1 keeps nearby eigenvalues exact. */
static double ddiff(double beta, double a, double b, double l0)
{
    double ea = exp(-beta * (a - l0));
    if (a == b) return beta * beta * ea;
    return -beta * exp(-beta * (b - l0)) * expm1(-beta * (a - b)) / (a - b);
}

int hpi_load_stiff_eval(const hp_load_stiff *S, int nv, const int *idx, const double *x, double *f,
                        double *grad, double *hess, double *lam_min)
{
    const double beta = S->beta;
    double K[36], dK[HP_MAX_BLADDERS][36], d2K[HP_MAX_BLADDERS][36];
    memcpy(K, S->K0, sizeof K);
    for (int j = 0; j < nv; ++j) {
        int k = idx[j];
        double F, F1, F2, a[3];
        if (hpi_load_bladder_force(S->M, k, x[j] * 1e3, S->rho[k], &F, &F1, &F2) != HP_OK ||
            hpi_load_bladder_stiff(S->M, k, x[j] * 1e3, S->rho[k], a) != HP_OK)
            return -1;
        F1 *= 1e3; /* per kPa */
        F2 *= 1e6;
        for (int q = 0; q < 36; ++q) {
            K[q] += a[0] * S->JJ[k][q] - F * S->H[k][q];
            dK[j][q] = 1e3 * a[1] * S->JJ[k][q] - F1 * S->H[k][q];
            d2K[j][q] = 1e6 * a[2] * S->JJ[k][q] - F2 * S->H[k][q];
        }
    }
    double lam[6], V[36];
    if (hpi_kin_symeig6(K, lam, V) != 0) return -1;
    /* Shifted by the smallest eigenvalue: no overflow, the same ratios. */
    double e[6], Z = 0.0;
    for (int i = 0; i < 6; ++i) Z += (e[i] = exp(-beta * (lam[i] - lam[0])));
    double obj = -lam[0] + log(Z) / beta;
    if (lam_min) *lam_min = lam[0];
    /* G_j = Vᵀ·dK_j·V, the derivatives in the eigenbasis. */
    double G[HP_MAX_BLADDERS][36], gk[HP_MAX_BLADDERS];
    for (int j = 0; j < nv; ++j) {
        double T[36];
        for (int a = 0; a < 6; ++a)
            for (int c = 0; c < 6; ++c) {
                double s = 0.0;
                for (int b = 0; b < 6; ++b) s += dK[j][a * 6 + b] * V[b * 6 + c];
                T[a * 6 + c] = s;
            }
        for (int a = 0; a < 6; ++a)
            for (int c = 0; c < 6; ++c) {
                double s = 0.0;
                for (int b = 0; b < 6; ++b) s += V[b * 6 + a] * T[b * 6 + c];
                G[j][a * 6 + c] = s;
            }
        /* Z_j / Z with Z_j = sum_i g'(lam_i)·G_ii: d obj = Z_j / (beta·Z). */
        double s = 0.0;
        for (int i = 0; i < 6; ++i) s += e[i] * G[j][i * 6 + i];
        gk[j] = -s / Z;
    }
    for (int j = 0; j < nv; ++j) {
        double d = x[j] - S->target[idx[j]] * 1e-3;
        obj += 0.5 * S->squeeze * d * d;
    }
    if (f) *f = obj;
    if (grad)
        for (int j = 0; j < nv; ++j)
            grad[j] = gk[j] + S->squeeze * (x[j] - S->target[idx[j]] * 1e-3);
    if (hess) {
        /* d² obj = (1/beta)·(Z_jl / Z − Z_j·Z_l / Z²), Z_jl = sum_ab g'[a,b]·G_j,ab·G_l,ab
         * + [j == l]·sum_a g'(lam_a)·(Vᵀ d2K_j V)_aa; Z_j / Z = −beta·gk[j]. */
        for (int j = 0; j < nv; ++j)
            for (int l = 0; l <= j; ++l) {
                double s = 0.0;
                for (int a = 0; a < 6; ++a)
                    for (int b = 0; b < 6; ++b)
                        s += ddiff(beta, lam[a], lam[b], lam[0]) * G[j][a * 6 + b] *
                             G[l][a * 6 + b];
                if (j == l)
                    for (int a = 0; a < 6; ++a) {
                        double v = 0.0;
                        for (int b = 0; b < 6; ++b)
                            for (int c = 0; c < 6; ++c)
                                v += V[b * 6 + a] * d2K[j][b * 6 + c] * V[c * 6 + a];
                        s += -beta * e[a] * v;
                    }
                double h = (s / Z - beta * beta * gk[j] * gk[l]) / beta;
                if (j == l) h += S->squeeze;
                hess[j * nv + l] = hess[l * nv + j] = h;
            }
    }
    return 0;
}
