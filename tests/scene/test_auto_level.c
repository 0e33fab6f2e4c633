/* Auto is resolved once: for every catalogue scene (every .yaml file in scenarios/), the level a planner
 * built from the scene's settings plans at (what `headplan solve`, batch and the Python
 * Planner plan with) is the level hp_scene_plan_level gives (analyze's note, solve's choice
 * of table), the one hp_scene_kinematic_only refuses (`headplan render`) and the contact
 * level hp_scene_analyze reports; and the reason given is the planner's own text. The
 * reference is hp_planner_create + hp_planner_level / hp_planner_level_choice. */
#include "support/test_util.h"

#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SCN HP_SOURCE_DIR "/scenarios"
#define MAX_SCENES 64

static int by_name(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* The catalogue's layout scene files, sorted (a deterministic order for the messages). */
static int catalogue(char *names[MAX_SCENES])
{
    DIR *dir = opendir(SCN);
    assert_non_null(dir);
    int n = 0;
    for (struct dirent *e; (e = readdir(dir)) != NULL;) {
        size_t len = strlen(e->d_name);
        if (len < 6 || strcmp(e->d_name + len - 5, ".yaml") != 0) continue;
        assert_true(n < MAX_SCENES);
        names[n] = malloc(sizeof SCN + len + 1);
        assert_non_null(names[n]);
        snprintf(names[n], sizeof SCN + len + 1, "%s/%s", SCN, e->d_name);
        /* A single-bladder study has no level to plan at. */
        if (hp_scene_file_kind(names[n]) == HP_SCENE_BLADDER) free(names[n]);
        else ++n;
    }
    closedir(dir);
    qsort(names, (size_t)n, sizeof names[0], by_name);
    return n;
}

/* Asserts that every entry point gives scene sc (read from file) the planner's level;
 * returns that level. */
static hp_level check_scene(const char *file, const hp_scene *sc)
{
    hp_diag d = {{0}};
    /* The reference: the planner's one decision. */
    hp_settings s;
    assert_int_equal(hp_scene_settings(sc, &s, &d), HP_OK);
    hp_planner *p = NULL;
    hp_level planned = HP_LEVEL_AUTO;
    char planner_why[512] = "";
    if (hp_planner_create(&sc->layout, &s, &p, &d) == HP_OK) {
        planned = hp_planner_level(p);
        assert_int_equal(hp_planner_level_choice(p, planner_why, sizeof planner_why), HP_OK);
        hp_planner_destroy(p);
    } else if (strncmp(d.text, "load: ", 6) == 0) {
        /* The load level refused the layout (load_prone.yaml: the bladders cannot carry the
         * head): solve was at the load level, and says so with the load level's refusal. */
        planned = HP_LEVEL_LOAD;
    } else {
        print_error("%s: planner: %s\n", file, d.text);
        fail();
    }

    /* solve's and analyze's decision (hp_scene_plan_level). */
    int use_load = -1;
    char why[512];
    hp_level_refusal refused = HP_LEVEL_REFUSED_UNKNOWN;
    assert_int_equal(hp_scene_plan_level(sc, NULL, &use_load, why, sizeof why, &refused, &d),
                     HP_OK);
    if (use_load != (planned == HP_LEVEL_LOAD)) {
        print_error("%s: the planner plans %s, hp_scene_plan_level says use_load %d\n", file,
                    hp_level_name(planned), use_load);
        fail();
    }
    /* Auto's reason: the planner's text, word for word (model.level: load has its own). */
    if (s.level == HP_LEVEL_AUTO && sc->has_load && planner_why[0] &&
        strcmp(why, planner_why) != 0) {
        print_error("%s: hp_scene_plan_level why '%s'\n  planner's '%s'\n", file, why, planner_why);
        fail();
    }

    /* render's refusal (hp_scene_kinematic_only). */
    refused = HP_LEVEL_REFUSED_UNKNOWN;
    hp_error e = hp_scene_kinematic_only(sc, NULL, "render", &refused, &d);
    assert_int_equal(e, planned == HP_LEVEL_LOAD ? HP_ERR_DOMAIN : HP_OK);
    assert_int_equal(refused,
                     planned == HP_LEVEL_LOAD ? HP_LEVEL_REFUSED_LOAD : HP_LEVEL_REFUSED_NONE);

    /* analyze's contact level: the planner's when it plans a contact level. */
    if (planned != HP_LEVEL_LOAD) {
        hp_scene_analysis *x = malloc(sizeof *x);
        assert_non_null(x);
        if (hp_scene_analyze(&sc->layout, &s, x, &d) != HP_OK) {
            print_error("%s: analyze: %s\n", file, d.text);
            fail();
        }
        if (x->level != planned) {
            print_error("%s: the planner plans %s, analyze reports %s\n", file,
                        hp_level_name(planned), hp_level_name(x->level));
            fail();
        }
        free(x);
    }
    return planned;
}

/* Replaces every `from` in text (allocated) by `to`; returns the new text, frees text. */
static char *replace_all(char *text, const char *from, const char *to)
{
    size_t nf = strlen(from), nt = strlen(to), count = 0;
    for (const char *at = text; (at = strstr(at, from)) != NULL; at += nf) ++count;
    char *out = malloc(strlen(text) + count * nt + 1), *w = out;
    assert_non_null(out);
    const char *r = text;
    for (const char *at; (at = strstr(r, from)) != NULL; r = at + nf) {
        memcpy(w, r, (size_t)(at - r));
        w += at - r;
        memcpy(w, to, nt);
        w += nt;
    }
    strcpy(w, r);
    free(text);
    return out;
}

static void test_every_catalogue_scene_gets_one_level(void **state)
{
    (void)state;
    char *names[MAX_SCENES];
    int n = catalogue(names), load_scenes = 0;
    assert_true(n >= 10); /* the catalogue, not an empty folder */
    hp_scene *sc = malloc(sizeof *sc);
    assert_non_null(sc);
    for (int i = 0; i < n; ++i) {
        hp_diag d = {{0}};
        if (hp_scene_load(names[i], sc, &d) != HP_OK) {
            print_error("%s: %s\n", names[i], d.text);
            fail();
        }
        load_scenes += check_scene(names[i], sc) == HP_LEVEL_LOAD;
        free(names[i]);
    }
    free(sc);
    /* Both answers occur, so the agreement was tested both ways. */
    assert_true(load_scenes > 0);
    assert_true(load_scenes < n);
}

/* A load scene auto keeps kinematic: load_supine.yaml with a 0.05 kg head on bladders
 * preloaded 2 mm (its sides are; its base is preloaded here) (the nominal pressures hold it, a rest about 1 mm away under the fitted
 * law) and model.tolerance_mm 100 (above that model error). The level is a contact level,
 * and the reason analyze and render are given is the planner's whole line, not a second
 * decision's. (The 4.5 kg head finds no rest on those pressures: auto takes the load level,
 * tests/cli/auto_model_error.sh.) */
static void test_a_load_scene_auto_keeps_kinematic(void **state)
{
    (void)state;
    size_t n;
    char *text = hp_test_read_all(SCN "/load_supine.yaml", &n);
    text[n] = '\0';
    text = replace_all(text, "Ro_mm: 45}", "Ro_mm: 45, preload_mm: 2}");
    text = replace_all(text, "tolerance_mm: 0.01", "tolerance_mm: 100");
    text = replace_all(text, "mass_kg: 4.5", "mass_kg: 0.05");
    hp_scene *sc = malloc(sizeof *sc);
    assert_non_null(sc);
    hp_diag d = {{0}};
    if (hp_scene_parse(text, strlen(text), SCN "/load_supine.yaml", sc, &d) != HP_OK) {
        print_error("%s\n", d.text);
        fail();
    }
    free(text);
    assert_int_equal(sc->has_load, 1);
    assert_int_equal(sc->level, HP_LEVEL_AUTO);
    assert_int_not_equal(check_scene("load_supine.yaml, preloaded", sc), HP_LEVEL_LOAD);
    free(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_catalogue_scene_gets_one_level),
        cmocka_unit_test(test_a_load_scene_auto_keeps_kinematic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
