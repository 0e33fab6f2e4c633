/* Bladder validation, material conventions and the volume law. */
#include "iab/iab_internal.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

/* A cavity below 1e-9 of the outer radius is no bladder; the bound keeps every power of a
 * scaled radius that the model forms (up to the eighth) inside the double range. */
#define HP_IAB_MIN_RI_OVER_RO 1e-9

hp_error hp_iab_moduli_to_paper(hp_material_convention conv, double a, double b, double *C1,
                                double *C2)
{
    if (!C1 || !C2) return HP_ERR_NULL;
    if (!isfinite(a) || !isfinite(b)) return HP_ERR_INVALID;
    switch (conv) {
    case HP_MATERIAL_PAPER:
        *C1 = a;
        *C2 = b;
        return HP_OK;
    case HP_MATERIAL_FE: /* W = C10(I1−3) + C01(I2−3) = ½(2C10)(I1−3) + ½(2C01)(I2−3) */
        if (!isfinite(2.0 * a) || !isfinite(2.0 * b)) return HP_ERR_INVALID;
        *C1 = 2.0 * a;
        *C2 = 2.0 * b;
        return HP_OK;
    }
    return HP_ERR_INVALID;
}

/* The power of two 2^(1−e) for Ro = m·2^e, m in [0.5, 1), so that Ro·scale lies in [1, 2).
 * Every validated call of the model forms it (a few per bladder and plan), so for a normal
 * Ro it is read off the exponent bits: the same double frexp and ldexp give, exactly. */
static double scale_for(double Ro)
{
    uint64_t u;
    memcpy(&u, &Ro, sizeof u);
    int E = (int)((u >> 52) & 0x7ff); /* biased exponent: Ro = 1.f·2^(E−1023) */
    if (E >= 1 && E <= 2045) {
        /* e = E − 1022, so 2^(1−e) = 2^(1023−E), whose biased exponent 2046 − E is normal */
        uint64_t v = (uint64_t)(2046 - E) << 52;
        double scale;
        memcpy(&scale, &v, sizeof scale);
        return scale;
    }
    int e;
    frexp(Ro, &e);
    return ldexp(1.0, 1 - e);
}

/* The checks of hpi_iab_scaled_init one by one, for the message naming the first field that
 * fails; only called when one does. */
static hp_error invalid_bladder(const hp_iab *b, hp_diag *diag)
{
    if (!b) return hp_diag_set(diag, HP_ERR_NULL, "bladder: NULL pointer");
    if (!isfinite(b->Ri))
        return hp_diag_set(diag, HP_ERR_INVALID, "Ri: must be a finite number (got %g)", b->Ri);
    if (!isfinite(b->Ro))
        return hp_diag_set(diag, HP_ERR_INVALID, "Ro: must be a finite number (got %g)", b->Ro);
    if (!isfinite(b->C1))
        return hp_diag_set(diag, HP_ERR_INVALID, "C1: must be a finite number (got %g)", b->C1);
    if (!isfinite(b->C2))
        return hp_diag_set(diag, HP_ERR_INVALID, "C2: must be a finite number (got %g)", b->C2);
    if (!(b->Ri > 0)) return hp_diag_set(diag, HP_ERR_INVALID, "Ri: must be > 0 m (got %g)", b->Ri);
    if (!(b->Ro > b->Ri))
        return hp_diag_set(diag, HP_ERR_DOMAIN, "Ro: must be greater than Ri (Ro %g m, Ri %g m)",
                           b->Ro, b->Ri);
    if (!(b->Ri >= HP_IAB_MIN_RI_OVER_RO * b->Ro))
        return hp_diag_set(diag, HP_ERR_DOMAIN, "Ri: must be at least %g of Ro (Ri %g m, Ro %g m)",
                           HP_IAB_MIN_RI_OVER_RO, b->Ri, b->Ro);
    if (!(b->C1 > 0))
        return hp_diag_set(diag, HP_ERR_INVALID, "C1: must be > 0 Pa (got %g)", b->C1);
    return hp_diag_set(diag, HP_ERR_INVALID, "C2: must be >= 0 Pa (got %g)", b->C2);
}

hp_error hpi_iab_scaled_init(const hp_iab *b, hp_iab_s *s, hp_diag *diag)
{
    /* Every model call starts here (several per bladder and plan), so a valid bladder passes
     * in one chain of comparisons, each false for NaN: 0 < Ri < Ro <= DBL_MAX makes Ri and Ro
     * finite, and the bounds on C1 and C2 make them finite. That is exactly the conjunction
     * of invalid_bladder's checks, which names the field when one fails. */
    if (!(b && b->Ri > 0 && b->Ro > b->Ri && b->Ro <= DBL_MAX &&
          b->Ri >= HP_IAB_MIN_RI_OVER_RO * b->Ro && b->C1 > 0 && b->C1 <= DBL_MAX && b->C2 >= 0 &&
          b->C2 <= DBL_MAX))
        return invalid_bladder(b, diag);
    if (s) {
        s->scale = scale_for(b->Ro);
        s->inv_scale = 1.0 / s->scale;
        s->Ri = b->Ri * s->scale;
        s->Ro = b->Ro * s->scale;
        s->C1 = b->C1;
        s->C2 = b->C2;
        s->W = hpi_iab_cube_diff(s->Ro, s->Ri);
        s->Ri_m = b->Ri;
        s->iRi = 1.0 / s->Ri;
    }
    return HP_OK;
}

hp_error hp_iab_validate(const hp_iab *b, hp_diag *diag)
{
    return hpi_iab_scaled_init(b, NULL, diag);
}

/* Dekker's exact product without FMA: a·b = p + e exactly (no overflow and normal low parts
 * here: the arguments of hpi_iab_cbrt are reduced to [1, 8), hpi_iab_cbrt_near's range is
 * bounded). */
static void two_prod(double a, double b, double *p, double *e)
{
    const double split = 134217729.0; /* 2^27 + 1 */
    double ca = split * a, cb = split * b;
    double ah = ca - (ca - a), al = a - ah;
    double bh = cb - (cb - b), bl = b - bh;
    *p = a * b;
    *e = ((ah * bh - *p) + ah * bl + al * bh) + al * bl;
}

/* One Newton step on y³ = a from y, with the residual a − y³ formed exactly (y² and y²·y as
 * double-doubles; a − p3 is exact by Sterbenz's lemma when y³ is within a factor of two of
 * a). From a start of relative error δ the error after it is about δ² + δ·2⁻⁵² + 2⁻¹⁰⁵
 * relative plus the one rounding of y + correction. *corr is the correction, so that a
 * caller can tell how far the start was. Needs |y| < 2^480 and y³ far from underflow
 * (Dekker's split, the low parts). */
static inline double cbrt_refine(double a, double y, double *corr)
{
    double p2, e2, p3, e3;
    two_prod(y, y, &p2, &e2);
    two_prod(p2, y, &p3, &e3);
    double res = ((a - p3) - e3) - e2 * y;
    *corr = res / (3.0 * p2);
    return y + *corr;
}

/* cbrt(a) on [1, 8) to 1.8e-6 relative: a = m·2^k, m in [1, 2), by the degree-5 interpolant
 * of cbrt at the Chebyshev nodes in t = m − 1.5, times cbrt(2^k). Evaluated in Estrin's
 * scheme (three independent pairs joined by t² and t⁴): half the dependent chain of
 * Horner's, and the start only needs to be near. */
static inline double cbrt_poly(double m, int k)
{
    static const double cbrt2k[3] = {1.0, 1.2599210498948731648, 1.5874010519681994748};
    double t = m - 1.5, t2 = t * t;
    double y = (1.144712948162971 + t * 0.2543816456245348) +
               t2 * ((-0.056436294682727636 + t * 0.020886322742378068) +
                     t2 * (-0.010271170742077187 + t * 0.005072953325269895));
    return y * cbrt2k[k];
}

/* cbrt_poly and one plain Newton step, which squares the relative error: 1.8e-6 -> 3.2e-12
 * (plus rounding). */
static inline double cbrt_start(double m, int k, double a)
{
    double y = cbrt_poly(m, k);
    return y - (y * y * y - a) / (3.0 * y * y);
}

/* The argument reduction of hpi_iab_cbrt for a normal positive x = m·2^e, m in [1, 2),
 * e = 3q + k, k in {0, 1, 2}: cbrt(x) = cbrt(m·2^k)·2^q. Returns 0 for any other x. */
static inline int cbrt_reduce(double x, double *m, int *k, double *a, double *sc)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    int E = (int)(u >> 52);          /* the sign bit too: negative x has E >= 2048 */
    if (E < 1 || E > 2046) return 0; /* 0, subnormal, negative, inf, NaN */
    int e = E - 1023;
    int q = (e + 1200) / 3 - 400; /* floor(e/3): e + 1200 > 0 */
    *k = e - 3 * q;
    uint64_t mu = (u & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL;
    memcpy(m, &mu, sizeof *m);
    *a = *m * (double)(1 << *k);              /* exact, in [1, 8) */
    uint64_t su = (uint64_t)(1023 + q) << 52; /* 2^q, q in [-341, 341]: normal */
    memcpy(sc, &su, sizeof *sc);
    return 1;
}

double hpi_iab_cbrt(double x)
{
#if FLT_EVAL_METHOD != 0
    return cbrt(x); /* Dekker's product needs plain double arithmetic */
#else
    double m, a, sc, corr;
    int k;
    if (!cbrt_reduce(x, &m, &k, &a, &sc)) return cbrt(x);
    /* From the start's 3.2e-12 the exact-residual step leaves 1e-23 relative plus the one
     * rounding of y + correction, so the result is the correctly rounded cube root unless
     * that lies within ~1e-7 ulp of a midpoint (then still within 0.5 ulp + 1e-7). */
    return cbrt_refine(a, cbrt_start(m, k, a), &corr) * sc;
#endif
}

double hpi_iab_cbrt_near(double x, double y0)
{
#if FLT_EVAL_METHOD != 0
    (void)y0;
    return cbrt(x);
#else
    /* The range keeps Dekker's products and their low parts normal; a start within 2^-40
     * leaves at most 2^-80 + 2^-92 + 2^-105 relative before the last rounding, below the
     * 1e-23 that hpi_iab_cbrt's own start leaves: the same guarantee. */
    if (x >= 0x1p-300 && x <= 0x1p300 && y0 > 0 && y0 <= 0x1p101) {
        double corr, y = cbrt_refine(x, y0, &corr);
        if (fabs(corr) <= 0x1p-40 * y0) return y;
    }
    return hpi_iab_cbrt(x);
#endif
}

double hpi_iab_s_ro(const hp_iab_s *s, double ri) { return hpi_iab_cbrt(s->W + ri * ri * ri); }

hp_error hpi_iab_s_ro_m(const hp_iab_s *s, double ri, double *ro)
{
    double ris;
    hp_error e = hpi_iab_s_radius(s, ri, &ris);
    if (e != HP_OK) return e;
    *ro = hpi_iab_s_ro(s, ris) * s->inv_scale;
    return HP_OK;
}

hp_error hpi_iab_s_ri_m(const hp_iab_s *s, double ro, double *ri)
{
    double ros;
    hp_error e = hpi_iab_s_radius(s, ro, &ros);
    if (e != HP_OK) return e;
    double c = ros * ros * ros - s->W; /* ri³; cancels for thick walls and near collapse */
    if (!(c > 0)) return HP_ERR_DOMAIN;
    /* The start: cbrt(c) to 1.8e-6 relative (hpi_iab_cbrt's polynomial alone), or worse when
     * c cancelled (then libm's cbrt of the rounded c where the polynomial does not apply). */
    double m, a, sc;
    int k;
    double r = cbrt_reduce(c, &m, &k, &a, &sc) ? cbrt_poly(m, k) * sc : cbrt(c);
    /* Two Newton steps on ri³ − Ri³ = ro³ − Ro³, both sides formed without cancellation:
     * 1.8e-6 -> 3e-12 -> 1e-23 relative, and the residual is known to ~ulp(|ro³ − Ro³|), so
     * ri ends within a few ulps wherever the law itself is well conditioned
     * (dri/dro = ro²/ri²). The slope's division runs beside the residual, off the chain. */
    double rhs = hpi_iab_cube_diff(ros, s->Ro);
    for (int it = 0; it < 2; ++it) {
        double inv_slope = 1.0 / (3.0 * r * r);
        r -= (hpi_iab_cube_diff(r, s->Ri) - rhs) * inv_slope;
    }
    if (!(r > 0) || !isfinite(r)) return HP_ERR_DOMAIN;
    *ri = r * s->inv_scale; /* = r / scale exactly, without a division on the chain */
    return HP_OK;
}

hp_error hp_iab_ro(const hp_iab *b, double ri, double *ro)
{
    if (!ro) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    hp_error e = hpi_iab_scaled_init(b, &s, NULL);
    return e != HP_OK ? e : hpi_iab_s_ro_m(&s, ri, ro);
}

hp_error hp_iab_ri(const hp_iab *b, double ro, double *ri)
{
    if (!ri) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    hp_error e = hpi_iab_scaled_init(b, &s, NULL);
    return e != HP_OK ? e : hpi_iab_s_ri_m(&s, ro, ri);
}
