/* The QP's warm start (hpi_qp_solve_warm, planner/qp.c) against the cold Goldfarb–Idnani
 * solve on thousands of seeded random QPs of the realtime backend's shape: guessed with the
 * true active set it gives the same answer to a tolerance derived from the conditioning;
 * guessed wrong (subsets, supersets, other sets, a twin pair) it falls back: refused on a
 * multiplier's sign or a violated row, the loop from the guessed rows it keeps gives the
 * cold answer to the same tolerance and, where that is unique, the same active set; refused
 * otherwise, the cold solve bit for bit; guessed empty, either the unconstrained minimum or
 * the cold solve. Plus its refusals one by one, and bad input and infeasibility still reported
 * as such whatever the guess. */
#include "support/test_util.h"
#include "support/layout_fixture.h"
#include "planner/qp.h"
#include "common/dense.h"

#include <float.h>

#define NM HP_QP_NMAX
#define EPS DBL_EPSILON

/* A random QP of the realtime backend's shape: n in 1..6, m <= 16 (or 32) rows, most in
 * twin pairs (c, −c) bounding c·x from both sides, the rest single; rows scaled by 10^±1
 * (the backend's rows differ in size); G = F Fᵀ from a random lower-triangular factor F
 * with diagonal in [e^−2, e], so G's condition number spans several decades; some rows
 * nearly parallel to another; x = 0 strictly feasible, or (one QP in four) a vertex where
 * many rows meet. The unused columns of C and entries of a hold NaN: the solver must never
 * read them. */
static void realtime_qp(hp_qp *q, uint64_t *seed)
{
    memset(q, 0, sizeof *q);
    int n = 1 + (int)(test_rng_next(seed) % NM);
    /* up to 8 pairs and 16 rows (the default layouts' 8 bladders); one QP in eight up to
     * the solver's 32 rows (16 bladders) */
    int mmax = test_rng_next(seed) % 8 == 0 ? HP_QP_MMAX : 16;
    int pairs = (int)(test_rng_next(seed) % (unsigned)(mmax / 2 + 1));
    int single = (int)(test_rng_next(seed) % (unsigned)(mmax - 2 * pairs + 1));
    if (single > 4) single = 4;
    q->n = n;
    q->m = 2 * pairs + single;
    double F[NM * NM] = {0};
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < i; ++j) F[i * NM + j] = lf_uniform(seed);
        F[i * NM + i] = exp(-0.5 + 1.5 * lf_uniform(seed));
    }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double s = 0;
            for (int k = 0; k < n; ++k) s += F[i * NM + k] * F[j * NM + k];
            q->G[i * n + j] = s;
        }
    for (int i = 0; i < NM; ++i) q->a[i] = i < n ? 5.0 * lf_uniform(seed) : NAN;
    for (int j = 0; j < q->m; ++j) {
        double *c = &q->C[j * NM], scale = pow(10.0, lf_uniform(seed));
        int twin = j < 2 * pairs && j % 2 == 1;
        for (int i = 0; i < NM; ++i)
            c[i] = i >= n ? NAN : twin ? -c[i - NM] : scale * lf_uniform(seed);
        /* one row in five nearly parallel to an earlier leading row, 1e-9..1e-2 off:
         * active together they make the Gram matrix ill-conditioned */
        int lead = j >= 2 * pairs ? j - 1 : j - 2;
        if (!twin && lead >= 0 && test_rng_next(seed) % 5 == 0) {
            double off = pow(10.0, -5.5 + 3.5 * lf_uniform(seed));
            for (int i = 0; i < n; ++i)
                c[i] = scale * (q->C[lead * NM + i] + off * lf_uniform(seed));
        }
        double norm = 0;
        for (int i = 0; i < n; ++i) norm += c[i] * c[i];
        q->b[j] = -(0.05 + 0.5 * (lf_uniform(seed) + 1.0)) * sqrt(norm);
    }
    if (test_rng_next(seed) % 4 == 0) {
        /* a vertex: every leading row through the point v (its twin's bound beyond), the
         * unconstrained minimum pulled 5 away: many rows active at once, often more than
         * n (degenerate), nearly parallel ones among them */
        double v[NM], p[NM];
        for (int i = 0; i < n; ++i) {
            v[i] = lf_uniform(seed);
            p[i] = v[i] + 5.0 * lf_uniform(seed);
        }
        for (int i = 0; i < n; ++i) {
            double g = 0;
            for (int k = 0; k < n; ++k) g += q->G[i * n + k] * p[k];
            q->a[i] = -g;
        }
        for (int j = 0; j < q->m; ++j) {
            if (j < 2 * pairs && j % 2 == 1) continue;
            double cv = 0;
            for (int i = 0; i < n; ++i) cv += q->C[j * NM + i] * v[i];
            if (j < 2 * pairs) q->b[j + 1] = -cv + q->b[j + 1]; /* c·x <= c·v + width */
            q->b[j] = cv;
        }
    }
}

/* An upper bound on the 2-norm condition number of the symmetric positive definite k×k A
 * (leading dimension k): trace(A)·‖L⁻¹‖_F² (common/dense.h); +inf if not definite. */
static double cond_bound(const double *A, int k)
{
    double L[NM * NM], tr = 0;
    if (k == 0) return 1.0;
    if (!hpi_cholesky(A, k, k, 0.0, L, k)) return INFINITY;
    for (int i = 0; i < k; ++i) tr += A[i * k + i];
    return tr * hpi_cholesky_inv_frob2(L, k, k);
}

/* The conditioning the tolerances derive from: κ(G) and κ(S) of the scaled matrix
 * S_ij = C_i G⁻¹ C_jᵀ / (D_i D_j), D_i² = C_i G⁻¹ C_iᵀ, over the rows in set (computed here
 * with G⁻¹ by hpi_cholesky_solve, not as the solver does). */
static void conditioning(const hp_qp *q, const int *set, double *kg, double *ks)
{
    int n = q->n, idx[NM], k = 0;
    for (int j = 0; j < q->m; ++j)
        if (set[j] && k < NM) idx[k++] = j;
    double L[NM * NM], Gc[NM][NM], S[NM * NM], D[NM];
    *kg = cond_bound(q->G, n);
    assert_int_equal(hpi_cholesky(q->G, n, n, 0.0, L, n), 1);
    for (int c = 0; c < k; ++c) {
        for (int i = 0; i < n; ++i) Gc[c][i] = q->C[idx[c] * NM + i];
        hpi_cholesky_solve(L, n, n, Gc[c]);
        double s = 0;
        for (int i = 0; i < n; ++i) s += q->C[idx[c] * NM + i] * Gc[c][i];
        D[c] = sqrt(s);
    }
    for (int c = 0; c < k; ++c)
        for (int e = 0; e < k; ++e) {
            double s = 0;
            for (int i = 0; i < n; ++i) s += q->C[idx[c] * NM + i] * Gc[e][i];
            S[c * k + e] = s / (D[c] * D[e]);
        }
    *ks = cond_bound(S, k);
}

/* 1 when the cold answer is clearly non-degenerate: every active multiplier and every
 * inactive row's slack (per unit-norm row) above 1e-6 relative to the data's size, far
 * above the rounding (<= 1e-9 here), so the active set is unique and stable to rounding. */
static int non_degenerate(const hp_qp *q)
{
    double umax = 0;
    for (int j = 0; j < q->m; ++j) umax = fmax(umax, q->u[j]);
    for (int j = 0; j < q->m; ++j) {
        double cx = 0, nn = 0;
        for (int i = 0; i < q->n; ++i) {
            cx += q->C[j * NM + i] * q->x[i];
            nn += q->C[j * NM + i] * q->C[j * NM + i];
        }
        if (q->active[j] && !(q->u[j] > 1e-6 * (1.0 + umax))) return 0;
        if (!q->active[j] && !((cx - q->b[j]) / sqrt(nn) > 1e-6)) return 0;
    }
    return 1;
}

static void assert_same_bits(const hp_qp *w, const hp_qp *c)
{
    assert_memory_equal(w->x, c->x, sizeof w->x);
    assert_memory_equal(w->u, c->u, sizeof w->u);
    assert_memory_equal(w->active, c->active, sizeof w->active);
    assert_int_equal(w->iterations, c->iterations);
}

static double inf_norm(const double *v, int n)
{
    double s = 0;
    for (int i = 0; i < n; ++i) s = fmax(s, fabs(v[i]));
    return s;
}

static double worst_x = 0, worst_u = 0; /* the largest error / tolerance ratios seen */

/* The warm answer w (from the rows w->active) against the cold one c. Tolerances: both
 * solves are backward stable in the data (triangular solves, Cholesky, Givens rotations),
 * so each x carries a forward error of about (n + k)·ε·κ(G)·X, X = max(|x|, |G⁻¹a|) the
 * size of the terms x is summed from; the active rows enter through their factor, whose
 * condition is √κ(S) (the cold solve's R; the warm path squares it in S, but its x sees
 * only √κ(S): the argument above warm_try in qp.c), S the larger of the two sets'. Hence
 * |Δx| <= 64·ε·κ(G)·√κ(S)·X (64 >= 4·(n + k): room for the bounds' constants). The
 * multipliers solve the normal equations in S, so carry κ(S) itself:
 * |Δu| <= 64·ε·κ(G)·κ(S)·U, U the largest multiplier plus |a| (the size of the right-hand
 * side they are solved from); compared only when both sets are the same (elsewhere, at a
 * degenerate vertex, the multipliers are not unique). */
static void compare(const hp_qp *w, const hp_qp *c)
{
    double kg, ks, kw;
    conditioning(c, c->active, &kg, &ks);
    conditioning(c, w->active, &kg, &kw);
    ks = fmax(ks, kw);
    double xu[NM];
    double L[NM * NM];
    for (int i = 0; i < c->n; ++i) xu[i] = -c->a[i];
    assert_int_equal(hpi_cholesky(c->G, c->n, c->n, 0.0, L, c->n), 1);
    hpi_cholesky_solve(L, c->n, c->n, xu);
    double X = fmax(inf_norm(c->x, c->n), inf_norm(xu, c->n));
    double U = inf_norm(c->u, c->m) + inf_norm(c->a, c->n);
    double tx = 64 * EPS * kg * sqrt(ks) * X, tu = 64 * EPS * kg * ks * U;
    for (int i = 0; i < c->n; ++i) {
        hp_assert_close(w->x[i], c->x[i], 0, tx);
        worst_x = fmax(worst_x, fabs(w->x[i] - c->x[i]) / tx);
    }
    if (memcmp(w->active, c->active, sizeof w->active) != 0) return;
    for (int j = 0; j < c->m; ++j) {
        hp_assert_close(w->u[j], c->u[j], 0, tu);
        worst_u = fmax(worst_u, fabs(w->u[j] - c->u[j]) / tu);
    }
}

static void test_warm_vs_cold(void **st)
{
    (void)st;
    uint64_t seed = 1617;
    int cold_fail = 0, accepted = 0, nondeg = 0, refused_cond = 0, wrong = 0, empty_ok = 0;
    int pairs = 0, kept = 0, point_found = 0;
    for (int t = 0; t < 6000; ++t) {
        hp_qp cold, w;
        realtime_qp(&cold, &seed);
        int m = cold.m, n = cold.n;
        hp_qp base = cold;
        hp_qp_status cs = hpi_qp_solve(&cold, 200, 1e-12);
        if (cs != HP_QP_OPTIMAL) {
            /* a vertex whose feasible set is the point itself, emptied by the rounding of
             * b: the warm start, whatever the guess, must not find an answer either */
            ++cold_fail;
            for (int v = 0; v < 20; ++v) {
                int g[HP_QP_MMAX];
                for (int j = 0; j < m; ++j) g[j] = v == 0 ? 0 : test_rng_next(&seed) % 3 == 0;
                w = base;
                hp_qp_status ws = hpi_qp_solve_warm(&w, NULL, g, 200, 1e-12);
                assert_int_not_equal(w.warm, HP_QP_WARM_ACCEPTED);
                if (ws == HP_QP_OPTIMAL && w.iterations > w.gi_steps) {
                    /* started from the rows a sign refusal kept, the other rounding may
                     * find the point: then it must be one, every row within feas_tol */
                    for (int j = 0; j < m; ++j) {
                        double cx = 0, nn = 0;
                        for (int i = 0; i < n; ++i) {
                            cx += base.C[j * NM + i] * w.x[i];
                            nn += base.C[j * NM + i] * base.C[j * NM + i];
                        }
                        if (nn > 0) assert_true((cx - base.b[j]) / sqrt(nn) >= -2e-12);
                    }
                    ++point_found;
                    continue;
                }
                assert_int_equal(ws, cs);
            }
            continue;
        }
        assert_int_equal(cold.warm, HP_QP_WARM_NONE);
        int nd = non_degenerate(&cold);
        nondeg += nd;

        /* (i) the true active set */
        w = base;
        assert_int_equal(hpi_qp_solve_warm(&w, NULL, cold.active, 200, 1e-12), HP_QP_OPTIMAL);
        if (w.warm == HP_QP_WARM_ACCEPTED) {
            ++accepted;
            compare(&w, &cold);
            int k = 0;
            for (int j = 0; j < m; ++j) k += w.active[j];
            assert_int_equal(w.iterations, k); /* one add step per guessed row */
            if (nd) assert_memory_equal(w.active, cold.active, sizeof w.active);
        } else {
            /* only an ill-conditioned true set may be refused: check it is one */
            double kg, ks;
            conditioning(&cold, cold.active, &kg, &ks);
            if (!(w.warm == HP_QP_WARM_CONDITION && ks > 1e6) && nd) {
                print_error("QP %d: true set refused (%d), κ(S) %g\n", t, w.warm, ks);
                fail();
            }
            refused_cond += w.warm == HP_QP_WARM_CONDITION;
            if (w.iterations > w.gi_steps) /* a degenerate vertex: the loop from the rows kept */
                compare(&w, &cold);
            else assert_same_bits(&w, &cold);
        }

        /* (ii) wrong sets: the true set with one row flipped (a superset or a subset),
         * a random set, and a twin pair added */
        for (int v = 0; v < 3 && m > 0; ++v) {
            int g[HP_QP_MMAX];
            memcpy(g, cold.active, sizeof g);
            if (v == 0) {
                int j = (int)(test_rng_next(&seed) % (unsigned)m);
                g[j] = !g[j];
            } else if (v == 1) {
                for (int j = 0; j < m; ++j) g[j] = test_rng_next(&seed) % 3 == 0;
            } else {
                int j = (int)(test_rng_next(&seed) % (unsigned)m) | 1; /* odd: a twin if paired */
                int is_twin = j < m;
                for (int i = 0; i < n && is_twin; ++i)
                    is_twin = base.C[j * NM + i] == -base.C[(j - 1) * NM + i];
                if (!is_twin) continue;
                g[j] = g[j - 1] = 1;
                ++pairs;
            }
            if (memcmp(g, cold.active, (size_t)m * sizeof *g) == 0) continue;
            w = base;
            assert_int_equal(hpi_qp_solve_warm(&w, NULL, g, 200, 1e-12), HP_QP_OPTIMAL);
            if (v == 2) assert_int_equal(w.warm, HP_QP_WARM_SHAPE);
            if (w.warm == HP_QP_WARM_ACCEPTED) {
                /* a wrong set may pass only where the answer is degenerate (a row active
                 * with a zero multiplier, or inactive on its bound): then x is the same */
                assert_false(nd);
                compare(&w, &cold);
            } else if (w.iterations > w.gi_steps) {
                /* refused on a multiplier's sign or another row's violation, the loop
                 * started from the rows kept */
                assert_true(w.warm == HP_QP_WARM_SIGN || w.warm == HP_QP_WARM_VIOLATED);
                compare(&w, &cold);
                if (nd) assert_memory_equal(w.active, cold.active, sizeof w.active);
                kept += nd;
            } else {
                assert_same_bits(&w, &cold);
                wrong += nd;
            }
        }

        /* (iii) the empty set: the unconstrained minimum when nothing is active */
        int none[HP_QP_MMAX] = {0}, k = 0;
        for (int j = 0; j < m; ++j) k += cold.active[j];
        w = base;
        assert_int_equal(hpi_qp_solve_warm(&w, NULL, none, 200, 1e-12), HP_QP_OPTIMAL);
        if (k == 0) {
            assert_int_equal(w.warm, HP_QP_WARM_ACCEPTED);
            assert_int_equal(w.iterations, 0);
            compare(&w, &cold);
            ++empty_ok;
        } else {
            assert_int_not_equal(w.warm, HP_QP_WARM_ACCEPTED);
            assert_same_bits(&w, &cold);
        }
    }
    print_message("cold not optimal %d, accepted %d, non-degenerate %d, refused for "
                  "conditioning %d, wrong sets falling back %d, empty accepted %d, twin pairs "
                  "%d, sign refusals started from the rows kept %d (a point of an empty cold "
                  "QP found %d); worst |Δx|/tol %.3g, |Δu|/tol %.3g\n",
                  cold_fail, accepted, nondeg, refused_cond, wrong, empty_ok, pairs, kept,
                  point_found, worst_x, worst_u);
    /* the sample exercises every branch */
    assert_true(accepted > 5000 && nondeg > 3000 && wrong > 4000 && kept > 1000 && empty_ok > 100 &&
                pairs > 500 && refused_cond > 10 && cold_fail < 10);
}

/* The caller's Cholesky factor (as the backend passes it) changes nothing: the warm answer
 * with it is the warm answer without it, bit for bit, accepted or not. */
static void test_warm_factored_same_bits(void **st)
{
    (void)st;
    uint64_t seed = 4242;
    for (int t = 0; t < 1000; ++t) {
        hp_qp q, r;
        realtime_qp(&q, &seed);
        hp_qp cold = q;
        hp_qp_status cs = hpi_qp_solve(&cold, 200, 1e-12);
        int g[HP_QP_MMAX];
        memcpy(g, cold.active, sizeof g);
        if (t % 2 && q.m > 0) g[t % q.m] = !g[t % q.m];
        double L[NM * NM];
        assert_int_equal(hpi_cholesky(q.G, q.n, q.n, 0.0, L, q.n), 1);
        r = q;
        hp_qp_status ws = hpi_qp_solve_warm(&q, NULL, g, 200, 1e-12);
        assert_int_equal(hpi_qp_solve_warm(&r, L, g, 200, 1e-12), ws);
        /* only a QP empty to rounding may differ (test_warm_vs_cold) */
        if (ws != cs) assert_true(cs != HP_QP_OPTIMAL && q.iterations > q.gi_steps);
        assert_int_equal(q.warm, r.warm);
        assert_same_bits(&q, &r);
    }
}

/* The set-up a QP keeps between solves (hp_qp.ck_: the inverse factor, and the inverse and
 * R after a warm start's kept rows) changes nothing: a second solve on the same struct with
 * only a and b changed (as the realtime backend's QPs at the linear level change from plan
 * to plan, G and the rows the same), warm-started from the same guess as the solve before it
 * (the first one's active set, with one row wrong on three trials in four), is the solve
 * of a copy that keeps nothing, bit for bit. The sample must reach both kept set-ups. */
static void test_setup_cache_same_bits(void **st)
{
    (void)st;
    uint64_t seed = 777;
    int kept_inverse = 0, kept_adds = 0;
    for (int t = 0; t < 2000; ++t) {
        hp_qp q;
        realtime_qp(&q, &seed);
        hp_qp_status s1 = hpi_qp_solve_warm(&q, NULL, NULL, 200, 1e-12);
        if (s1 == HP_QP_BAD_INPUT) continue;
        int g[HP_QP_MMAX];
        memcpy(g, q.active, sizeof g);
        /* one row of the true set's guess wrong on most trials: a refused guess whose kept
         * rows start the loop (warm_gi), the adds kept */
        if (t % 4 && q.m > 0) g[t % q.m] = !g[t % q.m];
        (void)hpi_qp_solve_warm(&q, NULL, g, 200, 1e-12);
        for (int i = 0; i < q.n; ++i) q.a[i] *= 1.0 + 0.2 * (lf_uniform(&seed) - 0.5);
        for (int j = 0; j < q.m; ++j) q.b[j] += 0.05 * (lf_uniform(&seed) - 0.5);
        kept_inverse += q.ck_ >= 1;
        kept_adds += q.ck_ == 2;
        hp_qp fresh = q;
        fresh.ck_ = 0; /* keeps nothing */
        double L[NM * NM];
        const double *Lg = t % 2 && hpi_cholesky(q.G, q.n, q.n, 0.0, L, q.n) ? L : NULL;
        hp_qp_status a = hpi_qp_solve_warm(&q, Lg, g, 200, 1e-12);
        assert_int_equal(hpi_qp_solve_warm(&fresh, Lg, g, 200, 1e-12), a);
        assert_int_equal(q.warm, fresh.warm);
        assert_same_bits(&q, &fresh);
    }
    print_message("set-up kept before the second solve: the inverse %d, the adds %d of 2000\n",
                  kept_inverse, kept_adds);
    assert_true(kept_inverse > 1000 && kept_adds > 300);
}

/* The refusals, one by one, on a 3-variable QP whose answer has rows 0 and 2 active:
 * the true set is accepted; a twin pair, more rows than n, a zero row and a budget below
 * the guess's size are refused unsolved; dependent rows for conditioning; a subset and a
 * superset on the multiplier's sign or another row's violation. */
static void test_warm_refusals(void **st)
{
    (void)st;
    hp_qp q;
    memset(&q, 0, sizeof q);
    q.n = 3;
    q.m = 8;
    for (int i = 0; i < 3; ++i) q.G[i * 3 + i] = 1.0;
    q.a[0] = q.a[1] = q.a[2] = -10.0; /* unconstrained minimum (10, 10, 10) */
    const double rows[8][3] = {
        {-1, 0, 0},     {1, 0, 0}, /* twin pair: 0 <= x0 <= 1 */
        {0, -1, 0},     {0, 1, 0}, /* twin pair: 0 <= x1 <= 2 */
        {0, 0, -1},                /* x2 <= 50: inactive */
        {0, 0, 0},                 /* zero row, 0 >= −1 */
        {-1, 0, 0},                /* a copy of row 0, x0 <= 3: inactive */
        {-1, -1e-9, 0},            /* nearly row 0, x0 + 1e-9 x1 <= 4: inactive */
    };
    const double b[8] = {-1, 0, -2, 0, -50, -1, -3, -4};
    for (int j = 0; j < 8; ++j) {
        memcpy(&q.C[j * NM], rows[j], sizeof rows[j]);
        q.b[j] = b[j];
    }
    hp_qp cold = q;
    assert_int_equal(hpi_qp_solve(&cold, 100, 1e-12), HP_QP_OPTIMAL);
    const int truth[8] = {1, 0, 1, 0, 0, 0, 0, 0};
    assert_memory_equal(cold.active, truth, sizeof truth);
    struct {
        int g[8], budget;
        hp_qp_warm want;
    } cases[] = {
        {{1, 0, 1, 0, 0, 0, 0, 0}, 100, HP_QP_WARM_ACCEPTED},
        {{1, 1, 1, 0, 0, 0, 0, 0}, 100, HP_QP_WARM_SHAPE},     /* twin pair */
        {{1, 0, 1, 0, 1, 0, 0, 1}, 100, HP_QP_WARM_SHAPE},     /* 4 rows, n = 3 */
        {{1, 0, 1, 0, 0, 1, 0, 0}, 100, HP_QP_WARM_SHAPE},     /* the zero row */
        {{1, 0, 1, 0, 0, 0, 0, 0}, 1, HP_QP_WARM_SHAPE},       /* budget 1 < 2 rows */
        {{1, 0, 0, 0, 0, 0, 1, 0}, 100, HP_QP_WARM_CONDITION}, /* row 6 = row 0 */
        {{1, 0, 0, 0, 0, 0, 0, 1}, 100, HP_QP_WARM_CONDITION}, /* κ(S) ~ 1e18 */
        {{0, 0, 1, 0, 0, 0, 0, 0}, 100, HP_QP_WARM_VIOLATED},  /* x0 = 10 > 1 */
        {{1, 0, 1, 0, 1, 0, 0, 0}, 100, HP_QP_WARM_SIGN},      /* x2 <= 50 pulled to 50 */
        {{0, 0, 0, 0, 0, 0, 0, 0}, 100, HP_QP_WARM_VIOLATED},  /* (10, 10, 10) */
    };
    for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
        hp_qp w = q;
        hp_qp_status s = hpi_qp_solve_warm(&w, NULL, cases[c].g, cases[c].budget, 1e-12);
        if (w.warm != cases[c].want) {
            print_error("case %zu: warm %d, want %d\n", c, w.warm, cases[c].want);
            fail();
        }
        if (cases[c].budget == 1) { /* the fallback runs on the same budget: 2 adds > 1 */
            assert_int_equal(s, HP_QP_ITERATION_LIMIT);
            continue;
        }
        assert_int_equal(s, HP_QP_OPTIMAL);
        for (int i = 0; i < 3; ++i) hp_assert_close(w.x[i], cold.x[i], 0, 1e-14);
        if (w.warm == HP_QP_WARM_SIGN) {
            /* row 4 dropped, rows 0 and 2 kept: the loop has nothing left to add */
            assert_memory_equal(w.active, truth, sizeof truth);
            assert_int_equal(w.iterations, 2);
            assert_int_equal(w.gi_steps, 0);
        } else if (w.warm == HP_QP_WARM_VIOLATED && w.iterations > w.gi_steps) {
            /* row 2 kept, the loop adds row 0 */
            assert_memory_equal(w.active, truth, sizeof truth);
            assert_int_equal(w.iterations, 2);
            assert_int_equal(w.gi_steps, 1);
        } else if (w.warm != HP_QP_WARM_ACCEPTED) {
            assert_same_bits(&w, &cold);
        }
    }
    /* the answer by hand: x = (1, 2, 10), multipliers of x0 <= 1 and x1 <= 2: 9 and 8 */
    hp_qp w = q;
    assert_int_equal(hpi_qp_solve_warm(&w, NULL, truth, 100, 1e-12), HP_QP_OPTIMAL);
    assert_int_equal(w.iterations, 2);
    hp_assert_close(w.x[0], 1.0, 0, 1e-15);
    hp_assert_close(w.x[1], 2.0, 0, 1e-15);
    hp_assert_close(w.x[2], 10.0, 0, 1e-15);
    hp_assert_close(w.u[0], 9.0, 0, 1e-14);
    hp_assert_close(w.u[2], 8.0, 0, 1e-14);
    /* the guess may be the output array itself (the backend passes q->active) */
    w = cold;
    assert_int_equal(hpi_qp_solve_warm(&w, NULL, w.active, 100, 1e-12), HP_QP_OPTIMAL);
    assert_int_equal(w.warm, HP_QP_WARM_ACCEPTED);
    assert_memory_equal(w.active, truth, sizeof truth);
}

/* Whatever the guess, bad input is refused and an empty feasible set reported: NaN or
 * infinity in a guessed row, its b, G or a gives HP_QP_BAD_INPUT; x0 >= 1 with x0 <= 0
 * stays HP_QP_INFEASIBLE guessed with either row, both, or none; so does an unsatisfiable
 * zero row. */
static void test_warm_bad_input_and_infeasible(void **st)
{
    (void)st;
    const double bad[] = {NAN, INFINITY, -INFINITY};
    uint64_t seed = 5;
    hp_qp base;
    realtime_qp(&base, &seed);
    while (base.n < 3 || base.m < 4) realtime_qp(&base, &seed);
    hp_qp cold = base;
    assert_int_equal(hpi_qp_solve(&cold, 200, 1e-12), HP_QP_OPTIMAL);
    int g[HP_QP_MMAX] = {0};
    g[2] = 1; /* a guessed row, whatever the answer */
    for (int v = 0; v < 3; ++v) {
        double *where[] = {&base.C[2 * NM + 1], &base.b[2], &base.G[1], &base.a[0]};
        for (size_t k = 0; k < sizeof where / sizeof *where; ++k) {
            hp_qp q = base;
            *(double *)((char *)&q + ((char *)where[k] - (char *)&base)) = bad[v];
            assert_int_equal(hpi_qp_solve_warm(&q, NULL, g, 200, 1e-12), HP_QP_BAD_INPUT);
            assert_int_equal(hpi_qp_solve_warm(&q, NULL, cold.active, 200, 1e-12), HP_QP_BAD_INPUT);
        }
    }
    hp_qp q;
    memset(&q, 0, sizeof q);
    q.n = 2;
    q.m = 3;
    q.G[0] = q.G[3] = 1.0;
    q.C[0] = 1.0; /* x0 >= 1 */
    q.b[0] = 1.0;
    q.C[NM] = -1.0; /* −x0 >= 0 */
    q.b[1] = 0.0;
    q.b[2] = -1.0; /* zero row 0 >= −1: holds */
    const int guesses[4][3] = {{1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 0}};
    for (int k = 0; k < 4; ++k) {
        hp_qp w = q;
        assert_int_equal(hpi_qp_solve_warm(&w, NULL, guesses[k], 100, 1e-12), HP_QP_INFEASIBLE);
        assert_int_not_equal(w.warm, HP_QP_WARM_ACCEPTED);
    }
    q.b[1] = -5.0; /* now feasible; the zero row made unsatisfiable: 0 >= 1 */
    q.b[2] = 1.0;
    for (int k = 0; k < 4; ++k) {
        hp_qp w = q;
        assert_int_equal(hpi_qp_solve_warm(&w, NULL, guesses[k], 100, 1e-12), HP_QP_INFEASIBLE);
    }
}

/* The leading rows of q that come in exact twin pairs (row 2i + 1 = −row 2i in the first
 * n columns), counted here by comparison, independently of the solver. */
static int leading_pairs(const hp_qp *q)
{
    int p = 0;
    for (; 2 * p + 1 < q->m; ++p)
        for (int i = 0; i < q->n; ++i)
            if (q->C[(2 * p + 1) * NM + i] != -q->C[2 * p * NM + i]) return p;
    return p;
}

/* Declaring the twin pairs (hp_qp.pairs) changes no bit of any answer: on 3000 QPs of the
 * realtime backend's shape (one in seven with a pair of zero rows, which may make it
 * infeasible), cold and warm (the cold active set, and it with a row flipped), with G
 * factored by the solver and by the caller, the status, x, u, the active set, the step
 * count and the warm start's verdict equal those of the same QP with pairs = 0. A count
 * outside 0..m/2 and a NaN in a declared pair's b are refused. */
static void test_declared_pairs_same_bits(void **st)
{
    (void)st;
    uint64_t seed = 1616;
    int declared = 0;
    for (int t = 0; t < 3000; ++t) {
        hp_qp q;
        realtime_qp(&q, &seed);
        int p = leading_pairs(&q);
        if (p > 0 && t % 7 == 0)
            for (int i = 0; i < q.n; ++i) {
                q.C[i] = 0.0;
                q.C[NM + i] = -0.0;
            }
        declared += p > 0;
        hp_qp cold = q, pc = q;
        pc.pairs = p;
        hp_qp_status cs = hpi_qp_solve(&cold, 200, 1e-12);
        assert_int_equal(hpi_qp_solve(&pc, 200, 1e-12), cs);
        assert_same_bits(&pc, &cold);
        int g[HP_QP_MMAX];
        memcpy(g, cold.active, sizeof g);
        if (t % 2 && q.m > 0) g[t % q.m] = !g[t % q.m];
        double L[NM * NM];
        assert_int_equal(hpi_cholesky(q.G, q.n, q.n, 0.0, L, q.n), 1);
        for (int f = 0; f < 2; ++f) {
            hp_qp w0 = q, w1 = q;
            w1.pairs = p;
            hp_qp_status ws = hpi_qp_solve_warm(&w0, f ? L : NULL, g, 200, 1e-12);
            assert_int_equal(hpi_qp_solve_warm(&w1, f ? L : NULL, g, 200, 1e-12), ws);
            assert_int_equal(w1.warm, w0.warm);
            assert_same_bits(&w1, &w0);
        }
    }
    assert_true(declared > 1500); /* most generated QPs have pairs */
    hp_qp q;
    realtime_qp(&q, &seed);
    while (leading_pairs(&q) < 2) realtime_qp(&q, &seed);
    for (int bad = 0; bad < 2; ++bad) {
        hp_qp w = q;
        w.pairs = bad ? -1 : w.m / 2 + 1;
        assert_int_equal(hpi_qp_solve(&w, 200, 1e-12), HP_QP_BAD_INPUT);
    }
    for (int r = 0; r < 2; ++r) {
        hp_qp w = q;
        w.pairs = 2;
        w.b[2 + r] = NAN;
        assert_int_equal(hpi_qp_solve(&w, 200, 1e-12), HP_QP_BAD_INPUT);
        w = q;
        w.pairs = 2;
        w.C[2 * NM] = INFINITY; /* the checked row of a declared pair */
        assert_int_equal(hpi_qp_solve(&w, 200, 1e-12), HP_QP_BAD_INPUT);
    }
}

/* common/dense.c runs its routines through copies with a constant n for n = 1..6 (the
 * warm start's Gram matrices): each must give the bits of the textbook loops written out
 * here in the same order of operations (no reordering: the same sums, the same divisions),
 * for n = 1..8 (7, 8: the general copy), with leading dimensions larger than n. */
static void test_dense_fixed_sizes_same_bits(void **st)
{
    (void)st;
    uint64_t seed = 99;
    for (int t = 0; t < 400; ++t) {
        int n = 1 + t % 8, ld = n + t % 3;
        double F[64], A[100], L[100], Lr[100], b[10], br[10];
        for (int i = 0; i < n * n; ++i) F[i] = lf_uniform(&seed);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double s = i == j ? 0.5 : 0.0;
                for (int k = 0; k < n; ++k) s += F[i * n + k] * F[j * n + k];
                A[i * ld + j] = s;
            }
        /* reference: L_jj = sqrt(A_jj − Σ L_jk²), L_ij = (A_ij − Σ L_ik L_jk) / L_jj */
        for (int j = 0; j < n; ++j) {
            double s = A[j * ld + j];
            for (int k = 0; k < j; ++k) s -= Lr[j * ld + k] * Lr[j * ld + k];
            Lr[j * ld + j] = sqrt(s);
            for (int i = j + 1; i < n; ++i) {
                double u = A[i * ld + j];
                for (int k = 0; k < j; ++k) u -= Lr[i * ld + k] * Lr[j * ld + k];
                Lr[i * ld + j] = u / Lr[j * ld + j];
            }
        }
        assert_int_equal(hpi_cholesky(A, ld, n, 0.0, L, ld), 1);
        for (int i = 0; i < n; ++i)
            assert_memory_equal(&L[i * ld], &Lr[i * ld], (size_t)(i + 1) * sizeof *L);
        for (int i = 0; i < n; ++i) b[i] = br[i] = lf_uniform(&seed);
        for (int i = 0; i < n; ++i) {
            for (int k = 0; k < i; ++k) br[i] -= Lr[i * ld + k] * br[k];
            br[i] /= Lr[i * ld + i];
        }
        for (int i = n - 1; i >= 0; --i) {
            for (int k = i + 1; k < n; ++k) br[i] -= Lr[k * ld + i] * br[k];
            br[i] /= Lr[i * ld + i];
        }
        hpi_cholesky_solve(L, ld, n, b);
        assert_memory_equal(b, br, (size_t)n * sizeof *b);
        double fr = 0, x[10];
        for (int j = 0; j < n; ++j)
            for (int i = j; i < n; ++i) {
                double u = i == j ? 1.0 : 0.0;
                for (int k = j; k < i; ++k) u -= Lr[i * ld + k] * x[k];
                x[i] = u / Lr[i * ld + i];
                fr += x[i] * x[i];
            }
        double got = hpi_cholesky_inv_frob2(L, ld, n);
        assert_memory_equal(&got, &fr, sizeof fr);
    }
}

/* hpi_qp_solve_lazy: on seeded random QPs of the realtime shape, some rows' b raised by a random
 * amount (a stand-in: the constraint tightened, never loosened) and marked lazy; one QP in seven
 * has a pair of zero rows first, whose b alone decides (a raised one that no x satisfies must stop
 * the solve on it, not call the QP infeasible). Each stop (HP_QP_LAZY) names a marked row, whose
 * exact b is then put back, and the solve starts again (as the realtime backend does after a warm
 * start's stop); the solve that runs to its end must be the exact QP's solve bit for bit (status,
 * x, multipliers, active set, iterations, what the warm start did), with no guess, with the exact
 * answer's active set as the guess and with a random guess. With resume, each stop of the full
 * solve's loop (qp.resumable) goes on from its iterate (hpi_qp_resume_lazy) instead of starting
 * again, and so does a stop in the warm start's check of the other rows (after its equality solve);
 * a stop on a guessed stand-in row (before it) starts again. The counts: *stops (started again),
 * *resumes, *skipped (stand-in rows never needed), *repeats (equality solves of the warm start
 * beyond one per solve: the work a start again repeats, qp.warm_solved), *zstops (stops on a zero
 * row); returns the solves compared. */
static long lazy_sweep(uint64_t seed, int resume, long *stops, long *resumes, long *skipped,
                       long *repeats, long *rescans, long *zstops)
{
    long solves = 0;
    for (int t = 0; t < 3000; ++t) {
        hp_qp exact;
        realtime_qp(&exact, &seed);
        int m = exact.m;
        if (t % 7 == 0 && m >= 2) /* a pair of zero rows: its b alone decides, 0 >= b */
            for (int i = 0; i < exact.n; ++i) {
                exact.C[i] = 0.0;
                exact.C[NM + i] = -0.0;
            }
        hp_qp probe = exact;
        if (hpi_qp_solve(&probe, 200, 1e-12) != HP_QP_OPTIMAL) continue;
        for (int v = 0; v < 3; ++v) {
            int g[HP_QP_MMAX] = {0};
            for (int j = 0; j < m; ++j)
                g[j] = v == 1 ? probe.active[j] : v == 2 && test_rng_next(&seed) % 4 == 0;
            hp_qp ref = exact, q = exact;
            hp_qp_status rs = hpi_qp_solve_warm(&ref, NULL, v ? g : NULL, 200, 1e-12);
            unsigned char lazy[HP_QP_MMAX] = {0};
            for (int j = 0; j < m; ++j)
                if (test_rng_next(&seed) % 2 == 0) {
                    lazy[j] = 1;
                    q.b[j] += pow(10.0, -6.0 + 6.0 * test_rng_uniform(&seed, 0.0, 1.0));
                }
            int hit;
            hp_qp_status qs = hpi_qp_solve_lazy(&q, NULL, v ? g : NULL, lazy, &hit, 200, 1e-12);
            int eq = q.warm_solved, scans = q.scans, again = 0;
            while (qs == HP_QP_LAZY) {
                assert_true(hit >= 0 && hit < m && lazy[hit]);
                *zstops += t % 7 == 0 && m >= 2 && hit < 2; /* as zeroed above */
                lazy[hit] = 0;
                q.b[hit] = exact.b[hit];
                if (resume && q.resumable) {
                    ++*resumes;
                    qs = hpi_qp_resume_lazy(&q, lazy, &hit, 200, 1e-12);
                } else {
                    ++*stops;
                    again = 1;
                    qs = hpi_qp_solve_lazy(&q, NULL, v ? g : NULL, lazy, &hit, 200, 1e-12);
                }
                eq += q.warm_solved;
                scans += q.scans;
            }
            *repeats += eq > 1 ? eq - 1 : 0;
            /* a solve only resumed scans the rows as often as the exact one */
            if (!again) *rescans += scans - ref.scans;
            for (int j = 0; j < m; ++j) *skipped += lazy[j];
            ++solves;
            assert_int_equal(qs, rs);
            if (rs != HP_QP_OPTIMAL) continue;
            assert_memory_equal(q.x, ref.x, sizeof q.x);
            assert_memory_equal(q.u, ref.u, sizeof q.u);
            assert_memory_equal(q.active, ref.active, sizeof q.active);
            assert_int_equal(q.iterations, ref.iterations);
            assert_int_equal(q.warm, ref.warm);
        }
    }
    return solves;
}

static void test_lazy_rows_same_bits(void **st)
{
    (void)st;
    long stops = 0, resumes = 0, skipped = 0, repeats = 0, rescans = 0, zstops = 0;
    long solves = lazy_sweep(0x1a2e, 0, &stops, &resumes, &skipped, &repeats, &rescans, &zstops);
    print_message("lazy rows: %ld solves, %ld stops for an exact b (%ld on a zero row), %ld "
                  "stand-in rows never needed, %ld warm equality solves repeated\n",
                  solves, stops, zstops, skipped, repeats);
    assert_true(solves > 6000);
    assert_true(stops > 0 && skipped > 0 && zstops > 0);
    assert_true(repeats > 0); /* starting again repeats the warm start's equality solve */
}

/* test_lazy_rows_same_bits with resume: the stopped solve goes on from its iterate with the
 * row made exact, and the finished solve equals the exact solve in x, multipliers, active
 * set, iterations and the warm start's outcome, without solving a warm start's equality
 * system twice. A finished solve is not resumable. */
static void test_lazy_resume_same_bits(void **st)
{
    (void)st;
    long stops = 0, resumes = 0, skipped = 0, repeats = 0, rescans = 0, zstops = 0;
    long solves = lazy_sweep(0x2e5e, 1, &stops, &resumes, &skipped, &repeats, &rescans, &zstops);
    print_message("lazy rows resumed: %ld solves, %ld stops resumed, %ld started again, %ld warm "
                  "equality solves repeated, %ld rows' products formed again\n",
                  solves, resumes, stops, repeats, rescans);
    assert_true(solves > 6000);
    assert_true(resumes > 1000);
    /* a stop after the warm start's equality solve resumes its check: never solved twice */
    assert_int_equal(repeats, 0);
    /* nor are the rows' products at the stopped iterate formed again: a solve that only
     * resumed scans for the most violated row as often as the exact solve (each resume's
     * first scan reuses the stop's) */
    assert_int_equal(rescans, 0);
    uint64_t seed = 0x5e5;
    hp_qp q;
    realtime_qp(&q, &seed);
    assert_int_equal(hpi_qp_solve(&q, 200, 1e-12) == HP_QP_LAZY, 0);
    assert_false(q.resumable);
    assert_int_equal(hpi_qp_resume_lazy(&q, NULL, NULL, 200, 1e-12), HP_QP_BAD_INPUT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_warm_vs_cold),
        cmocka_unit_test(test_warm_factored_same_bits),
        cmocka_unit_test(test_setup_cache_same_bits),
        cmocka_unit_test(test_warm_refusals),
        cmocka_unit_test(test_warm_bad_input_and_infeasible),
        cmocka_unit_test(test_declared_pairs_same_bits),
        cmocka_unit_test(test_dense_fixed_sizes_same_bits),
        cmocka_unit_test(test_lazy_rows_same_bits),
        cmocka_unit_test(test_lazy_resume_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
