/* Every scenario in scenarios/ parses, and parses to the values its file states.
 *
 * References are independent of the parser: numbers typed from the files by hand, unit
 * conversions written out here, and the geometry of touch placement recomputed from the
 * ellipsoid's implicit equation (outward normal ∝ (x/a², y/b², z/c²)). */
#include "support/test_util.h"

#include "headplan/hp_scene.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

#define SCN HP_SOURCE_DIR "/scenarios/"
#define DEG (3.14159265358979323846 / 180.0)

/* The path of scenario `name` (a static buffer). */
static const char *scn_path(const char *name)
{
    static char path[512];
    snprintf(path, sizeof path, "%s%s", SCN, name);
    return path;
}

static void expect_loaded(const char *name, hp_error e, const hp_diag *d)
{
    if (e != HP_OK) print_error("%s: %s\n", name, d->text);
    assert_int_equal(e, HP_OK);
}

static hp_scene *load(const char *name)
{
    static hp_scene s;
    hp_diag d = {{0}};
    expect_loaded(name, hp_scene_load(scn_path(name), &s, &d), &d);
    return &s;
}

static hp_bladder_study *load_study(const char *name)
{
    static hp_bladder_study s;
    hp_diag d = {{0}};
    expect_loaded(name, hp_study_load(scn_path(name), &s, &d), &d);
    return &s;
}

static int index_of(const hp_scene *s, const char *name)
{
    for (int k = 0; k < s->layout.n; ++k)
        if (strcmp(s->layout.bladders[k].name, name) == 0) return k;
    return -1;
}

static void test_every_scenario_parses(void **state)
{
    (void)state;
    DIR *dir = opendir(SCN);
    assert_non_null(dir);
    int count = 0;
    struct dirent *ent;
    while ((ent = readdir(dir))) {
        size_t n = strlen(ent->d_name);
        if (n < 6 || strcmp(ent->d_name + n - 5, ".yaml") != 0) continue;
        char path[512];
        snprintf(path, sizeof path, "%s", scn_path(ent->d_name));
        if (hp_scene_file_kind(path) == HP_SCENE_BLADDER) {
            hp_bladder_study *s = load_study(ent->d_name);
            assert_int_equal(s->version, 1);
            assert_true(strlen(s->name) > 0);
            /* The layout reader judges it as a study, then refuses the kind. */
            static hp_scene other;
            hp_diag d = {{0}};
            assert_int_equal(hp_scene_load(path, &other, &d), HP_ERR_INVALID);
            assert_non_null(strstr(d.text, "a single-bladder study, not a layout scene"));
        } else {
            hp_scene *s = load(ent->d_name);
            assert_int_equal(s->version, 1);
            assert_true(strlen(s->name) > 0);
            static hp_bladder_study other;
            hp_diag d = {{0}};
            assert_int_equal(hp_study_load(path, &other, &d), HP_ERR_INVALID);
            assert_non_null(strstr(d.text, "a layout scene, not a single-bladder study"));
        }
        ++count;
    }
    closedir(dir);
    assert_true(count >= 9); /* the two tables, six study scenes and nodding.yaml */
}

static void test_paper_expansion(void **state)
{
    (void)state;
    hp_bladder_study *s = load_study("paper_expansion.yaml");
    assert_int_equal(s->study, HP_STUDY_IK);
    /* mm -> m is one multiplication by 1e-3: exact to 1 ulp */
    hp_assert_close(s->iab.Ri, 0.027, 1e-15, 0);
    hp_assert_close(s->iab.Ro, 0.030, 1e-15, 0);
    hp_assert_close(s->study_ri, 0.030, 1e-15, 0);
    assert_true(s->iab.C1 == 1.1e4 && s->iab.C2 == 2.2e4);
    assert_int_equal(s->convention, HP_MATERIAL_PAPER);
    assert_int_equal(s->has_printed, 1);
    assert_string_equal(s->printed_ro.text, ".033");
    assert_true(s->printed_ro.value == 0.033);
    assert_true(s->printed_pressure.given && s->printed_pressure.value == 0.76);
    assert_string_equal(s->printed_title, "Volumetric Deformation (Expansion)");
}

static void test_paper_compression(void **state)
{
    (void)state;
    hp_bladder_study *s = load_study("paper_compression.yaml");
    hp_assert_close(s->iab.Ri, 0.025, 1e-15, 0);
    hp_assert_close(s->study_ri, 0.023, 1e-15, 0); /* the errata: 23 mm, not the printed .03 */
    assert_string_equal(s->printed_ri.text, ".03");
    assert_true(s->printed_pressure.value == -0.34);
}

/* Touch placement on the default head: contact on the stated ray and on the surface,
 * centre Ro out along the outward normal, contact distance Ro (touching at rest). */
static void test_default_layout(void **state)
{
    (void)state;
    static const struct {
        const char *name;
        double d[3];
    } want[8] = {
        {"base_neck_left", {0.35, -0.45, -1}}, {"base_neck_right", {-0.35, -0.45, -1}},
        {"base_skull_left", {0.35, 0.45, -1}}, {"base_skull_right", {-0.35, 0.45, -1}},
        {"side_fore_left", {1, 0.45, 0.15}},   {"side_fore_right", {-1, 0.45, 0.15}},
        {"side_chin_left", {1, -0.45, -0.15}}, {"side_chin_right", {-1, -0.45, -0.15}},
    };
    hp_scene *s = load("default.yaml");
    const hp_layout *L = &s->layout;
    assert_int_equal(L->n, 8);
    assert_int_equal(L->head.shape, HP_HEAD_ELLIPSOID);
    const double ax[3] = {0.0775, 0.115, 0.0975};
    for (int i = 0; i < 3; ++i) hp_assert_close(L->head.semi_axes[i], ax[i], 1e-15, 0);
    assert_true(L->head.mass == 4.5);
    for (int k = 0; k < 8; ++k) {
        double contact[3], rho0;
        assert_int_equal(hp_layout_contact(L, k, contact, NULL, &rho0), HP_OK);
        int j = index_of(s, want[k].name);
        assert_int_equal(j, k);
        const hp_bladder *b = &L->bladders[k];
        hp_assert_close(b->iab.Ri, 0.027, 1e-15, 0);
        hp_assert_close(b->iab.Ro, 0.030, 1e-15, 0);
        hp_assert_close(b->p_min, -5000, 1e-15, 0);
        hp_assert_close(b->p_max, 10000, 1e-15, 0);
        assert_true(b->stretch_min == 0.8 && b->stretch_max == 1.3);
        assert_true(b->rate_max > 1e300); /* omitted: unlimited (+inf) */
        /* reference contact: p = t·d with (t·d/a)² summed = 1 */
        double q = 0, p[3], n[3], nn = 0;
        for (int i = 0; i < 3; ++i) q += (want[k].d[i] / ax[i]) * (want[k].d[i] / ax[i]);
        for (int i = 0; i < 3; ++i) {
            p[i] = want[k].d[i] / sqrt(q);
            n[i] = p[i] / (ax[i] * ax[i]);
            nn += n[i] * n[i];
        }
        /* the surface point and normal are computed in a few flops each: 1e-12 m (a
         * picometre) covers rounding with a wide margin; the layout derives the contact
         * with its own root find, good to its 1e-12-level tolerance */
        for (int i = 0; i < 3; ++i) {
            double c = p[i] + 0.030 * n[i] / sqrt(nn);
            hp_assert_close(b->center[i], c, 0, 1e-12);
            hp_assert_close(contact[i], p[i], 0, 1e-9);
        }
        hp_assert_close(rho0, 0.030, 0, 1e-9);
        /* the paper's arrangement: base under the occiput, left = +X, neck = -Y */
        int base = strncmp(b->name, "base", 4) == 0;
        int left = strstr(b->name, "left") != NULL;
        int low = strstr(b->name, "neck") || strstr(b->name, "chin");
        if (base) assert_true(p[2] < 0);
        else assert_true(fabs(p[0]) > fabs(p[2]));
        assert_true(left ? p[0] > 0 : p[0] < 0);
        assert_true(low ? p[1] < 0 : p[1] > 0);
    }
    assert_int_equal(s->level, HP_LEVEL_AUTO);
    hp_assert_close(s->level_tolerance, 1e-5, 1e-15, 0);
    assert_int_equal(s->has_auto_range, 1);
    hp_assert_close(s->auto_trans, 5e-3, 1e-15, 0);
    hp_assert_close(s->auto_rot, 3 * DEG, 1e-15, 0);
    assert_int_equal(s->backend, HP_BACKEND_REALTIME);
    assert_true(s->tolerance == 1e-9 && s->max_iter == 200 && s->max_time == 1.0 &&
                s->weight_mm_per_deg == 1.0);
    assert_int_equal(s->has_correction, 1);
    const double corr[6] = {1e-3, 0, -0.5e-3, 0.3 * DEG, 0, -0.2 * DEG};
    for (int i = 0; i < 6; ++i) hp_assert_close(s->correction[i], corr[i], 1e-15, 0);
    assert_int_equal(s->has_trace, 1);
    assert_string_equal(s->trace_path, SCN "traces/drift_10hz.csv");
    assert_int_equal(s->trace_rows, HP_TRACE_DEVIATION);
}

static void test_sphere_head(void **state)
{
    (void)state;
    hp_scene *s = load("sphere_head.yaml");
    const hp_layout *L = &s->layout;
    assert_int_equal(L->head.shape, HP_HEAD_SPHERE);
    for (int i = 0; i < 3; ++i) hp_assert_close(L->head.semi_axes[i], 0.09, 1e-15, 0);
    assert_true(L->head.mass == 0.0); /* not stated: no load model */
    /* touch_mm [40,-40,-70]: the centre is (1 + 30/90)·p on a sphere at the origin */
    int k = index_of(s, "base_neck_left");
    const double p[3] = {0.040, -0.040, -0.070};
    for (int i = 0; i < 3; ++i) hp_assert_close(L->bladders[k].center[i], p[i] * 4 / 3, 0, 1e-15);
    assert_int_equal(s->level, HP_LEVEL_SURFACE);
    /* defaults where the solver section omits a key */
    assert_true(s->max_iter == HP_DEFAULT_MAX_ITER && s->tolerance == 1e-9);
    assert_int_equal(s->restarts, HP_DEFAULT_RESTARTS);
    assert_int_equal(s->has_trace, 0);
}

/* solver.restarts reaches the planner settings; a value other than the default (7) shows
 * it was read, and the bounds 0 and 64 are accepted. */
static void test_solver_restarts(void **state)
{
    (void)state;
    static const char *const VALUES[] = {"3", "0", "64"};
    for (int i = 0; i < 3; ++i) {
        char text[512];
        snprintf(text, sizeof text,
                 "headplan_scene: 1\nname: restarts\nhead: {shape: sphere, radius_mm: 90}\n"
                 "bladder_defaults: {Ri_mm: 27, Ro_mm: 30, material: {convention: paper, "
                 "C1_pa: 1.1e4, C2_pa: 2.2e4}, pressure_min_kpa: -5, pressure_max_kpa: 10, "
                 "stretch_min: 0.8, stretch_max: 1.3}\n"
                 "bladders:\n  - {name: a, touch_dir: [0, 0, -1]}\n"
                 "solver: {backend: nlopt-slsqp, restarts: %s}\n",
                 VALUES[i]);
        static hp_scene s;
        hp_diag d = {{0}};
        expect_loaded("restarts", hp_scene_parse(text, strlen(text), "restarts.yaml", &s, &d), &d);
        assert_int_equal(s.restarts, atoi(VALUES[i]));
        hp_settings st;
        assert_int_equal(hp_scene_settings(&s, &st, &d), HP_OK);
        assert_int_equal(st.restarts, atoi(VALUES[i]));
        assert_int_equal(st.backend, HP_BACKEND_NLOPT_SLSQP);
    }
}

static void test_soft_material(void **state)
{
    (void)state;
    hp_scene *s = load("soft_material.yaml");
    const hp_bladder *b = &s->layout.bladders[0];
    /* fe convention: C1 = 2·C10 = 1.1e4, C2 = 2·C01 = 0 (exact doubling) */
    assert_true(b->iab.C1 == 1.1e4 && b->iab.C2 == 0.0);
    hp_iab_limit lp;
    assert_int_equal(hp_iab_limit_point(&b->iab, &lp), HP_OK);
    assert_int_equal(lp.exists, 1);
    assert_true(lp.lambda_i > 1.38 && lp.lambda_i < 1.48); /* "near 1.43" (docs/model.md §3) */
    assert_true(b->stretch_max < lp.lambda_i);
    assert_int_equal(s->level, HP_LEVEL_PLANE);
}

static void test_saturation_and_rotation(void **state)
{
    (void)state;
    hp_scene *s = load("saturation.yaml");
    hp_assert_close(s->layout.bladders[3].rate_max, 2000, 1e-15, 0);
    assert_int_equal(s->backend, HP_BACKEND_IPOPT);
    hp_assert_close(s->correction[0], 0.015, 1e-15, 0);
    hp_assert_close(s->correction[5], 10 * DEG, 1e-15, 0);
    s = load("large_rotation.yaml");
    hp_assert_close(s->correction[3], 6 * DEG, 1e-15, 0);
    hp_assert_close(s->correction[4], 4 * DEG, 1e-15, 0);
    s = load("nodding.yaml");
    assert_int_equal(s->has_correction, 0);
    assert_string_equal(s->trace_path, SCN "traces/nodding.csv");
}

/* The scenes do what their comments claim: the default layout commands all six directions,
 * the near-degenerate one is much worse conditioned, the sphere head has rank 3. (The
 * thresholds are wide: these scenes are for studies, not for pinning the analysis.) */
static void test_layout_conditioning(void **state)
{
    (void)state;
    hp_layout_analysis a;
    hp_scene *s = load("default.yaml");
    assert_int_equal(hp_layout_analyze(&s->layout, HP_LEVEL_LINEAR, &a), HP_OK);
    assert_int_equal(a.rank, 6);
    double cond_default = a.condition;
    assert_true(cond_default < 50);
    s = load("near_degenerate.yaml");
    assert_int_equal(hp_layout_analyze(&s->layout, HP_LEVEL_LINEAR, &a), HP_OK);
    assert_int_equal(a.rank, 6);
    assert_true(a.condition > 5 * cond_default);
    s = load("sphere_head.yaml");
    assert_int_equal(hp_layout_analyze(&s->layout, HP_LEVEL_LINEAR, &a), HP_OK);
    assert_int_equal(a.rank, 3);
    assert_int_equal(a.rotation_commandable, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_scenario_parses),
        cmocka_unit_test(test_paper_expansion),
        cmocka_unit_test(test_paper_compression),
        cmocka_unit_test(test_default_layout),
        cmocka_unit_test(test_sphere_head),
        cmocka_unit_test(test_soft_material),
        cmocka_unit_test(test_solver_restarts),
        cmocka_unit_test(test_saturation_and_rotation),
        cmocka_unit_test(test_layout_conditioning),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
