/* The paper's two integral forms of the pressure, by fixed Gauss–Legendre and adaptive
 * Gauss–Kronrod quadrature. They exist to check the closed form (and the paper), not for
 * speed. The integrands are the paper's, term for term:
 *   P(r) = ∫_ri^ro 2C1(r/R² − R⁴/r⁵) + 2C2(r³/R⁴ − R²/r³) dr,   R³ = Ri³ + (r³ − ri³),
 *   P(R) = ∫_Ri^Ro 2C1(1/r − R⁶/r⁷) − 2C2(R⁴/r⁵ − r/R²) dR,    r³ = ri³ + (R³ − Ri³),
 * with the cube differences formed as (x − y)(x² + xy + y²) so no cancellation enters the
 * map between r and R. */
#include "iab/iab_internal.h"

#include <float.h>
#include <math.h>

/* Most intervals the adaptive rule may hold (fixed stack storage, no allocation). */
#define HP_IAB_GK_MAX_INTERVALS 256

typedef struct {
    const hp_iab_s *s;
    double ri; /* scaled inner radius */
    hp_quad_form form;
} integrand;

/* The integrand at offset t from the lower end of its interval (r = ri + t for the current
 * form, R = Ri + t for the reference form), and in *mag the sum of the absolute values of
 * its four terms: the scale of its rounding error. Integrating over the offset, with the
 * wall thickness ro − ri = W/(ro² + ro·ri + ri²) formed without cancellation, keeps the
 * interval exact to rounding of the thickness itself: a thin wall stretched to λi = 3 is
 * ~1e-3 of ro thick, and integrating over [ri, ro] as rounded doubles would cost ~1e-13. */
static double eval(const integrand *q, double t, double *mag)
{
    const hp_iab_s *s = q->s;
    double c1 = 2.0 * s->C1, c2 = 2.0 * s->C2;
    if (q->form == HP_QUAD_CURRENT) {
        double ri = q->ri, r = ri + t;
        double R = cbrt(s->Ri * s->Ri * s->Ri + t * (r * r + r * ri + ri * ri));
        double R2 = R * R, r2 = r * r, r3 = r2 * r;
        double t1 = r / R2, t2 = R2 * R2 / (r3 * r2), t3 = r3 / (R2 * R2), t4 = R2 / r3;
        *mag = c1 * (t1 + t2) + c2 * (t3 + t4);
        return c1 * (t1 - t2) + c2 * (t3 - t4);
    }
    double Ri = s->Ri, R = Ri + t;
    double r = cbrt(q->ri * q->ri * q->ri + t * (R * R + R * Ri + Ri * Ri));
    double R2 = R * R, R4 = R2 * R2, r2 = r * r, r5 = r2 * r2 * r;
    double t1 = 1.0 / r, t2 = R4 * R2 / (r5 * r2), t3 = R4 / r5, t4 = r / R2;
    *mag = c1 * (t1 + t2) + c2 * (t3 + t4);
    return c1 * (t1 - t2) - c2 * (t3 - t4);
}

/* Validates and sets up the integrand and its interval of offsets [0, thickness]. */
static hp_error setup(const hp_iab *b, double ri, hp_quad_form form, hp_iab_s *s, integrand *q,
                      double *lo, double *hi)
{
    hp_error e = hpi_iab_scaled_init(b, s, NULL);
    if (e != HP_OK) return e;
    if (form != HP_QUAD_CURRENT && form != HP_QUAD_REFERENCE) return HP_ERR_INVALID;
    if (!isfinite(ri)) return HP_ERR_INVALID;
    if (!(ri > 0)) return HP_ERR_DOMAIN;
    double ris = ri * s->scale;
    if (!(ris >= 1e-30 && ris <= 1e30)) return HP_ERR_DOMAIN;
    q->s = s;
    q->ri = ris;
    q->form = form;
    *lo = 0.0;
    if (form == HP_QUAD_CURRENT) {
        double ro = hpi_iab_s_ro(s, ris);
        *hi = s->W / (ro * ro + ro * ris + ris * ris); /* ro − ri */
    } else {
        *hi = s->Ro - s->Ri;
    }
    return HP_OK;
}

hp_error hp_iab_ik_gauss(const hp_iab *b, double ri, hp_quad_form form, int n, double *P)
{
    if (!P) return HP_ERR_NULL;
    hp_iab_s s;
    integrand q;
    double lo, hi;
    const double *x = NULL, *w = NULL;
    hp_error e = setup(b, ri, form, &s, &q, &lo, &hi);
    if (e == HP_OK) e = hpi_iab_gl_cached(n, &x, &w);
    if (e != HP_OK) return e;
    double c = 0.5 * (lo + hi), h = 0.5 * (hi - lo), sum = 0, mag;
    for (int k = 0; k < (n + 1) / 2; ++k) {
        if (x[k] == 0.0) sum += w[k] * eval(&q, c, &mag);
        else sum += w[k] * (eval(&q, c - h * x[k], &mag) + eval(&q, c + h * x[k], &mag));
    }
    double p = h * sum;
    if (!isfinite(p)) return HP_ERR_DOMAIN;
    *P = p;
    return HP_OK;
}

/* Kronrod 15-point nodes (x ≥ 0, descending) and weights, and the weights of the embedded
 * 7-point Gauss rule (on the odd-indexed Kronrod nodes); standard published constants,
 * checked in tests/iab by exact integration of monomials (degree 22 and 13). */
static const double xgk[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
static const double wgk[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
static const double wg[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

void hpi_iab_gk15_rule(const double **x, const double **wk, const double **wgauss)
{
    *x = xgk;
    *wk = wgk;
    *wgauss = wg;
}

typedef struct {
    double a, b, val, err, mag;
} interval;

/* One 15-point Kronrod evaluation on [iv->a, iv->b]; the error estimate is |K15 − G7|
 * (pessimistic: it is the error of the 7-point rule, while K15 is far more accurate). */
static void gk15(const integrand *q, interval *iv)
{
    double c = 0.5 * (iv->a + iv->b), h = 0.5 * (iv->b - iv->a), m;
    double fc = eval(q, c, &m);
    double k = wgk[7] * fc, g = wg[3] * fc, mag = wgk[7] * m;
    for (int j = 0; j < 7; ++j) {
        double m1, m2;
        double f1 = eval(q, c - h * xgk[j], &m1), f2 = eval(q, c + h * xgk[j], &m2);
        k += wgk[j] * (f1 + f2);
        mag += wgk[j] * (m1 + m2);
        if (j % 2 == 1) g += wg[j / 2] * (f1 + f2);
    }
    iv->val = k * h;
    iv->err = fabs((k - g) * h);
    iv->mag = mag * fabs(h);
}

hp_error hp_iab_ik_adaptive(const hp_iab *b, double ri, hp_quad_form form, double rel_tol,
                            double *P, double *err_est, int *evals)
{
    if (!P) return HP_ERR_NULL;
    if (!(rel_tol > 0) || !isfinite(rel_tol)) return HP_ERR_INVALID;
    hp_iab_s s;
    integrand q;
    double lo, hi;
    hp_error e = setup(b, ri, form, &s, &q, &lo, &hi);
    if (e != HP_OK) return e;
    interval iv[HP_IAB_GK_MAX_INTERVALS];
    int n = 1, nev = 15;
    iv[0].a = lo;
    iv[0].b = hi;
    gk15(&q, &iv[0]);
    for (;;) {
        double val = 0, err = 0, mag = 0;
        int worst = 0;
        for (int i = 0; i < n; ++i) {
            val += iv[i].val;
            err += iv[i].err;
            mag += iv[i].mag;
            if (iv[i].err > iv[worst].err) worst = i;
        }
        /* Done at the tolerance, or when the estimate reaches the rounding noise of the
         * integrand itself (64ε·∫Σ|terms|): near λi = 1 the paper's integrand is a
         * difference of nearly equal terms and no subdivision can do better. */
        double floor_noise = 64.0 * DBL_EPSILON * mag;
        int ok = err <= rel_tol * fabs(val) || err <= floor_noise;
        if (!isfinite(val) || !isfinite(err)) return HP_ERR_DOMAIN;
        if (ok || n + 1 > HP_IAB_GK_MAX_INTERVALS) {
            if (err_est) *err_est = err;
            if (evals) *evals = nev;
            if (!ok) {
                *P = NAN;
                return HP_ERR_NO_CONVERGENCE;
            }
            *P = val;
            return HP_OK;
        }
        interval *w = &iv[worst];
        double mid = 0.5 * (w->a + w->b);
        if (!(mid > w->a && mid < w->b)) { /* cannot split further */
            if (err_est) *err_est = err;
            if (evals) *evals = nev;
            *P = NAN;
            return HP_ERR_NO_CONVERGENCE;
        }
        iv[n].a = mid;
        iv[n].b = w->b;
        w->b = mid;
        gk15(&q, w);
        gk15(&q, &iv[n]);
        ++n;
        nev += 30;
    }
}
