/* The inflation limit point and forward kinematics (pressure -> inner radius). */
#include "iab/iab_internal.h"
#include "common/next_double.h"

#include <float.h>
#include <math.h>

/* Scan grid for the limit point: geometric in λi from 1 to HP_LP_SPAN·max(1, Ro/Ri). The
 * first maximum of P lies where the C1 part of P peaks (any C2 > 0 only delays it); for a
 * neo-Hookean shell that is λi ≈ 1.38 (thin) up to about 1.7·Ro/Ri (thick), well inside. */
#define HP_LP_SPAN 64.0
#define HP_LP_GRID 1024

static double dP(const hp_iab_s *s, double ri)
{
    double p, d1;
    if (hpi_iab_s_ik(s, ri, &p, &d1, NULL) != HP_OK) return NAN;
    return d1;
}

/* Bisects to adjacent doubles for the sign change of dP/dri in [lo, hi], dP(lo) > 0 >= dP(hi).
 * Bisection rather than Newton: dP/dri is known to its rounding level only, and bisection
 * lands where its computed sign changes, whatever its slope. */
static double bisect_dp(const hp_iab_s *s, double lo, double hi)
{
    for (int it = 0; it < 200; ++it) {
        double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi)) break;
        if (dP(s, mid) > 0) lo = mid;
        else hi = mid;
    }
    return lo;
}

/* Minimum of dP/dri on [lo, hi] by golden-section search: the point and the value. */
static double golden_min_dp(const hp_iab_s *s, double lo, double hi, double *at)
{
    const double g = 0.6180339887498949;
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = dP(s, x1), f2 = dP(s, x2);
    for (int it = 0; it < 120 && hi - lo > 4.0 * DBL_EPSILON * hi; ++it) {
        if (f1 < f2) {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - g * (hi - lo);
            f1 = dP(s, x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + g * (hi - lo);
            f2 = dP(s, x2);
        }
    }
    *at = f1 < f2 ? x1 : x2;
    return f1 < f2 ? f1 : f2;
}

/* The limit point in scaled units: *ri_lp = +inf when none. */
static hp_error limit_scaled(const hp_iab_s *s, double *ri_lp, double *p_lp)
{
    double top = HP_LP_SPAN * fmax(1.0, s->Ro / s->Ri);
    double ratio = pow(top, 1.0 / HP_LP_GRID);
    double prev_r = s->Ri, prev_d = dP(s, s->Ri), pprev_d = INFINITY;
    if (!(prev_d > 0)) return HP_ERR_DOMAIN; /* cannot happen for a valid bladder */
    for (int k = 1; k <= HP_LP_GRID; ++k) {
        double r = s->Ri * pow(ratio, k);
        double d = dP(s, r);
        if (isnan(d)) return HP_ERR_DOMAIN;
        if (!(d > 0)) {
            double r_lp = bisect_dp(s, prev_r, r);
            *ri_lp = r_lp;
            return hpi_iab_s_ik(s, r_lp, p_lp, NULL, NULL);
        }
        /* A local minimum of dP/dri at the previous grid point: the slope may dip below zero
         * and recover between grid points (C2/C1 just below the threshold for a limit
         * point). Search the two cells around it. */
        if (prev_d < pprev_d && prev_d <= d && k >= 2) {
            double lo = s->Ri * pow(ratio, k - 2), at;
            if (!(golden_min_dp(s, lo, r, &at) > 0)) {
                double r_lp = bisect_dp(s, lo, at);
                *ri_lp = r_lp;
                return hpi_iab_s_ik(s, r_lp, p_lp, NULL, NULL);
            }
        }
        pprev_d = prev_d;
        prev_d = d;
        prev_r = r;
    }
    *ri_lp = INFINITY;
    *p_lp = INFINITY;
    return HP_OK;
}

hp_error hp_iab_limit_point(const hp_iab *b, hp_iab_limit *lp)
{
    if (!lp) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    hp_error e = hpi_iab_scaled_init(b, &s, NULL);
    double r, p;
    if (e == HP_OK) e = limit_scaled(&s, &r, &p);
    if (e != HP_OK) return e;
    lp->exists = isfinite(r);
    lp->lambda_i = lp->exists ? r / s.Ri : INFINITY;
    lp->ri = lp->exists ? r / s.scale : INFINITY;
    lp->pressure = p;
    return HP_OK;
}

/* A root as the iteration leaves it: ri (scaled inside solve_bracket, metres from
 * fk_scaled), the scaled outer radius and the pressure the last evaluation there formed
 * (NAN when none did), the slope of the last Newton step (a few ulps from the root), and
 * the closed-form pressure evaluations spent; ri2, ro2, p2 the same of the other double the
 * last look evaluated next to the root (ri2 NAN when none). */
typedef struct fk_root {
    double ri, ro, p, d;
    double ri2, ro2, p2;
    int evals;
} fk_root;

/* The last look of solve_bracket: candidate xs evaluated (pressure p, outer radius ro) after
 * x (px, rox): the better of the two for target replaces best if it is better, and o keeps
 * the other as the root's neighbour (a caller moving off the root by an ulp has it). */
static void last_look(double target, double x, double px, double rox, double xs, double ps,
                      double ros, double *best, double *best_p, double *best_ro,
                      const double *best_f, fk_root *o)
{
    if (fabs(ps - target) < *best_f) {
        *best = xs;
        *best_p = ps;
        *best_ro = ros;
    }
    int x_best = *best == x;
    o->ri2 = x_best ? xs : x;
    o->p2 = x_best ? ps : px;
    o->ro2 = x_best ? ros : rox;
}

/* Safeguarded Newton on P(ri) = target inside [lo, hi] with P(lo) < target < P(hi): every
 * iterate stays strictly inside the bracket, which shrinks at every step; a Newton step that
 * leaves it or fails to halve the step before last is replaced by bisection. o gets the root
 * (scaled), the pressure and outer radius evaluated there, the last slope and the number of
 * evaluations. */
static hp_error solve_bracket(const hp_iab_s *s, double target, double lo, double hi, double guess,
                              const double at_guess[3], int loose, fk_root *o)
{
    /* A guess inside the bracket (a nearby answer) saves most steps; the bracket and the
     * bisection fallback make any start safe. */
    int start_known = guess >= lo && guess <= hi && at_guess;
    double x = guess > lo && guess < hi ? guess : 0.5 * (lo + hi);
    if (start_known) x = guess; /* an end of the bracket when its pressure made it one */
    double dx_old = hi - lo, dx = dx_old;
    /* The outer radius of each evaluation is kept with it (hpi_iab_s_ik forms it for the
     * pressure): the caller gets the root's without another cube root. */
    double best = x, best_f = INFINITY, best_ro = NAN, best_p = NAN, ro = NAN, x_ro = NAN;
    int newton = 0; /* x is a short Newton step from x_ro, whose outer radius ro is */
    for (int it = 0; it < 300; ++it) {
        double p, d;
        /* The first step at the guess: its pressure, slope and outer radius when the caller
         * formed them (hpi_iab_s_ik's bits), else evaluated here; a Newton step's outer
         * radius from the last one's (hpi_iab_cbrt_near: the same bits but within ~1e-7 ulp
         * of a midpoint, a third of the cube root's latency). */
        if (it == 0 && start_known) {
            p = at_guess[0];
            d = at_guess[1];
            ro = at_guess[2];
        } else if (++o->evals, (newton ? hpi_iab_s_pressure_slope_near(s, x, x_ro, ro, &p, &ro, &d)
                                       : hpi_iab_s_pressure_slope(s, x, &p, &ro, &d)) != HP_OK) {
            return HP_ERR_DOMAIN;
        }
        x_ro = x;
        o->d = d;
        double f = p - target;
        if (fabs(f) < best_f) {
            best_f = fabs(f);
            best = x;
            best_ro = ro;
            best_p = p;
        }
        if (f == 0) break;
        if (f < 0) lo = x;
        else hi = x;
        /* A Newton correction below the rounding of x: x is the root to rounding. Without
         * this stop a Newton iteration that converged from one side (P is concave on most
         * of the stable branch, so it does) had its last, sub-ulp step rejected as not
         * inside the bracket, and ~45 bisection steps then closed the bracket's far side
         * to its last ulps. The neighbour on the root's side (P increases with ri) is
         * looked at instead: the bisection ended on the two doubles around the root, the
         * same candidates. */
        if (d > 0 && fabs(f / d) <= 0.5 * DBL_EPSILON * x) {
            if (loose) break; /* x is the root to rounding; its neighbour not looked at */
            double xs = f < 0 ? hpi_next_up(x) : hpi_next_down(x), ps, ros;
            ++o->evals;
            if (hpi_iab_s_pressure_ro_near(s, xs, x, ro, &ps, &ros) == HP_OK)
                last_look(target, x, p, ro, xs, ps, ros, &best, &best_p, &best_ro, &best_f, o);
            break;
        }
        if (!(hi - lo > 2.0 * DBL_EPSILON * hi)) break;
        double xn = x - f / d;
        if (d > 0 && xn > lo && xn < hi && fabs(2.0 * (xn - x)) < fabs(dx_old)) {
            dx_old = dx;
            dx = xn - x;
            if (fabs(dx) <= DBL_EPSILON * x) { /* converged: one last look at xn */
                if (loose) break;              /* x, an ulp or two from the root */
                double pn, ron;
                ++o->evals;
                if (hpi_iab_s_pressure_ro_near(s, xn, x, ro, &pn, &ron) == HP_OK)
                    last_look(target, x, p, ro, xn, pn, ron, &best, &best_p, &best_ro, &best_f, o);
                break;
            }
            x = xn;
            /* Within 1e-7 of the last: a first-order start of its outer radius is within
             * ~1e-14, inside hpi_iab_cbrt_near's 2^-40 (a longer step: the full root). */
            newton = fabs(dx) <= 1e-7 * x;
        } else {
            dx_old = dx;
            dx = 0.5 * (hi - lo);
            x = lo + dx;
            newton = 0;
            if (!(x > lo && x < hi)) break;
        }
    }
    o->ri = best;
    o->ro = best_ro;
    o->p = best_p;
    return HP_OK;
}

/* The root of P on the stable branch into o (o->ri in metres, the rest as fk_root says).
 * The start st (may be NULL, or st->ri NAN: none) is taken when it lies on the stable
 * branch's side of Ri and below the limit point: st->exact, its pressure is the closed
 * form's bits there (then a start whose pressure is P is the root at once); with st->slope
 * its pressure, slope and outer radius are not evaluated again. A start only changes the
 * steps: the bracket and the bisection fallback make the iteration safe from any; its
 * p_2ri only the evaluations (the same bits as evaluating 2·Ri). */
static hp_error fk_scaled(const hp_iab_s *sp, double r_lp, double p_lp, double P,
                          const hpi_iab_fk_start *st, fk_root *o)
{
    const hp_iab_s s = *sp;
    hp_error e;
    o->ro = o->p = o->d = o->ri2 = o->ro2 = o->p2 = NAN;
    o->evals = 0;
    if (!isfinite(P)) return HP_ERR_INVALID;
    if (P == 0) {
        o->ri = s.Ri_m;
        return HP_OK;
    }
    double lo, hi, p;
    if (P > 0 && P >= p_lp) return HP_ERR_NO_STABLE;
    /* A guess on the right side of Ri and below the limit point whose pressure is exactly P
     * (the usual case when it is the radius the pressure came from) is what the search
     * below would return: P is strictly increasing on the stable branch, so the guess lies
     * strictly inside the bracket found there and the safeguarded Newton iteration, which
     * starts at it, stops at once. */
    double g = st ? st->ri * s.scale : NAN;
    double rg, at_g[3];
    int g_known = 0, g_exact = st && st->exact && st->slope, g_has_p = 0;
#define FK_ON_BRANCH(x) (P > 0 ? (x) > s.Ri && (x) < r_lp : (x) > 0 && (x) < s.Ri)
    if (st && st->slope && !st->exact && FK_ON_BRANCH(g) && st->d > 0 && isfinite(st->d)) {
        /* A pressure near the closed form's at the start (the previous answer's, for a
         * reading): one Newton step from it, then the start is evaluated there as any. */
        double g1 = g - (st->p - P) / st->d;
        if (FK_ON_BRANCH(g1)) g = g1;
    }
    if (FK_ON_BRANCH(g)) {
        if (g_exact) {
            /* The caller's evaluation at the start (a memo of the last root near here): no
             * second one. */
            at_g[0] = st->p;
            at_g[1] = st->d;
            at_g[2] = st->ro * s.scale;
            g_has_p = isfinite(at_g[0]) && at_g[2] > 0;
            g_known = g_has_p && st->d > 0 && isfinite(st->d);
            p = at_g[0];
            rg = at_g[2];
        } else {
            /* A reading near the guess (a measured pressure): the Newton iteration below
             * starts at the guess with this pressure and its slope, not a second evaluation
             * there. A slope the model cannot form leaves the pressure (the fallback's,
             * the same bits) without it. */
            ++o->evals;
            int slope = hpi_iab_s_pressure_slope(&s, g, &p, &rg, &at_g[1]) == HP_OK;
            if (slope || hpi_iab_s_pressure_ro(&s, g, &p, &rg) == HP_OK) {
                at_g[0] = p;
                at_g[2] = rg;
                g_exact = g_has_p = 1;
                g_known = slope;
            }
        }
#undef FK_ON_BRANCH
        if (g_has_p && g_exact && p == P) {
            o->ri = g * s.inv_scale;
            o->ro = rg;
            o->p = p;
            o->d = g_known ? at_g[1] : NAN;
            return HP_OK;
        }
    }
    /* A start whose pressure is the closed form's is one end of the bracket: no search. */
    int below = g_has_p && g_exact && p < P, above = g_has_p && g_exact && p > P;
    if (P > 0) {
        lo = s.Ri;
        if (isfinite(r_lp)) {
            /* P at r_lp is p_lp > P (the caller's limit point, computed there by the same
             * hpi_iab_s_ik): r_lp is the upper end, with no evaluation. */
            hi = r_lp;
        } else if (above) {
            hi = g;
        } else {
            /* No limit point: P grows without bound (like 2C2(1 − Ri/Ro)λi), so doubling
             * finds an upper end, or leaves the range of the model. */
            hi = 2.0 * s.Ri;
            for (int probe = 0;; ++probe) {
                if (probe == 0 && st && st->p_2ri > 0) {
                    p = st->p_2ri; /* the caller's evaluation at 2·Ri: the same bits */
                } else {
                    ++o->evals;
                    if (hpi_iab_s_ik(&s, hi, &p, NULL, NULL) != HP_OK || hi > 1e30)
                        return HP_ERR_DOMAIN;
                }
                if (p >= P) break;
                lo = hi;
                hi *= 2.0;
            }
            if (p == P) {
                o->ri = hi / s.scale;
                return HP_OK;
            }
        }
        if (below && g > lo) lo = g;
        if (above && g < hi) hi = g;
    } else if (below || above) {
        /* Compression from a start: P → −∞ as ri → 0, so 0 is a lower end too (never
         * evaluated: the iteration stays strictly inside). */
        lo = below ? g : 0.0;
        hi = below ? s.Ri : g;
    } else {
        /* Compression: P → −∞ as ri → 0, so halving finds a lower end. */
        hi = s.Ri;
        lo = 0.5 * s.Ri;
        for (;;) {
            ++o->evals;
            if (lo < 1e-30 || hpi_iab_s_ik(&s, lo, &p, NULL, NULL) != HP_OK) return HP_ERR_DOMAIN;
            if (p <= P) break;
            hi = lo;
            lo *= 0.5;
        }
        if (p == P) {
            o->ri = lo / s.scale;
            return HP_OK;
        }
    }
    fk_root r = *o;
    e = solve_bracket(&s, P, lo, hi, g, g_known ? at_g : NULL, st && st->loose, &r);
    o->evals = r.evals;
    if (e != HP_OK) return e;
    o->ri = r.ri * s.inv_scale;
    o->ro = r.ro;
    o->p = r.p;
    o->d = r.d;
    o->ri2 = r.ri2 * s.inv_scale;
    o->ro2 = r.ro2;
    o->p2 = r.p2;
    return HP_OK;
}

hp_error hp_iab_fk(const hp_iab *b, double P, double *ri)
{
    if (!ri) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    hp_error e = hpi_iab_scaled_init(b, &s, NULL);
    if (e != HP_OK) return e;
    if (!isfinite(P)) return HP_ERR_INVALID;
    double r_lp = INFINITY, p_lp = INFINITY;
    if (P > 0 && (e = limit_scaled(&s, &r_lp, &p_lp)) != HP_OK) return e;
    fk_root o;
    e = fk_scaled(&s, r_lp, p_lp, P, NULL, &o);
    if (e == HP_OK) *ri = o.ri;
    return e;
}

hp_error hp_iab_fk_limit(const hp_iab *b, const hp_iab_limit *lp, double P, double *ri)
{
    return hpi_iab_fk_limit_warm(b, lp, P, NAN, ri);
}

/* The limit point of hpi_iab_fk_limit_warm in scaled units, checked against the bladder. */
static hp_error limit_init(const hp_iab_s *s, const hp_iab_limit *lp, double P, double *r_lp,
                           double *p_lp)
{
    if (!isfinite(P)) return HP_ERR_INVALID;
    *r_lp = lp->exists ? lp->ri * s->scale : INFINITY;
    *p_lp = lp->exists ? lp->pressure : INFINITY;
    if (lp->exists && !(*r_lp > s->Ri && isfinite(*p_lp))) return HP_ERR_INVALID;
    return HP_OK;
}

/* A start at ri_guess [m] alone (NAN: none): its pressure evaluated there. */
static const hpi_iab_fk_start *start_at(double ri_guess, hpi_iab_fk_start *st)
{
    *st = (hpi_iab_fk_start){.ri = ri_guess};
    return isnan(ri_guess) ? NULL : st;
}

hp_error hpi_iab_fk_limit_warm(const hp_iab *b, const hp_iab_limit *lp, double P, double ri_guess,
                               double *ri)
{
    if (!ri || !lp) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    hp_error e = hpi_iab_scaled_init(b, &s, NULL);
    return e != HP_OK ? e : hpi_iab_s_fk_limit_warm(&s, lp, P, ri_guess, ri);
}

hp_error hpi_iab_s_fk_limit_warm(const hp_iab_s *s, const hp_iab_limit *lp, double P,
                                 double ri_guess, double *ri)
{
    if (!ri || !lp) return HP_ERR_NULL;
    hpi_iab_fk_start st;
    hpi_iab_fk_out o;
    hp_error e = hpi_iab_s_fk_from(s, lp, P, start_at(ri_guess, &st), &o);
    if (e == HP_OK) *ri = o.ri;
    return e;
}

hp_error hpi_iab_s_fk_from(const hp_iab_s *s, const hp_iab_limit *lp, double P,
                           const hpi_iab_fk_start *st, hpi_iab_fk_out *out)
{
    if (!out || !lp) return HP_ERR_NULL;
    double r_lp, p_lp;
    fk_root o = {0};
    hp_error e = limit_init(s, lp, P, &r_lp, &p_lp);
    if (e == HP_OK) e = fk_scaled(s, r_lp, p_lp, P, st, &o);
    out->evals = o.evals;
    if (e != HP_OK) return e;
    out->ri = o.ri;
    out->ro = o.ro * s->inv_scale; /* exact: a power of two */
    out->p = o.p;
    out->d = o.d;
    out->ri2 = o.ri2;
    out->ro2 = o.ro2 * s->inv_scale;
    out->p2 = o.p2;
    return HP_OK;
}

hp_error hpi_iab_s_fk_limit_warm_ro(const hp_iab_s *s, const hp_iab_limit *lp, double P,
                                    double ri_guess, double *ri, double *ro)
{
    if (!ri || !ro || !lp) return HP_ERR_NULL;
    hpi_iab_fk_start st;
    hpi_iab_fk_out o;
    hp_error e = hpi_iab_s_fk_from(s, lp, P, start_at(ri_guess, &st), &o);
    if (e == HP_OK) e = hpi_iab_s_fk_ro(s, &o, ro);
    if (e == HP_OK) *ri = o.ri;
    return e;
}

hp_error hpi_iab_s_fk_ro(const hp_iab_s *s, const hpi_iab_fk_out *o, double *ro)
{
    /* hp_iab_ro(b, r) scales r back to the same g (a power of two, both ways exact) and
     * checks its range; whenever that is not plainly so, it is asked. */
    double rs = o->ri * s->scale;
    if (isfinite(o->ro) && rs >= 1e-30 && rs <= 1e30) {
        *ro = o->ro;
        return HP_OK;
    }
    return hpi_iab_s_ro_m(s, o->ri, ro);
}

hp_error hpi_iab_fk_limit_warm_ro(const hp_iab *b, const hp_iab_limit *lp, double P,
                                  double ri_guess, double *ri, double *ro)
{
    if (!ri || !ro || !lp) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    hp_error e = hpi_iab_scaled_init(b, &s, NULL);
    return e != HP_OK ? e : hpi_iab_s_fk_limit_warm_ro(&s, lp, P, ri_guess, ri, ro);
}
