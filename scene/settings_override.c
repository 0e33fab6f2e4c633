/* Named overrides of planner settings (hp_scene.h): the command line's options and the
 * Python module's keywords, one table, each value checked by the planner's own per-field
 * check (planner/settings_check.h) in the override's units. */
#include "headplan/hp_scene.h"
#include "common/names.h"
#include "planner/names.h"
#include "planner/settings_check.h"
#include "scene/strict_number.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

typedef enum { OV_BACKEND, OV_LEVEL, OV_REAL, OV_INT, OV_BOOL } ov_kind;

typedef struct override {
    const char *name; /* with the unit of its value in the name where it has one */
    ov_kind kind;
    size_t field;       /* offsetof in hp_settings (OV_REAL, OV_INT, OV_BOOL) */
    double si_per_unit; /* the field's SI value of one unit of the override (OV_REAL) */
    const char *(*check)(double si); /* the planner's check of the field (OV_REAL) */
    const char *unit;                /* said after the check's phrase, "" for none */
} override;

/* An integer field's check takes a long: a value beyond [lo, hi] (NaN, a huge one that no
 * long holds) or not whole is out of range as it is, so it is handed lo - 1. */
static const char *whole(double v, long lo, long hi, const char *(*check)(long))
{
    if (!(v >= (double)lo && v <= (double)hi) || v != floor(v)) return check(lo - 1);
    return check((long)v);
}

static const char *check_max_iter(double v)
{
    return whole(v, 1, HP_MAX_ITER_MAX, hpi_check_max_iter);
}

static const char *check_restarts(double v)
{
    return whole(v, 0, HP_RESTARTS_MAX, hpi_check_restarts);
}

static const override TABLE[] = {
    {"backend", OV_BACKEND, 0, 0, NULL, ""},
    {"level", OV_LEVEL, 0, 0, NULL, ""},
    {"tolerance", OV_REAL, offsetof(hp_settings, tolerance), 1.0, hpi_check_tolerance, ""},
    {"max_iter", OV_INT, offsetof(hp_settings, max_iter), 1.0, check_max_iter, ""},
    {"max_time_s", OV_REAL, offsetof(hp_settings, max_time), 1.0, hpi_check_max_time, ""},
    {"weight_mm_per_deg", OV_REAL, offsetof(hp_settings, weight_mm_per_deg), 1.0, hpi_check_weight,
     ""},
    {"level_tolerance_mm", OV_REAL, offsetof(hp_settings, level_tolerance), 1e-3,
     hpi_check_level_tolerance, " mm"},
    {"warm_start", OV_BOOL, offsetof(hp_settings, warm_start), 1.0, NULL, ""},
    {"restarts", OV_INT, offsetof(hp_settings, restarts), 1.0, check_restarts, ""},
};
#define N_OVERRIDES (sizeof TABLE / sizeof TABLE[0])

const char *hp_scene_override_name(size_t i) { return i < N_OVERRIDES ? TABLE[i].name : NULL; }

static const override *find(const char *name)
{
    for (size_t i = 0; name && i < N_OVERRIDES; ++i)
        if (strcmp(TABLE[i].name, name) == 0) return &TABLE[i];
    return NULL;
}

/* A number's text or the number given: the value of a numeric override. */
static hp_error number_of(const override *o, const char *text, double number, double *v, hp_diag *d)
{
    if (!text) {
        *v = number;
        return HP_OK;
    }
    const char *why = hpi_strict_double(text, strlen(text), v);
    if (why) return hp_diag_set(d, HP_ERR_INVALID, "%s: '%s': %s", o->name, text, why);
    return HP_OK;
}

hp_error hp_scene_settings_override(hp_settings *s, const char *name, const char *text,
                                    double number, hp_diag *d)
{
    if (!s || !name) return hp_diag_set(d, HP_ERR_NULL, "settings override: NULL argument");
    const override *o = find(name);
    if (!o) return hp_diag_set(d, HP_ERR_INVALID, "%s: no such setting", name);
    if (o->kind == OV_BACKEND || o->kind == OV_LEVEL) {
        if (!text) return hp_diag_set(d, HP_ERR_INVALID, "%s: expected a name", o->name);
        if (o->kind == OV_BACKEND) {
            if (hp_backend_parse(text, &s->backend) == HP_OK) return HP_OK;
            char words[96];
            return hp_diag_set(d, HP_ERR_INVALID, "backend: unknown backend '%s' (%s)", text,
                               hpi_names_join(hpi_backend_words, NULL, words, sizeof words));
        }
        if (hp_level_parse(text, &s->level) == HP_OK) return HP_OK;
        char names[96];
        return hp_diag_set(d, HP_ERR_INVALID, "level: unknown level '%s' (%s)", text,
                           hp_scene_level_names(1, ", ", names, sizeof names));
    }
    double v;
    hp_error e = number_of(o, text, number, &v, d);
    if (e != HP_OK) return e;
    char *field = (char *)s + o->field;
    if (o->kind == OV_BOOL) {
        if (v != 0 && v != 1)
            return hp_diag_set(d, HP_ERR_INVALID, "%s: must be 0 or 1 (got %g)", o->name, v);
        *(int *)(void *)field = (int)v;
        return HP_OK;
    }
    double si = v * o->si_per_unit;
    const char *why = o->check(si);
    if (why) return hp_diag_set(d, HP_ERR_INVALID, "%s: %s%s (got %g)", o->name, why, o->unit, v);
    if (o->kind == OV_INT) *(int *)(void *)field = (int)v;
    else *(double *)(void *)field = si;
    return HP_OK;
}
