/* The restart points of the offline backends. Spread along the segment from the start's pose
 * to the desired pose: the closest reachable pose of a far target is a vertex of the curved
 * set the limits leave, and which vertex a local method reaches is decided by its first
 * linearisation (docs/planner.md, Convergence); starting partway along the correction
 * linearises the limits elsewhere and reaches other vertices. The fractions are the base-2
 * van der Corput sequence (1/2, 1/4, 3/4, 1/8, 5/8, ...), so the points of m restarts are
 * among those of m + 1: more restarts never lose a start, and as the best answer is kept,
 * never give a worse one. Deterministic: the same program gives the same points. */
#include "planner/multistart.h"

void hpi_multistart_point(const hp_problem *pb, const double *xs, int j, double *x)
{
    double f = 0.0, scale = 0.5;
    for (unsigned k = (unsigned)j; k > 0; k >>= 1, scale *= 0.5)
        if (k & 1u) f += scale;
    for (int i = 0; i < pb->nx; ++i) x[i] = xs[i];
    for (int i = 0; i < 6; ++i)
        if (pb->w[i] > 0.0) x[i] = xs[i] + f * (pb->d[i] - xs[i]);
}
