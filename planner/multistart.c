/* The restart points of the offline backends. Spread along the segment from the start's pose
 * to the desired pose: the closest reachable pose of a far target is a vertex of the curved
 * set the limits leave, and which vertex a local method reaches is decided by its first
 * linearisation (docs/planner.md, Convergence); starting partway along the correction
 * linearises the limits elsewhere and reaches other vertices. Deterministic: the same
 * program gives the same points, so a plan is reproducible. */
#include "planner/multistart.h"

void hpi_multistart_point(const hp_problem *pb, const double *xs, int j, int m, double *x)
{
    double f = ((double)j - 0.5) / (double)m;
    for (int i = 0; i < pb->nx; ++i) x[i] = xs[i];
    for (int i = 0; i < 6; ++i)
        if (pb->w[i] > 0.0) x[i] = xs[i] + f * (pb->d[i] - xs[i]);
}
