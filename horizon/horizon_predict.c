/* The receding horizon's periodic prediction (HP_PREDICT_PERIODIC): one component of the
 * recent desired poses fitted by a sinusoid on a linear trend, at a period read from the
 * signal's own level crossings. */
#include "horizon/horizon_internal.h"
#include "common/dense.h"

#include <math.h>

/* Hysteresis of the level crossings, as a fraction of the largest deviation from the trend
 * line: a crossing counts only once the signal has gone that far to the other side, so that
 * tracker noise (a few hundredths of a millimetre on the horizon traces, against a breathing
 * amplitude of 0.6–1.5 mm) makes none. */
#define PF_BAND 0.25
/* Fewest rows a fit is tried on. */
#define PF_MIN_ROWS 8
/* Most rows a fit uses (the newest). */
#define PF_MAX_ROWS 256

/* The line a + e·τ (τ = t − t0) fitted to the rows; 0 when the times do not span an
 * interval. */
static int trend(const double *t, const double *x, int stride, int count, double t0, double *a,
                 double *e)
{
    double st = 0, sx = 0, stt = 0, stx = 0;
    for (int k = 0; k < count; ++k) {
        double tau = t[k] - t0, v = x[stride * k];
        st += tau;
        sx += v;
        stt += tau * tau;
        stx += tau * v;
    }
    double den = count * stt - st * st;
    if (!(den > 0)) return 0;
    *e = (count * stx - st * sx) / den;
    *a = (sx - *e * st) / count;
    return isfinite(*a) && isfinite(*e);
}

/* Without cur: the linear least squares p[0..3] = a, e, b, c on 1, τ, cos, sin (cw, sw at
 * the rows' τ). With cur (a, e, b, c of a fit at the same w): the Gauss–Newton step p[0..4]
 * on a, e, b, c and w, whose column for w is τ·(c·cos − b·sin). 0 when the normal matrix is
 * not positive definite. */
static int least_squares(const double *tau, const double *x, const double *cw, const double *sw,
                         int m, const double *cur, double *p)
{
    const int np = cur ? 5 : 4;
    double M[25] = {0};
    for (int r = 0; r < 5; ++r) p[r] = 0;
    for (int k = 0; k < m; ++k) {
        double phi[5] = {1.0, tau[k], cw[k], sw[k], 0.0}, y = x[k];
        if (cur) {
            phi[4] = tau[k] * (cur[3] * cw[k] - cur[2] * sw[k]);
            y -= cur[0] + cur[1] * tau[k] + cur[2] * cw[k] + cur[3] * sw[k];
        }
        for (int r = 0; r < np; ++r) {
            p[r] += phi[r] * y;
            for (int q = 0; q <= r; ++q) M[np * r + q] += phi[r] * phi[q];
        }
    }
    if (!hpi_cholesky(M, np, np, 1e-12, M, np)) return 0;
    hpi_cholesky_solve(M, np, np, p);
    return 1;
}

int hpi_horizon_periodic_fit(const double *t, const double *x, int stride, int count,
                             hpi_periodic *f)
{
    if (count < PF_MIN_ROWS) return 0;
    const double t0 = t[count - 1];
    double a, e;
    if (!trend(t, x, stride, count, t0, &a, &e)) return 0;
    double rmax = 0;
    for (int k = 0; k < count; ++k) rmax = fmax(rmax, fabs(x[stride * k] - a - e * (t[k] - t0)));
    if (!(rmax > 0) || !isfinite(rmax)) return 0;
    /* Level crossings of the signal about its trend line, each at the time the line between
     * the two samples around it crosses zero. */
    const double band = PF_BAND * rmax;
    /* per direction (0 falling, 1 rising): how many, the first and the last */
    int side = 0, nc[2] = {0, 0};
    double first[2] = {0, 0}, last[2] = {0, 0};
    for (int k = 0; k < count; ++k) {
        double r = x[stride * k] - a - e * (t[k] - t0);
        int s = r > band ? 1 : r < -band ? -1 : 0;
        if (s && side && s != side) {
            int m = k;
            double rm = r, rp = r;
            while (m > 0) {
                rp = x[stride * (m - 1)] - a - e * (t[m - 1] - t0);
                if ((rp > 0) != (rm > 0)) break;
                rm = rp;
                --m;
            }
            double tc = m > 0 ? t[m - 1] + (t[m] - t[m - 1]) * rp / (rp - rm) : t[0];
            int up = s > 0;
            if (nc[up] == 0) first[up] = tc;
            last[up] = tc;
            nc[up]++;
        }
        if (s) side = s;
    }
    /* The period from crossings in one direction: whole periods apart whatever the trend
     * line's offset, which shifts rising and falling crossings in opposite directions. */
    const int dir = nc[1] >= nc[0];
    if (nc[dir] < 2) return 0; /* no whole period seen */
    const double period = (last[dir] - first[dir]) / (nc[dir] - 1);
    if (!(period > 0) || !isfinite(period)) return 0;
    const double w = 2.0 * 3.14159265358979323846 / period;
    /* Least squares on 1, τ, cos wτ, sin wτ over the rows of the last two periods (at most
     * PF_MAX_ROWS), then one Gauss–Newton step on all five parameters with w among them:
     * the crossings give the period to about 1 % (the trend line's slope, fitted over a
     * non-whole number of cycles, tilts them), which puts the phase a second ahead off by
     * a few hundredths of a radian; the step, at the same cosines and sines, removes most of
     * it. */
    double cw[PF_MAX_ROWS], sw[PF_MAX_ROWS], tau[PF_MAX_ROWS], xv[PF_MAX_ROWS];
    int used = 0;
    for (int k = count - 1; k >= 0 && t0 - t[k] <= 2.0 * period && used < PF_MAX_ROWS; --k) {
        tau[used] = t[k] - t0;
        xv[used] = x[stride * k];
        cw[used] = cos(w * tau[used]);
        sw[used] = sin(w * tau[used]);
        used++;
    }
    if (used < PF_MIN_ROWS) return 0;
    double p[5];
    if (!least_squares(tau, xv, cw, sw, used, NULL, p)) return 0;
    double dp[5];
    if (!least_squares(tau, xv, cw, sw, used, p, dp)) return 0;
    /* A step that moves the period by more than a tenth is no refinement: keep the first. */
    if (fabs(dp[4]) <= 0.1 * w) {
        for (int r = 0; r < 4; ++r) p[r] += dp[r];
        p[4] = w + dp[4];
    } else {
        p[4] = w;
    }
    for (int r = 0; r < 5; ++r)
        if (!isfinite(p[r])) return 0;
    f->t0 = t0;
    f->a = p[0];
    f->e = p[1];
    f->b = p[2];
    f->c = p[3];
    f->omega = p[4];
    return 1;
}

double hpi_horizon_periodic_at(const hpi_periodic *f, double t)
{
    double tau = t - f->t0;
    return f->a + f->e * tau + f->b * cos(f->omega * tau) + f->c * sin(f->omega * tau);
}
