/* Contact distances at the three levels: values against independent formulas, exact J and
 * H against central differences and Richardson-extrapolated differences. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "kin_test_util.h"
#include "kinematics/kin_geom.h"
#include "kinematics/kin_internal.h"

#include <string.h>

static hp_layout LAY;

static int setup(void **state)
{
    (void)state;
    return default_layout(&LAY);
}

static double rho_at(const hp_layout *L, hp_level lv, const double xi[6], int k)
{
    double rho[HP_MAX_BLADDERS];
    assert_int_equal(hp_contact_eval(L, lv, xi, rho, NULL, NULL), HP_OK);
    return rho[k];
}

/* Central difference of J (for H) at step h, and of rho (for J) Richardson-extrapolated.
 * Tolerances, in SI (rho ~ 0.03 m, lever ~ 0.13 m, curvature radius >= 52 mm):
 *  - J vs Richardson of rho (h = 2.5e-4 and 1.25e-4): the h⁴ term was measured at
 *    1.2e-9 for h = 1e-3 (coefficient ~5e3), so 5e-12 here; rounding ε·0.03/1.25e-4 ≈
 *    5e-14: tolerance 1e-10 (J entries are O(0.01..1)).
 *  - J vs plain central difference (h = 1e-6): truncation h²·|ρ'''|/6 <= 1e-12·1e3/6,
 *    rounding ε·0.03/1e-6 ≈ 7e-12: tolerance 1e-8.
 *  - H vs central difference of J (h = 1e-6): same reasoning one order up: rel 1e-7 plus
 *    abs 1e-8 (entries O(0.01..10)).
 *  - H vs Richardson of second differences of rho (h = 2e-3 and 1e-3): rounding
 *    4ε·0.03/(1e-3)² ≈ 3e-11, truncation h⁴ terms <= 1e-12·1e4: tolerance 1e-7 + 1e-6 rel. */
static void check_level_derivs(const hp_layout *L, hp_level lv, const double xi[6])
{
    int n = L->n;
    double rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6], H[HP_MAX_BLADDERS * 36];
    assert_int_equal(hp_contact_eval(L, lv, xi, rho, J, H), HP_OK);
    for (int i = 0; i < 6; ++i) {
        double xp[6], xm[6], Jp[HP_MAX_BLADDERS * 6], Jm[HP_MAX_BLADDERS * 6];
        double rp[HP_MAX_BLADDERS], rm[HP_MAX_BLADDERS];
        const double h = 1e-6;
        memcpy(xp, xi, sizeof xp);
        memcpy(xm, xi, sizeof xm);
        xp[i] += h;
        xm[i] -= h;
        assert_int_equal(hp_contact_eval(L, lv, xp, rp, Jp, NULL), HP_OK);
        assert_int_equal(hp_contact_eval(L, lv, xm, rm, Jm, NULL), HP_OK);
        for (int k = 0; k < n; ++k) {
            hp_assert_close(J[k * 6 + i], (rp[k] - rm[k]) / (2 * h), 0, 1e-8);
            for (int j = 0; j < 6; ++j)
                hp_assert_close(H[k * 36 + j * 6 + i], (Jp[k * 6 + j] - Jm[k * 6 + j]) / (2 * h),
                                1e-7, 1e-8);
            double D[2];
            for (int l = 0; l < 2; ++l) {
                double s = 2.5e-4 / (1 << l), a[6], b[6];
                memcpy(a, xi, sizeof a);
                memcpy(b, xi, sizeof b);
                a[i] += s;
                b[i] -= s;
                D[l] = (rho_at(L, lv, a, k) - rho_at(L, lv, b, k)) / (2 * s);
            }
            hp_assert_close(J[k * 6 + i], (4 * D[1] - D[0]) / 3, 0, 1e-10);
        }
    }
    /* Second method for H: Richardson of the second differences of rho itself. */
    for (int i = 0; i < 6; ++i)
        for (int j = i; j < 6; ++j) {
            double D[HP_MAX_BLADDERS][2];
            for (int l = 0; l < 2; ++l) {
                double s = 2e-3 / (1 << l);
                double x[4][6], r[4][HP_MAX_BLADDERS];
                const int si[4] = {1, 1, -1, -1}, sj[4] = {1, -1, 1, -1};
                for (int q = 0; q < 4; ++q) {
                    memcpy(x[q], xi, sizeof x[q]);
                    x[q][i] += si[q] * s;
                    x[q][j] += sj[q] * s;
                    assert_int_equal(hp_contact_eval(L, lv, x[q], r[q], NULL, NULL), HP_OK);
                }
                for (int k = 0; k < n; ++k)
                    D[k][l] = (r[0][k] - r[1][k] - r[2][k] + r[3][k]) / (4 * s * s);
            }
            for (int k = 0; k < n; ++k)
                hp_assert_close(H[k * 36 + i * 6 + j], (4 * D[k][1] - D[k][0]) / 3, 1e-6, 1e-7);
        }
}

static void test_derivatives_all_levels(void **state)
{
    (void)state;
    uint64_t rng = 2024;
    const double zero[6] = {0};
    for (int lv = HP_LEVEL_LINEAR; lv <= HP_LEVEL_SURFACE; ++lv) {
        check_level_derivs(&LAY, (hp_level)lv, zero);
        for (int i = 0; i < 12; ++i) {
            double xi[6];
            kin_rng_pose(&rng, 0.02, 0.26, 0, xi);
            check_level_derivs(&LAY, (hp_level)lv, xi);
        }
    }
    /* A sphere head, off-centre pivot. */
    hp_head s = default_head();
    s.shape = HP_HEAD_SPHERE;
    s.semi_axes[0] = 0.09;
    s.center[2] = 0.01;
    hp_layout L;
    assert_int_equal(default_layout_on(&L, &s, 0.0), 0);
    L.pivot[1] = 0.02;
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    for (int i = 0; i < 4; ++i) {
        double xi[6];
        kin_rng_pose(&rng, 0.02, 0.26, 0, xi);
        check_level_derivs(&L, HP_LEVEL_SURFACE, xi);
        check_level_derivs(&L, HP_LEVEL_PLANE, xi);
    }
}

/* At xi = 0 all three levels have the same value (rho0) and Jacobian (the linear J0 from
 * its closed form). J agreement to 1e-15: both are sums of three products of O(1) terms. */
static void test_levels_agree_at_zero(void **state)
{
    (void)state;
    const double zero[6] = {0};
    double r[3][HP_MAX_BLADDERS], J[3][HP_MAX_BLADDERS * 6];
    for (int lv = 0; lv < 3; ++lv)
        assert_int_equal(hp_contact_eval(&LAY, (hp_level)lv, zero, r[lv], J[lv], NULL), HP_OK);
    for (int k = 0; k < LAY.n; ++k) {
        hp_assert_close(r[0][k], 0.030, 0, 1e-15); /* touching at Ro, no preload */
        for (int lv = 1; lv < 3; ++lv) {
            hp_assert_close(r[lv][k], r[0][k], 0, 1e-16);
            for (int i = 0; i < 6; ++i)
                hp_assert_close(J[lv][k * 6 + i], J[0][k * 6 + i], 0, 1e-15);
        }
    }
}

/* Plane level against the direct formula n(ξ)ᵀ(c − p(ξ)), p(ξ) = pivot + R(p − pivot) + t,
 * n(ξ) = R n (computed here without the back-transform the library uses): 1e-16 m. Surface
 * level against a brute-force moved ellipsoid: the surface point pivot + R(s − pivot) + t
 * for s on the nominal surface, minimised over a dense sample near the contact. */
static void test_plane_formula(void **state)
{
    (void)state;
    uint64_t rng = 99;
    for (int it = 0; it < 200; ++it) {
        double xi[6], R[9], rho[HP_MAX_BLADDERS];
        kin_rng_pose(&rng, 0.03, 0.5, 0, xi);
        hp_rotation(xi[3], xi[4], xi[5], R);
        assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_PLANE, xi, rho, NULL, NULL), HP_OK);
        for (int k = 0; k < LAY.n; ++k) {
            double pm[3], nm[3], v = 0, c0[3], n0[3];
            assert_int_equal(hp_layout_contact(&LAY, k, c0, n0, NULL), HP_OK);
            for (int i = 0; i < 3; ++i) {
                pm[i] = LAY.pivot[i] + xi[i];
                nm[i] = 0;
                for (int j = 0; j < 3; ++j) {
                    pm[i] += R[i * 3 + j] * (c0[j] - LAY.pivot[j]);
                    nm[i] += R[i * 3 + j] * n0[j];
                }
            }
            for (int i = 0; i < 3; ++i) v += nm[i] * (LAY.bladders[k].center[i] - pm[i]);
            hp_assert_close(rho[k], v, 0, 1e-16);
        }
    }
}

static void test_surface_brute_force(void **state)
{
    (void)state;
    const double xi[6] = {0.004, -0.006, 0.003, 0.05, -0.08, 0.06};
    double R[9], rho[HP_MAX_BLADDERS];
    hp_rotation(xi[3], xi[4], xi[5], R);
    assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_SURFACE, xi, rho, NULL, NULL), HP_OK);
    const double *a = LAY.head.semi_axes;
    for (int k = 0; k < LAY.n; ++k) {
        /* Parametrise the surface by angles around the nominal contact; a fine grid then
         * a local refinement by repeated grid shrinking (independent of the root find). */
        double p0[3], c0[3];
        assert_int_equal(hp_layout_contact(&LAY, k, c0, NULL, NULL), HP_OK);
        for (int i = 0; i < 3; ++i) p0[i] = c0[i] / a[i];
        double th0 = acos(p0[2]), ph0 = atan2(p0[1], p0[0]);
        double best = INFINITY, bt = th0, bp = ph0, span = 0.3;
        for (int round = 0; round < 40; ++round) {
            double ct = bt, cp = bp;
            for (int i = -10; i <= 10; ++i)
                for (int j = -10; j <= 10; ++j) {
                    double th = ct + span * i / 10, ph = cp + span * j / 10;
                    double s[3] = {a[0] * sin(th) * cos(ph), a[1] * sin(th) * sin(ph),
                                   a[2] * cos(th)};
                    double e = 0;
                    for (int m = 0; m < 3; ++m) {
                        double w = LAY.pivot[m] + xi[m];
                        for (int l = 0; l < 3; ++l) w += R[m * 3 + l] * (s[l] - LAY.pivot[l]);
                        e += (LAY.bladders[k].center[m] - w) * (LAY.bladders[k].center[m] - w);
                    }
                    e = sqrt(e);
                    if (e < best) {
                        best = e;
                        bt = th;
                        bp = ph;
                    }
                }
            span *= 0.5;
        }
        /* The refined grid minimum converges to ~1e-16 relative; 1e-14 m allows rounding of
         * the trigonometric parametrisation. */
        hp_assert_close(rho[k], best, 0, 1e-14);
    }
}

/* The contact model's closed-form assembly against the generic chain rule it replaced, kept
 * here as the reference: c' = Rᵀu + pivot, its derivatives ∂c'/∂θ_j = ∂R/∂θ_jᵀ u from all
 * three rotation derivatives, J = [−R g, (∂c'/∂θ)ᵀ g], and the Hessian Cᵀ ∇²f C plus the
 * gradient term from all nine second derivatives of R (hpi_kin_rotation_derivs, itself
 * checked against plain products in test_pose.c), all with full 3-term sums. The library
 * drops exact zero terms and moves exact negations out of the same sums, so every distance,
 * Jacobian and Hessian entry must be equal (==; only the sign of a zero may differ), at the
 * plane and surface levels, on 400 seeded poses up to 20 mm and up to 170° (and some with
 * one angle exactly 0 or ±π/2). */
static void ref_contact(const hp_layout *L, hp_level lv, const double xi[6], double *rho, double *J,
                        double *H)
{
    double R[9], dR[3][9], d2R[3][3][9];
    hpi_kin_rotation_derivs(xi + 3, R, dR, d2R);
    for (int k = 0; k < L->n; ++k) {
        const double *c = L->bladders[k].center;
        double u[3], cp[3], Cr[3][3], f, g[3], hf[9];
        for (int i = 0; i < 3; ++i) u[i] = c[i] - L->pivot[i] - xi[i];
        for (int m = 0; m < 3; ++m) {
            cp[m] = R[m] * u[0] + R[3 + m] * u[1] + R[6 + m] * u[2] + L->pivot[m];
            for (int j = 0; j < 3; ++j)
                Cr[m][j] = dR[j][m] * u[0] + dR[j][3 + m] * u[1] + dR[j][6 + m] * u[2];
        }
        if (lv == HP_LEVEL_SURFACE) {
            assert_int_equal(hpi_kin_head_distance(&L->head, cp, &f, g, hf, NULL), HP_OK);
        } else {
            double p[3], n[3];
            assert_int_equal(hp_layout_contact(L, k, p, n, NULL), HP_OK);
            f = n[0] * (cp[0] - p[0]) + n[1] * (cp[1] - p[1]) + n[2] * (cp[2] - p[2]);
            memcpy(g, n, sizeof g);
        }
        rho[k] = f;
        for (int i = 0; i < 3; ++i) {
            J[k * 6 + i] = g[0] * -R[i * 3] + g[1] * -R[i * 3 + 1] + g[2] * -R[i * 3 + 2];
            J[k * 6 + 3 + i] = g[0] * Cr[0][i] + g[1] * Cr[1][i] + g[2] * Cr[2][i];
        }
        double Hs[6][6] = {{0}};
        if (lv == HP_LEVEL_SURFACE) {
            double C[3][6], hC[3][6];
            for (int m = 0; m < 3; ++m)
                for (int i = 0; i < 3; ++i) {
                    C[m][i] = -R[i * 3 + m];
                    C[m][3 + i] = Cr[m][i];
                }
            for (int a = 0; a < 3; ++a)
                for (int i = 0; i < 6; ++i)
                    hC[a][i] = hf[a * 3] * C[0][i] + hf[a * 3 + 1] * C[1][i] +
                               hf[a * 3 + 2] * C[2][i];
            for (int i = 0; i < 6; ++i)
                for (int j = i; j < 6; ++j)
                    Hs[i][j] = C[0][i] * hC[0][j] + C[1][i] * hC[1][j] + C[2][i] * hC[2][j];
        }
        for (int b = 0; b < 3; ++b) {
            const double *D = dR[b];
            for (int a = 0; a < 3; ++a)
                Hs[a][3 + b] -= D[a * 3] * g[0] + D[a * 3 + 1] * g[1] + D[a * 3 + 2] * g[2];
            for (int a = 0; a <= b; ++a) {
                const double *Q = d2R[a][b];
                double qg[3];
                for (int l = 0; l < 3; ++l)
                    qg[l] = Q[l * 3] * g[0] + Q[l * 3 + 1] * g[1] + Q[l * 3 + 2] * g[2];
                Hs[3 + a][3 + b] += u[0] * qg[0] + u[1] * qg[1] + u[2] * qg[2];
            }
        }
        for (int i = 0; i < 6; ++i)
            for (int j = i; j < 6; ++j) H[k * 36 + i * 6 + j] = H[k * 36 + j * 6 + i] = Hs[i][j];
    }
}

static void test_generic_form(void **state)
{
    (void)state;
    uint64_t rng = 404;
    const double PI = 3.14159265358979323846;
    for (int it = 0; it < 400; ++it) {
        double xi[6];
        kin_rng_pose(&rng, it % 2 ? 0.02 : 0.003, it % 2 ? 2.97 : 0.1, it % 7 == 0, xi);
        if (it % 10 == 3) xi[3 + it % 3] = 0.0;
        if (it % 10 == 5) xi[3 + it % 3] = it % 4 ? PI / 2 : -PI / 2;
        for (int lv = HP_LEVEL_PLANE; lv <= HP_LEVEL_SURFACE; ++lv) {
            double rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6], H[HP_MAX_BLADDERS * 36];
            double rr[HP_MAX_BLADDERS], Jr[HP_MAX_BLADDERS * 6], Hr[HP_MAX_BLADDERS * 36];
            assert_int_equal(hp_contact_eval(&LAY, (hp_level)lv, xi, rho, J, H), HP_OK);
            ref_contact(&LAY, (hp_level)lv, xi, rr, Jr, Hr);
            for (int k = 0; k < LAY.n; ++k) {
                assert_true(rho[k] == rr[k]);
                for (int i = 0; i < 6; ++i) assert_true(J[k * 6 + i] == Jr[k * 6 + i]);
                for (int i = 0; i < 36; ++i) assert_true(H[k * 36 + i] == Hr[k * 36 + i]);
            }
        }
    }
}

/* The order hpi_kin_contact_inside documents (kin_geom.h), computed here from the public
 * linear-level evaluation: at the surface level the bladder whose linear distance (mm) lies
 * furthest outside its bounds, max(lo − v, v − hi), lowest index on a tie, then the others
 * in index order; at the linear and plane levels index order. order[0..n-1]. */
static void inside_order(const hp_layout *L, hp_level lv, const double xi[6], const double *lo,
                         const double *hi, int order[HP_MAX_BLADDERS])
{
    double rl[HP_MAX_BLADDERS];
    assert_int_equal(hp_contact_eval(L, HP_LEVEL_LINEAR, xi, rl, NULL, NULL), HP_OK);
    int first = 0;
    double most = -INFINITY;
    for (int k = 0; lv == HP_LEVEL_SURFACE && k < L->n; ++k) {
        double v = rl[k] * 1000.0, over = fmax(lo[k] - v, v - hi[k]);
        if (over > most) {
            most = over;
            first = k;
        }
    }
    order[0] = first;
    for (int k = 0, j = 1; k < L->n; ++k)
        if (k != first) order[j++] = k;
}

/* hpi_kin_contact_inside against a full hp_contact_eval at the same pose: the verdict is
 * the exact one (every distance in mm inside its bounds, boundaries included); inside, all
 * n distances are the full evaluation's bits; outside, exactly the bladders of the documented
 * order up to the first one outside are written, with the full evaluation's bits, and the
 * rest untouched. Bounds at a distance itself and one ulp past it probe the comparison
 * exactly; bounds well past it (a target beyond reach) make the prediction matter. */
static void check_inside(const hp_geom *G, hp_level lv, const double xi[6], const double *lo,
                         const double *hi, int *verdict, int *skipped)
{
    double rho[HP_MAX_BLADDERS], got[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6],
        gJ[HP_MAX_BLADDERS * 6], got2[HP_MAX_BLADDERS];
    int order[HP_MAX_BLADDERS];
    assert_int_equal(hp_contact_eval(&LAY, lv, xi, rho, J, NULL), HP_OK);
    int want = 1;
    for (int k = 0; k < LAY.n; ++k) want &= rho[k] * 1000.0 >= lo[k] && rho[k] * 1000.0 <= hi[k];
    for (int k = 0; k < LAY.n; ++k) got[k] = -1.0;
    for (int i = 0; i < LAY.n * 6; ++i) gJ[i] = -1.0;
    int inside = -1, inside2 = -1;
    assert_int_equal(hpi_kin_contact_inside(&LAY, G, lv, xi, 1000.0, lo, hi, got, NULL, &inside),
                     HP_OK);
    assert_int_equal(inside, want);
    /* With the Jacobian asked for: the same distances and verdict, and the full
     * evaluation's Jacobian rows (bit for bit) of exactly the bladders evaluated. */
    assert_int_equal(hpi_kin_contact_inside(&LAY, G, lv, xi, 1000.0, lo, hi, got2, gJ, &inside2),
                     HP_OK);
    assert_int_equal(inside2, want);
    inside_order(&LAY, lv, xi, lo, hi, order);
    int reached = 1; /* still evaluating, in the documented order */
    for (int j = 0; j < LAY.n; ++j) {
        int k = order[j];
        if (reached) {
            assert_true(got[k] == rho[k]);
            assert_true(got2[k] == rho[k]);
            assert_memory_equal(&gJ[k * 6], &J[k * 6], 6 * sizeof *J);
            reached = rho[k] * 1000.0 >= lo[k] && rho[k] * 1000.0 <= hi[k];
        } else {
            assert_true(got[k] == -1.0); /* never evaluated */
            for (int i = 0; i < 6; ++i) assert_true(gJ[k * 6 + i] == -1.0);
        }
    }
    *verdict = want;
    /* Whether the stop came before some bladder index order would have evaluated. */
    int first_out = 0;
    while (first_out < LAY.n && rho[first_out] * 1000.0 >= lo[first_out] &&
           rho[first_out] * 1000.0 <= hi[first_out])
        ++first_out;
    *skipped = !want && order[0] > first_out;
}

/* 900 seeded poses up to 10 mm and 0.1 rad at the three levels, bounds as check_inside
 * says. Each verdict occurs more than 200 times, and more than 25 "outside" verdicts (at
 * the surface level) stop before reaching the first bladder outside in index order, so the
 * order is exercised. A NaN pose is an error, never inside, every distance NaN; a NULL
 * argument is refused; a NaN bound is outside. */
static void test_inside(void **state)
{
    (void)state;
    hp_geom G;
    assert_int_equal(hpi_geom_derive(&LAY, &G, NULL), HP_OK);
    uint64_t rng = 505;
    int outs = 0, ins = 0, skips = 0;
    for (int it = 0; it < 900; ++it) {
        double xi[6];
        kin_rng_pose(&rng, 0.01, 0.1, 0, xi);
        hp_level lv = (hp_level)(HP_LEVEL_LINEAR + it % 3);
        double rho[HP_MAX_BLADDERS], lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS];
        assert_int_equal(hp_contact_eval(&LAY, lv, xi, rho, NULL, NULL), HP_OK);
        for (int k = 0; k < LAY.n; ++k) {
            double mm = rho[k] * 1000.0;
            /* mostly inside; in a third of the poses one bladder in eight at or one ulp past
             * a bound, in another third one in four well past a bound (0.01..3 mm) */
            int mode = (it / 3) % 3;
            int pick = mode == 0                          ? (int)test_rng_uniform(&rng, 0, 32)
                       : mode == 1                        ? 4 + (int)test_rng_uniform(&rng, 0, 4)
                       : test_rng_uniform(&rng, 0, 4) < 1 ? 8
                                                          : 4;
            double past = test_rng_uniform(&rng, 0.01, 3.0);
            lo[k] = pick == 0 ? mm : pick == 1 ? nextafter(mm, INFINITY) : mm - 1.0;
            hi[k] = pick == 2 ? mm : pick == 3 ? nextafter(mm, -INFINITY) : mm + 1.0;
            if (pick == 8 && it % 2) lo[k] = mm + past;
            if (pick == 8 && !(it % 2)) hi[k] = mm - past;
        }
        int v, sk;
        check_inside(&G, lv, xi, lo, hi, &v, &sk);
        outs += !v;
        ins += v;
        skips += sk;
    }
    assert_true(outs > 200 && ins > 200 && skips > 25); /* 441, 459, 48 */
    double xi[6] = {0, 0, 0, NAN, 0, 0}, got[HP_MAX_BLADDERS], lo[HP_MAX_BLADDERS] = {0},
           hi[HP_MAX_BLADDERS];
    for (int k = 0; k < LAY.n; ++k) hi[k] = 1e9;
    int inside = 1;
    assert_int_equal(
        hpi_kin_contact_inside(&LAY, &G, HP_LEVEL_SURFACE, xi, 1000.0, lo, hi, got, NULL, &inside),
        HP_ERR_INVALID);
    assert_int_equal(inside, 0);
    for (int k = 0; k < LAY.n; ++k) assert_true(isnan(got[k]));
    xi[3] = 0.0;
    const double *bad[4][2] = {{NULL, hi}, {lo, NULL}, {lo, hi}, {lo, hi}};
    for (int c = 0; c < 4; ++c)
        assert_int_equal(hpi_kin_contact_inside(&LAY, &G, HP_LEVEL_SURFACE, xi, 1000.0, bad[c][0],
                                                bad[c][1], c == 2 ? NULL : got, NULL,
                                                c == 3 ? NULL : &inside),
                         HP_ERR_NULL);
    /* A NaN bound is outside whatever the order (the comparison fails). */
    hi[LAY.n - 1] = NAN;
    inside = 1;
    assert_int_equal(
        hpi_kin_contact_inside(&LAY, &G, HP_LEVEL_PLANE, xi, 1000.0, lo, hi, got, NULL, &inside),
        HP_OK);
    assert_int_equal(inside, 0);
}

/* The prediction can be wrong: the bladder the linear level puts furthest outside is
 * inside (its bound exactly at its distance), another one is outside by one ulp of its
 * distance, every other bound is 1 m away. The verdict is still "outside", the predicted
 * bladder was evaluated (at the surface level first) and so was the one outside. At the
 * plane (index order) and surface levels, on seeded poses of 10 mm and 0.2 rad, where the
 * linear level differs from the exact distance by far more than an ulp (asserted), each
 * other bladder in turn as the one outside. */
static void test_inside_prediction_wrong(void **state)
{
    (void)state;
    hp_geom G;
    assert_int_equal(hpi_geom_derive(&LAY, &G, NULL), HP_OK);
    uint64_t rng = 606;
    for (int it = 0; it < 40; ++it) {
        double xi[6], rl[HP_MAX_BLADDERS], rho[HP_MAX_BLADDERS];
        kin_rng_pose(&rng, 0.01, 0.2, 1, xi);
        hp_level lv = it % 2 ? HP_LEVEL_SURFACE : HP_LEVEL_PLANE;
        assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_LINEAR, xi, rl, NULL, NULL), HP_OK);
        assert_int_equal(hp_contact_eval(&LAY, lv, xi, rho, NULL, NULL), HP_OK);
        /* A: the largest |exact − linear|, the bound put on the side the linear value is past. */
        int a = 0;
        for (int k = 1; k < LAY.n; ++k)
            if (fabs(rho[k] - rl[k]) > fabs(rho[a] - rl[a])) a = k;
        assert_true(fabs(rho[a] - rl[a]) * 1000.0 > 1e-6); /* mm: ~1e9 ulps of 30 mm */
        for (int b = 0; b < LAY.n; ++b) {
            if (b == a) continue;
            double lo[HP_MAX_BLADDERS], hi[HP_MAX_BLADDERS], got[HP_MAX_BLADDERS];
            int order[HP_MAX_BLADDERS];
            for (int k = 0; k < LAY.n; ++k) {
                lo[k] = rho[k] * 1000.0 - 1000.0;
                hi[k] = rho[k] * 1000.0 + 1000.0;
                got[k] = -1.0;
            }
            if (rl[a] < rho[a]) lo[a] = rho[a] * 1000.0;
            else hi[a] = rho[a] * 1000.0;
            /* b outside by one ulp on the side its linear value is not past, so its predicted
             * violation is about −|exact − linear| + 1 ulp, below a's +|exact − linear|. */
            if (rl[b] < rho[b]) hi[b] = nextafter(rho[b] * 1000.0, -INFINITY);
            else lo[b] = nextafter(rho[b] * 1000.0, INFINITY);
            inside_order(&LAY, lv, xi, lo, hi, order);
            if (lv == HP_LEVEL_SURFACE)
                assert_int_equal(order[0], a); /* the construction makes a the predicted worst */
            int inside = -1;
            assert_int_equal(
                hpi_kin_contact_inside(&LAY, &G, lv, xi, 1000.0, lo, hi, got, NULL, &inside),
                HP_OK);
            assert_int_equal(inside, 0);
            if (lv == HP_LEVEL_SURFACE) assert_true(got[a] == rho[a]);
            assert_true(got[b] == rho[b]);
            int v, sk;
            check_inside(&G, lv, xi, lo, hi, &v, &sk);
            assert_int_equal(v, 0);
        }
    }
}

/* hpi_kin_contact_eval_mask: rho, J and the masked bladders' Hessians are the bits of a full
 * evaluation; the other bladders' 36 entries of H are not written (a sentinel survives);
 * an error writes NaN everywhere. 300 seeded poses and masks, plane and surface. */
static void test_eval_mask(void **state)
{
    (void)state;
    hp_geom G;
    assert_int_equal(hpi_geom_derive(&LAY, &G, NULL), HP_OK);
    uint64_t rng = 9090;
    const double sentinel = 12345.0;
    for (int it = 0; it < 300; ++it) {
        hp_level lv = it % 2 ? HP_LEVEL_SURFACE : HP_LEVEL_PLANE;
        double xi[6], rf[HP_MAX_BLADDERS], Jf[HP_MAX_BLADDERS * 6], Hf[HP_MAX_BLADDERS * 36];
        double rm[HP_MAX_BLADDERS], Jm[HP_MAX_BLADDERS * 6], Hm[HP_MAX_BLADDERS * 36];
        unsigned char mask[HP_MAX_BLADDERS];
        kin_rng_pose(&rng, 0.01, 0.2, 0, xi);
        for (int k = 0; k < LAY.n; ++k) mask[k] = test_rng_uniform(&rng, 0, 1) < 0.3;
        if (it % 7 == 0) memset(mask, 0, sizeof mask);
        for (int i = 0; i < LAY.n * 36; ++i) Hm[i] = sentinel;
        assert_int_equal(hpi_contact_eval_g(&LAY, &G, lv, xi, rf, Jf, Hf), HP_OK);
        assert_int_equal(hpi_kin_contact_eval_mask(&LAY, &G, lv, xi, NULL, mask, rm, Jm, Hm),
                         HP_OK);
        assert_memory_equal(rf, rm, LAY.n * sizeof *rf);
        assert_memory_equal(Jf, Jm, LAY.n * 6 * sizeof *Jf);
        for (int k = 0; k < LAY.n; ++k)
            for (int i = 0; i < 36; ++i) {
                double want = mask[k] ? Hf[k * 36 + i] : sentinel;
                assert_memory_equal(&want, &Hm[k * 36 + i], sizeof want);
            }
    }
    double bad[6] = {0, NAN, 0, 0, 0, 0}, r[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6],
           H[HP_MAX_BLADDERS * 36];
    unsigned char none[HP_MAX_BLADDERS] = {0};
    for (int i = 0; i < LAY.n * 36; ++i) H[i] = sentinel;
    assert_int_equal(
        hpi_kin_contact_eval_mask(&LAY, &G, HP_LEVEL_SURFACE, bad, NULL, none, r, J, H),
        HP_ERR_INVALID);
    for (int i = 0; i < LAY.n * 36; ++i) assert_true(isnan(H[i]));
}

static void test_bad_args(void **state)
{
    (void)state;
    double xi[6] = {0, 0, 0, 0, 0, 0}, rho[HP_MAX_BLADDERS];
    assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_AUTO, xi, rho, NULL, NULL), HP_ERR_INVALID);
    assert_int_equal(hp_contact_eval(NULL, HP_LEVEL_PLANE, xi, rho, NULL, NULL), HP_ERR_NULL);
    xi[4] = NAN;
    assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_SURFACE, xi, rho, NULL, NULL), HP_ERR_INVALID);
    assert_true(isnan(rho[0]));
    hp_layout un = LAY; /* a layout whose geometry is invalid: the call refuses it */
    un.n = 0;
    xi[4] = 0;
    assert_int_equal(hp_contact_eval(&un, HP_LEVEL_SURFACE, xi, rho, NULL, NULL), HP_ERR_INVALID);
    /* A pose that drives a bladder centre deep into the head: a domain error, NaN outputs. */
    for (int i = 0; i < 3; ++i) xi[i] = LAY.bladders[0].center[i] - LAY.head.center[i];
    assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_SURFACE, xi, rho, NULL, NULL), HP_ERR_DOMAIN);
    assert_true(isnan(rho[0]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_derivatives_all_levels),
        cmocka_unit_test(test_levels_agree_at_zero),
        cmocka_unit_test(test_plane_formula),
        cmocka_unit_test(test_surface_brute_force),
        cmocka_unit_test(test_bad_args),
        cmocka_unit_test(test_generic_form),
        cmocka_unit_test(test_inside),
        cmocka_unit_test(test_inside_prediction_wrong),
        cmocka_unit_test(test_eval_mask),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
