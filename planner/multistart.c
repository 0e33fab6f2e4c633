/* The restarts of the offline backends. Spread along the segment from the start's pose to the
 * desired pose: the closest reachable pose of a far target is a vertex of the curved set the
 * limits leave, and which vertex a local method reaches is decided by its first
 * linearisation (docs/planner.md, Convergence); starting partway along the correction
 * linearises the limits elsewhere and reaches other vertices. The fractions are the base-2
 * van der Corput sequence (1/2, 1/4, 3/4, 1/8, 5/8, ...), so the points of m restarts are
 * among those of m + 1: more restarts never lose a start, and as the best answer is kept,
 * never give a worse one. Deterministic: the same program gives the same points. */
#include "planner/multistart.h"
#include "planner/backend_common.h"
#include "planner/clock.h"

#include <math.h>
#include <string.h>

void hpi_multistart_point(const hp_problem *pb, const double *xs, int j, double *x)
{
    double f = 0.0, scale = 0.5;
    for (unsigned k = (unsigned)j; k > 0; k >>= 1, scale *= 0.5)
        if (k & 1u) f += scale;
    for (int i = 0; i < pb->nx; ++i) x[i] = xs[i];
    for (int i = 0; i < 6; ++i)
        if (pb->w[i] > 0.0) x[i] = xs[i] + f * (pb->d[i] - xs[i]);
}

/* The objective at v, +inf when it cannot be evaluated. */
static double objective_at(const hp_problem *pb, const double *v)
{
    double f;
    return hpi_problem_objective(pb, v, &f, NULL, NULL) == HP_OK && isfinite(f) ? f : HUGE_VAL;
}

int hpi_multistart_run(const hp_problem *pb, const double *xs, int restarts, double t0,
                       double max_time, double tol, hpi_multistart_solve solve, void *ctx,
                       double *v, hp_backend_result *r, int *ran)
{
    *ran = 0;
    if (restarts <= 0 || !r->converged) return 0;
    int binds = 0;
    for (int k = 0; k < pb->n; k++)
        binds |= !(v[6 + k] - pb->ri_lo[k] > HP_BINDING_TOL_MM &&
                   pb->ri_hi[k] - v[6 + k] > HP_BINDING_TOL_MM);
    if (!binds) return 0;
    double best = objective_at(pb, v);
    int kept = 0;
    for (int j = 1; j <= restarts; j++) {
        double left = max_time - (hpi_plan_now() - t0);
        if (!(left > 0.0)) break;
        double xj[HP_PROBLEM_NX_MAX], vj[HP_PROBLEM_NX_MAX];
        hp_backend_result rj = *r;
        hpi_multistart_point(pb, xs, j, xj);
        hpi_backend_clip(pb, xj);
        if (!solve(ctx, pb, xj, left, vj, &rj)) break;
        ++*ran;
        r->iterations += rj.iterations;
        double f = objective_at(pb, vj);
        /* Better by more than rounding: 1e-12 of the objective (a squared distance). */
        if (!rj.converged || !(f < best * (1.0 - 1e-12)) ||
            !hpi_backend_first_order_ok(pb, vj, tol))
            continue;
        best = f;
        kept = j;
        memcpy(v, vj, (size_t)pb->nx * sizeof *v);
        r->status = rj.status;
        r->raw_code = rj.raw_code;
    }
    return kept;
}
