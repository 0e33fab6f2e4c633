/* Example: plan one head correction with the installed headplan library.
 *
 * Builds the paper's eight-bladder layout on the default adult head in code, creates a
 * realtime planner, asks for a 1 mm lateral shift with 0.5 degrees of yaw, and prints every
 * bladder's pressure. Then asks for a correction far beyond reach and prints the closest
 * reachable pose and the limits that bind. Exit status 0 when both answers are as expected.
 *
 * Build against an installed headplan: see examples/CMakeLists.txt (find_package) or
 *   cc plan_correction.c $(pkg-config --cflags --libs headplan) -lm */
#include <headplan/headplan.h>
#include <headplan/hp_planner.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Touch points (unit-sphere directions scaled onto the ellipsoid) of the eight bladders. */
static int build_layout(hp_layout *L)
{
    static const char *const names[8] = {"base_neck_left",   "base_neck_right", "base_skull_left",
                                         "base_skull_right", "side_fore_left",  "side_fore_right",
                                         "side_chin_left",   "side_chin_right"};
    static const double dir[8][3] = {{0.35, -0.45, -1}, {-0.35, -0.45, -1}, {0.35, 0.45, -1},
                                     {-0.35, 0.45, -1}, {1, 0.45, 0.15},    {-1, 0.45, 0.15},
                                     {1, -0.45, -0.15}, {-1, -0.45, -0.15}};
    memset(L, 0, sizeof *L);
    L->head.shape = HP_HEAD_ELLIPSOID;
    L->head.semi_axes[0] = HP_HEAD_DEFAULT_A;
    L->head.semi_axes[1] = HP_HEAD_DEFAULT_B;
    L->head.semi_axes[2] = HP_HEAD_DEFAULT_C;
    L->head.mass = HP_HEAD_DEFAULT_MASS;
    L->n = 8;
    for (int k = 0; k < 8; ++k) {
        hp_bladder *B = &L->bladders[k];
        snprintf(B->name, sizeof B->name, "%s", names[k]);
        B->iab = (hp_iab){.Ri = 0.027, .Ro = 0.030, .C1 = 1.1e4, .C2 = 2.2e4};
        B->p_min = -5e3;
        B->p_max = 10e3;
        B->stretch_min = 0.8;
        B->stretch_max = 1.3;
        B->rate_max = INFINITY;
        /* the surface point on the ray from the centre along dir */
        double s = 0, p[3];
        for (int i = 0; i < 3; ++i) s += pow(dir[k][i] / L->head.semi_axes[i], 2);
        for (int i = 0; i < 3; ++i) p[i] = dir[k][i] / sqrt(s);
        hp_diag d;
        if (hp_head_center_from_touch(&L->head, p, B->iab.Ro, 0.0, B->center, &d) != HP_OK) {
            fprintf(stderr, "example: %s: %s\n", B->name, d.text);
            return 1;
        }
    }
    hp_diag d;
    if (hp_layout_prepare(L, &d) != HP_OK) {
        fprintf(stderr, "example: layout: %s\n", d.text);
        return 1;
    }
    return 0;
}

static void show(const hp_layout *L, const hp_result *r, const hp_planner *p)
{
    double a[6];
    hp_pose_to_clinical(r->achieved, a);
    printf("status %s (%s)\n", hp_status_name(r->status),
           *hp_planner_note(p) ? hp_planner_note(p) : hp_planner_error(p));
    for (int k = 0; k < L->n; ++k)
        printf("  %-18s %10.2f Pa%s\n", L->bladders[k].name, r->bladders[k].pressure,
               r->bladders[k].binding ? "  (on a limit)" : "");
    printf("  achieved: %.4f %.4f %.4f mm, %.4f %.4f %.4f deg\n", a[0], a[1], a[2], a[3], a[4],
           a[5]);
}

int main(void)
{
    hp_layout L;
    if (build_layout(&L)) return 1;
    hp_settings s;
    hp_settings_default(&s);
    hp_planner *p = NULL;
    hp_diag d;
    if (hp_planner_create(&L, &s, &p, &d) != HP_OK) {
        fprintf(stderr, "example: planner: %s\n", d.text);
        return 1;
    }
    printf("headplan %s\n", hp_version());
    const double small[6] = {1.0, 0, 0, 0, 0, 0.5}, far[6] = {25.0, 0, 0, 0, 0, 0};
    double xi[6];
    hp_result r;
    int ok = 1;
    hp_pose_from_clinical(small, xi);
    ok &= hp_plan(p, xi, &r) == HP_OK && r.status == HP_STATUS_REACHED;
    show(&L, &r, p);
    hp_pose_from_clinical(far, xi);
    ok &= hp_plan(p, xi, &r) == HP_OK && r.status == HP_STATUS_CLOSEST;
    show(&L, &r, p);
    hp_planner_destroy(p);
    return ok ? 0 : 1;
}
