/* The contact laws (contact_law.h): one function per law, each with its exact first and
 * second derivatives, so that the load model, the load planner and its stiffness all use
 * the same formula. */
#include "contact_law.h"
#include "common/units.h"
#include "contact_law_fit.h"
#include "headplan/hp_iab.h"

#include <math.h>

#include <string.h>

void hpi_claw_cap(double P, double ro, double rho, hp_claw *c)
{
    const double pi = HP_PI;
    double a = pi * (ro - rho) * (ro + rho); /* the cap's base area; (ro − rho)(ro + rho)
                                              * keeps its relative accuracy near touching */
    double d = ro - rho;
    memset(c, 0, sizeof *c);
    c->F = P * a;
    c->d[HP_CLAW_P] = a;
    c->d[HP_CLAW_RO] = 2.0 * pi * P * ro;
    c->d[HP_CLAW_RHO] = -2.0 * pi * P * rho;
    c->d2[HP_CLAW_P][HP_CLAW_RO] = c->d2[HP_CLAW_RO][HP_CLAW_P] = 2.0 * pi * ro;
    c->d2[HP_CLAW_P][HP_CLAW_RHO] = c->d2[HP_CLAW_RHO][HP_CLAW_P] = -2.0 * pi * rho;
    c->d2[HP_CLAW_RO][HP_CLAW_RO] = 2.0 * pi * P;
    c->d2[HP_CLAW_RHO][HP_CLAW_RHO] = -2.0 * pi * P;
    c->W = P * pi * d * d * (ro - d / 3.0);
}

/* Second-order forward derivatives in the law's three variables (P, ro, rho): a value
 * with its gradient and Hessian, so a formula written once gives exact derivatives. */
typedef struct hd {
    double v, g[3], h[3][3];
} hd;

static hd hd_const(double v)
{
    hd r;
    memset(&r, 0, sizeof r);
    r.v = v;
    return r;
}

static hd hd_var(double v, int i)
{
    hd r = hd_const(v);
    r.g[i] = 1.0;
    return r;
}

static hd hd_lin(double a, hd x, double b, hd y) /* a·x + b·y */
{
    hd r;
    r.v = a * x.v + b * y.v;
    for (int i = 0; i < 3; ++i) {
        r.g[i] = a * x.g[i] + b * y.g[i];
        for (int j = 0; j < 3; ++j) r.h[i][j] = a * x.h[i][j] + b * y.h[i][j];
    }
    return r;
}

static hd hd_scale(double a, hd x) { return hd_lin(a, x, 0.0, x); }

static hd hd_mul(hd x, hd y)
{
    hd r;
    r.v = x.v * y.v;
    for (int i = 0; i < 3; ++i) {
        r.g[i] = x.v * y.g[i] + y.v * x.g[i];
        for (int j = 0; j < 3; ++j)
            r.h[i][j] = x.v * y.h[i][j] + y.v * x.h[i][j] + x.g[i] * y.g[j] + x.g[j] * y.g[i];
    }
    return r;
}

static hd hd_inv(hd x) /* 1/x: f' = −1/x², f'' = 2/x³ */
{
    hd r;
    double f = 1.0 / x.v, f1 = -f * f, f2 = 2.0 * f * f * f;
    r.v = f;
    for (int i = 0; i < 3; ++i) {
        r.g[i] = f1 * x.g[i];
        for (int j = 0; j < 3; ++j) r.h[i][j] = f1 * x.h[i][j] + f2 * x.g[i] * x.g[j];
    }
    return r;
}

static hd hd_poly(hd x, const double *c, int n) /* c[0] + c[1]·x + ... + c[n−1]·x^(n−1) */
{
    hd r = hd_const(c[n - 1]);
    for (int k = n - 2; k >= 0; --k) r = hd_lin(1.0, hd_mul(r, x), 1.0, hd_const(c[k]));
    return r;
}

void hpi_claw_fem(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c)
{
    hd p = hd_var(P, HP_CLAW_P), r = hd_var(ro, HP_CLAW_RO), q = hd_var(rho, HP_CLAW_RHO);
    hd inv_r = hd_inv(r);
    hd d = hd_lin(1.0, hd_const(1.0), -1.0, hd_mul(q, inv_r)); /* delta/ro = 1 − rho/ro */
    hd wall = hd_scale(b->wall, inv_r);                        /* wall/ro */
    hd cp = hd_scale(b->C1, hd_inv(p));                        /* C1/P */
    hd kap = hd_scale(b->curv, r);                             /* ro/Rh */
    hd s = hd_const(1.0 + HP_CLAW_FIT_BC * (b->C2 / b->C1 - HP_CLAW_FIT_C0) -
                    HP_CLAW_FIT_BW * HP_CLAW_FIT_W0 - HP_CLAW_FIT_BP / HP_CLAW_FIT_P0);
    s = hd_lin(1.0, s, HP_CLAW_FIT_BW, wall);
    s = hd_lin(1.0, s, HP_CLAW_FIT_BP, cp);
    s = hd_lin(1.0, s, HP_CLAW_FIT_BK, kap);
    static const double ga[4] = {0.0, HP_CLAW_FIT_A1, HP_CLAW_FIT_A2, HP_CLAW_FIT_A3};
    static const double wa[5] = {0.0, 0.0, HP_CLAW_FIT_A1 / 2.0, HP_CLAW_FIT_A2 / 3.0,
                                 HP_CLAW_FIT_A3 / 4.0};
    hd scale = hd_scale(HP_PI, hd_mul(p, hd_mul(r, r))); /* P·pi·ro² */
    hd F = hd_mul(scale, hd_mul(s, hd_poly(d, ga, 4)));
    hd W = hd_mul(hd_mul(scale, r), hd_mul(s, hd_poly(d, wa, 5)));
    c->F = F.v;
    for (int i = 0; i < 3; ++i) {
        c->d[i] = F.g[i];
        for (int j = i; j < 3; ++j) c->d2[i][j] = c->d2[j][i] = F.h[i][j]; /* symmetric */
    }
    c->W = W.v;
}

hp_claw_domain hpi_claw_fem_domain(const hp_claw_bladder *b, double P, double ro, double rho)
{
    double d = 1.0 - rho / ro, w = b->wall / ro, p = P / b->C1, m = b->C2 / b->C1, k = ro * b->curv;
    /* !(x <= hi) also refuses NaN */
    if (!(d >= 0.0 && d <= HP_CLAW_FIT_DMAX)) return HP_CLAW_INDENT;
    if (!(w >= HP_CLAW_FIT_WMIN && w <= HP_CLAW_FIT_WMAX)) return HP_CLAW_WALL;
    if (!(p >= HP_CLAW_FIT_PMIN && p <= HP_CLAW_FIT_PMAX)) return HP_CLAW_PRESSURE;
    if (!(m >= HP_CLAW_FIT_CMIN && m <= HP_CLAW_FIT_CMAX)) return HP_CLAW_MODULI;
    if (!(k >= 0.0 && k <= HP_CLAW_FIT_KMAX)) return HP_CLAW_CURVATURE;
    return HP_CLAW_IN;
}

const char *hpi_claw_domain_name(hp_claw_domain d)
{
    static const char *const names[] = {"in", "indent", "wall", "pressure", "moduli", "curvature"};
    return (unsigned)d < sizeof names / sizeof names[0] ? names[d] : "?";
}

void hpi_claw_bladder_of(const struct hp_iab *iab, const double semi[3], const double x[3],
                         hp_claw_bladder *b)
{
    double a2 = semi[0] * semi[0], b2 = semi[1] * semi[1], c2 = semi[2] * semi[2];
    double q = x[0] * x[0] / (a2 * a2) + x[1] * x[1] / (b2 * b2) + x[2] * x[2] / (c2 * c2);
    double h = 1.0 / sqrt(q), r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
    b->C1 = iab->C1;
    b->C2 = iab->C2;
    b->wall = iab->Ro - iab->Ri;
    b->curv = h * h * h * (a2 + b2 + c2 - r2) / (2.0 * a2 * b2 * c2);
}

void hpi_claw_eval(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                   hp_claw *c)
{
    if (law == HP_CLAW_LAW_FEM) hpi_claw_fem(b, P, ro, rho, c);
    else hpi_claw_cap(P, ro, rho, c);
}
