/* Layout analysis: conditioning of the contact Jacobian in clinical units, the weakest
 * direction in words, and the reach of each axis inside the bladders' limits. */
#include "kin_internal.h"
#include "kin_geom.h"
#include "common/units.h"
#include "linalg.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define RAD_PER_DEG HP_RAD_PER_DEG
/* Reach is searched up to these caps (a correction beyond them is not clinical). */
/* Coarse scan steps before bisection, so that a feasible set that is not an interval
 * along the axis still yields its first boundary. */
#define REACH_SCAN 100
#define REACH_BISECT 60

static const char *const dir_words[6] = {
    "lateral shift", "longitudinal shift", "vertical shift", "pitch", "roll", "yaw"};

/* 1 when every bladder can hold contact at pose xi inside its stretch and pressure limits. */
static int feasible(void *ctx, const double xi[6])
{
    const hp_kin_reach_ctx *c = ctx;
    const hp_layout *L = c->L;
    double rho[HP_MAX_BLADDERS];
    if (hp_contact_eval(L, c->level, xi, rho, NULL, NULL) != HP_OK) return 0;
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *b = &L->bladders[k];
        double ri, P;
        if (hp_iab_ri(&b->iab, rho[k], &ri) != HP_OK) return 0;
        double lam = ri / b->iab.Ri;
        if (!(lam >= b->stretch_min && lam <= b->stretch_max)) return 0;
        if (hp_iab_ik(&b->iab, ri, &P) != HP_OK) return 0;
        if (!(P >= b->p_min && P <= b->p_max)) return 0;
    }
    return 1;
}

double hpi_kin_reach_axis(int (*ok)(void *ctx, const double xi[6]), void *ctx, int axis,
                          double sign, int scan)
{
    double cap = axis < 3 ? HP_REACH_CAP_MM : HP_REACH_CAP_DEG;
    double unit = axis < 3 ? 1e-3 : RAD_PER_DEG;
    double xi[6] = {0};
    if (!ok(ctx, xi)) return 0.0;
    double good = 0.0, bad = -1.0;
    for (int i = 1; i <= scan; ++i) {
        double s = cap * i / scan;
        xi[axis] = sign * s * unit;
        if (!ok(ctx, xi)) {
            bad = s;
            break;
        }
        good = s;
    }
    if (bad < 0) return cap;
    for (int i = 0; i < REACH_BISECT; ++i) {
        double mid = 0.5 * (good + bad);
        xi[axis] = sign * mid * unit;
        if (ok(ctx, xi)) good = mid;
        else bad = mid;
    }
    return good;
}

static void describe(const double v[6], char *out, size_t size)
{
    int dom = 0;
    for (int i = 1; i < 6; ++i)
        if (fabs(v[i]) > fabs(v[dom])) dom = i;
    int len = snprintf(out, size, "%s", dir_words[dom]);
    int first = 1;
    for (int i = 0; i < 6; ++i) {
        if (i == dom || !(fabs(v[i]) >= 0.3)) continue;
        len += snprintf(out + len, size - (size_t)len, "%s%s", first ? " with some " : " and ",
                        dir_words[i]);
        first = 0;
        if ((size_t)len >= size) break;
    }
}

hp_error hp_layout_analyze(const hp_layout *L, hp_level level, hp_layout_analysis *out)
{
    if (!L || !out) return HP_ERR_NULL;
    hp_geom G;
    if (hpi_geom_derive(L, &G, NULL) != HP_OK) return HP_ERR_INVALID;
    if (!hp_level_is_geometry(level)) return HP_ERR_INVALID;
    double xi0[6] = {0}, J[HP_MAX_BLADDERS * 6];
    hp_error err = hp_contact_eval(L, HP_LEVEL_LINEAR, xi0, NULL, J, NULL);
    if (err) return err;
    /* Translation columns: m/m = mm/mm. Rotation columns: m/rad -> mm/deg. */
    for (int k = 0; k < L->n; ++k)
        for (int j = 3; j < 6; ++j) J[k * 6 + j] *= 1e3 * RAD_PER_DEG;
    double sv[6], V[36];
    if (hpi_kin_svd6(L->n, J, sv, V) != 0) return HP_ERR_NO_CONVERGENCE;
    memset(out, 0, sizeof *out);
    for (int j = 0; j < 6; ++j) out->singular_values[j] = sv[j];
    /* The rank is the one decision of hp_layout_identify (dimensionless, head-centred): the
     * singular values here, in mm and degrees about the pivot, depend on units and on the
     * pivot (1 km away they span 9 decades), so a threshold on them would not. */
    hp_identifiable id;
    err = hp_layout_identify(L, &id);
    if (err) return err;
    int rank = id.rank;
    out->rank = rank;
    out->condition = rank < 6 ? INFINITY : sv[0] / sv[5];
    /* Sign convention: the largest component positive, so the words read the same. */
    int dom = 0;
    for (int i = 1; i < 6; ++i)
        if (fabs(V[i * 6 + 5]) > fabs(V[dom * 6 + 5])) dom = i;
    double sgn = V[dom * 6 + 5] < 0 ? -1.0 : 1.0;
    for (int i = 0; i < 6; ++i) out->weakest[i] = sgn * V[i * 6 + 5];
    describe(out->weakest, out->weakest_words, sizeof out->weakest_words);
    out->rotation_commandable = L->head.shape != HP_HEAD_SPHERE;
    /* Only the components the planner commands have a reach (the others stay 0). */
    hp_kin_reach_ctx ctx = {L, level};
    for (int i = 0; i < 6; ++i) {
        if (!id.commanded[i]) continue;
        out->reach[i][0] = -hpi_kin_reach_axis(feasible, &ctx, i, -1.0, REACH_SCAN);
        out->reach[i][1] = hpi_kin_reach_axis(feasible, &ctx, i, 1.0, REACH_SCAN);
    }
    return HP_OK;
}
