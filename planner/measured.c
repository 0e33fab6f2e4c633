/* Pressures the bladders hold now, from the caller: set_previous (exact, inside the limits)
 * and set_measured (a sensor's reading: clamped within a tolerance, its radii and pose
 * fitted from the last answer when something first needs them). */
#include "planner/planner_internal.h"
#include "kinematics/fit_internal.h"
#include "common/test_count.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

static atomic_ulong fk_evals;
static atomic_int refuse_next;

unsigned long hpi_test_measured_fk_evals(void) { return atomic_load(&fk_evals); }

void hpi_test_measured_refuse(int on) { atomic_store(&refuse_next, on); }

hp_error hpi_plan_previous_from(hp_planner *p, const double *P, int warm, const char *who)
{
    hp_result r = p->nominal;
    double ro[HP_MAX_BLADDERS];
    for (int k = 0; k < p->L.n; ++k) {
        const hp_bladder *B = &p->L.bladders[k];
        const hp_iab_s *s = &p->sb.iab_s[k];
        /* From the previous answer's radius when warm: a reading near it takes a step or two
         * of the FK's Newton iteration instead of a search of the whole stable branch; the
         * same root to rounding whatever the start (hpi_iab_fk_limit_warm). */
        double ri, root;
        const hp_bladder_result *pr = &p->prev.bladders[k];
        /* The previous answer's radius with its pressure and the slope there (formed from
         * the radii, no pressure evaluation): one Newton step toward the reading before the
         * FK's first evaluation, so that a reading a sensor's noise away is the root after
         * about two. */
        hpi_iab_fk_start st = {
            .ri = pr->ri, .p = pr->pressure, .ro = pr->ro, .slope = 1, .loose = 1};
        if (!warm ||
            hpi_iab_s_slopes(s, pr->ri * s->scale, pr->ro * s->scale, &st.d, NULL) != HP_OK)
            st.slope = 0;
        hpi_iab_fk_out o;
        /* The outer radius comes with the root (the FK's last evaluation formed it, the
         * same bits as hpi_iab_s_ro_m of the root). */
        hp_error e = hpi_iab_s_fk_from(s, &p->sb.limit[k], P[k], warm ? &st : NULL, &o);
        hpi_count(&fk_evals, (unsigned long)o.evals);
        if (e == HP_OK) e = hpi_iab_s_fk_ro(s, &o, &ro[k]);
        root = o.ri;
        /* The root of a pressure inside [p_lo, p_hi] lies inside [ri_lo, ri_hi] up to an
         * ulp or two: keep the stretch inside its limits to the last bit (and the outer
         * radius then of the clamped radius). */
        ri = e == HP_OK ? fmin(fmax(root, p->sb.ri_lo[k]), p->sb.ri_hi[k]) : root;
        if (e == HP_OK && ri != root) e = hpi_iab_s_ro_m(s, ri, &ro[k]);
        if (e != HP_OK) {
            hpi_text_set(p->err, who);
            hpi_text_add(p->err, ": no stable radius for the pressure of ");
            hpi_text_add(p->err, B->name);
            return HP_ERR_INVALID;
        }
        r.bladders[k].ri = ri;
        r.bladders[k].ro = ro[k];
        r.bladders[k].pressure = P[k];
        r.bladders[k].stretch = ri / B->iab.Ri;
        r.bladders[k].binding = 0;
    }
    double xi[6], resid;
    /* The pose becomes the safe output's achieved: one the fit does not find would be stated
     * for pressures that do not hold it (before, the nominal pose). The fit is in the
     * commanded components, as the round trip's: the others are stated as 0, and a layout
     * that cannot observe them (five bladders, a flat ring) has no fit in all six, which
     * refused even its own nominal pressures. Warm: from the previous answer's pose, a few
     * steps away for a reading near the last plan (a fit from the nominal pose takes the
     * whole way, most of set_previous's cost); from the nominal pose when it fails. */
    int fitted = 0;
    /* The linear level's fit is linear least squares: solved directly with the factor
     * prepared at the first reading (a quarter of a reading's cost by the iteration). */
    if (warm && p->level == HP_LEVEL_LINEAR) {
        if (!p->lin_fit_tried) {
            p->lin_fit_tried = 1;
            (void)hpi_kin_linear_fit_prepare(&p->L, &p->G, p->commanded, &p->lin_fit);
        }
        fitted = p->lin_fit.ready &&
                 hpi_kin_linear_fit_solve(&p->lin_fit, &p->L, &p->G, ro, xi, &resid) == HP_OK;
    }
    if (warm && !fitted) {
        double x0[6];
        for (int i = 0; i < 6; ++i) x0[i] = p->commanded[i] ? p->prev.achieved[i] : 0.0;
        fitted = hpi_kin_fit(&p->L, &p->G, p->level, ro, p->commanded, x0, NULL, NULL, xi, &resid,
                             NULL) == HP_OK;
    }
    if (!fitted && hpi_plan_fit_from_nominal(p, ro, p->commanded, NULL, xi, &resid) != HP_OK) {
        hpi_text_set(p->err, who);
        hpi_text_add(p->err, ": forward contact kinematics from the nominal pose finds no pose "
                             "these pressures hold (it did not converge)");
        return HP_ERR_INVALID;
    }
    for (int i = 0; i < 6; ++i) r.achieved[i] = p->commanded[i] ? xi[i] : 0.0;
    hpi_plan_set_previous_answer(p, &r);
    /* The radii solve P to the FK's precision, not to set_previous_result's tolerance. */
    p->prev_checked = 0;
    return HP_OK;
}

hp_error hp_planner_set_measured(hp_planner *p, const double *pressures, unsigned *clamped)
{
    if (!p) return HP_ERR_NULL;
    if (!pressures) {
        hpi_text_set(p->err, "set_measured: pressures is NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) return HP_ERR_STATE;
    double P[HP_MAX_BLADDERS], plo[HP_MAX_BLADDERS], phi[HP_MAX_BLADDERS];
    /* The level's own pressure bounds: the load level's differ from the kinematic ones. */
    if (p->load) {
        hpi_load_level_bounds(p->load, plo, phi);
    } else {
        memcpy(plo, p->sb.p_lo, (size_t)p->L.n * sizeof *plo);
        memcpy(phi, p->sb.p_hi, (size_t)p->L.n * sizeof *phi);
    }
    unsigned mask = 0;
    for (int k = 0; k < p->L.n; ++k) {
        const hp_bladder *B = &p->L.bladders[k];
        double tol = HP_MEASURED_TOL_REL * (B->p_max - B->p_min), lo = plo[k], hi = phi[k],
               v = pressures[k];
        if (!(v >= lo - tol && v <= hi + tol)) {
            hpi_text_set(p->err, "set_measured: bladder ");
            hpi_text_add(p->err, B->name);
            if (!isfinite(v)) {
                hpi_text_add(p->err, ": pressure not finite");
            } else {
                hpi_text_add(p->err, ": pressure ");
                hpi_text_add_num(p->err, v, 3);
                hpi_text_add(p->err, " Pa lies ");
                hpi_text_add_num(p->err, v < lo ? lo - v : v - hi, 3);
                hpi_text_add(p->err, " Pa beyond the pressures its limits allow (tolerance ");
                hpi_text_add_num(p->err, tol, 3);
                hpi_text_add(p->err, " Pa)");
            }
            return HP_ERR_INVALID;
        }
        P[k] = fmin(fmax(v, lo), hi);
        if (P[k] != v) mask |= 1u << k;
    }
    if (p->load) {
        hp_error e = hpi_load_level_set_previous(p->load, P);
        if (e == HP_OK && clamped) *clamped = mask;
        return e;
    }
    /* A reading no plan used is derived first: its radii and pose start this one's, as
     * they did when every reading was derived at once (dropped when it has none). */
    char err[HP_DIAG_MAX];
    memcpy(err, p->err, sizeof err);
    if (hpi_plan_measured_derive(p) != HP_OK) memcpy(p->err, err, sizeof err);
    /* Most plans need no radius of the reading: the rate windows are centred on its
     * pressures, and a plan the direct chain answers reads nothing else of it. Its radii
     * and pose are derived when a solve, a hold or the safe output first needs them
     * (hpi_plan_measured_derive), from the answer before it: the same bits as at once. */
    memcpy(p->meas_P, P, (size_t)p->L.n * sizeof *P);
    memcpy(p->pb.p_prev, P, (size_t)p->L.n * sizeof *P);
    p->meas_pending = 1;
    p->prev_checked = 0;
    /* The next start is this reading's answer, not a backend's own last point. */
    if (p->ops && p->ops->warm_point && p->bstate) p->ops->warm_point(p->bstate, 0);
    if (p->ops && p->ops->reading && p->bstate) p->ops->reading(p->bstate);
    if (clamped) *clamped = mask;
    return HP_OK;
}

int hpi_plan_measured_start_ok(const hp_planner *p)
{
    if (!p->meas_pending) return 1;
    /* A budget's iterate is no answer to start from for a backend that is not real-time:
     * the reading, where the bladders are, carries the progress the cycles make (started
     * from the iterate, NLopt SLSQP with a 20 us budget ran out of time on 1 659 of 3 000
     * noisy-trace plans, against 147). The realtime backend starts from it: deriving the
     * reading is a contact fit before the solve's budget begins, which the plans after a
     * time-limit then overran by (docs/control-loop.md, A time budget that holds). */
    if (p->prev.status != HP_STATUS_REACHED && p->prev.status != HP_STATUS_CLOSEST &&
        p->prev.status != HP_STATUS_UNCOMMANDED &&
        !(p->prev.status == HP_STATUS_TIME_LIMIT && (p->ops->caps & HP_BACKEND_REAL_TIME)))
        return 0;
    /* Without rate limits the windows are the static limits, which every previous answer
     * meets (an answer's pressures are clamped into them; set_previous and
     * set_previous_result check them). */
    if (p->rate_free) return 1;
    /* Inside its static limits, and inside its window by the slack at which the window's
     * radius bound does not matter (hpi_setup_rate_clear's test): the answer's radii then
     * lie inside this cycle's radius bounds too. One pass over the bladders. */
    const hp_problem *pb = &p->pb;
    for (int k = 0; k < p->L.n; ++k) {
        double P = p->prev.bladders[k].pressure;
        if (!(P >= p->sb.p_lo[k] && P <= p->sb.p_hi[k]) ||
            !hpi_setup_rate_clear_row(&p->sb, k, pb->w_lo[k], pb->w_hi[k], P))
            return 0;
    }
    return 1;
}

hp_error hpi_plan_measured_derive(hp_planner *p)
{
    if (!p->meas_pending) return HP_OK;
    char held[HP_DIAG_MAX], why[HP_DIAG_MAX];
    memcpy(held, p->err, sizeof held);
    if (atomic_load(&refuse_next)) {
        hpi_text_set(p->err, "set_measured: refused by the test hook");
    } else if (hpi_plan_previous_from(p, p->meas_P, 1, "set_measured") == HP_OK) {
        return HP_OK;
    }
    /* Dropped: the previous answer is the one before the reading, its pressures the
     * windows' centres again. */
    p->meas_pending = 0;
    for (int k = 0; k < p->L.n; ++k) p->pb.p_prev[k] = p->prev.bladders[k].pressure;
    /* The windows move with their centres. Nothing reads them after a drop today (a plan
     * that drops its reading ends in its safe output; between plans the next validate
     * works them out), but hp_problem.w_lo promises p_prev's windows for the rest of a plan. */
    if (!p->rate_free) hpi_setup_rate_windows(&p->L, &p->pb);
    memcpy(why, p->err, sizeof why);
    hpi_text_set(p->err, held);
    if (*held) hpi_text_add(p->err, "; ");
    hpi_text_add(p->err, why);
    hpi_text_add(p->err, ": the reading is dropped");
    return HP_ERR_INVALID;
}
