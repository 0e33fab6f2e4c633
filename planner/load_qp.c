/* The load planner's separable QP by its 6-dimensional dual (see load_qp.h). */
#include "planner/load_qp.h"
#include "kinematics/load_internal.h"

#include <math.h>
#include <string.h>

int hpi_load_box_qp(int nv, const double *H, const double *g, const double *l, const double *u,
                    int max_iter, double *d);

hp_load_qp_status hpi_load_qp_solve(int nv, const double *M, const double c[6], const double *h,
                                    const double *g, const double *l, const double *u, double tol,
                                    int max_iter, double lambda[6], double *d, int *iterations)
{
    /* The method of multipliers: each outer step minimises the augmented Lagrangian
     * ½Σh(d−g)² + λᵀ(Md + c) + ½ρ|Md + c|² over the box (a finite active-set box QP),
     * then λ += ρ(Md + c); ρ grows tenfold whenever the residual fails to shrink fourfold.
     * A residual that persists as ρ grows past 1e12 of its start means no d in the box
     * solves the equations. */
    double hmax = 0.0, mmax = 0.0;
    for (int i = 0; i < nv; ++i) {
        hmax = fmax(hmax, h[i]);
        double s = 0.0;
        for (int r = 0; r < 6; ++r) s += M[r * nv + i] * M[r * nv + i];
        mmax = fmax(mmax, s);
    }
    if (!(mmax > 0)) mmax = 1.0;
    const double rho0 = 1e3 * hmax / mmax;
    double rho = rho0, prev = INFINITY;
    double H[HP_LOAD_QP_NMAX * HP_LOAD_QP_NMAX], q[HP_LOAD_QP_NMAX];
    for (int it = 0; it < max_iter; ++it) {
        if (iterations) *iterations = it + 1;
        for (int i = 0; i < nv; ++i) {
            double v = -h[i] * g[i];
            for (int r = 0; r < 6; ++r) v += M[r * nv + i] * (lambda[r] + rho * c[r]);
            q[i] = v;
            for (int j = 0; j < nv; ++j) {
                double a = i == j ? h[i] : 0.0;
                for (int r = 0; r < 6; ++r) a += rho * M[r * nv + i] * M[r * nv + j];
                H[i * nv + j] = a;
            }
        }
        if (hpi_load_box_qp(nv, H, q, l, u, 4 * nv + 40, d) != 0)
            return rho > 1e6 * rho0 ? HP_LOAD_QP_INFEASIBLE : HP_LOAD_QP_ITERATION_LIMIT;
        double res[6], err = 0.0;
        for (int r = 0; r < 6; ++r) {
            res[r] = c[r];
            for (int i = 0; i < nv; ++i) res[r] += M[r * nv + i] * d[i];
            err = fmax(err, fabs(res[r]));
        }
        for (int r = 0; r < 6; ++r) lambda[r] += rho * res[r];
        if (err <= tol) return HP_LOAD_QP_OPTIMAL;
        if (err > 0.25 * prev) rho *= 10.0;
        if (rho > 1e12 * rho0) return HP_LOAD_QP_INFEASIBLE;
        prev = err;
    }
    return HP_LOAD_QP_ITERATION_LIMIT;
}

int hpi_load_box_qp(int nv, const double *H, const double *g, const double *l, const double *u,
                    int max_iter, double *d)
{
    int state[HP_LOAD_QP_NMAX]; /* 0 free, -1 at lower, +1 at upper */
    for (int i = 0; i < nv; ++i) {
        d[i] = 0.0;
        state[i] = l[i] >= 0.0 ? -1 : (u[i] <= 0.0 ? 1 : 0);
        if (state[i]) d[i] = state[i] < 0 ? l[i] : u[i];
    }
    for (int it = 0; it < max_iter; ++it) {
        /* Minimise over the free variables with the others held at their bounds. */
        int F[HP_LOAD_QP_NMAX], nf = 0;
        for (int i = 0; i < nv; ++i)
            if (!state[i]) F[nf++] = i;
        double A[HP_LOAD_QP_NMAX * HP_LOAD_QP_NMAX], x[HP_LOAD_QP_NMAX];
        for (int a = 0; a < nf; ++a) {
            double r = -g[F[a]];
            for (int j = 0; j < nv; ++j)
                if (state[j]) r -= H[F[a] * nv + j] * d[j];
            x[a] = r;
            for (int b = 0; b < nf; ++b) A[a * nf + b] = H[F[a] * nv + F[b]];
        }
        if (nf && hpi_load_cholesky(nf, A) != 0) return -1;
        if (nf) hpi_load_cholesky_solve(nf, A, x);
        /* Move towards the free minimiser until the first bound. */
        double t = 1.0;
        int hit = -1, hit_side = 0;
        for (int a = 0; a < nf; ++a) {
            int i = F[a];
            double step = x[a] - d[i];
            if (x[a] > u[i] && step > 0 && (u[i] - d[i]) / step < t) {
                t = (u[i] - d[i]) / step;
                hit = i;
                hit_side = 1;
            } else if (x[a] < l[i] && step < 0 && (l[i] - d[i]) / step < t) {
                t = (l[i] - d[i]) / step;
                hit = i;
                hit_side = -1;
            }
        }
        for (int a = 0; a < nf; ++a) d[F[a]] += t * (x[a] - d[F[a]]);
        if (hit >= 0) { /* the first bound on the way: it joins the active set */
            state[hit] = hit_side;
            d[hit] = hit_side > 0 ? u[hit] : l[hit];
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
