/* Fitting a bladder's moduli C1, C2 to free-inflation measurements (see hp_calib.h and
 * docs/calibration.md). The pressure is linear in the moduli at a fixed radius,
 * P = C1·a(ri) + C2·b(ri), which gives both the starting point (linear least squares in
 * pressure) and the exact Jacobian of the radius the model predicts (implicit function
 * theorem: dri/dCj = −(∂P/∂Cj)/(∂P/∂ri)). */
#include "headplan/hp_calib.h"
#include "calib/calib_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAT_MAX_ITERS 200
#define MAT_LAMBDA_MAX 1e16
/* Above this condition number of the Jacobian with columns scaled by the moduli, the data
 * see only one combination of C1 and C2: a relative error of 1e-4 in the radii (2.7 µm on
 * 27 mm, below a caliper's resolution) could then move the moduli by 100 %. The number grows
 * like 0.7/max|λi − 1| for points on one side of λ = 1 and 0.18/max|λi − 1| on both sides
 * (docs/calibration.md). */
#define MAT_COND_MAX 1e4
/* A fit whose radii miss the measured ones by more than this fraction of their mean (RMS)
 * does not fit: 5 % is 1.35 mm on a 27 mm bladder, ~70x a caliper's 0.02 mm, while a wrong
 * unit (cm read as mm: 10x) or wrong reference radii miss by tens of percent or more. */
#define MAT_RMS_REL_MAX 0.05

/* a(ri) = ∂P/∂C1 and b(ri) = ∂P/∂C2 at inner radius ri: the closed form with unit moduli. */
static hp_error basis(double Ri, double Ro, double ri, double *a, double *b)
{
    hp_iab u1 = {Ri, Ro, 1.0, 0.0}, u12 = {Ri, Ro, 1.0, 1.0};
    double p1, p12;
    hp_error e = hp_iab_ik(&u1, ri, &p1);
    if (!e) e = hp_iab_ik(&u12, ri, &p12);
    if (e) return e;
    *a = p1;
    *b = p12 - p1;
    return HP_OK;
}

/* ∂P/∂R at fixed inner radius ri of the closed form
 * P = 2·C1·[f(λi) − f(λo)] + 2·C2·[g(λi) − g(λo)], f(λ) = −1/λ − 1/(4λ⁴), g(λ) = λ − 1/(2λ²),
 * λi = ri/Ri, λo = ro/Ro, ro³ = Ro³ + ri³ − Ri³, for R = Ri (ref CALIB_REF_RI) or Ro. */
static double dP_dref(const hp_iab *m, double ri, double ro, int ref)
{
    double li = ri / m->Ri, lo = ro / m->Ro;
    double fpi = 1.0 / (li * li) + 1.0 / (li * li * li * li * li), gpi = 1.0 + 1.0 / (li * li * li);
    double fpo = 1.0 / (lo * lo) + 1.0 / (lo * lo * lo * lo * lo), gpo = 1.0 + 1.0 / (lo * lo * lo);
    double Pli = 2.0 * (m->C1 * fpi + m->C2 * gpi), Plo = -2.0 * (m->C1 * fpo + m->C2 * gpo);
    if (ref == CALIB_REF_RI) /* dλi/dRi = −ri/Ri², dro/dRi = −Ri²/ro² */
        return Pli * (-ri / (m->Ri * m->Ri)) + Plo * (-(m->Ri * m->Ri) / (ro * ro * m->Ro));
    /* dro/dRo = Ro²/ro², so dλo/dRo = Ro/ro² − ro/Ro² */
    return Plo * (m->Ro / (ro * ro) - ro / (m->Ro * m->Ro));
}

hp_error calib_model_radius(const hp_iab *m, const hp_iab_limit *lp, hp_calib_radius kind, double P,
                            int ref, double *r, double dr[3])
{
    double ri, Pri, dP, a, b, ro;
    hp_error e = hp_iab_fk_limit(m, lp, P, &ri);
    if (!e) e = hp_iab_ik_derivs(m, ri, &Pri, &dP, NULL);
    if (!e) e = basis(m->Ri, m->Ro, ri, &a, &b);
    if (!e) e = hp_iab_ro(m, ri, &ro);
    if (e) return e;
    if (!(dP > 0)) return HP_ERR_NO_STABLE;
    double scale = 1.0;
    *r = ri;
    if (kind == HP_CALIB_OUTER) {
        *r = ro;
        scale = (ri / ro) * (ri / ro); /* dro/dri from the volume law */
    }
    if (dr) {
        dr[0] = -scale * a / dP;
        dr[1] = -scale * b / dP;
        if (ref != CALIB_REF_NONE) {
            /* dri/dR = −(∂P/∂R)/(∂P/∂ri) at fixed P; an outer radius also moves with R
             * directly through the volume law: ∂ro/∂Ri = −Ri²/ro², ∂ro/∂Ro = Ro²/ro². */
            double dri = -dP_dref(m, ri, ro, ref) / dP;
            dr[2] = scale * dri;
            if (kind == HP_CALIB_OUTER)
                dr[2] += ref == CALIB_REF_RI ? -(m->Ri * m->Ri) / (ro * ro)
                                             : (m->Ro * m->Ro) / (ro * ro);
        }
    }
    return HP_OK;
}

/* Weighted residuals e_i = (r_meas − r_model)/σ_i and, if J is not NULL, their Jacobian
 * (n×2, row-major). Returns the index of the point that failed through *bad. */
static hp_error residuals(const hp_iab *m, hp_calib_radius kind, const hp_calib_point *pts, int n,
                          double *e, double *J, int *bad, hp_iab_limit *lp_out)
{
    hp_iab_limit lp;
    hp_error err = hp_iab_limit_point(m, &lp);
    if (err) return err;
    if (lp_out) *lp_out = lp;
    for (int i = 0; i < n; ++i) {
        double r, dr[3];
        if (lp.exists && !(pts[i].pressure < lp.pressure)) err = HP_ERR_NO_STABLE;
        else err = calib_model_radius(m, &lp, kind, pts[i].pressure, CALIB_REF_NONE, &r, dr);
        if (err) {
            if (bad) *bad = i;
            return err;
        }
        e[i] = (pts[i].radius - r) / pts[i].sigma;
        if (J) {
            J[2 * i] = -dr[0] / pts[i].sigma;
            J[2 * i + 1] = -dr[1] / pts[i].sigma;
        }
    }
    return HP_OK;
}

static double sumsq(int n, const double *v)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += v[i] * v[i];
    return s;
}

/* A = JᵀJ (2×2, symmetric) and g = Jᵀe. */
static void normal_eq(int n, const double *J, const double *e, double A[3], double g[2])
{
    A[0] = A[1] = A[2] = 0.0;
    if (g) g[0] = g[1] = 0.0;
    for (int i = 0; i < n; ++i) {
        A[0] += J[2 * i] * J[2 * i];
        A[1] += J[2 * i] * J[2 * i + 1];
        A[2] += J[2 * i + 1] * J[2 * i + 1];
        if (g) {
            g[0] += J[2 * i] * e[i];
            g[1] += J[2 * i + 1] * e[i];
        }
    }
}

/* Inverse of the symmetric 2×2 [A0 A1; A1 A2] into inv (same layout). 0 when singular. */
static int inv2(const double A[3], double inv[3])
{
    double det = A[0] * A[2] - A[1] * A[1];
    if (!(det > 0) || !isfinite(det)) return 0;
    inv[0] = A[2] / det;
    inv[1] = -A[1] / det;
    inv[2] = A[0] / det;
    return 1;
}

/* Condition number of the 2×2 symmetric positive semidefinite S = JᵀJ as sqrt of its
 * eigenvalue ratio (the singular values of J). */
static double cond2(const double S[3])
{
    double tr = 0.5 * (S[0] + S[2]);
    double dd = hypot(0.5 * (S[0] - S[2]), S[1]);
    double lmax = tr + dd, lmin = (S[0] * S[2] - S[1] * S[1]) / lmax;
    if (!(lmin > 0)) return INFINITY;
    return sqrt(lmax / lmin);
}

/* Condition number of the Jacobian whose normal matrix is A, with columns scaled by the
 * moduli of m, a modulus below a tenth of their sum by that tenth: the question for C2 = 0
 * (neo-Hookean) is whether the data tell it from C2 = 0.1·C1, not from 1e-12 Pa, and a column
 * scaled by C2 -> 0 would make any data "unidentifiable". */
static double scaled_cond(const hp_iab *m, const double A[3])
{
    double floor_c = 0.1 * (m->C1 + m->C2), sc1 = fmax(m->C1, floor_c), sc2 = fmax(m->C2, floor_c);
    double S[3] = {A[0] * sc1 * sc1, A[1] * sc1 * sc2, A[2] * sc2 * sc2};
    return cond2(S);
}

/* scaled_cond at moduli m for the points (e, J: n and 2n of scratch); NaN when m leaves a
 * point without a stable radius (nothing is known then). */
static double cond_at(const hp_iab *m, hp_calib_radius kind, const hp_calib_point *pts, int n,
                      double *e, double *J)
{
    double A[3];
    if (residuals(m, kind, pts, n, e, J, NULL, NULL) != HP_OK) return NAN;
    normal_eq(n, J, e, A, NULL);
    return scaled_cond(m, A);
}

static hp_error refuse_ill(hp_diag *diag, double cond, const double *ri_meas, int n, double Ri)
{
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < n; ++i) {
        lo = fmin(lo, ri_meas[i] / Ri);
        hi = fmax(hi, ri_meas[i] / Ri);
    }
    return hp_diag_set(diag, HP_ERR_INVALID,
                       "cannot determine both moduli: the Jacobian's condition number is "
                       "%.3g (> %.0e; 1e-4 relative error in a radius could move the moduli by "
                       "100 %%): the measured stretches lambda_i = %.4f..%.4f only see one "
                       "combination of C1 and C2; measure further from lambda = 1, on both sides",
                       cond, MAT_COND_MAX, lo, hi);
}

/* HP_ERR_INVALID when the fitted radii (weighted residuals e) miss the measured ones by more
 * than MAT_RMS_REL_MAX of their mean; the message compares the data with the reference
 * radius R they should lie near, to point at a wrong unit. */
static hp_error refuse_misfit(hp_diag *diag, hp_calib_radius kind, const hp_calib_point *pts, int n,
                              const double *e, double R)
{
    double ss = 0.0, mean = 0.0;
    for (int i = 0; i < n; ++i) {
        double r = e[i] * pts[i].sigma;
        ss += r * r;
        mean += pts[i].radius / n;
    }
    double rms = sqrt(ss / n);
    if (rms <= MAT_RMS_REL_MAX * mean) return HP_OK;
    const char *name = kind == HP_CALIB_INNER ? "Ri" : "Ro";
    double ratio = mean / R;
    char unit[160] = "";
    if (ratio < 0.5 || ratio > 2.0)
        snprintf(unit, sizeof unit,
                 "; the measured radii average %.4g mm against %s %.4g mm: check their unit "
                 "(mm; a radius in cm reads 10x too small)",
                 mean * 1e3, name, R * 1e3);
    return hp_diag_set(diag, HP_ERR_INVALID,
                       "the fit misses the data: residual RMS %.4g mm is %.3g %% of the mean "
                       "measured radius %.4g mm (more than %g %%); no moduli of this bladder "
                       "reproduce these radii%s",
                       rms * 1e3, 100.0 * rms / mean, mean * 1e3, 100.0 * MAT_RMS_REL_MAX, unit);
}

void calib_material_invalidate(hp_material_fit *out)
{
    double nan = NAN;
    out->C1 = out->C2 = out->C10 = out->C01 = nan;
    out->se[0] = out->se[1] = out->corr = out->condition = out->t = out->s = nan;
    out->rms = out->limit_pressure = nan;
    out->ci[0][0] = out->ci[0][1] = out->ci[1][0] = out->ci[1][1] = nan;
    out->n = out->dof = out->iterations = 0;
    out->ref_fitted = 0;
    out->ref_kind = HP_CALIB_INNER;
    out->ref = out->ref_se = out->ref_ci[0] = out->ref_ci[1] = nan;
    out->ref_corr[0] = out->ref_corr[1] = nan;
}

static long line_of(const hp_calib_point *p, int i) { return p->line ? p->line : i + 1; }

/* Checks the points and the design before any fitting; converts measured radii to inner
 * radii for the starting fit. */
static hp_error check_points(double Ri, double Ro, hp_calib_radius kind, const hp_calib_point *pts,
                             int n, double *ri_meas, hp_diag *d)
{
    hp_iab geo = {Ri, Ro, 1.0, 1.0};
    hp_diag sub = {{0}};
    if (hp_iab_validate(&geo, &sub)) return hp_diag_set(d, HP_ERR_INVALID, "%s", sub.text);
    if (kind != HP_CALIB_INNER && kind != HP_CALIB_OUTER)
        return hp_diag_set(d, HP_ERR_INVALID, "kind: must be inner or outer radius");
    if (n < 0 || n > HP_CALIB_MAX_ROWS)
        return hp_diag_set(d, HP_ERR_INVALID, "n: %d points (at most %d)", n, HP_CALIB_MAX_ROWS);
    for (int i = 0; i < n; ++i) {
        const hp_calib_point *p = &pts[i];
        long ln = line_of(p, i);
        if (!isfinite(p->pressure))
            return hp_diag_set(d, HP_ERR_INVALID, "point %ld: pressure: must be finite", ln);
        if (!(p->radius > 0) || !isfinite(p->radius))
            return hp_diag_set(d, HP_ERR_INVALID, "point %ld: radius: must be finite and > 0", ln);
        if (!(p->sigma > 0) || !isfinite(p->sigma))
            return hp_diag_set(d, HP_ERR_INVALID, "point %ld: sigma: must be finite and > 0", ln);
        ri_meas[i] = p->radius;
        if (kind == HP_CALIB_OUTER && hp_iab_ri(&geo, p->radius, &ri_meas[i]) != HP_OK)
            return hp_diag_set(d, HP_ERR_INVALID,
                               "point %ld: outer radius %g mm: the cavity would collapse "
                               "(needs ro > %g mm)",
                               ln, p->radius * 1e3, cbrt(Ro * Ro * Ro - Ri * Ri * Ri) * 1e3);
    }
    /* Each distinct pressure is one equation in (C1, C2); P = 0 holds Ri whatever they are. */
    int distinct = 0;
    double first = 0.0;
    for (int i = 0; i < n; ++i) {
        if (pts[i].pressure == 0.0) continue;
        if (distinct == 0) {
            first = pts[i].pressure;
            distinct = 1;
        } else if (pts[i].pressure != first) {
            distinct = 2;
            break;
        }
    }
    if (distinct < 2)
        return hp_diag_set(d, HP_ERR_INVALID,
                           "cannot determine both moduli: %s (each pressure gives one equation "
                           "in C1 and C2; measure at two or more different pressures)",
                           distinct == 0 ? "no non-zero pressure" : "only one non-zero pressure");
    if (n < 3)
        return hp_diag_set(d, HP_ERR_INVALID,
                           "%d points for 2 moduli: at least 3 are needed to estimate the "
                           "scatter (and so the intervals)",
                           n);
    return HP_OK;
}

/* Starting moduli: weighted linear least squares of P = C1·a(ri) + C2·b(ri) at the measured
 * radii, moved inside C1 > 0, C2 >= 0 when the data's noise pushes it out. */
static void start_point(double Ri, double Ro, const hp_calib_point *pts, const double *ri, int n,
                        double *C1, double *C2)
{
    double A[3] = {0}, g[2] = {0}, s11 = 0.0, s1p = 0.0;
    for (int i = 0; i < n; ++i) {
        double a, b;
        if (basis(Ri, Ro, ri[i], &a, &b)) continue;
        double w = 1.0 / (pts[i].sigma * pts[i].sigma);
        A[0] += w * a * a;
        A[1] += w * a * b;
        A[2] += w * b * b;
        g[0] += w * a * pts[i].pressure;
        g[1] += w * b * pts[i].pressure;
        s11 += w * (a + b) * (a + b);
        s1p += w * (a + b) * pts[i].pressure;
    }
    double inv[3];
    if (inv2(A, inv)) {
        *C1 = inv[0] * g[0] + inv[1] * g[1];
        *C2 = inv[1] * g[0] + inv[2] * g[1];
        if (*C1 > 0 && *C2 >= 0) return;
    }
    /* One common modulus K for both (C1 = C2 = K) from P = K·(a + b). */
    double K = s11 > 0 ? s1p / s11 : 1e4;
    if (!(K > 0) || !isfinite(K)) K = 1e4;
    *C1 = *C2 = K;
}

void calib_material_result(hp_material_fit *out, const double C[2], const double se[2], double corr,
                           double cond, int dof, double s2, const double *e,
                           const hp_calib_point *pts, int n, double *resid, int iterations,
                           const hp_iab_limit *lp)
{
    double tq = hp_calib_t_quantile(0.975, dof);
    out->C1 = C[0];
    out->C2 = C[1];
    out->C10 = 0.5 * C[0];
    out->C01 = 0.5 * C[1];
    for (int j = 0; j < 2; ++j) {
        out->se[j] = se[j];
        out->ci[j][0] = C[j] - tq * se[j];
        out->ci[j][1] = C[j] + tq * se[j];
    }
    out->corr = corr;
    out->condition = cond;
    out->n = n;
    out->dof = dof;
    out->t = tq;
    out->s = sqrt(s2);
    double ss = 0.0;
    for (int i = 0; i < n; ++i) {
        double r = e[i] * pts[i].sigma;
        ss += r * r;
        if (resid) resid[i] = r;
    }
    out->rms = sqrt(ss / n);
    out->iterations = iterations;
    out->limit_pressure = lp->exists ? lp->pressure : INFINITY;
}

hp_error hp_fit_material(double Ri, double Ro, hp_calib_radius kind, const hp_calib_point *pts,
                         int n, hp_material_fit *out, double *resid, hp_diag *diag)
{
    if (!out) return HP_ERR_NULL;
    calib_material_invalidate(out);
    if (!pts && n > 0) return HP_ERR_NULL;
    double *work = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1) * 5);
    if (!work) return hp_diag_set(diag, HP_ERR_NOMEM, "out of memory");
    double *ri_meas = work, *e = work + n, *et = work + 2 * n, *J = work + 3 * n;
    hp_iab m = {Ri, Ro, NAN, NAN}; /* the moduli of the search */
    int searching = 0;             /* 1 from the start point until the search has converged */
    hp_error err = check_points(Ri, Ro, kind, pts, n, ri_meas, diag);
    if (err) goto done;

    double C[2];
    start_point(Ri, Ro, pts, ri_meas, n, &C[0], &C[1]);
    m.C1 = C[0];
    m.C2 = C[1];
    searching = 1;
    /* The fit in pressure can follow a falling branch, the fit in radius cannot: when the
     * moduli the pressures suggest put the largest measured radius past their own limit
     * point, the bladder was measured beyond it (under volume control) and the
     * pressure-controlled model has no radius there. */
    hp_iab_limit lp0;
    if (hp_iab_limit_point(&m, &lp0) == HP_OK && lp0.exists) {
        int imax = 0;
        for (int i = 1; i < n; ++i)
            if (ri_meas[i] > ri_meas[imax]) imax = i;
        if (!(ri_meas[imax] < lp0.ri)) {
            err = hp_diag_set(
                diag, HP_ERR_INVALID,
                "the fit runs into the limit point: point %ld (ri %.6g mm) lies "
                "past the inflation limit point (lambda_i %.4f, %.6g Pa) of the moduli "
                "its pressures suggest; fit stable-branch points only",
                line_of(&pts[imax], imax), ri_meas[imax] * 1e3, lp0.lambda_i, lp0.pressure);
            goto done;
        }
    }
    int bad = -1;
    err = residuals(&m, kind, pts, n, e, J, &bad, NULL);
    /* The linear start may put a large pressure past the limit point: stiffen until not. */
    for (int k = 0; err == HP_ERR_NO_STABLE && k < 60; ++k) {
        m.C2 = m.C2 > 0 ? m.C2 * 2.0 : 0.1 * m.C1;
        err = residuals(&m, kind, pts, n, e, J, &bad, NULL);
    }
    if (err) {
        err = hp_diag_set(diag, HP_ERR_INVALID,
                          "point %ld: no starting moduli hold pressure %g Pa on the stable "
                          "branch",
                          bad >= 0 ? line_of(&pts[bad], bad) : 0L,
                          bad >= 0 ? pts[bad].pressure : NAN);
        goto done;
    }
    double cost = sumsq(n, e), lambda = 1e-3;
    int it = 0, converged = 0, last_reject_limit = -1;
    while (it < MAT_MAX_ITERS) {
        ++it;
        double A[3], g[2], inv[3];
        normal_eq(n, J, e, A, g);
        double Ad[3] = {A[0] * (1.0 + lambda), A[1], A[2] * (1.0 + lambda)};
        if (!inv2(Ad, inv)) {
            converged = 1; /* singular: the condition check below says why */
            break;
        }
        double step[2] = {-(inv[0] * g[0] + inv[1] * g[1]), -(inv[1] * g[0] + inv[2] * g[1])};
        int at_bound = m.C2 + step[1] < 0;
        if (at_bound) {
            /* The model's bound C2 >= 0 (neo-Hookean data sit on it): C2 stops at 0 and C1
             * takes the minimiser of the same damped quadratic model along C2 = 0. */
            step[1] = -m.C2;
            step[0] = -(g[0] + A[1] * step[1]) / Ad[0];
        }
        hp_iab t = m;
        t.C1 += step[0];
        t.C2 = at_bound ? 0.0 : m.C2 + step[1];
        double ct = INFINITY;
        int tbad = -1;
        if (t.C1 > 0) { /* t.C2 >= 0: held at 0 above */
            hp_error te = residuals(&t, kind, pts, n, et, NULL, &tbad, NULL);
            if (te == HP_OK) ct = sumsq(n, et);
            last_reject_limit = te == HP_ERR_NO_STABLE ? tbad : -1;
        } else {
            last_reject_limit = -2; /* a modulus would leave the model's range */
        }
        double rel = fmax(fabs(step[0]) / m.C1, fabs(step[1]) / fmax(m.C1, m.C2));
        if (ct <= cost) {
            m = t;
            cost = ct;
            err = residuals(&m, kind, pts, n, e, J, &bad, NULL);
            if (err) break;
            lambda = fmax(lambda * 0.1, 1e-15);
            last_reject_limit = -1;
            if (rel < 1e-13) {
                converged = 1;
                break;
            }
        } else {
            lambda *= 10.0;
            if (lambda > MAT_LAMBDA_MAX || rel < 1e-13) {
                converged = last_reject_limit == -1 || rel < 1e-13;
                break;
            }
        }
    }
    if (err) {
        err = hp_diag_set(diag, HP_ERR_INVALID, "the fit failed at point %ld",
                          bad >= 0 ? line_of(&pts[bad], bad) : 0L);
        goto done;
    }
    if (!converged && last_reject_limit >= 0) {
        err = hp_diag_set(diag, HP_ERR_INVALID,
                          "the fit runs into the limit point: the moduli the data prefer leave "
                          "no stable radius for pressure %g Pa (point %ld); measure below the "
                          "bladder's inflation limit",
                          pts[last_reject_limit].pressure,
                          line_of(&pts[last_reject_limit], last_reject_limit));
        goto done;
    }
    if (!converged && last_reject_limit == -2) {
        err = hp_diag_set(diag, HP_ERR_INVALID,
                          "the fit runs into the model's bound C1 > 0 (C1 %.6g Pa, C2 %.6g "
                          "Pa): the data prefer moduli the Mooney-Rivlin shell cannot have "
                          "(it requires C1 > 0, C2 >= 0)",
                          m.C1, m.C2);
        goto done;
    }
    if (!converged) {
        err = hp_diag_set(diag, HP_ERR_NO_CONVERGENCE, "the fit did not converge in %d iterations",
                          MAT_MAX_ITERS);
        goto done;
    }

    searching = 0;
    hp_iab_limit lp;
    bad = -1;
    err = residuals(&m, kind, pts, n, e, J, &bad, &lp);
    if (err) {
        err = hp_diag_set(diag, HP_ERR_INVALID, "the fit failed at point %ld",
                          bad >= 0 ? line_of(&pts[bad], bad) : 0L);
        goto done;
    }
    /* A measured radius past the fitted limit point lies on the unstable branch: the
     * stable-branch model cannot have produced it. */
    for (int i = 0; i < n; ++i)
        if (lp.exists && !(ri_meas[i] < lp.ri)) {
            err = hp_diag_set(diag, HP_ERR_INVALID,
                              "the fit runs into the limit point: point %ld's radius lies past "
                              "the fitted bladder's limit point (ri %.6g mm >= %.6g mm)",
                              line_of(&pts[i], i), ri_meas[i] * 1e3, lp.ri * 1e3);
            goto done;
        }
    err = refuse_misfit(diag, kind, pts, n, e, kind == HP_CALIB_INNER ? Ri : Ro);
    if (err) goto done;
    double A[3], inv[3];
    normal_eq(n, J, e, A, NULL);
    double cond = scaled_cond(&m, A);
    if (!(cond <= MAT_COND_MAX) || !inv2(A, inv)) {
        err = refuse_ill(diag, cond, ri_meas, n, Ri);
        goto done;
    }
    int dof = n - 2;
    double s2 = cost / dof;
    double se[2] = {sqrt(s2 * inv[0]), sqrt(s2 * inv[2])}, th[2] = {m.C1, m.C2};
    calib_material_result(out, th, se, inv[1] / sqrt(inv[0] * inv[2]), cond, dof, s2, e, pts, n,
                          resid, it, &lp);
done:
    /* A search that failed (no convergence, a bound, a limit point) on data that see only
     * one combination of the moduli failed because of that: the noise decides where such a
     * search wanders. Refused for the reason that holds whatever the noise. */
    if (err && searching) {
        double c = cond_at(&m, kind, pts, n, et, J);
        if (c > MAT_COND_MAX) err = refuse_ill(diag, c, ri_meas, n, Ri);
    }
    free(work);
    if (err) calib_material_invalidate(out);
    return err;
}

hp_error hp_fit_material_gain(double Ri, double Ro, hp_calib_radius kind, const hp_calib_point *pts,
                              int n, const hp_material_fit *fit, const double *cand, int ncand,
                              double sigma, double *shrink, hp_diag *diag)
{
    if (!pts || !fit || !cand || !shrink) return HP_ERR_NULL;
    if (!(sigma > 0) || !isfinite(sigma) || ncand < 0 || n < 1 || n > HP_CALIB_MAX_ROWS)
        return hp_diag_set(diag, HP_ERR_INVALID, "sigma, ncand or n out of range");
    hp_iab m = {Ri, Ro, fit->C1, fit->C2};
    hp_diag sub = {{0}};
    if (hp_iab_validate(&m, &sub)) return hp_diag_set(diag, HP_ERR_INVALID, "%s", sub.text);
    double *work = malloc(sizeof(double) * (size_t)n * 3);
    if (!work) return hp_diag_set(diag, HP_ERR_NOMEM, "out of memory");
    hp_iab_limit lp;
    int bad = -1;
    hp_error err = residuals(&m, kind, pts, n, work, work + n, &bad, &lp);
    double A[3] = {0}, inv[3] = {0};
    if (!err) {
        normal_eq(n, work + n, work, A, NULL);
        if (!inv2(A, inv)) err = hp_diag_set(diag, HP_ERR_INVALID, "singular information");
    }
    for (int j = 0; !err && j < ncand; ++j) {
        double r, dr[3];
        shrink[2 * j] = shrink[2 * j + 1] = NAN;
        if (!isfinite(cand[j]) || (lp.exists && !(cand[j] < lp.pressure))) continue;
        if (calib_model_radius(&m, &lp, kind, cand[j], CALIB_REF_NONE, &r, dr)) continue;
        double j0 = dr[0] / sigma, j1 = dr[1] / sigma;
        double An[3] = {A[0] + j0 * j0, A[1] + j0 * j1, A[2] + j1 * j1}, invn[3];
        if (!inv2(An, invn)) continue;
        shrink[2 * j] = sqrt(invn[0] / inv[0]);
        shrink[2 * j + 1] = sqrt(invn[2] / inv[2]);
    }
    free(work);
    return err;
}
