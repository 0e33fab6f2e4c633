/* The contact law's one home (kinematics/contact_law.c): its value against an independent
 * evaluation of F = P·pi·(2·ro·delta − delta²) in __float128, its first and second
 * derivatives against central differences, its work W against F (dW/drho = −F, W = 0 at
 * touch), and the load model's law (hpi_load_law) reading the same numbers. The fitted law
 * (hpi_claw_fem): its derivatives against Richardson-extrapolated central differences, its
 * work, its domain, and its force against every converged row of the finite-element
 * sweep (fem/tables/sweep.csv) within the error docs/accuracy.md states; its closed forms
 * (value, derivatives, work, dF/drho) against the forward-mode reference of
 * tests/support/claw_ref.h on a seeded sweep of its whole domain and its edges. */
#include "support/test_util.h"
#include "kinematics/contact_law.h"
#include "kinematics/contact_law_fit.h"
#include "kinematics/load_internal.h"
#include "support/claw_ref.h"
#include "support/default_layout.h"
#include "support/rng.h"

#include <quadmath.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
        hpi_claw_cap(P, ro, rho, &c);
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
    hpi_claw_cap(xp[0], xp[1], xp[2], &a);
    hpi_claw_cap(xm[0], xm[1], xm[2], &b);
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
        hpi_claw_cap(x[0], x[1], x[2], &c);
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
    hpi_claw_cap(5e3, 0.03, 0.03, &t); /* at touch: no force, no work */
    assert_true(t.F == 0.0 && t.W == 0.0);
}

/* A load model on the default layout (ellipsoid head), its law set by law. */
static hp_load_model cap_model;
static void model_on(hp_load_model *M, hp_claw_law law)
{
    hp_layout L;
    hp_load_spec spec;
    assert_int_equal(default_layout(&L), 0);
    hp_load_spec_default(&L.head, &spec);
    assert_int_equal(hpi_load_model_setup(M, &L, &spec, HP_LEVEL_SURFACE, NULL), HP_OK);
    M->law = law;
}

/* The load model's law is the same function (plus the contact switch and the chain rule
 * through ro(P)): bit for bit where the bladder touches. */
static void test_load_law_reads_it(void **st)
{
    (void)st;
    model_on(&cap_model, HP_CLAW_LAW_CAP);
    for (int i = 0; i < 210; ++i) {
        double P, ro, rho, dro = 1e-6 * (1 + i % 3);
        state(i, &P, &ro, &rho);
        hp_claw c;
        hp_load_force f;
        hpi_claw_cap(P, ro, rho, &c);
        hpi_load_law(&cap_model, 0, P, ro, dro, rho, 0, &f);
        assert_true(f.F == c.F);
        assert_true(f.dF_drho == c.d[HP_CLAW_RHO]);
        assert_true(f.dF_dro == c.d[HP_CLAW_RO]);
        assert_true(f.dF_dP == c.d[HP_CLAW_P] + c.d[HP_CLAW_RO] * dro);
        assert_true(f.E == c.W);
    }
}

/* The fitted law at a spread of states inside its domain (the box of the tables). */
static void fem_state(int i, hp_claw_bladder *b, double x[3])
{
    double u[4] = {(double)(i % 5) / 4.0, (double)(i % 7) / 6.0, (double)(i % 3) / 2.0,
                   (double)(i % 11) / 10.0};
    double ro = 0.033;
    b->C1 = 1.1e4;
    b->C2 = b->C1 * (i % 2 ? HP_CLAW_FIT_CMAX : HP_CLAW_FIT_CMIN);
    b->wall = ro *
              (HP_CLAW_FIT_WMIN + (HP_CLAW_FIT_WMAX - HP_CLAW_FIT_WMIN) * (0.01 + 0.98 * u[0]));
    b->curv = HP_CLAW_FIT_KMAX * 0.99 * u[2] / ro;
    x[0] = b->C1 *
           (HP_CLAW_FIT_PMIN + (HP_CLAW_FIT_PMAX - HP_CLAW_FIT_PMIN) * (0.01 + 0.98 * u[1]));
    x[1] = ro;
    x[2] = ro * (1.0 - (0.005 + (HP_CLAW_FIT_DMAX - 0.01) * u[3]));
}

static void fem_at(const hp_claw_bladder *b, const double x[3], hp_claw *c)
{
    hpi_claw_fem(b, x[0], x[1], x[2], c);
}

/* Richardson-extrapolated central difference of the law's F (which = 0), d[k] (which = 1+k)
 * or W (which = 4) along variable j: error O(h⁴) ~ 1e-13 relative at h = 1e-3 of the
 * scale, rounding ~ eps/h ~ 1e-13: 1e-8 relative is a wide margin. */
typedef void (*law_fn)(hp_claw_law, const hp_claw_bladder *, double, double, double, hp_claw *);

static double rich_of(law_fn eval, hp_claw_law law, const hp_claw_bladder *b, const double x[3],
                      int j, double h, int which)
{
    double v[4];
    const double hs[4] = {h, -h, h / 2, -h / 2};
    for (int m = 0; m < 4; ++m) {
        double y[3] = {x[0], x[1], x[2]};
        y[j] += hs[m];
        hp_claw c;
        eval(law, b, y[0], y[1], y[2], &c);
        v[m] = which == 0 ? c.F : which == 4 ? c.W : c.d[which - 1];
    }
    double D1 = (v[0] - v[1]) / (2 * h), D2 = (v[2] - v[3]) / h;
    return (4 * D2 - D1) / 3;
}

static double rich(const hp_claw_bladder *b, const double x[3], int j, double h, int which)
{
    return rich_of(hpi_claw_eval, HP_CLAW_LAW_FEM, b, x, j, h, which);
}

/* The law's derivatives at x against Richardson-extrapolated central differences (tolerances
 * as rich_of says), and its work: dW/drho = −F. */
static void check_fem_derivatives(const hp_claw_bladder *b, const double x[3])
{
    assert_int_equal(hpi_claw_fem_domain(b, x[0], x[1], x[2]), HP_CLAW_IN);
    hp_claw c;
    fem_at(b, x, &c);
    const double scale[3] = {x[0], x[1], x[1]};
    for (int j = 0; j < 3; ++j) {
        double h = 1e-3 * scale[j];
        double fs = fabs(c.F) / scale[j];
        hp_assert_close(c.d[j], rich(b, x, j, h, 0), 1e-8, 1e-9 * fs);
        for (int k = 0; k < 3; ++k) {
            hp_assert_close(c.d2[j][k], rich(b, x, k, 1e-3 * scale[k], 1 + j), 1e-7,
                            1e-8 * fs / scale[k]);
            assert_true(c.d2[j][k] == c.d2[k][j]);
        }
    }
    /* W is the integral of F over the contact distance: dW/drho = −F */
    hp_assert_close(rich(b, x, HP_CLAW_RHO, 1e-3 * x[1], 4), -c.F, 1e-8, 0.0);
}

static void test_fem_derivatives(void **st)
{
    (void)st;
    for (int i = 0; i < 120; ++i) {
        hp_claw_bladder b;
        double x[3];
        fem_state(i, &b, x);
        check_fem_derivatives(&b, x);
    }
    hp_claw t;
    hp_claw_bladder b0;
    double x0[3];
    fem_state(0, &b0, x0);
    hpi_claw_fem(&b0, x0[0], x0[1], x0[1], &t);
    assert_true(t.F == 0.0 && t.W == 0.0);
}

/* The fitted law's shape where a planner relies on it: no force without pressure (P = 0
 * gives exactly 0 with finite derivatives, as the load model's contact switch has it, and
 * the force is continuous there: below 1e-3 of its value at the domain's smallest pressure
 * when P is 1e-6 of C1), positive and rising with the indentation (dF/drho < 0) and with the
 * pressure at a fixed radius (dF/dP > 0) over the domain, and finite (no division by P)
 * for the negative pressures the scenes allow, where the domain refuses it by name. */
static void test_fem_shape(void **st)
{
    (void)st;
    for (int i = 0; i < 120; ++i) {
        hp_claw_bladder b;
        double x[3];
        fem_state(i, &b, x);
        hp_claw c, z, t, lo;
        hpi_claw_fem(&b, x[0], x[1], x[2], &c);
        assert_true(c.F > 0.0 && c.d[HP_CLAW_RHO] < 0.0 && c.d[HP_CLAW_P] > 0.0);
        hpi_claw_fem(&b, 0.0, x[1], x[2], &z);
        assert_true(z.F == 0.0 && z.W == 0.0);
        for (int j = 0; j < 3; ++j) {
            assert_true(isfinite(z.d[j]));
            for (int k = 0; k < 3; ++k) assert_true(isfinite(z.d2[j][k]));
        }
        hpi_claw_fem(&b, 1e-6 * b.C1, x[1], x[2], &t);
        hpi_claw_fem(&b, HP_CLAW_FIT_PMIN * b.C1, x[1], x[2], &lo);
        assert_true(t.F >= 0.0 && t.F < 1e-3 * lo.F);
        for (double P = -5e3; P < 0.0; P += 1e3) {
            hpi_claw_fem(&b, P, x[1], x[2], &t);
            assert_true(isfinite(t.F) && isfinite(t.d[HP_CLAW_P]) && isfinite(t.W));
            assert_int_equal(hpi_claw_fem_domain(&b, P, x[1], x[2]), HP_CLAW_PRESSURE);
        }
        assert_int_equal(hpi_claw_fem_domain(&b, 0.0, x[1], x[2]), HP_CLAW_PRESSURE);
    }
}

/* The tables cover the load scenes' low pressures on their 3 mm shell (C1 11 kPa): 0.5 kPa
 * (P/C1 0.045) is inside the domain, and so is the wall/ro of the shell inflated to 6 kPa
 * (3/37.4 mm, 0.080), the stretch 1.33 just above the default stretch_max 1.3. */
static void test_fem_covers_scenes(void **st)
{
    (void)st;
    assert_true(HP_CLAW_FIT_PMIN <= 500.0 / 1.1e4);
    assert_true(HP_CLAW_FIT_WMIN <= 3.0 / 37.4);
}

/* hpi_claw_eval_drho is the law's dF/drho with its own derivatives: its value and gradient
 * equal the law's d[rho] and d2[.][rho] (same forward derivatives: to rounding, 1e-12), its
 * Hessian the Richardson-extrapolated central differences of its gradient (1e-7, as above);
 * under both laws. */
static void test_drho(void **st)
{
    (void)st;
    for (int i = 0; i < 60; ++i) {
        hp_claw_bladder b;
        double x[3];
        fem_state(i, &b, x);
        for (int law = HP_CLAW_LAW_CAP; law <= HP_CLAW_LAW_FEM; ++law) {
            hp_claw c, r;
            hpi_claw_eval((hp_claw_law)law, &b, x[0], x[1], x[2], &c);
            hpi_claw_eval_drho((hp_claw_law)law, &b, x[0], x[1], x[2], &r);
            double fs = fabs(c.d[HP_CLAW_RHO]);
            hp_assert_close(r.F, c.d[HP_CLAW_RHO], 1e-12, 0.0);
            const double scale[3] = {x[0], x[1], x[1]};
            for (int j = 0; j < 3; ++j) {
                hp_assert_close(r.d[j], c.d2[j][HP_CLAW_RHO], 1e-12, 1e-12 * fs / scale[j]);
                for (int k = 0; k < 3; ++k)
                    hp_assert_close(r.d2[j][k],
                                    rich_of(hpi_claw_eval_drho, (hp_claw_law)law, &b, x, k,
                                            1e-3 * scale[k], 1 + j),
                                    1e-7, 1e-8 * fs / (scale[j] * scale[k]));
            }
        }
    }
}

static void test_fem_domain(void **st)
{
    (void)st;
    hp_claw_bladder b0, *b = &b0;
    double x0[3];
    fem_state(0, b, x0);
    double ro = x0[1];
    assert_int_equal(hpi_claw_fem_domain(b, x0[0], ro, ro * 0.9), HP_CLAW_IN);
    assert_int_equal(hpi_claw_fem_domain(b, x0[0], ro, ro * 0.5), HP_CLAW_INDENT);
    assert_int_equal(hpi_claw_fem_domain(b, x0[0], ro, NAN), HP_CLAW_INDENT);
    assert_int_equal(hpi_claw_fem_domain(b, x0[0], ro, ro * 1.01), HP_CLAW_INDENT);
    hp_claw_bladder w = *b;
    w.wall = 0.02;
    assert_int_equal(hpi_claw_fem_domain(&w, x0[0], ro, ro * 0.9), HP_CLAW_WALL);
    assert_int_equal(hpi_claw_fem_domain(b, 5e4, ro, ro * 0.9), HP_CLAW_PRESSURE);
    w = *b;
    w.C2 = 1e5;
    assert_int_equal(hpi_claw_fem_domain(&w, x0[0], ro, ro * 0.9), HP_CLAW_MODULI);
    w = *b;
    w.curv = 1.0 / 0.02;
    assert_int_equal(hpi_claw_fem_domain(&w, x0[0], ro, ro * 0.9), HP_CLAW_CURVATURE);
    w.curv = -1.0 / 0.09; /* a concave head is outside the tables */
    assert_int_equal(hpi_claw_fem_domain(&w, x0[0], ro, ro * 0.9), HP_CLAW_CURVATURE);
    assert_string_equal(hpi_claw_domain_name(HP_CLAW_CURVATURE), "curvature");
}

/* Column index of name in a CSV header line. */
static int column(char *header, const char *name)
{
    int i = 0;
    for (char *t = strtok(header, ",\n"); t; t = strtok(NULL, ",\n"), ++i)
        if (strcmp(t, name) == 0) return i;
    return -1;
}

static const char *field(const char *line, int col, char *buf, size_t n)
{
    const char *p = line;
    for (int i = 0; i < col && p; ++i) {
        p = strchr(p, ',');
        if (p) ++p;
    }
    if (!p) return "";
    size_t k = strcspn(p, ",\n");
    if (k >= n) k = n - 1;
    memcpy(buf, p, k);
    buf[k] = 0;
    return buf;
}

/* Every converged row of the committed sweep, against the law in C (independent of the
 * fitting script's own evaluation): worst relative error in force at most the bound
 * docs/accuracy.md states (HP_TEST_LAW_MAX_ERR). */
#define HP_TEST_LAW_MAX_ERR 0.05
static void test_fem_against_tables(void **st)
{
    (void)st;
    FILE *f = fopen(HP_SOURCE_DIR "/fem/tables/sweep.csv", "r");
    assert_non_null(f);
    char line[1024], header[1024] = "";
    int n = 0, outside = 0;
    double worst = 0.0;
    enum { NCOL = 9 };
    static const char *const names[NCOL] = {
        "Ri_mm",          "Ro_mm", "C1_pa",         "C2_pa",
        "P_pa",           "ro_mm", "delta_over_ro", "ro_over_head_radius",
        "F_over_P_pi_ro2"};
    int col[NCOL + 1];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') continue;
        if (!header[0]) {
            for (int i = 0; i < NCOL; ++i) {
                strcpy(header, line);
                col[i] = column(header, names[i]);
                assert_true(col[i] >= 0);
            }
            strcpy(header, line);
            col[NCOL] = column(header, "note");
            continue;
        }
        char buf[64];
        if (field(line, col[NCOL], buf, sizeof buf)[0]) continue; /* did not converge */
        double v[NCOL];
        for (int i = 0; i < NCOL; ++i) v[i] = atof(field(line, col[i], buf, sizeof buf));
        double ro = v[5] * 1e-3, rho = ro * (1.0 - v[6]);
        hp_claw_bladder b = {v[2], v[3], (v[1] - v[0]) * 1e-3, v[7] / ro};
        /* a case converged at too few indentations is outside the fit and its domain
         * (fem/fit_law.py, MIN_ROWS): the domain check must say so */
        if (hpi_claw_fem_domain(&b, v[4], ro, rho) != HP_CLAW_IN) {
            ++outside;
            continue;
        }
        hp_claw c;
        hpi_claw_fem(&b, v[4], ro, rho, &c);
        double g = c.F / (v[4] * 3.14159265358979323846 * ro * ro);
        double e = fabs(g / v[8] - 1.0);
        if (e > worst) worst = e;
        ++n;
    }
    fclose(f);
    print_message("fitted law against %d FEM rows inside its domain (%d outside): worst "
                  "relative error %.2f %%\n",
                  n, outside, 100 * worst);
    assert_true(n >= 30 && outside <= 2);
    assert_true(worst <= HP_TEST_LAW_MAX_ERR);
}

/* What the fitted law needs from a bladder and the head: C1, C2 copied, the wall Ro − Ri,
 * and the head's mean curvature at the contact point, against closed forms: a sphere's
 * 1/R everywhere, an ellipsoid's (a/b² + a/c²)/2 at (a, 0, 0) and (b/a² + b/c²)/2 at
 * (0, b, 0) (the principal curvatures at an axis end are the axis over the others²). */
static void test_bladder_of(void **st)
{
    (void)st;
    hp_iab iab = {0.05, 0.0545, 110e3, 220e3};
    hp_claw_bladder b;
    const double sph[3] = {0.09, 0.09, 0.09}, ps[3] = {0.0, 0.09 * 0.6, 0.09 * 0.8};
    hpi_claw_bladder_of(&iab, sph, ps, &b);
    assert_true(b.C1 == 110e3 && b.C2 == 220e3);
    assert_true(fabs(b.wall - 0.0045) <= 1e-15);
    assert_true(fabs(b.curv - 1.0 / 0.09) <= 1e-12 / 0.09);
    const double ax[3] = {0.0775, 0.115, 0.0975}, pole[3] = {0.0775, 0, 0}, eq[3] = {0, 0.115, 0};
    hpi_claw_bladder_of(&iab, ax, pole, &b);
    double k = 0.5 * (ax[0] / (ax[1] * ax[1]) + ax[0] / (ax[2] * ax[2]));
    assert_true(fabs(b.curv - k) <= 1e-12 * k);
    hpi_claw_bladder_of(&iab, ax, eq, &b);
    k = 0.5 * (ax[1] / (ax[0] * ax[0]) + ax[1] / (ax[2] * ax[2]));
    assert_true(fabs(b.curv - k) <= 1e-12 * k);
}

/* The load model's law under the fitted law reads hpi_claw_fem with the model's own
 * bladder (moduli, wall, the head's curvature at the nominal contact): bit for bit. */
static void test_load_law_fem(void **st)
{
    (void)st;
    static hp_load_model M;
    model_on(&M, HP_CLAW_LAW_FEM);
    for (int k = 0; k < M.layout.n; ++k) {
        hp_claw_bladder b;
        hpi_claw_bladder_of(&M.layout.bladders[k].iab, M.geom.head.semi_axes, M.geom.contact[k],
                            &b);
        assert_true(b.curv > 0);
        double ro = 0.06, rho = 0.056, P = 20e3, dro = 1e-7;
        hp_claw c;
        hp_load_force f;
        hpi_claw_fem(&b, P, ro, rho, &c);
        hpi_load_law(&M, k, P, ro, dro, rho, 0, &f);
        assert_true(f.F == c.F);
        assert_true(f.dF_drho == c.d[HP_CLAW_RHO]);
        assert_true(f.dF_dP == c.d[HP_CLAW_P] + c.d[HP_CLAW_RO] * dro);
        assert_true(f.E == c.W);
    }
}

/* Outside the fitted law's domain the load model refuses by name: the bladder and the
 * group ("indent" past the tables' largest indentation); inside it says nothing. The state
 * is inside the tables' box: wall/ro = 3/33 in [0.085, 0.098], P/C1 = 0.3, d = 0.1. */
static void test_load_domain_named(void **st)
{
    (void)st;
    static hp_load_model M;
    model_on(&M, HP_CLAW_LAW_FEM);
    double ro = M.layout.bladders[2].iab.Ro * 1.1, P = 0.3 * M.layout.bladders[2].iab.C1;
    hp_diag d;
    memset(&d, 0, sizeof d);
    assert_int_equal(hpi_load_claw_check(&M, 2, P, ro, ro * 0.9, &d), HP_OK);
    assert_int_equal(hpi_load_claw_check(&M, 2, P, ro, ro * 0.5, &d), HP_ERR_INVALID);
    assert_non_null(strstr(d.text, M.layout.bladders[2].name));
    assert_non_null(strstr(d.text, "indent"));
    /* the cap law has no fitted domain: nothing to refuse */
    M.law = HP_CLAW_LAW_CAP;
    assert_int_equal(hpi_load_claw_check(&M, 2, P, ro, ro * 0.5, &d), HP_OK);
}

/* The cheaper evaluations (hpi_claw_eval_to: the value, or also the gradient, or also the
 * Hessian; W only with HP_CLAW_WORK) give the same bits as the full one for what they
 * compute, and NaN for what they do not (so a caller reading a part it did not ask for fails
 * loudly), under both laws, on a grid of the fitted law's domain with its edges: 5 points in
 * each of P/C1, wall/ro, C2/C1, ro/Rh and delta/ro. Bit equality, not a tolerance: the parts
 * are the same operations in the same order, only what is not asked for is skipped. */
static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

static void test_eval_orders_same_bits(void **st)
{
    (void)st;
    const double ro = 0.0334;
    int n = 0;
    for (int i = 0; i < 5 * 5 * 5 * 5 * 5; ++i) {
        double u[5];
        for (int m = 0, r = i; m < 5; ++m, r /= 5) u[m] = (double)(r % 5) / 4.0;
        hp_claw_bladder b;
        b.C1 = 1.1e4;
        b.C2 = b.C1 * (HP_CLAW_FIT_CMIN + (HP_CLAW_FIT_CMAX - HP_CLAW_FIT_CMIN) * u[0]);
        b.wall = ro * (HP_CLAW_FIT_WMIN + (HP_CLAW_FIT_WMAX - HP_CLAW_FIT_WMIN) * u[1]);
        b.curv = HP_CLAW_FIT_KMAX * u[2] / ro;
        double P = b.C1 * (HP_CLAW_FIT_PMIN + (HP_CLAW_FIT_PMAX - HP_CLAW_FIT_PMIN) * u[3]);
        double rho = ro * (1.0 - HP_CLAW_FIT_DMAX * u[4]);
        assert_int_equal(hpi_claw_fem_domain(&b, P, ro, rho), HP_CLAW_IN);
        for (int law = HP_CLAW_LAW_CAP; law <= HP_CLAW_LAW_FEM; ++law) {
            hp_claw full;
            hpi_claw_eval((hp_claw_law)law, &b, P, ro, rho, &full);
            /* o = 3 (HP_CLAW_GRADIENT | HP_CLAW_HESSIAN, an easy caller's slip) means the
             * Hessian: the highest order named, never an order past it. */
            for (int ow = 0; ow < 8; ++ow) {
                int asked = ow % 4, work = ow >= 4;
                int o = asked > HP_CLAW_HESSIAN ? HP_CLAW_HESSIAN : asked;
                hp_claw c;
                hpi_claw_eval_to((hp_claw_law)law, &b, P, ro, rho,
                                 (hp_claw_order)(asked | (work ? HP_CLAW_WORK : 0)), &c);
                assert_true(same_bits(c.F, full.F));
                assert_true(work ? same_bits(c.W, full.W) : isnan(c.W));
                for (int j = 0; j < 3; ++j) {
                    assert_true(o >= HP_CLAW_GRADIENT ? same_bits(c.d[j], full.d[j])
                                                      : isnan(c.d[j]));
                    for (int k = 0; k < 3; ++k)
                        assert_true(o >= HP_CLAW_HESSIAN ? same_bits(c.d2[j][k], full.d2[j][k])
                                                         : isnan(c.d2[j][k]));
                }
                ++n;
            }
        }
    }
    assert_int_equal(n, 3125 * 2 * 8);
}

/* got against the reference want, whose terms add up in magnitude to mag: both evaluations
 * take about 40 rounded steps, each off by at most an ulp of a partial sum no larger than
 * mag, so each is within ~40·eps·mag (1e-14·mag) of the exact value; 1e-13·mag leaves a
 * factor 4 above the two together, and is still 1e-13 of the largest term. */
static void ref_close(double got, double want, double mag)
{
    hp_assert_close(got, want, 0.0, 1e-13 * mag);
}

/* The closed forms of hpi_claw_fem (F, gradient, Hessian, W) and hpi_claw_eval_drho (dF/drho
 * and its gradient and Hessian) against the reference at one state. */
static void check_against_ref(const hp_claw_bladder *b, double P, double ro, double rho)
{
    hp_claw c, r, m;
    hpi_claw_fem(b, P, ro, rho, &c);
    claw_ref_fem(b, P, ro, rho, CREF_F, 0, &r);
    claw_ref_fem(b, P, ro, rho, CREF_F, 1, &m);
    ref_close(c.F, r.F, m.F);
    ref_close(c.W, r.W, m.W);
    for (int i = 0; i < 3; ++i) {
        ref_close(c.d[i], r.d[i], m.d[i]);
        for (int j = 0; j < 3; ++j) ref_close(c.d2[i][j], r.d2[i][j], m.d2[i][j]);
    }
    hpi_claw_eval_drho(HP_CLAW_LAW_FEM, b, P, ro, rho, &c);
    claw_ref_fem(b, P, ro, rho, CREF_DRHO, 0, &r);
    claw_ref_fem(b, P, ro, rho, CREF_DRHO, 1, &m);
    ref_close(c.F, r.F, m.F);
    assert_true(c.W == 0.0);
    for (int i = 0; i < 3; ++i) {
        ref_close(c.d[i], r.d[i], m.d[i]);
        for (int j = 0; j < 3; ++j) ref_close(c.d2[i][j], r.d2[i][j], m.d2[i][j]);
    }
}

/* A state from u in [0, 1]^5 spanning the domain: C2/C1, wall/ro, ro/Rh, P/C1, delta/ro. */
static void domain_state(const double u[5], double C1, double ro, hp_claw_bladder *b, double *P,
                         double *rho)
{
    b->C1 = C1;
    b->C2 = C1 * (HP_CLAW_FIT_CMIN + (HP_CLAW_FIT_CMAX - HP_CLAW_FIT_CMIN) * u[0]);
    b->wall = ro * (HP_CLAW_FIT_WMIN + (HP_CLAW_FIT_WMAX - HP_CLAW_FIT_WMIN) * u[1]);
    b->curv = HP_CLAW_FIT_KMAX * u[2] / ro;
    *P = C1 * (HP_CLAW_FIT_PMIN + (HP_CLAW_FIT_PMAX - HP_CLAW_FIT_PMIN) * u[3]);
    *rho = ro * (1.0 - HP_CLAW_FIT_DMAX * u[4]);
}

/* The closed forms against the reference over the whole domain: 4000 seeded states (C1 in
 * 5..200 kPa, ro in 20..60 mm and every dimensionless group over its fitted range), the 32
 * corners of the domain, and at each corner the edges the load model reaches: touch (d = 0),
 * no pressure (P = 0) and a vanishing one (1e-9 of C1). On 200 of the seeded states, the
 * derivatives against central differences too (check_fem_derivatives). */
static void test_fem_closed_forms(void **st)
{
    (void)st;
    uint64_t seed = 31;
    for (int i = 0; i < 4000; ++i) {
        double u[5];
        for (int m = 0; m < 5; ++m) u[m] = test_rng_unit(&seed);
        double C1 = test_rng_uniform(&seed, 5e3, 2e5), ro = test_rng_uniform(&seed, 0.02, 0.06);
        hp_claw_bladder b;
        double P, rho;
        domain_state(u, C1, ro, &b, &P, &rho);
        check_against_ref(&b, P, ro, rho);
        if (i < 200) {
            const double x[3] = {P, ro, rho};
            check_fem_derivatives(&b, x);
        }
    }
    for (int i = 0; i < 32; ++i) {
        double u[5];
        for (int m = 0; m < 5; ++m) u[m] = (double)((i >> m) & 1);
        hp_claw_bladder b;
        double P, rho, ro = 0.0334;
        domain_state(u, 1.1e4, ro, &b, &P, &rho);
        assert_int_equal(hpi_claw_fem_domain(&b, P, ro, rho), HP_CLAW_IN);
        check_against_ref(&b, P, ro, rho);
        check_against_ref(&b, P, ro, ro);
        check_against_ref(&b, 0.0, ro, rho);
        check_against_ref(&b, 1e-9 * b.C1, ro, rho);
        check_against_ref(&b, 0.0, ro, ro);
    }
}

int main(void)
{
    const struct CMUnitTest t[] = {
        cmocka_unit_test(test_cap_value),
        cmocka_unit_test(test_cap_derivatives),
        cmocka_unit_test(test_load_law_reads_it),
        cmocka_unit_test(test_fem_derivatives),
        cmocka_unit_test(test_fem_domain),
        cmocka_unit_test(test_fem_against_tables),
        cmocka_unit_test(test_bladder_of),
        cmocka_unit_test(test_load_law_fem),
        cmocka_unit_test(test_load_domain_named),
        cmocka_unit_test(test_fem_shape),
        cmocka_unit_test(test_fem_covers_scenes),
        cmocka_unit_test(test_drho),
        cmocka_unit_test(test_eval_orders_same_bits),
        cmocka_unit_test(test_fem_closed_forms),
    };
    return cmocka_run_group_tests(t, NULL, NULL);
}
