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

json_t *cli_json_model_error(const cli_model_error *e)
{
    json_t *o = json_object();
    const hpi_fidelity_result *m = &e->m;
    json_object_set_new(o, "level", json_string(hp_level_name(e->level)));
    json_object_set_new(o, "measured", json_boolean(!*e->not_measured));
    json_object_set_new(o, "not_measured",
                        *e->not_measured ? json_string(e->not_measured) : json_null());
    json_object_set_new(o, "law", json_string("fitted"));
    json_object_set_new(o, "bounded", json_boolean(isfinite(m->pose_mm)));
    json_object_set_new(o, "pose_mm", cli_json_num(m->pose_mm));
    json_object_set_new(o, "pose_deg", cli_json_num(m->pose_deg));
    json_object_set_new(o, "law_band", json_real(CLI_FIDELITY_LAW_BAND));
    json_object_set_new(o, "band_mm", cli_json_num(m->band_mm));
    json_object_set_new(o, "band_deg", cli_json_num(m->band_deg));
    json_object_set_new(o, "domain", json_string(m->domain));
    json_object_set_new(o, "indent_max", cli_json_num(m->indent_max));
    json_object_set_new(o, "carried", cli_json_num(m->carried));
    json_object_set_new(o, "mass_kg", json_real(e->mass));
    json_object_set_new(o, "mass", json_string(e->own_mass ? "scene" : "default"));
    json_object_set_new(o, "solver_tolerance", json_real(e->tolerance));
    return o;
}
