/* headplan solve at the load level: which level a scene with a `load` section gets, and
 * the load planner's answer with its equilibrium residual, holding compliance, the forward
 * statics' round trip and the binding limits. */
#include "cli/cli_output.h"
#include "cli/cli_fidelity.h"
#include "cli/cmd_solve_load.h"
#include "cli/json_out.h"
#include "cli/exit_codes.h"
#include "headplan/hp_planner.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cli_load_level(const char *cmd, const hp_scene *sc, const char *level_arg, int *use_load,
                   char *why, size_t len)
{
    hp_diag d = {{0}};
    hp_level_refusal refused;
    hp_error e = hp_scene_plan_level(sc, level_arg, use_load, why, len, &refused, &d);
    if (!e) {
        /* the library says "the caller's level": here the caller is --level */
        if (*use_load && why && len && level_arg && strcmp(level_arg, "load") == 0)
            snprintf(why, len, "load: asked for by --level");
        return 0;
    }
    *use_load = 0;
    if (refused == HP_LEVEL_REFUSED_NO_LOAD)
        return cli_fail(CLI_EXIT_USAGE, cmd,
                        "--level: load needs a scene with a 'load' section (%s has none)",
                        sc->file);
    /* An unknown --level is the settings' to name (cli_settings), as for any scene. */
    if (refused == HP_LEVEL_REFUSED_UNKNOWN) return 0;
    return cli_fail(CLI_EXIT_DATAERR, cmd, "%s: load: %s", sc->file,
                    d.text[0] ? d.text : hp_error_message(e));
}

int cli_kinematic_only(const char *cmd, const hp_scene *sc, const char *level_arg,
                       const char *instead)
{
    if (level_arg && strcmp(level_arg, "load") == 0) {
        char levels[96];
        return cli_fail(CLI_EXIT_USAGE, cmd,
                        "--level: load is not planned by %s; it plans the contact levels (%s)", cmd,
                        hp_scene_level_names(0, ", ", levels, sizeof levels));
    }
    hp_diag d = {{0}};
    hp_level_refusal refused;
    hp_error e = hp_scene_kinematic_only(sc, level_arg, cmd, &refused, &d);
    /* An unknown --level is the settings' to name (cli_settings), as for any scene. */
    if (!e || refused == HP_LEVEL_REFUSED_UNKNOWN) return 0;
    if (refused == HP_LEVEL_REFUSED_LOAD)
        return cli_fail(CLI_EXIT_DATAERR, cmd, "%s: %s", d.text, instead);
    return cli_fail(CLI_EXIT_DATAERR, cmd, "%s", d.text);
}

static void binding_text(unsigned flags, char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = '\0';
    for (int f = 0; f < HP_BIND_COUNT && n < len; ++f)
        if (flags & (1u << f))
            n += (size_t)snprintf(buf + n, len - n, "%s%s", n ? "," : "", hp_binding_name(1u << f));
    if (!n) snprintf(buf, len, "-");
}

/* Hoop stress at the inner surface [kPa] of an answer's bladder (NaN when it cannot be
 * evaluated). */
static double hoop_kpa(const hp_bladder *B, const hp_bladder_result *b)
{
    double s;
    return hp_iab_hoop_stress_inner(&B->iab, b->ri, &s) == HP_OK ? s * 1e-3 : NAN;
}

void cli_print_hoop(const hp_layout *L, const hp_result *r)
{
    int any = 0;
    for (int k = 0; k < L->n; ++k) any |= L->bladders[k].stress_max > 0;
    if (!any) return;
    printf("\n%-18s %12s %12s\n", "bladder", "hoop_kpa", "limit_kpa");
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        if (B->stress_max > 0 && isfinite(B->stress_max))
            printf("%-18s %12.4f %12.4f\n", B->name, hoop_kpa(B, &r->bladders[k]),
                   B->stress_max * 1e-3);
        else printf("%-18s %12.4f %12s\n", B->name, hoop_kpa(B, &r->bladders[k]), "-");
    }
}

static void print_table(const hp_layout *L, const hp_result *r, const hp_load_info *info,
                        const char *msg, const char *why, hp_level geom, hp_load_tiebreak tie,
                        const cli_model_error *me)
{
    double d[6], a[6];
    hp_pose_to_clinical(r->desired, d);
    hp_pose_to_clinical(r->achieved, a);
    /* A CLOSEST answer explains itself on its status line, as the kinematic levels' do. */
    printf("status      %s%s%s\n", hp_status_name(r->status), *msg ? " — " : "", msg);
    printf("level       load (contact geometry %s, tie-breaker %s), backend %s, %.1f us\n",
           hp_level_name(geom), hp_load_tiebreak_name(tie), hp_backend_name(r->backend),
           r->solve_time * 1e6);
    printf("why         %s\n\n", why);
    printf("%-18s %10s %10s %12s %8s %10s %10s %8s  %s\n", "bladder", "ri_mm", "ro_mm",
           "pressure_pa", "stretch", "force_n", "hoop_kpa", "indent", "binding");
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder_result *b = &r->bladders[k];
        char bind[128];
        binding_text(b->binding, bind, sizeof bind);
        printf("%-18s %10.4f %10.4f %12.2f %8.4f %10.4f %10.4f %8.4f  %s\n", L->bladders[k].name,
               b->ri * 1e3, b->ro * 1e3, b->pressure, b->stretch, info->force[k],
               hoop_kpa(&L->bladders[k], b), info->indent[k], bind);
    }
    printf("\n%-10s %12s %12s %12s\n", "pose", "desired", "achieved", "error");
    for (int i = 0; i < 6; ++i)
        printf("%-10s %12.6f %12.6f %12.3g\n", hp_pose_key(i), d[i], a[i], a[i] - d[i]);
    const hp_load_holding *h = &info->holding;
    printf("\nequilibrium residual  %.3g N, %.3g N*m (Newton-Euler, from the contact points)\n",
           info->residual_force, info->residual_moment);
    /* An unstable hold (a saddle) is left by the forward statics' descent: it finds no rest,
     * which is a fact about the hold, not a distance. */
    if (isfinite(info->rest_error))
        printf("forward statics       rest %.3g mm/deg from the achieved pose\n", info->rest_error);
    else
        printf("forward statics       no rest found from the achieved pose (the head does not "
               "settle there: see holding)\n");
    /* Beside the forward statics on the planner's own law: the rest on the reference's. */
    char line[512];
    cli_model_error_text(me, line, sizeof line);
    printf("%-21s %s\n", "model error", line);
    printf("holding               at the answer: %s; weakest %s, %.4g %s\n",
           h->stable ? "stable" : "NOT stable (the stiffness is not positive definite)",
           h->weakest_words, h->weakest_compliance, h->weakest_is_rotation ? "deg/(N*m)" : "mm/N");
    printf("compliance            x %.4g, y %.4g, z %.4g mm/N; pitch %.4g, roll %.4g, yaw %.4g "
           "deg/(N*m)\n",
           h->compliance[0], h->compliance[1], h->compliance[2], h->compliance[3], h->compliance[4],
           h->compliance[5]);
}

static int print_json(const char *cmd, const hp_layout *L, const hp_result *r,
                      const hp_load_info *info, const char *msg, const char *why, hp_level geom,
                      hp_load_tiebreak tie, const cli_model_error *me)
{
    json_t *o = json_object();
    json_object_set_new(o, "status", json_string(hp_status_name(r->status)));
    json_object_set_new(o, "backend", json_string(hp_backend_name(r->backend)));
    json_object_set_new(o, "level", json_string("load"));
    json_object_set_new(o, "geometry", json_string(hp_level_name(geom)));
    json_object_set_new(o, "tiebreak", json_string(hp_load_tiebreak_name(tie)));
    json_object_set_new(o, "why", json_string(why));
    json_object_set_new(o, "desired", cli_json_pose(r->desired));
    json_object_set_new(o, "achieved", cli_json_pose(r->achieved));
    json_t *bl = json_array();
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder_result *b = &r->bladders[k];
        json_t *e = json_object(), *bind = json_array();
        json_object_set_new(e, "name", json_string(L->bladders[k].name));
        json_object_set_new(e, "ri_mm", json_real(b->ri * 1e3));
        json_object_set_new(e, "ro_mm", json_real(b->ro * 1e3));
        json_object_set_new(e, "pressure_pa", json_real(b->pressure));
        json_object_set_new(e, "force_n", json_real(info->force[k]));
        json_object_set_new(e, "hoop_stress_kpa", cli_json_num(hoop_kpa(&L->bladders[k], b)));
        json_object_set_new(e, "indent", cli_json_num(info->indent[k]));
        for (int f = 0; f < HP_BIND_COUNT; ++f)
            if (b->binding & (1u << f))
                json_array_append_new(bind, json_string(hp_binding_name(1u << f)));
        json_object_set_new(e, "binding", bind);
        json_array_append_new(bl, e);
    }
    json_object_set_new(o, "bladders", bl);
    json_object_set_new(o, "residual_force_n", json_real(info->residual_force));
    json_object_set_new(o, "residual_moment_nm", json_real(info->residual_moment));
    json_object_set_new(o, "rest_error", cli_json_num(info->rest_error));
    json_object_set_new(o, "model_error", cli_json_model_error(me));
    const hp_load_holding *h = &info->holding;
    json_t *c = json_object();
    static const char *const keys[6] = {"x_mm_per_n",       "y_mm_per_n",      "z_mm_per_n",
                                        "pitch_deg_per_nm", "roll_deg_per_nm", "yaw_deg_per_nm"};
    for (int i = 0; i < 6; ++i) json_object_set_new(c, keys[i], cli_json_num(h->compliance[i]));
    json_object_set_new(o, "compliance", c);
    json_object_set_new(o, "stable", json_boolean(h->stable));
    json_object_set_new(o, "weakest", json_string(h->weakest_words));
    json_object_set_new(o, "weakest_compliance", cli_json_num(h->weakest_compliance));
    json_object_set_new(o, "iterations", json_integer(r->iterations));
    json_object_set_new(o, "message", json_string(msg)); /* the status line's words */
    char *s = json_dumps(o, JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(CLI_JSON_REAL_PRECISION));
    json_decref(o);
    if (!s) return cli_fail(CLI_EXIT_SOFTWARE, cmd, "cannot format JSON output");
    cli_put_line(s);
    free(s);
    return 0;
}

int cli_planner_refused(const char *cmd, const char *name, const char *backend_opt, hp_error e,
                        const hp_diag *d)
{
    /* Refused for the backend (one that does not plan the load level, or does not solve the
     * scene's tie-breaker) that --backend chose: the command line's fault, 64 naming the
     * option, as an unknown --backend is. */
    static const char BACKEND[] = "backend: ";
    if (e == HP_ERR_INVALID && backend_opt &&
        (strncmp(d->text, BACKEND, sizeof BACKEND - 1) == 0 ||
         strncmp(d->text, "load_tiebreak: ", 15) == 0)) {
        const char *why = d->text;
        if (strncmp(why, BACKEND, sizeof BACKEND - 1) == 0) why += sizeof BACKEND - 1;
        return cli_fail(CLI_EXIT_USAGE, cmd, "--backend %s: %s", backend_opt, why);
    }
    return cli_fail(e == HP_ERR_INVALID || e == HP_ERR_DOMAIN ? CLI_EXIT_DATAERR
                                                              : CLI_EXIT_SOFTWARE,
                    cmd, "%s: %s", name, d->text);
}

int cli_solve_load(const char *cmd, const hp_scene *sc, const char *name, hp_planner *p,
                   const hp_settings *s, const double desired[6], const char *from, int json,
                   const char *why)
{
    const hp_layout *L = hp_planner_layout(p);
    const hp_level geom = hp_load_model_level(hp_planner_load_model(p));
    hp_result r;
    hp_load_info info;
    hp_error e = hp_plan(p, desired, &r);
    if (e == HP_OK && (r.status == HP_STATUS_REACHED || r.status == HP_STATUS_CLOSEST))
        e = hp_planner_load_info(p, &info);
    if (e)
        return cli_fail(CLI_EXIT_SOFTWARE, cmd, "%s: load planner failed: %s", name,
                        hp_error_message(e));
    if (r.status == HP_STATUS_INVALID_INPUT)
        return cli_fail(CLI_EXIT_DATAERR, cmd, "%s: %s", from, hp_planner_error(p));
    if (r.status != HP_STATUS_REACHED && r.status != HP_STATUS_CLOSEST)
        return cli_fail(CLI_EXIT_SOFTWARE, cmd, "%s: %s: %s", name, hp_status_name(r.status),
                        hp_planner_error(p));
    int status = r.status == HP_STATUS_REACHED ? CLI_EXIT_OK : CLI_EXIT_CLOSEST;
    const hp_load_tiebreak tie = s->load_tiebreak;
    cli_model_error me;
    cli_model_error_of(sc, &r, HP_LEVEL_LOAD, s->tolerance, &me);
    if (json) {
        if (print_json(cmd, L, &r, &info, hp_planner_message(p), why, geom, tie, &me))
            status = CLI_EXIT_SOFTWARE;
    } else {
        print_table(L, &r, &info, hp_planner_message(p), why, geom, tie, &me);
    }
    return status;
}
