/* Bladder sections of a scene: material, radii and limits (with bladder_defaults), the
 * single-bladder study and the values a paper printed. */
#include "scene/scene_parts.h"
#include "iab/names.h"

#include <math.h>
#include <string.h>

static const char *const PAPER_KEYS[] = {"convention", "C1_pa", "C2_pa", NULL};
static const char *const FE_KEYS[] = {"convention", "C10_pa", "C01_pa", NULL};

hp_error sp_material(const sr_ctx *c, const yt_node *node, const char *path, hp_iab *iab,
                     hp_material_convention *conv, double written[2])
{
    static const char *const ANY_KEYS[] = {"convention", "C1_pa",  "C2_pa",
                                           "C10_pa",     "C01_pa", NULL};
    hp_error e = sr_map(c, node, path, ANY_KEYS, NULL);
    if (e) return e;
    const yt_node *cv;
    char p[SR_PATH_MAX], name[16];
    if ((e = sr_require(c, node, path, "convention", &cv))) return e;
    sr_join(p, sizeof p, path, "convention");
    if ((e = sr_word(c, cv, p, "convention", hpi_material_convention_words, name, sizeof name)))
        return e;
    hp_material_convention mc = HP_MATERIAL_PAPER;
    (void)hp_material_convention_parse(name, &mc); /* cannot fail: name is in the table */
    const char *const *keys = mc == HP_MATERIAL_PAPER ? PAPER_KEYS : FE_KEYS;
    if ((e = sr_map(c, node, path, keys,
                    mc == HP_MATERIAL_PAPER ? "with convention paper" : "with convention fe")))
        return e;
    double v[2];
    for (int i = 0; i < 2; ++i) {
        const yt_node *n;
        if ((e = sr_require(c, node, path, keys[1 + i], &n))) return e;
        sr_join(p, sizeof p, path, keys[1 + i]);
        if ((e = sr_number(c, n, p, &v[i]))) return e;
        if (i == 0 && !(v[i] > 0))
            return sr_fail(c, n, p, HP_ERR_INVALID, "must be > 0 Pa (got %g)", v[i]);
        if (i == 1 && !(v[i] >= 0))
            return sr_fail(c, n, p, HP_ERR_INVALID, "must be >= 0 Pa (got %g)", v[i]);
    }
    double C1, C2;
    if (hp_iab_moduli_to_paper(mc, v[0], v[1], &C1, &C2) != HP_OK)
        return sr_fail(c, node, path, HP_ERR_INVALID, "moduli out of range");
    iab->C1 = C1;
    iab->C2 = C2;
    if (conv) *conv = mc;
    if (written) {
        written[0] = v[0];
        written[1] = v[1];
    }
    return HP_OK;
}

/* Looks key up in map, else in defaults; sets *node (NULL when absent in both) and path. */
static void lookup(const yt_node *map, const char *path, const yt_node *defaults, const char *key,
                   const yt_node **node, char *p, size_t size)
{
    *node = yt_map_get(map, key);
    if (*node) {
        sr_join(p, size, path, key);
    } else if (defaults && (*node = yt_map_get(defaults, key))) {
        sr_join(p, size, "bladder_defaults", key);
    }
}

static hp_error missing(const sr_ctx *c, const yt_node *map, const char *path, const char *key)
{
    char p[SR_PATH_MAX];
    sr_join(p, sizeof p, path, key);
    return sr_fail(c, map, p, HP_ERR_PARSE,
                   "missing required key (set it here or in bladder_defaults)");
}

/* Reads one number-valued parameter; *given says whether it was there. */
static hp_error param(const sr_ctx *c, const yt_node *map, const char *path,
                      const yt_node *defaults, int require, const char *key, double scale,
                      double *out, int *given, const yt_node **where, char *wpath)
{
    const yt_node *n;
    lookup(map, path, defaults, key, &n, wpath, SR_PATH_MAX);
    *given = n != NULL;
    *where = n ? n : map;
    if (!n) {
        sr_join(wpath, SR_PATH_MAX, path, key);
        return require ? missing(c, map, path, key) : HP_OK;
    }
    double v;
    hp_error e = sr_number(c, n, wpath, &v);
    if (e) return e;
    *out = v * scale;
    return HP_OK;
}

enum { P_RI, P_RO, P_PMIN, P_PMAX, P_SMIN, P_SMAX, P_RATE, P_STRESS, P_COUNT };

hp_error sp_bladder_params(const sr_ctx *c, const yt_node *map, const char *path,
                           const yt_node *defaults, int require, hp_bladder *b)
{
    static const char *const key[P_COUNT] = {
        "Ri_mm",       "Ro_mm",       "pressure_min_kpa", "pressure_max_kpa",
        "stretch_min", "stretch_max", "rate_max_kpa",     "stress_max_kpa"};
    static const double scale[P_COUNT] = {1e-3, 1e-3, 1e3, 1e3, 1.0, 1.0, 1e3, 1e3};
    double v[P_COUNT] = {0};
    int given[P_COUNT] = {0};
    const yt_node *at[P_COUNT];
    char p[P_COUNT][SR_PATH_MAX];
    hp_error e;
    for (int i = 0; i < P_COUNT; ++i) {
        p[i][0] = '\0';
        int req = require && i != P_RATE && i != P_STRESS;
        if ((e = param(c, map, path, defaults, req, key[i], scale[i], &v[i], &given[i], &at[i],
                       p[i])))
            return e;
    }
    /* signs, then the pairs */
    if (given[P_RI] && !(v[P_RI] > 0))
        return sr_fail(c, at[P_RI], p[P_RI], HP_ERR_INVALID, "must be > 0 mm (got %g)",
                       v[P_RI] * 1e3);
    if (given[P_RO] && !(v[P_RO] > 0))
        return sr_fail(c, at[P_RO], p[P_RO], HP_ERR_INVALID, "must be > 0 mm (got %g)",
                       v[P_RO] * 1e3);
    if (given[P_SMIN] && !(v[P_SMIN] > 0))
        return sr_fail(c, at[P_SMIN], p[P_SMIN], HP_ERR_INVALID, "must be > 0 (got %g)", v[P_SMIN]);
    if (given[P_RATE] && !(v[P_RATE] > 0))
        return sr_fail(c, at[P_RATE], p[P_RATE], HP_ERR_INVALID,
                       "must be > 0 kPa (got %g; omit the key for no rate limit)",
                       v[P_RATE] * 1e-3);
    if (given[P_STRESS] && !(v[P_STRESS] > 0))
        return sr_fail(c, at[P_STRESS], p[P_STRESS], HP_ERR_INVALID,
                       "must be > 0 kPa (got %g; omit the key for no stress limit)",
                       v[P_STRESS] * 1e-3);
    if (given[P_RI] && given[P_RO] && !(v[P_RI] < v[P_RO]))
        return sr_fail(c, at[P_RI], p[P_RI], HP_ERR_DOMAIN,
                       "must be less than Ro_mm (Ri %g mm, Ro %g mm)", v[P_RI] * 1e3,
                       v[P_RO] * 1e3);
    if (given[P_PMIN] && given[P_PMAX] && !(v[P_PMIN] < v[P_PMAX]))
        return sr_fail(c, at[P_PMIN], p[P_PMIN], HP_ERR_INVALID,
                       "must be less than pressure_max_kpa (min %g kPa, max %g kPa)",
                       v[P_PMIN] * 1e-3, v[P_PMAX] * 1e-3);
    if (given[P_SMIN] && given[P_SMAX] && !(v[P_SMIN] < v[P_SMAX]))
        return sr_fail(c, at[P_SMIN], p[P_SMIN], HP_ERR_INVALID,
                       "must be less than stretch_max (min %g, max %g)", v[P_SMIN], v[P_SMAX]);

    const yt_node *mat;
    char mpath[SR_PATH_MAX];
    mpath[0] = '\0';
    lookup(map, path, defaults, "material", &mat, mpath, sizeof mpath);
    hp_iab iab = {.Ri = v[P_RI], .Ro = v[P_RO]};
    if (mat) {
        if ((e = sp_material(c, mat, mpath, &iab, NULL, NULL))) return e;
    } else if (require) {
        return missing(c, map, path, "material");
    }
    if (require) {
        hp_diag sub;
        if ((e = hp_iab_validate(&iab, &sub))) return sr_fail(c, map, path, e, "%s", sub.text);
        hp_iab_limit lp;
        if ((e = hp_iab_limit_point(&iab, &lp)))
            return sr_fail(c, map, path, e, "limit point: %s", hp_error_message(e));
        if (lp.exists && !(v[P_SMAX] < lp.lambda_i))
            return sr_fail(c, at[P_SMAX], p[P_SMAX], HP_ERR_INVALID,
                           "must be below the inflation limit point of this material "
                           "(stretch_max %g >= limit %.6g)",
                           v[P_SMAX], lp.lambda_i);
    }
    b->iab = iab;
    b->p_min = v[P_PMIN];
    b->p_max = v[P_PMAX];
    b->stretch_min = v[P_SMIN];
    b->stretch_max = v[P_SMAX];
    b->rate_max = given[P_RATE] ? v[P_RATE] : INFINITY;
    b->stress_max = given[P_STRESS] ? v[P_STRESS] : 0.0;
    return HP_OK;
}

hp_error sp_study(const sr_ctx *c, const yt_node *node, hp_bladder_study *s)
{
    static const char *const KEYS[] = {"Ri_mm", "Ro_mm", "material", "ri_mm", "pressure_pa", NULL};
    const char *path = "bladder";
    hp_error e = sr_map(c, node, path, KEYS, "in a single-bladder study");
    if (e) return e;
    double v[2];
    const yt_node *n[2];
    char p[SR_PATH_MAX];
    for (int i = 0; i < 2; ++i) {
        const char *k = i == 0 ? "Ri_mm" : "Ro_mm";
        if ((e = sr_require(c, node, path, k, &n[i]))) return e;
        sr_join(p, sizeof p, path, k);
        if ((e = sr_number(c, n[i], p, &v[i]))) return e;
        if (!(v[i] > 0))
            return sr_fail(c, n[i], p, HP_ERR_INVALID, "must be > 0 mm (got %g)", v[i]);
    }
    if (!(v[0] < v[1]))
        return sr_fail(c, n[0], "bladder.Ri_mm", HP_ERR_DOMAIN,
                       "must be less than Ro_mm (Ri %g mm, Ro %g mm)", v[0], v[1]);
    s->iab.Ri = v[0] * 1e-3;
    s->iab.Ro = v[1] * 1e-3;
    const yt_node *mat;
    if ((e = sr_require(c, node, path, "material", &mat))) return e;
    if ((e = sp_material(c, mat, "bladder.material", &s->iab, &s->convention, s->moduli_written)))
        return e;
    hp_diag sub;
    if ((e = hp_iab_validate(&s->iab, &sub))) return sr_fail(c, node, path, e, "%s", sub.text);

    const yt_node *ri = yt_map_get(node, "ri_mm"), *P = yt_map_get(node, "pressure_pa");
    if (ri && P)
        return sr_fail(c, P, "bladder.pressure_pa", HP_ERR_PARSE,
                       "give ri_mm (inverse kinematics) or pressure_pa (forward), not both");
    if (!ri && !P)
        return sr_fail(c, node, "bladder.ri_mm", HP_ERR_PARSE,
                       "missing required key: give ri_mm (inverse kinematics) or "
                       "pressure_pa (forward)");
    if (ri) {
        double x;
        if ((e = sr_number(c, ri, "bladder.ri_mm", &x))) return e;
        if (!(x > 0))
            return sr_fail(c, ri, "bladder.ri_mm", HP_ERR_INVALID, "must be > 0 mm (got %g)", x);
        s->study = HP_STUDY_IK;
        s->study_ri = x * 1e-3;
    } else {
        double x;
        if ((e = sr_number(c, P, "bladder.pressure_pa", &x))) return e;
        s->study = HP_STUDY_FK;
        s->study_pressure = x;
    }
    return HP_OK;
}

hp_error sp_printed(const sr_ctx *c, const yt_node *node, hp_bladder_study *s)
{
    static const char *const KEYS[] = {"title", "note", "C1_pa",       "C2_pa", "Ri_m", "ri_m",
                                       "Ro_m",  "ro_m", "pressure_pa", "dV_m3", NULL};
    const char *path = "paper_printed";
    hp_error e = sr_map(c, node, path, KEYS, NULL);
    if (e) return e;
    hp_scene_printed *slot[8] = {&s->printed_C1,       &s->printed_C2, &s->printed_Ri,
                                 &s->printed_ri,       &s->printed_Ro, &s->printed_ro,
                                 &s->printed_pressure, &s->printed_dV};
    char p[SR_PATH_MAX];
    for (int i = 0; i < 8; ++i) {
        const yt_node *n = yt_map_get(node, KEYS[2 + i]);
        if (!n) continue;
        sr_join(p, sizeof p, path, KEYS[2 + i]);
        if ((e = sr_number_text(c, n, p, &slot[i]->value, slot[i]->text, sizeof slot[i]->text)))
            return e;
        slot[i]->given = 1;
    }
    const yt_node *t = yt_map_get(node, "title");
    if (t && (e = sr_text(c, t, "paper_printed.title", s->printed_title, sizeof s->printed_title)))
        return e;
    t = yt_map_get(node, "note");
    if (t && (e = sr_text(c, t, "paper_printed.note", s->printed_note, sizeof s->printed_note)))
        return e;
    s->has_printed = 1;
    return HP_OK;
}
