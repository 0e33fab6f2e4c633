/* headplan.analyze: the layout analysis (hp_scene_analyze: hp_layout_analyze with the
 * planner's reach, and the contact models' error bounds) as a dict, with the keys of `headplan analyze --json`. Units: mm and degrees. */
#include "hpy.h"
#include "common/units.h"

#include <math.h>
#include <string.h>

static PyObject *array(const double *v, npy_intp rows, npy_intp cols, double scale)
{
    PyArrayObject *a = hpy_new(cols ? 2 : 1, rows, cols, NPY_DOUBLE);
    if (!a) return NULL;
    double *o = PyArray_DATA(a);
    for (npy_intp i = 0; i < rows * (cols ? cols : 1); ++i) o[i] = v[i] * scale;
    return (PyObject *)a;
}

PyObject *hpy_analyze(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    static char *kw[] = {"scene", "level", NULL};
    PyObject *scene;
    const char *level = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|z:analyze", kw, &scene, &level)) return NULL;
    const hp_scene *sc = hpy_layout_scene(scene);
    if (!sc) return NULL;
    hp_settings s;
    PyObject *over = level ? Py_BuildValue("{s:s}", "level", level) : NULL;
    if (level && !over) return NULL;
    int rc = hpy_settings(sc, over, &s);
    Py_XDECREF(over);
    if (rc < 0) return NULL;
    /* The load level's contact geometry is analysed at the scene's own kinematic level. */
    if (s.level == HP_LEVEL_LOAD) s.level = sc->level;
    hp_scene_analysis x;
    hp_diag dg = {{0}};
    hp_error e;
    Py_BEGIN_ALLOW_THREADS e = hp_scene_analyze(&sc->layout, &s, &x, &dg);
    Py_END_ALLOW_THREADS if (e != HP_OK) return hpy_fail("%s: %s", sc->file, dg.text);
    const hp_layout_analysis an = x.an;

    PyObject *d = PyDict_New(), *w = PyDict_New(), *b = PyDict_New();
    if (!d || !w || !b) goto fail;
    if (hpy_put(w, "vector", array(an.weakest, 6, 0, 1.0)) ||
        hpy_put(w, "phrase", PyUnicode_FromString(an.weakest_words)) ||
        hpy_put(w, "singular_value", PyFloat_FromDouble(an.singular_values[5])))
        goto fail;
    if (hpy_put(b, "tolerance_mm", PyFloat_FromDouble(s.level_tolerance * 1e3)) ||
        hpy_put(b, "translation_mm", PyFloat_FromDouble(x.trans * 1e3)) ||
        hpy_put(b, "rotation_deg", PyFloat_FromDouble(x.rot * 180.0 / HP_PI)))
        goto fail;
    for (int l = 0; l < HP_LEVEL_COUNT_; ++l) {
        if (!hp_level_is_geometry((hp_level)l)) continue;
        char key[32];
        snprintf(key, sizeof key, "%s_mm", hp_level_name((hp_level)l));
        if (hpy_put(b, key, PyFloat_FromDouble(x.bound[l] * 1e3))) goto fail;
    }
    if (hpy_put(b, "auto_level", PyUnicode_FromString(hp_level_name(x.auto_level)))) goto fail;
    /* Reach: 6×2, negative then positive direction; NaN where the planner commands none. */
    double reach[12];
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 2; ++j) reach[i * 2 + j] = an.reach[i][j];
    Py_INCREF(w);
    Py_INCREF(b);
    if (hpy_put(d, "scene", PyUnicode_FromString(sc->name)) ||
        hpy_put(d, "level", PyUnicode_FromString(hp_level_name(x.level))) ||
        hpy_put(d, "level_requested", PyUnicode_FromString(hp_level_name(x.requested))) ||
        hpy_put(d, "singular_values", array(an.singular_values, 6, 0, 1.0)) ||
        hpy_put(d, "rank", PyLong_FromLong(an.rank)) ||
        hpy_put(d, "condition", PyFloat_FromDouble(an.condition)) ||
        hpy_put(d, "weakest_direction", w) ||
        hpy_put(d, "rotation_commandable", PyBool_FromLong(an.rotation_commandable)) ||
        hpy_put(d, "reach", array(reach, 6, 2, 1.0)) || hpy_put(d, "error_bounds", b)) {
        w = b = NULL; /* references passed on (or dropped) by hpy_put */
        goto fail;
    }
    Py_DECREF(w);
    Py_DECREF(b);
    return d;
fail:
    Py_XDECREF(d);
    Py_XDECREF(w);
    Py_XDECREF(b);
    return NULL;
}
