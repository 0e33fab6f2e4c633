/* The load level's answers (REACHED or CLOSEST) and their stability: a hold can be only an
 * unstable equilibrium of the planner's own load model (a saddle: its stiffness K = −dQ/dxi
 * is not positive definite and the head, let go there, leaves). The library never calls an
 * answer REACHED that its own forward model does not confirm, so HOLD looks for a stable
 * member of the holding family (docs/load.md, "Stable holds") and a pose held only at a
 * saddle is neither REACHED nor CLOSEST. What this test asserts, on every backend that plans
 * the load level:
 *   - every answer, REACHED or CLOSEST, is a stable hold: K, assembled here from
 *     hp_load_eval's Jacobian, passes an independent Cholesky factorisation
 *     (tests/support/spd.h), and the forward statics of the returned pressures, started at
 *     the answer, rests within 1e-6 mm/deg of it (the statics' own stopping test is 1e-12
 *     mm/deg, so 1e-6 leaves room for nothing but a head that moves); a pose held only at a
 *     saddle is refused (SOLVER_ERROR, the safe output) with a message saying so;
 *   - none is silent: for every answer hp_planner_load_info, which solve and analyze print
 *     as "holding ... NOT stable" and "no rest found", reports the stability that check
 *     finds, and a rest error above 1e-6 mm/deg wherever the head leaves the answer;
 *   - every CLOSEST answer names a binding limit; one found instead of a saddle names
 *     "stability" (HP_BIND_STABILITY) on exactly the bladders that carry load there (their
 *     force from hp_load_eval, here), and its note says it is the nearest stable hold the
 *     search found, not a proven nearest stable pose.
 *
 * The cases follow the fidelity benchmark's (bench/bench_fidelity.c): the catalogue's load
 * scenes, each with its own correction and six seeded ones inside the clinical range
 * (|t| <= 20 mm, every angle <= 15°; the test's own seeds), planned with the scene's
 * settings; and the load tests' default layout (support/load_fixture.h) at the nominal
 * pose, the 10 mm lift and the small correction the planner tests use, and six seeded
 * corrections of at most 10 mm / 10°. */
#include "support/test_util.h"

#include "common/units.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"
#include "support/load_fixture.h"
#include "support/load_stiffness.h"
#include "support/spd.h"
#include "support/rng.h"

#include <stdlib.h>
#include <string.h>

#define SCN HP_SOURCE_DIR "/scenarios/"
#define N_SWEEP 6
#define T_MAX 0.020                    /* [m] */
#define ANGLE_MAX (15.0 * HP_PI / 180) /* [rad] */

static const char *const SCENES[] = {SCN "load_heavy.yaml", SCN "load_supine.yaml",
                                     SCN "load_tilted.yaml"};
#define NSCENE ((int)(sizeof SCENES / sizeof SCENES[0]))

/* K at (xi, P) (tests/support/load_stiffness.h) positive definite? */
static int stable_at(const hp_load_model *M, const double xi[6], const double *P)
{
    double K[36];
    assert_int_equal(test_load_stiffness(M, xi, P, K), 0);
    return test_positive_definite6(K);
}

/* N_SWEEP seeded corrections after t[0..n) (uniform direction, uniform size up to tmax
 * [m] and amax [rad]); returns the new count. */
static int sweep(uint64_t seed, double tmax, double amax, int n, double (*t)[6])
{
    for (int k = 0; k < N_SWEEP; ++k) {
        double u[6], nt = 0.0, nr = 0.0;
        for (int i = 0; i < 6; ++i) u[i] = test_rng_normal(&seed);
        for (int i = 0; i < 3; ++i) {
            nt += u[i] * u[i];
            nr += u[3 + i] * u[3 + i];
        }
        nt = sqrt(nt);
        nr = sqrt(nr);
        double at = tmax * test_rng_unit(&seed), ar = amax * test_rng_unit(&seed);
        for (int i = 0; i < 3; ++i) {
            t[n][i] = at * u[i] / nt;
            t[n][3 + i] = ar * u[3 + i] / nr;
        }
        ++n;
    }
    return n;
}

/* The load-level backends: the test runs every one that plans the load level. */
static const hp_backend BACKENDS[] = {HP_BACKEND_REALTIME, HP_BACKEND_IPOPT,
                                      HP_BACKEND_NLOPT_SLSQP};
#define NBACKEND ((int)(sizeof BACKENDS / sizeof BACKENDS[0]))

typedef struct tally {
    int answered, reached, stable_reached, stable_closest, unstable_answers, not_reached_unstable;
    int stability;  /* CLOSEST answers naming "stability" (found instead of a saddle) */
    int violations; /* answers (REACHED or CLOSEST) the forward model does not confirm */
} tally;

/* Plans every correction t[0..nc) on p from its reset state and checks each answer. */
static void check_plans(hp_planner *p, const char *what, const double (*t)[6], int nc, tally *y)
{
    const hp_load_model *M = hp_planner_load_model(p);
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
    for (int c = 0; c < nc; ++c) {
        hp_result r;
        hp_planner_reset(p);
        assert_int_equal(hp_plan(p, t[c], &r), HP_OK);
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < r.n; ++k) {
            P[k] = r.bladders[k].pressure;
            assert_true(P[k] >= lo[k] && P[k] <= hi[k]);
        }
        if (r.status != HP_STATUS_REACHED && r.status != HP_STATUS_CLOSEST) {
            /* A refusal names its cause; count the ones that are the saddle. */
            assert_true(hp_planner_error(p)[0] != '\0');
            y->not_reached_unstable += strstr(hp_planner_error(p),
                                              "only at an unstable equilibrium") != NULL;
            continue;
        }
        ++y->answered;
        y->reached += r.status == HP_STATUS_REACHED;
        hp_load_holding h;
        assert_int_equal(hp_load_holding_at(M, r.achieved, P, &h), HP_OK);
        int pd = stable_at(M, r.achieved, P);
        assert_int_equal(h.stable, pd);
        /* The forward model's check: the head, let go at the answer, stays there. */
        double rest[6], moved = INFINITY;
        if (hp_load_rest(M, P, r.achieved, rest, NULL) == HP_OK) {
            moved = 0.0;
            for (int i = 0; i < 6; ++i)
                moved = fmax(moved,
                             fabs(rest[i] - r.achieved[i]) / (i < 3 ? 1e-3 : HP_RAD_PER_DEG));
        }
        /* Never silent: the planner's own report says what the checks here find. */
        hp_load_info info;
        assert_int_equal(hp_planner_load_info(p, &info), HP_OK);
        assert_int_equal(info.holding.stable, pd);
        if (!(moved <= 1e-6)) assert_false(info.rest_error <= 1e-6);
        int confirmed = pd && moved <= 1e-6;
        if (!confirmed) {
            print_message("%s case %d: %s answer is not a stable equilibrium (weakest %s; its "
                          "rest from there moves %.3g mm/deg)\n",
                          what, c, hp_status_name(r.status), h.weakest_words, moved);
            ++y->unstable_answers;
        }
        y->violations += !confirmed;
        if (r.status == HP_STATUS_CLOSEST) {
            /* What binds is named (closest_names_binding); "stability" exactly where the
             * bladder carries load, computed here from the model. */
            double Q[6], force[HP_MAX_BLADDERS];
            assert_int_equal(hp_load_eval(M, r.achieved, P, Q, NULL, NULL, force, NULL), HP_OK);
            int named = 0, stab = 0, carrying = 0;
            for (int k = 0; k < r.n; ++k) {
                named += r.bladders[k].binding != 0;
                stab += (r.bladders[k].binding & HP_BIND_STABILITY) != 0;
                carrying += force[k] > 0.0;
            }
            assert_true(named > 0);
            if (stab) {
                for (int k = 0; k < r.n; ++k)
                    assert_int_equal((r.bladders[k].binding & HP_BIND_STABILITY) != 0,
                                     force[k] > 0.0);
                assert_true(carrying > 0);
                const char *note = hp_planner_note(p);
                assert_non_null(strstr(note, " stability"));
                assert_non_null(strstr(note, "the nearest stable hold the search found"));
                assert_non_null(strstr(note, "not a proven nearest stable pose"));
                ++y->stability;
            }
        } else {
            for (int k = 0; k < r.n; ++k)
                assert_int_equal(r.bladders[k].binding & HP_BIND_STABILITY, 0);
        }
        if (r.status == HP_STATUS_REACHED) y->stable_reached += confirmed;
        else y->stable_closest += confirmed;
    }
}

/* The catalogue's load scenes: the scene's correction, then N_SWEEP seeded ones. */
static void test_scenes(void **state)
{
    (void)state;
    tally y = {0};
    for (int s = 0; s < NSCENE; ++s)
        for (int b = 0; b < NBACKEND; ++b) {
            hp_scene *sc = malloc(sizeof *sc);
            assert_non_null(sc);
            hp_diag d = {{0}};
            assert_int_equal(hp_scene_load(SCENES[s], sc, &d), HP_OK);
            hp_settings set;
            assert_int_equal(hp_scene_settings(sc, &set, NULL), HP_OK);
            set.level = sc->load_geometry;
            set.backend = BACKENDS[b];
            set.use_rate_limits = 0;
            set.max_time = 60.0; /* the scenes' 1 s budget is wall-clock: never time-limit */
            hp_planner *p = NULL;
            assert_int_equal(load_create(&sc->layout, &sc->load, &set,
                                         (hp_load_tiebreak)sc->load_tiebreak, &p, &d),
                             HP_OK);
            double t[1 + N_SWEEP][6];
            int nc = 0;
            if (sc->has_correction) memcpy(t[nc++], sc->correction, sizeof t[0]);
            nc = sweep(0x5eed0000ull + (uint64_t)s, T_MAX, ANGLE_MAX, nc, t);
            char what[200];
            snprintf(what, sizeof what, "%s (%s)", SCENES[s], hp_backend_name(BACKENDS[b]));
            check_plans(p, what, (const double(*)[6])t, nc, &y);
            hp_planner_destroy(p);
            free(sc);
        }
    print_message("scenes: answers %d (reached %d, of them confirmed %d; closest confirmed %d, "
                  "naming stability %d), not confirmed %d; refused as unstable %d\n",
                  y.answered, y.reached, y.stable_reached, y.stable_closest, y.stability,
                  y.unstable_answers, y.not_reached_unstable);
    /* Without the stability flag these cases gave 39 answers and 12 refusals as saddles
     * (load_heavy's correction and two seeded ones, one seeded load_supine correction, on
     * each backend): their stable holds found nearby named no binding limit. Each of the
     * 12 is now a confirmed stable CLOSEST answer naming "stability" (checked above) or
     * still refused with the message, and fewer are refused. */
    assert_int_equal(y.answered + y.not_reached_unstable, 39 + 12);
    assert_true(y.not_reached_unstable < 12);
    assert_true(y.stability >= 12 - y.not_reached_unstable);
    /* load_supine's own correction is reached on each backend (the scenes' sweeps reach
     * beyond what their layouts hold: those answers are CLOSEST). */
    assert_true(y.stable_reached >= NBACKEND);
    assert_int_equal(y.violations, 0);
}

/* The load tests' default layout (support/load_fixture.h: 20 % of the default head under
 * the cap law): the nominal pose, the 10 mm lift, the planner tests' small correction, and
 * N_SWEEP seeded corrections of at most 10 mm and 10°. */
static void test_default_layout(void **state)
{
    (void)state;
    tally y = {0};
    double t[3 + N_SWEEP][6] = {{0},
                                {0, 0, 10e-3, 0, 0, 0},
                                {1e-3, 0, -0.5e-3, 0.3 * HP_RAD_PER_DEG, 0, -0.2 * HP_RAD_PER_DEG}};
    int nc = sweep(0x5eed0100ull, 10e-3, 10.0 * HP_RAD_PER_DEG, 3, t);
    for (int b = 0; b < NBACKEND; ++b) {
        hp_planner *p = load_lf_planner(BACKENDS[b], HP_LEVEL_LOAD, INFINITY, NULL);
        assert_non_null(p);
        check_plans(p, hp_backend_name(BACKENDS[b]), (const double(*)[6])t, nc, &y);
        hp_planner_destroy(p);
    }
    print_message("default layout: answers %d (reached %d, of them confirmed %d; closest "
                  "confirmed %d, naming stability %d), not confirmed %d; refused as unstable "
                  "%d\n",
                  y.answered, y.reached, y.stable_reached, y.stable_closest, y.stability,
                  y.unstable_answers, y.not_reached_unstable);
    assert_true(y.stable_reached >= 3);
    assert_int_equal(y.violations, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_scenes),
                                       cmocka_unit_test(test_default_layout)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
