/* The dense Goldfarb–Idnani QP (planner/qp.c) on its own: random strictly convex QPs against
 * the KKT conditions checked independently and against an exhaustive enumeration of active
 * sets, degenerate vertices (many constraints through one point, duplicated rows),
 * infeasibility detection, and the refusal of non-finite input wherever it sits. */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "planner/qp.h"
#include "common/dense.h"

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
    q->pairs = 0; /* no declared twin pairs (q is not zero-initialised) */
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
        int n = 1 + (int)(test_rng_next(&seed) % 6),
            m = (int)(test_rng_next(&seed) % (HP_QP_MMAX + 1));
        random_qp(&q, &seed, n, m);
        assert_int_equal(hpi_qp_solve(&q, 200, 1e-12), HP_QP_OPTIMAL);
        /* 1e-9: the data are O(10), the factorisations well conditioned (G >= I). */
        check_kkt(&q, 1e-9);
    }
}

/* A caller's Cholesky factor of G (hpi_qp_solve_factored, as the realtime backend passes
 * the factor of its convexity test) gives the same answer as the solver's own
 * factorisation, bit for bit: it is the same computation, done once instead of twice. */
static void test_factored_same_bits(void **st)
{
    (void)st;
    uint64_t seed = 77;
    hp_qp q, r;
    for (int t = 0; t < 2000; ++t) {
        int n = 1 + (int)(test_rng_next(&seed) % 6),
            m = (int)(test_rng_next(&seed) % (HP_QP_MMAX + 1));
        random_qp(&q, &seed, n, m);
        double L[HP_QP_NMAX * HP_QP_NMAX];
        for (int i = 0; i < n * n; ++i) L[i] = NAN; /* entries above the diagonal: not read */
        assert_int_equal(hpi_cholesky(q.G, n, n, 0.1, L, n), 1);
        memcpy(&r, &q, sizeof r);
        assert_int_equal(hpi_qp_solve(&q, 200, 1e-12), HP_QP_OPTIMAL);
        assert_int_equal(hpi_qp_solve_factored(&r, L, 200, 1e-12), HP_QP_OPTIMAL);
        assert_memory_equal(q.x, r.x, sizeof q.x);
        assert_memory_equal(q.u, r.u, sizeof q.u);
        assert_memory_equal(q.active, r.active, sizeof q.active);
        assert_int_equal(q.iterations, r.iterations);
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
    assert_int_equal(hpi_qp_solve(&q, 200, 1e-12), HP_QP_OPTIMAL);
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
    q.C[0] = 1.0; /* x0 >= 1 */
    q.b[0] = 1.0;
    q.C[HP_QP_NMAX] = -1.0; /* −x0 >= 0, i.e. x0 <= 0 */
    q.b[1] = 0.0;
    assert_int_equal(hpi_qp_solve(&q, 100, 1e-12), HP_QP_INFEASIBLE);
    /* bad input: G not positive definite, NaN in b, zero budget */
    q.b[1] = -5.0;
    q.G[3] = -1.0;
    assert_int_equal(hpi_qp_solve(&q, 100, 1e-12), HP_QP_BAD_INPUT);
    q.G[3] = 1.0;
    q.b[0] = NAN;
    assert_int_equal(hpi_qp_solve(&q, 100, 1e-12), HP_QP_BAD_INPUT);
    q.b[0] = 1.0;
    assert_int_equal(hpi_qp_solve(&q, 0, 1e-12), HP_QP_BAD_INPUT);
    assert_int_equal(hpi_qp_solve(&q, 100, 1e-12), HP_QP_OPTIMAL);
    hp_assert_close(q.x[0], 1.0, 0, 1e-15);
}

/* Solves the k×k system M y = r (row-major, leading dimension k) by Gaussian elimination
 * with partial pivoting, in place; returns the smallest pivot's magnitude (0: singular). */
static double gauss_solve(double *M, double *r, int k)
{
    double minpiv = INFINITY;
    for (int c = 0; c < k; ++c) {
        int piv = c;
        for (int i = c + 1; i < k; ++i)
            if (fabs(M[i * k + c]) > fabs(M[piv * k + c])) piv = i;
        if (!(fabs(M[piv * k + c]) > 0)) return 0.0;
        minpiv = fmin(minpiv, fabs(M[piv * k + c]));
        for (int j = 0; j < k; ++j) {
            double t = M[c * k + j];
            M[c * k + j] = M[piv * k + j];
            M[piv * k + j] = t;
        }
        double t = r[c];
        r[c] = r[piv];
        r[piv] = t;
        for (int i = c + 1; i < k; ++i) {
            double f = M[i * k + c] / M[c * k + c];
            for (int j = c; j < k; ++j) M[i * k + j] -= f * M[c * k + j];
            r[i] -= f * r[c];
        }
    }
    for (int i = k - 1; i >= 0; --i) {
        double t = r[i];
        for (int j = i + 1; j < k; ++j) t -= M[i * k + j] * r[j];
        r[i] = t / M[i * k + i];
    }
    return minpiv;
}

/* The reference: every subset S of at most n rows, taken as equalities, gives the KKT system
 * [G −C_Sᵀ; C_S 0][x; u_S] = [−a; b_S]; the answer is the subset whose solution is primal
 * feasible with u_S >= 0 (unique for random data: strict complementarity holds with
 * probability 1). Shares no code with the solver. Returns 0 if no subset qualifies. */
static int enumerate_qp(const hp_qp *q, double *x, double *u, int *active)
{
    int n = q->n, m = q->m, found = 0;
    double best = 0;
    for (unsigned S = 0; S < (1u << m); ++S) {
        int idx[HP_QP_MMAX], k = 0;
        for (int j = 0; j < m; ++j)
            if (S & (1u << j)) idx[k++] = j;
        if (k > n) continue;
        int dim = n + k;
        double M[(HP_QP_NMAX + HP_QP_NMAX) * (HP_QP_NMAX + HP_QP_NMAX)] = {0}, r[12];
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) M[i * dim + j] = q->G[i * n + j];
            for (int c = 0; c < k; ++c) {
                M[i * dim + n + c] = -q->C[idx[c] * HP_QP_NMAX + i];
                M[(n + c) * dim + i] = q->C[idx[c] * HP_QP_NMAX + i];
            }
            r[i] = -q->a[i];
        }
        for (int c = 0; c < k; ++c) r[n + c] = q->b[idx[c]];
        double piv = gauss_solve(M, r, dim);
        if (!(piv > 1e-9)) continue; /* dependent rows: another subset has the answer */
        int ok = 1;
        for (int c = 0; c < k; ++c) ok &= r[n + c] >= -1e-10;
        for (int j = 0; j < m && ok; ++j) {
            double s = -q->b[j];
            for (int i = 0; i < n; ++i) s += q->C[j * HP_QP_NMAX + i] * r[i];
            ok = s >= -1e-10;
        }
        if (!ok || (found && piv <= best)) continue;
        found = 1;
        best = piv; /* of several (degenerate) candidates, the best conditioned */
        memcpy(x, r, (size_t)n * sizeof *x);
        for (int j = 0; j < m; ++j) {
            u[j] = 0.0;
            active[j] = 0;
        }
        for (int c = 0; c < k; ++c) {
            u[idx[c]] = r[n + c];
            active[idx[c]] = 1;
        }
    }
    return found;
}

/* Random small QPs in the realtime backend's shape — rows in pairs (c, −c) bounding c·x
 * from both sides, so the solver's shared-row path runs — mixed with unpaired rows, zero
 * rows, and n < 6 with NaN in the unused columns of C (the solver must never read them),
 * against the enumeration above: x, every u and the active set agree. Tolerance 1e-8: the
 * data are O(10), G >= I, and the reference's pivots exceed 1e-9 only for well-posed
 * subsets; rounding in both methods is ~1e-13 here. */
static void test_random_vs_enumeration(void **st)
{
    (void)st;
    uint64_t seed = 16;
    int checked = 0, with_pairs = 0;
    for (int t = 0; t < 1500; ++t) {
        hp_qp q;
        memset(&q, 0, sizeof q);
        int n = 1 + (int)(test_rng_next(&seed) % 4), m = (int)(test_rng_next(&seed) % 11);
        random_qp(&q, &seed, n, m);
        for (int c = 0; c < m; ++c)
            for (int i = n; i < HP_QP_NMAX; ++i) q.C[c * HP_QP_NMAX + i] = NAN;
        for (int i = n; i < HP_QP_NMAX; ++i) q.a[i] = NAN;
        int style = (int)(test_rng_next(&seed) % 3); /* 0 unpaired, 1 pairs, 2 pairs + a zero row */
        if (style > 0) {
            for (int c = 1; c < m; c += 2) {
                for (int i = 0; i < n; ++i)
                    q.C[c * HP_QP_NMAX + i] = -q.C[(c - 1) * HP_QP_NMAX + i];
                q.b[c] = -0.5 - 0.5 * fabs(lf_uniform(&seed)); /* width > 0: feasible */
            }
            with_pairs += m > 1;
        }
        if (style == 2 && m > 0) {
            for (int i = 0; i < n; ++i) q.C[(m - 1) * HP_QP_NMAX + i] = 0.0;
            q.b[m - 1] = -1.0; /* 0 >= −1: always satisfied */
        }
        double xr[HP_QP_NMAX], ur[HP_QP_MMAX];
        int ar[HP_QP_MMAX];
        assert_true(enumerate_qp(&q, xr, ur, ar));
        assert_int_equal(hpi_qp_solve(&q, 200, 1e-12), HP_QP_OPTIMAL);
        for (int i = 0; i < n; ++i) hp_assert_close(q.x[i], xr[i], 1e-8, 1e-8);
        for (int j = 0; j < m; ++j) {
            hp_assert_close(q.u[j], ur[j], 1e-8, 1e-8);
            assert_int_equal(q.active[j], ar[j]);
        }
        ++checked;
    }
    assert_int_equal(checked, 1500);
    assert_true(with_pairs > 500);
}

/* Non-finite input anywhere — either triangle or the diagonal of G, a, b, a row of C on its
 * own or one that negates the row before but for one entry — and a row whose squared norm
 * overflows are refused as HP_QP_BAD_INPUT; the same QP without the fault solves. */
/* Non-finite input refused wherever it sits, for n < HP_QP_NMAX (rows copied and padded)
 * and n = HP_QP_NMAX (rows read in place), with G factored by the QP and with the caller's
 * factor (then the QP checks G's upper triangle and the factor's diagonal itself). */
static void bad_input_at(int n, int factored)
{
    const double bad[] = {NAN, INFINITY, -INFINITY};
    uint64_t seed = 99;
    hp_qp base;
    memset(&base, 0, sizeof base);
    random_qp(&base, &seed, n, 6);
    for (int c = 1; c < 6; c += 2)
        for (int i = 0; i < n; ++i) base.C[c * HP_QP_NMAX + i] = -base.C[(c - 1) * HP_QP_NMAX + i];
    double Lg[36] = {0};
    assert_true(hpi_cholesky(base.G, n, n, 0.0, Lg, n));
    const double *L = factored ? Lg : NULL;
    hp_qp q = base;
    assert_int_equal(hpi_qp_solve_factored(&q, L, 100, 1e-12), HP_QP_OPTIMAL);
    for (int v = 0; v < 3; ++v) {
        /* with a factor given, G's lower triangle is the factor's business (qp.h) */
        double *where[] = {&q.G[0 * n + 3],
                           &q.G[2 * n + 3],
                           &q.a[1],
                           &q.b[4],
                           &q.C[0 * HP_QP_NMAX + 2],
                           &q.C[3 * HP_QP_NMAX + 1],
                           &q.C[4 * HP_QP_NMAX + n - 1],
                           &q.G[3 * n + 0],
                           &q.G[2 * n + 2]};
        size_t nw = sizeof where / sizeof *where - (factored ? 2 : 0);
        for (size_t w = 0; w < nw; ++w) {
            q = base;
            *where[w] = bad[v];
            if (!(hpi_qp_solve_factored(&q, L, 100, 1e-12) == HP_QP_BAD_INPUT)) {
                print_error("n %d factored %d: value %g at input %zu not refused\n", n, factored,
                            bad[v], w);
                fail();
            }
        }
        if (factored) { /* a non-finite diagonal entry of the given factor */
            double Lb[36];
            memcpy(Lb, Lg, sizeof Lb);
            Lb[2 * n + 2] = bad[v] == -INFINITY ? INFINITY : bad[v];
            q = base;
            assert_int_equal(hpi_qp_solve_factored(&q, Lb, 100, 1e-12), HP_QP_BAD_INPUT);
        }
    }
    q = base;
    q.C[2 * HP_QP_NMAX + 0] = 1e200; /* |row|² = 1e400 overflows */
    assert_int_equal(hpi_qp_solve_factored(&q, L, 100, 1e-12), HP_QP_BAD_INPUT);
}

static void test_bad_input_everywhere(void **st)
{
    (void)st;
    for (int n = 4; n <= HP_QP_NMAX; n += HP_QP_NMAX - 4)
        for (int f = 0; f < 2; ++f) bad_input_at(n, f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_kkt),
        cmocka_unit_test(test_factored_same_bits),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_infeasible),
        cmocka_unit_test(test_random_vs_enumeration),
        cmocka_unit_test(test_bad_input_everywhere),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
