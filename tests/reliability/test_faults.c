/* Fault injection: every way each backend can fail, provoked honestly where possible (tiny
 * budgets, failing or NaN evaluations) and through the test-only hooks of
 * planner/backend_testing.h where not (codes a healthy problem never produces). For each:
 * hp_plan returns HP_OK with the right status enum and the backend's raw code kept, a result
 * that passes every safety invariant (inside the limits, finite, the safe output on a
 * failure), an error text on the planner, nothing printed; and the next plan, with the fault
 * removed, works again. docs/safety.md has the table this test pins. */
#define _GNU_SOURCE
#include "rel_common.h"
#include "planner/backend_testing.h"

#include <IpReturnCodes.h>
#include <nlopt.h>
#include <sys/stat.h>
#include <unistd.h>

enum hook { H_NONE, H_IPOPT_FAULT, H_IPOPT_FORCE, H_NLOPT_FAULT, H_NLOPT_FORCE, H_RT_FAULT };

typedef struct fault_case {
    const char *name;
    hp_backend backend;
    hp_level level;
    enum hook hook;
    int value;       /* fault or forced code */
    int max_iter;    /* 0: default */
    double max_time; /* 0: default */
    hp_status want;
    int want_raw;
    int safe_output; /* 1: the result must be the safe output (pose_error +inf) */
    int conflict;    /* 1: 1 Pa rate limits around previous pressures no pose holds */
} fault_case;

/* A target well beyond reach on every level (20 mm up, 20 mm sideways, 10° yaw), so the
 * backend always runs. */
static const double far_target[6] = {0.02, 0.0, 0.02, 0.0, 0.0, 0.17453292519943295};

/* A raw code the test does not pin (none at present: a NaN objective now stops NLopt with
 * FORCED_STOP in every build, where SLSQP's own code used to differ between builds). */
#define ANY_RAW (-999999)
/* Any of NLopt's success codes (> 0): which stopping test fires first (FTOL or XTOL) at a
 * point the core then refuses depends on the last bits of the start. */
#define NLOPT_ANY_SUCCESS (-999998)

static const fault_case cases[] = {
    /* ---- Ipopt: honest ---- */
    {"ipopt NaN objective", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FAULT,
     HP_TEST_FAULT_NAN_OBJECTIVE, 0, 0, HP_STATUS_SOLVER_ERROR, Invalid_Number_Detected, 1, 0},
    {"ipopt constraints return false", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FAULT,
     HP_TEST_FAULT_FAIL_CONSTRAINTS, 0, 0, HP_STATUS_SOLVER_ERROR, Invalid_Number_Detected, 1, 0},
    {"ipopt intermediate asks to stop", HP_BACKEND_IPOPT, HP_LEVEL_PLANE, H_IPOPT_FAULT,
     HP_TEST_FAULT_STOP, 0, 0, HP_STATUS_SOLVER_ERROR, User_Requested_Stop, 1, 0},
    /* One Ipopt iteration leaves the radii far from any pose: no feasible iterate, so the
     * limit status holds the safe output. */
    {"ipopt max_iter 1", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_NONE, 0, 1, 0,
     HP_STATUS_ITERATION_LIMIT, Maximum_Iterations_Exceeded, 1, 0},
    /* Ipopt's budget is the plan's clock, read by the intermediate callback (a user stop);
     * Ipopt's own CPU-time stop is left at its never-reached default. */
    {"ipopt max_time 1e-9 s", HP_BACKEND_IPOPT, HP_LEVEL_LINEAR, H_NONE, 0, 0, 1e-9,
     HP_STATUS_TIME_LIMIT, User_Requested_Stop, 0, 0},
    /* ---- Ipopt: forced codes ---- */
    {"ipopt forced infeasible", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Infeasible_Problem_Detected, 0, 0, HP_STATUS_INFEASIBLE_START, Infeasible_Problem_Detected, 1,
     0},
    {"ipopt forced restoration failed", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Restoration_Failed, 0, 0, HP_STATUS_SOLVER_ERROR, Restoration_Failed, 1, 0},
    {"ipopt forced step computation", HP_BACKEND_IPOPT, HP_LEVEL_LINEAR, H_IPOPT_FORCE,
     Error_In_Step_Computation, 0, 0, HP_STATUS_SOLVER_ERROR, Error_In_Step_Computation, 1, 0},
    {"ipopt forced search direction tiny", HP_BACKEND_IPOPT, HP_LEVEL_PLANE, H_IPOPT_FORCE,
     Search_Direction_Becomes_Too_Small, 0, 0, HP_STATUS_SOLVER_ERROR,
     Search_Direction_Becomes_Too_Small, 1, 0},
    {"ipopt forced diverging", HP_BACKEND_IPOPT, HP_LEVEL_PLANE, H_IPOPT_FORCE, Diverging_Iterates,
     0, 0, HP_STATUS_SOLVER_ERROR, Diverging_Iterates, 1, 0},
    {"ipopt forced too few DOF", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Not_Enough_Degrees_Of_Freedom, 0, 0, HP_STATUS_SOLVER_ERROR, Not_Enough_Degrees_Of_Freedom, 1,
     0},
    {"ipopt forced invalid problem", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Invalid_Problem_Definition, 0, 0, HP_STATUS_SOLVER_ERROR, Invalid_Problem_Definition, 1, 0},
    {"ipopt forced invalid option", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Invalid_Option, 0, 0, HP_STATUS_SOLVER_ERROR, Invalid_Option, 1, 0},
    {"ipopt forced unrecoverable exception", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Unrecoverable_Exception, 0, 0, HP_STATUS_SOLVER_ERROR, Unrecoverable_Exception, 1, 0},
    {"ipopt forced non-Ipopt exception", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     NonIpopt_Exception_Thrown, 0, 0, HP_STATUS_SOLVER_ERROR, NonIpopt_Exception_Thrown, 1, 0},
    {"ipopt forced out of memory", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Insufficient_Memory, 0, 0, HP_STATUS_SOLVER_ERROR, Insufficient_Memory, 1, 0},
    {"ipopt forced internal error", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Internal_Error, 0, 0, HP_STATUS_SOLVER_ERROR, Internal_Error, 1, 0},
    {"ipopt forced max_iter", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Maximum_Iterations_Exceeded, 0, 0, HP_STATUS_ITERATION_LIMIT, Maximum_Iterations_Exceeded, 0,
     0},
    {"ipopt forced cpu time", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_IPOPT_FORCE,
     Maximum_CpuTime_Exceeded, 0, 0, HP_STATUS_TIME_LIMIT, Maximum_CpuTime_Exceeded, 0, 0},
    /* ---- NLopt SLSQP ---- */
    {"slsqp NaN objective", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_SURFACE, H_NLOPT_FAULT,
     HP_TEST_FAULT_NAN_OBJECTIVE, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_FORCED_STOP, 1, 0},
    {"slsqp constraints fail (forced stop)", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_SURFACE,
     H_NLOPT_FAULT, HP_TEST_FAULT_FAIL_CONSTRAINTS, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_FORCED_STOP,
     1, 0},
    {"slsqp max_iter 1 (maxeval)", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_PLANE, H_NONE, 0, 1, 0,
     HP_STATUS_ITERATION_LIMIT, NLOPT_MAXEVAL_REACHED, 0, 0},
    {"slsqp max_time 1e-9 s", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_LINEAR, H_NONE, 0, 0, 1e-9,
     HP_STATUS_TIME_LIMIT, NLOPT_MAXTIME_REACHED, 0, 0},
    {"slsqp forced failure", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_SURFACE, H_NLOPT_FORCE, NLOPT_FAILURE,
     0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_FAILURE, 1, 0},
    {"slsqp forced invalid args", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_SURFACE, H_NLOPT_FORCE,
     NLOPT_INVALID_ARGS, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_INVALID_ARGS, 1, 0},
    {"slsqp forced out of memory", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_SURFACE, H_NLOPT_FORCE,
     NLOPT_OUT_OF_MEMORY, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_OUT_OF_MEMORY, 1, 0},
    {"slsqp forced forced-stop", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_SURFACE, H_NLOPT_FORCE,
     NLOPT_FORCED_STOP, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_FORCED_STOP, 1, 0},
    /* Roundoff at the true optimum: the KKT check accepts the point (closest, raw −4); at a
     * point one evaluation old it does not (the iterate is held as an iteration limit is
     * not claimed: SOLVER_ERROR with the safe output). */
    {"slsqp forced roundoff at optimum", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_LINEAR, H_NLOPT_FORCE,
     NLOPT_ROUNDOFF_LIMITED, 0, 0, HP_STATUS_CLOSEST, NLOPT_ROUNDOFF_LIMITED, 0, 0},
    {"slsqp forced roundoff early", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_LINEAR, H_NLOPT_FORCE,
     NLOPT_ROUNDOFF_LIMITED, 1, 0, HP_STATUS_SOLVER_ERROR, NLOPT_ROUNDOFF_LIMITED, 1, 0},
    /* ---- NLopt COBYLA ---- */
    {"cobyla NaN objective", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_SURFACE, H_NLOPT_FAULT,
     HP_TEST_FAULT_NAN_OBJECTIVE, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_FORCED_STOP, 1, 0},
    {"cobyla constraints fail (forced stop)", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_SURFACE,
     H_NLOPT_FAULT, HP_TEST_FAULT_FAIL_CONSTRAINTS, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_FORCED_STOP,
     1, 0},
    {"cobyla max_iter 1 (maxeval)", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_PLANE, H_NONE, 0, 1, 0,
     HP_STATUS_ITERATION_LIMIT, NLOPT_MAXEVAL_REACHED, 0, 0},
    {"cobyla max_time 1e-9 s", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_LINEAR, H_NONE, 0, 0, 1e-9,
     HP_STATUS_TIME_LIMIT, NLOPT_MAXTIME_REACHED, 0, 0},
    {"cobyla forced failure", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_SURFACE, H_NLOPT_FORCE,
     NLOPT_FAILURE, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_FAILURE, 1, 0},
    {"cobyla forced invalid args", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_SURFACE, H_NLOPT_FORCE,
     NLOPT_INVALID_ARGS, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_INVALID_ARGS, 1, 0},
    {"cobyla forced out of memory", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_SURFACE, H_NLOPT_FORCE,
     NLOPT_OUT_OF_MEMORY, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_OUT_OF_MEMORY, 1, 0},
    {"cobyla forced roundoff early", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_LINEAR, H_NLOPT_FORCE,
     NLOPT_ROUNDOFF_LIMITED, 1, 0, HP_STATUS_SOLVER_ERROR, NLOPT_ROUNDOFF_LIMITED, 1, 0},
    {"cobyla forced forced-stop", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_SURFACE, H_NLOPT_FORCE,
     NLOPT_FORCED_STOP, 0, 0, HP_STATUS_SOLVER_ERROR, NLOPT_FORCED_STOP, 1, 0},
    /* ---- realtime ---- */
    {"realtime QP budget 1 (linear)", HP_BACKEND_REALTIME, HP_LEVEL_LINEAR, H_NONE, 0, 1, 0,
     HP_STATUS_ITERATION_LIMIT, 2 /* HP_QP_ITERATION_LIMIT */, 1, 0},
    {"realtime QP budget 1 (surface)", HP_BACKEND_REALTIME, HP_LEVEL_SURFACE, H_NONE, 0, 1, 0,
     HP_STATUS_ITERATION_LIMIT, 2 /* HP_QP_ITERATION_LIMIT */, 1, 0},
    {"realtime NaN contact (linear)", HP_BACKEND_REALTIME, HP_LEVEL_LINEAR, H_RT_FAULT,
     HP_TEST_FAULT_NAN_CONTACT, 0, 0, HP_STATUS_SOLVER_ERROR, 3 /* HP_QP_BAD_INPUT */, 1, 0},
    {"realtime NaN contact (surface)", HP_BACKEND_REALTIME, HP_LEVEL_SURFACE, H_RT_FAULT,
     HP_TEST_FAULT_NAN_CONTACT, 0, 0, HP_STATUS_SOLVER_ERROR, 3 /* HP_QP_BAD_INPUT */, 1, 0},
    {"realtime NaN contact after first QP (surface)", HP_BACKEND_REALTIME, HP_LEVEL_SURFACE,
     H_RT_FAULT, HP_TEST_FAULT_NAN_CONTACT_LATE, 0, 0, HP_STATUS_SOLVER_ERROR, 0, 1, 0},
    {"realtime SQP budget 3 (surface)", HP_BACKEND_REALTIME, HP_LEVEL_SURFACE, H_NONE, 0, 3, 0,
     HP_STATUS_ITERATION_LIMIT, 0, 0, 0},
    {"realtime max_time 1e-9 s (surface)", HP_BACKEND_REALTIME, HP_LEVEL_SURFACE, H_NONE, 0, 0,
     1e-9, HP_STATUS_TIME_LIMIT, 0, 0, 0},
    /* ---- conflicting rate limits: each bladder's window is non-empty, no pose meets all ---- */
    {"realtime conflicting rate limits", HP_BACKEND_REALTIME, HP_LEVEL_SURFACE, H_NONE, 0, 0, 0,
     HP_STATUS_INFEASIBLE_START, 1 /* HP_QP_INFEASIBLE */, 1, 1},
    {"ipopt conflicting rate limits", HP_BACKEND_IPOPT, HP_LEVEL_SURFACE, H_NONE, 0, 0, 0,
     HP_STATUS_INFEASIBLE_START, Infeasible_Problem_Detected, 1, 1},
    /* SLSQP reports success (XTOL or FTOL reached) at a point that breaks the contacts: the
     * core refuses it. */
    {"slsqp conflicting rate limits", HP_BACKEND_NLOPT_SLSQP, HP_LEVEL_SURFACE, H_NONE, 0, 0, 0,
     HP_STATUS_SOLVER_ERROR, NLOPT_ANY_SUCCESS, 1, 1},
    {"cobyla conflicting rate limits", HP_BACKEND_NLOPT_COBYLA, HP_LEVEL_SURFACE, H_NONE, 0, 0, 0,
     HP_STATUS_SOLVER_ERROR, NLOPT_XTOL_REACHED, 1, 1},
};

static void set_hook(enum hook h, int v)
{
    switch (h) {
    case H_IPOPT_FAULT: hpi_test_ipopt_fault(v); break;
    case H_IPOPT_FORCE: hpi_test_ipopt_force_status(v); break;
    case H_NLOPT_FAULT: hpi_test_nlopt_fault(v); break;
    case H_NLOPT_FORCE: hpi_test_nlopt_force_result(v); break;
    case H_RT_FAULT: hpi_test_realtime_fault(v); break;
    default: break;
    }
}

static void clear_hooks(void)
{
    hpi_test_ipopt_fault(HP_TEST_FAULT_NONE);
    hpi_test_ipopt_force_status(HP_TEST_NO_FORCE);
    hpi_test_nlopt_fault(HP_TEST_FAULT_NONE);
    hpi_test_nlopt_force_result(HP_TEST_NO_FORCE);
    hpi_test_realtime_fault(HP_TEST_FAULT_NONE);
}

static int mismatches;

static void run_case(const fault_case *fc)
{
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_settings s;
    hp_settings_default(&s);
    s.backend = fc->backend;
    s.level = fc->level;
    if (fc->max_iter) s.max_iter = fc->max_iter;
    s.max_time = fc->max_time > 0 ? fc->max_time : 60.0; /* speed-independent outcome */
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    assert_int_equal(hp_planner_create(&L, &s, &p, &d), HP_OK);
    rel_ctx c;
    rel_ctx_init(&c, p);
    /* A first, healthy plan so the safe output is a real previous answer, not the nominal. */
    const double near[6] = {0.5e-3, 0.2e-3, -0.3e-3, 0.003, 0.002, -0.001};
    hp_result r;
    hp_error e = hp_plan(p, near, &r);
    REL_ASSERT(&c, e, near, &r, REL_INV_ALL, fc->name);
    assert_int_equal(r.status, HP_STATUS_REACHED);
    hp_result before = r;
    if (fc->conflict) {
        /* The pressures of two far answers in opposite directions, alternating by bladder:
         * each is valid, together no pose holds them; with a 1 Pa rate limit the next plan's
         * windows cannot all hold. */
        hp_planner_destroy(p);
        for (int k = 0; k < L.n; ++k) L.bladders[k].rate_max = 1.0;
        assert_int_equal(hp_planner_create(&L, &s, &p, &d), HP_OK);
        rel_ctx_init(&c, p);
        hp_planner *q = rel_planner(&L, HP_BACKEND_REALTIME, fc->level, INFINITY, 0);
        const double up[6] = {0, 0, 0.03, 0, 0, 0}, down[6] = {0, 0, -0.03, 0, 0, 0};
        hp_result ru, rd;
        assert_int_equal(hp_plan(q, up, &ru), HP_OK);
        assert_int_equal(hp_plan(q, down, &rd), HP_OK);
        hp_planner_destroy(q);
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < L.n; ++k) P[k] = (k % 2 ? ru : rd).bladders[k].pressure;
        assert_int_equal(hp_planner_set_previous(p, P), HP_OK);
        rel_ctx_capture_safe(&c, p);
        before = c.safe;
    }

    char path[] = "/tmp/hp_rel_faultXXXXXX";
    int sink = mkstemp(path);
    assert_true(sink >= 0);
    unlink(path);
    fflush(stdout);
    fflush(stderr);
    int o1 = dup(1), o2 = dup(2);
    dup2(sink, 1);
    dup2(sink, 2);
    set_hook(fc->hook, fc->value);
    e = hp_plan(p, far_target, &r);
    clear_hooks();
    fflush(stdout);
    fflush(stderr);
    dup2(o1, 1);
    dup2(o2, 2);
    close(o1);
    close(o2);
    struct stat sb;
    fstat(sink, &sb);
    close(sink);

    print_message("%-46s -> %-16s raw %5d  '%s'\n", fc->name, hp_status_name(r.status), r.raw_code,
                  hp_planner_error(p)[0] ? hp_planner_error(p) : hp_planner_note(p));
    assert_int_equal(sb.st_size, 0);
    REL_ASSERT(&c, e, far_target, &r, REL_INV_ALL, fc->name);
    int raw_ok = fc->want_raw == ANY_RAW ||
                 (fc->want_raw == NLOPT_ANY_SUCCESS ? r.raw_code > 0 : r.raw_code == fc->want_raw);
    if (r.status != fc->want || !raw_ok) {
        print_error("%s: got %s raw %d, want %s raw %d\n", fc->name, hp_status_name(r.status),
                    r.raw_code, hp_status_name(fc->want), fc->want_raw);
        ++mismatches;
    }
    assert_true(strlen(hp_planner_error(p)) + strlen(hp_planner_note(p)) > 0);
    if (fc->safe_output != isinf(r.pose_error)) {
        print_error("%s: safe output %d expected, pose_error %g\n", fc->name, fc->safe_output,
                    r.pose_error);
        ++mismatches;
    } else if (fc->safe_output) {
        assert_true(isinf(r.pose_error));
        for (int k = 0; k < L.n; ++k)
            assert_memory_equal(&r.bladders[k].pressure, &before.bladders[k].pressure,
                                sizeof(double));
    } else {
        assert_true(isfinite(r.pose_error));
    }
    /* Recovery: with the fault gone a fresh planner answers the same far target. */
    hp_planner_destroy(p);
    for (int k = 0; k < L.n; ++k) L.bladders[k].rate_max = INFINITY;
    s.max_iter = HP_DEFAULT_MAX_ITER;
    s.max_time = 60.0; /* the recovery must not depend on the machine's speed */
    assert_int_equal(hp_planner_create(&L, &s, &p, &d), HP_OK);
    rel_ctx_init(&c, p);
    e = hp_plan(p, far_target, &r);
    REL_ASSERT(&c, e, far_target, &r, REL_INV_ALL, "recovery");
    assert_true(r.status == HP_STATUS_CLOSEST || r.status == HP_STATUS_ITERATION_LIMIT);
    hp_planner_destroy(p);
}

static void faults_every_backend(void **st)
{
    (void)st;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) run_case(&cases[i]);
    assert_int_equal(mismatches, 0);
}

/* The hooks are inert by default: with none set, the fault table's far target gives the
 * same answer as a planner that never saw a hook (bit for bit, realtime). */
static void hooks_inert_by_default(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(lf_layout(&L), HP_OK);
    hp_planner *a = rel_planner(&L, HP_BACKEND_REALTIME, HP_LEVEL_SURFACE, INFINITY, 0);
    hp_result r1, r2;
    assert_int_equal(hp_plan(a, far_target, &r1), HP_OK);
    hpi_test_realtime_fault(HP_TEST_FAULT_NAN_CONTACT);
    hpi_test_realtime_fault(HP_TEST_FAULT_NONE);
    hp_planner_reset(a);
    assert_int_equal(hp_plan(a, far_target, &r2), HP_OK);
    assert_int_equal(r1.status, HP_STATUS_CLOSEST);
    for (int k = 0; k < L.n; ++k)
        assert_memory_equal(&r1.bladders[k].pressure, &r2.bladders[k].pressure, sizeof(double));
    hp_planner_destroy(a);
}

/* Regression: a sphere head's rotations are not commanded; the general backends once left
 * them free, met the contacts with them, and the core (holding them at 0) got radii no pose
 * holds -> solver-error for ~95 % of far targets at the plane level. Now they are fixed at
 * 0: Ipopt answers every one; SLSQP/COBYLA at least half (measured 24 of 40 for SLSQP; their first-order check may still refuse a
 * degenerate vertex, labelled solver-error). */
static void uncommanded_components_held_fixed(void **st)
{
    (void)st;
    hp_layout L;
    assert_int_equal(rel_layout(&L, REL_SPHERE), HP_OK);
    for (int bi = 1; bi < 4; ++bi) {
        hp_planner *p = rel_planner(&L, rel_backends[bi], HP_LEVEL_PLANE, INFINITY, 0);
        rel_ctx c;
        rel_ctx_init(&c, p);
        uint64_t seed = 5;
        int closest = 0, n = 40;
        for (int t = 0; t < n; ++t) {
            double cm[6], xi[6];
            hp_result r;
            for (int i = 0; i < 6; ++i) cm[i] = 40.0 * lf_uniform(&seed);
            lf_pose(cm, xi);
            hp_error e = hp_plan(p, xi, &r);
            REL_ASSERT(&c, e, xi, &r, REL_INV_ALL, hp_backend_name(rel_backends[bi]));
            closest += r.status == HP_STATUS_CLOSEST;
            for (int i = 3; i < 6; ++i) assert_true(r.achieved[i] == 0.0);
        }
        print_message("sphere/plane %s: %d of %d closest\n", hp_backend_name(rel_backends[bi]),
                      closest, n);
        assert_true(rel_backends[bi] == HP_BACKEND_IPOPT ? closest == n : closest >= n / 2);
        hp_planner_destroy(p);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(uncommanded_components_held_fixed),
        cmocka_unit_test(hooks_inert_by_default),
        cmocka_unit_test(faults_every_backend),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
