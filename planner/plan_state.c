/* The planner's state between plans, shared by its lifecycle (planner.c) and its plan
 * (plan.c): pose scaling, the answer of a pose, the fit from the nominal pose and the
 * previous answer. */
#include "planner/planner_internal.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

static atomic_ulong answer_rows;
static atomic_int answer_memo_off;

unsigned long hpi_test_answer_rows(void) { return atomic_load(&answer_rows); }
void hpi_test_answer_memo(int on) { atomic_store(&answer_memo_off, !on); }

void hpi_plan_to_scaled(const double xi[6], double x[6])
{
    for (int i = 0; i < 6; ++i) x[i] = xi[i] * hpi_pose_scaled_per_si(i);
}

void hpi_plan_from_scaled(const double x[6], double xi[6]) { hpi_setup_pose_from_scaled(x, xi); }

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* 1 when the memo holds bladder k's row at distance rho_mm [mm] and radius bounds lo, hi. */
static int memo_holds(const hp_answer_memo *m, int k, double rho_mm, double lo, double hi)
{
    return m->valid[k] && same_bits(m->rho[k], rho_mm) && same_bits(m->ri_lo[k], lo) &&
           same_bits(m->ri_hi[k], hi);
}

/* Bladder k's pressure window in this plan: its limits, within the rate window around the
 * previous pressure (a reading's, derived or not) when a rate limit applies. */
static inline void row_window(const hp_planner *p, int k, double *plo, double *phi)
{
    const hp_bladder *B = &p->L.bladders[k];
    *plo = p->sb.p_lo[k];
    *phi = p->sb.p_hi[k];
    if (p->s.use_rate_limits && isfinite(B->rate_max)) {
        double wl, wh;
        hpi_rate_window(p->pb.p_prev[k], B->rate_max, &wl, &wh);
        *plo = fmax(*plo, wl);
        *phi = fmin(*phi, wh);
    }
}

/* The rest of bladder k's row br (its pressure in its window) at distance rho_mm: the
 * radius correction (c: its inner radius was clamped), the binding flags, and 0 when it
 * left a limit or was not finite. */
static inline int row_finish(const hp_planner *p, int k, hp_bladder_result *br, int c,
                             double rho_mm, double *clamp_mm)
{
    const hp_bladder *B = &p->L.bladders[k];
    if (c) *clamp_mm = fmax(*clamp_mm, fabs(br->ro * HP_MM_PER_M - rho_mm));
    double ro_mm = br->ro * HP_MM_PER_M;
    if (ro_mm <= p->pb.ro_lo[k] + HP_BINDING_TOL_MM) br->binding |= p->lo_flags[k];
    if (ro_mm >= p->pb.ro_hi[k] - HP_BINDING_TOL_MM) br->binding |= p->hi_flags[k];
    return br->pressure >= B->p_min && br->pressure <= B->p_max && isfinite(br->ri) &&
           isfinite(br->ro);
}

/* The direct answer under deferred rate bounds (hpi_plan_answer_from_pose with direct):
 * bladder by bladder, each row from the memo or evaluated (and kept there), in this plan's
 * window, checked, and tested against the rate window; the first row near its window's
 * end ends it, as the plan discards the answer then. Row by row, the chains of one
 * bladder's radius and pressure no longer overlap with the next bladder's (answer_eval),
 * but a discarded answer stops at its first such row (the first on most new targets). */
static int answer_direct(hp_planner *p, const double x[6], const double *rho, hp_result *res,
                         double *clamp_mm)
{
    hp_answer_memo *m = &p->ans_memo;
    const int memo = !atomic_load_explicit(&answer_memo_off, memory_order_relaxed);
    for (int k = 0; k < p->L.n; ++k) {
        hp_bladder_result *br = &res->bladders[k];
        const double lo = p->pb.ri_lo_si[k], hi = p->pb.ri_hi_si[k];
        int c;
        if (memo && memo_holds(m, k, rho[k], lo, hi)) {
            *br = m->res[k];
            c = m->clamped[k];
        } else {
            atomic_fetch_add_explicit(&answer_rows, 1ul, memory_order_relaxed);
            double ri;
            m->valid[k] = 0; /* its row is overwritten */
            if (hpi_setup_ri_from_ro_s(&p->sb.iab_s[k], rho[k] / HP_MM_PER_M, lo, hi, &ri, &c) !=
                    HP_OK ||
                hpi_setup_bladder_from_ri_s(&p->L.bladders[k], &p->sb.iab_s[k],
                                            rho[k] / HP_MM_PER_M, ri, c, -INFINITY, INFINITY,
                                            br) != HP_OK)
                return 0;
            if (memo) {
                m->res[k] = *br;
                m->clamped[k] = (unsigned char)c;
                m->rho[k] = rho[k];
                m->ri_lo[k] = lo;
                m->ri_hi[k] = hi;
                m->valid[k] = 1;
            }
        }
        double plo, phi;
        row_window(p, k, &plo, &phi);
        br->pressure = hpi_setup_pressure_in(br->pressure, plo, phi);
        if (!row_finish(p, k, br, c, rho[k], clamp_mm)) return 0;
        if (!hpi_setup_rate_clear_row(&p->L, &p->sb, p->pb.p_prev, k, br->pressure))
            return HPI_ANSWER_NEAR_RATE;
    }
    hpi_plan_from_scaled(x, res->achieved);
    return 1;
}

/* The answer evaluated from the distances rho [mm]: every bladder's inner radius first,
 * then the pressures (each half is a chain of roots and divisions, and back to back the
 * processor overlaps one bladder's chain with the next one's: the same bits as one pass). */
static inline int answer_eval(hp_planner *p, const double x[6], const double *rho, hp_result *res,
                              double *clamp_mm)
{
    const int n = p->L.n;
    atomic_fetch_add_explicit(&answer_rows, (unsigned long)n, memory_order_relaxed);
    double ri[HP_MAX_BLADDERS];
    int clamped[HP_MAX_BLADDERS];
    for (int k = 0; k < n; ++k)
        if (hpi_setup_ri_from_ro_s(&p->sb.iab_s[k], rho[k] / HP_MM_PER_M, p->pb.ri_lo_si[k],
                                   p->pb.ri_hi_si[k], &ri[k], &clamped[k]) != HP_OK)
            return 0;
    for (int k = 0; k < n; ++k) {
        double plo, phi;
        row_window(p, k, &plo, &phi);
        hp_bladder_result *br = &res->bladders[k];
        if (hpi_setup_bladder_from_ri_s(&p->L.bladders[k], &p->sb.iab_s[k], rho[k] / HP_MM_PER_M,
                                        ri[k], clamped[k], plo, phi, br) != HP_OK)
            return 0;
        if (!row_finish(p, k, br, clamped[k], rho[k], clamp_mm)) return 0;
    }
    hpi_plan_from_scaled(x, res->achieved);
    return 1;
}

int hpi_plan_answer_from_pose(hp_planner *p, const double x[6], const double *rho_known, int direct,
                              hp_result *res, double *clamp_mm)
{
    double rho[HP_MAX_BLADDERS];
    *clamp_mm = 0;
    if (rho_known) memcpy(rho, rho_known, sizeof(double) * (size_t)p->L.n);
    else if (hpi_setup_contact_scaled(&p->L, &p->G, p->level, x, rho, NULL) != HP_OK) return 0;
    return direct ? answer_direct(p, x, rho, res, clamp_mm) : answer_eval(p, x, rho, res, clamp_mm);
}

hp_error hpi_plan_fit_from_nominal(const hp_planner *p, const double *ro, const int free_[6],
                                   const hp_kin_fit_near *near, double xi[6], double *residual_rms)
{
    /* With fk_free: hp_contact_fk's own checks, so this is a drop-in for it. */
    if (free_ == p->fk_free) {
        int nf = 0;
        for (int i = 0; i < 6; ++i) nf += free_[i] != 0;
        if (p->L.n < nf) return HP_ERR_INVALID;
        for (int k = 0; k < p->L.n; ++k)
            if (!(ro[k] > 0) || !isfinite(ro[k])) return HP_ERR_INVALID;
    }
    const double zero[6] = {0};
    return hpi_kin_fit(&p->L, &p->G, p->level, ro, free_, zero, p->nom_ok ? &p->nom : NULL, near,
                       xi, residual_rms, NULL);
}

void hpi_plan_set_previous_answer(hp_planner *p, const hp_result *r)
{
    if (r != &p->prev) p->prev = *r;
    p->prev_checked = 1; /* hp_planner_set_previous clears it after this call */
    p->meas_pending = 0;
    hpi_plan_to_scaled(r->achieved, p->x_prev);
    for (int k = 0; k < p->L.n; ++k) p->x_prev[6 + k] = r->bladders[k].ri * HP_MM_PER_M;
    for (int k = 0; k < p->L.n; ++k) p->pb.p_prev[k] = r->bladders[k].pressure;
    /* The next start is this answer's pose and radii, not a backend's own last point. */
    if (p->ops && p->ops->warm_point && p->bstate) p->ops->warm_point(p->bstate, 0);
}
