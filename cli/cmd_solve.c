/* headplan solve: a scene file -> every bladder's pressure for one desired correction, the
 * achieved pose and the status. Command-line units: mm and degrees; the library speaks SI. */
#include "cli/cli_output.h"
#include "cli/cli_fidelity.h"
#include "cli/cli_args.h"
#include "cli/cli_paths.h"
#include "cli/cli_scene.h"
#include "cli/json_out.h"
#include "cli/cmd_solve_load.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const CMD = "solve";

static void help(void)
{
    char names[96], backends[96];
    hp_settings def;
    hp_settings_default(&def);
    printf("usage: headplan solve SCENE [--correction X,Y,Z,PITCH,ROLL,YAW] [--backend NAME]\n"
           "                      [--level NAME] [--json]\n\n"
           "Plans the bladder pressures that produce one desired head correction for the\n"
           "layout in SCENE (a YAML scene file, scenes.md in the documentation), inside every\n"
           "bladder's pressure and stretch limits. When the correction is out of reach the\n"
           "answer is the closest reachable one, and the limits that bind are named. A single\n"
           "solve starts from the nominal pose: per-cycle rate limits do not apply (see\n"
           "headplan batch).\n\n"
           "  --correction X,Y,Z,PITCH,ROLL,YAW  desired correction, mm and degrees (pitch\n"
           "                 about X, roll about Y, yaw about Z); default: the scene's\n"
           "  --backend NAME %s;\n"
           "                 default: %s unless the scene says\n"
           "  --level NAME   contact model: %s (the head's\n"
           "                 weight, load.md); default: the scene's\n"
           "  --json         one JSON object on stdout instead of the tables\n"
           "  --help         this text\n\n"
           "A correction outside the layout's identifiable range (headplan analyze) is refused.\n"
           "The part of a correction the layout cannot observe (e.g. a sphere's turn about its\n"
           "centre) is not commanded: it is shown, and the status is 'uncommanded'.\n\n"
           "Beside the solver's error the answer states its model error: the head let go\n"
           "under its weight with the answer's pressures held, on the contact law fitted to\n"
           "the finite-element reference, rests that far from the achieved pose (mm, deg;\n"
           "'unbounded' when it finds no rest), with the fitted law's own band.\n\n"
           "exit status: 0 reached, 1 only the closest reachable correction, 2 uncommanded\n"
           "(the commanded part reached, the rest not observable), 64 bad command line, 65 bad\n"
           "scene or correction (also outside the identifiable range), 66 scene cannot be\n"
           "read, 70 solver failure\n\n"
           "documentation: %s\n"
           "example scenes: %s\n",
           cli_backend_names(" or ", backends, sizeof backends), hp_backend_name(def.backend),
           hp_scene_level_names(1, " or ", names, sizeof names), cli_doc_dir(), cli_scene_dir());
}

typedef struct solve_args {
    const char *scene, *correction, *backend, *level;
    int json;
} solve_args;

/* Returns -1 to continue, or the exit status (0 after --help). */
static int parse(int argc, char **argv, solve_args *a)
{
    static const char *const names[] = {"--correction", "--backend", "--level"};
    const char **const slots[] = {&a->correction, &a->backend, &a->level};
    return cli_scene_args(CMD, argc, argv, help, names, slots, 3, &a->json, &a->scene);
}

static json_t *binding_json(unsigned flags)
{
    json_t *a = json_array();
    for (int b = 0; b < HP_BIND_COUNT; ++b)
        if (flags & (1u << b)) json_array_append_new(a, json_string(hp_binding_name(1u << b)));
    return a;
}

/* Component i of the correction is (partly) outside what the layout commands: its error is
 * the uncommanded part, not a miss. u is clinical (mm, deg). */
static int uncommanded_axis(const double u[6], int i) { return fabs(u[i]) > HP_DEFAULT_TOLERANCE; }

static int print_json(const hp_layout *L, const hp_result *r, const char *msg,
                      const char *level_why, const cli_model_error *me)
{
    json_t *o = json_object();
    json_object_set_new(o, "status", json_string(hp_status_name(r->status)));
    json_object_set_new(o, "backend", json_string(hp_backend_name(r->backend)));
    json_object_set_new(o, "level", json_string(hp_level_name(r->level)));
    json_object_set_new(o, "level_choice", *level_why ? json_string(level_why) : json_null());
    json_object_set_new(o, "desired", cli_json_pose(r->desired));
    json_object_set_new(o, "achieved", cli_json_pose(r->achieved));
    double err[6];
    for (int i = 0; i < 6; ++i) err[i] = r->achieved[i] - r->desired[i];
    json_object_set_new(o, "error", cli_json_pose(err)); /* achieved − desired, as the table */
    json_t *cmd = json_object();
    for (int i = 0; i < 6; ++i)
        json_object_set_new(cmd, hp_pose_key(i), json_boolean(r->commanded[i]));
    json_object_set_new(o, "commanded", cmd);
    json_object_set_new(o, "uncommanded", cli_json_pose(r->uncommanded));
    json_t *ud = json_array();
    double u[6];
    hp_pose_to_clinical(r->uncommanded, u);
    for (int i = 0; i < 6; ++i)
        if (uncommanded_axis(u, i)) json_array_append_new(ud, json_string(hp_pose_key(i)));
    json_object_set_new(o, "uncommanded_directions", ud);
    json_object_set_new(o, "model_error", cli_json_model_error(me));
    json_t *bl = json_array();
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        const hp_bladder_result *b = &r->bladders[k];
        json_t *e = json_object();
        json_object_set_new(e, "name", json_string(B->name));
        json_object_set_new(e, "center_mm", cli_json_vec(B->center, 3, 1e3));
        json_object_set_new(e, "Ri_mm", json_real(B->iab.Ri * 1e3));
        json_object_set_new(e, "Ro_mm", json_real(B->iab.Ro * 1e3));
        json_object_set_new(e, "c1_pa", json_real(B->iab.C1));
        json_object_set_new(e, "c2_pa", json_real(B->iab.C2));
        json_object_set_new(e, "pressure_min_pa", json_real(B->p_min));
        json_object_set_new(e, "pressure_max_pa", json_real(B->p_max));
        json_object_set_new(e, "ri_mm", json_real(b->ri * 1e3));
        json_object_set_new(e, "ro_mm", json_real(b->ro * 1e3));
        json_object_set_new(e, "pressure_pa", json_real(b->pressure));
        json_object_set_new(e, "binding", binding_json(b->binding));
        json_array_append_new(bl, e);
    }
    json_object_set_new(o, "bladders", bl);
    json_t *h = json_object();
    json_object_set_new(h, "shape", json_string(hp_head_shape_name(L->head.shape)));
    json_object_set_new(h, "center_mm", cli_json_vec(L->head.center, 3, 1e3));
    if (L->head.shape == HP_HEAD_SPHERE)
        json_object_set_new(h, "radius_mm", json_real(L->head.semi_axes[0] * 1e3));
    else json_object_set_new(h, "semi_axes_mm", cli_json_vec(L->head.semi_axes, 3, 1e3));
    json_object_set_new(o, "head", h);
    json_object_set_new(o, "pivot_mm", cli_json_vec(L->pivot, 3, 1e3));
    json_object_set_new(o, "iterations", json_integer(r->iterations));
    json_object_set_new(o, "solve_time_us", json_real(r->solve_time * 1e6));
    json_object_set_new(o, "message", json_string(msg));
    char *s = json_dumps(o, JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(CLI_JSON_REAL_PRECISION));
    json_decref(o);
    if (!s) return cli_fail(CLI_EXIT_SOFTWARE, CMD, "cannot format JSON output");
    cli_put_line(s);
    free(s);
    return 0;
}

static void print_table(const hp_layout *L, const hp_result *r, const char *msg,
                        const cli_model_error *me)
{
    double d[6], a[6], u[6];
    hp_pose_to_clinical(r->desired, d);
    hp_pose_to_clinical(r->achieved, a);
    hp_pose_to_clinical(r->uncommanded, u);
    printf("status      %s%s%s\n", hp_status_name(r->status), *msg ? " — " : "", msg);
    printf("backend     %s (contact level %s), %d iterations, %.1f us\n\n",
           hp_backend_name(r->backend), hp_level_name(r->level), r->iterations,
           r->solve_time * 1e6);
    printf("%-18s %10s %10s %12s %8s  %s\n", "bladder", "ri_mm", "ro_mm", "pressure_pa", "stretch",
           "binding");
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder_result *b = &r->bladders[k];
        printf("%-18s %10.4f %10.4f %12.2f %8.4f  ", L->bladders[k].name, b->ri * 1e3, b->ro * 1e3,
               b->pressure, b->stretch);
        int any = 0;
        for (int f = 0; f < HP_BIND_COUNT; ++f)
            if (b->binding & (1u << f)) {
                printf("%s%s", any ? "," : "", hp_binding_name(1u << f));
                any = 1;
            }
        printf("%s\n", any ? "" : "-");
    }
    /* error: achieved − desired, whatever its cause; where it is the part of the correction
     * the layout cannot command (the uncommanded column) the row says so. */
    printf("\n%-10s %12s %12s %12s %14s\n", "pose", "desired", "achieved", "error", "uncommanded");
    for (int i = 0; i < 6; ++i)
        printf("%-10s %12.6f %12.6f %12.3g %14.6f%s\n", hp_pose_key(i), d[i], a[i], a[i] - d[i],
               u[i],
               uncommanded_axis(u, i) ? "  (uncommanded)"
               : r->commanded[i]      ? ""
                                      : "  (not commanded)");
    /* Beside the solver's error (the column above): the model's against the reference. */
    char line[512];
    cli_model_error_text(me, line, sizeof line);
    printf("%-13s %s\n", "model error", line);
}

int cmd_solve(int argc, char **argv)
{
    solve_args a = {0};
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    hp_level lv;
    char names[96];
    if (a.level && hp_level_parse(a.level, &lv))
        return cli_fail(CLI_EXIT_USAGE, CMD, "--level: unknown level '%s' (%s)", a.level,
                        hp_scene_level_names(1, ", ", names, sizeof names));

    double corr_clin[6];
    if (a.correction && (rc = cli_doubles(CMD, "--correction", a.correction, 6, corr_clin)))
        return rc;
    hp_scene *sc = NULL;
    if ((rc = cli_load_scene(CMD, a.scene, NULL, &sc))) return rc;
    double desired[6];
    if (a.correction) {
        hp_pose_from_clinical(corr_clin, desired);
        if ((rc = cli_scene_set_correction(CMD, sc, desired))) {
            free(sc);
            return rc;
        }
    } else if (sc->has_correction) {
        memcpy(desired, sc->correction, sizeof desired);
    } else {
        free(sc);
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "--correction: missing (the scene %s states no correction)",
                        cli_name(a.scene));
    }
    hp_settings s;
    if ((rc = cli_settings(CMD, sc, a.backend, a.level, &s))) {
        free(sc);
        return rc;
    }
    s.use_rate_limits = 0; /* one solve from the nominal pose: no previous cycle */

    hp_diag d = {{0}};
    hp_error e;
    hp_planner *p = NULL;
    e = hp_planner_create(&sc->layout, &s, &p, &d);
    if (e != HP_OK) {
        int r2 = cli_planner_refused(CMD, cli_name(a.scene), a.backend, e, &d);
        free(sc);
        return r2;
    }
    char level_why[HP_DIAG_MAX];
    hp_planner_level_choice(p, level_why, sizeof level_why); /* p is built: HP_OK */
    if (hp_planner_level(p) == HP_LEVEL_LOAD) {
        char why[HP_DIAG_MAX];
        snprintf(why, sizeof why, "%s", level_why);
        if (!*why)
            snprintf(why, sizeof why, "load: asked for by %s", a.level ? "--level" : "model.level");
        rc = cli_solve_load(CMD, sc, cli_name(a.scene), p, &s, desired,
                            a.correction ? "--correction" : "correction", a.json, why);
        hp_planner_destroy(p);
        free(sc);
        return rc;
    }
    hp_result r;
    e = hp_plan(p, desired, &r);
    const char *msg = hp_planner_message(p);
    int status;
    if (e != HP_OK) {
        status = cli_fail(CLI_EXIT_SOFTWARE, CMD, "%s: planner call failed: %s", cli_name(a.scene),
                          hp_error_message(e));
    } else if (r.status == HP_STATUS_INVALID_INPUT) {
        status = cli_fail(CLI_EXIT_DATAERR, CMD, "%s: %s",
                          a.correction ? "--correction" : "correction", msg);
    } else if (r.status == HP_STATUS_TIME_LIMIT || r.status == HP_STATUS_ITERATION_LIMIT) {
        /* The planner's message names the budget that stopped the backend (the same text
         * Python's result carries), so the user knows what to raise. */
        status = cli_fail(CLI_EXIT_SOFTWARE, CMD, "%s: %s (no answer printed)", cli_name(a.scene),
                          msg);
    } else if (r.status != HP_STATUS_REACHED && r.status != HP_STATUS_CLOSEST &&
               r.status != HP_STATUS_UNCOMMANDED) {
        /* The planner's message starts with the status name already. */
        const char *name = hp_status_name(r.status);
        int named = strncmp(msg, name, strlen(name)) == 0;
        status = cli_fail(CLI_EXIT_SOFTWARE, CMD, "%s: %s%s%s", cli_name(a.scene),
                          named ? "" : name, named ? "" : ": ", msg);
    } else {
        status = r.status == HP_STATUS_REACHED       ? CLI_EXIT_OK
                 : r.status == HP_STATUS_UNCOMMANDED ? CLI_EXIT_UNCOMMANDED
                                                     : CLI_EXIT_CLOSEST;
        cli_model_error me;
        cli_model_error_of(sc, &r, r.level, s.tolerance, &me);
        if (a.json) {
            if (print_json(hp_planner_layout(p), &r, msg, level_why, &me))
                status = CLI_EXIT_SOFTWARE;
        } else {
            print_table(hp_planner_layout(p), &r, msg, &me);
            cli_print_hoop(hp_planner_layout(p), &r);
            if (level_why[0]) printf("\nlevel choice: %s\n", level_why);
        }
    }
    hp_planner_destroy(p);
    free(sc);
    return status;
}
