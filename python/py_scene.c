/* headplan.Scene and headplan.load_scene: a scene read by the library's parser, from a file
 * or from a dict (serialised as JSON, which the YAML parser reads as flow style). */
#include "hpy.h"

#include <string.h>

static void scene_dealloc(PyObject *o)
{
    hpy_scene *self = (hpy_scene *)o;
    PyMem_Free(self->sc);
    PyMem_Free(self->st);
    Py_TYPE(o)->tp_free(o);
}

/* json.dumps's default= hook: NumPy arrays and scalars become lists and numbers. */
static PyObject *json_default(PyObject *self, PyObject *obj)
{
    (void)self;
    if (PyObject_HasAttrString(obj, "tolist")) return PyObject_CallMethod(obj, "tolist", NULL);
    return PyErr_Format(PyExc_TypeError, "scene dict: a %s is not a number, text, list or dict",
                        Py_TYPE(obj)->tp_name);
}
static PyMethodDef json_default_def = {"json_default", json_default, METH_O, NULL};

/* The dict as JSON text, one key per line so that the parser's line:col points at it. */
static PyObject *dict_text(PyObject *dict)
{
    PyObject *json = PyImport_ImportModule("json");
    if (!json) return NULL;
    PyObject *dumps = PyObject_GetAttrString(json, "dumps");
    Py_DECREF(json);
    PyObject *hook = PyCFunction_New(&json_default_def, NULL);
    PyObject *args = PyTuple_Pack(1, dict);
    PyObject *kw = Py_BuildValue("{s:i,s:O}", "indent", 1, "default", hook);
    PyObject *text = dumps && hook && args && kw ? PyObject_Call(dumps, args, kw) : NULL;
    Py_XDECREF(dumps);
    Py_XDECREF(hook);
    Py_XDECREF(args);
    Py_XDECREF(kw);
    return text;
}

/* The storage for a scene of kind k: a layout scene or a study. -1 when out of memory. */
static int alloc_kind(hpy_scene *obj, hp_scene_kind k)
{
    if (k == HP_SCENE_BLADDER) return (obj->st = PyMem_Calloc(1, sizeof *obj->st)) ? 0 : -1;
    return (obj->sc = PyMem_Calloc(1, sizeof *obj->sc)) ? 0 : -1;
}

PyObject *hpy_load_scene(PyObject *self, PyObject *arg)
{
    (void)self;
    hpy_scene *obj = PyObject_New(hpy_scene, &hpy_scene_type);
    if (!obj) return NULL;
    obj->sc = NULL;
    obj->st = NULL;
    hp_diag d = {{0}};
    hp_error e;
    if (PyDict_Check(arg)) {
        PyObject *text = dict_text(arg);
        if (!text) {
            Py_DECREF(obj);
            return NULL;
        }
        Py_ssize_t len;
        const char *utf8 = PyUnicode_AsUTF8AndSize(text, &len);
        if (utf8 && alloc_kind(obj, hp_scene_kind_of(utf8, (size_t)len)) < 0) {
            Py_DECREF(text);
            Py_DECREF(obj);
            return PyErr_NoMemory();
        }
        e = !utf8     ? HP_ERR_NOMEM
            : obj->st ? hp_study_parse(utf8, (size_t)len, "<dict>", obj->st, &d)
                      : hp_scene_parse(utf8, (size_t)len, "<dict>", obj->sc, &d);
        Py_DECREF(text);
        if (!utf8) {
            Py_DECREF(obj);
            return NULL;
        }
    } else {
        PyObject *path = NULL;
        if (!PyUnicode_FSConverter(arg, &path)) {
            Py_DECREF(obj);
            PyErr_Clear();
            return PyErr_Format(PyExc_TypeError, "load_scene: expected a path or a dict, got %s",
                                Py_TYPE(arg)->tp_name);
        }
        const char *p = PyBytes_AS_STRING(path);
        hp_scene_kind kind;
        Py_BEGIN_ALLOW_THREADS kind = hp_scene_file_kind(p);
        Py_END_ALLOW_THREADS if (alloc_kind(obj, kind) < 0)
        {
            Py_DECREF(path);
            Py_DECREF(obj);
            return PyErr_NoMemory();
        }
        Py_BEGIN_ALLOW_THREADS e = obj->st ? hp_study_load(p, obj->st, &d)
                                           : hp_scene_load(p, obj->sc, &d);
        Py_END_ALLOW_THREADS Py_DECREF(path);
    }
    if (e != HP_OK) {
        Py_DECREF(obj);
        return hpy_fail("%s", d.text);
    }
    return (PyObject *)obj;
}

const hp_scene *hpy_layout_scene(PyObject *obj)
{
    if (!PyObject_TypeCheck(obj, &hpy_scene_type)) {
        PyErr_Format(PyExc_TypeError, "expected a headplan.Scene, got %s", Py_TYPE(obj)->tp_name);
        return NULL;
    }
    const hpy_scene *self = (const hpy_scene *)obj;
    if (!self->sc) {
        hpy_fail("%s: a single-bladder study has no layout (see headplan.ik / headplan.fk)",
                 self->st->file);
        return NULL;
    }
    return self->sc;
}

static PyObject *vec_mm(const double *v, int n, double scale)
{
    PyArrayObject *a = hpy_new(1, n, 0, NPY_DOUBLE);
    if (!a) return NULL;
    double *o = PyArray_DATA(a);
    for (int i = 0; i < n; ++i) o[i] = v[i] * scale;
    return (PyObject *)a;
}

static PyObject *bladder_dict(const hp_layout *L, int k)
{
    const hp_bladder *B = &L->bladders[k];
    /* The nominal contact, derived from the (validated) layout; NaN if it could not be. */
    double pt[3], nv[3], rho0;
    if (hp_layout_contact(L, k, pt, nv, &rho0) != HP_OK) {
        for (int i = 0; i < 3; ++i) pt[i] = nv[i] = NAN;
        rho0 = NAN;
    }
    PyObject *d = PyDict_New();
    if (!d) return NULL;
    int bad = hpy_put(d, "name", PyUnicode_FromString(B->name)) ||
              hpy_put(d, "center_mm", vec_mm(B->center, 3, 1e3)) ||
              hpy_put(d, "Ri_mm", PyFloat_FromDouble(B->iab.Ri * 1e3)) ||
              hpy_put(d, "Ro_mm", PyFloat_FromDouble(B->iab.Ro * 1e3)) ||
              hpy_put(d, "c1_pa", PyFloat_FromDouble(B->iab.C1)) ||
              hpy_put(d, "c2_pa", PyFloat_FromDouble(B->iab.C2)) ||
              hpy_put(d, "pressure_min_pa", PyFloat_FromDouble(B->p_min)) ||
              hpy_put(d, "pressure_max_pa", PyFloat_FromDouble(B->p_max)) ||
              hpy_put(d, "stretch_min", PyFloat_FromDouble(B->stretch_min)) ||
              hpy_put(d, "stretch_max", PyFloat_FromDouble(B->stretch_max)) ||
              hpy_put(d, "rate_max_pa", PyFloat_FromDouble(B->rate_max)) ||
              hpy_put(d, "contact_mm", vec_mm(pt, 3, 1e3)) ||
              hpy_put(d, "normal", vec_mm(nv, 3, 1.0)) ||
              hpy_put(d, "rho0_mm", PyFloat_FromDouble(rho0 * 1e3));
    if (bad) Py_CLEAR(d);
    return d;
}

static PyObject *layout_dict(const hp_scene *sc)
{
    const hp_layout *L = &sc->layout;
    PyObject *head = PyDict_New(), *d = PyDict_New(), *bl = PyList_New(0);
    int bad = !head || !d || !bl;
    bad = bad || hpy_put(head, "shape", PyUnicode_FromString(hp_head_shape_name(L->head.shape))) ||
          hpy_put(head, "center_mm", vec_mm(L->head.center, 3, 1e3)) ||
          hpy_put(head, "semi_axes_mm", vec_mm(L->head.semi_axes, 3, 1e3)) ||
          hpy_put(head, "mass_kg", PyFloat_FromDouble(L->head.mass));
    for (int k = 0; !bad && k < L->n; ++k) {
        PyObject *b = bladder_dict(L, k);
        bad = !b || PyList_Append(bl, b) < 0;
        Py_XDECREF(b);
    }
    if (!bad) {
        Py_INCREF(head);
        Py_INCREF(bl);
        bad = hpy_put(d, "head", head) || hpy_put(d, "pivot_mm", vec_mm(L->pivot, 3, 1e3)) ||
              hpy_put(d, "bladders", bl);
    }
    Py_XDECREF(head);
    Py_XDECREF(bl);
    if (bad) Py_CLEAR(d);
    return d;
}

static PyObject *get_layout(PyObject *o, void *c)
{
    (void)c;
    const hp_scene *sc = hpy_layout_scene(o);
    return sc ? layout_dict(sc) : NULL;
}

static PyObject *get_bladder(PyObject *o, void *c)
{
    (void)c;
    const hp_bladder_study *sc = ((hpy_scene *)o)->st;
    if (!sc) Py_RETURN_NONE;
    return Py_BuildValue("{s:d,s:d,s:d,s:d}", "Ri_mm", sc->iab.Ri * 1e3, "Ro_mm", sc->iab.Ro * 1e3,
                         "c1_pa", sc->iab.C1, "c2_pa", sc->iab.C2);
}

static PyObject *get_name(PyObject *o, void *c)
{
    (void)c;
    const hpy_scene *self = (const hpy_scene *)o;
    return PyUnicode_FromString(self->sc ? self->sc->name : self->st->name);
}

static PyObject *get_file(PyObject *o, void *c)
{
    (void)c;
    const hpy_scene *self = (const hpy_scene *)o;
    return PyUnicode_DecodeFSDefault(self->sc ? self->sc->file : self->st->file);
}

static PyObject *get_kind(PyObject *o, void *c)
{
    (void)c;
    return PyUnicode_FromString(
        hp_scene_kind_name(((hpy_scene *)o)->sc ? HP_SCENE_LAYOUT : HP_SCENE_BLADDER));
}

static PyObject *get_names(PyObject *o, void *c)
{
    (void)c;
    const hp_scene *sc = ((hpy_scene *)o)->sc;
    int n = sc ? sc->layout.n : 0;
    PyObject *t = PyTuple_New(n);
    for (int k = 0; t && k < n; ++k) {
        PyObject *s = PyUnicode_FromString(sc->layout.bladders[k].name);
        if (!s) {
            Py_CLEAR(t);
            break;
        }
        PyTuple_SET_ITEM(t, k, s);
    }
    return t;
}

static PyObject *get_correction(PyObject *o, void *c)
{
    (void)c;
    const hp_scene *sc = ((hpy_scene *)o)->sc;
    if (!sc || !sc->has_correction) Py_RETURN_NONE;
    double mm_deg[6];
    hp_pose_to_clinical(sc->correction, mm_deg);
    return vec_mm(mm_deg, 6, 1.0);
}

static PyObject *get_trace(PyObject *o, void *c)
{
    (void)c;
    const hp_scene *sc = ((hpy_scene *)o)->sc;
    if (!sc || !sc->has_trace) Py_RETURN_NONE;
    return PyUnicode_DecodeFSDefault(sc->trace_path);
}

static PyObject *get_trace_rows(PyObject *o, void *c)
{
    (void)c;
    const hp_scene *sc = ((hpy_scene *)o)->sc;
    return PyUnicode_FromString(hp_trace_rows_name(sc ? sc->trace_rows : HP_TRACE_DEVIATION));
}

static PyObject *get_backend(PyObject *o, void *c)
{
    (void)c;
    const hp_scene *sc = ((hpy_scene *)o)->sc;
    hp_settings def; /* a study has no solver section: the planner's defaults */
    hp_settings_default(&def);
    return PyUnicode_FromString(hp_backend_name(sc ? sc->backend : def.backend));
}

static PyObject *get_level(PyObject *o, void *c)
{
    (void)c;
    const hp_scene *sc = ((hpy_scene *)o)->sc;
    hp_settings def; /* a study has no model section: the planner's defaults */
    hp_settings_default(&def);
    /* model.level: load is a planner of its own (hp_scene_plan_level), not a contact level. */
    if (sc && sc->level_load) return PyUnicode_FromString("load");
    return PyUnicode_FromString(hp_level_name(sc ? sc->level : def.level));
}

static PyObject *scene_repr(PyObject *o)
{
    const hpy_scene *self = (const hpy_scene *)o;
    const hp_scene *sc = self->sc;
    return PyUnicode_FromFormat("<headplan.Scene '%s' (%s, %d bladders) from %s>",
                                sc ? sc->name : self->st->name,
                                hp_scene_kind_name(sc ? HP_SCENE_LAYOUT : HP_SCENE_BLADDER),
                                sc ? sc->layout.n : 1, sc ? sc->file : self->st->file);
}

static PyGetSetDef scene_getset[] = {
    {"name", get_name, NULL, "the scene's name", NULL},
    {"file", get_file, NULL, "the file it was read from ('<dict>' for a dict)", NULL},
    {"kind", get_kind, NULL, "'layout' or 'bladder'", NULL},
    {"bladder_names", get_names, NULL, "tuple of the bladders' names (layout scenes)", NULL},
    {"correction", get_correction, NULL,
     "the scene's correction as [x_mm, y_mm, z_mm, pitch_deg, roll_deg, yaw_deg], or None", NULL},
    {"trace", get_trace, NULL, "the scene's trace path (resolved), or None", NULL},
    {"trace_rows", get_trace_rows, NULL, "'deviation' or 'correction': what the trace holds", NULL},
    {"backend", get_backend, NULL, "the scene's solver backend name", NULL},
    {"level", get_level, NULL,
     "the scene's model.level: 'linear', 'plane', 'surface', 'auto' or 'load'", NULL},
    {"layout", get_layout, NULL,
     "dict: head (shape, center_mm, semi_axes_mm, mass_kg), pivot_mm, and bladders (a list of\n"
     "dicts: name, center_mm, Ri_mm, Ro_mm, c1_pa, c2_pa, pressure_min_pa, pressure_max_pa,\n"
     "stretch_min, stretch_max, rate_max_pa, contact_mm, normal, rho0_mm). Layout scenes only.",
     NULL},
    {"bladder", get_bladder, NULL,
     "single-bladder scenes: dict Ri_mm, Ro_mm, c1_pa, c2_pa (ready for ik/fk); else None", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject hpy_scene_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "headplan.Scene",
    .tp_basicsize = sizeof(hpy_scene),
    .tp_dealloc = scene_dealloc,
    .tp_repr = scene_repr,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A scene read by headplan.load_scene (a layout or a single-bladder study).\n"
              "Read-only; lengths in mm, angles in degrees, pressures in Pa.",
    .tp_getset = scene_getset,
};
