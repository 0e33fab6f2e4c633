/* Gauss–Legendre nodes and weights by Newton's method on the Legendre recurrence. */
#define _POSIX_C_SOURCE 200809L
#include "iab/iab_internal.h"
#include "common/units.h"

#include <math.h>
#include <pthread.h>

/* P_n(x) and P_n'(x) by the three-term recurrence (k+1)P_{k+1} = (2k+1)xP_k − kP_{k−1}. */
static void legendre(int n, double x, double *p, double *dp)
{
    double p0 = 1.0, p1 = x;
    for (int k = 1; k < n; ++k) {
        double p2 = ((2.0 * k + 1.0) * x * p1 - k * p0) / (k + 1.0);
        p0 = p1;
        p1 = p2;
    }
    *p = n == 0 ? 1.0 : p1;
    /* (1 − x²)P_n' = n(P_{n−1} − xP_n); nodes are interior, so 1 − x² > 0. */
    *dp = n * (p0 - x * p1) / (1.0 - x * x);
}

hp_error hpi_iab_gl_rule(int n, double *x, double *w)
{
    if (!x || !w) return HP_ERR_NULL;
    if (n < 1 || n > HP_IAB_GL_MAX) return HP_ERR_INVALID;
    const double pi = HP_PI;
    int half = (n + 1) / 2;
    for (int i = 0; i < half; ++i) {
        /* Tricomi's estimate of the (i+1)-th largest root; Newton converges from it in a
         * few steps for every n <= 64. */
        double t = cos(pi * (i + 0.75) / (n + 0.5));
        double p, dp;
        /* Quadratic convergence: once a step is below 1e-13 the next one is below the
         * rounding level, so one more step and stop. */
        int last = 0;
        for (int it = 0; it < 50 && last < 2; ++it) {
            legendre(n, t, &p, &dp);
            double dt = p / dp;
            t -= dt;
            if (last || fabs(dt) < 1e-13) ++last;
        }
        legendre(n, t, &p, &dp);
        if (2 * i + 1 == n) t = 0.0; /* the middle node of an odd rule is exactly 0 */
        x[i] = t;
        w[i] = 2.0 / ((1.0 - t * t) * dp * dp);
    }
    return HP_OK;
}

/* Every rule is computed once per process (about 0.1 ms for all 64), so a quadrature costs
 * only its integrand evaluations; pthread_once makes the first use thread-safe. */
static double cache_x[HP_IAB_GL_MAX + 1][(HP_IAB_GL_MAX + 1) / 2];
static double cache_w[HP_IAB_GL_MAX + 1][(HP_IAB_GL_MAX + 1) / 2];
static pthread_once_t cache_once = PTHREAD_ONCE_INIT;

static void fill_cache(void)
{
    for (int n = 1; n <= HP_IAB_GL_MAX; ++n) (void)hpi_iab_gl_rule(n, cache_x[n], cache_w[n]);
}

hp_error hpi_iab_gl_cached(int n, const double **x, const double **w)
{
    if (!x || !w) return HP_ERR_NULL;
    if (n < 1 || n > HP_IAB_GL_MAX) return HP_ERR_INVALID;
    pthread_once(&cache_once, fill_cache);
    *x = cache_x[n];
    *w = cache_w[n];
    return HP_OK;
}
