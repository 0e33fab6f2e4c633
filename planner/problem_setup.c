/* Limits as radius bounds, commanded directions, scaled contact evaluation. */
#include "planner/problem_setup.h"
#include "common/exact_prod.h"
#include "common/minmax.h"
#include "common/test_count.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

static atomic_ulong rate_solves, rate_evals, rate_lazy_setups, rate_resolves, rate_rederived,
    rate_windows, rate_stands_new;
static atomic_int rate_eager;

unsigned long hpi_test_rate_bound_solves(void) { return atomic_load(&rate_solves); }
unsigned long hpi_test_rate_bound_evals(void) { return atomic_load(&rate_evals); }
unsigned long hpi_test_rate_lazy_setups(void) { return atomic_load(&rate_lazy_setups); }
unsigned long hpi_test_rate_resolves(void) { return atomic_load(&rate_resolves); }
unsigned long hpi_test_rate_rederived(void) { return atomic_load(&rate_rederived); }
unsigned long hpi_test_rate_windows(void) { return atomic_load(&rate_windows); }
unsigned long hpi_test_rate_stands_new(void) { return atomic_load(&rate_stands_new); }
void hpi_test_rate_lazy(int on) { atomic_store(&rate_eager, !on); }
int hpi_setup_rate_lazy(void) { return !atomic_load_explicit(&rate_eager, memory_order_relaxed); }

/* Moves ri up (up) or down until its pressure is >= p (up) or <= p; FK roots sit within a
 * few ulps of the exact radius, so a few widening steps always suffice. The bladder as
 * validated once (hpi_iab_s_ik_m: the bits of hp_iab_ik). p0: the pressure at *ri when the
 * caller has it (those bits; NAN: evaluated here), ro0 the outer radius there (NAN: not
 * known); nb (may be NULL) another radius the caller evaluated (the root find's look at the
 * double beside its root, hpi_iab_fk_out.ri2), taken when a step lands on it. A step too
 * small to move the radius (1e-16 of it, below half an ulp when its mantissa is below
 * 1.11) keeps the last look's pressure. Either way the pressures are the bits an
 * evaluation there gives: the same moved radius as evaluating each step. On success *ro
 * gets the outer radius at the moved ri [m] (hp_iab_ro's bits) when ro is not NULL, and
 * *p_at the pressure there (those bits; p_at may be NULL). *evals counts the evaluations.
 * Returns 0 when it could not. */
static int nudge_n(const hp_iab_s *s, double *ri, double p, int up, double p0, double ro0,
                   const hpi_iab_fk_out *nb, double *p_at, double *ro, int *evals)
{
    double r = *ri, step = fabs(r) * 1e-16, last = r, P = p0, o = ro0;
    double r2 = nb ? nb->ri2 : NAN; /* NAN: equal to no radius */
    for (int i = 0; i < 80; ++i) {
        if (r == r2) {
            P = nb->p2;
            o = nb->ro2;
        } else if (i > 0 ? r != last : isnan(p0)) {
            ++*evals;
            if (hpi_iab_s_ik_ro_m(s, r, &P, &o) != HP_OK) P = NAN;
        }
        last = r;
        if (up ? P >= p : P <= p) {
            *ri = r;
            if (p_at) *p_at = P;
            return !ro || !isnan(*ro = o) || hpi_iab_s_ro_m(s, r, ro) == HP_OK;
        }
        r += up ? step : -step;
        step *= 2.0;
    }
    return 0;
}

static int nudge(const hp_iab_s *s, double *ri, double p, int up)
{
    int evals = 0;
    return nudge_n(s, ri, p, up, NAN, NAN, NULL, NULL, NULL, &evals);
}

/* The largest dP/dro [Pa/m] of a bladder over [lo, hi] (m), twice the largest of 257 even
 * samples (the slope is smooth there and varies by a small factor across the interval: the
 * factor 2 covers what falls between samples). dP/dro = dP/dri · ri²/ro² (ro³ − ri³ is
 * constant). NAN when the model fails at a sample. */
static double slope_max(const hp_iab_s *s, double lo, double hi)
{
    double m = 0.0;
    for (int i = 0; i <= 256; ++i) {
        double ri = (lo + (hi - lo) * i / 256.0) * s->scale, P, d1;
        if (hpi_iab_s_ik(s, ri, &P, &d1, NULL) != HP_OK) return NAN;
        double ro = hpi_iab_s_ro(s, ri);
        m = fmax(m, d1 * s->scale * (ri * ri) / (ro * ro));
    }
    return 2.0 * m;
}

/* The knots of bladder k (hp_static_bounds.knot_*): HP_RATE_KNOTS points whose pressures
 * are spread evenly over [p_lo, p_hi] (the static interval's ends ri_lo, ri_hi, and the FK
 * roots of the evenly spaced pressures between them), each with its inner and outer radius,
 * the closed form's pressure there (the bits hpi_iab_s_ik_ro_m gives: a knot is an
 * evaluated point, not an estimate) and its slope dP/dri (per scaled length, hpi_iab_s_slopes).
 * Even in pressure, not in radius: the pressure's slope varies fivefold over the interval,
 * and even radii left 770 Pa between the low knots, wider than half a 1 kPa window, so a
 * window there had no knot inside and both its ends were solved at once (the plans that
 * made the loop benchmark's p99.9). 0 when the model fails at one or the pressures or radii
 * do not rise (then no stand-in or start is made from them). */
static int rate_knots(const hp_iab_s *s, const hp_iab_limit *lp, const hp_envelope *env,
                      hp_static_bounds *b, int k)
{
    double p2;
    b->p_2ri[k] = hpi_iab_s_ik(s, 2.0 * s->Ri, &p2, NULL, NULL) == HP_OK && p2 > 0 ? p2 : 0.0;
    b->knot_dp[k] = INFINITY; /* no knots: a remembered bound is near wherever it lies */
    for (int i = 0; i < HP_RATE_KNOTS; ++i) {
        double ri = i == 0 ? env->ri_lo : env->ri_hi, ro, P, d, d2;
        if (i > 0 && i < HP_RATE_KNOTS - 1) {
            double t = env->p_lo + (env->p_hi - env->p_lo) * i / (HP_RATE_KNOTS - 1.0);
            hpi_iab_fk_out o;
            if (hpi_iab_s_fk_from(s, lp, t, NULL, &o) != HP_OK) return 0;
            ri = o.ri;
        }
        if (hpi_iab_s_ik_ro_m(s, ri, &P, &ro) != HP_OK ||
            hpi_iab_s_slopes(s, ri * s->scale, ro * s->scale, &d, &d2) != HP_OK || !isfinite(P) ||
            !isfinite(ro) || !(d > 0 && isfinite(d)) || !isfinite(d2) ||
            (i > 0 &&
             !(P > b->knot_p[k][i - 1] && ro > b->knot_ro[k][i - 1] && ri > b->knot_ri[k][i - 1])))
            return 0;
        b->knot_ri[k][i] = ri;
        b->knot_ro[k][i] = ro;
        b->knot_p[k][i] = P;
        b->knot_d[k][i] = d;
        b->knot_d2[k][i] = d2;
    }
    b->knot_dp[k] = (b->knot_p[k][HP_RATE_KNOTS - 1] - b->knot_p[k][0]) / (HP_RATE_KNOTS - 1);
    return 1;
}

/* The knot interval of pressure p on bladder k: j in 0..HP_RATE_KNOTS − 2 with knot_p[j] <=
 * p <= knot_p[j + 1] when p lies within the knots (else the first or the last interval).
 * The knots' pressures are nearly even (knot_dp apart): the index from p, then a step or
 * two, not a search. */
static int knot_index(const hp_static_bounds *b, int k, double p)
{
    const double *kp = b->knot_p[k];
    double u = (p - kp[0]) / b->knot_dp[k];
    int j = u > 0 ? (u < HP_RATE_KNOTS - 2 ? (int)u : HP_RATE_KNOTS - 2) : 0;
    while (j > 0 && kp[j] > p) --j;
    while (j < HP_RATE_KNOTS - 2 && kp[j + 1] < p) ++j;
    return j;
}

/* A start for the root find of pressure pw on bladder k: the inner radius [m] the quintic
 * Hermite interpolant of ri(P) through the two knots around pw gives (their radii, slopes
 * dri/dP = 1/P' and curvatures d²ri/dP² = −P''/P'³), written as the left knot's radius plus
 * a correction so that its rounding is the correction's. Over the default scene's knots it
 * lies within 2e-10 of the radius (the cubic through radii and slopes alone: 9e-8), so one
 * Newton step from it reaches the root to rounding and the root find evaluates three
 * times: the start, the Newton point, the double beside it (the cubic's starts took a
 * second Newton step on the step trace's slowest plans: 4.5 evaluations an end). NAN when
 * pw lies outside the knots (or they failed): the root find then starts without it. Only a
 * start: the root is the FK's whatever the guess. */
double hpi_setup_knot_guess(const hp_static_bounds *b, int k, double pw)
{
    const double *kp = b->knot_p[k];
    if (!b->knots_ok[k] || !(pw >= kp[0] && pw <= kp[HP_RATE_KNOTS - 1])) return NAN;
    int j = knot_index(b, k, pw);
    double h = kp[j + 1] - kp[j], t = (pw - kp[j]) / h, sc = b->iab_s[k].scale;
    /* P' and P'' per metre; h times dri/dP and h² times d²ri/dP² at the two knots */
    double s0 = b->knot_d[k][j] * sc, s1 = b->knot_d[k][j + 1] * sc;
    double c0 = b->knot_d2[k][j] * sc * sc, c1 = b->knot_d2[k][j + 1] * sc * sc;
    double v0 = h / s0, v1 = h / s1;
    double a0 = -(v0 * v0 * v0) * c0 / h, a1 = -(v1 * v1 * v1) * c1 / h;
    double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
    double r0 = b->knot_ri[k][j], dr = b->knot_ri[k][j + 1] - r0;
    return r0 +
           ((10.0 * t3 - 15.0 * t4 + 6.0 * t5) * dr + (t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5) * v0 +
            (-4.0 * t3 + 7.0 * t4 - 3.0 * t5) * v1 + 0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5) * a0 +
            0.5 * (t3 - 2.0 * t4 + t5) * a1);
}

/* Tightest of two bounds with their flags; equal bounds keep both flags. */
static void take_max(double *v, unsigned *f, double cand, unsigned cf)
{
    if (cand > *v) {
        *v = cand;
        *f = cf;
    } else if (cand == *v) {
        *f |= cf;
    }
}

static void take_min(double *v, unsigned *f, double cand, unsigned cf)
{
    if (cand < *v) {
        *v = cand;
        *f = cf;
    } else if (cand == *v) {
        *f |= cf;
    }
}

hp_error hpi_bladder_envelope(const hp_bladder *B, hp_envelope *out, hp_diag *d)
{
    if (!B || !out) return hp_diag_set(d, HP_ERR_NULL, "bladder or envelope is NULL");
    const hp_iab *m = &B->iab;
    hp_iab_limit lp;
    hp_iab_s s = {0};
    hp_error e = hp_iab_limit_point(m, &lp);
    if (e == HP_OK) e = hpi_iab_scaled_init(m, &s, NULL);
    if (e != HP_OK)
        return hp_diag_set(d, e, "bladder %s: limit point: %s", B->name, hp_error_message(e));
    /* The stretch limits as radii that keep them in exact arithmetic (the rounded
     * product can lie an ulp outside): every backend's answer is clamped into these. */
    double lo = hpi_prod_up(B->stretch_min, m->Ri);
    double hi = hpi_prod_down(B->stretch_max, m->Ri);
    unsigned lof = HP_BIND_STRETCH_MIN, hif = HP_BIND_STRETCH_MAX;
    if (lp.exists) take_min(&hi, &hif, lp.ri * (1.0 - HP_STABLE_MARGIN), HP_BIND_LIMIT_POINT);
    double rs; /* the hoop-stress limit as a radius bound (monotone: iab/iab_stress.c) */
    if (B->stress_max > 0 && isfinite(B->stress_max) && hi > m->Ri &&
        hp_iab_stress_radius(m, B->stress_max, hi, &rs) == HP_OK)
        take_min(&hi, &hif, rs, HP_BIND_STRESS_MAX);

    double r;
    e = hp_iab_fk(m, B->p_min, &r);
    if (e != HP_OK)
        return hp_diag_set(d, HP_ERR_INVALID,
                           "bladder %s: pressure_min %.6g Pa has no stable radius (%s)", B->name,
                           B->p_min, hp_error_message(e));
    take_max(&lo, &lof, r, HP_BIND_PRESSURE_MIN);
    if (!lp.exists || B->p_max < lp.pressure) {
        e = hp_iab_fk(m, B->p_max, &r);
        if (e == HP_OK) take_min(&hi, &hif, r, HP_BIND_PRESSURE_MAX);
        else if (e != HP_ERR_NO_STABLE)
            return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: pressure_max %.6g Pa: %s", B->name,
                               B->p_max, hp_error_message(e));
    }
    /* FK roots are exact to a few ulps; make the pressure bounds hold exactly. */
    if ((lof & HP_BIND_PRESSURE_MIN) && !nudge(&s, &lo, B->p_min, 1))
        return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: pressure_min bound", B->name);
    if ((hif & HP_BIND_PRESSURE_MAX) && !nudge(&s, &hi, B->p_max, 0))
        return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: pressure_max bound", B->name);
    /* lo >= stretch_min · Ri exactly, so the reported stretch ri / Ri (the exact
     * quotient rounded, a monotone map) is >= stretch_min too; the same for hi. The
     * pressure nudges only moved the bounds inward. */
    double plo, phi;
    if (!(lo < hi) || lo / m->Ri < B->stretch_min || hi / m->Ri > B->stretch_max ||
        hp_iab_ik(m, lo, &plo) != HP_OK || hp_iab_ik(m, hi, &phi) != HP_OK)
        return hp_diag_set(d, HP_ERR_INVALID,
                           "bladder %s: the pressure and stretch limits leave no stable "
                           "radius (ri %.6g..%.6g mm)",
                           B->name, lo * HP_MM_PER_M, hi * HP_MM_PER_M);
    /* Pressures are returned clamped into [p_lo, p_hi] c [p_min, p_max]. */
    out->limit = lp;
    out->ri_lo = lo;
    out->ri_hi = hi;
    out->lo_flags = lof;
    out->hi_flags = hif;
    out->p_lo = plo > B->p_min ? plo : B->p_min;
    out->p_hi = phi < B->p_max ? phi : B->p_max;
    if (hp_iab_ro(m, lo, &out->ro_lo) != HP_OK) out->ro_lo = NAN;
    if (hp_iab_ro(m, hi, &out->ro_hi) != HP_OK) out->ro_hi = NAN;
    return HP_OK;
}

hp_error hpi_setup_static_bounds(const hp_layout *L, hp_static_bounds *b, hp_diag *d)
{
    if (!L || !b) return hp_diag_set(d, HP_ERR_NULL, "layout or bounds is NULL");
    for (int k = 0; k < L->n; ++k) {
        hp_envelope env;
        hp_error e = hpi_bladder_envelope(&L->bladders[k], &env, d);
        if (e == HP_OK) e = hpi_iab_scaled_init(&L->bladders[k].iab, &b->iab_s[k], NULL);
        if (e != HP_OK) return e;
        b->limit[k] = env.limit;
        b->ri_lo[k] = env.ri_lo;
        b->ri_hi[k] = env.ri_hi;
        b->lo_flags[k] = env.lo_flags;
        b->hi_flags[k] = env.hi_flags;
        b->p_lo[k] = env.p_lo;
        b->p_hi[k] = env.p_hi;
        b->ro_lo[k] = env.ro_lo;
        b->ro_hi[k] = env.ro_hi;
        b->rate_slack[k] = hpi_setup_rate_slack(slope_max(&b->iab_s[k], env.ri_lo, env.ri_hi));
        b->knots_ok[k] = rate_knots(&b->iab_s[k], &env.limit, &env, b, k);
    }
    return HP_OK;
}

/* 1 when m (may be NULL) holds the bound of a window end at pressure pw, bit for bit. */
static int memo_holds(const hp_rate_end *m, double pw)
{
    return m && m->ok && memcmp(&m->p, &pw, sizeof pw) == 0;
}

/* The radius bound of one rate window end at pressure pw (up: a lower bound, whose
 * pressure must be >= pw) and its outer radius, from the memo when it holds pw, else solved
 * and memoised. Returns 0 when no stable radius has it. */
static int rate_bound(const hp_static_bounds *b, int k, double pw, int up, hp_rate_memo *memo,
                      double *r, double *ro)
{
    hp_rate_end *m = memo ? (up ? &memo->down[k] : &memo->up[k]) : NULL;
    if (memo_holds(m, pw)) {
        *r = m->r;
        *ro = m->ro;
        return 1;
    }
    hpi_count(&rate_solves, 1);
    /* From the knots' interpolant (hpi_setup_knot_guess): one evaluation there, within 2e-10 of the
     * root, then one Newton step and the look at the double beside it. The last bound of
     * the same window end (the memo) is the start only where the knots give none: even a
     * sensor's noise of a few Pa away it took a Newton step more (on the seeded chains of
     * tests/planner/test_rate_bounds.c: 3.19 evaluations a solve from a memo within 20 Pa,
     * 2.89 from the knots; against the cubic interpolant of ri(P) the memo had paid). A
     * bound solved with a memo (a planner's) starts at the knots even the first time, where
     * it searched a bracket from nothing (9 evaluations; the step trace's first plans after
     * a jump solve several such ends). The same root to rounding either way (that test:
     * against the cold reference along such chains); without a memo
     * (hpi_setup_cycle_bounds) the cold root find's bits, which that test holds it to. */
    int held = m && m->ok;
    double g = m ? hpi_setup_knot_guess(b, k, pw) : NAN;
    /* A radius alone (the knots' guess, evaluated there; NAN: no start, as for none) */
    hpi_iab_fk_start st = {.ri = g};
    if (isnan(g) && held)
        st = (hpi_iab_fk_start){
            .ri = m->r, .p = m->p_at, .d = m->d, .ro = m->ro, .slope = 1, .exact = 1};
    /* A bladder without a limit point: the search for an upper end of a start below the
     * root probes 2·Ri first, evaluated once per layout instead (the same bits). */
    st.p_2ri = b->p_2ri[k];
    hpi_iab_fk_out o;
    int evals = 0;
    const hp_iab_s *s = &b->iab_s[k];
    hp_error e = hpi_iab_s_fk_from(s, &b->limit[k], pw, &st, &o);
    /* The nudge's first look is the root's own evaluation when the root find ended on one
     * (the same bits as evaluating it again). */
    *r = o.ri;
    double p_at = NAN;
    int found = e == HP_OK && nudge_n(s, r, pw, up, o.p, o.ro, &o, &p_at, ro, &evals);
    hpi_count(&rate_evals, (unsigned long)(o.evals + evals));
    if (!found) return 0;
    if (m) {
        m->p = pw;
        m->r = *r;
        m->ro = *ro;
        m->p_at = p_at; /* the nudge's last look: the closed form's bits at the bound */
        m->d = o.d;
        m->ok = 1;
    }
    return 1;
}

hp_error hpi_setup_cycle_bounds(const hp_layout *L, const hp_static_bounds *b, const double *p_prev,
                                int use_rate, hp_problem *pb, unsigned *lo_flags,
                                unsigned *hi_flags, hp_diag *d)
{
    return hpi_setup_cycle_bounds_memo(L, b, p_prev, use_rate, NULL, pb, lo_flags, hi_flags, d);
}

/* 1 when a point whose closed-form pressure is ps [Pa] serves as the stand-in of the window
 * end at pw (up: the lower end): beyond pw by the rate slack on the window's side, which
 * puts it strictly inside the exact bound, and within a knot spacing of that, no farther
 * inside than a knot's can lie: a kept stand-in's test (lazy_stand). stand_in tests a
 * memo's bound the same way in its own form (the same decisions: for doubles a - b >= 0
 * exactly when a >= b), written out there because through this function the step trace's
 * p99.9 plan cost 51 to 62 instructions more (bench/loop_tail.sh). */
static int stand_serves(const hp_static_bounds *b, int k, double pw, double ps, int up)
{
    double d = up ? ps - (pw + b->rate_slack[k]) : (pw - b->rate_slack[k]) - ps;
    return d >= 0.0 && d <= b->knot_dp[k];
}

/* A stand-in for the outer-radius bound [m] of the window end at pressure pw (up: the
 * lower end, whose radius bound must have a pressure >= pw), strictly inside the exact
 * bound: the outer radius of a point whose closed-form pressure lies beyond pw by the rate
 * slack on the window's side: the last bound solved for that end when its pressure lies
 * within a knot spacing of that (a window moves little from cycle to cycle; no search),
 * else the nearer of it and the bladder's nearest knot. Not the memo whenever it
 * qualifies: a memo left by a window far away (before a jump, or on the other side of a
 * binding limit) qualifies too, and a stand-in that far inside crossed the other end's, so
 * that both ends were solved at once. The pressure rises with the radius on the stable
 * branch, so the exact bound, where the pressure crosses pw, lies outside that point by at
 * least the slack's radius (about 1e-5 mm; the closed form's last-bit wobble is ~1e-11 Pa).
 * No model evaluation; NAN when no point qualifies. *ps receives the closed-form pressure
 * at the stand-in's point (NAN with none), by which a later window's end can take it again
 * (stand_serves). */
static double stand_in(const hp_static_bounds *b, int k, double pw, int up, const hp_rate_end *m,
                       double *ps)
{
    double sl = b->rate_slack[k], r = NAN, pr = NAN;
    *ps = NAN;
    if (!isfinite(sl)) return NAN;
    const double *kp = b->knot_p[k], *kr = b->knot_ro[k];
    int memo = m && m->ok, ok = b->knots_ok[k];
    if (up) { /* the smallest radius with P >= pw + sl */
        double t = pw + sl;
        if (memo && m->p_at >= t && m->p_at - t <= b->knot_dp[k]) return *ps = m->p_at, m->ro;
        if (ok && kp[HP_RATE_KNOTS - 1] >= t) {
            int j = knot_index(b, k, t); /* kp[j] <= t <= kp[j + 1], or t below the knots */
            j += !(kp[j] >= t);
            r = kr[j];
            pr = kp[j];
        }
        if (memo && m->p_at >= t && !(m->ro >= r)) return *ps = m->p_at, m->ro;
        return *ps = pr, r;
    }
    double t = pw - sl; /* the largest radius with P <= pw - sl */
    if (memo && m->p_at <= t && t - m->p_at <= b->knot_dp[k]) return *ps = m->p_at, m->ro;
    if (ok && kp[0] <= t) {
        int j = knot_index(b, k, t); /* kp[j] <= t <= kp[j + 1], or t above the knots */
        j += kp[j + 1] <= t;
        r = kr[j];
        pr = kp[j];
    }
    if (memo && m->p_at <= t && !(m->ro <= r)) return *ps = m->p_at, m->ro;
    return *ps = pr, r;
}

/* Bladder k's bounds into pb: inner radii lo, hi and outer radii rol, roh [m], each also
 * in mm. */
static inline void put_bounds(hp_problem *pb, int k, double lo, double hi, double rol, double roh)
{
    pb->ri_lo_si[k] = lo;
    pb->ri_hi_si[k] = hi;
    pb->ri_lo[k] = lo * HP_MM_PER_M;
    pb->ri_hi[k] = hi * HP_MM_PER_M;
    pb->ro_lo[k] = rol * HP_MM_PER_M;
    pb->ro_hi[k] = roh * HP_MM_PER_M;
}

/* Bladder k's bounds for this plan: the static ones intersected with the ends of its rate
 * window win (the caller's hpi_rate_window around p_prev[k]; NULL: the static bounds
 * alone), each solved exactly unless lazy_lo / lazy_hi (may be NULL) marks it: then a
 * stand-in (stand_in) for its outer radius, and the static inner radius. *nostand is set
 * when a stand-in was asked for and none could be made (the caller solves the end).
 * *nder (may be NULL) counts the window ends derived (stand-in, memo or solve). */
static hp_error bladder_bounds(const hp_layout *L, const hp_static_bounds *b, int k,
                               const double *p_prev, const double win[2], hp_rate_memo *memo,
                               const unsigned char *lazy_lo, const unsigned char *lazy_hi,
                               hp_problem *pb, unsigned *lo_flags, unsigned *hi_flags, int *nostand,
                               int *nder, hp_diag *d)
{
    const hp_bladder *B = &L->bladders[k];
    double lo = b->ri_lo[k], hi = b->ri_hi[k];
    unsigned lof = b->lo_flags[k], hif = b->hi_flags[k];
    /* The rate bounds solved and their outer radii (hp_iab_ro's bits, from the solve). */
    double r_r[2] = {NAN, NAN}, ro_r[2] = {NAN, NAN};
    double sro_lo = NAN, sro_hi = NAN; /* stand-ins' outer radii [m] */
    if (win) {
        double r, ps, pl = win[0], ph = win[1];
        if (nder) *nder += (pl > b->p_lo[k]) + (ph < b->p_hi[k]);
        if (pl > b->p_lo[k]) {
            if (lazy_lo && lazy_lo[k]) {
                sro_lo = stand_in(b, k, pl, 1, memo ? &memo->down[k] : NULL, &ps);
                *nostand |= isnan(sro_lo);
            } else if (rate_bound(b, k, pl, 1, memo, &r, &ro_r[0])) {
                take_max(&lo, &lof, r_r[0] = r, HP_BIND_RATE_DOWN);
            } else {
                return hp_diag_set(d, HP_ERR_INVALID,
                                   "bladder %s: rate limit: no stable radius at %.6g Pa", B->name,
                                   pl);
            }
        }
        if (ph < b->p_hi[k]) {
            if (lazy_hi && lazy_hi[k]) {
                sro_hi = stand_in(b, k, ph, 0, memo ? &memo->up[k] : NULL, &ps);
                *nostand |= isnan(sro_hi);
            } else if (rate_bound(b, k, ph, 0, memo, &r, &ro_r[1])) {
                take_min(&hi, &hif, r_r[1] = r, HP_BIND_RATE_UP);
            } else {
                return hp_diag_set(d, HP_ERR_INVALID,
                                   "bladder %s: rate limit: no stable radius at %.6g Pa", B->name,
                                   ph);
            }
        }
        /* A window narrower than the pressure step of one ulp of radius (about 4e-12 Pa;
         * a limit of 1e-300 kPa): no radius need have its pressure inside it, and the
         * two roots, each moved inward until its pressure is, pass each other by ulps.
         * The previous pressure lies in the window and in [p_lo, p_hi], so its own root
         * (within those ulps) is the one radius: the bladder holds its pressure, which
         * the plan reports clamped into the window (hpi_setup_bladder_from_ri_s). A gap
         * beyond 1e-12 of the radius (27 fm at 27 mm) would be no rounding: refused. */
        if (lo > hi && lo - hi <= 1e-12 * lo) lo = hi = fmin(fmax(hi, b->ri_lo[k]), b->ri_hi[k]);
    }
    if (*nostand) return HP_OK;
    /* The static bounds' outer radii when the rate limits left them as they were. */
    double rol = lo == b->ri_lo[k] ? b->ro_lo[k] : lo == r_r[0] ? ro_r[0] : NAN;
    double roh = hi == b->ri_hi[k] ? b->ro_hi[k] : hi == r_r[1] ? ro_r[1] : NAN;
    if (!(lo <= hi) || (isnan(rol) && hp_iab_ro(&B->iab, lo, &rol) != HP_OK) ||
        (isnan(roh) && hp_iab_ro(&B->iab, hi, &roh) != HP_OK))
        return hp_diag_set(d, HP_ERR_INVALID,
                           "bladder %s: the rate limit around %.6g Pa leaves no radius "
                           "inside the pressure and stretch limits",
                           B->name, p_prev ? p_prev[k] : 0.0);
    /* A stand-in replaces the outer radius where it is tighter than the exact end's other
     * bound could be: a stand-in lies inside the exact rate bound, so whichever of the two
     * (static, rate) the exact plan takes, the stand-in is inside it. rol and roh are
     * numbers here (a NaN was evaluated above or refused), so hpi_max2 and hpi_min2 give fmax's
     * and fmin's answer without their library calls. */
    if (!isnan(sro_lo)) {
        rol = hpi_max2(sro_lo, rol);
        if (rol != b->ro_lo[k]) lof = HP_BIND_RATE_DOWN;
    }
    if (!isnan(sro_hi)) {
        roh = hpi_min2(sro_hi, roh);
        if (roh != b->ro_hi[k]) hif = HP_BIND_RATE_UP;
    }
    put_bounds(pb, k, lo, hi, rol, roh);
    if (lo_flags) lo_flags[k] = lof;
    if (hi_flags) hi_flags[k] = hif;
    return HP_OK;
}

hp_error hpi_setup_cycle_bounds_memo(const hp_layout *L, const hp_static_bounds *b,
                                     const double *p_prev, int use_rate, hp_rate_memo *memo,
                                     hp_problem *pb, unsigned *lo_flags, unsigned *hi_flags,
                                     hp_diag *d)
{
    if (!use_rate || !p_prev) { /* the static bounds as they are (every plan starts so) */
        for (int k = 0; k < L->n; ++k) {
            put_bounds(pb, k, b->ri_lo[k], b->ri_hi[k], b->ro_lo[k], b->ro_hi[k]);
            if (lo_flags) lo_flags[k] = b->lo_flags[k];
            if (hi_flags) hi_flags[k] = b->hi_flags[k];
            int nostand = 0; /* a volume law that failed there: evaluated again, or refused */
            hp_error e = isnan(b->ro_lo[k]) || isnan(b->ro_hi[k])
                             ? bladder_bounds(L, b, k, NULL, NULL, NULL, NULL, NULL, pb, lo_flags,
                                              hi_flags, &nostand, NULL, d)
                             : HP_OK;
            if (e != HP_OK) return e;
        }
        return HP_OK;
    }
    for (int k = 0; k < L->n; ++k) {
        int nostand = 0;
        double w[2];
        int rated = isfinite(L->bladders[k].rate_max);
        if (rated) hpi_rate_window(p_prev[k], L->bladders[k].rate_max, &w[0], &w[1]);
        hp_error e = bladder_bounds(L, b, k, p_prev, rated ? w : NULL, memo, NULL, NULL, pb,
                                    lo_flags, hi_flags, &nostand, NULL, d);
        if (e != HP_OK) return e;
    }
    return HP_OK;
}

/* The width of the window of outer radii [mm] below which a bladder's ends are solved at
 * once: a stand-in so narrow could make the plan's pinned test (plan.c, rate_pinned) or
 * the realtime margin (half a window of 4e-11 mm) see another window than the exact one. */
#define HP_LAZY_MIN_WIDTH_MM (2.0 * HP_BINDING_TOL_MM)

/* A new stand-in for bladder k's window end in z (up: the lower), kept in z->stand. */
static inline double lazy_stand_new(hp_rate_lazy *z, int k, int up)
{
    double ps, pw = up ? z->pb->w_lo[k] : z->pb->w_hi[k]; /* ps: stand_in writes it */
    double r = stand_in(z->b, k, pw, up,
                        z->memo ? (up ? &z->memo->down[k] : &z->memo->up[k]) : NULL, &ps);
    hpi_count(&rate_stands_new, 1);
    hp_rate_stand *st = z->stand;
    if (st) {
        st->ok[!up][k] = (unsigned char)!isnan(r);
        st->p[!up][k] = ps;
        st->ro[!up][k] = r;
    }
    return r;
}

/* The stand-in of bladder k's window end in z (up: the lower): the one z->stand keeps when
 * it serves the end (stand_serves), else a new one (lazy_stand_new). Inline: the kept one
 * is most ends' answer, a few instructions. */
static inline double lazy_stand(hp_rate_lazy *z, int k, int up)
{
    const hp_rate_stand *st = z->stand;
    if (st && st->ok[!up][k] &&
        stand_serves(z->b, k, up ? z->pb->w_lo[k] : z->pb->w_hi[k], st->p[!up][k], up))
        return st->ro[!up][k];
    return lazy_stand_new(z, k, up);
}

/* Bladder k's bounds with the static inner radii and the outer radii rol, roh [m] (the
 * static ones ro_lo, ro_hi, or stand-ins where tighter): a flag says a rate limit where an
 * outer radius is not the static one. The caller's static outer radii: read again here
 * they would be loaded again after the stores (which may alias them). */
static inline void lazy_store(hp_rate_lazy *z, int k, double rol, double roh, double ro_lo,
                              double ro_hi)
{
    const hp_static_bounds *b = z->b;
    put_bounds(z->pb, k, b->ri_lo[k], b->ri_hi[k], rol, roh);
    if (z->lo_flags) z->lo_flags[k] = rol != ro_lo ? HP_BIND_RATE_DOWN : b->lo_flags[k];
    if (z->hi_flags) z->hi_flags[k] = roh != ro_hi ? HP_BIND_RATE_UP : b->hi_flags[k];
}

/* Bladder k when both its ends are marked stand-ins (every bladder of a plan's set-up but those a
 * memo holds an end of): bladder_bounds' steps for that case alone, the same operations on the same
 * numbers. The marks say pl > p_lo and ph < p_hi (hpi_setup_cycle_bounds_lazy), the radii stay the
 * static ones (lo < hi), their outer radii are numbers, and the stand-ins take the outer radii
 * where tighter. Returns 0, nothing stored, for any other case, a stand-in that cannot be made, or
 * a window too narrow for them: lazy_static_end (one end at a static limit) or lazy_general decides
 * those. Inline, apart from the general way: the set-up's loop runs it for every bladder. */
static inline int lazy_common(hp_rate_lazy *z, int k, int *nder)
{
    const hp_static_bounds *b = z->b;
    double ro_lo = b->ro_lo[k], ro_hi = b->ro_hi[k];
    if (!(z->lo[k] && z->hi[k]) || isnan(ro_lo) || isnan(ro_hi)) return 0;
    double sl = lazy_stand(z, k, 1), sh = lazy_stand(z, k, 0);
    double rol = hpi_max2(sl, ro_lo), roh = hpi_min2(sh, ro_hi);
    double rol_mm = rol * HP_MM_PER_M, roh_mm = roh * HP_MM_PER_M;
    if (isnan(sl) || isnan(sh) || !(roh_mm - rol_mm > HP_LAZY_MIN_WIDTH_MM)) return 0;
    if (nder) *nder += 2;
    lazy_store(z, k, rol, roh, ro_lo, ro_hi);
    return 1;
}

/* Bladder k when one end is a marked stand-in and the other's window end lies beyond the
 * static limit (a bladder at or near a pressure limit): bladder_bounds' steps for that case
 * alone, as lazy_common's for two stand-ins. The unmarked end keeps the static bounds and
 * flags, as bladder_bounds leaves an end whose window end is beyond the static limit; its
 * outer radius is a number. Returns 1 when stored; 0, nothing stored, for any other case
 * (both ends or none marked, the other end a memo's) or a window too narrow for the
 * stand-in; -1 when no stand-in can be made, where bladder_bounds solves both ends. Apart
 * from lazy_common, after it: folded into it, its extra tests cost every bladder about 12
 * instructions (95 a plan of the step trace with the plan's own answers, where few
 * bladders come here; bench/loop_tail.sh). */
static inline int lazy_static_end(hp_rate_lazy *z, int k, double pl, double ph)
{
    const hp_static_bounds *b = z->b;
    int up = z->lo[k]; /* the marked end is the lower */
    if (up == z->hi[k] || (up ? ph < b->p_hi[k] : pl > b->p_lo[k])) return 0;
    double ro_lo = b->ro_lo[k], ro_hi = b->ro_hi[k];
    if (isnan(ro_lo) || isnan(ro_hi)) return 0;
    double sr = lazy_stand(z, k, up);
    if (isnan(sr)) return -1;
    double rol = up ? hpi_max2(sr, ro_lo) : ro_lo, roh = up ? ro_hi : hpi_min2(sr, ro_hi);
    double rol_mm = rol * HP_MM_PER_M, roh_mm = roh * HP_MM_PER_M;
    if (!(roh_mm - rol_mm > HP_LAZY_MIN_WIDTH_MM)) return 0;
    lazy_store(z, k, rol, roh, ro_lo, ro_hi);
    return 1;
}

/* Bladder k the general way (bladder_bounds): the ends marked in z stand-ins, or both solved
 * when a stand-in cannot be made or leaves too narrow a window. *nder (may be NULL) counts
 * the ends derived. A resolve comes here directly: it has cleared the mark of an end it
 * needs exact, which lazy_common and lazy_static_end never solve. */
static hp_error lazy_general(hp_rate_lazy *z, int k, int *nder, hp_diag *d)
{
    int nostand = 0;
    hp_problem *pb = z->pb;
    double w[2] = {pb->w_lo[k], pb->w_hi[k]};
    hp_error e = bladder_bounds(z->L, z->b, k, pb->p_prev, w, z->memo, z->lo, z->hi, pb,
                                z->lo_flags, z->hi_flags, &nostand, nder, d);
    if (e != HP_OK) return e;
    if (!(z->lo[k] || z->hi[k]) || (!nostand && pb->ro_hi[k] - pb->ro_lo[k] > HP_LAZY_MIN_WIDTH_MM))
        return HP_OK;
    z->lo[k] = z->hi[k] = 0;
    nostand = 0;
    return bladder_bounds(z->L, z->b, k, pb->p_prev, w, z->memo, NULL, NULL, pb, z->lo_flags,
                          z->hi_flags, &nostand, nder, d);
}

hp_error hpi_setup_cycle_bounds_lazy(hp_rate_lazy *z, hp_diag *d)
{
    hpi_count(&rate_lazy_setups, 1);
    z->failed = 0;
    /* Locals: the marks are chars, which may alias anything, so each store of one would
     * have every field read through z loaded again. */
    const hp_static_bounds *b = z->b;
    const double *w_lo = z->pb->w_lo, *w_hi = z->pb->w_hi;
    hp_rate_memo *memo = z->memo;
    int n = z->L->n;
    for (int k = 0; k < n; ++k) {
        /* Without a rate limit [-inf, inf], which binds nowhere. */
        double pl = w_lo[k], ph = w_hi[k];
        /* An end the memo holds costs nothing exact (a plan holding its answer) */
        z->lo[k] = pl > b->p_lo[k] && !memo_holds(&memo->down[k], pl);
        z->hi[k] = ph < b->p_hi[k] && !memo_holds(&memo->up[k], ph);
        if (lazy_common(z, k, NULL)) continue;
        int c = lazy_static_end(z, k, pl, ph);
        if (c > 0) continue;
        if (c < 0) z->lo[k] = z->hi[k] = 0; /* bladder_bounds' way without a stand-in */
        hp_error e = lazy_general(z, k, NULL, d);
        if (e != HP_OK) return e;
    }
    return HP_OK;
}

/* Bladder k's one stand-in end (up: the lower) made exact, the other end's bounds as they
 * are in z->pb: the bits bladder_bounds and lazy_common give for the bladder, since the
 * other end's bounds do not depend on this one's (its inner radius is the static one or
 * its own exact bound, its outer radius that bound's or its stand-in's). Where they would
 * depend on it, it does not decide and returns 0 with nothing stored: the solved bound
 * beyond the other end (a window narrower than an ulp's pressure step, or no radius left),
 * the window of outer radii too narrow for the other end's stand-in, an outer radius the
 * volume law does not give. 1 when stored; -1 when the end has no stable radius. */
static int exact_end(hp_rate_lazy *z, int k, int up)
{
    const hp_static_bounds *b = z->b;
    hp_problem *pb = z->pb;
    double r, ro;
    if (!rate_bound(b, k, up ? z->pb->w_lo[k] : z->pb->w_hi[k], up, z->memo, &r, &ro)) return -1;
    double v = up ? b->ri_lo[k] : b->ri_hi[k];
    unsigned f = up ? b->lo_flags[k] : b->hi_flags[k];
    if (up) take_max(&v, &f, r, HP_BIND_RATE_DOWN);
    else take_min(&v, &f, r, HP_BIND_RATE_UP);
    double vro = v == (up ? b->ri_lo[k] : b->ri_hi[k]) ? (up ? b->ro_lo[k] : b->ro_hi[k])
                 : v == r                              ? ro
                                                       : NAN;
    if (!(up ? v <= pb->ri_hi_si[k] : pb->ri_lo_si[k] <= v) || isnan(vro)) return 0;
    double ro_mm = vro * HP_MM_PER_M;
    if ((up ? z->hi[k] : z->lo[k]) &&
        !((up ? pb->ro_hi[k] - ro_mm : ro_mm - pb->ro_lo[k]) > HP_LAZY_MIN_WIDTH_MM))
        return 0;
    *(up ? &pb->ri_lo_si[k] : &pb->ri_hi_si[k]) = v;
    *(up ? &pb->ri_lo[k] : &pb->ri_hi[k]) = v * HP_MM_PER_M;
    *(up ? &pb->ro_lo[k] : &pb->ro_hi[k]) = ro_mm;
    unsigned *fl = up ? z->lo_flags : z->hi_flags;
    if (fl) fl[k] = f;
    return 1;
}

int hpi_setup_rate_resolve(hp_rate_lazy *z, int k, unsigned ends)
{
    unsigned char lo = z->lo[k] && !(ends & 1u), hi = z->hi[k] && !(ends & 2u);
    if (lo == z->lo[k] && hi == z->hi[k]) return 1;
    /* One end made exact: that end's bounds alone (exact_end), else the whole bladder. */
    int tried = lo == z->lo[k] || hi == z->hi[k];
    int one = tried ? exact_end(z, k, lo != z->lo[k]) : 0;
    int nder = tried;
    z->lo[k] = lo;
    z->hi[k] = hi;
    hp_error e = one > 0 ? HP_OK : one < 0 ? HP_ERR_INVALID : lazy_general(z, k, &nder, NULL);
    hpi_count(&rate_resolves, 1);
    hpi_count(&rate_rederived, (unsigned long)nder);
    if (e == HP_OK) return 1;
    z->failed = 1;
    return 0;
}

int hpi_setup_rate_touch(hp_rate_lazy *z, const double *rho_mm, int n, double margin_mm)
{
    if (!z) return 1;
    int ok = 1;
    for (int k = 0; k < n; ++k) {
        if (!z->lo[k] && !z->hi[k]) continue;
        double r = rho_mm[k];
        /* false for a NaN: nothing to decide (every comparison of it fails either way) */
        unsigned ends = (z->lo[k] && r < z->pb->ro_lo[k] + margin_mm ? 1u : 0u) |
                        (z->hi[k] && r > z->pb->ro_hi[k] - margin_mm ? 2u : 0u);
        if (ends) ok &= hpi_setup_rate_resolve(z, k, ends);
    }
    return ok;
}

/* Where bladder k's outer radius r [mm] lies against the knots around pressure pw (lower:
 * pw is a window's lower end, else its upper): 2 when more than margin_mm beyond the knot
 * whose pressure brackets pw from outside (the pressure rises with the radius on the stable
 * branch, so the radius where the pressure crosses pw lies inside that knot's, and r beyond
 * it too), 1 when only beyond the knot inside it (near pw, one knot spacing or less), else
 * 0 (a NaN r: 0). */
static int knot_side(const hp_static_bounds *b, int k, double pw, int lower, double r,
                     double margin_mm)
{
    const double *kp = b->knot_p[k], *kr = b->knot_ro[k];
    int j = knot_index(b, k, pw);
    if (lower)
        return kp[j] <= pw && r < kr[j] * HP_MM_PER_M - margin_mm ? 2 : r < kr[j + 1] * HP_MM_PER_M;
    return kp[j + 1] >= pw && r > kr[j + 1] * HP_MM_PER_M + margin_mm ? 2 : r > kr[j] * HP_MM_PER_M;
}

int hpi_setup_rate_surely_out(const hp_rate_lazy *z, const double *rho_mm, int n, double margin_mm)
{
    if (!z) return 0;
    const hp_static_bounds *b = z->b;
    for (int k = 0; k < n; ++k) {
        if (!(z->lo[k] || z->hi[k]) || !b->knots_ok[k]) continue;
        if (z->lo[k] && knot_side(b, k, z->pb->w_lo[k], 1, rho_mm[k], margin_mm) == 2) return 1;
        if (z->hi[k] && knot_side(b, k, z->pb->w_hi[k], 0, rho_mm[k], margin_mm) == 2) return 1;
    }
    return 0;
}

int hpi_setup_rate_surely_left(const hp_layout *L, const hp_static_bounds *b, const double *p_prev,
                               const double *rho_mm, double margin_mm, unsigned *near)
{
    *near = 0;
    for (int k = 0; k < L->n; ++k) {
        double rate = L->bladders[k].rate_max;
        if (!isfinite(rate) || !b->knots_ok[k]) continue;
        /* hpi_rate_window moves its ends only inward from these (pl >= tl, ph <= th): a
         * knot that brackets tl or th from outside brackets the window's end, and an end
         * tighter than the static bound here is one there. No window worked out. */
        double tl = p_prev[k] - rate, th = p_prev[k] + rate;
        int lo = tl > b->p_lo[k] ? knot_side(b, k, tl, 1, rho_mm[k], margin_mm) : 0;
        int hi = th < b->p_hi[k] ? knot_side(b, k, th, 0, rho_mm[k], margin_mm) : 0;
        if (lo == 2 || hi == 2) return 1;
        if (lo || hi) *near |= 1u << k;
    }
    return 0;
}

int hpi_setup_rate_pending(const hp_rate_lazy *z)
{
    if (!z) return 0;
    for (int k = 0; k < z->L->n; ++k)
        if (z->lo[k] || z->hi[k]) return 1;
    return 0;
}

int hpi_setup_rate_clear(const hp_layout *L, const hp_static_bounds *b, const hp_problem *pb,
                         const hp_bladder_result *br)
{
    /* A bladder without a rate limit has [-inf, inf]: clear. */
    for (int k = 0; k < L->n; ++k)
        if (!hpi_setup_rate_clear_row(b, k, pb->w_lo[k], pb->w_hi[k], br[k].pressure)) return 0;
    return 1;
}

void hpi_setup_rate_windows(const hp_layout *L, hp_problem *pb)
{
    hpi_count(&rate_windows, (unsigned long)L->n);
    for (int k = 0; k < L->n; ++k)
        hpi_rate_window(pb->p_prev[k], L->bladders[k].rate_max, &pb->w_lo[k], &pb->w_hi[k]);
}

void hpi_setup_pose_from_scaled(const double x[6], double xi[6])
{
    for (int i = 0; i < 3; ++i) {
        xi[i] = x[i] / HP_MM_PER_M;
        xi[i + 3] = x[i + 3] / HP_DEG_PER_RAD;
    }
}

hp_error hpi_setup_contact_scaled(const hp_layout *L, const hp_geom *G, hp_level level,
                                  const double x[6], double *rho_mm, double *J_s)
{
    return hpi_setup_contact_scaled_warm(L, G, level, x, NULL, rho_mm, J_s);
}

hp_error hpi_setup_contact_scaled_warm(const hp_layout *L, const hp_geom *G, hp_level level,
                                       const double x[6], hp_kin_dist_warm *warm, double *rho_mm,
                                       double *J_s)
{
    double xi[6], J[HP_MAX_BLADDERS * 6];
    hpi_setup_pose_from_scaled(x, xi);
    hp_error e = hpi_kin_contact_eval_warm(L, G, level, xi, warm, rho_mm, J_s ? J : NULL, NULL);
    if (e != HP_OK) return e;
    for (int k = 0; k < L->n; ++k) {
        rho_mm[k] *= HP_MM_PER_M;
        if (!isfinite(rho_mm[k])) return HP_ERR_DOMAIN;
        if (!J_s) continue;
        for (int i = 0; i < 3; ++i) {
            J_s[k * 6 + i] = J[k * 6 + i];                                        /* mm/mm */
            J_s[k * 6 + i + 3] = J[k * 6 + i + 3] * HP_MM_PER_M / HP_DEG_PER_RAD; /* mm/deg */
        }
    }
    return HP_OK;
}

hp_error hpi_setup_contact_inside(const hp_layout *L, const hp_geom *G, hp_level level,
                                  const double x[6], const double *lo_mm, const double *hi_mm,
                                  double *rho_mm, double *J_si, int *inside)
{
    double xi[6];
    hpi_setup_pose_from_scaled(x, xi);
    hp_error e = hpi_kin_contact_inside(L, G, level, xi, HP_MM_PER_M, lo_mm, hi_mm, rho_mm, J_si,
                                        inside);
    if (e != HP_OK || !*inside) {
        *inside = 0;
        return e;
    }
    for (int k = 0; k < L->n; ++k) rho_mm[k] *= HP_MM_PER_M;
    return HP_OK;
}

hp_error hpi_setup_bladder_from_ro(const hp_bladder *B, double ro, double ri_lo, double ri_hi,
                                   double p_lo, double p_hi, hp_bladder_result *out, int *clamped)
{
    if (!isfinite(ro)) return HP_ERR_INVALID;
    hp_iab_s s;
    if (hpi_iab_scaled_init(&B->iab, &s, NULL) != HP_OK) return HP_ERR_DOMAIN;
    return hpi_setup_bladder_from_ro_s(B, &s, ro, ri_lo, ri_hi, p_lo, p_hi, out, clamped);
}

hp_error hpi_setup_ri_from_ro_s(const hp_iab_s *s, double ro, double ri_lo, double ri_hi,
                                double *ri_out, int *clamped)
{
    double ri;
    int c = 0;
    if (!isfinite(ro)) return HP_ERR_INVALID;
    /* The model on the bladder validated once (hp_iab_ri, hp_iab_ro and hp_iab_ik after
     * their validation: the same bits). */
    if (hpi_iab_s_ri_m(s, ro, &ri) != HP_OK) {
        ri = ri_lo; /* collapsed cavity: the lower bound is the nearest valid radius */
        c = 1;
    }
    if (ri < ri_lo) {
        ri = ri_lo;
        c = 1;
    }
    if (ri > ri_hi) {
        ri = ri_hi;
        c = 1;
    }
    *ri_out = ri;
    *clamped = c;
    return HP_OK;
}

hp_error hpi_setup_bladder_from_ri_s(const hp_bladder *B, const hp_iab_s *s, double ro, double ri,
                                     int clamped, double p_lo, double p_hi, hp_bladder_result *out)
{
    double P;
    /* A clamped ri: its pressure and outer radius from one evaluation. Else ro is the outer
     * radius of ri to a few ulps (ri was solved from it): the pressure's own outer radius
     * starts there (the same bits as hpi_iab_s_ik_m but within ~1e-7 ulp of a rounding
     * midpoint). */
    hp_error e = clamped ? hpi_iab_s_ik_ro_m(s, ri, &P, &ro) : hpi_iab_s_ik_near_m(s, ri, ro, &P);
    if (e != HP_OK || !isfinite(P)) return HP_ERR_DOMAIN;
    P = hpi_setup_pressure_in(P, p_lo, p_hi);
    out->ri = ri;
    out->ro = ro;
    out->pressure = P;
    out->stretch = ri / B->iab.Ri;
    out->binding = 0;
    return HP_OK;
}

hp_error hpi_setup_bladder_from_ro_s(const hp_bladder *B, const hp_iab_s *s, double ro,
                                     double ri_lo, double ri_hi, double p_lo, double p_hi,
                                     hp_bladder_result *out, int *clamped)
{
    double ri;
    int c;
    hp_error e = hpi_setup_ri_from_ro_s(s, ro, ri_lo, ri_hi, &ri, &c);
    if (e == HP_OK) e = hpi_setup_bladder_from_ri_s(B, s, ro, ri, c, p_lo, p_hi, out);
    if (e == HP_OK && clamped) *clamped = c;
    return e;
}
