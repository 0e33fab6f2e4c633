/* An independent check of the load level's contact law F = P·pi·(ro² − rho²): the
 * axisymmetric contact of an inflated Mooney–Rivlin spherical membrane with a rigid
 * frictionless plate at constant pressure, solved by shooting on the membrane's
 * equilibrium equations (the formulation of Feng & Yang, 1973), with no cap approximation.
 *
 * Set-up: a spherical membrane of reference radius R and thickness H, inflated to pressure
 * P (free radius ro = lambda·R), squeezed between two parallel plates at distance 2·rho
 * (by symmetry: one plate at height rho above the fixed equatorial plane, which is what a
 * bladder with a fixed centre against a flat patch of head sees). Tensions per unit
 * deformed length (strain energy W = ½C1(I1−3) + ½C2(I2−3), incompressible):
 *   T1 = H·(l1/l2)·(1 − 1/(l1⁴l2²))·(C1 + C2·l2²),  T2 = the same with 1 <-> 2.
 * Along the reference arc s0 (pole at s0 = 0, equator at s0 = pi·R/2), with r0 = R·sin(s0/R),
 * l2 = r/r0, ds = l1·ds0 and phi the tangent's angle below the horizontal:
 *   r' = l1·cos(phi), z' = −l1·sin(phi),
 *   (r·T1)' = l1·T2·cos(phi)                          (meridional equilibrium),
 *   phi' = l1·(P − T2·sin(phi)/r)/T1                  (normal equilibrium; free part),
 * and in the contact disc phi = 0 with only the meridional equation (the plate carries the
 * pressure). The flat patch of radius a carries exactly F = P·pi·a² (its edge tension is
 * horizontal), so the membrane gives F(delta) through a(delta); the law uses
 * a² = ro² − rho² (the undeformed sphere cut by the plate). Shooting: for each contact
 * edge s0_a, the centre stretch l_c is found (bisection) so that the meridian reaches the
 * equator vertical (phi = pi/2 at s0 = pi·R/2); then rho = z(s0_a) − z(equator).
 * Fixed-step RK4 (1000 steps per part); doubling the steps changes F by < 1e-6 relative
 * (asserted below), far under the errors compared. */
#include "support/test_util.h"

#include <string.h>

static const double PI = 3.14159265358979323846;
/* Dimensionless: R = H = C1 = 1; C2/C1 = 2 (the paper's moduli ratio). */
static const double C2 = 2.0;

static double tension(double la, double lb)
{
    return (la / lb) * (1.0 - 1.0 / (la * la * la * la * lb * lb)) * (1.0 + C2 * lb * lb);
}

/* dT1/dl1 and dT1/dl2 by central differences of the closed form (h = 1e-6: truncation
 * ~1e-12, rounding ~1e-10 relative; the shooting's own accuracy is checked separately). */
static void tension_partials(double l1, double l2, double *d1, double *d2)
{
    const double h = 1e-6;
    *d1 = (tension(l1 + h, l2) - tension(l1 - h, l2)) / (2 * h);
    *d2 = (tension(l1, l2 + h) - tension(l1, l2 - h)) / (2 * h);
}

/* State y = (r, z, phi, l1) at reference arc s0; contact = 1 keeps phi = 0. */
static void rhs(double s0, const double y[4], double P, int contact, double dy[4])
{
    double r = y[0], phi = contact ? 0.0 : y[2], l1 = y[3];
    double r0 = sin(s0), dr0 = cos(s0);
    double l2 = r / r0;
    double T1 = tension(l1, l2), T2 = tension(l2, l1);
    double dr = l1 * cos(phi);
    double dl2 = (dr - l2 * dr0) / r0;
    double a, b;
    tension_partials(l1, l2, &a, &b);
    /* (r T1)' = r' T1 + r (a l1' + b l2') = l1 T2 cos(phi) -> l1' */
    double dl1 = (l1 * T2 * cos(phi) - dr * T1 - r * b * dl2) / (r * a);
    dy[0] = dr;
    dy[1] = -l1 * sin(phi);
    dy[2] = contact ? 0.0 : l1 * (P - T2 * sin(phi) / r) / T1;
    dy[3] = dl1;
}

static void rk4(double s_from, double s_to, int steps, double y[4], double P, int contact)
{
    double h = (s_to - s_from) / steps;
    for (int i = 0; i < steps; ++i) {
        double s = s_from + i * h, k1[4], k2[4], k3[4], k4[4], t[4];
        rhs(s, y, P, contact, k1);
        for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k1[j];
        rhs(s + 0.5 * h, t, P, contact, k2);
        for (int j = 0; j < 4; ++j) t[j] = y[j] + 0.5 * h * k2[j];
        rhs(s + 0.5 * h, t, P, contact, k3);
        for (int j = 0; j < 4; ++j) t[j] = y[j] + h * k3[j];
        rhs(s + h, t, P, contact, k4);
        for (int j = 0; j < 4; ++j) y[j] += h / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    }
}

/* Integrates from the contact centre (stretch lc) to the equator; returns phi − pi/2 there
 * and the contact radius a and half gap rho. */
static double shoot(double lc, double s0a, double P, int steps, double *a, double *rho)
{
    const double eps = 1e-6;
    double y[4] = {lc * sin(eps), 0.0, 0.0, lc};
    rk4(eps, s0a, steps, y, P, 1);
    *a = y[0];
    double z_edge = y[1];
    rk4(s0a, PI / 2, steps, y, P, 0);
    *rho = z_edge - y[1];
    return y[2] - PI / 2;
}

/* The centre stretch for contact edge s0a, by bisection on the equator angle. */
static int solve_contact(double s0a, double P, double lfree, int steps, double *a, double *rho)
{
    /* The equator angle turns very fast near the root (a centre stretch a little too
     * small curls the meridian over): scan for the sign change from + to − where both
     * values are small, then bisect. */
    double lo = 0.0, hi = 0.0, flo = 0.0, alo, rlo, prev_l = 0.0, prev_f = 0.0;
    int found = 0;
    for (int i = 0; i <= 200 && !found; ++i) {
        double l = lfree * (0.95 + 0.1 * i / 200.0);
        double f = shoot(l, s0a, P, steps, &alo, &rlo);
        if (i > 0 && prev_f > 0 && f <= 0 && prev_f < 1.0 && f > -1.0) {
            lo = prev_l;
            flo = prev_f;
            hi = l;
            found = 1;
        }
        prev_l = l;
        prev_f = f;
    }
    if (!found) return -1;
    for (int it = 0; it < 100; ++it) {
        double mid = 0.5 * (lo + hi), am, rm;
        double fm = shoot(mid, s0a, P, steps, &am, &rm);
        if ((fm < 0) == (flo < 0)) {
            lo = mid;
            flo = fm;
        } else {
            hi = mid;
        }
        *a = am;
        *rho = rm;
        if (hi - lo < 1e-14) break;
    }
    return 0;
}

/* The law against the membrane for delta/ro up to about 0.27, inflated to lambda = 1.1
 * (P from the free sphere: P = 2·T(l, l)/(R·l)). Asserted: step halving changes the
 * contact radius and the gap by < 1e-6 relative; the force rises with the indentation; and
 * the law's relative error, printed as a table (copied into docs/load.md), stays in the
 * measured band. */
static void test_membrane_vs_law(void **state)
{
    (void)state;
    const double lfree = 1.1;
    const double P = 2.0 * tension(lfree, lfree) / lfree;
    const double ro = lfree;
    printf("# delta/ro   F_membrane/(P*pi*ro^2)   F_law/(P*pi*ro^2)   law error\n");
    int rows = 0;
    double prevF = 0.0;
    for (double s0a = 0.02; s0a <= 0.55; s0a += 0.08) {
        double a = NAN, rho = NAN, a2 = NAN, rho2 = NAN; /* set by solve_contact on success */
        assert_int_equal(solve_contact(s0a, P, lfree, 1000, &a, &rho), 0);
        assert_int_equal(solve_contact(s0a, P, lfree, 2000, &a2, &rho2), 0);
        hp_assert_close(a2 * a2, a * a, 1e-6, 0.0);
        hp_assert_close(rho2, rho, 1e-6, 0.0);
        double delta = ro - rho;
        double Fm = a * a, Fl = ro * ro - rho * rho;
        double err = (Fl - Fm) / Fm;
        printf("  %8.4f   %12.6f   %12.6f   %+8.3f %%\n", delta / ro, Fm / (ro * ro),
               Fl / (ro * ro), 100 * err);
        /* What the comparison shows (docs/load.md): the membrane flattens less than the
         * cap for the same indentation, so the law overestimates the force, by a factor
         * that falls from ~8 as delta/ro -> 0 to ~2 at delta/ro = 0.25. Asserted: the sign
         * and the bounds of that measured band (±10 % of the measured factor). */
        assert_true(delta > 0 && Fm > prevF);
        assert_true(err > 0);
        if (delta / ro <= 0.01) assert_true(err > 5.0 && err < 8.0);
        if (delta / ro >= 0.2 && delta / ro <= 0.27) assert_true(err > 0.9 && err < 1.5);
        prevF = Fm;
        ++rows;
    }
    assert_true(rows >= 7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_membrane_vs_law),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
