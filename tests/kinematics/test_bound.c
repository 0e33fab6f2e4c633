/* Error bounds of the linear and plane levels against the surface level, and the choice of
 * level by tolerance. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "kin_test_util.h"
#include "kinematics/kin_geom.h"
#include "common/units.h"

static hp_layout LAY;

static int setup(void **state)
{
    (void)state;
    return default_layout(&LAY);
}

/* Worst sampled |level − surface| over poses with |t| = T and |θ| = rot exactly (the bound
 * grows with both sizes, so the sphere surfaces hold the worst cases), plus a share inside. */
static double sampled_worst(const hp_layout *L, hp_level lv, double T, double rot, int count,
                            uint64_t seed)
{
    uint64_t rng = seed;
    double worst = 0.0;
    for (int it = 0; it < count; ++it) {
        double xi[6], rs[HP_MAX_BLADDERS], rl[HP_MAX_BLADDERS];
        kin_rng_pose(&rng, T, rot, it % 4 != 0, xi);
        assert_int_equal(hp_contact_eval(L, HP_LEVEL_SURFACE, xi, rs, NULL, NULL), HP_OK);
        assert_int_equal(hp_contact_eval(L, lv, xi, rl, NULL, NULL), HP_OK);
        for (int k = 0; k < L->n; ++k) worst = fmax(worst, fabs(rl[k] - rs[k]));
    }
    return worst;
}

/* Sizes from trivial to large; every sampled error must stay under the bound, and at the
 * moderate sizes (1..10 mm, 1..5°) the bound must be within ×20 of the sampled worst. */
static void test_bounds_hold_and_are_tight(void **state)
{
    (void)state;
    const double sizes[][2] = {{1e-5, 1e-4},    {0.001, 0.0175}, {0.003, 0.0349},
                               {0.005, 0.0524}, {0.010, 0.0873}, {0.005, 0.0},
                               {0.0, 0.0524},   {0.02, 0.2},     {0.04, 0.5}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; ++s)
        for (int lv = HP_LEVEL_LINEAR; lv <= HP_LEVEL_PLANE; ++lv) {
            double T = sizes[s][0], rot = sizes[s][1], b;
            assert_int_equal(hp_contact_error_bound(&LAY, (hp_level)lv, T, rot, &b), HP_OK);
            double w = sampled_worst(&LAY, (hp_level)lv, T, rot, 4000, 1000 + s);
            print_message("%-7s T %5.1f mm rot %5.2f deg: sampled %.3e mm bound %.3e mm (x%.2f)\n",
                          hp_level_name((hp_level)lv), T * 1e3, rot * 57.29578, w * 1e3, b * 1e3,
                          b / w);
            assert_true(w <= b);
            int moderate = T <= 0.010 && rot <= 0.0873 && (T >= 0.001 || rot >= 0.0175);
            if (moderate) assert_true(b <= 20.0 * w);
        }
    double b;
    assert_int_equal(hp_contact_error_bound(&LAY, HP_LEVEL_SURFACE, 0.01, 0.1, &b), HP_OK);
    assert_true(b == 0.0);
    assert_int_equal(hp_contact_error_bound(&LAY, HP_LEVEL_PLANE, 0.0, 0.0, &b), HP_OK);
    assert_true(b == 0.0);
    assert_int_equal(hp_contact_error_bound(&LAY, HP_LEVEL_PLANE, -1.0, 0.0, &b), HP_ERR_INVALID);
    assert_int_equal(hp_contact_error_bound(&LAY, HP_LEVEL_PLANE, 0.0, NAN, &b), HP_ERR_INVALID);
}

/* The bounds also hold on other heads and pivots: a sphere with an off-centre pivot, and a
 * flatter ellipsoid with the pivot 3 cm behind the head centre. */
static void test_bounds_other_layouts(void **state)
{
    (void)state;
    hp_head heads[2] = {default_head(), default_head()};
    heads[0].shape = HP_HEAD_SPHERE;
    heads[0].semi_axes[0] = 0.09;
    heads[1].semi_axes[0] = 0.06;
    heads[1].semi_axes[2] = 0.11;
    const double pivots[2][3] = {{0.01, 0.02, -0.01}, {0.0, 0.0, -0.03}};
    for (int c = 0; c < 2; ++c) {
        hp_layout L;
        assert_int_equal(default_layout_on(&L, &heads[c], 0.0), 0);
        for (int i = 0; i < 3; ++i) L.pivot[i] = pivots[c][i];
        assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
        const double sizes[3][2] = {{0.002, 0.02}, {0.01, 0.1}, {0.03, 0.3}};
        for (int s = 0; s < 3; ++s)
            for (int lv = HP_LEVEL_LINEAR; lv <= HP_LEVEL_PLANE; ++lv) {
                double b;
                assert_int_equal(
                    hp_contact_error_bound(&L, (hp_level)lv, sizes[s][0], sizes[s][1], &b), HP_OK);
                double w = sampled_worst(&L, (hp_level)lv, sizes[s][0], sizes[s][1], 2000, 77 + s);
                assert_true(w <= b);
            }
    }
}

/* The ordering linear >= plane and the choice of the cheapest level meeting tol. */
static void test_auto(void **state)
{
    (void)state;
    double bl, bp;
    const double T = 0.003, rot = 0.035;
    assert_int_equal(hp_contact_error_bound(&LAY, HP_LEVEL_LINEAR, T, rot, &bl), HP_OK);
    assert_int_equal(hp_contact_error_bound(&LAY, HP_LEVEL_PLANE, T, rot, &bp), HP_OK);
    assert_true(bp < bl);
    hp_level lv;
    assert_int_equal(hp_contact_auto(&LAY, bl * 1.0001, T, rot, &lv), HP_OK);
    assert_int_equal(lv, HP_LEVEL_LINEAR);
    assert_int_equal(hp_contact_auto(&LAY, 0.5 * (bl + bp), T, rot, &lv), HP_OK);
    assert_int_equal(lv, HP_LEVEL_PLANE);
    assert_int_equal(hp_contact_auto(&LAY, bp * 0.999, T, rot, &lv), HP_OK);
    assert_int_equal(lv, HP_LEVEL_SURFACE);
    assert_int_equal(hp_contact_auto(&LAY, 0.0, 0.0, 0.0, &lv), HP_OK);
    assert_int_equal(lv, HP_LEVEL_LINEAR); /* the zero correction is exact at every level */
    assert_int_equal(hp_contact_auto(&LAY, NAN, T, rot, &lv), HP_ERR_INVALID);
}

/* hpi_kin_contact_step_bound against the remainder itself: from random poses (|t| <= 20 mm,
 * |θ| <= 20°), steps of three sizes (translation <= 0.05·h m, rotation <= h rad, h = 1e-2,
 * 1e-3, 1e-4; a quarter pure translations, a quarter pure rotations), on the default head,
 * a sphere with an off-centre pivot and a flatter ellipsoid. The remainder
 * |rho(ξ + Δ) − rho(ξ) − J·Δ| must stay under the bound plus the evaluations' rounding
 * (3e-15 m: 64 roundings of a distance below 0.1 m, far below the remainders measured
 * here, ~1e-12..1e-6 m). The linear level's bound is 0 and its remainder only rounding. */
/* Layout c of three: the default head, a 90 mm sphere and an elongated ellipsoid, each
 * with the default bladders and its own pivot offset. */
static void three_layouts(int c, hp_layout *L, hp_geom *G)
{
    hp_head h = default_head();
    if (c == 1) {
        h.shape = HP_HEAD_SPHERE;
        h.semi_axes[0] = 0.09;
    } else if (c == 2) {
        h.semi_axes[0] = 0.06;
        h.semi_axes[2] = 0.11;
    }
    const double pivots[3][3] = {{0, 0, 0}, {0.01, 0.02, -0.01}, {0.0, 0.0, -0.03}};
    assert_int_equal(default_layout_on(L, &h, 0.0), 0);
    for (int i = 0; i < 3; ++i) L->pivot[i] += pivots[c][i];
    assert_int_equal(hp_layout_prepare(L, NULL), HP_OK);
    assert_int_equal(hpi_geom_derive(L, G, NULL), HP_OK);
}

static void test_step_bound(void **state)
{
    (void)state;
    const double hs[3] = {1e-2, 1e-3, 1e-4};
    uint64_t rng = 4711;
    for (int c = 0; c < 3; ++c) {
        hp_layout L;
        hp_geom G;
        three_layouts(c, &L, &G);
        for (int lv = HP_LEVEL_LINEAR; lv <= HP_LEVEL_SURFACE; ++lv) {
            double worst_ratio = 0.0; /* remainder / bound, printed */
            int infinite[3] = {0, 0, 0};
            for (int it = 0; it < 1500; ++it) {
                double h = hs[it % 3], xa[6], dx[6], xb[6];
                kin_rng_pose(&rng, 0.02, 0.35, 0, xa);
                kin_rng_pose(&rng, 0.05 * h, h, 0, dx);
                if (it % 4 == 1) dx[3] = dx[4] = dx[5] = 0.0;
                if (it % 4 == 2) dx[0] = dx[1] = dx[2] = 0.0;
                for (int i = 0; i < 6; ++i) xb[i] = xa[i] + dx[i];
                double ra[HP_MAX_BLADDERS], rb[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6],
                    b[HP_MAX_BLADDERS];
                assert_int_equal(hpi_contact_eval_g(&L, &G, (hp_level)lv, xa, ra, J, NULL), HP_OK);
                assert_int_equal(hpi_contact_eval_g(&L, &G, (hp_level)lv, xb, rb, NULL, NULL),
                                 HP_OK);
                assert_int_equal(hpi_kin_contact_step_bound(&L, &G, (hp_level)lv, xa, dx, ra, b),
                                 HP_OK);
                for (int k = 0; k < L.n; ++k) {
                    double lin = ra[k];
                    for (int i = 0; i < 6; ++i) lin += J[k * 6 + i] * dx[i];
                    double rem = fabs(rb[k] - lin);
                    if (lv == HP_LEVEL_LINEAR) assert_true(b[k] == 0.0);
                    /* infinite only where the step may come near the head (V >= rho) */
                    assert_true(b[k] >= 0.0);
                    if (b[k] == INFINITY) ++infinite[it % 3];
                    if (!(rem <= b[k] + 3e-15))
                        print_error("layout %d level %d step %d bladder %d: remainder %.3e m "
                                    "bound %.3e m\n",
                                    c, lv, it, k, rem, b[k]);
                    assert_true(rem <= b[k] + 3e-15);
                    if (b[k] > 0) worst_ratio = fmax(worst_ratio, rem / b[k]);
                }
            }
            print_message("layout %d %-7s: largest remainder / bound %.3f; infinite bounds "
                          "%d/%d/%d at h = 1e-2/1e-3/1e-4\n",
                          c, hp_level_name((hp_level)lv), worst_ratio, infinite[0], infinite[1],
                          infinite[2]);
            /* Steps of a converging solver (h <= 1e-4 here) always get a finite bound. */
            assert_int_equal(infinite[2], 0);
        }
        /* A step long enough to reach the head: no finite bound at the surface level. */
        double xa[6] = {0}, dx[6] = {0.2, 0, 0, 0, 0, 0}, ra[HP_MAX_BLADDERS], b[HP_MAX_BLADDERS];
        assert_int_equal(hpi_contact_eval_g(&L, &G, HP_LEVEL_SURFACE, xa, ra, NULL, NULL), HP_OK);
        assert_int_equal(hpi_kin_contact_step_bound(&L, &G, HP_LEVEL_SURFACE, xa, dx, ra, b),
                         HP_OK);
        for (int k = 0; k < L.n; ++k) assert_true(b[k] == INFINITY);
        /* Arguments */
        dx[0] = NAN;
        assert_int_equal(hpi_kin_contact_step_bound(&L, &G, HP_LEVEL_PLANE, xa, dx, ra, b),
                         HP_ERR_INVALID);
        dx[0] = 0.0;
        xa[4] = INFINITY;
        assert_int_equal(hpi_kin_contact_step_bound(&L, &G, HP_LEVEL_PLANE, xa, dx, ra, b),
                         HP_ERR_INVALID);
        xa[4] = 0.0;
        assert_int_equal(hpi_kin_contact_step_bound(&L, &G, HP_LEVEL_SURFACE, xa, dx, NULL, b),
                         HP_ERR_NULL);
        assert_int_equal(hpi_kin_contact_step_bound(&L, &G, HP_LEVEL_PLANE, xa, dx, NULL, b),
                         HP_OK);
        assert_int_equal(hpi_kin_contact_step_bound(&L, &G, HP_LEVEL_AUTO, xa, dx, ra, b),
                         HP_ERR_INVALID);
        assert_int_equal(hpi_kin_contact_step_bound(&L, NULL, HP_LEVEL_PLANE, xa, dx, ra, b),
                         HP_ERR_NULL);
    }
}

/* hpi_kin_contact_ball_curvature against the model's exact Hessians: at random poses inside
 * random balls (three heads, centres up to 20 mm / 20 deg, radii 0.01..5 scaled units) no
 * |vᵀHv| along random unit scaled directions, nor the largest eigenvalue magnitude of the
 * scaled Hessian, exceeds the bound; and the bound is not vacuous (the largest ratio is
 * printed and must exceed 1/50, so a bound inflated by a factor of 50 fails too). */
static void test_ball_curvature(void **state)
{
    (void)state;
    const double radii[4] = {0.01, 0.3, 1.0, 5.0};
    uint64_t rng = 977;
    for (int c = 0; c < 3; ++c) {
        hp_layout L;
        hp_geom G;
        three_layouts(c, &L, &G);
        for (int lv = HP_LEVEL_LINEAR; lv <= HP_LEVEL_SURFACE; ++lv) {
            double worst = 0.0;
            int infinite = 0;
            for (int it = 0; it < 400; ++it) {
                double r = radii[it % 4], xc[6], rc[HP_MAX_BLADDERS], h[HP_MAX_BLADDERS];
                kin_rng_pose(&rng, 0.02, 0.35, 0, xc);
                assert_int_equal(hpi_contact_eval_g(&L, &G, (hp_level)lv, xc, rc, NULL, NULL),
                                 HP_OK);
                assert_int_equal(hpi_kin_contact_ball_curvature(&L, &G, (hp_level)lv, xc, r, rc, h),
                                 HP_OK);
                for (int s = 0; s < 4; ++s) {
                    /* a point of the ball: a random scaled offset of length <= r */
                    double off[6], n2 = 0, p[6];
                    for (int i = 0; i < 6; ++i) {
                        off[i] = test_rng_normal(&rng);
                        n2 += off[i] * off[i];
                    }
                    double len = r * test_rng_uniform(&rng, 0.0, 1.0) / sqrt(n2);
                    if (s == 0) len = r / sqrt(n2); /* on its boundary */
                    for (int i = 0; i < 6; ++i)
                        p[i] = xc[i] + off[i] * len * (i < 3 ? 1e-3 : HP_PI / 180.0);
                    double rp[HP_MAX_BLADDERS], H[HP_MAX_BLADDERS * 36];
                    assert_int_equal(hpi_contact_eval_g(&L, &G, (hp_level)lv, p, rp, NULL, H),
                                     HP_OK);
                    for (int k = 0; k < L.n; ++k) {
                        if (lv == HP_LEVEL_LINEAR) {
                            assert_true(h[k] == 0.0);
                            continue;
                        }
                        assert_true(h[k] > 0.0);
                        /* infinite only at the surface level (a ball near the head) */
                        if (h[k] == INFINITY) {
                            assert_int_equal(lv, HP_LEVEL_SURFACE);
                            ++infinite;
                            continue;
                        }
                        /* the Hessian in mm per scaled unit² */
                        double Hs[36];
                        for (int a = 0; a < 6; ++a)
                            for (int b = 0; b < 6; ++b)
                                Hs[a * 6 + b] = 1e3 * H[k * 36 + a * 6 + b] *
                                                (a < 3 ? 1e-3 : HP_PI / 180.0) *
                                                (b < 3 ? 1e-3 : HP_PI / 180.0);
                        /* its spectral norm by power iteration on Hs² (symmetric): the
                         * Rayleigh quotient never exceeds the norm, so it is a fair test */
                        double v[6] = {1, 1, 1, 1, 1, 1}, lam = 0;
                        for (int pw = 0; pw < 60; ++pw) {
                            double w[6] = {0}, nn = 0;
                            for (int a = 0; a < 6; ++a)
                                for (int b = 0; b < 6; ++b) w[a] += Hs[a * 6 + b] * v[b];
                            for (int a = 0; a < 6; ++a) nn += w[a] * w[a];
                            nn = sqrt(nn);
                            if (!(nn > 0)) break;
                            lam = nn / sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3] +
                                            v[4] * v[4] + v[5] * v[5]);
                            for (int a = 0; a < 6; ++a) v[a] = w[a] / nn;
                        }
                        /* and one random direction's quadratic form */
                        double u[6], un = 0, q = 0;
                        for (int a = 0; a < 6; ++a) {
                            u[a] = test_rng_normal(&rng);
                            un += u[a] * u[a];
                        }
                        for (int a = 0; a < 6; ++a)
                            for (int b = 0; b < 6; ++b) q += u[a] * Hs[a * 6 + b] * u[b];
                        q = fabs(q) / un;
                        double m = fmax(lam, q);
                        if (!(m <= h[k]))
                            print_error("layout %d level %d ball %d bladder %d: |H| %.6e > bound "
                                        "%.6e mm/unit^2\n",
                                        c, lv, it, k, m, h[k]);
                        assert_true(m <= h[k]);
                        worst = fmax(worst, m / h[k]);
                    }
                }
            }
            if (lv == HP_LEVEL_LINEAR) continue;
            print_message("layout %d %-7s: largest |Hessian| / ball bound %.3f (infinite "
                          "bounds: %d of %d)\n",
                          c, hp_level_name((hp_level)lv), worst, infinite, 400 * 4 * L.n);
            assert_true(worst > 0.02);
            assert_true(infinite < 400 * L.n); /* balls of 5 units near the head only */
        }
        /* A ball that may reach the head: no finite bound at the surface level. */
        double x0[6] = {0}, r0[HP_MAX_BLADDERS], h[HP_MAX_BLADDERS];
        assert_int_equal(hpi_contact_eval_g(&L, &G, HP_LEVEL_SURFACE, x0, r0, NULL, NULL), HP_OK);
        assert_int_equal(hpi_kin_contact_ball_curvature(&L, &G, HP_LEVEL_SURFACE, x0, 200.0, r0, h),
                         HP_OK);
        for (int k = 0; k < L.n; ++k) assert_true(h[k] == INFINITY);
        /* Arguments */
        assert_int_equal(hpi_kin_contact_ball_curvature(&L, &G, HP_LEVEL_PLANE, x0, -1.0, r0, h),
                         HP_ERR_INVALID);
        assert_int_equal(hpi_kin_contact_ball_curvature(&L, &G, HP_LEVEL_PLANE, x0, NAN, r0, h),
                         HP_ERR_INVALID);
        assert_int_equal(hpi_kin_contact_ball_curvature(&L, &G, HP_LEVEL_SURFACE, x0, 1.0, NULL, h),
                         HP_ERR_NULL);
        assert_int_equal(hpi_kin_contact_ball_curvature(&L, &G, HP_LEVEL_AUTO, x0, 1.0, r0, h),
                         HP_ERR_INVALID);
        x0[3] = NAN;
        assert_int_equal(hpi_kin_contact_ball_curvature(&L, &G, HP_LEVEL_PLANE, x0, 1.0, r0, h),
                         HP_ERR_INVALID);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bounds_hold_and_are_tight),
        cmocka_unit_test(test_bounds_other_layouts),
        cmocka_unit_test(test_auto),
        cmocka_unit_test(test_step_bound),
        cmocka_unit_test(test_ball_curvature),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
