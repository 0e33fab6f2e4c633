/* load.gravity_dir is a direction: any finite non-zero vector is scaled to 9.80665 m/s^2,
 * however large or small its components (their squares may overflow or underflow), and
 * the zero vector is refused as such. */
#include "test_util.h"

#include "headplan/headplan.h"

#include <stdio.h>
#include <string.h>

/* The load scene with gravity_dir replaced by `dir`; returns hp_scene_parse's code. */
static hp_error load_with(const char *dir, hp_scene *sc, hp_diag *d)
{
    char path[512], text[8192];
    snprintf(path, sizeof path, "%s/scenarios/load_supine.yaml", HP_SOURCE_DIR);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    const char *key = "gravity_dir: [0, 0, -1]";
    char *at = strstr(text, key);
    assert_non_null(at);
    char out[8192];
    snprintf(out, sizeof out, "%.*s%s%s", (int)(at - text), text, dir, at + strlen(key));
    return hp_scene_parse(out, strlen(out), "g.yaml", sc, d);
}

static void test_huge_and_tiny_directions(void **st)
{
    (void)st;
    static hp_scene sc;
    hp_diag d = {{0}};
    /* |g|² overflows (1e616): still the direction (1, 1, 0)/√2. */
    assert_int_equal(load_with("gravity_dir: [1e308, 1e308, 0]", &sc, &d), HP_OK);
    double h = HP_GRAVITY / sqrt(2.0);
    hp_assert_close(sc.load.gravity[0], h, 1e-15, 0);
    hp_assert_close(sc.load.gravity[1], h, 1e-15, 0);
    assert_true(sc.load.gravity[2] == 0.0);
    /* |g|² underflows to 0 (1e-400): still the direction -z. */
    assert_int_equal(load_with("gravity_dir: [0, 0, -1e-200]", &sc, &d), HP_OK);
    assert_true(sc.load.gravity[2] == -HP_GRAVITY);
    assert_true(sc.load.gravity[0] == 0.0 && sc.load.gravity[1] == 0.0);
    /* The zero vector has no direction. */
    assert_int_equal(load_with("gravity_dir: [0, 0, 0]", &sc, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "load.gravity_dir: must be a non-zero direction"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_huge_and_tiny_directions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
