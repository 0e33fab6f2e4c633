/* load.gravity_dir is a direction: any finite non-zero vector is scaled to 9.80665 m/s^2,
 * however large or small its components (their squares may overflow or underflow), and
 * the zero vector is refused as such. */
#include "support/test_util.h"

#include "headplan/headplan.h"

#include <stdio.h>
#include <string.h>

/* The load scene with gravity_dir replaced by `dir`; returns hp_scene_parse's code. */
static hp_error load_with(const char *dir, hp_scene *sc, hp_diag *d)
{
    char *out = hp_test_edit_file(HP_SOURCE_DIR "/scenarios/load_supine.yaml",
                                  "gravity_dir: [0, 0, -1]", dir);
    hp_error e = hp_scene_parse(out, strlen(out), "g.yaml", sc, d);
    free(out);
    return e;
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
