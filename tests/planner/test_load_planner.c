/* The load-level planner (realtime): reachable poses are held (equilibrium residual below
 * 1e-9 N, round trip through the forward statics), an unreachable pose gives the nearest
 * held one with the binding limits named, every pressure stays inside its bounds, and
 * layouts that cannot carry the head are refused at create with the direction named. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "headplan/hp_planner.h"
#include "support/load_fixture.h"
#include "support/load_stiffness.h"
#include "kinematics/linalg.h"
#include "kinematics/load_internal.h"
#include "planner/load_solve.h"
#include "planner/load_stable.h"

#include <string.h>

/* The default layout with stretch_max raised to 1.6 (p_max 10 kPa then binds first at
 * about 8 kPa... the stretch cap is ~9 kPa): the base bladders can then carry the 4.5 kg
 * head at the nominal pose. With the default 1.3 they cannot (test_unreachable). */
static void layout_with(hp_layout *L, double stretch_max)
{
    assert_int_equal(default_layout(L), 0);
    for (int k = 0; k < L->n; ++k) L->bladders[k].stretch_max = stretch_max;
    assert_int_equal(hp_layout_prepare(L, NULL), HP_OK);
}

/* The default layout at stretch_max carrying the default head's weight. */
static void loaded(hp_layout *L, hp_load_spec *s, double stretch_max)
{
    layout_with(L, stretch_max);
    hp_load_spec_default(&L->head, s);
    s->law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
}

static hp_planner *make_at(const hp_layout *L, const hp_load_spec *s, hp_level level)
{
    hp_planner *p = NULL;
    hp_diag d;
    d.text[0] = '\0';
    hp_settings set;
    hp_settings_default(&set);
    set.max_time = 60.0; /* the outcome, not the clock, is asserted */
    set.level = level;
    hp_error e = load_create(L, s, &set, HP_TIE_LEAST_SQUEEZE, &p, &d);
    if (e) print_error("create: %s\n", d.text);
    assert_int_equal(e, HP_OK);
    return p;
}

static hp_planner *make(const hp_layout *L, const hp_load_spec *s)
{
    return make_at(L, s, HP_LEVEL_SURFACE);
}

static void assert_in_bounds(const hp_planner *p, const hp_result *r)
{
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
    for (int k = 0; k < r->n; ++k) {
        assert_true(isfinite(r->bladders[k].pressure));
        assert_true(r->bladders[k].pressure >= lo[k] && r->bladders[k].pressure <= hi[k]);
    }
}

/* The supine scene of the tests: the default layout at stretch_max 1.6 carrying the whole
 * head along −Z; settings at the surface level on the realtime backend. */
static void supine(hp_layout *L, hp_load_spec *s, hp_settings *set)
{
    loaded(L, s, 1.6);
    hp_settings_default(set);
    set->max_time = 60.0; /* the outcome, not the clock, is asserted */
    set->level = HP_LEVEL_SURFACE;
}

/* Nominal pose, reachable: REACHED, the generalized force below 1e-9 N, the Newton–Euler
 * residual from the contact points below 1e-9 N, and the forward statics started at the
 * NOMINAL pose (not at the answer) returns the desired pose to 1e-8 mm: the hold is stable
 * with its smallest stiffness eigenvalue at least the 0.01 N/mm margin (a compliance of at
 * most 100 mm/N), so 1e-12 N of residual moves it at most 1e-10 mm. */
static void test_reached_nominal(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    loaded(&L, &s, 1.6);
    hp_planner *p = make(&L, &s);
    double d[6] = {0}, Q[6], P[HP_MAX_BLADDERS];
    hp_result r;
    hp_load_info info;
    assert_int_equal(load_plan(p, d, &r, &info), HP_OK);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    assert_true(r.pose_error == 0.0);
    assert_in_bounds(p, &r);
    for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure;
    assert_int_equal(
        hp_load_eval(hp_planner_load_model(p), r.achieved, P, Q, NULL, NULL, NULL, NULL), HP_OK);
    for (int i = 0; i < 6; ++i) assert_true(fabs(Q[i]) < 1e-9);
    assert_true(info.residual_force < 1e-9);
    assert_true(info.residual_moment < 1e-10);
    /* The plain least-squeeze pick (HOLD alone) is unique and symmetric: its four base
     * forces are equal. It is a saddle here, so the answer is the least squeeze among the
     * stable holds, which need not be symmetric (a mirror pair of stable holds can beat
     * every symmetric one). The answer squeezes no less than the pick and is stable. */
    const hp_load_model *M = hp_planner_load_model(p);
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], t0[HP_MAX_BLADDERS] = {0}, Pp[HP_MAX_BLADDERS],
                                                     Fp[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
    assert_int_equal(hpi_load_hold(M, d, lo, hi, t0, NULL, 200, Pp, Fp, NULL), HP_LOAD_SOLVE_OK);
    for (int k = 1; k < 4; ++k) hp_assert_close(Fp[k], Fp[0], 1e-9, 0.0);
    double sp = 0.0, sa = 0.0;
    for (int k = 0; k < r.n; ++k) {
        sp += Pp[k] * Pp[k];
        sa += P[k] * P[k];
    }
    assert_true(test_load_smallest_stiffness(M, d, Pp) < 0.0);
    assert_true(test_load_smallest_stiffness(M, d, P) >= HP_LOAD_STABLE_MARGIN);
    assert_true(sa >= sp);
    double rest[6];
    assert_int_equal(hp_load_rest(hp_planner_load_model(p), P, NULL, rest, NULL), HP_OK);
    for (int i = 0; i < 6; ++i)
        assert_true(fabs(rest[i] - d[i]) / (i < 3 ? 1e-3 : 0.0174532925199) < 1e-8);
    hp_planner_destroy(p);
}

/* A vertical lift of 10 mm is held too (higher pressures, sides joining in); the rest
 * started at the answer stays there to 1e-9 mm. */
static void test_reached_lift(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    loaded(&L, &s, 1.6);
    hp_planner *p = make(&L, &s);
    double d[6] = {0, 0, 10e-3, 0, 0, 0};
    hp_result r;
    hp_load_info info;
    assert_int_equal(load_plan(p, d, &r, &info), HP_OK);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    assert_in_bounds(p, &r);
    assert_true(info.residual_force < 1e-9 && info.residual_moment < 1e-10);
    assert_true(info.rest_error < 1e-9);
    /* The least-squeeze pick at this pose is a saddle of the potential (K not positive
     * definite: test_tiebreak_stiffness); a REACHED answer is the least squeeze among the
     * stable holds instead: K positive definite with its smallest eigenvalue (assembled
     * here from hp_load_eval) at least the stable margin, a finite weakest compliance. */
    assert_int_equal(info.holding.stable, 1);
    assert_true(isfinite(info.holding.weakest_compliance));
    double P[HP_MAX_BLADDERS];
    for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure;
    assert_true(test_load_smallest_stiffness(hp_planner_load_model(p), d, P) >=
                HP_LOAD_STABLE_MARGIN);
    hp_planner_destroy(p);
}

/* An asymmetric correction at every contact level: REACHED, generalized force below 1e-9
 * N; at the plane and surface levels also the Newton–Euler equations from the contact
 * points (at the linear level they measure the linearisation's own error instead). */
static void test_levels(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    loaded(&L, &s, 1.6);
    const hp_level lv[3] = {HP_LEVEL_LINEAR, HP_LEVEL_PLANE, HP_LEVEL_SURFACE};
    const double d[6] = {1e-3, 0, -0.5e-3, 0.3 * 0.0174532925199, 0, -0.2 * 0.0174532925199};
    for (int l = 0; l < 3; ++l) {
        hp_planner *p = make_at(&L, &s, lv[l]);
        hp_result r;
        hp_load_info info;
        double Q[6], P[HP_MAX_BLADDERS];
        assert_int_equal(load_plan(p, d, &r, &info), HP_OK);
        assert_int_equal(r.status, HP_STATUS_REACHED);
        assert_int_equal(r.level, HP_LEVEL_LOAD);
        assert_int_equal(hp_load_model_level(hp_planner_load_model(p)), lv[l]);
        assert_in_bounds(p, &r);
        for (int k = 0; k < r.n; ++k) P[k] = r.bladders[k].pressure;
        assert_int_equal(
            hp_load_eval(hp_planner_load_model(p), r.achieved, P, Q, NULL, NULL, NULL, NULL),
            HP_OK);
        for (int i = 0; i < 6; ++i) assert_true(fabs(Q[i]) < 1e-9);
        if (l > 0) assert_true(info.residual_force < 1e-9 && info.residual_moment < 1e-10);
        hp_planner_destroy(p);
    }
}

/* First-order optimality of the least-squeeze answer, checked from outside: for the
 * bladders that carry and sit strictly inside their bounds, P must lie in the span of
 * the columns of dQ/dP (the gradient of sum P² is a combination of the constraints'
 * gradients). Least squares for the six multipliers; the residual must be below 1e-6 of
 * |P| (the solvers stop at micropascal steps). */
static int assert_kkt(const hp_planner *p, const hp_result *r, const hp_load_info *info)
{
    const hp_load_model *M = hp_planner_load_model(p);
    double P[HP_MAX_BLADDERS], Q[6], G[6 * HP_MAX_BLADDERS], lo[HP_MAX_BLADDERS],
        hi[HP_MAX_BLADDERS];
    int n = r->n, free_[HP_MAX_BLADDERS], nf = 0;
    assert_int_equal(hp_planner_pressure_bounds(p, lo, hi), HP_OK);
    for (int k = 0; k < n; ++k) P[k] = r->bladders[k].pressure;
    assert_int_equal(hp_load_eval(M, r->achieved, P, Q, NULL, G, NULL, NULL), HP_OK);
    for (int k = 0; k < n; ++k)
        if (info->force[k] > 0 && P[k] > lo[k] + 1.0 && P[k] < hi[k] - 1.0) free_[nf++] = k;
    if (nf <= 6) return nf; /* as many equations as free pressures: nothing to choose */
    /* Normal equations (G_f G_fᵀ) mu = G_f P_f, 6×6, by Gaussian elimination. */
    double A[36] = {0}, y[6] = {0}, mu[6];
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 6; ++j)
            for (int a = 0; a < nf; ++a) A[i * 6 + j] += G[i * n + free_[a]] * G[j * n + free_[a]];
        for (int a = 0; a < nf; ++a) y[i] += G[i * n + free_[a]] * P[free_[a]];
    }
    memcpy(mu, y, sizeof mu);
    hp_test_solve6(A, mu);
    double res = 0.0, norm = 0.0;
    for (int a = 0; a < nf; ++a) {
        double v = P[free_[a]];
        for (int i = 0; i < 6; ++i) v -= G[i * n + free_[a]] * mu[i];
        res = fmax(res, fabs(v));
        norm = fmax(norm, fabs(P[free_[a]]));
    }
    if (!(res <= 1e-6 * norm)) print_error("KKT residual %g Pa of %g Pa\n", res, norm);
    assert_true(res <= 1e-6 * norm);
    return nf;
}

/* The realtime, Ipopt and NLopt SLSQP backends agree on reachable poses: the same
 * pressures to 1e-6 Pa. Both start the tie-breaker from the same exact feasibility point
 * (phase 1) and solve it independently (SQP on the QP of load_qp.c vs Ipopt's interior
 * point with the exact Hessian); phase 2 moves the pressures (e.g. the side bladders from
 * 1.8 N to nothing at the nominal pose), so the agreement is not a shared starting
 * point. Both answers are held (equilibrium residual below 1e-9 N). Where the plain
 * least-squeeze pick (HOLD alone, hpi_load_hold) is a stable hold the answer is that pick
 * and meets least squeeze's first-order conditions; where it is not, the answer is a
 * stable hold (smallest eigenvalue at least the stable margin) that squeezes no less than
 * the pick (it is the least squeeze among the stable holds, a subset). */
static void test_backends_agree(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    loaded(&L, &s, 1.6);
    hp_settings set;
    hp_settings_default(&set);
    set.max_time = 60.0; /* the outcome, not the clock, is asserted */
    set.level = HP_LEVEL_SURFACE;
    hp_planner *p[3];
    hp_diag d;
    const hp_backend backends[3] = {HP_BACKEND_REALTIME, HP_BACKEND_IPOPT, HP_BACKEND_NLOPT_SLSQP};
    for (int b = 0; b < 3; ++b) {
        set.backend = backends[b];
        assert_int_equal(load_create(&L, &s, &set, HP_TIE_LEAST_SQUEEZE, &p[b], &d), HP_OK);
    }
    const double deg = 0.0174532925199;
    const double ds[3][6] = {{1e-3, 0, -0.5e-3, 0.3 * deg, 0, -0.2 * deg},
                             {0, 0, 5e-3, 0, 0, 0},
                             {-1e-3, 1e-3, 2e-3, 0.6 * deg, 0.6 * deg, 0}};
    int chosen = 0;
    for (int q = 0; q < 3; ++q) {
        hp_result r[3];
        hp_load_info in[3];
        for (int b = 0; b < 3; ++b) {
            assert_int_equal(load_plan(p[b], ds[q], &r[b], &in[b]), HP_OK);
            assert_int_equal(r[b].status, HP_STATUS_REACHED);
            assert_true(in[b].residual_force < 1e-9 && in[b].residual_moment < 1e-10);
            const hp_load_model *M = hp_planner_load_model(p[b]);
            double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS],
                t0[HP_MAX_BLADDERS] = {0}, Pp[HP_MAX_BLADDERS], Fp[HP_MAX_BLADDERS],
                P[HP_MAX_BLADDERS];
            assert_int_equal(hp_planner_pressure_bounds(p[b], lo, hi), HP_OK);
            assert_int_equal(hpi_load_hold(M, ds[q], lo, hi, t0, NULL, 200, Pp, Fp, NULL),
                             HP_LOAD_SOLVE_OK);
            double sp = 0.0, sa = 0.0;
            for (int k = 0; k < r[b].n; ++k) {
                P[k] = r[b].bladders[k].pressure;
                sp += Pp[k] * Pp[k];
                sa += P[k] * P[k];
            }
            if (test_load_smallest_stiffness(M, ds[q], Pp) >= HP_LOAD_STABLE_MARGIN) {
                chosen += assert_kkt(p[b], &r[b], &in[b]) > 6;
            } else {
                assert_true(test_load_smallest_stiffness(M, ds[q], P) >= HP_LOAD_STABLE_MARGIN);
                assert_true(sa >= sp * (1.0 - 1e-12));
            }
        }
        for (int b = 1; b < 3; ++b)
            for (int k = 0; k < r[0].n; ++k)
                hp_assert_close(r[b].bladders[k].pressure, r[0].bladders[k].pressure, 0.0, 1e-6);
    }
    (void)chosen; /* least squeeze mostly ends with six carrying bladders: a vertex, where
                   * this check has nothing to test; the agreement below still does */
    for (int b = 0; b < 3; ++b) hp_planner_destroy(p[b]);
}

/* With stretch_max 1.3 the base cannot hold 80 % of the head at the nominal pose: CLOSEST,
 * lower (z < 0), every bladder at its stretch cap with the stretch_max flag, and still an
 * equilibrium (residual below 1e-9 N) whose forward statics is the returned pose. (The
 * whole head is beyond these limits inside the indentation range: no pose holds it.) */
static void test_unreachable(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    loaded(&L, &s, 1.3);
    s.mass *= 0.8;
    hp_planner *p = make(&L, &s);
    double d[6] = {0};
    hp_result r;
    hp_load_info info;
    assert_int_equal(load_plan(p, d, &r, &info), HP_OK);
    assert_int_equal(r.status, HP_STATUS_CLOSEST);
    assert_true(r.achieved[2] < -1e-4); /* 0.42 mm lower */
    assert_in_bounds(p, &r);
    for (int k = 0; k < 4; ++k) assert_true(r.bladders[k].binding & HP_BIND_STRETCH_MAX);
    assert_true(info.residual_force < 1e-9 && info.residual_moment < 1e-10);
    assert_true(info.rest_error < 1e-9);
    hp_planner_destroy(p);
}

/* A hoop-stress limit below the stretch cap's stress binds by the name stress_max, at the
 * load level (the base cannot hold the head at the nominal pose any more: closest, lower)
 * and in the kinematic planner (a 25 mm lift needs the base past the limit). Every returned
 * bladder's inner hoop stress stays within its limit (1e-9 relative: the bisection's
 * bound side). */
static void test_stress_binding(void **state)
{
    (void)state;
    hp_layout L;
    layout_with(&L, 1.6);
    double s_cap;
    assert_int_equal(
        hp_iab_hoop_stress_inner(&L.bladders[0].iab, 1.6 * L.bladders[0].iab.Ri, &s_cap), HP_OK);
    for (int k = 0; k < 4; ++k) L.bladders[k].stress_max = 0.3 * s_cap;
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    hp_load_spec s;
    hp_load_spec_default(&L.head, &s);
    s.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    s.mass *= 0.8; /* the whole head is beyond the indentation range at this stress limit */
    hp_planner *p = make(&L, &s);
    double d[6] = {0};
    hp_result r;
    hp_load_info info;
    assert_int_equal(load_plan(p, d, &r, &info), HP_OK);
    assert_int_equal(r.status, HP_STATUS_CLOSEST);
    int bound = 0;
    for (int k = 0; k < r.n; ++k) {
        double h;
        assert_int_equal(hp_iab_hoop_stress_inner(&L.bladders[k].iab, r.bladders[k].ri, &h), HP_OK);
        if (k < 4) assert_true(h <= 0.3 * s_cap * (1 + 1e-9));
        bound += (r.bladders[k].binding & HP_BIND_STRESS_MAX) != 0;
    }
    assert_true(bound >= 1);
    assert_string_equal(hp_binding_name(HP_BIND_STRESS_MAX), "stress_max");
    hp_planner_destroy(p);

    hp_planner *kp = NULL;
    assert_int_equal(hp_planner_create(&L, NULL, &kp, NULL), HP_OK);
    double lift[6] = {0, 0, 25e-3, 0, 0, 0};
    assert_int_equal(hp_plan(kp, lift, &r), HP_OK);
    assert_int_equal(r.status, HP_STATUS_CLOSEST);
    bound = 0;
    for (int k = 0; k < 4; ++k) {
        double h;
        assert_int_equal(hp_iab_hoop_stress_inner(&L.bladders[k].iab, r.bladders[k].ri, &h), HP_OK);
        assert_true(h <= 0.3 * s_cap * (1 + 1e-9));
        bound += (r.bladders[k].binding & HP_BIND_STRESS_MAX) != 0;
    }
    assert_true(bound >= 1);
    hp_planner_destroy(kp);
}

/* A layout of base bladders only, with gravity pointing anterior (+z, a prone patient):
 * nothing pushes the head down, and create says which way support is missing. A weight
 * beyond what the bladders can carry at their largest pressures is refused too. */
static void test_refused(void **state)
{
    (void)state;
    hp_layout L;
    layout_with(&L, 1.3);
    L.n = 4;
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    hp_load_spec s;
    hp_load_spec_default(&L.head, &s);
    s.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
    s.gravity[2] = +HP_GRAVITY;
    hp_planner *p = (hp_planner *)1;
    hp_diag d;
    assert_int_equal(load_create(&L, &s, NULL, HP_TIE_LEAST_SQUEEZE, &p, &d), HP_ERR_INVALID);
    assert_null(p);
    assert_non_null(strstr(d.text, "no bladder pushes against gravity"));
    assert_non_null(strstr(d.text, "-z"));
    s.gravity[2] = -HP_GRAVITY;
    s.mass = 100.0;
    assert_int_equal(load_create(&L, &s, NULL, HP_TIE_LEAST_SQUEEZE, &p, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "can carry at most"));
    /* A sphere head cannot be held at the load level. */
    hp_layout S;
    hp_head h = default_head();
    h.shape = HP_HEAD_SPHERE;
    h.semi_axes[0] = h.semi_axes[1] = h.semi_axes[2] = 0.09;
    assert_int_equal(default_layout_on(&S, &h, 0.0), 0);
    s.mass = 4.5;
    assert_int_equal(load_create(&S, &s, NULL, HP_TIE_LEAST_SQUEEZE, &p, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, "sphere"));
}

/* The `previous` tie-breaker: planning the same pose again returns the same pressures
 * (the previous ones hold it: distance 0), and a nearby pose's pressures are closer to the
 * previous ones than least squeeze's are (sum of squares). */
static void test_tiebreak_previous(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    loaded(&L, &s, 1.6);
    hp_settings set;
    hp_settings_default(&set);
    set.max_time = 60.0; /* the outcome, not the clock, is asserted */
    set.level = HP_LEVEL_SURFACE;
    hp_planner *prev = NULL, *ls = NULL;
    assert_int_equal(load_create(&L, &s, &set, HP_TIE_PREVIOUS, &prev, NULL), HP_OK);
    assert_int_equal(load_create(&L, &s, &set, HP_TIE_LEAST_SQUEEZE, &ls, NULL), HP_OK);
    const double a[6] = {0, 0, 5e-3, 0, 0, 0}, b[6] = {0.5e-3, 0, 5.5e-3, 0, 0, 0};
    hp_result r0, r1, r2, q;
    assert_int_equal(load_plan(prev, a, &r0, NULL), HP_OK);
    assert_int_equal(load_plan(prev, a, &r1, NULL), HP_OK);
    for (int k = 0; k < r0.n; ++k)
        hp_assert_close(r1.bladders[k].pressure, r0.bladders[k].pressure, 0.0, 1e-6);
    assert_int_equal(load_plan(prev, b, &r2, NULL), HP_OK);
    assert_int_equal(load_plan(ls, b, &q, NULL), HP_OK);
    assert_int_equal(r2.status, HP_STATUS_REACHED);
    double dp = 0.0, dl = 0.0;
    for (int k = 0; k < r0.n; ++k) {
        double e = r2.bladders[k].pressure - r1.bladders[k].pressure;
        double f = q.bladders[k].pressure - r1.bladders[k].pressure;
        dp += e * e;
        dl += f * f;
    }
    assert_true(dp <= dl * (1 + 1e-9));
    assert_string_equal(hp_load_tiebreak_name(HP_TIE_PREVIOUS), "previous");
    hp_load_tiebreak t;
    assert_int_equal(hp_load_tiebreak_parse("least-squeeze", &t), HP_OK);
    assert_int_equal(t, HP_TIE_LEAST_SQUEEZE);
    assert_int_equal(hp_load_tiebreak_parse("stiff", &t), HP_ERR_INVALID);
    hp_planner_destroy(prev);
    hp_planner_destroy(ls);
}

/* The minimum-holding-stiffness tie-breaker (Ipopt) at the 10 mm lift, where the plain
 * least-squeeze pick is a saddle and the planner's least squeeze among the stable holds sits
 * near the stable margin (test_reached_lift): the stiffness answer is REACHED, an
 * equilibrium (1e-9 N), STABLE (K positive definite), with a smallest stiffness eigenvalue
 * above least squeeze's, and the forward statics started 0.5 mm / 0.5° away (not at the
 * answer) returns the desired pose to 1e-8 mm / degree (the stable rest attracts; the
 * softest direction's compliance is below 1e3 mm/N, so 1e-12 N of rounding moves it far
 * less). Realtime and NLopt refuse the tie-breaker by name at create. */
static void test_tiebreak_stiffness(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    hp_settings set;
    supine(&L, &s, &set);
    hp_planner *ls = NULL, *st = NULL;
    hp_diag d;
    d.text[0] = '\0';
    assert_int_equal(load_create(&L, &s, &set, HP_TIE_LEAST_SQUEEZE, &ls, &d), HP_OK);
    for (int b = 0; b < 2; ++b) {
        set.backend = b ? HP_BACKEND_NLOPT_SLSQP : HP_BACKEND_REALTIME;
        assert_int_equal(load_create(&L, &s, &set, HP_TIE_STIFFNESS, &st, &d), HP_ERR_INVALID);
        assert_null(st);
        assert_non_null(strstr(d.text, "stiffness"));
        assert_non_null(strstr(d.text, "ipopt"));
    }
    set.backend = HP_BACKEND_IPOPT;
    hp_error e = load_create(&L, &s, &set, HP_TIE_STIFFNESS, &st, &d);
    if (e) print_error("create: %s\n", d.text);
    assert_int_equal(e, HP_OK);
    const double lift[6] = {0, 0, 10e-3, 0, 0, 0};
    hp_result r0, r1;
    hp_load_info i0, i1;
    assert_int_equal(load_plan(ls, lift, &r0, &i0), HP_OK);
    assert_int_equal(load_plan(st, lift, &r1, &i1), HP_OK);
    assert_int_equal(r0.status, HP_STATUS_REACHED);
    assert_int_equal(i0.holding.stable, 1); /* least squeeze among the stable holds */
    assert_int_equal(r1.status, HP_STATUS_REACHED);
    assert_in_bounds(st, &r1);
    assert_true(i1.residual_force < 1e-9 && i1.residual_moment < 1e-10);
    if (!i1.holding.stable)
        print_error("stiffness hold not stable: %s\n", i1.holding.weakest_words);
    assert_int_equal(i1.holding.stable, 1);
    assert_true(i1.holding.weakest_compliance < 1e3);
    const hp_load_model *M = hp_planner_load_model(st);
    double P[HP_MAX_BLADDERS], x0[6], rest[6], lam[2];
    for (int k = 0; k < r1.n; ++k) P[k] = r1.bladders[k].pressure;
    for (int i = 0; i < 6; ++i) x0[i] = lift[i] + 0.5 * hpi_load_unit(i);
    assert_int_equal(hp_load_rest(M, P, x0, rest, NULL), HP_OK);
    for (int i = 0; i < 6; ++i) assert_true(fabs(rest[i] - lift[i]) / hpi_load_unit(i) < 1e-8);
    double P0[HP_MAX_BLADDERS];
    for (int k = 0; k < r0.n; ++k) P0[k] = r0.bladders[k].pressure;
    lam[0] = test_load_smallest_stiffness(M, lift, P0);
    lam[1] = test_load_smallest_stiffness(M, lift, P);
    /* The plain least-squeeze pick (HOLD alone) is the saddle; the planner's least squeeze
     * is a stable hold at the margin's order, the stiffness tie-breaker's a firmer one. */
    double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], t0[HP_MAX_BLADDERS] = {0}, Pp[HP_MAX_BLADDERS],
                                                     Fp[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_pressure_bounds(ls, lo, hi), HP_OK);
    assert_int_equal(
        hpi_load_hold(hp_planner_load_model(ls), lift, lo, hi, t0, NULL, 200, Pp, Fp, NULL),
        HP_LOAD_SOLVE_OK);
    double lam_pick = test_load_smallest_stiffness(M, lift, Pp);
    print_message("smallest stiffness eigenvalue: least-squeeze pick %.4g, least squeeze "
                  "among the stable holds %.4g, stiffness %.4g N/mm\n",
                  lam_pick, lam[0], lam[1]);
    assert_true(lam_pick < 0);
    assert_true(lam[0] >= HP_LOAD_STABLE_MARGIN && lam[1] > lam[0]);
    hp_planner_destroy(ls);
    hp_planner_destroy(st);
}

/* The stiffness objective's exact gradient and Hessian (load_stiffness.c) against central
 * differences (step 1e-4 kPa: truncation ~1e-8 of the scale, rounding ~1e-12), and its
 * value against the soft minimum of the eigenvalues of K assembled independently by
 * hp_load_eval (to 1e-9 N/mm). At the 10 mm lift with pressures inside every bound, under
 * each contact law: the fitted law is not linear in P, so K(P) is not affine in P there. */
static void stiffness_derivatives(hp_claw_law law)
{
    hp_layout L;
    hp_load_spec s;
    hp_settings set;
    supine(&L, &s, &set);
    hp_load_model *M = NULL;
    assert_int_equal(hp_load_model_create(&L, &s, HP_LEVEL_SURFACE, &M, NULL), HP_OK);
    M->law = law;
    const double xi[6] = {0.2e-3, -0.1e-3, 10e-3, 0.3 * 0.0174532925199, 0, 0};
    double target[HP_MAX_BLADDERS] = {0};
    hp_load_stiff S;
    assert_int_equal(hpi_load_stiff_init(&S, M, xi, target), HP_OK);
    /* Every bladder pressed (above its touching pressure) at a spread of pressures. */
    int idx[HP_MAX_BLADDERS], nv = L.n;
    double x[HP_MAX_BLADDERS], P[HP_MAX_BLADDERS];
    for (int k = 0; k < nv; ++k) {
        idx[k] = k;
        x[k] = 7.0 + 0.25 * k; /* kPa */
        P[k] = x[k] * 1e3;
    }
    double f, g[HP_MAX_BLADDERS], H[HP_MAX_BLADDERS * HP_MAX_BLADDERS], lmin;
    assert_int_equal(hpi_load_stiff_eval(&S, nv, idx, x, &f, g, H, &lmin), 0);
    double force[HP_MAX_BLADDERS], Q[6], dQ[36], K[36], ev[6], V[36];
    assert_int_equal(hp_load_eval(M, xi, P, Q, dQ, NULL, force, NULL), HP_OK);
    for (int k = 0; k < nv; ++k) assert_true(force[k] > 0);
    /* The soft minimum needs every eigenvalue: the test's own decomposition of K. */
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            K[i * 6 + j] = -dQ[i * 6 + j] * hpi_load_unit(i) * hpi_load_unit(j) * 1e3;
    assert_int_equal(hpi_kin_symeig6(K, ev, V), 0);
    double z = 0.0, sq = 0.0;
    for (int i = 0; i < 6; ++i) z += exp(-S.beta * ev[i]);
    for (int k = 0; k < nv; ++k) sq += 0.5 * S.squeeze * x[k] * x[k];
    hp_assert_close(f, log(z) / S.beta + sq, 1e-9, 1e-9);
    hp_assert_close(lmin, test_load_smallest_stiffness(M, xi, P), 1e-9, 1e-9);
    const double h = 1e-4;
    double gs = 0.0, hs = 0.0, eg = 0.0, eh = 0.0;
    for (int j = 0; j < nv; ++j) gs = fmax(gs, fabs(g[j]));
    for (int j = 0; j < nv * nv; ++j) hs = fmax(hs, fabs(H[j]));
    for (int j = 0; j < nv; ++j) {
        double xp[HP_MAX_BLADDERS], xm[HP_MAX_BLADDERS], fp, fm, gp[HP_MAX_BLADDERS],
            gm[HP_MAX_BLADDERS];
        memcpy(xp, x, sizeof xp);
        memcpy(xm, x, sizeof xm);
        xp[j] += h;
        xm[j] -= h;
        assert_int_equal(hpi_load_stiff_eval(&S, nv, idx, xp, &fp, gp, NULL, NULL), 0);
        assert_int_equal(hpi_load_stiff_eval(&S, nv, idx, xm, &fm, gm, NULL, NULL), 0);
        hp_assert_close(g[j], (fp - fm) / (2 * h), 0.0, 1e-6 * gs);
        eg = fmax(eg, fabs(g[j] - (fp - fm) / (2 * h)));
        for (int l = 0; l < nv; ++l) {
            hp_assert_close(H[l * nv + j], (gp[l] - gm[l]) / (2 * h), 0.0, 1e-6 * hs);
            eh = fmax(eh, fabs(H[l * nv + j] - (gp[l] - gm[l]) / (2 * h)));
        }
    }
    print_message("stiffness objective (%s law): |grad| %.3g, gradient error %.2g; |hess| "
                  "%.3g, Hessian error %.2g\n",
                  law == HP_CLAW_LAW_FEM ? "fitted" : "cap", gs, eg, hs, eh);
    hp_load_model_destroy(M);
}

static void test_stiffness_derivatives(void **state)
{
    (void)state;
    stiffness_derivatives(HP_CLAW_LAW_CAP);
    stiffness_derivatives(HP_CLAW_LAW_FEM);
}

/* The fitted law's domain on the plan path: a load plan whose answer presses a bladder
 * outside the tables the law was fitted to is refused by name (SOLVER_ERROR, the bladder
 * and the group in hp_planner_error, the safe output inside the bounds), and one inside is
 * returned. The supine layout under the fitted law (set on the planner's own model after
 * create: the load level's law is the cap law today) with a light load (0.3 kg: base
 * pressures about 4.0 kPa, inside the tables) and a heavier one (1.2 kg: about 6.4 kPa,
 * where the inflated shell's wall/ro falls below the tables' 0.080, the first group it
 * leaves; without the check that plan was REACHED). */
static void law_domain_plan(double mass, hp_status want, const char *group)
{
    hp_layout L;
    hp_load_spec s;
    hp_settings set;
    supine(&L, &s, &set);
    s.mass = mass;
    hp_planner *p = make(&L, &s);
    /* the planner's own model, written through: no public call picks the law */
    const hp_load_model *cm = hp_planner_load_model(p);
    hp_load_model *m;
    memcpy(&m, &cm, sizeof m);
    m->law = HP_CLAW_LAW_FEM;
    double d[6] = {0};
    hp_result r;
    hp_load_info info;
    assert_int_equal(load_plan(p, d, &r, &info), HP_OK);
    print_message("fitted law, %.2f kg: status %d, base %.0f Pa: %s\n", mass, (int)r.status,
                  r.bladders[0].pressure, hp_planner_error(p));
    assert_int_equal(r.status, want);
    assert_in_bounds(p, &r);
    if (group) {
        assert_non_null(strstr(hp_planner_error(p), "outside the fitted law's domain"));
        assert_non_null(strstr(hp_planner_error(p), group));
        int named = 0;
        for (int k = 0; k < L.n; ++k)
            named |= strstr(hp_planner_error(p), L.bladders[k].name) != NULL;
        assert_true(named);
    } else {
        assert_string_equal(hp_planner_error(p), "");
    }
    hp_planner_destroy(p);
}

static void test_law_domain(void **state)
{
    (void)state;
    law_domain_plan(0.3, HP_STATUS_REACHED, NULL);
    law_domain_plan(1.2, HP_STATUS_SOLVER_ERROR, "wall");
}

/* set_previous and the rate limits at the load level: a previous pressure outside the
 * bounds is refused (nothing changes); with every bladder's rate_max at 0.5 kPa and the
 * previous pressures those of the nominal hold, a 10 mm lift (which needs the base about
 * 1.6 kPa higher: 7.80 against 6.19 kPa) is CLOSEST, every pressure within 0.5 kPa of the
 * previous one (to 1e-9 relative) and at least one flagged rate_up, still an equilibrium
 * (1e-9 N); with rate limits off in the settings the same plan is REACHED. */
static void test_rate_limits(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    hp_settings set;
    supine(&L, &s, &set);
    for (int k = 0; k < L.n; ++k) L.bladders[k].rate_max = 500.0;
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    hp_planner *free_ = make(&L, &s), *lim = make(&L, &s);
    hp_result r0, r1, r2;
    hp_load_info info;
    const double zero[6] = {0}, lift[6] = {0, 0, 10e-3, 0, 0, 0};
    assert_int_equal(load_plan(free_, zero, &r0, NULL), HP_OK);
    assert_int_equal(r0.status, HP_STATUS_REACHED);
    double prev[HP_MAX_BLADDERS], bad[HP_MAX_BLADDERS];
    for (int k = 0; k < r0.n; ++k) prev[k] = bad[k] = r0.bladders[k].pressure;
    bad[2] = NAN;
    assert_int_equal(hp_planner_set_previous(lim, bad), HP_ERR_INVALID);
    assert_non_null(strstr(hp_planner_error(lim), "previous pressure"));
    bad[2] = 1e9;
    assert_int_equal(hp_planner_set_previous(lim, bad), HP_ERR_INVALID);
    assert_int_equal(hp_planner_set_previous(lim, prev), HP_OK);
    assert_int_equal(load_plan(lim, lift, &r1, &info), HP_OK);
    assert_int_equal(r1.status, HP_STATUS_CLOSEST);
    assert_in_bounds(lim, &r1);
    int up = 0;
    for (int k = 0; k < r1.n; ++k) {
        /* Exactly inside the rate window as the planner computes it (prev ± rate_max in
         * double): no relative slack. */
        assert_true(r1.bladders[k].pressure <= prev[k] + 500.0);
        assert_true(r1.bladders[k].pressure >= prev[k] - 500.0);
        up += (r1.bladders[k].binding & HP_BIND_RATE_UP) != 0;
    }
    assert_true(up >= 1);
    assert_true(r1.achieved[2] > 0 && r1.achieved[2] < lift[2]);
    assert_true(info.residual_force < 1e-9 && info.residual_moment < 1e-10);
    /* Without rate limits in the settings: reached. */
    set.use_rate_limits = 0;
    hp_planner *off = NULL;
    assert_int_equal(load_create(&L, &s, &set, HP_TIE_LEAST_SQUEEZE, &off, NULL), HP_OK);
    assert_int_equal(hp_planner_set_previous(off, prev), HP_OK);
    assert_int_equal(load_plan(off, lift, &r2, NULL), HP_OK);
    assert_int_equal(r2.status, HP_STATUS_REACHED);
    hp_planner_destroy(free_);
    hp_planner_destroy(lim);
    hp_planner_destroy(off);
}

/* NaN input: INVALID_INPUT with the safe output (pressures inside bounds, finite). */
static void test_invalid_input(void **state)
{
    (void)state;
    hp_layout L;
    hp_load_spec s;
    loaded(&L, &s, 1.6);
    hp_planner *p = make(&L, &s);
    double d[6] = {NAN, 0, 0, 0, 0, 0};
    hp_result r;
    assert_int_equal(load_plan(p, d, &r, NULL), HP_OK);
    assert_int_equal(r.status, HP_STATUS_INVALID_INPUT);
    assert_in_bounds(p, &r);
    assert_true(isinf(r.pose_error));
    hp_planner_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reached_nominal),
        cmocka_unit_test(test_reached_lift),
        cmocka_unit_test(test_levels),
        cmocka_unit_test(test_backends_agree),
        cmocka_unit_test(test_unreachable),
        cmocka_unit_test(test_stress_binding),
        cmocka_unit_test(test_refused),
        cmocka_unit_test(test_invalid_input),
        cmocka_unit_test(test_tiebreak_previous),
        cmocka_unit_test(test_tiebreak_stiffness),
        cmocka_unit_test(test_stiffness_derivatives),
        cmocka_unit_test(test_law_domain),
        cmocka_unit_test(test_rate_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
