/* Layout sections of a scene: the head and the bladders' placement. */
#include "scene/scene_parts.h"
#include "kinematics/names.h"

#include <math.h>
#include <string.h>

hp_error sp_head(const sr_ctx *c, const yt_node *node, const char *path, hp_head *h)
{
    static const char *const ANY[] = {"shape",     "radius_mm", "semi_axes_mm",
                                      "center_mm", "mass_kg",   NULL};
    static const char *const SPHERE[] = {"shape", "radius_mm", "center_mm", "mass_kg", NULL};
    static const char *const ELLIPSOID[] = {"shape", "semi_axes_mm", "center_mm", "mass_kg", NULL};
    hp_error e = sr_map(c, node, path, ANY, NULL);
    if (e) return e;
    const yt_node *sh;
    char p[SR_PATH_MAX], name[32];
    if ((e = sr_require(c, node, path, "shape", &sh))) return e;
    sr_join(p, sizeof p, path, "shape");
    if ((e = sr_word(c, sh, p, "shape", hpi_head_shape_words, name, sizeof name))) return e;
    (void)hp_head_shape_parse(name, &h->shape); /* cannot fail: name is in the table */
    int sphere = h->shape == HP_HEAD_SPHERE;
    if ((e = sr_map(c, node, path, sphere ? SPHERE : ELLIPSOID,
                    sphere ? "for a sphere head" : "for an ellipsoid head")))
        return e;
    const yt_node *n;
    if (sphere) {
        double r;
        if ((e = sr_require(c, node, path, "radius_mm", &n))) return e;
        sr_join(p, sizeof p, path, "radius_mm");
        if ((e = sr_number(c, n, p, &r))) return e;
        if (!(r > 0)) return sr_fail(c, n, p, HP_ERR_INVALID, "must be > 0 mm (got %g)", r);
        h->semi_axes[0] = h->semi_axes[1] = h->semi_axes[2] = r * 1e-3;
    } else {
        double a[3];
        if ((e = sr_require(c, node, path, "semi_axes_mm", &n))) return e;
        sr_join(p, sizeof p, path, "semi_axes_mm");
        if ((e = sr_vector(c, n, p, 3, a))) return e;
        for (int i = 0; i < 3; ++i) {
            if (!(a[i] > 0)) {
                char ip[SR_PATH_MAX];
                sr_index(ip, sizeof ip, p, (size_t)i);
                return sr_fail(c, n->items[i], ip, HP_ERR_INVALID, "must be > 0 mm (got %g)", a[i]);
            }
            h->semi_axes[i] = a[i] * 1e-3;
        }
    }
    if ((n = yt_map_get(node, "center_mm"))) {
        double x[3];
        sr_join(p, sizeof p, path, "center_mm");
        if ((e = sr_vector(c, n, p, 3, x))) return e;
        for (int i = 0; i < 3; ++i) h->center[i] = x[i] * 1e-3;
    }
    h->mass = 0.0;
    if ((n = yt_map_get(node, "mass_kg"))) {
        double m;
        sr_join(p, sizeof p, path, "mass_kg");
        if ((e = sr_number(c, n, p, &m))) return e;
        if (!(m > 0))
            return sr_fail(c, n, p, HP_ERR_INVALID,
                           "must be > 0 kg (got %g; omit the key for no load model)", m);
        h->mass = m;
    }
    return HP_OK;
}

/* Names become CSV columns and JSON keys: letters, digits, '_' and '-' only. */
static int good_name(const char *s)
{
    if (!*s) return 0;
    for (; *s; ++s)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') ||
              *s == '_' || *s == '-'))
            return 0;
    return 1;
}

/* The surface point of head h along direction d from its centre. Exact up to rounding, so
 * it satisfies the surface equation to a few ulps. */
static int surface_along(const hp_head *h, const double d[3], double p[3])
{
    double s = 0.0;
    for (int i = 0; i < 3; ++i) {
        double u = d[i] / h->semi_axes[i];
        s += u * u;
    }
    if (!(s > 0) || !isfinite(s)) return 0;
    double t = 1.0 / sqrt(s);
    for (int i = 0; i < 3; ++i) p[i] = h->center[i] + t * d[i];
    return 1;
}

static hp_error placement(const sr_ctx *c, const yt_node *map, const char *path,
                          const hp_head *head, hp_bladder *b)
{
    static const char *const KINDS[] = {"center_mm", "touch_mm", "touch_dir"};
    const yt_node *given = NULL;
    int kind = -1;
    char p[SR_PATH_MAX];
    for (int i = 0; i < 3; ++i) {
        const yt_node *n = yt_map_get(map, KINDS[i]);
        if (!n) continue;
        if (given) {
            sr_join(p, sizeof p, path, KINDS[i]);
            return sr_fail(c, n, p, HP_ERR_PARSE,
                           "give one placement: center_mm, touch_mm or touch_dir (also has %s)",
                           KINDS[kind]);
        }
        given = n;
        kind = i;
    }
    if (!given) {
        return sr_fail(c, map, path, HP_ERR_PARSE,
                       "missing placement: give one of center_mm, touch_mm, touch_dir");
    }
    sr_join(p, sizeof p, path, KINDS[kind]);
    double x[3];
    hp_error e = sr_vector(c, given, p, 3, x);
    if (e) return e;
    double preload = 0.0;
    const yt_node *pl = yt_map_get(map, "preload_mm");
    if (pl) {
        char pp[SR_PATH_MAX];
        sr_join(pp, sizeof pp, path, "preload_mm");
        if (kind == 0)
            return sr_fail(c, pl, pp, HP_ERR_PARSE,
                           "preload_mm goes with touch_mm or touch_dir, not center_mm");
        if ((e = sr_number(c, pl, pp, &preload))) return e;
        preload *= 1e-3;
        if (!(preload > -b->iab.Ro))
            return sr_fail(c, pl, pp, HP_ERR_INVALID, "must be > -Ro_mm (got %g mm)",
                           preload * 1e3);
    }
    if (kind == 0) {
        for (int i = 0; i < 3; ++i) b->center[i] = x[i] * 1e-3;
        return HP_OK;
    }
    double pt[3];
    if (kind == 1) {
        for (int i = 0; i < 3; ++i) pt[i] = x[i] * 1e-3;
    } else if (!surface_along(head, x, pt)) {
        return sr_fail(c, given, p, HP_ERR_INVALID, "must be a non-zero direction");
    }
    hp_diag sub;
    e = hp_head_center_from_touch(head, pt, b->iab.Ro, preload, b->center, &sub);
    if (e) return sr_fail(c, given, p, e, "%s", sub.text);
    return HP_OK;
}

hp_error sp_bladders(const sr_ctx *c, const yt_node *list, const yt_node *defaults, hp_layout *L)
{
    static const char *const KEYS[] = {
        "name",        "center_mm",   "touch_mm",     "touch_dir",        "preload_mm",
        "Ri_mm",       "Ro_mm",       "material",     "pressure_min_kpa", "pressure_max_kpa",
        "stretch_min", "stretch_max", "rate_max_kpa", "stress_max_kpa",   NULL};
    if (list->type != YT_SEQUENCE)
        return sr_fail(c, list, "bladders", HP_ERR_PARSE, "expected a list of bladders, found %s",
                       sr_type_name(list));
    if (list->n < 1 || list->n > HP_MAX_BLADDERS)
        return sr_fail(c, list, "bladders", HP_ERR_INVALID, "must hold 1 to %d bladders (has %zu)",
                       HP_MAX_BLADDERS, list->n);
    for (size_t k = 0; k < list->n; ++k) {
        const yt_node *m = list->items[k];
        char path[SR_PATH_MAX], p[SR_PATH_MAX];
        sr_index(path, sizeof path, "bladders", k);
        hp_error e = sr_map(c, m, path, KEYS, NULL);
        if (e) return e;
        hp_bladder *b = &L->bladders[k];
        const yt_node *nm;
        if ((e = sr_require(c, m, path, "name", &nm))) return e;
        sr_join(p, sizeof p, path, "name");
        if ((e = sr_text(c, nm, p, b->name, sizeof b->name))) return e;
        if (!good_name(b->name))
            return sr_fail(c, nm, p, HP_ERR_INVALID, "'%s': use letters, digits, '_' and '-' only",
                           b->name);
        for (size_t j = 0; j < k; ++j)
            if (strcmp(L->bladders[j].name, b->name) == 0)
                return sr_fail(c, nm, p, HP_ERR_INVALID, "'%s' is used twice (also bladders[%zu])",
                               b->name, j);
        if ((e = sp_bladder_params(c, m, path, defaults, 1, b))) return e;
        if ((e = placement(c, m, path, &L->head, b))) return e;
    }
    L->n = (int)list->n;
    return HP_OK;
}
