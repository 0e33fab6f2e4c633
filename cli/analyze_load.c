/* headplan analyze: the load at the nominal pose. */
#include "cli/analyze_load.h"
#include "cli/json_out.h"
#include "headplan/hp_planner.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct load_report {
    int assumed; /* 1: no load section, whole head mass along −Z assumed */
    hp_load_spec spec;
    double sag, k_gravity; /* predicted sag of a kinematic plan [m], stiffness [N/m] */
    int use_load;
    char why[HP_DIAG_MAX]; /* the planner's reason, whole (hp_planner_level_choice) */
    int held;              /* 1: the load planner answered at the nominal pose */
    char refused[HP_DIAG_MAX];
    hp_result r;
    hp_load_info info;
} load_report;

/* What auto decides with this load: the planner's own decision and reason
 * (hp_planner_level_for, what hp_planner_create runs for solve, batch and Python) from the
 * scene's settings with level auto and the load of `load` (the scene's, or the assumed
 * one), so that for a scene that states its load this line is the reason solve gives. */
static hp_error auto_choice(const hp_scene *sc, const hp_settings *load, load_report *rep)
{
    hp_settings s;
    hp_diag d = {{0}};
    hp_error e = hp_scene_settings(sc, &s, &d);
    if (e != HP_OK) return e;
    s.level = HP_LEVEL_AUTO;
    s.load = load->load;
    s.load_geometry = load->load_geometry;
    s.load_tiebreak = load->load_tiebreak;
    s.backend = load->backend;
    hp_level chosen = HP_LEVEL_AUTO;
    e = hp_planner_level_for(&sc->layout, &s, &chosen, rep->why, sizeof rep->why, &d);
    rep->use_load = e == HP_OK && chosen == HP_LEVEL_LOAD;
    return e;
}

/* Fills rep; returns 0, or -1 when the scene states no mass. */
static int compute(const hp_scene *sc, load_report *rep)
{
    memset(rep, 0, sizeof *rep);
    if (!(sc->layout.head.mass > 0)) return -1;
    rep->assumed = !sc->has_load;
    if (sc->has_load) rep->spec = sc->load;
    else hp_load_spec_default(&sc->layout.head, &rep->spec);
    hp_settings s;
    hp_settings_default(&s);
    s.level = HP_LEVEL_LOAD;
    s.load = rep->spec;
    s.load_geometry = sc->has_load ? sc->load_geometry : HP_LEVEL_SURFACE;
    s.load_tiebreak = sc->has_load ? (hp_load_tiebreak)sc->load_tiebreak : HP_TIE_LEAST_SQUEEZE;
    /* The stiffness tie-breaker is solved on Ipopt only (hp_planner_create). */
    if (s.load_tiebreak == HP_TIE_STIFFNESS) s.backend = HP_BACKEND_IPOPT;
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    hp_error e = hp_planner_create(&sc->layout, &s, &p, &d);
    /* The sag from the planner's load model; a layout the load level refuses still has it
     * (its own model), with the refusal beside it. */
    hp_load_model *own = NULL;
    const hp_load_model *M = hp_planner_load_model(p);
    if (e != HP_OK) {
        snprintf(rep->refused, sizeof rep->refused, "%s", d.text);
        if (hp_load_model_create(&sc->layout, &rep->spec, s.load_geometry, &own, &d) == HP_OK)
            M = own;
    }
    /* A layout the planner refuses has no decision of auto's to report: no auto line. */
    if (auto_choice(sc, &s, rep) != HP_OK) rep->why[0] = '\0';
    if (!M || hp_load_predicted_sag(M, &rep->sag, &rep->k_gravity) != HP_OK) {
        if (!M) snprintf(rep->refused, sizeof rep->refused, "%s", d.text);
        hp_load_model_destroy(own);
        hp_planner_destroy(p);
        return 0;
    }
    hp_load_model_destroy(own);
    if (p) {
        double zero[6] = {0};
        rep->held = hp_plan(p, zero, &rep->r) == HP_OK &&
                    (rep->r.status == HP_STATUS_REACHED || rep->r.status == HP_STATUS_CLOSEST) &&
                    hp_planner_load_info(p, &rep->info) == HP_OK;
    }
    hp_planner_destroy(p);
    return 0;
}

void cli_analyze_load_text(const hp_scene *sc)
{
    load_report *rep = malloc(sizeof *rep);
    if (!rep || compute(sc, rep) != 0) {
        free(rep);
        return;
    }
    const double g = HP_GRAVITY;
    printf("\nload at the nominal pose (%s)\n",
           rep->assumed ? "the scene has no load section: the whole head mass along -Z is "
                          "assumed; plans stay kinematic"
                        : "the scene's load section");
    printf("%-13s %.4g kg (%.4g N)\n", "carried", rep->spec.mass, rep->spec.mass * g);
    if (isinf(rep->sag))
        printf("%-13s unbounded (nothing is inflated at the nominal pose)\n", "kinematic sag");
    else
        printf("%-13s %.4g mm (%.4g N/mm along gravity)\n", "kinematic sag", rep->sag * 1e3,
               rep->k_gravity * 1e-3);
    if (rep->why[0]) printf("%-13s %s\n", "auto", rep->why);
    if (rep->refused[0]) {
        printf("%-13s %s\n", "cannot hold", rep->refused);
    } else if (rep->held) {
        const hp_load_holding *h = &rep->info.holding;
        double a[6];
        hp_pose_to_clinical(rep->r.achieved, a);
        printf("%-13s %s", "held",
               rep->r.status == HP_STATUS_REACHED ? "at the nominal pose" : "only lower: closest");
        if (rep->r.status != HP_STATUS_REACHED)
            printf(" (%.4f, %.4f, %.4f) mm, (%.4f, %.4f, %.4f) deg", a[0], a[1], a[2], a[3], a[4],
                   a[5]);
        printf("\n%-13s %s; weakest %s, %.4g %s\n", "holding", h->stable ? "stable" : "NOT stable",
               h->weakest_words, h->weakest_compliance,
               h->weakest_is_rotation ? "deg/(N*m)" : "mm/N");
        printf("%-13s x %.4g, y %.4g, z %.4g mm/N; pitch %.4g, roll %.4g, yaw %.4g deg/(N*m)\n",
               "compliance", h->compliance[0], h->compliance[1], h->compliance[2], h->compliance[3],
               h->compliance[4], h->compliance[5]);
        printf("%-13s", "pressures_pa");
        for (int k = 0; k < rep->r.n; ++k) printf(" %.1f", rep->r.bladders[k].pressure);
        printf("\n");
    }
    free(rep);
}

json_t *cli_analyze_load_json(const hp_scene *sc)
{
    load_report *rep = malloc(sizeof *rep);
    if (!rep || compute(sc, rep) != 0) {
        free(rep);
        return NULL;
    }
    json_t *o = json_object();
    json_object_set_new(o, "assumed", json_boolean(rep->assumed));
    json_object_set_new(o, "mass_kg", json_real(rep->spec.mass));
    json_object_set_new(o, "kinematic_sag_mm", cli_json_num(rep->sag * 1e3));
    json_object_set_new(o, "auto", json_string(rep->why));
    json_object_set_new(o, "refused", rep->refused[0] ? json_string(rep->refused) : json_null());
    if (rep->held) {
        const hp_load_holding *h = &rep->info.holding;
        json_object_set_new(o, "status", json_string(hp_status_name(rep->r.status)));
        json_object_set_new(o, "stable", json_boolean(h->stable));
        json_object_set_new(o, "weakest", json_string(h->weakest_words));
        json_object_set_new(o, "weakest_compliance", cli_json_num(h->weakest_compliance));
        json_t *c = json_array();
        for (int i = 0; i < 6; ++i) json_array_append_new(c, cli_json_num(h->compliance[i]));
        json_object_set_new(o, "compliance", c);
    }
    free(rep);
    return o;
}
