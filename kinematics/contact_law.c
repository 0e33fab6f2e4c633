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
 * with its gradient and Hessian, so a formula written once gives exact derivatives. o is
 * the highest order carried (hp_claw_order): an operation carries the lower of its operands'
 * orders and skips the rest (left unset), so a caller that needs no Hessian does not pay for
 * one. What is carried is computed by the same operations in the same order whatever o is:
 * the same bits. A constant carries every order (its derivatives are 0). */
typedef struct hd {
    double v, g[3], h[3][3];
    int o;
} hd;

/* The arithmetic below is inlined into each order's entry (fem_value, fem_gradient,
 * fem_hessian), where o is a constant: the tests on it fold away and the skipped orders cost
 * nothing. Without the forced inlining the compiler keeps these as calls, and the run-time
 * tests cost more than the Hessian they skip. */
#if defined(__GNUC__)
#define HD_INLINE static inline __attribute__((always_inline))
#else
#define HD_INLINE static inline
#endif

HD_INLINE hd hd_const(double v)
{
    hd r;
    memset(&r, 0, sizeof r);
    r.v = v;
    r.o = HP_CLAW_HESSIAN;
    return r;
}

HD_INLINE hd hd_var(double v, int i, int o)
{
    hd r = hd_const(v);
    r.g[i] = 1.0;
    r.o = o;
    return r;
}

HD_INLINE int hd_min(int a, int b) { return a < b ? a : b; }

/* r carrying order o, its value set: the orders it does not carry are cleared (stores the
 * compiler drops once inlined, where nothing reads them), so that no copy of r reads an
 * unset field. Returns whether r carries the gradient. */
HD_INLINE int hd_begin(hd *r, int o, double v)
{
    r->o = o;
    r->v = v;
    if (o < HP_CLAW_HESSIAN)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) r->h[i][j] = 0.0;
    if (o < HP_CLAW_GRADIENT)
        for (int i = 0; i < 3; ++i) r->g[i] = 0.0;
    return o >= HP_CLAW_GRADIENT;
}

HD_INLINE hd hd_lin(double a, hd x, double b, hd y) /* a·x + b·y */
{
    hd r;
    if (!hd_begin(&r, hd_min(x.o, y.o), a * x.v + b * y.v)) return r;
    for (int i = 0; i < 3; ++i) r.g[i] = a * x.g[i] + b * y.g[i];
    if (r.o < HP_CLAW_HESSIAN) return r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.h[i][j] = a * x.h[i][j] + b * y.h[i][j];
    return r;
}

HD_INLINE hd hd_scale(double a, hd x) { return hd_lin(a, x, 0.0, x); }

HD_INLINE hd hd_mul(hd x, hd y)
{
    hd r;
    if (!hd_begin(&r, hd_min(x.o, y.o), x.v * y.v)) return r;
    for (int i = 0; i < 3; ++i) r.g[i] = x.v * y.g[i] + y.v * x.g[i];
    if (r.o < HP_CLAW_HESSIAN) return r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r.h[i][j] = x.v * y.h[i][j] + y.v * x.h[i][j] + x.g[i] * y.g[j] + x.g[j] * y.g[i];
    return r;
}

HD_INLINE hd hd_chain(hd x, double f, double f1, double f2) /* f(x) given f, f', f'' at x */
{
    hd r;
    if (!hd_begin(&r, x.o, f)) return r;
    for (int i = 0; i < 3; ++i) r.g[i] = f1 * x.g[i];
    if (r.o < HP_CLAW_HESSIAN) return r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.h[i][j] = f1 * x.h[i][j] + f2 * x.g[i] * x.g[j];
    return r;
}

HD_INLINE hd hd_inv(hd x) /* 1/x: f' = −1/x², f'' = 2/x³ */
{
    double f = 1.0 / x.v;
    return hd_chain(x, f, -f * f, 2.0 * f * f * f);
}

HD_INLINE hd hd_rsqrt(hd x) /* x^(−1/2): f' = −f/(2x), f'' = 3f/(4x²) */
{
    double f = 1.0 / sqrt(x.v);
    return hd_chain(x, f, -0.5 * f / x.v, 0.75 * f / (x.v * x.v));
}

HD_INLINE hd hd_poly(hd x, const double *c, int n) /* c[0] + c[1]·x + ... + c[n−1]·x^(n−1) */
{
    hd r = hd_const(c[n - 1]);
    for (int k = n - 2; k >= 0; --k) r = hd_lin(1.0, hd_mul(r, x), 1.0, hd_const(c[k]));
    return r;
}

/* The fitted law's pieces: d = delta/ro, pi·ro², the pressure's share P·s and the wall's
 * share w = b_p·mu·P/sqrt(P² + (pc·mu)²) (mu = C1 + C2), so that
 *     F = pi·ro²·(P·s·G(d) + w·H(d)),  G(d) = d·(a1 + a2·d + a3·d²),  H(d) = G(d)·(1 + b_d·d).
 * The wall's share vanishes with P (no force without pressure, as the load model's contact
 * switch has it) and is smooth and bounded for every P. */
typedef struct fem_parts {
    hd r, d, area, ps, w;
} fem_parts;

HD_INLINE fem_parts fem_parts_of(const hp_claw_bladder *b, double P, double ro, double rho, int o)
{
    fem_parts f;
    hd p = hd_var(P, HP_CLAW_P, o), q = hd_var(rho, HP_CLAW_RHO, o);
    f.r = hd_var(ro, HP_CLAW_RO, o);
    hd inv_r = hd_inv(f.r);
    f.d = hd_lin(1.0, hd_const(1.0), -1.0, hd_mul(q, inv_r)); /* delta/ro = 1 − rho/ro */
    hd wall = hd_scale(b->wall, inv_r);                       /* wall/ro */
    hd kap = hd_scale(b->curv, f.r);                          /* ro/Rh */
    hd s = hd_const(1.0 - HP_CLAW_FIT_BW * HP_CLAW_FIT_W0);
    s = hd_lin(1.0, s, HP_CLAW_FIT_BW, wall);
    s = hd_lin(1.0, s, HP_CLAW_FIT_BK, kap);
    f.ps = hd_mul(p, s);
    double mu = b->C1 + b->C2;
    double pc = HP_CLAW_FIT_PC * mu;
    f.w = hd_scale(HP_CLAW_FIT_BP * mu,
                   hd_mul(p, hd_rsqrt(hd_lin(1.0, hd_mul(p, p), pc * pc, hd_const(1.0)))));
    f.area = hd_scale(HP_PI, hd_mul(f.r, f.r));
    return f;
}

/* F's value and the derivatives it carries into c; what it does not carry is NaN. */
HD_INLINE void hd_out(hd F, hp_claw *c)
{
    c->F = F.v;
    for (int i = 0; i < 3; ++i) {
        c->d[i] = F.o >= HP_CLAW_GRADIENT ? F.g[i] : NAN;
        for (int j = i; j < 3; ++j) /* symmetric */
            c->d2[i][j] = c->d2[j][i] = F.o >= HP_CLAW_HESSIAN ? F.h[i][j] : NAN;
    }
}

#define A1 HP_CLAW_FIT_A1
#define A2 HP_CLAW_FIT_A2
#define A3 HP_CLAW_FIT_A3
#define BD HP_CLAW_FIT_BD
/* G and H as polynomials in d, their derivatives, and their integrals from 0 */
static const double G_[4] = {0.0, A1, A2, A3};
static const double H_[5] = {0.0, A1, A2 + A1 *BD, A3 + A2 *BD, A3 *BD};
static const double G1_[3] = {A1, 2.0 * A2, 3.0 * A3};
static const double H1_[4] = {A1, 2.0 * (A2 + A1 * BD), 3.0 * (A3 + A2 * BD), 4.0 * A3 *BD};
static const double GI_[5] = {0.0, 0.0, A1 / 2.0, A2 / 3.0, A3 / 4.0};
static const double HI_[6] = {
    0.0, 0.0, A1 / 2.0, (A2 + A1 * BD) / 3.0, (A3 + A2 * BD) / 4.0, A3 *BD / 5.0};
#undef A1
#undef A2
#undef A3
#undef BD

/* pi·ro²·(P·s·g(d) + w·h(d)) for a pair of polynomials (g, h) */
HD_INLINE hd fem_sum(const fem_parts *f, const double *g, int ng, const double *h, int nh)
{
    hd v = hd_lin(1.0, hd_mul(f->ps, hd_poly(f->d, g, ng)), 1.0,
                  hd_mul(f->w, hd_poly(f->d, h, nh)));
    return hd_mul(f->area, v);
}

HD_INLINE void fem_to(const hp_claw_bladder *b, double P, double ro, double rho, int o, hp_claw *c)
{
    fem_parts f = fem_parts_of(b, P, ro, rho, o);
    hd_out(fem_sum(&f, G_, 4, H_, 5), c);
    /* W = integral of F over rho' from rho to ro = ro·(the same with G, H integrated in d);
     * only its value is used, so its parts are evaluated without derivatives (same bits). */
    fem_parts v = o == HP_CLAW_VALUE ? f : fem_parts_of(b, P, ro, rho, HP_CLAW_VALUE);
    c->W = hd_mul(v.r, fem_sum(&v, GI_, 5, HI_, 6)).v;
}

static void fem_value(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c)
{
    fem_to(b, P, ro, rho, HP_CLAW_VALUE, c);
}

static void fem_gradient(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c)
{
    fem_to(b, P, ro, rho, HP_CLAW_GRADIENT, c);
}

void hpi_claw_fem(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c)
{
    fem_to(b, P, ro, rho, HP_CLAW_HESSIAN, c);
}

/* dF/drho = −(1/ro)·pi·ro²·(P·s·G'(d) + w·H'(d)) (dd/drho = −1/ro). */
static void fem_drho(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c)
{
    fem_parts f = fem_parts_of(b, P, ro, rho, HP_CLAW_HESSIAN);
    hd_out(hd_scale(-1.0, hd_mul(hd_inv(f.r), fem_sum(&f, G1_, 3, H1_, 4))), c);
    c->W = 0.0;
}

/* dF/drho of the cap law: −2·pi·P·rho. */
static void cap_drho(double P, double rho, hp_claw *c)
{
    memset(c, 0, sizeof *c);
    c->F = -2.0 * HP_PI * P * rho;
    c->d[HP_CLAW_P] = -2.0 * HP_PI * rho;
    c->d[HP_CLAW_RHO] = -2.0 * HP_PI * P;
    c->d2[HP_CLAW_P][HP_CLAW_RHO] = c->d2[HP_CLAW_RHO][HP_CLAW_P] = -2.0 * HP_PI;
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

void hpi_claw_eval_to(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                      hp_claw_order o, hp_claw *c)
{
    if (law == HP_CLAW_LAW_FEM) {
        if (o == HP_CLAW_VALUE) fem_value(b, P, ro, rho, c);
        else if (o == HP_CLAW_GRADIENT) fem_gradient(b, P, ro, rho, c);
        else hpi_claw_fem(b, P, ro, rho, c);
        return;
    }
    hpi_claw_cap(P, ro, rho, c); /* a few products: computed whole, then trimmed to o */
    for (int i = 0; i < 3; ++i) {
        if (o < HP_CLAW_GRADIENT) c->d[i] = NAN;
        for (int j = 0; j < 3; ++j)
            if (o < HP_CLAW_HESSIAN) c->d2[i][j] = NAN;
    }
}

void hpi_claw_eval(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                   hp_claw *c)
{
    hpi_claw_eval_to(law, b, P, ro, rho, HP_CLAW_HESSIAN, c);
}

void hpi_claw_eval_drho(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                        hp_claw *c)
{
    if (law == HP_CLAW_LAW_FEM) fem_drho(b, P, ro, rho, c);
    else cap_drho(P, rho, c);
}
