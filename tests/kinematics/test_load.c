/* The load model: the membrane law against hand values, the exact derivatives of the
 * generalized force against Richardson-extrapolated central differences and against the
 * potential, the forward statics' rest against the Newton–Euler equations computed from
 * the contact points, and the compliance against the rest's response to a small weight. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "headplan/hp_load.h"

#include <string.h>

static hp_load_model *MOD[3]; /* linear, plane, surface */
static const hp_level LEVELS[3] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
/* Base bladders carry the weight, sides hold it laterally: a stable rest about 1 mm below
 * the nominal pose (lower side pressures give rests that are unstable in y or roll). */
static const double P_HOLD[8] = {6e3, 6e3, 6e3, 6e3, 7e3, 7e3, 7e3, 7e3};

static int setup(void **state)
{
    (void)state;
    hp_layout L;
    if (default_layout(&L) != 0) return -1;
    hp_load_spec s;
    hp_load_spec_default(&L.head, &s);
    s.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    for (int i = 0; i < 3; ++i)
        if (hp_load_model_create(&L, &s, LEVELS[i], &MOD[i], NULL) != HP_OK) return -1;
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    for (int i = 0; i < 3; ++i) hp_load_model_destroy(MOD[i]);
    return 0;
}

/* F = P·pi·(2·ro·delta − delta²) by hand: P = 10 kPa, ro = 30 mm (a free radius), delta = 1
 * mm gives pi·1e4·59e-6 = 1.85354 N; the spring rate 2·pi·P·ro = 1.885 kN/m of the issue. */
static void test_law_hand_values(void **state)
{
    (void)state;
    const hp_load_model *M = MOD[2];
    /* Find the pressure whose free radius is 30 mm + 1 mm past the nominal contact of
     * bladder 0, then check F at rho = ro − 1 mm through the public evaluation. */
    double ro, dro;
    assert_int_equal(hp_load_radius(M, 0, 1e4, &ro, &dro), HP_OK);
    /* Volume law and IK give ro; dro/dP against a central difference (h = 1 Pa: the
     * truncation h²·ro'''/6 is ~1e-20 m/Pa, rounding ε·0.03/1 ≈ 7e-18). */
    double rp, rm;
    assert_int_equal(hp_load_radius(M, 0, 1e4 + 1.0, &rp, NULL), HP_OK);
    assert_int_equal(hp_load_radius(M, 0, 1e4 - 1.0, &rm, NULL), HP_OK);
    hp_assert_close(dro, (rp - rm) / 2.0, 1e-6, 0.0);
    const double pi = 3.14159265358979323846;
    double delta = 1e-3, want = 1e4 * pi * (2.0 * ro * delta - delta * delta);
    /* Move the head away along bladder 0's normal so that rho_0 = ro − delta exactly at
     * the linear level: rho = rho0 + J·xi with J_0 = −nᵀ for translation. */
    const hp_load_model *ML = MOD[0];
    double n0[3], rho00;
    assert_int_equal(hp_layout_contact(hp_load_model_layout(ML), 0, NULL, n0, &rho00), HP_OK);
    double shift = ro - delta - rho00, xi[6] = {0};
    for (int i = 0; i < 3; ++i) xi[i] = -shift * n0[i];
    double P[8] = {1e4, 0, 0, 0, 0, 0, 0, 0}, Q[6], F[8];
    assert_int_equal(hp_load_eval(ML, xi, P, Q, NULL, NULL, F, NULL), HP_OK);
    hp_assert_close(F[0], want, 1e-12, 0.0);
    hp_assert_close(want, 1.0 * pi * 1e4 * (2.0 * ro - 1e-3) * 1e-3, 1e-14, 0.0);
    for (int k = 1; k < 8; ++k) assert_true(F[k] == 0.0); /* P = 0 carries nothing */
    /* A bladder at negative pressure or not touching carries nothing either. */
    P[0] = -1e3;
    assert_int_equal(hp_load_eval(ML, xi, P, Q, NULL, NULL, F, NULL), HP_OK);
    assert_true(F[0] == 0.0);
}

/* Richardson extrapolation of the central difference of f along coordinate i:
 * (4·D(h/2) − D(h))/3, error O(h⁴). */
typedef void (*vec_fn)(const hp_load_model *M, const double *x, double *out, int nout);

static void q_of_xi(const hp_load_model *M, const double *x, double *out, int nout)
{
    (void)nout;
    assert_int_equal(hp_load_eval(M, x, P_HOLD, out, NULL, NULL, NULL, NULL), HP_OK);
}

static const double *XI_AT;
static void q_of_p(const hp_load_model *M, const double *P, double *out, int nout)
{
    (void)nout;
    assert_int_equal(hp_load_eval(M, XI_AT, P, out, NULL, NULL, NULL, NULL), HP_OK);
}

static void richardson(const hp_load_model *M, vec_fn f, const double *x0, int nx, int i, double h,
                       int nout, double *d)
{
    double x[16], a[6], b[6], c[6], e[6];
    memcpy(x, x0, (size_t)nx * sizeof *x);
    x[i] = x0[i] + h;
    f(M, x, a, nout);
    x[i] = x0[i] - h;
    f(M, x, b, nout);
    x[i] = x0[i] + h / 2.0;
    f(M, x, c, nout);
    x[i] = x0[i] - h / 2.0;
    f(M, x, e, nout);
    for (int r = 0; r < nout; ++r) {
        double D1 = (a[r] - b[r]) / (2.0 * h), D2 = (c[r] - e[r]) / h;
        d[r] = (4.0 * D2 - D1) / 3.0;
    }
}

/* Pose where every bladder is in contact with P_HOLD (the sides expanded by 3 kPa, the base
 * sunk a few mm), with some rotation so no term vanishes by symmetry. */
static const double XI_TEST[6] = {0.4e-3, -0.3e-3, -3e-3, 0.01, -0.008, 0.012};

/* dQ/dxi and dQ/dP against Richardson differences (second method: Q = −dPi/dxi below).
 * Q is O(10 N) with derivatives O(1e4 N/m, 1e3 N·m/rad); steps h = 1e-5 m / rad (ξ) and
 * 2 Pa (P) keep every bladder on one branch of the law (none crosses delta = 0 within h;
 * asserted by forces > 0). Truncation of the extrapolated difference is h⁴·|Q^(5)|, below
 * 1e-20·1e15 ≈ 1e-5 of the derivative scale; rounding ε·|Q|/h ≈ 2e-10·... : tolerance
 * 1e-6 relative to the largest entry of each column. */
static void test_derivatives(void **state)
{
    (void)state;
    for (int l = 0; l < 3; ++l) {
        const hp_load_model *M = MOD[l];
        double Q[6], dX[36], dP[48], F[8];
        assert_int_equal(hp_load_eval(M, XI_TEST, P_HOLD, Q, dX, dP, F, NULL), HP_OK);
        for (int k = 0; k < 8; ++k) assert_true(F[k] > 0.1);
        for (int j = 0; j < 6; ++j) {
            double d[6], scale = 0.0;
            richardson(M, q_of_xi, XI_TEST, 6, j, 1e-5, 6, d);
            for (int r = 0; r < 6; ++r) scale = fmax(scale, fabs(d[r]));
            for (int r = 0; r < 6; ++r) hp_assert_close(dX[r * 6 + j], d[r], 0.0, 1e-6 * scale);
        }
        XI_AT = XI_TEST;
        for (int k = 0; k < 8; ++k) {
            double d[6], scale = 0.0;
            richardson(M, q_of_p, P_HOLD, 8, k, 2.0, 6, d);
            for (int r = 0; r < 6; ++r) scale = fmax(scale, fabs(d[r]));
            assert_true(scale > 0);
            for (int r = 0; r < 6; ++r) hp_assert_close(dP[r * 8 + k], d[r], 0.0, 1e-6 * scale);
        }
    }
}

/* Q = −dPi/dxi: the generalized force is the potential's gradient (a second, independent
 * formula: the cap volume and the centre of mass's height, no Jacobians). Richardson on Pi
 * with h = 1e-5: same tolerance reasoning as above. */
static void test_potential(void **state)
{
    (void)state;
    for (int l = 0; l < 3; ++l) {
        const hp_load_model *M = MOD[l];
        double Q[6], scale = 0.0;
        assert_int_equal(hp_load_eval(M, XI_TEST, P_HOLD, Q, NULL, NULL, NULL, NULL), HP_OK);
        for (int i = 0; i < 6; ++i) scale = fmax(scale, fabs(Q[i]));
        for (int j = 0; j < 6; ++j) {
            double x[6], e[4], hs[4] = {1e-5, -1e-5, 0.5e-5, -0.5e-5};
            for (int t = 0; t < 4; ++t) {
                double q[6];
                memcpy(x, XI_TEST, sizeof x);
                x[j] += hs[t];
                assert_int_equal(hp_load_eval(M, x, P_HOLD, q, NULL, NULL, NULL, &e[t]), HP_OK);
            }
            double D1 = (e[0] - e[1]) / 2e-5, D2 = (e[2] - e[3]) / 1e-5;
            hp_assert_close(-Q[j], (4.0 * D2 - D1) / 3.0, 0.0, 1e-6 * scale);
        }
    }
}

/* The forward statics finds a rest where Q vanishes and, at the plane and surface levels,
 * the Newton–Euler equations computed from the contact points hold: force below 1e-9 N
 * and moment below 1e-10 N·m (the weight is 44 N, lever arms 0.1 m: relative 1e-11).
 * The rest is stable (K positive definite) and independent of the starting pose. */
static void test_rest(void **state)
{
    (void)state;
    for (int l = 0; l < 3; ++l) {
        const hp_load_model *M = MOD[l];
        double xi[6], xi2[6];
        hp_load_rest_info info;
        assert_int_equal(hp_load_rest(M, P_HOLD, NULL, xi, &info), HP_OK);
        assert_true(info.q_norm < 1e-9);
        if (l > 0) {
            assert_true(info.residual_force < 1e-9);
            assert_true(info.residual_moment < 1e-10);
        }
        assert_true(info.holding.stable);
        assert_true(xi[2] < 0); /* the head sinks into the base */
        double start[6] = {2e-3, -2e-3, 3e-3, 0.02, 0.02, -0.02};
        assert_int_equal(hp_load_rest(M, P_HOLD, start, xi2, NULL), HP_OK);
        for (int i = 0; i < 6; ++i) hp_assert_close(xi2[i], xi[i], 0.0, 1e-12);
        /* Symmetric pressures on a left-right symmetric layout: no lateral shift, roll or
         * yaw at the rest. */
        assert_true(fabs(xi[0]) < 1e-12 && fabs(xi[4]) < 1e-12 && fabs(xi[5]) < 1e-12);
    }
}

/* With nothing inflated the head falls: no rest. */
static void test_no_rest(void **state)
{
    (void)state;
    double P[8] = {0}, xi[6];
    assert_int_equal(hp_load_rest(MOD[2], P, NULL, xi, NULL), HP_ERR_NO_CONVERGENCE);
}

/* The compliance K⁻¹ predicts how far the rest moves when the weight grows a little:
 * 1 % more mass (0.44 N) moves the rest by C·ΔW to first order; the second-order
 * remainder is ~1 % of the move, so a 3 % tolerance on the vertical component. */
static void test_compliance_predicts(void **state)
{
    (void)state;
    hp_load_spec heavier = *hp_load_model_spec(MOD[2]);
    heavier.mass *= 1.01;
    hp_load_model *M2 = NULL;
    assert_int_equal(hp_load_model_create(hp_load_model_layout(MOD[2]), &heavier,
                                          hp_load_model_level(MOD[2]), &M2, NULL),
                     HP_OK);
    double xi[6], xi2[6];
    hp_load_rest_info info;
    assert_int_equal(hp_load_rest(MOD[2], P_HOLD, NULL, xi, &info), HP_OK);
    assert_int_equal(hp_load_rest(M2, P_HOLD, xi, xi2, NULL), HP_OK);
    hp_load_model_destroy(M2);
    double dW = 0.01 * hp_load_model_spec(MOD[2])->mass * HP_GRAVITY;
    /* y and pitch couple with z: compare the full K⁻¹·ΔQ, not compliance[2] alone. */
    double K[36];
    memcpy(K, info.holding.K, sizeof K);
    double d[6] = {0, 0, -dW, 0, 0, 0};
    hp_test_solve6(K, d); /* K is positive definite here */
    hp_assert_close(xi2[2] - xi[2], d[2], 0.03, 0.0);
    assert_true(info.holding.compliance[2] > 0 && isfinite(info.holding.compliance[2]));
    assert_true(info.holding.sag > 0 && isfinite(info.holding.sag));
    assert_true(info.holding.weakest_compliance >= info.holding.compliance[0] * 0.999 ||
                info.holding.weakest_is_rotation);
}

/* auto's criterion. Without preload every bladder touches at zero pressure: no stiffness,
 * unbounded sag, the load level. With a 2 mm preload (each bladder inflated to reach the
 * head) the touching stiffness is k = sum_k 2·pi·P_k·rho_k·(u_k·ĝ)² by hand (the law's
 * dF/drho at delta = 0 along each pushing direction u_k = −n_k): the predicted sag equals
 * weight/k to rounding, and the decision flips exactly at tolerance = sag (both sides
 * tested, 1 % away). */
static void test_auto_choice(void **state)
{
    (void)state;
    int use;
    double sag;
    char why[200];
    assert_int_equal(hp_load_auto_choose(MOD[2], 1e-5, &use, &sag, why, sizeof why), HP_OK);
    assert_int_equal(use, 1);
    assert_true(isinf(sag));
    assert_non_null(strstr(why, "load"));
    hp_layout L;
    hp_head h = default_head();
    assert_int_equal(default_layout_on(&L, &h, 2e-3), 0);
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    hp_load_spec s;
    hp_load_spec_default(&L.head, &s);
    s.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    hp_load_model *M = NULL;
    assert_int_equal(hp_load_model_create(&L, &s, HP_LEVEL_SURFACE, &M, NULL), HP_OK);
    double kg;
    assert_int_equal(hp_load_predicted_sag(M, &sag, &kg), HP_OK);
    double k = 0.0;
    const double pi = 3.14159265358979323846;
    for (int j = 0; j < L.n; ++j) {
        double ri, P, nj[3], rho0;
        assert_int_equal(hp_layout_contact(hp_load_model_layout(M), j, NULL, nj, &rho0), HP_OK);
        assert_int_equal(hp_iab_ri(&L.bladders[j].iab, rho0, &ri), HP_OK);
        assert_int_equal(hp_iab_ik(&L.bladders[j].iab, ri, &P), HP_OK);
        assert_true(P > 0);
        double ug = nj[2]; /* u·ĝ = (−n)·(−ez) */
        k += 2.0 * pi * P * rho0 * ug * ug;
    }
    hp_assert_close(kg, k, 1e-12, 0.0);
    hp_assert_close(sag, s.mass * HP_GRAVITY / k, 1e-12, 0.0);
    assert_int_equal(hp_load_auto_choose(M, sag * 1.01, &use, NULL, why, sizeof why), HP_OK);
    assert_int_equal(use, 0);
    assert_non_null(strstr(why, "kinematic"));
    assert_int_equal(hp_load_auto_choose(M, sag * 0.99, &use, NULL, why, sizeof why), HP_OK);
    assert_int_equal(use, 1);
    assert_non_null(strstr(why, "load: predicted sag"));
    hp_load_model_destroy(M);
}

/* The model owns its layout and what is derived from it: the geometry stored at create
 * answers bit for bit as the public hp_contact_eval deriving it per call (each contact
 * force equals P·pi·(ro² − rho²) evaluated in the law's own operation order with rho from
 * hp_contact_eval on the model's layout), and editing the caller's layout after create
 * changes nothing (same bits as a model of an untouched copy; a model made from the edited
 * layout does differ, so the edit matters). */
static void test_owns_layout(void **state)
{
    (void)state;
    const double pi = 3.14159265358979323846;
    for (int l = 0; l < 3; ++l) {
        const hp_load_model *M = MOD[l];
        assert_int_equal(hp_load_model_level(M), LEVELS[l]);
        double rho[8], Q[6], F[8];
        assert_int_equal(
            hp_contact_eval(hp_load_model_layout(M), LEVELS[l], XI_TEST, rho, NULL, NULL), HP_OK);
        assert_int_equal(hp_load_eval(M, XI_TEST, P_HOLD, Q, NULL, NULL, F, NULL), HP_OK);
        for (int k = 0; k < 8; ++k) {
            double ro;
            assert_int_equal(hp_load_radius(M, k, P_HOLD[k], &ro, NULL), HP_OK);
            assert_true(ro > rho[k]);
            assert_true(F[k] == P_HOLD[k] * (pi * (ro - rho[k]) * (ro + rho[k])));
        }
    }
    hp_layout L, kept;
    assert_int_equal(default_layout(&L), 0);
    kept = L;
    hp_load_spec s;
    hp_load_spec_default(&L.head, &s);
    s.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    hp_load_model *M = NULL, *Mk = NULL, *Me = NULL;
    assert_int_equal(hp_load_model_create(&L, &s, HP_LEVEL_SURFACE, &M, NULL), HP_OK);
    L.bladders[0].center[2] -= 2e-3; /* edits after create */
    L.head.semi_axes[1] += 1e-3;
    s.mass *= 2.0;
    assert_int_equal(
        hp_load_model_create(&kept, hp_load_model_spec(M), HP_LEVEL_SURFACE, &Mk, NULL), HP_OK);
    assert_int_equal(hp_load_model_create(&L, &s, HP_LEVEL_SURFACE, &Me, NULL), HP_OK);
    assert_true(hp_load_model_layout(M)->bladders[0].center[2] == kept.bladders[0].center[2]);
    assert_true(hp_load_model_spec(M)->mass * 2.0 == s.mass);
    double Q[6], Qk[6], Qe[6], dQ[36], dQk[36];
    assert_int_equal(hp_load_eval(M, XI_TEST, P_HOLD, Q, dQ, NULL, NULL, NULL), HP_OK);
    assert_int_equal(hp_load_eval(Mk, XI_TEST, P_HOLD, Qk, dQk, NULL, NULL, NULL), HP_OK);
    assert_int_equal(hp_load_eval(Me, XI_TEST, P_HOLD, Qe, NULL, NULL, NULL, NULL), HP_OK);
    assert_memory_equal(Q, Qk, sizeof Q);
    assert_memory_equal(dQ, dQk, sizeof dQ);
    assert_memory_not_equal(Q, Qe, sizeof Q);
    hp_load_model_destroy(M);
    hp_load_model_destroy(Mk);
    hp_load_model_destroy(Me);
}

/* Bad input: every field of the load checked, NaN and infinity refused, outputs NaN on
 * error, a missing model refused by the calls that need one. */
static void test_bad_input(void **state)
{
    (void)state;
    hp_load_spec s;
    hp_load_spec_default(&hp_load_model_layout(MOD[0])->head, &s);
    s.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    assert_int_equal(hp_load_spec_validate(&s, NULL), HP_OK);
    hp_diag d;
    hp_load_spec b = s;
    b.mass = NAN;
    assert_int_equal(hp_load_spec_validate(&b, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "mass"));
    b = s;
    b.mass = 0.0;
    assert_int_equal(hp_load_spec_validate(&b, &d), HP_ERR_INVALID);
    b = s;
    b.com[1] = INFINITY;
    assert_int_equal(hp_load_spec_validate(&b, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "com"));
    b = s;
    b.gravity[2] = 0.0;
    assert_int_equal(hp_load_spec_validate(&b, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "gravity"));
    assert_int_equal(hp_load_spec_validate(NULL, &d), HP_ERR_NULL);
    hp_load_model *M = MOD[0];
    assert_int_equal(hp_load_model_create(hp_load_model_layout(MOD[0]), &s, HP_LEVEL_AUTO, &M, &d),
                     HP_ERR_INVALID);
    assert_null(M); /* *out is cleared on error */
    assert_non_null(strstr(d.text, "level"));
    assert_int_equal(
        hp_load_model_create(hp_load_model_layout(MOD[0]), &s, HP_LEVEL_SURFACE, NULL, &d),
        HP_ERR_NULL);
    assert_int_equal(hp_load_model_create(NULL, &s, HP_LEVEL_SURFACE, &M, &d), HP_ERR_NULL);
    assert_null(M);
    double xi[6] = {0, NAN, 0, 0, 0, 0}, Q[6], F[8];
    assert_int_equal(hp_load_eval(MOD[2], xi, P_HOLD, Q, NULL, NULL, F, NULL), HP_ERR_INVALID);
    for (int i = 0; i < 6; ++i) assert_true(isnan(Q[i]));
    xi[1] = 0.0;
    double P[8];
    memcpy(P, P_HOLD, sizeof P);
    P[3] = INFINITY;
    assert_int_equal(hp_load_eval(MOD[2], xi, P, Q, NULL, NULL, F, NULL), HP_ERR_INVALID);
    assert_int_equal(hp_load_rest(MOD[2], P, NULL, xi, NULL), HP_ERR_INVALID);
    /* No model: refused, outputs NaN; the accessors answer NULL / auto. */
    assert_int_equal(hp_load_eval(NULL, xi, P_HOLD, Q, NULL, NULL, NULL, NULL), HP_ERR_NULL);
    for (int i = 0; i < 6; ++i) assert_true(isnan(Q[i]));
    assert_int_equal(hp_load_rest(NULL, P_HOLD, NULL, xi, NULL), HP_ERR_NULL);
    assert_null(hp_load_model_layout(NULL));
    assert_null(hp_load_model_spec(NULL));
    assert_int_equal(hp_load_model_level(NULL), HP_LEVEL_AUTO);
    hp_load_model_destroy(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_law_hand_values), cmocka_unit_test(test_derivatives),
        cmocka_unit_test(test_potential),       cmocka_unit_test(test_rest),
        cmocka_unit_test(test_no_rest),         cmocka_unit_test(test_compliance_predicts),
        cmocka_unit_test(test_auto_choice),     cmocka_unit_test(test_owns_layout),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
