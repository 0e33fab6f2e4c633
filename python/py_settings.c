/* Planner settings for the Python module: the scene's model and solver sections, then the
 * keyword overrides a Planner is built with. */
#include "hpy.h"
#include "common/names.h"
#include "kinematics/names.h"
#include "planner/names.h"
#include "planner/settings_check.h"

#include <string.h>

static int kw_double(PyObject *kw, const char *key, double scale, double *out)
{
    PyObject *v = kw ? PyDict_GetItemString(kw, key) : NULL;
    if (!v || v == Py_None) return 0;
    double x;
    if (hpy_double(v, key, &x) < 0) return -1;
    *out = x * scale;
    return 0;
}

static int kw_text(PyObject *kw, const char *key, const char **out)
{
    PyObject *v = kw ? PyDict_GetItemString(kw, key) : NULL;
    if (!v || v == Py_None) return 0;
    if (!PyUnicode_Check(v)) {
        PyErr_Format(PyExc_TypeError, "%s: expected a str", key);
        return -1;
    }
    *out = PyUnicode_AsUTF8(v);
    return *out ? 0 : -1;
}

static int kw_int(PyObject *kw, const char *key, int lo, int hi, int *out)
{
    PyObject *v = kw ? PyDict_GetItemString(kw, key) : NULL;
    if (!v || v == Py_None) return 0;
    int x;
    if (hpy_int(v, key, &x) < 0) return -1;
    if (x < lo || x > hi) {
        hpy_fail("%s: must be in %d..%d (got %d)", key, lo, hi, x);
        return -1;
    }
    *out = x;
    return 0;
}

/* The keyword is in mm, the library's field in m: its check, said in the keyword's units
 * (as the scene reader says it for model.tolerance_mm). */
static int level_tolerance_mm(PyObject *kw, double level_tolerance)
{
    PyObject *v = kw ? PyDict_GetItemString(kw, "level_tolerance_mm") : NULL;
    const char *why = v && v != Py_None ? hp_check_level_tolerance(level_tolerance) : NULL;
    if (!why) return 0;
    hpy_fail("level_tolerance_mm: %s mm (got %g)", why, level_tolerance * 1e3);
    return -1;
}

int hpy_settings(const hp_scene *sc, PyObject *kw, hp_settings *s)
{
    static const char *const known[] = {"backend",           "level",      "tolerance",
                                        "max_iter",          "max_time_s", "weight_mm_per_deg",
                                        "level_tolerance_mm", "warm_start", NULL};
    if (kw) {
        PyObject *key, *value;
        Py_ssize_t pos = 0;
        while (PyDict_Next(kw, &pos, &key, &value)) {
            const char *k = PyUnicode_AsUTF8(key);
            if (!k) return -1;
            int found = 0;
            for (int i = 0; known[i]; ++i) found |= strcmp(k, known[i]) == 0;
            if (!found) {
                PyErr_Format(PyExc_TypeError, "Planner: unknown keyword '%s'", k);
                return -1;
            }
        }
    }
    hp_diag d = {{0}};
    if (hp_scene_settings(sc, s, &d) != HP_OK) {
        hpy_fail("%s: %s", sc->file, d.text);
        return -1;
    }
    const char *backend = NULL, *level = NULL;
    int warm = s->warm_start;
    if (kw_text(kw, "backend", &backend) || kw_text(kw, "level", &level) ||
        kw_double(kw, "tolerance", 1.0, &s->tolerance) ||
        kw_int(kw, "max_iter", 1, 1000000, &s->max_iter) ||
        kw_double(kw, "max_time_s", 1.0, &s->max_time) ||
        kw_double(kw, "weight_mm_per_deg", 1.0, &s->weight_mm_per_deg) ||
        kw_double(kw, "level_tolerance_mm", 1e-3, &s->level_tolerance) ||
        level_tolerance_mm(kw, s->level_tolerance) ||
        kw_int(kw, "warm_start", 0, 1, &warm))
        return -1;
    s->warm_start = warm;
    char names[96];
    if (backend && hp_backend_parse(backend, &s->backend) != HP_OK) {
        hpy_fail("backend: unknown backend '%s' (%s)", backend,
                 hp_names_join(hp_backend_words, NULL, names, sizeof names));
        return -1;
    }
    if (level && hp_level_parse(level, &s->level) != HP_OK) {
        hpy_fail("level: unknown level '%s' (%s)", level,
                 hp_scene_level_names(1, ", ", names, sizeof names));
        return -1;
    }
    if (s->level == HP_LEVEL_LOAD && !sc->has_load) { /* as the command line's --level load */
        hpy_fail("level: load needs a scene with a 'load' section (%s has none)", sc->file);
        return -1;
    }
    if (hp_settings_validate(s, &d) != HP_OK) {
        hpy_fail("%s", d.text);
        return -1;
    }
    return 0;
}
