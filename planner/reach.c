/* hp_planner_reach: the reach along each axis by the planner's own test, so that what
 * `headplan analyze` reports is where `headplan solve` stops answering REACHED. */
#include "planner/planner_internal.h"
#include "kinematics/kin_internal.h"

#include <math.h>

/* Scan steps per cap (0.025 mm, 0.015 deg): the round trip of a layout that barely
 * identifies rotations fails in gaps of ~0.03 mm along an axis (near-spherical head on six
 * bladders, plane level), which the limits' scan of 1/100 of the cap stepped over. */
#define PLAN_REACH_SCAN 2000

/* What the predicate needs: the planner and this search's bounds (no rate limits). */
typedef struct reach_ctx {
    const hp_planner *p;
    hp_problem pb;
} reach_ctx;

/* 1 when a single solve of desired xi from rest would be answered REACHED by the direct
 * chain: xi inside the identifiable range, the contact distances of its commanded part
 * (plan.c, steps 1-2) inside every bladder's outer-radius bounds, and the answer's strict
 * round trip (its pressures' forward contact kinematics from the nominal pose, plan.c)
 * giving its pose back. Without the last, a layout that barely identifies rotations (a
 * near-spherical head on six bladders) had reaches at 99 % of which solve refused the
 * answer as outside the identifiable range. */
static int direct_reached(void *ctx, const double xi[6])
{
    reach_ctx *c = ctx;
    const hp_planner *p = c->p;
    const hp_identifiable *id = &p->id;
    if (hpi_plan_range_check(id, xi, NULL) != 0) return 0;
    double xc[6], x[6], rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6];
    if (hp_pose_commanded_part(&p->L, id, p->level, xi, xc) != HP_OK) return 0;
    hpi_plan_to_scaled(xc, x);
    for (int i = 0; i < 6; ++i)
        if (!p->commanded[i]) x[i] = 0.0;
    int inside = 0;
    double *Jp = p->level == HP_LEVEL_LINEAR ? NULL : J;
    if (hpi_setup_contact_inside(&p->L, &p->G, p->level, x, c->pb.ro_lo, c->pb.ro_hi, rho, Jp,
                                 &inside) != HP_OK ||
        !inside)
        return 0;
    /* The answer hp_plan builds from these distances (planner.c, hpi_plan_answer_from_pose,
     * without rate limits), then its round trip with the direct chain's anchor, as hp_plan
     * runs it. */
    hp_result r;
    r.n = p->L.n;
    for (int k = 0; k < p->L.n; ++k) {
        double ri;
        int cl;
        if (hpi_setup_ri_from_ro_s(&p->sb.iab_s[k], rho[k] / HP_MM_PER_M, c->pb.ri_lo_si[k],
                                   c->pb.ri_hi_si[k], &ri, &cl) != HP_OK ||
            hpi_setup_bladder_from_ri_s(&p->L.bladders[k], &p->sb.iab_s[k], rho[k] / HP_MM_PER_M,
                                        ri, cl, p->sb.p_lo[k], p->sb.p_hi[k],
                                        &r.bladders[k]) != HP_OK)
            return 0;
    }
    double achieved[6];
    hpi_plan_from_scaled(x, achieved);
    hp_plan_anchor an = {x, rho, Jp, 0.0};
    hp_plan_trip t;
    return hpi_plan_round_trip(p, &r, achieved, &an, &t);
}

hp_error hp_planner_reach(const hp_planner *p, double reach[6][2])
{
    if (!p || !reach) return HP_ERR_NULL;
    if (!p->built) return HP_ERR_STATE;
    if (p->load) return HP_ERR_INVALID; /* the load level's reach is not a contact range */
    reach_ctx c = {p, p->pb};
    unsigned lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    hp_error e = hpi_setup_cycle_bounds(&p->L, &p->sb, NULL, 0, &c.pb, lo, hi, NULL);
    if (e != HP_OK) return e;
    for (int i = 0; i < 6; ++i) {
        if (!p->commanded[i]) {
            reach[i][0] = reach[i][1] = NAN;
            continue;
        }
        reach[i][0] = -hpi_kin_reach_axis(direct_reached, &c, i, -1.0, PLAN_REACH_SCAN);
        reach[i][1] = hpi_kin_reach_axis(direct_reached, &c, i, 1.0, PLAN_REACH_SCAN);
    }
    return HP_OK;
}
