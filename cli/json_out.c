/* JSON values shared by the --json outputs (see json_out.h). */
#include "cli/json_out.h"
#include "headplan/hp_pose.h"

#include <math.h>

json_t *cli_json_pose(const double xi[6])
{
    double c[6];
    hp_pose_to_clinical(xi, c);
    json_t *o = json_object();
    for (int i = 0; i < 6; ++i) json_object_set_new(o, hp_pose_key(i), json_real(c[i]));
    return o;
}

json_t *cli_json_vec(const double *v, int n, double scale)
{
    json_t *a = json_array();
    for (int i = 0; i < n; ++i) json_array_append_new(a, json_real(v[i] * scale));
    return a;
}

json_t *cli_json_num(double v) { return isfinite(v) ? json_real(v) : json_null(); }
