/* The load level's stable walk (load_walk.h): candidate pressures on a segment, each
 * answered by the forward statics' rest from the previous answer's pose, kept when the
 * caller's checks accept the rest and it is the nearest to the desired pose so far. An answer so found is a
 * pose its pressures really hold, by construction. No allocation. */
#include "planner/load_walk.h"

#include <math.h>
#include <string.h>

double hpi_load_pose_err(const double xi[6], const double desired[6], const double W[6])
{
    double e = 0.0;
    for (int i = 0; i < 6; ++i) {
        double v = (xi[i] - desired[i]) / hpi_load_unit(i);
        e += W[i] * v * v;
    }
    return e;
}

/* One candidate: the rest of P from xi0. 1 when it replaced *best. */
static int try_rest(const hp_load_model *M, const double *P, const double xi0[6],
                    const hpi_load_walk_goal *g, hpi_load_pick *best)
{
    double rest[6];
    if (hp_load_rest(M, P, xi0, rest, NULL) != HP_OK) return 0;
    double e = hpi_load_pose_err(rest, g->desired, g->W);
    if (!(e < best->err) || !g->check(g->ctx, rest, P)) return 0;
    best->err = e;
    memcpy(best->xi, rest, sizeof best->xi);
    memcpy(best->P, P, (size_t)M->layout.n * sizeof *P);
    return 1;
}

int hpi_load_walk(const hp_load_model *M, const double *prev_P, const double prev_xi[6],
                  const double *goal_P, const double *lo, const double *hi,
                  const hpi_load_walk_goal *g, hpi_load_pick *best)
{
    int got = 0;
    for (int j = HP_LOAD_WALK_STEPS; j >= 0; --j) {
        const double t = (double)j / HP_LOAD_WALK_STEPS;
        double Pc[HP_MAX_BLADDERS];
        for (int k = 0; k < M->layout.n; ++k)
            Pc[k] = fmin(fmax(prev_P[k] + t * (goal_P[k] - prev_P[k]), lo[k]), hi[k]);
        got |= try_rest(M, Pc, prev_xi, g, best);
    }
    return got;
}
