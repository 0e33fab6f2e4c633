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

/* The fitted law in closed form (contact_law.h). Its parts, each computed once: with
 * u = 1/ro, the indentation d = 1 − rho·u (d_P = 0, d_ro = rho·u², d_rho = −u,
 * d_roro = −2·rho·u³, d_rorho = u², d_rhorho = 0); the pressure share's factor
 * s(ro) = 1 + b_w·(wall·u − w0) + b_k·curv·ro (s' = b_k·curv − b_w·wall·u², s'' = 2·b_w·wall·u³);
 * the wall share w(P) = b_p·mu·P·t with t = (P² + (p_c·mu)²)^(−1/2) (w' = b_p·mu·(p_c·mu)²·t³,
 * w'' = −3·P·t²·w'). Each law's output is m(ro)·X with X = P·s·g(d) + w·h(d) for a pair of
 * polynomials (g, h): F has m = pi·ro² and (G, H); dF/drho has m = −pi·ro and (G', H')
 * (dd/drho = −1/ro); W has m = pi·ro³ and the integrals of (G, H) (value only). Only what the order asks
 * for is computed; what is computed is the same operations in the same order at every
 * order, so the same bits. The tests compare with forward-mode dual numbers
 * (tests/support/claw_ref.h). */
/* The pieces below are inlined into each order's entry (fem_value, fem_gradient,
 * hpi_claw_fem), where the order is a constant and the tests on it fold away. */
#if defined(__GNUC__)
#define FEM_INLINE static inline __attribute__((always_inline))
#else
#define FEM_INLINE static inline
#endif

typedef struct fem_parts {
    double P, d, d_r, d_q, d_rr, d_rq; /* _r: d/dro, _q: d/drho */
    double s, s_r, s_rr, w, w1, w2;
} fem_parts;

FEM_INLINE void fem_parts_of(const hp_claw_bladder *b, double P, double ro, double rho, int o,
                             fem_parts *f)
{
    double u = 1.0 / ro, bw = HP_CLAW_FIT_BW * b->wall * u, bk = HP_CLAW_FIT_BK * b->curv;
    double mu = b->C1 + b->C2, pc = HP_CLAW_FIT_PC * mu, bp = HP_CLAW_FIT_BP * mu;
    double t = 1.0 / sqrt(P * P + pc * pc);
    f->P = P;
    f->d = 1.0 - rho * u;
    f->s = (1.0 - HP_CLAW_FIT_BW * HP_CLAW_FIT_W0) + bw + bk * ro;
    f->w = bp * P * t;
    if (o < HP_CLAW_GRADIENT) return;
    f->d_r = rho * u * u;
    f->d_q = -u;
    f->s_r = bk - bw * u;
    f->w1 = bp * pc * pc * t * t * t;
    if (o < HP_CLAW_HESSIAN) return;
    f->d_rr = -2.0 * f->d_r * u;
    f->d_rq = u * u;
    f->s_rr = 2.0 * bw * u * u;
    f->w2 = -3.0 * P * t * t * f->w1;
}

#define A1 HP_CLAW_FIT_A1
#define A2 HP_CLAW_FIT_A2
#define A3 HP_CLAW_FIT_A3
#define BD HP_CLAW_FIT_BD

/* The polynomials of family n at d, with their d-derivatives up to order o: n = 0 gives
 * g = G, h = H (for F), n = 1 gives g = G', h = H' (for dF/drho). H = G·L with
 * L = 1 + b_d·d, so H^(j) = G^(j)·L + j·b_d·G^(j−1): H costs a few products once G's
 * derivatives (G = a1·d + a2·d² + a3·d³) are known. g[j] = G^(n+j), h[j] = H^(n+j). */
FEM_INLINE void fem_polys(int n, double d, int o, double g[3], double h[3])
{
    double G[4]; /* G and its first three d-derivatives, as far as needed */
    int top = n + o;
    G[0] = d * (A1 + d * (A2 + d * A3));
    if (top >= 1) G[1] = A1 + d * (2.0 * A2 + d * (3.0 * A3));
    if (top >= 2) G[2] = 2.0 * A2 + d * (6.0 * A3);
    if (top >= 3) G[3] = 6.0 * A3;
    double L = 1.0 + BD * d;
    for (int j = 0; j <= o; ++j) {
        int m = n + j;
        g[j] = G[m];
        h[j] = m == 0 ? G[0] * L : G[m] * L + (double)m * BD * G[m - 1];
    }
}

/* The integrals of G and H from 0 (for W): the coefficients of d^0, d^1, ... */
static const double GI_[5] = {0.0, 0.0, A1 / 2.0, A2 / 3.0, A3 / 4.0};
static const double HI_[6] = {
    0.0, 0.0, A1 / 2.0, (A2 + A1 * BD) / 3.0, (A3 + A2 * BD) / 4.0, A3 *BD / 5.0};
#undef A1
#undef A2
#undef A3
#undef BD

/* c[0] + c[1]·x + ... + c[n−1]·x^(n−1) by Horner's rule. */
FEM_INLINE double poly(const double *c, int n, double x)
{
    double p = c[n - 1];
    for (int k = n - 2; k >= 0; --k) p = p * x + c[k];
    return p;
}

/* m(ro)·X, X = P·s·g(d) + w·h(d), up to order o into c (F, d, d2; NaN beyond o), given g, h
 * with their d-derivatives up to o (fem_polys) and m, m', m''. */
FEM_INLINE void fem_out(const fem_parts *f, const double g[3], const double h[3], const double m[3],
                        int o, hp_claw *c)
{
    enum { P_ = HP_CLAW_P, R_ = HP_CLAW_RO, Q_ = HP_CLAW_RHO };
    double ps = f->P * f->s;
    double X = ps * g[0] + f->w * h[0];
    c->F = m[0] * X;
    for (int i = 0; i < 3; ++i) {
        c->d[i] = NAN;
        for (int j = 0; j < 3; ++j) c->d2[i][j] = NAN;
    }
    if (o < HP_CLAW_GRADIENT) return;
    double Xd = ps * g[1] + f->w * h[1]; /* dX/dd */
    double Prs = f->P * f->s_r;
    double XP = f->s * g[0] + f->w1 * h[0];
    double Xr = Prs * g[0] + Xd * f->d_r;
    double Xq = Xd * f->d_q;
    c->d[P_] = m[0] * XP;
    c->d[R_] = m[1] * X + m[0] * Xr;
    c->d[Q_] = m[0] * Xq;
    if (o < HP_CLAW_HESSIAN) return;
    double Xdd = ps * g[2] + f->w * h[2];
    double XPd = f->s * g[1] + f->w1 * h[1]; /* d²X/dP dd */
    double XPr = f->s_r * g[0] + XPd * f->d_r;
    double Xrr = f->P * f->s_rr * g[0] + 2.0 * Prs * g[1] * f->d_r + Xdd * f->d_r * f->d_r +
                 Xd * f->d_rr;
    double Xrq = Prs * g[1] * f->d_q + Xdd * f->d_r * f->d_q + Xd * f->d_rq;
    c->d2[P_][P_] = m[0] * f->w2 * h[0];
    c->d2[P_][R_] = c->d2[R_][P_] = m[1] * XP + m[0] * XPr;
    c->d2[P_][Q_] = c->d2[Q_][P_] = m[0] * XPd * f->d_q;
    c->d2[R_][R_] = m[2] * X + 2.0 * m[1] * Xr + m[0] * Xrr;
    c->d2[R_][Q_] = c->d2[Q_][R_] = m[1] * Xq + m[0] * Xrq;
    c->d2[Q_][Q_] = m[0] * Xdd * f->d_q * f->d_q;
}

/* The derivative order o names (its bits below HP_CLAW_WORK), at most the Hessian: a caller
 * that or-s two orders gets the higher, never an order the arrays below do not have. */
FEM_INLINE int order_of(int o)
{
    int k = o & (HP_CLAW_WORK - 1);
    return k > HP_CLAW_HESSIAN ? HP_CLAW_HESSIAN : k;
}

/* F (and W with HP_CLAW_WORK, else NaN) up to the order in o. */
FEM_INLINE void fem_to(const hp_claw_bladder *b, double P, double ro, double rho, int o, hp_claw *c)
{
    int k = order_of(o);
    fem_parts f;
    fem_parts_of(b, P, ro, rho, k, &f);
    const double area = HP_PI * (ro * ro), m[3] = {area, 2.0 * HP_PI * ro, 2.0 * HP_PI};
    double g[3], h[3];
    fem_polys(0, f.d, k, g, h);
    fem_out(&f, g, h, m, k, c);
    c->W = NAN;
    if (!(o & HP_CLAW_WORK)) return;
    /* W = integral of F over rho' from rho to ro = ro·pi·ro²·(P·s·∫G + w·∫H) */
    c->W = ro * (area * (f.P * f.s * poly(GI_, 5, f.d) + f.w * poly(HI_, 6, f.d)));
}

/* One entry per order the callers ask for (the constant folds the order's tests away). */
static void fem_value(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c)
{
    fem_to(b, P, ro, rho, HP_CLAW_VALUE, c);
}

static void fem_gradient(const hp_claw_bladder *b, double P, double ro, double rho, int work,
                         hp_claw *c)
{
    if (work) fem_to(b, P, ro, rho, HP_CLAW_GRADIENT | HP_CLAW_WORK, c);
    else fem_to(b, P, ro, rho, HP_CLAW_GRADIENT, c);
}

void hpi_claw_fem(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c)
{
    fem_to(b, P, ro, rho, HP_CLAW_HESSIAN | HP_CLAW_WORK, c);
}

/* dF/drho = m·(P·s·G'(d) + w·H'(d)) with m = −pi·ro (dd/drho = −1/ro times pi·ro²). */
static void fem_drho(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c)
{
    fem_parts f;
    fem_parts_of(b, P, ro, rho, HP_CLAW_HESSIAN, &f);
    const double m[3] = {-HP_PI * ro, -HP_PI, 0.0};
    double g[3], h[3];
    fem_polys(1, f.d, HP_CLAW_HESSIAN, g, h);
    fem_out(&f, g, h, m, HP_CLAW_HESSIAN, c);
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
        int k = order_of((int)o), work = ((int)o & HP_CLAW_WORK) != 0;
        if (k == HP_CLAW_GRADIENT) fem_gradient(b, P, ro, rho, work, c);
        else if (k == HP_CLAW_VALUE && !work) fem_value(b, P, ro, rho, c);
        else fem_to(b, P, ro, rho, (int)o, c); /* the rarer combinations */
        return;
    }
    hpi_claw_cap(P, ro, rho, c); /* a few products: computed whole, then trimmed to o */
    int k = order_of((int)o);
    for (int i = 0; i < 3; ++i) {
        if (k < HP_CLAW_GRADIENT) c->d[i] = NAN;
        for (int j = 0; j < 3; ++j)
            if (k < HP_CLAW_HESSIAN) c->d2[i][j] = NAN;
    }
    if (!(o & HP_CLAW_WORK)) c->W = NAN;
}

void hpi_claw_eval(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                   hp_claw *c)
{
    hpi_claw_eval_to(law, b, P, ro, rho, HP_CLAW_HESSIAN | HP_CLAW_WORK, c);
}

void hpi_claw_eval_drho(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                        hp_claw *c)
{
    if (law == HP_CLAW_LAW_FEM) fem_drho(b, P, ro, rho, c);
    else cap_drho(P, rho, c);
}
