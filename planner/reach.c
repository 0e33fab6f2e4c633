/* hp_planner_reach: the reach along each axis by the planner's own test, so that what
 * `headplan analyze` reports is where `headplan solve` stops answering REACHED. */
#include "planner/planner_internal.h"
#include "kinematics/kin_internal.h"

#include <math.h>

/* What the predicate needs: the planner and this search's bounds (no rate limits). */
typedef struct reach_ctx {
    const hp_planner *p;
    hp_problem pb;
} reach_ctx;

/* 1 when a single solve of desired xi would be answered by the direct chain: xi inside the
 * identifiable range, and the contact distances of its commanded part (plan.c, steps 1-2)
 * inside every bladder's outer-radius bounds. */
static int direct_reached(void *ctx, const double xi[6])
{
    reach_ctx *c = ctx;
    const hp_planner *p = c->p;
    const hp_identifiable *id = &p->id;
    if (hp_plan_range_check(id, xi, NULL) != 0) return 0;
    double xc[6], x[6], rho[HP_MAX_BLADDERS];
    if (hp_pose_commanded_part(&p->L, id, p->level, xi, xc) != HP_OK) return 0;
    hp_plan_to_scaled(xc, x);
    for (int i = 0; i < 6; ++i)
        if (!p->commanded[i]) x[i] = 0.0;
    int inside = 0;
    return hp_setup_contact_inside(&p->L, &p->G, p->level, x, c->pb.ro_lo, c->pb.ro_hi, rho, NULL,
                                   &inside) == HP_OK && inside;
}

hp_error hp_planner_reach(const hp_planner *p, double reach[6][2])
{
    if (!p || !reach) return HP_ERR_NULL;
    if (!p->built) return HP_ERR_STATE;
    reach_ctx c = {p, p->pb};
    unsigned lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    hp_error e = hp_setup_cycle_bounds(&p->L, &p->sb, NULL, 0, &c.pb, lo, hi, NULL);
    if (e != HP_OK) return e;
    for (int i = 0; i < 6; ++i) {
        if (!p->commanded[i]) {
            reach[i][0] = reach[i][1] = NAN;
            continue;
        }
        reach[i][0] = -hp_kin_reach_axis(direct_reached, &c, i, -1.0);
        reach[i][1] = hp_kin_reach_axis(direct_reached, &c, i, 1.0);
    }
    return HP_OK;
}
