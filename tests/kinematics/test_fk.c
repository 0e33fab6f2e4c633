/* Forward contact kinematics: pose -> radii -> pose round trips. */
#include "support/test_util.h"

#include "support/default_layout.h"
#include "kin_test_util.h"
#include "kinematics/fit_internal.h"
#include "kinematics/linalg.h"
#include "common/dense.h"

#include <string.h>

static hp_layout LAY;

static int setup(void **state)
{
    (void)state;
    return default_layout(&LAY);
}

/* Round trip at every level: radii from a pose, the pose back from the radii. Surface:
 * 1e-9 mm = 1e-12 m per translation and 1e-12 rad per angle (1e-9 mm at a 1 m lever);
 * the radii are exact to ~1e-17 m and the scaled Jacobian's condition is ~30, so the
 * attainable error is ~1e-15 m. RMS residual at the answer below 1e-15 m. */
static void test_round_trip(void **state)
{
    (void)state;
    uint64_t rng = 5;
    double worst[3] = {0};
    for (int lv = HP_LEVEL_LINEAR; lv <= HP_LEVEL_SURFACE; ++lv)
        for (int it = 0; it < 200; ++it) {
            double xi[6], ro[HP_MAX_BLADDERS], got[6], res;
            int iters;
            kin_rng_pose(&rng, 0.01, 0.09, 0, xi);
            assert_int_equal(hp_contact_eval(&LAY, (hp_level)lv, xi, ro, NULL, NULL), HP_OK);
            assert_int_equal(hp_contact_fk(&LAY, (hp_level)lv, ro, NULL, got, &res, &iters), HP_OK);
            for (int i = 0; i < 6; ++i) {
                hp_assert_close(got[i], xi[i], 0, 1e-12);
                worst[lv] = fmax(worst[lv], fabs(got[i] - xi[i]));
            }
            assert_true(res < 1e-15);
            assert_true(iters < 50);
        }
    print_message("worst round-trip error: linear %.2e, plane %.2e, surface %.2e (m or rad)\n",
                  worst[0], worst[1], worst[2]);
    /* A warm start at the answer returns it at once. */
    double xi[6] = {0.002, -0.001, 0.003, 0.01, -0.02, 0.015}, ro[HP_MAX_BLADDERS], got[6], res;
    int iters;
    assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_SURFACE, xi, ro, NULL, NULL), HP_OK);
    assert_int_equal(hp_contact_fk(&LAY, HP_LEVEL_SURFACE, ro, xi, got, &res, &iters), HP_OK);
    assert_true(iters <= 3);
    for (int i = 0; i < 6; ++i) hp_assert_close(got[i], xi[i], 0, 1e-12);
}

static double cosine(const double *J, const double *rho, const double *ro, int j)
{
    double g = 0, nj = 0, nr = 0;
    for (int k = 0; k < LAY.n; ++k) {
        double r = rho[k] - ro[k];
        g += J[k * 6 + j] * r;
        nj += J[k * 6 + j] * J[k * 6 + j];
        nr += r * r;
    }
    return fabs(g) / sqrt(nj * nr);
}

/* Inconsistent radii (noise of 0.1 mm): the fit is a least-squares stationary point at the
 * linear and surface levels, and the reported RMS is that of the returned pose. */
static void test_noisy(void **state)
{
    (void)state;
    uint64_t rng = 8;
    const double zero[6] = {0};
    double ro[HP_MAX_BLADDERS], xi[6], res, J[HP_MAX_BLADDERS * 6];
    assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_LINEAR, zero, ro, J, NULL), HP_OK);
    double noise[HP_MAX_BLADDERS];
    for (int k = 0; k < LAY.n; ++k) {
        noise[k] = 1e-4 * test_rng_normal(&rng);
        ro[k] += noise[k];
    }
    assert_int_equal(hp_contact_fk(&LAY, HP_LEVEL_LINEAR, ro, NULL, xi, &res, NULL), HP_OK);
    /* Optimality: the residual is orthogonal to every column of J (normal equations): the
     * cosine between r and column j below 1e-9 (a pose offset along column j of 1e-9·|r|/|J_j|,
     * i.e. below 1e-12 m or rad here). */
    double rho[HP_MAX_BLADDERS];
    assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_LINEAR, xi, rho, NULL, NULL), HP_OK);
    double ss = 0;
    for (int k = 0; k < LAY.n; ++k) ss += (rho[k] - ro[k]) * (rho[k] - ro[k]);
    hp_assert_close(res, sqrt(ss / LAY.n), 1e-12, 0);
    for (int j = 0; j < 6; ++j) assert_true(cosine(J, rho, ro, j) < 1e-9);
    assert_true(res > 1e-6); /* eight equations, six unknowns: noise cannot all be fitted */
    /* Surface level with the same noise: also a stationary point of the surface residual. */
    assert_int_equal(hp_contact_fk(&LAY, HP_LEVEL_SURFACE, ro, NULL, xi, &res, NULL), HP_OK);
    double Js[HP_MAX_BLADDERS * 6];
    assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_SURFACE, xi, rho, Js, NULL), HP_OK);
    for (int j = 0; j < 6; ++j) assert_true(cosine(Js, rho, ro, j) < 1e-9);
}

/* A sphere head: only translation is observable; rotations come back 0 and translations
 * exact (the sphere's radii do not depend on a rotation about its centre = pivot). */
static void test_sphere(void **state)
{
    (void)state;
    hp_head s = default_head();
    s.shape = HP_HEAD_SPHERE;
    s.semi_axes[0] = 0.09;
    hp_layout L;
    assert_int_equal(default_layout_on(&L, &s, 0.0), 0);
    assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
    double xi[6] = {0.004, -0.003, 0.002, 0.05, -0.03, 0.02}, ro[HP_MAX_BLADDERS], got[6], res;
    assert_int_equal(hp_contact_eval(&L, HP_LEVEL_SURFACE, xi, ro, NULL, NULL), HP_OK);
    assert_int_equal(hp_contact_fk(&L, HP_LEVEL_SURFACE, ro, NULL, got, &res, NULL), HP_OK);
    for (int i = 0; i < 3; ++i) hp_assert_close(got[i], xi[i], 0, 1e-12);
    for (int i = 3; i < 6; ++i) assert_true(got[i] == 0.0);
    assert_true(res < 1e-15);
}

static void test_bad_input(void **state)
{
    (void)state;
    double ro[HP_MAX_BLADDERS], xi[6], res;
    for (int k = 0; k < LAY.n; ++k) ro[k] = 0.03;
    ro[3] = NAN;
    assert_int_equal(hp_contact_fk(&LAY, HP_LEVEL_SURFACE, ro, NULL, xi, &res, NULL),
                     HP_ERR_INVALID);
    ro[3] = -0.01;
    assert_int_equal(hp_contact_fk(&LAY, HP_LEVEL_SURFACE, ro, NULL, xi, &res, NULL),
                     HP_ERR_INVALID);
    ro[3] = 0.03;
    assert_int_equal(hp_contact_fk(&LAY, HP_LEVEL_AUTO, ro, NULL, xi, &res, NULL), HP_ERR_INVALID);
    hp_layout few = LAY;
    few.n = 5;
    assert_int_equal(hp_layout_prepare(&few, NULL), HP_OK);
    assert_int_equal(hp_contact_fk(&few, HP_LEVEL_SURFACE, ro, NULL, xi, &res, NULL),
                     HP_ERR_INVALID);
    /* Five bladders cannot hold six degrees of freedom: the analysis says rank 5. */
    hp_layout_analysis a;
    assert_int_equal(hp_layout_analyze(&few, HP_LEVEL_LINEAR, &a), HP_OK);
    assert_int_equal(a.rank, 5);
    assert_true(isinf(a.condition));
    assert_true(a.singular_values[5] == 0.0);
}

/* hpi_kin_fit with the start point's model handed in takes the same steps as
 * hp_contact_fit (bit for bit: the handed-in model is what the fit computes there); with
 * an expected pose it may stop early, and then within tol/2 of it and of the full fit;
 * expecting a wrong pose (0.1 mm or 0.1 degree off in one component) never stops early and
 * gives the full fit. Tolerance 1e-10 m / 1e-10 rad (the planner's 1e-7 mm/deg scale);
 * targets from random poses up to 10 mm / 9 degrees at the plane and surface levels, a
 * quarter of them with one component held (not free). */
static void test_fit_start_and_near(void **state)
{
    (void)state;
    uint64_t rng = 17;
    const double zero[6] = {0};
    hp_geom G;
    assert_int_equal(hpi_geom_derive(&LAY, &G, NULL), HP_OK);
    for (int lv = HP_LEVEL_PLANE; lv <= HP_LEVEL_SURFACE; ++lv) {
        hp_kin_fit_start st;
        assert_int_equal(hpi_kin_fit_start_at(&LAY, &G, (hp_level)lv, zero, &st), HP_OK);
        int stopped = 0;
        for (int it = 0; it < 100; ++it) {
            double xi[6], ro[HP_MAX_BLADDERS], a[6], b[6], c[6], e[6], ra, rb;
            int fr[6] = {1, 1, 1, 1, 1, 1}, ia, ib, ic;
            kin_rng_pose(&rng, 0.01, 0.16, 0, xi);
            if (it % 4 == 0) {
                fr[it % 6] = 0;
                xi[it % 6] = 0.0;
            }
            assert_int_equal(hp_contact_eval(&LAY, (hp_level)lv, xi, ro, NULL, NULL), HP_OK);
            assert_int_equal(hp_contact_fit(&LAY, (hp_level)lv, ro, fr, zero, a, &ra, &ia), HP_OK);
            assert_int_equal(
                hpi_kin_fit(&LAY, &G, (hp_level)lv, ro, fr, zero, &st, NULL, b, &rb, &ib), HP_OK);
            assert_int_equal(ia, ib);
            assert_memory_equal(a, b, sizeof a);
            assert_true(ra == rb);
            hp_kin_fit_near nr;
            memset(&nr, 0, sizeof nr);
            for (int i = 0; i < 6; ++i) {
                nr.pose[i] = xi[i];
                nr.tol[i] = 1e-10;
            }
            assert_int_equal(
                hpi_kin_fit(&LAY, &G, (hp_level)lv, ro, fr, zero, &st, &nr, c, NULL, &ic), HP_OK);
            stopped += ic < ia;
            for (int i = 0; i < 6; ++i) {
                assert_true(fabs(c[i] - xi[i]) <= 0.5e-10);
                assert_true(fabs(c[i] - a[i]) <= 0.5e-10);
            }
            int k = it % 6;
            if (!fr[k]) k = (k + 1) % 6;
            nr.pose[k] += k < 3 ? 1e-4 : 1e-4 * 3.14159265358979323846 / 0.18;
            assert_int_equal(
                hpi_kin_fit(&LAY, &G, (hp_level)lv, ro, fr, zero, &st, &nr, e, NULL, &ic), HP_OK);
            assert_int_equal(ic, ia);
            assert_memory_equal(e, a, sizeof a);
        }
        /* How often it saved a step: information, not a requirement (it only saves time). */
        print_message("level %d: early stop in %d of 100 fits\n", lv, stopped);
    }
}

/* The fit's certificate (hpi_kin_fit_certified): a fit given the planned pose and its
 * distances as an anchor may stop as soon as the certificate proves where the rest of it
 * ends. Checked against the full fit (run to its end, no expected pose) on four heads
 * (the default ellipsoid, a sphere (translations only), an elongated ellipsoid, and the near-degenerate
 * 90/90.01/90.02 mm ellipsoid whose plane level has a second fit near the nominal pose), at
 * the plane and surface levels, for targets in three bands (0.5 mm/0.3°, 3 mm/2°,
 * 12 mm/8°; a quarter with one component held): the target distances are the planned
 * pose's with a few ulps of noise, as the planner's pressure round trip leaves them.
 * Whenever the certified fit reports a pose within the tolerance of the planned one, the
 * full fit ends within the tolerance too, and vice versa (the planner's verdict is the
 * same); the certificate fires on most fits of the regular heads and is refused wherever
 * the full fit ends elsewhere. Tolerance 1e-10 m and rad, the planner's 1e-7 mm/deg. */
static void test_fit_certificate(void **state)
{
    (void)state;
    hp_head heads[4] = {default_head(), default_head(), default_head(), default_head()};
    heads[1].shape = HP_HEAD_SPHERE;
    heads[1].semi_axes[0] = 0.09;
    heads[2].semi_axes[0] = 0.06;
    heads[2].semi_axes[2] = 0.11;
    heads[3].semi_axes[0] = 0.090;
    heads[3].semi_axes[1] = 0.09001;
    heads[3].semi_axes[2] = 0.09002;
    const double band[3][2] = {{5e-4, 0.3}, {3e-3, 2.0}, {12e-3, 8.0}};
    const double zero[6] = {0};
    double tol[6];
    for (int i = 0; i < 6; ++i) tol[i] = i < 3 ? 1e-10 : 1e-7 * 3.14159265358979323846 / 180.0;
    uint64_t rng = 2026;
    int total_cert = 0, total_elsewhere = 0, total_early = 0;
    for (int c = 0; c < 4; ++c) {
        hp_layout L;
        hp_geom G;
        assert_int_equal(default_layout_on(&L, &heads[c], 0.0), 0);
        assert_int_equal(hp_layout_prepare(&L, NULL), HP_OK);
        assert_int_equal(hpi_geom_derive(&L, &G, NULL), HP_OK);
        for (int lv = HP_LEVEL_PLANE; lv <= HP_LEVEL_SURFACE; ++lv) {
            hp_kin_fit_start st;
            assert_int_equal(hpi_kin_fit_start_at(&L, &G, (hp_level)lv, zero, &st), HP_OK);
            int cert = 0, elsewhere = 0, fits = 0, early = 0;
            for (int it = 0; it < 150; ++it) {
                const double *bd = band[it % 3];
                double xi[6], rho[HP_MAX_BLADDERS], ro[HP_MAX_BLADDERS], xa[6], xb[6], xc[6];
                int fr[6] = {1, 1, 1, 1, 1, 1}, ia, ib, ic;
                kin_rng_pose(&rng, bd[0], bd[1] * 3.14159265358979323846 / 180.0, 0, xi);
                if (it % 4 == 0) {
                    fr[it % 6] = 0;
                    xi[it % 6] = 0.0;
                }
                if (c == 1) /* a sphere's turns about its centre move no distance */
                    for (int i = 3; i < 6; ++i) {
                        fr[i] = 0;
                        xi[i] = 0.0;
                    }
                if (hpi_contact_eval_g(&L, &G, (hp_level)lv, xi, rho, NULL, NULL) != HP_OK)
                    continue;
                for (int k = 0; k < L.n; ++k)
                    ro[k] = rho[k] * (1.0 + 4e-16 * test_rng_uniform(&rng, -1.0, 1.0));
                hp_kin_fit_near nr;
                memset(&nr, 0, sizeof nr);
                for (int i = 0; i < 6; ++i) {
                    nr.pose[i] = xi[i];
                    nr.tol[i] = tol[i];
                }
                /* without the anchor: the fit as before the certificate */
                hp_error ec = hpi_kin_fit(&L, &G, (hp_level)lv, ro, fr, zero, &st, &nr, xc, NULL,
                                          &ic);
                nr.has_anchor = 1;
                memcpy(nr.anchor, xi, sizeof xi);
                memcpy(nr.anchor_rho, rho, sizeof rho);
                /* with the anchor's Jacobian too (the planner's direct chain) on odd targets:
                 * the proof may then hold before the first trial is evaluated */
                double Ja[HP_MAX_BLADDERS * 6];
                nr.anchor_J = it % 2 ? Ja : NULL;
                if (nr.anchor_J)
                    assert_int_equal(hpi_contact_eval_g(&L, &G, (hp_level)lv, xi, NULL, Ja, NULL),
                                     HP_OK);
                hp_error ea = hpi_kin_fit(&L, &G, (hp_level)lv, ro, fr, zero, &st, &nr, xa, NULL,
                                          &ia);
                /* the full fit, to its end */
                hp_error eb = hpi_kin_fit(&L, &G, (hp_level)lv, ro, fr, zero, &st, NULL, xb, NULL,
                                          &ib);
                ++fits;
                /* distances in units of the tolerance */
                double da = ea == HP_OK ? 0.0 : INFINITY, db = eb == HP_OK ? 0.0 : INFINITY;
                for (int i = 0; i < 6; ++i) {
                    da = fmax(da, fabs(xa[i] - xi[i]) / tol[i]);
                    db = fmax(db, fabs(xb[i] - xi[i]) / tol[i]);
                }
                /* a certified fit reports the anchor itself, bit for bit (an arrived one its
                 * own iterate, and with ia <= ic either way) */
                int certified = ea == HP_OK && memcmp(xa, xi, sizeof xa) == 0;
                assert_true(ea != HP_OK || ec != HP_OK || ia <= ic);
                cert += certified;
                early += certified && ia == 1; /* before any evaluation */
                elsewhere += !(db <= 1.0);
                if ((da <= 1.0) != (db <= 1.0) || (certified && !(db <= 0.5)))
                    print_error("head %d level %d target %d: certified %d, anchor fit %.3e, "
                                "full fit %.3e tolerances from the planned pose\n",
                                c, lv, it, certified, da, db);
                assert_int_equal(da <= 1.0, db <= 1.0);
                if (certified) assert_true(db <= 0.5);
                /* Expecting a pose 0.3 tolerances off in one free component (the fit still
                 * ends at the anchor): within the tolerance, yet beyond the quarter the
                 * certificate promises, so it must not fire. */
                int k = it % 6;
                while (!fr[k]) k = (k + 1) % 6;
                nr.pose[k] += 0.3 * tol[k];
                double xo[6];
                hpi_kin_fit(&L, &G, (hp_level)lv, ro, fr, zero, &st, &nr, xo, NULL, NULL);
                assert_true(memcmp(xo, xi, sizeof xo) != 0);
            }
            print_message("head %d %-7s: certified %d of %d fits (%d before evaluating a "
                          "step); full fit elsewhere in %d\n",
                          c, hp_level_name((hp_level)lv), cert, fits, early, elsewhere);
            if (c < 3) assert_true(cert >= fits / 2);
            if (c < 2)
                assert_true(early > 0); /* the elongated head's curvature bound is
                                                   too large for it */
            total_early += early;
            total_cert += cert;
            total_elsewhere += elsewhere;
        }
    }
    print_message("certified %d fits (%d before evaluating a step); %d full fits ended away "
                  "from the planned pose\n",
                  total_cert, total_early, total_elsewhere);
}

/* Column norms of J (n×nf), the fit's Marquardt scales. */
static void col_norms(int n, int nf, const double *J, double *D)
{
    for (int j = 0; j < nf; ++j) {
        double s = 0;
        for (int i = 0; i < n; ++i) s += J[i * nf + j] * J[i * nf + j];
        D[j] = sqrt(s);
    }
}

/* Largest |D_j·(a_j − b_j)| over max_j |D_j·b_j|: a step's error in the scaled unknowns
 * (the effect on the radii), relative to the step. */
static double scaled_err(int nf, const double *D, const double *a, const double *b)
{
    double e = 0, m = 0;
    for (int j = 0; j < nf; ++j) {
        e = fmax(e, fabs(D[j] * (a[j] - b[j])));
        m = fmax(m, fabs(D[j] * b[j]));
    }
    return e / m;
}

/* The condition bound the normal equations rely on is an upper bound: for random SPD
 * matrices (unit diagonal, 1..6, condition up to ~1e9) n·‖L⁻¹‖_F² >= λmax/λmin from an
 * independent symmetric eigen-decomposition (Eigen), to 1e-6 relative (the eigenvalues'
 * rounding, eps·λmax/λmin <= 1e-7). A 2×2 case by hand: A = [[4, 2], [2, 5]], L = [[2, 0],
 * [1, 2]], L⁻¹ = [[1/2, 0], [−1/4, 1/2]], ‖L⁻¹‖_F² = 1/4 + 1/16 + 1/4 = 9/16. */
static void test_cholesky_condition_bound(void **state)
{
    (void)state;
    double A2[4] = {4, 2, 2, 5}, L2[4];
    assert_int_equal(hpi_cholesky(A2, 2, 2, 0.0, L2, 2), 1);
    assert_true(hpi_cholesky_inv_frob2(L2, 2, 2) == 9.0 / 16.0);
    uint64_t rng = 23;
    for (int it = 0; it < 300; ++it) {
        int n = 1 + it % 6;
        double J[8 * 6], S[36] = {0}, L[36], lam[6], V[36];
        double tilt = pow(10.0, -test_rng_uniform(&rng, 0, 4.5)); /* near-collinear pair */
        for (int i = 0; i < 8; ++i)
            for (int j = 0; j < n; ++j) J[i * n + j] = test_rng_normal(&rng);
        if (n > 1)
            for (int i = 0; i < 8; ++i) J[i * n + n - 1] = J[i * n] + tilt * J[i * n + n - 1];
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k)
                for (int i = 0; i < 8; ++i) S[j * 6 + k] += J[i * n + j] * J[i * n + k];
        double d[6];
        for (int j = 0; j < n; ++j) d[j] = 1.0 / sqrt(S[j * 6 + j]);
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) S[j * 6 + k] *= d[j] * d[k];
        for (int j = 0; j < n; ++j) S[j * 6 + j] = 1.0;
        assert_int_equal(hpi_cholesky(S, 6, n, 0.0, L, 6), 1);
        double bound = n * hpi_cholesky_inv_frob2(L, 6, n);
        /* eigenvalues of the n×n block: pad to 6×6 with a unit diagonal (eigenvalue 1 lies
         * inside [λmin, λmax] of a unit-diagonal matrix, so it changes neither) */
        double P[36] = {0};
        for (int j = 0; j < 6; ++j)
            for (int k = 0; k < 6; ++k) P[j * 6 + k] = j < n && k < n ? S[j * 6 + k] : j == k;
        assert_int_equal(hpi_kin_symeig6(P, lam, V), 0);
        assert_true(lam[0] > 0);
        assert_true(bound >= lam[5] / lam[0] * (1 - 1e-6));
    }
}

/* The fit's two damped least-squares solvers against Eigen's column-pivoting QR
 * (hpi_kin_damped_lstsq), an independent factorisation, on seeded random 8×nf Jacobians
 * with the fit's column-norm scales and damping 0, 1e-3, 1, 1e3:
 * - well conditioned (scaled condition of J ~ 1..30): the normal equations are accepted
 *   and agree to 1e-9 of the step in the scaled unknowns (the bound nf·eps·1e6 = 7e-10 of
 *   HP_KIN_NORMAL_MAX_COND, for the worst accepted case), the QR to 1e-12 (a few ulps times
 *   the condition; measured below);
 * - two columns collinear to 1e-7 (scaled condition of J ~1e7, of the normal matrix 1e14)
 *   with a consistent right-hand side, undamped: the normal equations refuse, and the QR
 *   (what the fit then uses) agrees with Eigen to 1e-6 of the step (eps·1e7 = 2e-9, times
 *   the constants of a collinear pair's two large, cancelling components);
 * - the default layout's surface-level Jacobians at random poses (the planner's check):
 *   accepted, and equal to the QR step to 1e-12 (measured 2e-14). */
static void test_damped_solvers(void **state)
{
    (void)state;
    uint64_t rng = 29;
    const double lams[4] = {0.0, 1e-3, 1.0, 1e3};
    double worst_n = 0, worst_q = 0;
    for (int it = 0; it < 200; ++it) {
        int nf = 1 + it % 6, n = 8;
        double J[8 * 6], r[8], D[6], a[6], b[6], c[6];
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < nf; ++j) J[i * nf + j] = test_rng_normal(&rng) * (1.0 + j);
            r[i] = test_rng_normal(&rng);
        }
        col_norms(n, nf, J, D);
        double lambda = lams[it % 4];
        assert_int_equal(hpi_kin_damped_normal(n, nf, J, r, D, lambda, a), 0);
        assert_int_equal(hpi_kin_damped_qr(n, nf, J, r, D, lambda, b), 0);
        assert_int_equal(hpi_kin_damped_lstsq(n, nf, J, r, D, lambda, c), 0);
        worst_n = fmax(worst_n, scaled_err(nf, D, a, c));
        worst_q = fmax(worst_q, scaled_err(nf, D, b, c));
    }
    assert_true(worst_n <= 1e-9);
    assert_true(worst_q <= 1e-12);
    double worst_ill = 0;
    for (int it = 0; it < 50; ++it) {
        int nf = 6, n = 8;
        double J[8 * 6], r[8], D[6], x[6], a[6], b[6], c[6];
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < nf; ++j) J[i * nf + j] = test_rng_normal(&rng);
        for (int i = 0; i < n; ++i) J[i * nf + 5] = J[i * nf + 4] + 1e-7 * J[i * nf + 5];
        for (int j = 0; j < nf; ++j) x[j] = test_rng_normal(&rng);
        for (int i = 0; i < n; ++i) {
            r[i] = 0;
            for (int j = 0; j < nf; ++j) r[i] -= J[i * nf + j] * x[j];
        }
        col_norms(n, nf, J, D);
        assert_int_equal(hpi_kin_damped_normal(n, nf, J, r, D, 0.0, a), -1);
        assert_int_equal(hpi_kin_damped_qr(n, nf, J, r, D, 0.0, b), 0);
        assert_int_equal(hpi_kin_damped_lstsq(n, nf, J, r, D, 0.0, c), 0);
        worst_ill = fmax(worst_ill, scaled_err(nf, D, b, c));
    }
    assert_true(worst_ill <= 1e-6);
    hp_geom G;
    assert_int_equal(hpi_geom_derive(&LAY, &G, NULL), HP_OK);
    double worst_lay = 0;
    for (int it = 0; it < 100; ++it) {
        double xi[6], rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6], r[HP_MAX_BLADDERS], D[6];
        double a[6], b[6];
        kin_rng_pose(&rng, 0.01, 0.16, 0, xi);
        assert_int_equal(hp_contact_eval(&LAY, HP_LEVEL_SURFACE, xi, rho, J, NULL), HP_OK);
        for (int k = 0; k < LAY.n; ++k) r[k] = 1e-4 * test_rng_normal(&rng);
        col_norms(LAY.n, 6, J, D);
        double lambda = lams[it % 4];
        assert_int_equal(hpi_kin_damped_normal(LAY.n, 6, J, r, D, lambda, a), 0);
        assert_int_equal(hpi_kin_damped_qr(LAY.n, 6, J, r, D, lambda, b), 0);
        worst_lay = fmax(worst_lay, scaled_err(6, D, a, b));
    }
    assert_true(worst_lay <= 1e-12);
    print_message("damped steps vs Eigen: normal %.2e, QR %.2e, QR ill-conditioned %.2e; "
                  "default layout normal vs QR %.2e\n",
                  worst_n, worst_q, worst_ill, worst_lay);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_noisy),
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_fit_start_and_near),
        cmocka_unit_test(test_fit_certificate),
        cmocka_unit_test(test_cholesky_condition_bound),
        cmocka_unit_test(test_damped_solvers),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
