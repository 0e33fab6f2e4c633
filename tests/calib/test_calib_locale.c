/* A calibrated scene written under a host's comma locale (a Python or GUI host calling
 * setlocale(LC_ALL, "") in Germany) reads back with the same numbers: "%.17g" wrote
 * "77,5" into the scene file, which the C-locale reader then refused or misread. The file
 * must be the one written in the C locale, byte for byte. */
#define _POSIX_C_SOURCE 200809L
#include "support/test_util.h"
#include "support/comma_locale.h"
#include "headplan/headplan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* %.17g round-trips a double; the mm / kPa scaling on the way adds an ulp or two. */
#define close_rel(got, want) hp_assert_close(got, want, 1e-15, 1e-15)

static hp_scene base, back_c, back_comma; /* large: off the stack */

static void write_and_load(const char *path, const hp_layout *L, hp_scene *out)
{
    hp_diag d = {{0}};
    hp_error e = hp_calib_write_scene(path, L, HP_LEVEL_SURFACE, &base, "calibrated", NULL, 0, &d);
    if (e != HP_OK) print_error("%s\n", d.text);
    assert_int_equal(e, HP_OK);
    e = hp_scene_load(path, out, &d);
    if (e != HP_OK) print_error("%s\n", d.text);
    assert_int_equal(e, HP_OK);
}

static void test_written_under_comma_locale(void **state)
{
    (void)state;
    hp_diag d = {{0}};
    setlocale(LC_NUMERIC, "C");
    assert_int_equal(hp_scene_load(HP_SOURCE_DIR "/scenarios/load_tilted.yaml", &base, &d), HP_OK);
    /* fitted-looking numbers: every digit of %.17g in use */
    hp_layout L = base.layout;
    for (int k = 0; k < L.n; ++k)
        for (int i = 0; i < 3; ++i) L.bladders[k].center[i] += 1e-4 / (3.0 + k + i);
    L.head.semi_axes[0] += 1e-4 / 7.0;
    L.bladders[0].iab.C1 *= 1.0 + 1.0 / 3.0e3;

    char dir[] = "/tmp/hp_calib_locale_XXXXXX", pc[128], pk[128];
    assert_non_null(mkdtemp(dir));
    snprintf(pc, sizeof pc, "%s/c.yaml", dir);
    snprintf(pk, sizeof pk, "%s/comma.yaml", dir);
    write_and_load(pc, &L, &back_c);

    if (!comma_locale()) {
        print_message("no comma-decimal locale could be set or built: skipped\n");
        skip();
    }
    write_and_load(pk, &L, &back_comma);
    assert_true(is_comma()); /* the caller's locale is left as it was */
    setlocale(LC_NUMERIC, "C");

    size_t nc, nk;
    char *tc = hp_test_read_all(pc, &nc), *tk = hp_test_read_all(pk, &nk);
    assert_int_equal(nc, nk);
    assert_memory_equal(tc, tk, nc);
    free(tc);
    free(tk);
    assert_memory_equal(&back_c.layout, &back_comma.layout, sizeof back_c.layout);
    for (int k = 0; k < L.n; ++k) {
        const hp_bladder *a = &back_comma.layout.bladders[k], *w = &L.bladders[k];
        for (int i = 0; i < 3; ++i) close_rel(a->center[i] * 1e3, w->center[i] * 1e3);
        close_rel(a->iab.C1, w->iab.C1);
        close_rel(a->iab.Ri * 1e3, w->iab.Ri * 1e3);
        close_rel(a->p_max, w->p_max);
    }
    for (int i = 0; i < 3; ++i)
        close_rel(back_comma.layout.head.semi_axes[i] * 1e3, L.head.semi_axes[i] * 1e3);
    close_rel(back_comma.load_fraction, base.load_fraction);
    close_rel(back_comma.level_tolerance, base.level_tolerance);
    for (int j = 0; j < 6; ++j) close_rel(back_comma.correction[j], base.correction[j]);
    unlink(pc);
    unlink(pk);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_written_under_comma_locale),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
