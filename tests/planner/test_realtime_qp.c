/* The dense Goldfarb–Idnani QP (planner/qp.c) on its own: random strictly convex QPs against
 * the KKT conditions checked independently, degenerate vertices (many constraints through
 * one point, duplicated rows), and infeasibility detection. */
#include "test_util.h"
#include "tests/planner/layout_fixture.h"
#include "planner/qp.h"

/* KKT of min ½xᵀGx + aᵀx s.t. Cx >= b at the returned x and u:
 * stationarity Gx + a − Cᵀu = 0, primal feasibility, u >= 0, complementarity u·s = 0. */
static void check_kkt(const hp_qp *q, double tol)
{
    int n = q->n;
    for (int i = 0; i < n; ++i) {
        double g = q->a[i];
        for (int j = 0; j < n; ++j) g += q->G[i * n + j] * q->x[j];
        for (int c = 0; c < q->m; ++c) g -= q->C[c * HP_QP_NMAX + i] * q->u[c];
        hp_assert_close(g, 0.0, 0, tol);
    }
    for (int c = 0; c < q->m; ++c) {
        double s = -q->b[c];
        for (int i = 0; i < n; ++i) s += q->C[c * HP_QP_NMAX + i] * q->x[i];
        assert_true(s >= -tol);
        assert_true(q->u[c] >= -tol);
        hp_assert_close(q->u[c] * s, 0.0, 0, tol);
    }
}

static void random_qp(hp_qp *q, uint64_t *seed, int n, int m)
{
    q->n = n;
    q->m = m;
    double A[36];
    for (int i = 0; i < n * n; ++i) A[i] = lf_uniform(seed);
    for (int i = 0; i < n; ++i) /* G = AᵀA + I: symmetric positive definite */
        for (int j = 0; j < n; ++j) {
            double s = i == j ? 1.0 : 0.0;
            for (int k = 0; k < n; ++k) s += A[k * n + i] * A[k * n + j];
            q->G[i * n + j] = s;
        }
    for (int i = 0; i < n; ++i) q->a[i] = 10.0 * lf_uniform(seed);
    for (int c = 0; c < m; ++c) {
        for (int i = 0; i < n; ++i) q->C[c * HP_QP_NMAX + i] = lf_uniform(seed);
        q->b[c] = -1.0 + 0.5 * lf_uniform(seed); /* x = 0 is strictly feasible */
    }
}

static void test_random_kkt(void **st)
{
    (void)st;
    uint64_t seed = 2024;
    hp_qp q;
    for (int t = 0; t < 2000; ++t) {
        int n = 1 + (int)(lf_next(&seed) % 6), m = (int)(lf_next(&seed) % (HP_QP_MMAX + 1));
        random_qp(&q, &seed, n, m);
        assert_int_equal(hp_qp_solve(&q, 200, 1e-12), HP_QP_OPTIMAL);
        /* 1e-9: the data are O(10), the factorisations well conditioned (G >= I). */
        check_kkt(&q, 1e-9);
    }
}

/* Twelve constraints through one vertex in 3-D (and one duplicated row): a degenerate
 * optimum the dual method must settle without cycling. */
static void test_degenerate(void **st)
{
    (void)st;
    hp_qp q;
    memset(&q, 0, sizeof q);
    q.n = 3;
    q.m = 13;
    for (int i = 0; i < 3; ++i) {
        q.G[i * 3 + i] = 1.0;
        q.a[i] = -5.0; /* unconstrained minimum (5, 5, 5) */
    }
    uint64_t seed = 7;
    for (int c = 0; c < 12; ++c) { /* rows with positive entries through (1, 1, 1): x <= 1-ish */
        double r[3], dot = 0;
        for (int i = 0; i < 3; ++i) {
            r[i] = 0.2 + fabs(lf_uniform(&seed));
            dot += r[i];
        }
        for (int i = 0; i < 3; ++i) q.C[c * HP_QP_NMAX + i] = -r[i];
        q.b[c] = -dot;
    }
    memcpy(&q.C[12 * HP_QP_NMAX], &q.C[0], 3 * sizeof(double));
    q.b[12] = q.b[0];
    assert_int_equal(hp_qp_solve(&q, 200, 1e-12), HP_QP_OPTIMAL);
    check_kkt(&q, 1e-9);
    /* KKT above is the proof of optimality; as a second check, the shared vertex
     * (1, 1, 1) is feasible, so it cannot have a lower objective than the answer. */
    double fx = 0, fv = 0;
    for (int i = 0; i < 3; ++i) {
        fx += 0.5 * q.x[i] * q.x[i] - 5.0 * q.x[i];
        fv += 0.5 - 5.0;
    }
    assert_true(fx <= fv + 1e-12);
}

static void test_infeasible(void **st)
{
    (void)st;
    hp_qp q;
    memset(&q, 0, sizeof q);
    q.n = 2;
    q.m = 2;
    q.G[0] = q.G[3] = 1.0;
    q.C[0] = 1.0;             /* x0 >= 1 */
    q.b[0] = 1.0;
    q.C[HP_QP_NMAX] = -1.0;   /* −x0 >= 0, i.e. x0 <= 0 */
    q.b[1] = 0.0;
    assert_int_equal(hp_qp_solve(&q, 100, 1e-12), HP_QP_INFEASIBLE);
    /* bad input: G not positive definite, NaN in b, zero budget */
    q.b[1] = -5.0;
    q.G[3] = -1.0;
    assert_int_equal(hp_qp_solve(&q, 100, 1e-12), HP_QP_BAD_INPUT);
    q.G[3] = 1.0;
    q.b[0] = NAN;
    assert_int_equal(hp_qp_solve(&q, 100, 1e-12), HP_QP_BAD_INPUT);
    q.b[0] = 1.0;
    assert_int_equal(hp_qp_solve(&q, 0, 1e-12), HP_QP_BAD_INPUT);
    assert_int_equal(hp_qp_solve(&q, 100, 1e-12), HP_QP_OPTIMAL);
    hp_assert_close(q.x[0], 1.0, 0, 1e-15);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_kkt),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_infeasible),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
