/* The planner's program in scaled units: values against independent formulas (the nominal
 * pose touches every bladder; the linear Jacobian from the contact normals), and every
 * derivative against central finite differences at all three contact levels. */
#include "support/test_util.h"

#include "planner/problem.h"
#include "support/backend_fixture.h"

#include <stdlib.h>

#define PI 3.14159265358979323846

static hp_layout L;

static int setup(void **st)
{
    (void)st;
    return fx_layout(&L) == HP_OK ? 0 : -1;
}

/* A point away from every symmetry: a few mm and about a degree, radii spread round Ri. */
static void test_point(const hp_problem *pb, double *x)
{
    const double xi[6] = {1.7, -2.3, 0.9, 0.8, -1.1, 0.6};
    for (int i = 0; i < 6; i++) x[i] = xi[i];
    for (int k = 0; k < pb->n; k++) x[6 + k] = 27.0 + 0.9 * (k - 3.5);
}

static void nominal_touches(void **st)
{
    (void)st;
    const double d[6] = {0};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_SURFACE, d, &pb), HP_OK);
    double x[HP_PROBLEM_NX_MAX] = {0}, c[HP_MAX_BLADDERS];
    for (int k = 0; k < pb.n; k++) x[6 + k] = FX_RI * 1e3;
    for (int lv = HP_LEVEL_LINEAR; lv <= HP_LEVEL_SURFACE; lv++) {
        pb.level = (hp_level)lv;
        assert_int_equal(hpi_problem_constraints(&pb, x, c, NULL, NULL, NULL), HP_OK);
        /* ri = Ri gives ro = Ro = 30 mm exactly and the bladders were placed touching at
         * Ro: c = 0 up to the rounding of 30 mm (1e-14) and of the contact root find. */
        for (int k = 0; k < pb.n; k++) hp_assert_close(c[k], 0.0, 0.0, 1e-9);
    }
}

/* Independent values: c_k = cbrt(Ro³ + ri³ − Ri³) − 1000·ρ_k(ξ_SI) in mm; the linear level's
 * Jacobian row is [n, (p − pivot) × n] in mm/mm and mm/deg (c = ro − ρ, ∂ρ/∂t = −n). */
static void values_and_linear_jacobian(void **st)
{
    (void)st;
    const double d[6] = {0};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_LINEAR, d, &pb), HP_OK);
    double x[HP_PROBLEM_NX_MAX], c[HP_MAX_BLADDERS], jac[HP_MAX_BLADDERS * HP_PROBLEM_NX_MAX];
    test_point(&pb, x);
    assert_int_equal(hpi_problem_constraints(&pb, x, c, jac, NULL, NULL), HP_OK);
    double xi[6] = {x[0] * 1e-3,     x[1] * 1e-3,     x[2] * 1e-3,
                    x[3] * PI / 180, x[4] * PI / 180, x[5] * PI / 180};
    double rho[HP_MAX_BLADDERS];
    assert_int_equal(hp_contact_eval(&L, HP_LEVEL_LINEAR, xi, rho, NULL, NULL), HP_OK);
    for (int k = 0; k < pb.n; k++) {
        double ri = x[6 + k];
        double want = cbrt(30.0 * 30.0 * 30.0 + ri * ri * ri - 27.0 * 27.0 * 27.0) - 1e3 * rho[k];
        hp_assert_close(c[k], want, 0.0, 1e-12); /* 30 mm values: 1e-12 = ~100 ulp */
        const double *p = G.contact[k], *nv = G.normal[k];
        double m[3] = {p[1] * nv[2] - p[2] * nv[1], p[2] * nv[0] - p[0] * nv[2],
                       p[0] * nv[1] - p[1] * nv[0]};
        for (int i = 0; i < 3; i++) {
            hp_assert_close(jac[k * pb.nx + i], nv[i], 1e-12, 1e-15);
            hp_assert_close(jac[k * pb.nx + 3 + i], 1e3 * m[i] * PI / 180, 1e-12, 1e-15);
        }
        hp_assert_close(jac[k * pb.nx + 6 + k],
                        ri * ri / ((c[k] + 1e3 * rho[k]) * (c[k] + 1e3 * rho[k])), 1e-13, 0.0);
    }
}

/* Central differences with step h: truncation h²/6·|f'''| and rounding ~ε|f|/h. In these
 * units |f'''| is at most ~0.1 per unit³ (mu·P''' ~ 1e-8·2·3e3·5 Pa/mm³; ρ''' per deg³ ~ 5e-4
 * mm; ro''' ~ 1e-3/mm²) and |f| at most ~100 (c ~ 30 mm, P terms ~0.1), so with h = 1e-4
 * truncation is below 2e-10 and rounding below 2e-10; the surface level's root find adds its
 * ~1e-15 m noise / h ~ 1e-8 at worst. Measured worst: 1.7e-10. Tolerance 1e-8 absolute plus
 * 1e-7 relative: a wrong unit factor (π/180, 1e-3) or a dropped ro'' (~0.016/mm here) fails. */
#define FD_H 1e-4
#define FD_REL 1e-7
#define FD_ABS 1e-8

static void check_derivatives(hp_level level, double mu)
{
    const double d[6] = {0.5, -0.25, 1.0, 0.3, 0.2, -0.4};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, level, d, &pb), HP_OK);
    pb.mu = mu;
    for (int k = 0; k < pb.n; k++) pb.p_prev[k] = 500.0 * (k - 4);
    pb.w[3] = 2.5; /* not all weights equal */
    const int n = pb.n, nx = pb.nx;
    double x[HP_PROBLEM_NX_MAX];
    test_point(&pb, x);

    double f, g[HP_PROBLEM_NX_MAX], H[HP_PROBLEM_NX_MAX * HP_PROBLEM_NX_MAX];
    double c[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * HP_PROBLEM_NX_MAX];
    double lam[HP_MAX_BLADDERS], HL[HP_PROBLEM_NX_MAX * HP_PROBLEM_NX_MAX] = {0};
    for (int k = 0; k < n; k++) lam[k] = 0.7 - 0.3 * k;
    assert_int_equal(hpi_problem_objective(&pb, x, &f, g, H), HP_OK);
    assert_int_equal(hpi_problem_constraints(&pb, x, c, J, lam, HL), HP_OK);

    double worst_g = 0, worst_h = 0, worst_j = 0, worst_hl = 0;
    for (int j = 0; j < nx; j++) {
        double xp[HP_PROBLEM_NX_MAX], xm[HP_PROBLEM_NX_MAX];
        memcpy(xp, x, sizeof xp);
        memcpy(xm, x, sizeof xm);
        xp[j] += FD_H;
        xm[j] -= FD_H;
        double fp, fm, gp[HP_PROBLEM_NX_MAX], gm[HP_PROBLEM_NX_MAX];
        double cp[HP_MAX_BLADDERS], cm[HP_MAX_BLADDERS];
        double Jp[HP_MAX_BLADDERS * HP_PROBLEM_NX_MAX], Jm[HP_MAX_BLADDERS * HP_PROBLEM_NX_MAX];
        assert_int_equal(hpi_problem_objective(&pb, xp, &fp, gp, NULL), HP_OK);
        assert_int_equal(hpi_problem_objective(&pb, xm, &fm, gm, NULL), HP_OK);
        assert_int_equal(hpi_problem_constraints(&pb, xp, cp, Jp, NULL, NULL), HP_OK);
        assert_int_equal(hpi_problem_constraints(&pb, xm, cm, Jm, NULL, NULL), HP_OK);
        double fd = (fp - fm) / (2 * FD_H);
        worst_g = fmax(worst_g, fabs(fd - g[j]));
        hp_assert_close(g[j], fd, FD_REL, FD_ABS);
        for (int i = 0; i < nx; i++) {
            double fdh = (gp[i] - gm[i]) / (2 * FD_H);
            worst_h = fmax(worst_h, fabs(fdh - H[i * nx + j]));
            hp_assert_close(H[i * nx + j], fdh, FD_REL, FD_ABS);
            /* Σ λ_k ∂²c_k/∂x_i∂x_j from the Jacobian's differences. */
            double fdl = 0.0;
            for (int k = 0; k < n; k++) fdl += lam[k] * (Jp[k * nx + i] - Jm[k * nx + i]);
            fdl /= 2 * FD_H;
            worst_hl = fmax(worst_hl, fabs(fdl - HL[i * nx + j]));
            hp_assert_close(HL[i * nx + j], fdl, FD_REL, FD_ABS);
        }
        for (int k = 0; k < n; k++) {
            double fdc = (cp[k] - cm[k]) / (2 * FD_H);
            worst_j = fmax(worst_j, fabs(fdc - J[k * nx + j]));
            hp_assert_close(J[k * nx + j], fdc, FD_REL, FD_ABS);
        }
    }
    /* The Hessians are symmetric by construction: exactly, not just to rounding. */
    for (int i = 0; i < nx; i++)
        for (int j = 0; j < i; j++) {
            assert_true(H[i * nx + j] == H[j * nx + i]);
            hp_assert_close(HL[i * nx + j], HL[j * nx + i], 1e-14, 1e-15);
        }
    print_message("level %s mu %g: worst |FD - exact| grad %.2e hess %.2e jac %.2e "
                  "lagr-hess %.2e\n",
                  hp_level_name(level), mu, worst_g, worst_h, worst_j, worst_hl);
}

static void derivatives_linear(void **st)
{
    (void)st;
    check_derivatives(HP_LEVEL_LINEAR, 1e-8);
}
static void derivatives_plane(void **st)
{
    (void)st;
    check_derivatives(HP_LEVEL_PLANE, 1e-8);
}
static void derivatives_surface(void **st)
{
    (void)st;
    check_derivatives(HP_LEVEL_SURFACE, 1e-8);
    check_derivatives(HP_LEVEL_SURFACE, 0.0);
}

/* hess accumulates: constraints add onto what is there (the objective part). */
static void constraints_hessian_adds(void **st)
{
    (void)st;
    const double d[6] = {0};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_PLANE, d, &pb), HP_OK);
    double x[HP_PROBLEM_NX_MAX];
    test_point(&pb, x);
    const int nx = pb.nx;
    double lam[HP_MAX_BLADDERS];
    for (int k = 0; k < pb.n; k++) lam[k] = 1.0 + k;
    double h0[HP_PROBLEM_NX_MAX * HP_PROBLEM_NX_MAX] = {0};
    double h1[HP_PROBLEM_NX_MAX * HP_PROBLEM_NX_MAX];
    for (int i = 0; i < nx * nx; i++) h1[i] = 3.0;
    assert_int_equal(hpi_problem_constraints(&pb, x, NULL, NULL, lam, h0), HP_OK);
    assert_int_equal(hpi_problem_constraints(&pb, x, NULL, NULL, lam, h1), HP_OK);
    for (int i = 0; i < nx * nx; i++) hp_assert_close(h1[i], h0[i] + 3.0, 1e-15, 1e-14);
    /* pose–radius cross terms are zero (the structure Ipopt is given relies on it) */
    for (int i = 0; i < 6; i++)
        for (int k = 0; k < pb.n; k++) assert_true(h0[i * nx + 6 + k] == 0.0);
}

static void rejects_bad_input(void **st)
{
    (void)st;
    const double d[6] = {0};
    hp_problem pb;
    hp_geom G;
    assert_int_equal(fx_problem(&L, &G, HP_LEVEL_LINEAR, d, &pb), HP_OK);
    double x[HP_PROBLEM_NX_MAX], f, c[HP_MAX_BLADDERS];
    test_point(&pb, x);
    x[2] = NAN;
    assert_int_equal(hpi_problem_objective(&pb, x, &f, NULL, NULL), HP_ERR_INVALID);
    assert_int_equal(hpi_problem_constraints(&pb, x, c, NULL, NULL, NULL), HP_ERR_INVALID);
    test_point(&pb, x);
    x[7] = -1.0; /* ri <= 0: outside the bladder model */
    assert_int_not_equal(hpi_problem_constraints(&pb, x, c, NULL, NULL, NULL), HP_OK);
    pb.mu = 1e-8;
    assert_int_not_equal(hpi_problem_objective(&pb, x, &f, NULL, NULL), HP_OK);
    assert_int_equal(hpi_problem_objective(NULL, x, &f, NULL, NULL), HP_ERR_NULL);
    pb.nx = 7;
    assert_int_equal(hpi_problem_constraints(&pb, x, c, NULL, NULL, NULL), HP_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(nominal_touches),     cmocka_unit_test(values_and_linear_jacobian),
        cmocka_unit_test(derivatives_linear),  cmocka_unit_test(derivatives_plane),
        cmocka_unit_test(derivatives_surface), cmocka_unit_test(constraints_hessian_adds),
        cmocka_unit_test(rejects_bad_input),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
