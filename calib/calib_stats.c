/* Student's t quantile for the calibration intervals: the distribution function through the
 * regularised incomplete beta function (continued fraction, modified Lentz), inverted by
 * bisection. Only a few calls per fit, so clarity beats speed. */
#include "headplan/hp_calib.h"

#include <math.h>

/* Continued fraction of I_x(a, b), valid (fast) for x < (a + 1)/(a + b + 2). */
static double beta_cf(double a, double b, double x)
{
    const double tiny = 1e-300;
    double qab = a + b, qap = a + 1.0, qam = a - 1.0;
    /* c and d carry from one iteration to the next (Lentz's method), so their scope is
     * the function's. */
    // cppcheck-suppress variableScope
    double c = 1.0, d = 1.0 - qab * x / qap;
    if (fabs(d) < tiny) d = tiny;
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m <= 10000; ++m) {
        double m2 = 2.0 * m;
        double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        if (fabs(d) < tiny) d = tiny;
        c = 1.0 + aa / c;
        if (fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        h *= d * c;
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        if (fabs(d) < tiny) d = tiny;
        c = 1.0 + aa / c;
        if (fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (fabs(del - 1.0) < 1e-15) break;
    }
    return h;
}

/* Regularised incomplete beta I_x(a, b) for 0 <= x <= 1. */
static double inc_beta(double a, double b, double x)
{
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    double lbt = lgamma(a + b) - lgamma(a) - lgamma(b) + a * log(x) + b * log1p(-x);
    double bt = exp(lbt);
    if (x < (a + 1.0) / (a + b + 2.0)) return bt * beta_cf(a, b, x) / a;
    return 1.0 - bt * beta_cf(b, a, 1.0 - x) / b;
}

/* P(T <= t) for t >= 0 and dof degrees of freedom. */
static double t_cdf(double t, double dof)
{
    double x = dof / (dof + t * t);
    return 1.0 - 0.5 * inc_beta(0.5 * dof, 0.5, x);
}

/* The normal quantile by bisection on erfc (used for very large dof). */
static double normal_quantile(double p)
{
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
        double mid = 0.5 * (lo + hi);
        if (1.0 - 0.5 * erfc(mid / sqrt(2.0)) < p) lo = mid;
        else hi = mid;
    }
    return 0.5 * (lo + hi);
}

double hp_calib_t_quantile(double p, double dof)
{
    if (!(p >= 0.5 && p < 1.0) || !(dof >= 1.0) || isnan(dof)) return NAN;
    if (dof > 1e6) return normal_quantile(p);
    double lo = 0.0, hi = 1.0;
    while (t_cdf(hi, dof) < p && hi < 1e300) hi *= 2.0;
    for (int i = 0; i < 400 && hi - lo > 1e-14 * hi; ++i) {
        double mid = 0.5 * (lo + hi);
        if (t_cdf(mid, dof) < p) lo = mid;
        else hi = mid;
    }
    return 0.5 * (lo + hi);
}
