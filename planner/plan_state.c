/* The planner's state between plans, shared by its lifecycle (planner.c) and its plan
 * (plan.c): pose scaling, the answer of a pose, the fit from the nominal pose and the
 * previous answer. */
#include "planner/planner_internal.h"

#include <math.h>
#include <string.h>

void hpi_plan_to_scaled(const double xi[6], double x[6])
{
    for (int i = 0; i < 6; ++i) x[i] = xi[i] * hpi_pose_scaled_per_si(i);
}

void hpi_plan_from_scaled(const double x[6], double xi[6]) { hpi_setup_pose_from_scaled(x, xi); }

int hpi_plan_answer_from_pose(hp_planner *p, const double x[6], const double *rho_known,
                              hp_result *res, double *clamp_mm)
{
    double rho[HP_MAX_BLADDERS];
    *clamp_mm = 0;
    if (rho_known) memcpy(rho, rho_known, sizeof(double) * (size_t)p->L.n);
    else if (hpi_setup_contact_scaled(&p->L, &p->G, p->level, x, rho, NULL) != HP_OK) return 0;
    /* Every bladder's inner radius first, then the pressures: each half is a chain of
     * roots and divisions, and back to back the processor overlaps one bladder's chain with
     * the next one's (the same bits as one pass). */
    double ri[HP_MAX_BLADDERS];
    int clamped[HP_MAX_BLADDERS];
    for (int k = 0; k < p->L.n; ++k)
        if (hpi_setup_ri_from_ro_s(&p->sb.iab_s[k], rho[k] / HP_MM_PER_M, p->pb.ri_lo_si[k],
                                   p->pb.ri_hi_si[k], &ri[k], &clamped[k]) != HP_OK)
            return 0;
    for (int k = 0; k < p->L.n; ++k) {
        const hp_bladder *B = &p->L.bladders[k];
        double plo = p->sb.p_lo[k], phi = p->sb.p_hi[k];
        /* The windows' centres: the previous pressures (a reading's, derived or not). */
        if (p->s.use_rate_limits && isfinite(B->rate_max)) {
            double wl, wh;
            hpi_rate_window(p->pb.p_prev[k], B->rate_max, &wl, &wh);
            plo = fmax(plo, wl);
            phi = fmin(phi, wh);
        }
        int c = clamped[k];
        hp_bladder_result *br = &res->bladders[k];
        if (hpi_setup_bladder_from_ri_s(B, &p->sb.iab_s[k], rho[k] / HP_MM_PER_M, ri[k], c, plo,
                                        phi, br) != HP_OK)
            return 0;
        if (c) *clamp_mm = fmax(*clamp_mm, fabs(br->ro * HP_MM_PER_M - rho[k]));
        double ro_mm = br->ro * HP_MM_PER_M;
        if (ro_mm <= p->pb.ro_lo[k] + HP_BINDING_TOL_MM) br->binding |= p->lo_flags[k];
        if (ro_mm >= p->pb.ro_hi[k] - HP_BINDING_TOL_MM) br->binding |= p->hi_flags[k];
        if (!(br->pressure >= B->p_min && br->pressure <= B->p_max) || !isfinite(br->ri) ||
            !isfinite(br->ro))
            return 0;
    }
    hpi_plan_from_scaled(x, res->achieved);
    return 1;
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
