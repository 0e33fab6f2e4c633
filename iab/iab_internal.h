/* Internal helpers of the bladder model (not installed): shared by the iab module, and the
 * hp_iab_s_*_m functions below by the planner's per-plan path, which validates a bladder
 * once and then evaluates it several times.
 *
 * Lengths are rescaled by a power of two so that Ro lies in [1, 2): the scaling is exact,
 * pressures do not change (they depend on stretches only), and radii to the sixth power
 * neither overflow nor underflow for any bladder a user can describe. */
#ifndef HP_IAB_INTERNAL_H
#define HP_IAB_INTERNAL_H

#include "headplan/hp_iab.h"

#include <math.h>

/* A validated bladder in scaled lengths. */
typedef struct hp_iab_s {
    double Ri, Ro;    /* reference radii × scale */
    double C1, C2;    /* moduli [Pa] */
    double scale;     /* power of two: scaled length = length [m] × scale */
    double inv_scale; /* 1/scale, exact (a power of two): length [m] = scaled × inv_scale */
    double W;    /* Ro³ − Ri³ (scaled), the wall's volume / (4π/3); ro³ − ri³ = W always */
    double Ri_m; /* Ri [m] as given: FK's exact answer at P = 0 */
    double iRi;  /* 1/Ri (scaled), the slope's dλi/dri: the bits each slope formed again */
} hp_iab_s;

/* x³ − y³ without cancellation beyond the one rounding of x − y (exact by Sterbenz's lemma
 * when x and y are within a factor of two). */
static inline double hpi_iab_cube_diff(double x, double y)
{
    return (x - y) * (x * x + x * y + y * y);
}

/* Validates b and fills s. Same codes and messages as hp_iab_validate. */
hp_error hpi_iab_scaled_init(const hp_iab *b, hp_iab_s *s, hp_diag *diag);

/* A scaled radius from a radius r in metres: HP_ERR_INVALID for NaN/Inf, HP_ERR_DOMAIN for
 * r <= 0 or a radius so far from the bladder's size that its cube leaves the range. */
static inline hp_error hpi_iab_s_radius(const hp_iab_s *s, double r, double *out)
{
    if (!isfinite(r)) return HP_ERR_INVALID;
    if (!(r > 0)) return HP_ERR_DOMAIN;
    double rs = r * s->scale;
    if (!(rs >= 1e-30 && rs <= 1e30)) return HP_ERR_DOMAIN;
    *out = rs;
    return HP_OK;
}

/* The volume law, its inverse and the closed-form IK of a bladder already validated into s
 * (hpi_iab_scaled_init), in metres and pascals: the same codes and the same bits as hp_iab_ro,
 * hp_iab_ri and hp_iab_ik (which are these after the validation). For a caller that
 * evaluates one bladder several times, the validation (about a third of a call) once. */
hp_error hpi_iab_s_ro_m(const hp_iab_s *s, double ri, double *ro);
hp_error hpi_iab_s_ri_m(const hp_iab_s *s, double ro, double *ri);
hp_error hpi_iab_s_ik_m(const hp_iab_s *s, double ri, double *P);

/* The cube root of x, correctly rounded for a normal positive x except where the exact root
 * lies within ~1e-7 ulp of a midpoint between doubles (then within 0.5 ulp + 1e-7 ulp);
 * libm's cbrt for every other x (0, subnormal, negative, inf, NaN) and on a platform that
 * evaluates double expressions in wider precision. Several per bladder and plan, and
 * about half the price of libm's (which is within 1 ulp). */
double hpi_iab_cbrt(double x);

/* hpi_iab_cbrt(x) from a start y0 that is already close (a nearby root: the outer radius the
 * inner one was solved from): one exact-residual Newton step when it moves y0 by at most
 * 2^-40 relative, else hpi_iab_cbrt(x). The same guarantee as hpi_iab_cbrt (correctly rounded
 * but within ~1e-7 ulp of a midpoint), so the same bits except there, for about a third of
 * its latency (no polynomial, no first Newton division). Any y0 is safe (NaN, 0, far off:
 * the full cube root). */
double hpi_iab_cbrt_near(double x, double y0);

/* Scaled outer radius for scaled inner radius ri > 0: ro = cbrt(W + ri³) (hpi_iab_cbrt), a
 * sum of two positive terms (no cancellation). */
double hpi_iab_s_ro(const hp_iab_s *s, double ri);

/* 2C1[f(λ1) − f(λ2)] + 2C2[g(λ1) − g(λ2)] for two radii r1 < r2 of the same deformed wall
 * (λk = rk/Rk), in a cancellation-free form:
 *   f(a) − f(b) = (a − b)·[1/(ab) + (a + b)(a² + b²)/(4a⁴b⁴)],
 *   g(a) − g(b) = (a − b)·[1 + (a + b)/(2a²b²)],
 *   λ1 − λ2 = (r1R2 − r2R1)/(R1R2),  r1R2 − r2R1 = a·(r2³ − r1³)/(x² + xy + y²)
 * with x = r1R2, y = r2R1, a = r³ − R³ (the same everywhere in the wall, = ri³ − Ri³),
 * c21 = r2³ − r1³ > 0. Every bracket is a sum of positive terms, so the relative error is a
 * few ulps, including at λ → 1 where the naive difference cancels. */
double hpi_iab_s_energy_diff(const hp_iab_s *s, double r1, double R1, double r2, double R2,
                             double a, double c21);

/* Closed-form pressure and exact derivatives in scaled units (dP/dri per scaled length).
 * Requires ri > 0 finite; returns HP_ERR_DOMAIN when the result is not finite (ri so small
 * or so large that the pressure overflows). d1, d2 may be NULL. */
hp_error hpi_iab_s_ik(const hp_iab_s *s, double ri, double *P, double *d1, double *d2);

/* hpi_iab_s_ik's derivatives at scaled ri whose scaled outer radius is ro (hpi_iab_s_ro(s,
 * ri)): the same bits as hpi_iab_s_ik's, for a caller that has the pressure already. A
 * derivative not asked for is not formed (nor checked). d1, d2 may be NULL. */
hp_error hpi_iab_s_slopes(const hp_iab_s *s, double ri, double ro, double *d1, double *d2);

/* hpi_iab_s_ik_m for an inner radius ri [m] whose outer radius is known to be close to
 * ro_near [m] (the one ri was solved from by hpi_iab_s_ri_m): the outer radius the pressure
 * uses comes from hpi_iab_cbrt_near, so the same bits as hpi_iab_s_ik_m but within ~1e-7 ulp
 * of a rounding midpoint of that radius; any ro_near is safe. */
hp_error hpi_iab_s_ik_near_m(const hp_iab_s *s, double ri, double ro_near, double *P);

/* hpi_iab_s_ik_m and hpi_iab_s_ro_m of one inner radius ri [m] in one evaluation (the pressure
 * forms the outer radius anyway): the same codes as hpi_iab_s_ik_m, the same bits of *P and
 * *ro [m] as the two calls. */
hp_error hpi_iab_s_ik_ro_m(const hp_iab_s *s, double ri, double *P, double *ro);

/* hpi_iab_s_ik's pressure without derivatives, and the scaled outer radius it used
 * (hpi_iab_s_ro(s, ri), the same bits). */
hp_error hpi_iab_s_pressure_ro(const hp_iab_s *s, double ri, double *P, double *ro);
/* hpi_iab_s_pressure_ro and then hpi_iab_s_slopes' d1 at its outer radius, in one pass: the
 * same bits and codes as the two calls (the stretches ri/Ri and ro/Ro both formulas use are
 * formed once). The root find's evaluation of a Newton step. */
hp_error hpi_iab_s_pressure_slope(const hp_iab_s *s, double ri, double *P, double *ro, double *d1);
/* hpi_iab_s_pressure_slope and hpi_iab_s_pressure_ro at ri next to an evaluation at ri0
 * whose scaled outer radius was ro0 (a root find's next step or the double beside its
 * root): the outer radius from hpi_iab_cbrt_near, started a first-order step from ro0, so
 * the same bits except within ~1e-7 ulp of a rounding midpoint of that radius, for less
 * latency. Any ri0, ro0 are safe (NAN or far off: the full cube root). */
hp_error hpi_iab_s_pressure_slope_near(const hp_iab_s *s, double ri, double ri0, double ro0,
                                       double *P, double *ro, double *d1);
hp_error hpi_iab_s_pressure_ro_near(const hp_iab_s *s, double ri, double ri0, double ro0, double *P,
                                    double *ro);

/* hp_iab_fk_limit with a start for its safeguarded Newton iteration: ri_guess [m] (a
 * nearby answer; NAN or outside the bracket: the bracket's midpoint). The same root to
 * rounding whatever the guess. */
hp_error hpi_iab_fk_limit_warm(const hp_iab *b, const hp_iab_limit *lp, double P, double ri_guess,
                               double *ri);

/* hpi_iab_fk_limit_warm, then hp_iab_ro of its root: the same codes and the same bits of *ri
 * and *ro as the two calls, with the bladder validated once. When the guess is the root
 * (the planner's round trip of its own answer), the outer radius is the one the pressure's
 * evaluation at the guess already formed, so the pair costs one evaluation of the IK. */
hp_error hpi_iab_fk_limit_warm_ro(const hp_iab *b, const hp_iab_limit *lp, double P,
                                  double ri_guess, double *ri, double *ro);
/* hpi_iab_fk_limit_warm on a bladder already validated into s: the same codes after the
 * validation, the same bits. */
hp_error hpi_iab_s_fk_limit_warm(const hp_iab_s *s, const hp_iab_limit *lp, double P,
                                 double ri_guess, double *ri);
/* The same on a bladder already validated into s (hpi_iab_scaled_init): the same codes after
 * the validation, the same bits. */
hp_error hpi_iab_s_fk_limit_warm_ro(const hp_iab_s *s, const hp_iab_limit *lp, double P,
                                    double ri_guess, double *ri, double *ro);

/* A start for the bladder FK's Newton iteration: the radius ri [m]; with slope set, the
 * caller's evaluation there too: the pressure p, the slope d (dP/dri per scaled length, as
 * hpi_iab_s_slopes gives it) and the outer radius ro [m], which the FK then does not form
 * again when exact: p is the closed form's bits at ri (hpi_iab_s_pressure_ro's). Without
 * exact, p is only near them (the pressure stated with a radius): the FK takes one Newton
 * step from ri with p and d, and starts there as from a radius alone. */
typedef struct hpi_iab_fk_start {
    double ri, p, d, ro;
    int slope, exact;
    /* 1: a root within an ulp or two will do (the Newton iteration's last point, without
     * the look at the double next to it). */
    int loose;
    /* > 0: the closed form's pressure at twice Ri (hpi_iab_s_ik's bits at scaled 2·Ri, a
     * constant of the bladder the caller keeps), which the FK's search for an upper end of
     * a bladder without a limit point probes first: taken, not evaluated again. Else (0)
     * evaluated there when the search needs it. */
    double p_2ri;
} hpi_iab_fk_start;

/* A root with what its iteration formed: ri [m]; ro [m] and p, the outer radius and the
 * pressure (the closed form's bits) at ri when an evaluation there formed them, else NAN; d
 * the slope (per scaled length) of the last Newton step, a few ulps from ri, else NAN; ri2,
 * ro2, p2 the same of the other double the iteration's last look evaluated beside ri (ri2
 * NAN when none: a caller stepping off the root by an ulp need not evaluate it again);
 * evals the closed-form pressure evaluations spent (set on failure too). */
typedef struct hpi_iab_fk_out {
    double ri, ro, p, d;
    double ri2, ro2, p2;
    int evals;
} hpi_iab_fk_out;

/* hpi_iab_s_fk_limit_warm from a start st (NULL: none). The same root to rounding whatever
 * the start, the same codes. */
hp_error hpi_iab_s_fk_from(const hp_iab_s *s, const hp_iab_limit *lp, double P,
                           const hpi_iab_fk_start *st, hpi_iab_fk_out *o);
/* The root's outer radius [m] with hp_iab_ro's bits: o->ro when the FK formed it. */
hp_error hpi_iab_s_fk_ro(const hp_iab_s *s, const hpi_iab_fk_out *o, double *ro);

/* Gauss–Legendre rule of n points on [-1, 1] (1 <= n <= HP_IAB_GL_MAX): nodes x[k] >= 0 and
 * weights w[k] for k < (n + 1)/2 (the rule is symmetric; x[k] = 0 only for the middle node
 * of an odd rule). Computed by Newton's method on the Legendre recurrence; no allocation. */
#define HP_IAB_GL_MAX 64
hp_error hpi_iab_gl_rule(int n, double *x, double *w);
/* The same rule from a table filled once per process (thread-safe); the pointers stay valid
 * for the life of the process. */
hp_error hpi_iab_gl_cached(int n, const double **x, const double **w);

/* The Gauss–Kronrod 7–15 tables: x[0..7] Kronrod nodes >= 0 (descending, x[7] = 0), wk[0..7]
 * their weights, wg[0..3] the weights of the embedded Gauss rule on x[1], x[3], x[5], x[7]. */
void hpi_iab_gk15_rule(const double **x, const double **wk, const double **wg);

#endif
