/* The Python module `headplan`: its function table, headplan.Error, and the array helpers
 * every other file uses (see hpy.h and docs/python.md). */
#define HPY_IMPORT_ARRAY
#include "hpy.h"

#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

PyObject *hpy_error;

PyObject *hpy_fail(const char *fmt, ...)
{
    char buf[HP_DIAG_MAX + 256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    PyErr_SetString(hpy_error, buf);
    return NULL;
}

PyArrayObject *hpy_doubles(PyObject *obj, const char *name, int finite)
{
    /* First as whatever dtype it has, to refuse what is not a number before any cast. */
    PyArrayObject *any = (PyArrayObject *)PyArray_FROM_O(obj);
    if (!any) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s: not an array of numbers", name);
        return NULL;
    }
    char kind = PyArray_DESCR(any)->kind;
    if (kind != 'i' && kind != 'u' && kind != 'f') {
        PyErr_Format(PyExc_TypeError,
                     "%s: expected integers or floats (mm, degrees, Pa), got dtype kind '%c'", name,
                     kind);
        Py_DECREF(any);
        return NULL;
    }
    PyArrayObject *a = (PyArrayObject *)PyArray_FROM_OTF((PyObject *)any, NPY_DOUBLE,
                                                         NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
    Py_DECREF(any);
    if (!a) return NULL;
    if (finite) {
        const double *v = PyArray_DATA(a);
        npy_intp size = PyArray_SIZE(a);
        for (npy_intp i = 0; i < size; ++i)
            if (!isfinite(v[i])) {
                Py_DECREF(a);
                return (PyArrayObject *)hpy_fail("%s: element %zd is %s", name, (Py_ssize_t)i,
                                                 isnan(v[i]) ? "NaN" : "infinite");
            }
    }
    return a;
}

PyArrayObject *hpy_rows(PyObject *obj, const char *name, int cols, int one_row)
{
    PyArrayObject *a = hpy_doubles(obj, name, 0);
    if (!a) return NULL;
    int nd = PyArray_NDIM(a);
    npy_intp *dims = PyArray_DIMS(a);
    int ok = (nd == 2 && dims[1] == cols) || (one_row && nd == 1 && dims[0] == cols);
    if (!ok) {
        char shape[64] = "";
        size_t used = 0;
        for (int i = 0; i < nd && used < sizeof shape - 24; ++i)
            used += (size_t)snprintf(shape + used, sizeof shape - used, "%s%zd", i ? "×" : "",
                                     (Py_ssize_t)dims[i]);
        Py_DECREF(a);
        if (one_row)
            return (PyArrayObject *)hpy_fail("%s: expected shape (N, %d) or (%d,), got (%s)", name,
                                             cols, cols, shape);
        return (PyArrayObject *)hpy_fail("%s: expected shape (N, %d), got (%s)", name, cols, shape);
    }
    if (nd == 1) {
        npy_intp d2[2] = {1, cols};
        PyArray_Dims shape2 = {d2, 2};
        PyArrayObject *r = (PyArrayObject *)PyArray_Newshape(a, &shape2, NPY_CORDER);
        Py_DECREF(a);
        return r;
    }
    return a;
}

int hpy_double(PyObject *obj, const char *name, double *out)
{
    if (!PyFloat_Check(obj) && !PyLong_Check(obj) && !PyArray_IsScalar(obj, Integer) &&
        !PyArray_IsScalar(obj, Floating)) {
        PyErr_Format(PyExc_TypeError, "%s: expected a number", name);
        return -1;
    }
    double v = PyFloat_AsDouble(obj);
    if (v == -1.0 && PyErr_Occurred()) return -1;
    if (!isfinite(v)) {
        hpy_fail("%s: must be finite (got %g)", name, v);
        return -1;
    }
    *out = v;
    return 0;
}

int hpy_int(PyObject *obj, const char *name, int *out)
{
    if (!PyLong_Check(obj) && !PyArray_IsScalar(obj, Integer)) {
        PyErr_Format(PyExc_TypeError, "%s: expected an int", name);
        return -1;
    }
    PyObject *i = PyNumber_Index(obj);
    if (!i) return -1;
    int overflow = 0;
    long v = PyLong_AsLongAndOverflow(i, &overflow);
    if (!overflow && v == -1 && PyErr_Occurred()) {
        Py_DECREF(i);
        return -1;
    }
    if (overflow || v < INT_MIN || v > INT_MAX) {
        PyErr_Format(hpy_error, "%s: %S is out of range", name, i);
        Py_DECREF(i);
        return -1;
    }
    Py_DECREF(i);
    *out = (int)v;
    return 0;
}

PyArrayObject *hpy_new(int nd, npy_intp d0, npy_intp d1, int typenum)
{
    npy_intp dims[2] = {d0, d1};
    return (PyArrayObject *)PyArray_ZEROS(nd, dims, typenum, 0);
}

PyObject *hpy_str_array(const char *const *texts, npy_intp n)
{
    PyObject *list = PyList_New(n);
    if (!list) return NULL;
    for (npy_intp i = 0; i < n; ++i) {
        PyObject *s = PyUnicode_FromString(texts[i]);
        if (!s) {
            Py_DECREF(list);
            return NULL;
        }
        PyList_SET_ITEM(list, i, s);
    }
    /* A fixed-width str array: compares, masks and prints like the CSV column. */
    PyArray_Descr *d = PyArray_DescrNewFromType(NPY_UNICODE);
    if (!d) {
        Py_DECREF(list);
        return NULL;
    }
    size_t longest = 1;
    for (npy_intp i = 0; i < n; ++i)
        if (strlen(texts[i]) > longest) longest = strlen(texts[i]);
    d->elsize = (int)longest * 4; /* UCS4: as wide as the longest text, no wider */
    PyObject *arr = PyArray_FromAny(list, d, 1, 1, NPY_ARRAY_DEFAULT, NULL);
    Py_DECREF(list);
    return arr;
}

int hpy_put(PyObject *d, const char *key, PyObject *value)
{
    if (!value) return -1;
    int rc = PyDict_SetItemString(d, key, value);
    Py_DECREF(value);
    return rc;
}

PyObject *hpy_binding_names(PyObject *self, PyObject *arg)
{
    (void)self;
    /* Through __index__: the flags usually come as NumPy uint32 scalars from a result. */
    PyObject *index = PyNumber_Index(arg);
    if (!index) return NULL;
    int overflow = 0;
    long long v = PyLong_AsLongLongAndOverflow(index, &overflow);
    if (v == -1 && PyErr_Occurred()) {
        Py_DECREF(index);
        return NULL;
    }
    /* A bit beyond the defined flags (or a negative value) is no binding: naming none of it
     * would read as "binds nothing". */
    if (overflow || v < 0 || v >= (1ll << HP_BIND_COUNT)) {
        PyErr_Format(PyExc_ValueError,
                     "binding_names: flags must be in 0..%d (the HP_BIND_* bits), got %S",
                     (1 << HP_BIND_COUNT) - 1, index);
        Py_DECREF(index);
        return NULL;
    }
    Py_DECREF(index);
    unsigned long flags = (unsigned long)v;
    PyObject *list = PyList_New(0);
    for (int b = 0; list && b < HP_BIND_COUNT; ++b)
        if (flags & (1ul << b)) {
            PyObject *s = PyUnicode_FromString(hp_binding_name(1u << b));
            if (!s || PyList_Append(list, s) < 0) {
                Py_XDECREF(s);
                Py_CLEAR(list);
                break;
            }
            Py_DECREF(s);
        }
    return list;
}

static PyMethodDef functions[] = {
    {"load_scene", hpy_load_scene, METH_O,
     "load_scene(source) -> Scene\n\n"
     "Reads a scene: source is a path (str or os.PathLike) to a YAML scene file, or a dict\n"
     "with the same keys as the file (docs/scenes.md), which is serialised and parsed by the\n"
     "same parser. Units are the file's: every key names its unit (_mm, _deg, _pa, _kpa).\n"
     "Raises headplan.Error with the parser's 'FILE:LINE:COL: KEY: message' (for a dict the\n"
     "file is '<dict>' and the line counts in its JSON rendering, one key per line)."},
    {"ik", (PyCFunction)(void (*)(void))hpy_iab_ik, METH_VARARGS | METH_KEYWORDS,
     "ik(ri_mm, *, Ri_mm, Ro_mm, c1_pa, c2_pa) -> ndarray\n\n"
     "One bladder's inverse kinematics, vectorised: the pressure [Pa] that holds each inner\n"
     "radius ri_mm [mm] (any shape; a float64 array of the same shape comes back). Ri_mm and\n"
     "Ro_mm [mm] are the reference radii, c1_pa and c2_pa [Pa] the Mooney-Rivlin moduli in the\n"
     "paper's convention. The loop runs in C without the GIL. Equal bit for bit to\n"
     "`headplan ik --json`. Raises headplan.Error naming the first element out of the model's\n"
     "domain."},
    {"fk", (PyCFunction)(void (*)(void))hpy_iab_fk, METH_VARARGS | METH_KEYWORDS,
     "fk(pressure_pa, *, Ri_mm, Ro_mm, c1_pa, c2_pa) -> ndarray\n\n"
     "One bladder's forward kinematics, vectorised: the inner radius [mm] on the stable branch\n"
     "that holds each pressure [Pa] (any shape). Same bladder arguments as ik. The limit point\n"
     "is found once per call. Equal bit for bit to `headplan fk --json`. Raises\n"
     "headplan.Error naming the first pressure at or above the limit point."},
    {"analyze", (PyCFunction)(void (*)(void))hpy_analyze, METH_VARARGS | METH_KEYWORDS,
     "analyze(scene, level=None) -> dict\n\n"
     "The layout analysis of `headplan analyze`: singular values of the contact Jacobian\n"
     "(mm of contact distance per mm and per degree), rank, condition, the weakest direction\n"
     "(a unit 6-vector over x_mm..yaw_deg) and its words, the reach of every axis inside the\n"
     "bladders' limits (mm or degrees, 6×2: negative then positive direction), the linear and\n"
     "plane contact models' error bounds [mm], and the level used (level overrides the\n"
     "scene's; 'auto' resolves with the scene's tolerance and range)."},
    {"binding_names", hpy_binding_names, METH_O,
     "binding_names(flags) -> list of str\n\n"
     "The limits named by one bladder's binding flags (an int from a result's 'binding'\n"
     "array): 'pressure_min', 'pressure_max', 'stretch_min', 'stretch_max', 'rate_down',\n"
     "'rate_up', 'limit_point', 'stress_max', 'indent_max', 'cannot_pull', 'stability'\n"
     "(the last three at the load level). Raises ValueError for a negative value or a bit\n"
     "beyond these."},
    {"columns", hpy_columns, METH_NOARGS,
     "columns() -> list of dict\n\n"
     "The table of a planned row's columns that batch's files, the arrays of plan_many and\n"
     "run_trace and `headplan batch --columns` share: one dict per column with its name\n"
     "(pattern: {axis}, {unit}, {bladder}), unit, format, shape ('one', 'axes', 'bladders'),\n"
     "rows (in batch's files), numpy (its key in the dicts, or None), dtype and measured (a\n"
     "time, left out when two runs are compared)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT,
    "headplan",
    "headplan: bladder pressures for a desired 6-DOF head correction.\n\n"
    "Units everywhere: mm, degrees and Pa, as on the command line (poses are\n"
    "[x_mm, y_mm, z_mm, pitch_deg, roll_deg, yaw_deg]). See docs/python.md.\n\n"
    "  load_scene(path_or_dict) -> Scene\n"
    "  Planner(scene, backend=None, level=None, ...) with plan, plan_many, run_trace\n"
    "  ik / fk (one bladder, vectorised), analyze(scene), binding_names(flags)\n"
    "  Error: every failure the library reports (a ValueError)",
    -1,
    functions,
    NULL,
    NULL,
    NULL,
    NULL,
};

/* Declared for -Wmissing-prototypes: Python finds it by name in the shared object. */
PyMODINIT_FUNC PyInit_headplan(void);

PyMODINIT_FUNC PyInit_headplan(void)
{
    import_array();
    if (PyType_Ready(&hpy_scene_type) < 0 || PyType_Ready(&hpy_planner_type) < 0) return NULL;
    PyObject *m = PyModule_Create(&module);
    if (!m) return NULL;
    hpy_error = PyErr_NewExceptionWithDoc(
        "headplan.Error",
        "A failure the headplan library reports, with its one-line message (FILE:LINE:COL for\n"
        "scenes). A ValueError.",
        PyExc_ValueError, NULL);
    if (!hpy_error || PyModule_AddObject(m, "Error", hpy_error) < 0) goto fail;
    Py_INCREF(hpy_error); /* the module's reference was stolen; keep ours */
    Py_INCREF(&hpy_scene_type);
    if (PyModule_AddObject(m, "Scene", (PyObject *)&hpy_scene_type) < 0) goto fail;
    Py_INCREF(&hpy_planner_type);
    if (PyModule_AddObject(m, "Planner", (PyObject *)&hpy_planner_type) < 0) goto fail;
    if (PyModule_AddStringConstant(m, "__version__", hp_version()) < 0) goto fail;
    PyObject *keys = PyTuple_New(6);
    if (!keys) goto fail;
    for (int i = 0; i < 6; ++i) PyTuple_SET_ITEM(keys, i, PyUnicode_FromString(hp_pose_key(i)));
    if (PyModule_AddObject(m, "POSE_KEYS", keys) < 0) goto fail;
    return m;
fail:
    Py_DECREF(m);
    return NULL;
}
