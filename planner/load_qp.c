/* The load planner's separable QP by its 6-dimensional dual (see load_qp.h). */
#include "planner/load_qp.h"
#include "kinematics/load_internal.h"

#include <math.h>
#include <string.h>

/* d(λ), the dual function θ(λ) and its gradient phi = c + M d. */
static double dual(int nv, const double *M, const double c[6], const double *h,
                   const double *g, const double *l, const double *u, const double lam[6],
                   double *d, double phi[6])
{
    double theta = 0.0;
    for (int r = 0; r < 6; ++r) phi[r] = c[r];
    for (int i = 0; i < nv; ++i) {
        double a = 0.0;
        for (int r = 0; r < 6; ++r) a += M[r * nv + i] * lam[r];
        double v = g[i] - a / h[i];
        v = v < l[i] ? l[i] : (v > u[i] ? u[i] : v);
        d[i] = v;
        theta += 0.5 * h[i] * (v - g[i]) * (v - g[i]) + a * v;
        for (int r = 0; r < 6; ++r) phi[r] += M[r * nv + i] * v;
    }
    for (int r = 0; r < 6; ++r) theta += lam[r] * c[r];
    return theta;
}

hp_load_qp_status hp_load_qp_solve(int nv, const double *M, const double c[6],
                                   const double *h, const double *g, const double *l,
                                   const double *u, double tol, int max_iter,
                                   double lambda[6], double *d, int *iterations)
{
    double phi[6], theta = dual(nv, M, c, h, g, l, u, lambda, d, phi);
    /* The dual grows without bound exactly when the box misses the equations; a multiplier
     * this large (relative to the problem's own scale) is that divergence. */
    double scale = 1.0;
    for (int i = 0; i < nv; ++i) scale = fmax(scale, fabs(h[i] * g[i]));
    for (int it = 0; it < max_iter; ++it) {
        if (iterations) *iterations = it;
        double err = 0.0;
        for (int r = 0; r < 6; ++r) err = fmax(err, fabs(phi[r]));
        if (err <= tol) return HP_LOAD_QP_OPTIMAL;
        double S[36] = {0}, smax = 0.0;
        for (int i = 0; i < nv; ++i) {
            double a = 0.0;
            for (int r = 0; r < 6; ++r) a += M[r * nv + i] * lambda[r];
            double v = g[i] - a / h[i];
            if (!(v > l[i] && v < u[i])) continue; /* at a bound: no curvature */
            for (int r = 0; r < 6; ++r)
                for (int q = 0; q < 6; ++q) S[r * 6 + q] += M[r * nv + i] * M[q * nv + i] / h[i];
        }
        for (int r = 0; r < 6; ++r) smax = fmax(smax, S[r * 6 + r]);
        double F[36], step[6], reg = 1e-12 * (smax > 0 ? smax : 1.0);
        for (int attempt = 0;; ++attempt) {
            memcpy(F, S, sizeof F);
            for (int r = 0; r < 6; ++r) F[r * 6 + r] += reg;
            if (hp_load_cholesky(6, F) == 0) break;
            if (attempt > 30) return HP_LOAD_QP_ITERATION_LIMIT;
            reg *= 100.0;
        }
        memcpy(step, phi, sizeof step);
        hp_load_cholesky_solve(6, F, step);
        double slope = 0.0;
        for (int r = 0; r < 6; ++r) slope += phi[r] * step[r];
        double t = 1.0, lam[6], dn[HP_LOAD_QP_NMAX], phin[6], thn = theta;
        int ok = 0;
        for (int ls = 0; ls < 60; ++ls, t *= 0.5) {
            for (int r = 0; r < 6; ++r) lam[r] = lambda[r] + t * step[r];
            thn = dual(nv, M, c, h, g, l, u, lam, dn, phin);
            if (thn >= theta + 1e-4 * t * slope) {
                ok = 1;
                break;
            }
        }
        if (!ok) return HP_LOAD_QP_ITERATION_LIMIT;
        memcpy(lambda, lam, sizeof lam);
        memcpy(d, dn, (size_t)nv * sizeof *d);
        memcpy(phi, phin, sizeof phi);
        theta = thn;
        double lmax = 0.0;
        for (int r = 0; r < 6; ++r) lmax = fmax(lmax, fabs(lambda[r]));
        if (lmax > 1e12 * scale) return HP_LOAD_QP_INFEASIBLE;
    }
    if (iterations) *iterations = max_iter;
    return HP_LOAD_QP_ITERATION_LIMIT;
}

int hp_load_box_qp(int nv, const double *H, const double *g, const double *l,
                   const double *u, int max_iter, double *d)
{
    int state[HP_MAX_BLADDERS]; /* 0 free, -1 at lower, +1 at upper */
    for (int i = 0; i < nv; ++i) {
        d[i] = 0.0;
        state[i] = l[i] >= 0.0 ? -1 : (u[i] <= 0.0 ? 1 : 0);
        if (state[i]) d[i] = state[i] < 0 ? l[i] : u[i];
    }
    for (int it = 0; it < max_iter; ++it) {
        /* Minimise over the free variables with the others held at their bounds. */
        int F[HP_MAX_BLADDERS], nf = 0;
        for (int i = 0; i < nv; ++i)
            if (!state[i]) F[nf++] = i;
        double A[HP_MAX_BLADDERS * HP_MAX_BLADDERS], x[HP_MAX_BLADDERS];
        for (int a = 0; a < nf; ++a) {
            double r = -g[F[a]];
            for (int j = 0; j < nv; ++j)
                if (state[j]) r -= H[F[a] * nv + j] * d[j];
            x[a] = r;
            for (int b = 0; b < nf; ++b) A[a * nf + b] = H[F[a] * nv + F[b]];
        }
        if (nf && hp_load_cholesky(nf, A) != 0) return -1;
        if (nf) hp_load_cholesky_solve(nf, A, x);
        /* Move towards the free minimiser until the first bound. */
        double t = 1.0;
        int hit = -1;
        for (int a = 0; a < nf; ++a) {
            int i = F[a];
            double step = x[a] - d[i];
            if (x[a] > u[i] && step > 0 && (u[i] - d[i]) / step < t) {
                t = (u[i] - d[i]) / step;
                hit = i;
            } else if (x[a] < l[i] && step < 0 && (l[i] - d[i]) / step < t) {
                t = (l[i] - d[i]) / step;
                hit = i;
            }
        }
        for (int a = 0; a < nf; ++a) d[F[a]] += t * (x[a] - d[F[a]]);
        if (hit >= 0) {
            state[hit] = x[0] == x[0] && d[hit] >= u[hit] - 1e-300 ? 1 : -1;
            d[hit] = state[hit] > 0 ? u[hit] : l[hit];
            continue;
        }
        /* At the free minimiser: release the bound whose multiplier has the wrong sign. */
        int worst = -1;
        double wv = 0.0;
        for (int i = 0; i < nv; ++i) {
            if (!state[i] || l[i] == u[i]) continue;
            double gr = g[i];
            for (int j = 0; j < nv; ++j) gr += H[i * nv + j] * d[j];
            double v = state[i] < 0 ? -gr : gr; /* > 0: wants to move inside */
            if (v > wv) {
                wv = v;
                worst = i;
            }
        }
        if (worst < 0) return 0;
        state[worst] = 0;
    }
    return -1;
}
