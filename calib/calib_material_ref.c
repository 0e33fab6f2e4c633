/* Fitting one reference radius of a bladder together with its moduli (see hp_calib.h and
 * docs/calibration.md, "Fitting a reference radius"). Three parameters (C1, C2, R) with R the
 * inner or the outer reference radius; started from the two-moduli fit at the given radii. */
#include "headplan/hp_calib.h"
#include "calib/calib_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REF_MAX_ITERS 200
/* Above this condition number of the Jacobian with unit-norm columns the data cannot tell
 * the radius from the moduli. The same bound as the two-moduli fit's; measured on the
 * example bladder (Ri 27, Ro 30 mm, 12 points; docs/calibration.md): Ri from inner radii
 * over -4..6 kPa 18, over 3..6 kPa 93, over 5.0..5.1 kPa 9.9e4 (SE 27 mm: refused); Ro from
 * inner radii over -4..6 kPa 450, over 5..6 kPa 9.3e3 (SE 2 mm: answered, wide). */
#define REF_COND_MAX 1e4

typedef struct ref_ctx {
    double Ri, Ro;
    hp_calib_radius kind;
    int ref; /* CALIB_REF_RI or CALIB_REF_RO */
    const hp_calib_point *pts;
    int n;
} ref_ctx;

static void bladder_of(const ref_ctx *c, const double th[3], hp_iab *m)
{
    m->Ri = c->ref == CALIB_REF_RI ? th[2] : c->Ri;
    m->Ro = c->ref == CALIB_REF_RO ? th[2] : c->Ro;
    m->C1 = th[0];
    m->C2 = th[1];
}

/* Weighted residuals and (J not NULL) their Jacobian n×3. HP_ERR_DOMAIN when th leaves the
 * model (C1 <= 0, C2 < 0, not 0 < Ri < Ro), HP_ERR_NO_STABLE when a pressure has no stable
 * radius (its index in *bad). */
static hp_error eval(const ref_ctx *c, const double th[3], double *e, double *J, int *bad,
                     hp_iab_limit *lp_out)
{
    hp_iab m;
    bladder_of(c, th, &m);
    if (!(m.C1 > 0) || !(m.C2 >= 0) || !(m.Ri > 0) || !(m.Ro > m.Ri) || !isfinite(m.Ro) ||
        !isfinite(m.C1) || !isfinite(m.C2))
        return HP_ERR_DOMAIN;
    hp_iab_limit lp;
    hp_error err = hp_iab_limit_point(&m, &lp);
    if (err) return err;
    if (lp_out) *lp_out = lp;
    for (int i = 0; i < c->n; ++i) {
        const hp_calib_point *p = &c->pts[i];
        double r, dr[3];
        err = lp.exists && !(p->pressure < lp.pressure)
                  ? HP_ERR_NO_STABLE
                  : calib_model_radius(&m, &lp, c->kind, p->pressure, c->ref, &r, dr);
        if (err) {
            if (bad) *bad = i;
            return err;
        }
        e[i] = (p->radius - r) / p->sigma;
        if (J)
            for (int j = 0; j < 3; ++j) J[3 * i + j] = -dr[j] / p->sigma;
    }
    return HP_OK;
}

static double sumsq(int n, const double *v)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += v[i] * v[i];
    return s;
}

static long line_of(const hp_calib_point *p, int i) { return p->line ? p->line : i + 1; }

hp_error hp_fit_material_ref(double Ri, double Ro, hp_calib_radius kind, hp_calib_radius ref,
                             const hp_calib_point *pts, int n, hp_material_fit *out, double *resid,
                             hp_diag *diag)
{
    if (!out) return HP_ERR_NULL;
    if (ref != HP_CALIB_INNER && ref != HP_CALIB_OUTER) {
        calib_material_invalidate(out);
        return hp_diag_set(diag, HP_ERR_INVALID, "ref: must be inner (Ri) or outer (Ro)");
    }
    const char *rname = ref == HP_CALIB_INNER ? "Ri" : "Ro";
    hp_error err = hp_fit_material(Ri, Ro, kind, pts, n, out, NULL, diag);
    if (err) return err;
    if (n < 4) {
        calib_material_invalidate(out);
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "cannot determine %s: %d points for 3 parameters (C1, C2, %s): at "
                           "least 4 are needed to estimate the scatter",
                           rname, n, rname);
    }
    /* Each distinct pressure is one equation in (C1, C2, R). Zero pressure is one only for
     * the radius it returns: the inner radius is Ri there and the outer one Ro, whatever the
     * moduli; it says nothing about the other reference radius. */
    int eqs = 0, zero = 0;
    for (int i = 0; i < n; ++i) {
        int seen = 0;
        for (int k = 0; k < i && !seen; ++k) seen = pts[k].pressure == pts[i].pressure;
        if (seen) continue;
        if (pts[i].pressure != 0.0) ++eqs;
        else zero = 1;
    }
    if (zero && (int)kind == (int)ref) ++eqs;
    if (eqs < 3) {
        calib_material_invalidate(out);
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "cannot determine %s: the points give %d equation%s for 3 unknowns "
                           "(C1, C2, %s): each distinct pressure is one, zero pressure only "
                           "when the %s radius is measured; measure at three or more "
                           "different pressures",
                           rname, eqs, eqs == 1 ? "" : "s", rname,
                           ref == HP_CALIB_INNER ? "inner" : "outer");
    }
    ref_ctx c = {Ri, Ro, kind, ref == HP_CALIB_INNER ? CALIB_REF_RI : CALIB_REF_RO, pts, n};
    double th[3] = {out->C1, out->C2, ref == HP_CALIB_INNER ? Ri : Ro};
    double *work = malloc(sizeof(double) * (size_t)n * 8);
    if (!work) return hp_diag_set(diag, HP_ERR_NOMEM, "out of memory");
    double *e = work, *et = work + n, *J = work + 2 * (size_t)n, *S = work + 5 * (size_t)n;
    double scale[3], C[9], cond = NAN;
    int cols[3] = {0, 1, 2}, bad = -1, it = 0;
    err = eval(&c, th, e, J, &bad, NULL);
    double cost = sumsq(n, e), lambda = 1e-3;
    while (!err && it < REF_MAX_ITERS) {
        ++it;
        double dx[3], tt[3], rel = 0.0;
        calib_columns(n, 3, J, cols, 3, S, scale);
        if ((err = calib_lm_step(n, 3, S, scale, e, lambda, dx))) break;
        for (int j = 0; j < 3; ++j) {
            tt[j] = th[j] + dx[j];
            rel = fmax(rel, fabs(dx[j]) / fabs(th[j] > 0 ? th[j] : th[0]));
        }
        double ct = eval(&c, tt, et, NULL, NULL, NULL) ? INFINITY : sumsq(n, et);
        if (ct <= cost) {
            memcpy(th, tt, sizeof th);
            cost = ct;
            lambda = fmax(lambda * 0.1, 1e-15);
            if ((err = eval(&c, th, e, J, &bad, NULL))) break;
            if (rel < 1e-13) break;
        } else {
            lambda *= 10.0;
            if (lambda > 1e16 || rel < 1e-13) break;
        }
    }
    hp_iab_limit lp;
    if (!err) err = eval(&c, th, e, J, &bad, &lp);
    if (err) {
        err = hp_diag_set(diag, HP_ERR_INVALID, "fitting %s: the model failed at point %ld (%s)",
                          rname, bad >= 0 ? line_of(&pts[bad], bad) : 0L, hp_error_message(err));
        goto done;
    }
    calib_columns(n, 3, J, cols, 3, S, scale);
    if (calib_covariance(n, 3, S, scale, C, &cond) || !(cond <= REF_COND_MAX)) {
        err = hp_diag_set(diag, HP_ERR_INVALID,
                          "cannot determine %s: the Jacobian's condition number is %.3g (> %.0e): "
                          "these data cannot tell %s from the moduli (%s); keep %s fixed "
                          "(measure it unpressurised) or add points that see it",
                          rname, cond, REF_COND_MAX, rname,
                          ref == HP_CALIB_INNER
                              ? "a point at or near zero pressure pins Ri"
                              : "an outer radius near zero pressure pins Ro; from inner radii a "
                                "thin wall acts only through the moduli times its thickness",
                          rname);
        goto done;
    }
    /* A measured radius past the fitted limit point lies on the unstable branch. */
    {
        hp_iab m;
        bladder_of(&c, th, &m);
        for (int i = 0; lp.exists && i < n; ++i) {
            double ri = pts[i].radius;
            if (kind == HP_CALIB_OUTER)
                ri = cbrt(ri * ri * ri - m.Ro * m.Ro * m.Ro + m.Ri * m.Ri * m.Ri);
            if (!(ri < lp.ri)) {
                err = hp_diag_set(diag, HP_ERR_INVALID,
                                  "the fit runs into the limit point: point %ld's radius lies "
                                  "past the fitted bladder's limit point",
                                  line_of(&pts[i], i));
                goto done;
            }
        }
        int dof = n - 3;
        double s2 = cost / dof, tq = hp_calib_t_quantile(0.975, dof);
        double se[3];
        for (int j = 0; j < 3; ++j) se[j] = sqrt(s2 * C[4 * j]);
        calib_material_result(out, th, se, C[1] / sqrt(C[0] * C[4]), cond, dof, s2, e, pts, n,
                              resid, out->iterations + it, &lp);
        out->ref_fitted = 1;
        out->ref_kind = ref;
        out->ref = th[2];
        out->ref_se = se[2];
        out->ref_ci[0] = th[2] - tq * se[2];
        out->ref_ci[1] = th[2] + tq * se[2];
        out->ref_corr[0] = C[2] / sqrt(C[0] * C[8]);
        out->ref_corr[1] = C[5] / sqrt(C[4] * C[8]);
    }
done:
    free(work);
    if (err) calib_material_invalidate(out);
    return err;
}
