/* The request check of every planner (plan_range.h): what hp_plan and hp_load_plan accept as
 * a desired correction, and the words of a refusal. */
#include "planner/planner_internal.h"

#include <math.h>

int hpi_plan_range_check(const hp_identifiable *id, const double xi[6], double *size)
{
    /* Every plan passes here, and most corrections are far inside both limits: a bound that
     * is cheap and provably no smaller than the exact quantity decides those without hypot
     * or building R (~1 000 instructions of a ~10 000-instruction direct chain). The
     * Euclidean norm is at most the sum of the magnitudes; the rotation angle, a metric on
     * rotations invariant under products, is at most the sum of the three elementary
     * angles. Half the limit leaves the exact values' rounding (a few ulps) far from it, so
     * the verdict is the exact one. NaN fails every comparison and falls through. */
    double t1 = fabs(xi[0]) + fabs(xi[1]) + fabs(xi[2]);
    double r1 = fabs(xi[3]) + fabs(xi[4]) + fabs(xi[5]);
    if (t1 <= 0.5 * id->trans_limit && (id->centre_only || r1 <= 0.5 * id->rot_limit)) return 0;
    double tn = hypot(hypot(xi[0], xi[1]), xi[2]);
    if (size) *size = tn;
    if (!(tn <= id->trans_limit)) return 1;
    if (id->centre_only) return 0;
    double ang = hp_pose_rotation_angle(xi);
    if (size) *size = ang;
    return ang < id->rot_limit ? 0 : 2;
}

int hpi_plan_range_ok(const hp_identifiable *id, const double xi[6], const char *what, char *err)
{
    double size;
    int out = hpi_plan_range_check(id, xi, &size);
    if (out == 1) {
        hpi_text_set(err, what);
        hpi_text_add(err, " translation: |(x, y, z)| = ");
        hpi_text_add_num(err, size * HP_MM_PER_M, 1);
        hpi_text_add(err, " mm is outside the identifiable range (<= ");
        hpi_text_add_num(err, id->trans_limit * HP_MM_PER_M, 1);
        hpi_text_add(err, " mm, the head's smallest semi-axis)");
        return 0;
    }
    if (out == 2) {
        hpi_text_set(err, what);
        hpi_text_add(err, " rotation: angle ");
        hpi_text_add_num(err, size * HP_DEG_PER_RAD, 1);
        hpi_text_add(err, " deg is outside the identifiable range (below ");
        hpi_text_add_num(err, id->rot_limit * HP_DEG_PER_RAD, 0);
        hpi_text_add(err, " deg: the head looks the same after ");
        hpi_text_add(err, id->symmetry);
        hpi_text_add(err, ", so the contact distances confuse such a turn with a smaller one)");
        return 0;
    }
    return 1;
}

const char *const hpi_pose_component_names[6] = {"x", "y", "z", "pitch", "roll", "yaw"};

int hpi_plan_pose_out_of_range(const double xi[6])
{
    for (int i = 0; i < 6; ++i) {
        double lim = i < 3 ? HP_PLAN_MAX_TRANS : HP_PLAN_MAX_ROT;
        if (!isfinite(xi[i]) || !(fabs(xi[i]) <= lim)) return i;
    }
    return -1;
}

int hpi_plan_desired_ok(const hp_identifiable *id, const double desired[6], char *err)
{
    int i = hpi_plan_pose_out_of_range(desired);
    if (i >= 0) {
        hpi_text_set(err, "desired ");
        hpi_text_add(err, hpi_pose_component_names[i]);
        hpi_text_add(err, isfinite(desired[i]) ? ": " HP_PLAN_RANGE_TEXT : ": not finite");
        return 0;
    }
    return hpi_plan_range_ok(id, desired, "desired", err);
}
