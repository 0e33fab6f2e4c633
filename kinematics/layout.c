/* Layout validation and the nominal contact geometry of every bladder. */
#include "kin_internal.h"
#include "kin_geom.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The bladder's own checks that need no geometry. */
static hp_error check_bladder(const hp_layout *L, int k, hp_diag *diag)
{
    const hp_bladder *b = &L->bladders[k];
    size_t len = 0;
    while (len < HP_NAME_MAX && b->name[len] != '\0') ++len;
    if (len == 0)
        return hp_diag_set(diag, HP_ERR_INVALID, "bladder #%d: name: must not be empty", k + 1);
    if (len == HP_NAME_MAX)
        return hp_diag_set(diag, HP_ERR_INVALID, "bladder #%d: name: longer than %d characters",
                           k + 1, HP_NAME_MAX - 1);
    for (int j = 0; j < k; ++j)
        if (strncmp(L->bladders[j].name, b->name, HP_NAME_MAX) == 0)
            return hp_diag_set(diag, HP_ERR_INVALID,
                               "bladder '%s' (#%d): name: used twice (also #%d)", b->name, k + 1,
                               j + 1);
    if (!hpi_kin_finite3(b->center))
        return hp_diag_set(diag, HP_ERR_INVALID, "bladder '%s': center: must be finite", b->name);
    hp_diag sub;
    sub.text[0] = '\0';
    hp_error err = hp_iab_validate(&b->iab, &sub);
    if (err) return hp_diag_set(diag, err, "bladder '%s': %s", b->name, sub.text);
    if (!isfinite(b->p_min))
        return hp_diag_set(diag, HP_ERR_INVALID, "bladder '%s': p_min: must be finite", b->name);
    if (!isfinite(b->p_max))
        return hp_diag_set(diag, HP_ERR_INVALID, "bladder '%s': p_max: must be finite", b->name);
    if (!(b->p_min < b->p_max))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': p_max: must be > p_min (got %g Pa <= %g Pa)", b->name,
                           b->p_max, b->p_min);
    if (!(b->stretch_min > 0) || !isfinite(b->stretch_min))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': stretch_min: must be finite and > 0 (got %g)", b->name,
                           b->stretch_min);
    if (!isfinite(b->stretch_max) || !(b->stretch_max > b->stretch_min))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': stretch_max: must be finite and > stretch_min "
                           "(got %g)",
                           b->name, b->stretch_max);
    if (!(b->rate_max > 0)) /* +inf allowed: unlimited */
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': rate_max: must be > 0 or +inf (got %g Pa)", b->name,
                           b->rate_max);
    if (!(b->stress_max >= 0)) /* NaN and negatives; 0 and +inf mean no limit */
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': stress_max: must be > 0 (got %g Pa)", b->name,
                           b->stress_max);
    hp_iab_limit lp;
    err = hp_iab_limit_point(&b->iab, &lp);
    if (err)
        return hp_diag_set(diag, err, "bladder '%s': limit point: %s", b->name,
                           hp_error_message(err));
    if (lp.exists && !(b->stretch_max < lp.lambda_i))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': stretch_max: must be below the inflation limit point "
                           "(got %g >= %g)",
                           b->name, b->stretch_max, lp.lambda_i);
    return HP_OK;
}

/* Margin by which the nominal stretch must lie inside its limits: the nominal distance is
 * known to a few ulps, so a limit placed exactly at the nominal stretch (e.g. 1 without
 * preload) must fail whichever way the rounding falls. */
#define NOMINAL_STRETCH_MARGIN 1e-9

/* A bladder whose centre lies closer to the head than its outer radius overlaps the head:
 * at rest the head squeezes it to the contact distance. When that is too much (a collapsed
 * cavity, lam = NaN, or a stretch below stretch_min) the fault is the placement, not the
 * limit: the message says by how much to move the bladder out, to the distance at which
 * its inner radius is stretch_min·Ri (volume law ro³ = Ro³ + ri³ − Ri³). */
static hp_error overlap_fail(const hp_bladder *b, double rho0, double lam, hp_diag *diag)
{
    const hp_iab *m = &b->iab;
    double ri = b->stretch_min * m->Ri, ro = rho0;
    if (hp_iab_ro(m, ri, &ro) != HP_OK || !(ro > rho0)) ro = m->Ro;
    char squeeze[96];
    if (isnan(lam)) snprintf(squeeze, sizeof squeeze, "would collapse its cavity at rest");
    else
        snprintf(squeeze, sizeof squeeze, "compresses it to stretch %.6g at rest (stretch_min %g)",
                 lam, b->stretch_min);
    return hp_diag_set(diag, HP_ERR_INVALID,
                       "bladder '%s': center: the bladder overlaps the head: its centre is "
                       "%.6g mm from the head surface, less than its outer radius %.6g mm, so "
                       "the head %s: move it at least %.3g mm further from the head",
                       b->name, rho0 * 1e3, m->Ro * 1e3, squeeze, (ro - rho0) * 1e3);
}

/* The nominal pose must hold: stretch strictly inside its limits, pressure inside its own. */
static hp_error check_nominal(const hp_bladder *b, double rho0, hp_diag *diag)
{
    double ri, P;
    if (hp_iab_ri(&b->iab, rho0, &ri) != HP_OK) return overlap_fail(b, rho0, NAN, diag);
    double lam = ri / b->iab.Ri;
    if (!(b->stretch_min < lam - NOMINAL_STRETCH_MARGIN) && rho0 < b->iab.Ro)
        return overlap_fail(b, rho0, lam, diag);
    if (!(b->stretch_min < lam - NOMINAL_STRETCH_MARGIN))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': stretch_min: must be below the nominal stretch %.6g "
                           "(got %g)",
                           b->name, lam, b->stretch_min);
    if (!(lam + NOMINAL_STRETCH_MARGIN < b->stretch_max))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': stretch_max: must be above the nominal stretch %.6g "
                           "(got %g)",
                           b->name, lam, b->stretch_max);
    hp_error err = hp_iab_ik(&b->iab, ri, &P);
    if (err)
        return hp_diag_set(diag, err, "bladder '%s': nominal pressure: %s", b->name,
                           hp_error_message(err));
    if (!(b->p_min <= P))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': p_min: must be <= the nominal pressure %.6g Pa "
                           "(got %g Pa)",
                           b->name, P, b->p_min);
    if (!(P <= b->p_max))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%s': p_max: must be >= the nominal pressure %.6g Pa "
                           "(got %g Pa)",
                           b->name, P, b->p_max);
    return HP_OK;
}

/* The head as the geometry reads it: a sphere's three semi-axes all its radius. */
static hp_error head_of(const hp_layout *L, hp_head *h, hp_diag *diag)
{
    hp_error err = hpi_kin_head_validate(&L->head, diag);
    if (err) return err;
    *h = L->head;
    if (h->shape == HP_HEAD_SPHERE) h->semi_axes[1] = h->semi_axes[2] = h->semi_axes[0];
    return HP_OK;
}

static hp_error check_frame(const hp_layout *L, hp_diag *diag)
{
    if (!hpi_kin_finite3(L->pivot))
        return hp_diag_set(diag, HP_ERR_INVALID, "pivot: must be finite");
    if (!(L->n >= 1 && L->n <= HP_MAX_BLADDERS))
        return hp_diag_set(diag, HP_ERR_INVALID, "bladders: count must be 1..%d (got %d)",
                           HP_MAX_BLADDERS, L->n);
    return HP_OK;
}

/* Bladder k's nominal contact on head h: distance d, normal n, surface point p. The name
 * is printed with a bound: a layout that was never checked may not terminate it. */
static hp_error bladder_contact(const hp_head *h, const hp_bladder *b, int k, double *d,
                                double n[3], double p[3], hp_diag *diag)
{
    if (!hpi_kin_finite3(b->center))
        return hp_diag_set(diag, HP_ERR_INVALID, "bladder '%.*s' (#%d): center: must be finite",
                           HP_NAME_MAX - 1, b->name, k + 1);
    hp_error err = hpi_kin_head_distance(h, b->center, d, n, NULL, p);
    if (err != HP_OK || !(*d > 0))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "bladder '%.*s': center: must lie outside the head", HP_NAME_MAX - 1,
                           b->name);
    return HP_OK;
}

/* The linear level's Jacobian row of a bladder touching at point p with normal n:
 * ∂ρ/∂t = −n, ∂ρ/∂θ = −(p − pivot) × n (the contact point moves with the head). */
static void linear_row(const hp_layout *L, const double p[3], const double n[3], double row[6])
{
    double lv[3];
    for (int i = 0; i < 3; ++i) lv[i] = p[i] - L->pivot[i];
    row[0] = -n[0];
    row[1] = -n[1];
    row[2] = -n[2];
    row[3] = -(lv[1] * n[2] - lv[2] * n[1]);
    row[4] = -(lv[2] * n[0] - lv[0] * n[2]);
    row[5] = -(lv[0] * n[1] - lv[1] * n[0]);
}

hp_error hpi_geom_derive(const hp_layout *L, hp_geom *G, hp_diag *diag)
{
    if (!L || !G) return hp_diag_set(diag, HP_ERR_NULL, "layout: NULL");
    hp_error err = head_of(L, &G->head, diag);
    if (!err) hpi_kin_head_consts(&G->head, &G->headk);
    if (!err) err = check_frame(L, diag);
    for (int k = 0; !err && k < L->n; ++k) {
        err = bladder_contact(&G->head, &L->bladders[k], k, &G->rho0[k], G->normal[k],
                              G->contact[k], diag);
        for (int i = 0; i < 3; ++i) G->arm[k][i] = L->bladders[k].center[i] - L->pivot[i];
        if (!err) linear_row(L, G->contact[k], G->normal[k], G->row[k]);
    }
    return err;
}

hp_error hp_layout_contact(const hp_layout *L, int k, double point[3], double normal[3],
                           double *rho0)
{
    if (!L) return HP_ERR_NULL;
    hp_head h;
    hp_error err = head_of(L, &h, NULL);
    if (!err) err = check_frame(L, NULL);
    if (!err && !(k >= 0 && k < L->n)) err = HP_ERR_INVALID;
    double d, n[3], p[3];
    if (!err) err = bladder_contact(&h, &L->bladders[k], k, &d, n, p, NULL);
    if (err) return err;
    if (point) memcpy(point, p, sizeof p);
    if (normal) memcpy(normal, n, sizeof n);
    if (rho0) *rho0 = d;
    return HP_OK;
}

hp_error hp_layout_prepare(hp_layout *L, hp_diag *diag)
{
    if (!L) return hp_diag_set(diag, HP_ERR_NULL, "layout: NULL");
    hp_error err = head_of(L, &L->head, diag);
    if (!err) err = check_frame(L, diag);
    for (int k = 0; !err && k < L->n; ++k) err = check_bladder(L, k, diag);
    for (int k = 0; !err && k < L->n; ++k) {
        double d, n[3], p[3];
        err = bladder_contact(&L->head, &L->bladders[k], k, &d, n, p, diag);
        if (!err) err = check_nominal(&L->bladders[k], d, diag);
    }
    return err;
}
