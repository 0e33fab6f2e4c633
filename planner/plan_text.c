/* The round trip's message (hpi_plan_trip_text), built without allocating (text.h). */
#include "planner/planner_internal.h"

#include <math.h>
#include <string.h>

/* "(x, y, z) mm (pitch, roll, yaw) deg, W mm/deg away" of a round trip's end, with 9 decimals
 * (a reader can evaluate the distances there to ~1e-8 mm). */
static void add_trip_end(char *buf, const hp_plan_trip *t)
{
    double x[6];
    hpi_plan_to_scaled(t->end, x);
    hpi_text_add(buf, "(");
    for (int i = 0; i < 6; ++i) {
        hpi_text_add_num(buf, x[i], 9);
        hpi_text_add(buf, i == 2 ? ") mm (" : i == 5 ? ") deg, " : ", ");
    }
    hpi_text_add_num(buf, t->worst, 6);
    hpi_text_add(buf, " mm/deg away");
}

void hpi_plan_trip_text(char *buf, const hp_plan_trip *t)
{
    hpi_text_add(buf, "forward contact kinematics from the nominal pose ");
    if (!isfinite(t->worst)) {
        hpi_text_add(buf, "did not converge, so it cannot confirm these pressures' pose");
        return;
    }
    if (t->gap_mm <= HP_IDENT_NAME_MM) {
        hpi_text_add(buf, "finds another pose, ");
        add_trip_end(buf, t);
        hpi_text_add(buf, ", whose contact distances match these pressures' to within 1 nm");
        return;
    }
    hpi_text_add(buf, "stalled at ");
    add_trip_end(buf, t);
    if (isfinite(t->gap_mm)) {
        hpi_text_add(buf, ", where its contact distances miss these pressures' by ");
        hpi_text_add_num(buf, t->gap_mm, 6);
        hpi_text_add(buf, " mm");
    } else {
        hpi_text_add(buf, ", where its contact distances cannot be evaluated");
    }
    hpi_text_add(buf, ", so it cannot confirm their pose");
}
