/* The offline NLP's exact derivatives (what Ipopt is given, through its sparsity patterns)
 * against central finite differences of the same callbacks: gradient of the objective,
 * Jacobian of the contact and rate constraints, and the Hessian of the Lagrangian
 * obj_factor·∇²f + Σ λ_i ∇²g_i (lower triangle, filled out by symmetry), on four rows around
 * the step of the step trace, at the surface contact level, with a large smoothness weight so
 * its cross-row terms count. */
#include "support/test_util.h"
#include "tests/horizon/horizon_fixture.h"

#include "horizon/horizon_internal.h"

#define T_ROWS 4
#define N_B 8
#define NX (6 + N_B)
#define NV (T_ROWS * NX)
#define NC (T_ROWS * 2 * N_B)
/* Central differences in scaled units (mm, degrees): truncation ~h²·|f'''| ≈ 1e-10,
 * rounding ~1e-16·|f|/h ≈ 1e-9 for the values here; 1e-5 of the entry's scale leaves a wide
 * margin yet catches any wrong term (a wrong factor or sign is O(1) of the entry). */
#define FD_H 1e-5
#define FD_REL 1e-5

typedef struct eval {
    double f, grad[NV], g[NC], jac[NC * NV], hess[NV * NV];
} eval;

static void run(const hf_case *c, const hp_horizon_settings *hs, const double *x, const double *lam,
                eval *e)
{
    assert_int_equal(hpi_horizon_nlp_dense(&c->sc.layout, &c->s, hs, c->rows + 48, T_ROWS, c->p0, x,
                                           0.7, lam, &e->f, e->grad, e->g, e->jac, e->hess),
                     HP_OK);
}

static void test_derivatives(void **st)
{
    (void)st;
    hf_case *c = hf_load("horizon/step.yaml", "step.csv", 60);
    assert_non_null(c);
    assert_int_equal(c->sc.layout.n, N_B);
    c->s.level = HP_LEVEL_SURFACE;
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    hs.smooth = 0.3;
    double x[NV], lam[NC];
    uint64_t seed = 42;
    for (int t = 0; t < T_ROWS; ++t) {
        for (int i = 0; i < 6; ++i) {
            double s = i < 3 ? 1e3 : 57.295779513082320877;
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            x[t * NX + i] = 0.6 * c->rows[48 + t].correction[i] * s +
                            0.1 * ((double)(seed >> 11) / 9007199254740992.0 - 0.5);
        }
        for (int k = 0; k < N_B; ++k) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            x[t * NX + 6 + k] = 27.0 + 2.0 * ((double)(seed >> 11) / 9007199254740992.0);
        }
    }
    for (int i = 0; i < NC; ++i) {
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        lam[i] = 2.0 * ((double)(seed >> 11) / 9007199254740992.0) - 1.0;
    }
    eval *e0 = calloc(1, sizeof *e0), *ep = calloc(1, sizeof *ep), *em = calloc(1, sizeof *em);
    run(c, &hs, x, lam, e0);
    double worst_g = 0, worst_j = 0, worst_h = 0;
    for (int j = 0; j < NV; ++j) {
        double xp[NV], xm[NV];
        memcpy(xp, x, sizeof xp);
        memcpy(xm, x, sizeof xm);
        xp[j] += FD_H;
        xm[j] -= FD_H;
        run(c, &hs, xp, lam, ep);
        run(c, &hs, xm, lam, em);
        /* gradient entry j */
        double fd = (ep->f - em->f) / (2 * FD_H);
        double scale = 1.0 + fabs(e0->grad[j]);
        worst_g = fmax(worst_g, fabs(fd - e0->grad[j]) / scale);
        /* Jacobian column j */
        for (int r = 0; r < NC; ++r) {
            double fdj = (ep->g[r] - em->g[r]) / (2 * FD_H);
            worst_j = fmax(worst_j,
                           fabs(fdj - e0->jac[r * NV + j]) / (1.0 + fabs(e0->jac[r * NV + j])));
        }
        /* Hessian column j: d/dx_j of (0.7·∇f + Jᵀλ) */
        for (int i = 0; i < NV; ++i) {
            double lp = 0.7 * ep->grad[i], lm = 0.7 * em->grad[i];
            for (int r = 0; r < NC; ++r) {
                lp += lam[r] * ep->jac[r * NV + i];
                lm += lam[r] * em->jac[r * NV + i];
            }
            double fdh = (lp - lm) / (2 * FD_H);
            double h = i >= j ? e0->hess[i * NV + j] : e0->hess[j * NV + i];
            worst_h = fmax(worst_h, fabs(fdh - h) / (1.0 + fabs(h)));
        }
    }
    print_message("largest relative error: gradient %.3g, Jacobian %.3g, Hessian %.3g\n", worst_g,
                  worst_j, worst_h);
    assert_true(worst_g <= FD_REL);
    assert_true(worst_j <= FD_REL);
    assert_true(worst_h <= FD_REL);
    /* the smoothness term and the rate rows couple consecutive rows: a cross-row entry exists */
    assert_true(fabs(e0->hess[(NX + 6) * NV + 6]) > 0);
    free(e0);
    free(ep);
    free(em);
    free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_derivatives)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
