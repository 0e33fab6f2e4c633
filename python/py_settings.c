/* Planner settings for the Python module: the scene's model and solver sections, then the
 * keyword overrides a Planner is built with (the library's named overrides, and auto_pose). */
#include "hpy.h"

#include <string.h>

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

/* One keyword onto s through the library's override of the same name: a str for a name
 * (backend, level), else a number (an int where the field is one: max_iter, warm_start, restarts). */
static int kw_override(PyObject *kw, const char *key, hp_settings *s)
{
    PyObject *v = kw ? PyDict_GetItemString(kw, key) : NULL;
    if (!v || v == Py_None) return 0;
    const char *text = NULL;
    double x = 0;
    if (strcmp(key, "backend") == 0 || strcmp(key, "level") == 0) {
        if (kw_text(kw, key, &text)) return -1;
    } else if (strcmp(key, "max_iter") == 0 || strcmp(key, "warm_start") == 0 ||
               strcmp(key, "restarts") == 0) {
        int i;
        if (hpy_int(v, key, &i) < 0) return -1;
        x = i;
    } else if (hpy_double(v, key, &x) < 0) {
        return -1;
    }
    hp_diag d = {{0}};
    if (hp_scene_settings_override(s, key, text, x, &d) != HP_OK) {
        hpy_fail("%s", d.text);
        return -1;
    }
    return 0;
}

/* The auto_pose keyword: six numbers in a correction's units (mm, degrees) onto s; the
 * validator checks them (finite, in range) and names the component. */
static int kw_auto_pose(PyObject *kw, hp_settings *s)
{
    PyObject *v = kw ? PyDict_GetItemString(kw, "auto_pose") : NULL;
    if (!v || v == Py_None) return 0;
    PyArrayObject *a = hpy_doubles(v, "auto_pose", 0);
    if (!a) return -1;
    int ok = PyArray_NDIM(a) == 1 && PyArray_DIM(a, 0) == 6;
    if (ok) hp_pose_from_clinical((const double *)PyArray_DATA(a), s->auto_pose);
    Py_DECREF(a);
    if (!ok)
        hpy_fail("auto_pose: expected 6 values [x_mm, y_mm, z_mm, pitch_deg, roll_deg, yaw_deg]");
    return ok ? 0 : -1;
}

int hpy_settings(const hp_scene *sc, PyObject *kw, hp_settings *s)
{
    if (kw) {
        PyObject *key, *value;
        Py_ssize_t pos = 0;
        while (PyDict_Next(kw, &pos, &key, &value)) {
            const char *k = PyUnicode_AsUTF8(key);
            if (!k) return -1;
            int found = strcmp(k, "auto_pose") == 0;
            for (size_t i = 0; hp_scene_override_name(i); ++i)
                found |= strcmp(k, hp_scene_override_name(i)) == 0;
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
    for (size_t i = 0; hp_scene_override_name(i); ++i)
        if (kw_override(kw, hp_scene_override_name(i), s)) return -1;
    if (kw_auto_pose(kw, s)) return -1;
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
