/* The contact law's one home (kinematics/contact_law.c): its value against an independent
 * evaluation of F = P·pi·(2·ro·delta − delta²) in __float128, its first and second
 * derivatives against central differences, its work W against F (dW/drho = −F, W = 0 at
 * touch), and the load model's law (hp_load_law) reading the same numbers. */
#include "test_util.h"
#include "kinematics/contact_law.h"
#include "kinematics/load_internal.h"

#include <quadmath.h>

static __float128 qpi(void) { return acosq(-(__float128)1); }

/* A spread of states: P in 0.2..12 kPa, ro in 25..45 mm, delta/ro in 1e-4..0.9. */
static void state(int i, double *P, double *ro, double *rho)
{
    static const double dr[] = {1e-4, 0.01, 0.1, 0.26, 0.5, 0.9};
    *P = 200.0 + 11800.0 * (double)(i % 7) / 6.0;
    *ro = 0.025 + 0.020 * (double)(i % 5) / 4.0;
    *rho = *ro * (1.0 - dr[i % 6]);
}

static void test_cap_value(void **st)
{
    (void)st;
    for (int i = 0; i < 210; ++i) {
        double P, ro, rho;
        state(i, &P, &ro, &rho);
        hp_claw c;
        hp_claw_cap(P, ro, rho, &c);
        __float128 d = (__float128)ro - rho;
        __float128 want = (__float128)P * qpi() * (2 * (__float128)ro * d - d * d);
        /* The double evaluation rounds a handful of times: 1e-14 relative is ~50 ulps. */
        hp_assert_close(c.F, (double)want, 1e-14, 0.0);
        __float128 w = (__float128)P * qpi() * d * d * ((__float128)ro - d / 3);
        hp_assert_close(c.W, (double)w, 1e-13, 0.0);
    }
}

/* Central differences of a law in each variable: the cap law is quadratic in ro and rho
 * and linear in P, so the difference has no truncation error and its rounding is about
 * eps·|F|/h (h = 1e-6 of the variable's scale): 1e-7 relative is a wide margin. */
static void fd(double x[3], int j, double h, double *dF, double dd[3], double *dW)
{
    hp_claw a, b;
    double xp[3] = {x[0], x[1], x[2]}, xm[3] = {x[0], x[1], x[2]};
    xp[j] += h;
    xm[j] -= h;
    hp_claw_cap(xp[0], xp[1], xp[2], &a);
    hp_claw_cap(xm[0], xm[1], xm[2], &b);
    *dF = (a.F - b.F) / (2 * h);
    for (int k = 0; k < 3; ++k) dd[k] = (a.d[k] - b.d[k]) / (2 * h);
    *dW = (a.W - b.W) / (2 * h);
}

static void test_cap_derivatives(void **st)
{
    (void)st;
    for (int i = 0; i < 210; ++i) {
        double x[3];
        state(i, &x[0], &x[1], &x[2]);
        hp_claw c;
        hp_claw_cap(x[0], x[1], x[2], &c);
        const double scale[3] = {x[0], x[1], x[1]};
        for (int j = 0; j < 3; ++j) {
            double dF, dd[3], dW;
            fd(x, j, 1e-6 * scale[j], &dF, dd, &dW);
            double fs = fabs(c.F) / scale[j];
            hp_assert_close(c.d[j], dF, 1e-7, 1e-7 * fs);
            for (int k = 0; k < 3; ++k) {
                hp_assert_close(c.d2[j][k], dd[k], 1e-7, 1e-7 * fs / scale[k]);
                assert_true(c.d2[j][k] == c.d2[k][j]);
            }
            /* W = integral of F over the contact distance from rho to ro: dW/drho = −F
             * (W is cubic in rho: the difference is exact up to rounding). */
            if (j == HP_CLAW_RHO) hp_assert_close(dW, -c.F, 1e-7, 1e-7 * fabs(c.W) / x[1]);
        }
    }
    hp_claw t;
    hp_claw_cap(5e3, 0.03, 0.03, &t); /* at touch: no force, no work */
    assert_true(t.F == 0.0 && t.W == 0.0);
}

/* The load model's law is the same function (plus the contact switch and the chain rule
 * through ro(P)): bit for bit where the bladder touches. */
static void test_load_law_reads_it(void **st)
{
    (void)st;
    for (int i = 0; i < 210; ++i) {
        double P, ro, rho, dro = 1e-6 * (1 + i % 3);
        state(i, &P, &ro, &rho);
        hp_claw c;
        hp_load_force f;
        hp_claw_cap(P, ro, rho, &c);
        hp_load_law(P, ro, dro, rho, 0, &f);
        assert_true(f.F == c.F);
        assert_true(f.dF_drho == c.d[HP_CLAW_RHO]);
        assert_true(f.dF_dro == c.d[HP_CLAW_RO]);
        assert_true(f.dF_dP == c.d[HP_CLAW_P] + c.d[HP_CLAW_RO] * dro);
        assert_true(f.E == c.W);
    }
}

int main(void)
{
    const struct CMUnitTest t[] = {
        cmocka_unit_test(test_cap_value),
        cmocka_unit_test(test_cap_derivatives),
        cmocka_unit_test(test_load_law_reads_it),
    };
    return cmocka_run_group_tests(t, NULL, NULL);
}
