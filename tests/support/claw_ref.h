/* An independent evaluation of the fitted contact law (kinematics/contact_law.h) for the
 * tests: the same formula written once as a product of parts and differentiated by
 * second-order forward dual numbers (a value with its gradient and Hessian in P, ro, rho),
 * so that no derivative is derived by hand. The library evaluates hand-derived closed forms;
 * this reference shares no code with them, only the coefficients (contact_law_fit.h).
 *
 * In magnitude mode (claw_ref_fem_mag) every operation adds the absolute values of its terms:
 * the result is, for F, each derivative and W, the sum of the magnitudes of the terms the
 * formula adds (the scale the rounding of either evaluation is relative to, including the
 * absolute rounding of d = 1 − rho/ro near touch), which sizes the tests' tolerances. */
#ifndef HP_TEST_SUPPORT_CLAW_REF_H
#define HP_TEST_SUPPORT_CLAW_REF_H

#include "kinematics/contact_law.h"
#include "kinematics/contact_law_fit.h"

#include <math.h>
#include <string.h>

typedef struct cref {
    double v, g[3], h[3][3];
} cref;

static int cref_mag; /* 1: magnitude mode (single-threaded tests) */

static inline double cref_k(double a) { return cref_mag ? fabs(a) : a; }

static inline cref cref_const(double v)
{
    cref r;
    memset(&r, 0, sizeof r);
    r.v = cref_k(v);
    return r;
}

static inline cref cref_var(double v, int i)
{
    cref r = cref_const(v);
    r.g[i] = 1.0;
    return r;
}

static inline cref cref_lin(double a, cref x, double b, cref y) /* a·x + b·y */
{
    cref r;
    a = cref_k(a);
    b = cref_k(b);
    r.v = a * x.v + b * y.v;
    for (int i = 0; i < 3; ++i) {
        r.g[i] = a * x.g[i] + b * y.g[i];
        for (int j = 0; j < 3; ++j) r.h[i][j] = a * x.h[i][j] + b * y.h[i][j];
    }
    return r;
}

static inline cref cref_mul(cref x, cref y)
{
    cref r;
    r.v = x.v * y.v;
    for (int i = 0; i < 3; ++i) {
        r.g[i] = x.v * y.g[i] + y.v * x.g[i];
        for (int j = 0; j < 3; ++j)
            r.h[i][j] = x.v * y.h[i][j] + y.v * x.h[i][j] + x.g[i] * y.g[j] + x.g[j] * y.g[i];
    }
    return r;
}

static inline cref cref_chain(cref x, double f, double f1, double f2) /* f(x): f, f', f'' */
{
    cref r;
    f1 = cref_k(f1);
    f2 = cref_k(f2);
    r.v = cref_k(f);
    for (int i = 0; i < 3; ++i) {
        r.g[i] = f1 * x.g[i];
        for (int j = 0; j < 3; ++j) r.h[i][j] = f1 * x.h[i][j] + f2 * x.g[i] * x.g[j];
    }
    return r;
}

static inline cref cref_inv(cref x) /* 1/x, x > 0 */
{
    double f = 1.0 / x.v;
    return cref_chain(x, f, -f * f, 2.0 * f * f * f);
}

static inline cref cref_rsqrt(cref x) /* x^(−1/2), x > 0 */
{
    double f = 1.0 / sqrt(x.v);
    return cref_chain(x, f, -0.5 * f / x.v, 0.75 * f / (x.v * x.v));
}

/* c[0] + c[1]·x + ... + c[n−1]·x^(n−1), by powers (not Horner: another order of operations) */
static inline cref cref_poly(cref x, const double *c, int n)
{
    cref r = cref_const(0.0), p = cref_const(1.0);
    for (int k = 0; k < n; ++k) {
        r = cref_lin(1.0, r, c[k], p);
        p = cref_mul(p, x);
    }
    return r;
}

/* The law's polynomials in d (contact_law.h): G, H, their d-derivatives and integrals from 0. */
enum { CREF_F, CREF_DRHO, CREF_W };
static inline void cref_polys(int what, double g[6], int *ng, double h[6], int *nh)
{
    const double a1 = HP_CLAW_FIT_A1, a2 = HP_CLAW_FIT_A2, a3 = HP_CLAW_FIT_A3, bd = HP_CLAW_FIT_BD;
    const double G[4] = {0.0, a1, a2, a3}; /* G = d·(a1 + a2·d + a3·d²) */
    double H[5] = {0.0};                   /* H = G·(1 + bd·d) */
    for (int k = 0; k < 4; ++k) {
        H[k] += G[k];
        H[k + 1] += bd * G[k];
    }
    memset(g, 0, 6 * sizeof *g);
    memset(h, 0, 6 * sizeof *h);
    if (what == CREF_F) {
        memcpy(g, G, sizeof G);
        memcpy(h, H, sizeof H);
        *ng = 4, *nh = 5;
    } else if (what == CREF_DRHO) {
        for (int k = 1; k < 4; ++k) g[k - 1] = k * G[k];
        for (int k = 1; k < 5; ++k) h[k - 1] = k * H[k];
        *ng = 3, *nh = 4;
    } else {
        for (int k = 0; k < 4; ++k) g[k + 1] = G[k] / (k + 1);
        for (int k = 0; k < 5; ++k) h[k + 1] = H[k] / (k + 1);
        *ng = 5, *nh = 6;
    }
}

/* what = CREF_F: F = pi·ro²·(P·s·G(d) + w·H(d)); CREF_DRHO: dF/drho = −pi·ro·(P·s·G'(d) +
 * w·H'(d)); CREF_W: W = ro·pi·ro²·(P·s·∫G + w·∫H). With d = 1 − rho/ro,
 * s = 1 + b_w·(wall/ro − w0) + b_k·ro·curv, w = b_p·mu·P/sqrt(P² + (p_c·mu)²), mu = C1 + C2. */
static inline cref cref_fem(const hp_claw_bladder *b, double P, double ro, double rho, int what)
{
    cref p = cref_var(P, HP_CLAW_P), r = cref_var(ro, HP_CLAW_RO), q = cref_var(rho, HP_CLAW_RHO);
    cref ir = cref_inv(r);
    cref d = cref_lin(1.0, cref_const(1.0), -1.0, cref_mul(q, ir));
    cref s = cref_lin(1.0, cref_const(1.0 - HP_CLAW_FIT_BW * HP_CLAW_FIT_W0),
                      HP_CLAW_FIT_BW * b->wall, ir);
    s = cref_lin(1.0, s, HP_CLAW_FIT_BK * b->curv, r);
    double mu = b->C1 + b->C2, pc = HP_CLAW_FIT_PC * mu;
    cref w = cref_mul(
        cref_const(HP_CLAW_FIT_BP * mu),
        cref_mul(p, cref_rsqrt(cref_lin(1.0, cref_mul(p, p), 1.0, cref_const(pc * pc)))));
    double g[6], h[6];
    int ng, nh;
    cref_polys(what, g, &ng, h, &nh);
    cref v = cref_lin(1.0, cref_mul(cref_mul(p, s), cref_poly(d, g, ng)), 1.0,
                      cref_mul(w, cref_poly(d, h, nh)));
    cref m = what == CREF_F ? cref_mul(r, r) : what == CREF_DRHO ? r : cref_mul(r, cref_mul(r, r));
    return cref_mul(
        cref_const(what == CREF_DRHO ? -3.14159265358979323846 : 3.14159265358979323846),
        cref_mul(m, v));
}

/* The reference's F, derivatives and W into c (what = CREF_F), or dF/drho with its
 * derivatives (CREF_DRHO, W = 0); mag: the magnitude of the terms instead (see above). */
static inline void claw_ref_fem(const hp_claw_bladder *b, double P, double ro, double rho, int what,
                                int mag, hp_claw *c)
{
    cref_mag = mag;
    if (mag) P = fabs(P), ro = fabs(ro), rho = fabs(rho);
    cref F = cref_fem(b, P, ro, rho, what);
    c->F = F.v;
    for (int i = 0; i < 3; ++i) {
        c->d[i] = F.g[i];
        for (int j = 0; j < 3; ++j) c->d2[i][j] = F.h[i][j];
    }
    c->W = what == CREF_F ? cref_fem(b, P, ro, rho, CREF_W).v : 0.0;
    cref_mag = 0;
}

#endif
