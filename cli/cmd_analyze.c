/* headplan analyze: the layout analysis of a scene — conditioning of the contact Jacobian
 * (mm of radius change per mm and per degree), the weakest direction, the reach of each axis
 * inside the bladders' limits, the contact models' error bounds and the resolved geometry.
 * Command-line units: mm, degrees, Pa; the library speaks SI. */
#include "cli/cli_output.h"
#include "cli/analyze_load.h"
#include "common/units.h"
#include "cli/cli_args.h"
#include "cli/cli_fidelity.h"
#include "cli/cli_paths.h"
#include "cli/cli_scene.h"
#include "cli/cmd_solve_load.h"
#include "cli/json_out.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const CMD = "analyze";

/* The reach search caps of hp_layout_analyze (kinematics/analyze.c): a reach equal to one of
 * them means no limit was met inside it. Used only to label the human output. */

static const char *const SPHERE_NOTE =
    "sphere head: rotation about its centre cannot be commanded (pushing on a sphere cannot "
    "turn it); translation only, rank 3";

static void help(void)
{
    char names[96];
    printf("usage: headplan analyze SCENE [--level NAME] [--json]\n\n"
           "Analyses the bladder layout in SCENE (a YAML layout scene, scenes.md in the\n"
           "documentation) at its nominal pose: singular values, rank and condition number\n"
           "of the contact Jacobian (translation per mm, rotation per degree), the weakest\n"
           "direction, the largest correction along each axis inside every bladder's\n"
           "pressure and stretch limits (searched up to 50 mm and 30 deg), the error bounds\n"
           "of the linear and plane contact models and the level auto picks, the model\n"
           "error (the scene's plan held under the head's weight with the contact law\n"
           "fitted to the finite-element reference, beside the solver's tolerance; text\n"
           "only), and the resolved geometry (bladder centres, nominal contact points and\n"
           "normals). See kinematics.md and accuracy.md in the documentation.\n\n"
           "  --level NAME   contact model for the reach: %s;\n"
           "                 default: the scene's (auto resolves with the scene's tolerance);\n"
           "                 load (as solve plans it, load.md): the reach at the scene's\n"
           "                 kinematic level and the load section for the head's weight\n"
           "  --json         one JSON object on stdout instead of the text\n"
           "  --help         this text\n\n"
           "exit status: 0 ok, 64 bad command line, 65 bad scene or not a layout scene,\n"
           "66 scene cannot be read, 70 internal failure\n\n"
           "documentation: %s\n",
           hp_scene_level_names(1, " or ", names, sizeof names), cli_doc_dir());
}

typedef struct analyze_args {
    const char *scene, *level;
    int json;
} analyze_args;

/* Returns -1 to continue, or the exit status (0 after --help). */
static int parse(int argc, char **argv, analyze_args *a)
{
    static const char *const names[] = {"--level"};
    const char **const slots[] = {&a->level};
    return cli_scene_args(CMD, argc, argv, help, names, slots, 1, &a->json, &a->scene);
}

/* Everything one run reports besides the scene itself. */
typedef struct analysis {
    hp_scene_analysis x;  /* the library's analysis at the resolved level */
    int from_option;      /* 1 when --level gave it */
    int range_from_scene; /* 1: model.auto_*; 0: the planner's defaults (as solve uses) */
    int solve_load;       /* 1: solve plans this scene at the load level, not at level */
    char load_why[256];   /* why (cli_load_level) */
} analysis;

/* Resolves the level and the auto range from the planner settings the scene gives (the same
 * settings solve uses, so the level named here is the one a solve of this scene runs), then
 * runs the library's analysis. Returns -1 to continue, or the exit status. */
static int compute(const hp_scene *sc, const analyze_args *a, analysis *r)
{
    hp_settings s;
    /* --level load (as solve takes it) names the load level, not a contact level: the
     * reach is then analysed at the scene's kinematic level, as for a scene that says
     * model.level: load, and cli_load_level refuses it with solve's words on a scene
     * without a load section. */
    const int level_is_load = a->level && strcmp(a->level, HP_SCENE_LEVEL_LOAD) == 0;
    const char *kin_level = level_is_load ? NULL : a->level;
    int rc = cli_load_level(CMD, sc, a->level, &r->solve_load, r->load_why, sizeof r->load_why);
    if (rc) return rc;
    if ((rc = cli_settings(CMD, sc, NULL, kin_level, &s))) return rc;
    /* A load scene's kinematic level is its contact geometry; solve plans the load level. */
    if (s.level == HP_LEVEL_LOAD) s.level = sc->level;
    r->from_option = kin_level != NULL;
    r->range_from_scene = sc->has_auto_range;
    hp_diag d = {{0}};
    if (hp_scene_analyze(&sc->layout, &s, &r->x, &d) != HP_OK)
        return cli_fail(CLI_EXIT_SOFTWARE, CMD, "%s: %s", cli_name(a->scene), d.text);
    return -1;
}

/* Bladder k's nominal contact point, normal and distance, derived from the (validated)
 * scene layout; NaN should it fail. */
static void nominal_contact(const hp_layout *L, int k, double pt[3], double nv[3], double *rho0)
{
    if (hp_layout_contact(L, k, pt, nv, rho0) == HP_OK) return;
    for (int i = 0; i < 3; ++i) pt[i] = nv[i] = NAN;
    *rho0 = NAN;
}

static json_t *geometry_bladders_json(const hp_layout *L)
{
    json_t *bl = json_array();
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        json_t *e = json_object();
        json_object_set_new(e, "name", json_string(B->name));
        json_object_set_new(e, "center_mm", cli_json_vec(B->center, 3, 1e3));
        json_object_set_new(e, "Ri_mm", json_real(B->iab.Ri * 1e3));
        json_object_set_new(e, "Ro_mm", json_real(B->iab.Ro * 1e3));
        json_object_set_new(e, "c1_pa", json_real(B->iab.C1));
        json_object_set_new(e, "c2_pa", json_real(B->iab.C2));
        json_object_set_new(e, "pressure_min_pa", json_real(B->p_min));
        json_object_set_new(e, "pressure_max_pa", json_real(B->p_max));
        json_object_set_new(e, "stretch_min", json_real(B->stretch_min));
        json_object_set_new(e, "stretch_max", json_real(B->stretch_max));
        double pt[3], nv[3], rho0;
        nominal_contact(L, k, pt, nv, &rho0);
        json_object_set_new(e, "contact_mm", cli_json_vec(pt, 3, 1e3));
        json_object_set_new(e, "normal", cli_json_vec(nv, 3, 1.0));
        json_object_set_new(e, "rho0_mm", json_real(rho0 * 1e3));
        json_array_append_new(bl, e);
    }
    return bl;
}

static json_t *head_json(const hp_head *h)
{
    json_t *o = json_object();
    json_object_set_new(o, "shape", json_string(hp_head_shape_name(h->shape)));
    json_object_set_new(o, "center_mm", cli_json_vec(h->center, 3, 1e3));
    if (h->shape == HP_HEAD_SPHERE)
        json_object_set_new(o, "radius_mm", json_real(h->semi_axes[0] * 1e3));
    else json_object_set_new(o, "semi_axes_mm", cli_json_vec(h->semi_axes, 3, 1e3));
    json_object_set_new(o, "mass_kg", h->mass > 0 ? json_real(h->mass) : json_null());
    return o;
}

#define DEG_PER_RAD HP_DEG_PER_RAD

/* Unobservable motion m in mm and degrees, scaled so its largest component is 1 (sign:
 * that component positive), so that it reads "per degree" or "per mm". */
static void null_clinical(const hp_identifiable *id, int m, double c[6])
{
    hp_pose_to_clinical(id->null_space[m], c);
    int big = 0;
    for (int i = 1; i < 6; ++i)
        if (fabs(c[i]) > fabs(c[big]) * (1.0 + 1e-12)) big = i;
    double s = c[big];
    for (int i = 0; i < 6; ++i) c[i] = s != 0 ? c[i] / s : 0.0;
}

/* The identifiable range (hp_identifiable) as JSON: mm and degrees. */
static json_t *identifiable_json(const hp_identifiable *id)
{
    json_t *o = json_object();
    json_object_set_new(o, "rank", json_integer(id->rank));
    json_object_set_new(o, "relative_singular_values", cli_json_vec(id->rel_sv, 6, 1.0));
    json_t *cmd = json_object();
    for (int i = 0; i < 6; ++i)
        json_object_set_new(cmd, hp_pose_key(i), json_boolean(id->commanded[i]));
    json_object_set_new(o, "commanded", cmd);
    json_t *un = json_array();
    for (int m = 0; m < id->n_null; ++m) {
        double c[6];
        null_clinical(id, m, c);
        json_t *v = json_object();
        for (int i = 0; i < 6; ++i) json_object_set_new(v, hp_pose_key(i), json_real(c[i]));
        json_array_append_new(un, v);
    }
    json_object_set_new(o, "unobservable_motions", un);
    json_object_set_new(o, "only_centre_motion", json_boolean(id->centre_only));
    json_object_set_new(o, "rotation_angle_below_deg",
                        id->centre_only ? json_null() : json_real(id->rot_limit * DEG_PER_RAD));
    json_object_set_new(o, "translation_norm_max_mm", json_real(id->trans_limit * 1e3));
    json_object_set_new(o, "head_symmetry", json_string(id->symmetry));
    return o;
}

static int print_json(const hp_scene *sc, const analysis *r)
{
    const hp_layout *L = &sc->layout;
    const hp_layout_analysis *an = &r->x.an;
    json_t *o = json_object();
    json_object_set_new(o, "scene", json_string(sc->name));
    json_object_set_new(o, "level", json_string(hp_level_name(r->x.level)));
    json_object_set_new(o, "level_requested", json_string(hp_level_name(r->x.requested)));
    json_object_set_new(o, "level_source", json_string(r->from_option ? "option" : "scene"));
    json_object_set_new(o, "solve_level",
                        json_string(r->solve_load ? "load" : hp_level_name(r->x.level)));
    json_object_set_new(o, "singular_values", cli_json_vec(an->singular_values, 6, 1.0));
    json_object_set_new(o, "rank", json_integer(an->rank));
    json_object_set_new(o, "condition",
                        isfinite(an->condition) ? json_real(an->condition) : json_null());
    json_t *w = json_object();
    json_object_set_new(w, "vector", cli_json_vec(an->weakest, 6, 1.0));
    json_object_set_new(w, "phrase", json_string(an->weakest_words));
    json_object_set_new(w, "singular_value", json_real(an->singular_values[5]));
    json_object_set_new(o, "weakest_direction", w);
    json_object_set_new(o, "rotation_commandable", json_boolean(an->rotation_commandable));
    json_object_set_new(o, "note",
                        an->rotation_commandable ? json_null() : json_string(SPHERE_NOTE));
    json_t *reach = json_object();
    for (int i = 0; i < 6; ++i) {
        if (isnan(an->reach[i][0])) {
            json_object_set_new(reach, hp_pose_key(i), json_null()); /* not commanded */
            continue;
        }
        json_object_set_new(reach, hp_pose_key(i), cli_json_vec(an->reach[i], 2, 1.0));
    }
    json_object_set_new(o, "reach", reach);
    json_object_set_new(o, "identifiable", identifiable_json(&r->x.id));
    json_t *b = json_object();
    json_object_set_new(b, "tolerance_mm", json_real(sc->level_tolerance * 1e3));
    json_object_set_new(b, "translation_mm", json_real(r->x.trans * 1e3));
    json_object_set_new(b, "rotation_deg", json_real(r->x.rot * 180.0 / HP_PI));
    json_object_set_new(b, "range_source", json_string(r->range_from_scene ? "scene" : "default"));
    for (int l = 0; l < HP_LEVEL_COUNT_; ++l) {
        if (!hp_level_is_geometry((hp_level)l)) continue;
        char key[32];
        snprintf(key, sizeof key, "%s_mm", hp_level_name((hp_level)l));
        json_object_set_new(b, key, json_real(r->x.bound[l] * 1e3));
    }
    json_object_set_new(b, "auto_level", json_string(hp_level_name(r->x.auto_level)));
    json_object_set_new(o, "error_bounds", b);
    json_object_set_new(o, "head", head_json(&L->head));
    json_object_set_new(o, "pivot_mm", cli_json_vec(L->pivot, 3, 1e3));
    json_object_set_new(o, "bladders", geometry_bladders_json(L));
    json_t *load = cli_analyze_load_json(sc);
    json_object_set_new(o, "load", load ? load : json_null());
    char *s = json_dumps(o, JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(CLI_JSON_REAL_PRECISION));
    json_decref(o);
    if (!s) return cli_fail(CLI_EXIT_SOFTWARE, CMD, "cannot format JSON output");
    cli_put_line(s);
    free(s);
    return CLI_EXIT_OK;
}

static void print_vec3(const char *label, const double v[3], double scale, const char *unit)
{
    printf("%-13s (%.4f, %.4f, %.4f)%s%s\n", label, v[0] * scale, v[1] * scale, v[2] * scale,
           *unit ? " " : "", unit);
}

static void print_text(const hp_scene *sc, const analysis *r)
{
    const hp_layout *L = &sc->layout;
    const hp_head *h = &L->head;
    const hp_layout_analysis *an = &r->x.an;
    printf("%-13s %s\n", "scene", sc->name);
    if (h->shape == HP_HEAD_SPHERE)
        printf("%-13s sphere, radius %.4f mm\n", "head", h->semi_axes[0] * 1e3);
    else
        printf("%-13s ellipsoid, semi-axes %.4f x %.4f x %.4f mm\n", "head", h->semi_axes[0] * 1e3,
               h->semi_axes[1] * 1e3, h->semi_axes[2] * 1e3);
    print_vec3("head centre", h->center, 1e3, "mm");
    print_vec3("pivot", L->pivot, 1e3, "mm");
    printf("%-13s %s", "level", hp_level_name(r->x.level));
    if (r->x.requested == HP_LEVEL_AUTO) printf(" (auto)");
    printf(", from the %s\n", r->from_option ? "--level option" : "scene");
    if (r->solve_load)
        printf("%-13s solve plans this scene at the load level (%s); the reach below is "
               "kinematic, the load section at the end is what solve holds\n",
               "note", r->load_why);

    printf("\ncontact Jacobian at the nominal pose (mm of radius per mm and per degree)\n");
    printf("%-13s", "singular");
    for (int j = 0; j < 6; ++j) printf(" %10.6f", an->singular_values[j]);
    printf("\n%-13s %d of 6\n", "rank", an->rank);
    if (isfinite(an->condition)) printf("%-13s %.6g\n", "condition", an->condition);
    else printf("%-13s infinite (rank < 6)\n", "condition");
    printf("%-13s %s%s\n", "weakest", an->weakest_words,
           an->rank < 6 ? " (not observable: singular value 0)" : "");
    printf("%-13s", "  vector");
    for (int j = 0; j < 6; ++j) printf(" %s %+.4f", hp_pose_key(j), an->weakest[j]);
    printf("\n");
    if (!an->rotation_commandable) printf("%-13s %s\n", "note", SPHERE_NOTE);

    const hp_identifiable *id = &r->x.id;
    printf("\nidentifiable range: the corrections the contact distances tell apart\n");
    printf("%-13s %d of 6 (dimensionless, head-centred: independent of units, scale, pivot)\n",
           "rank", id->rank);
    printf("%-13s", "commanded");
    for (int i = 0; i < 6; ++i) printf(" %s%s", hp_pose_key(i), id->commanded[i] ? "" : "(no)");
    printf("\n");
    for (int m = 0; m < id->n_null; ++m) {
        double c[6];
        null_clinical(id, m, c);
        printf("%-13s", m == 0 ? "unobservable" : "");
        for (int i = 0; i < 6; ++i) printf(" %+.4f", c[i]);
        printf("  (mm, deg)\n");
    }
    printf("%-13s %s\n", "symmetry", id->symmetry);
    if (id->centre_only)
        printf("%-13s none identified: only the motion of the head centre is seen; a turn "
               "about the centre is reported as not commanded\n",
               "rotation");
    else
        printf("%-13s angle below %.4g deg (any axis; a half-turn maps the head onto "
               "itself)\n",
               "rotation", id->rot_limit * DEG_PER_RAD);
    printf("%-13s |(x, y, z)| up to %.4f mm (the head's smallest semi-axis)\n", "translation",
           id->trans_limit * 1e3);

    printf("\nreach inside every bladder's limits, as %s (level %s)\n",
           r->solve_load ? "a kinematic plan" : "solve plans", hp_level_name(r->x.level));
    printf("%-13s %12s %12s\n", "axis", "negative", "positive");
    for (int i = 0; i < 6; ++i) {
        if (isnan(an->reach[i][0])) {
            printf("%-13s %25s\n", hp_pose_key(i), "not commanded");
            continue;
        }
        double cap = i < 3 ? HP_REACH_CAP_MM : HP_REACH_CAP_DEG;
        int capped = an->reach[i][0] <= -cap || an->reach[i][1] >= cap;
        printf("%-13s %12.4f %12.4f%s\n", hp_pose_key(i), an->reach[i][0], an->reach[i][1],
               capped ? "  (search cap reached)" : "");
    }

    printf("\nerror bounds against the exact surface, corrections up to %.4g mm and %.4g deg"
           " (%s)\n",
           r->x.trans * 1e3, r->x.rot * 180.0 / HP_PI,
           r->range_from_scene ? "model.auto_translation_mm/auto_rotation_deg"
                               : "default range: the scene states none");
    for (int l = 0; l < HP_LEVEL_COUNT_; ++l) {
        if (!hp_level_is_geometry((hp_level)l)) continue;
        /* The exact distance's bound is 0 by definition, which the text says in words. */
        if (l == HP_LEVEL_SURFACE) printf("%-13s 0 (exact)\n", hp_level_name((hp_level)l));
        else printf("%-13s %.6g mm\n", hp_level_name((hp_level)l), r->x.bound[l] * 1e3);
    }
    printf("%-13s %s (tolerance %.6g mm)\n", "auto picks", hp_level_name(r->x.auto_level),
           sc->level_tolerance * 1e3);
    char model[HP_DIAG_MAX + 256];
    cli_fidelity_text(sc, r->solve_load ? HP_LEVEL_LOAD : r->x.level, model, sizeof model);
    printf("%-13s %s\n", "model error", model);

    printf("\n%-18s %-30s %-30s %-28s %6s %6s %8s %8s %8s %8s\n", "bladder", "centre_mm",
           "contact_mm", "normal", "Ri_mm", "Ro_mm", "C1_pa", "C2_pa", "Pmin_pa", "Pmax_pa");
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        char c[64], p[64], n[64];
        double pt[3], nv[3], rho0;
        nominal_contact(L, k, pt, nv, &rho0);
        snprintf(c, sizeof c, "(%.3f, %.3f, %.3f)", B->center[0] * 1e3, B->center[1] * 1e3,
                 B->center[2] * 1e3);
        snprintf(p, sizeof p, "(%.3f, %.3f, %.3f)", pt[0] * 1e3, pt[1] * 1e3, pt[2] * 1e3);
        snprintf(n, sizeof n, "(%.4f, %.4f, %.4f)", nv[0], nv[1], nv[2]);
        printf("%-18s %-30s %-30s %-28s %6.2f %6.2f %8.0f %8.0f %8.0f %8.0f\n", B->name, c, p, n,
               B->iab.Ri * 1e3, B->iab.Ro * 1e3, B->iab.C1, B->iab.C2, B->p_min, B->p_max);
    }
    cli_analyze_load_text(sc);
}

int cmd_analyze(int argc, char **argv)
{
    analyze_args a = {0};
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    /* An unknown --level is a usage error even when the scene is also bad: check it first. */
    hp_level lv;
    char names[96];
    if (a.level && strcmp(a.level, HP_SCENE_LEVEL_LOAD) != 0 && hp_level_parse(a.level, &lv))
        return cli_fail(CLI_EXIT_USAGE, CMD, "--level: unknown level '%s' (%s)", a.level,
                        hp_scene_level_names(1, ", ", names, sizeof names));

    hp_scene *sc = NULL;
    if ((rc = cli_load_scene(CMD, a.scene, "%s: analyze needs a layout scene (head and bladders)",
                             &sc)))
        return rc;
    analysis r;
    memset(&r, 0, sizeof r);
    rc = compute(sc, &a, &r);
    if (rc < 0) {
        if (a.json) rc = print_json(sc, &r);
        else {
            print_text(sc, &r);
            rc = CLI_EXIT_OK;
        }
    }
    free(sc);
    return rc;
}
