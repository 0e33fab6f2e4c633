/* headplan.Planner: plan one correction or an N×6 array of them (the loop in C, the GIL
 * released), each from the nominal pose like `headplan solve`. Traces: py_trace.c. */
#include "hpy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void hpy_planner_lock(hpy_planner *self)
{
    if (PyThread_acquire_lock(self->lock, NOWAIT_LOCK)) return;
    Py_BEGIN_ALLOW_THREADS PyThread_acquire_lock(self->lock, WAIT_LOCK);
    Py_END_ALLOW_THREADS
}

static int planner_init(PyObject *o, PyObject *args, PyObject *kwargs)
{
    hpy_planner *self = (hpy_planner *)o;
    /* Built once. The planner is created with the GIL released, so a second __init__ from
     * another thread found p still NULL and built one too: the first planner, lock and
     * names were overwritten and leaked. `building` is set and p stored under the GIL. */
    if (self->p || self->building) {
        PyErr_SetString(PyExc_RuntimeError,
                        self->p ? "Planner: already built" : "Planner: already being built");
        return -1;
    }
    PyObject *scene;
    if (!PyArg_ParseTuple(args, "O:Planner", &scene)) return -1;
    const hp_scene *sc = hpy_layout_scene(scene);
    hp_settings s;
    /* The scene's settings with the keywords' overrides; the planner resolves the level
     * (the load level included) as headplan solve's does. */
    if (!sc || hpy_settings(sc, kwargs, &s) < 0) return -1;
    /* One solve from the nominal pose at a time, like headplan solve: no previous cycle. */
    s.use_rate_limits = 0;
    PyThread_type_lock lock = PyThread_allocate_lock();
    PyObject *names = PyTuple_New(sc->layout.n);
    if (!lock || !names) {
        if (lock) PyThread_free_lock(lock);
        Py_XDECREF(names);
        PyErr_NoMemory();
        return -1;
    }
    for (int k = 0; k < sc->layout.n; ++k) {
        PyObject *nm = PyUnicode_FromString(sc->layout.bladders[k].name);
        if (!nm) {
            PyThread_free_lock(lock);
            Py_DECREF(names);
            return -1;
        }
        PyTuple_SET_ITEM(names, k, nm);
    }
    self->s = s;
    self->layout = sc->layout;
    self->has_trace = sc->has_trace;
    self->trace_rows = sc->trace_rows;
    memcpy(self->trace_path, sc->trace_path, sizeof self->trace_path);
    hp_diag d = {{0}};
    hp_error e;
    hp_planner *p = NULL;
    self->building = 1;
    Py_BEGIN_ALLOW_THREADS e = hp_planner_create(&self->layout, &self->s, &p, &d);
    Py_END_ALLOW_THREADS self->building = 0;
    if (e != HP_OK) {
        PyThread_free_lock(lock);
        Py_DECREF(names);
        hpy_fail("%s: %s", sc->file, d.text);
        return -1;
    }
    self->p = p;
    self->lock = lock;
    self->names = names;
    return 0;
}

static void planner_dealloc(PyObject *o)
{
    hpy_planner *self = (hpy_planner *)o;
    hp_planner_destroy(self->p);
    if (self->lock) PyThread_free_lock(self->lock);
    Py_XDECREF(self->names);
    Py_TYPE(o)->tp_free(o);
}

static int built(hpy_planner *self)
{
    if (self->p) return 1;
    PyErr_SetString(PyExc_RuntimeError, "Planner: not built (call Planner(scene, ...))");
    return 0;
}

/* Plans rows of poses (mm, degrees) into the block, each from the nominal pose. Runs
 * without the GIL; the caller holds the planner's lock. */
static hp_error plan_rows(hp_planner *p, const double *poses, hpy_block *b)
{
    for (npy_intp i = 0; i < b->rows; ++i) {
        double xi[6];
        hp_pose_from_clinical(&poses[i * 6], xi);
        hp_planner_reset(p);
        hp_result r;
        hp_error e = hp_plan(p, xi, &r);
        /* A NaN or out-of-range row is a status of its own, as in headplan batch. */
        if (e != HP_OK && r.status != HP_STATUS_INVALID_INPUT) return e;
        hpy_block_store(b, i, NULL, &r);
    }
    return HP_OK;
}

/* Plans an N×6 float64 array into a dict of arrays. msg (HP_DIAG_MAX chars, or NULL)
 * receives the last plan's message. It is copied before the planner's lock is released:
 * once it is, building the dict can run a finalizer that lets another thread plan on this
 * planner, and the texts would then be that plan's. */
static PyObject *plan_array(hpy_planner *self, PyArrayObject *poses, char *msg)
{
    hpy_block b;
    if (hpy_block_alloc(&b, PyArray_DIM(poses, 0), hp_planner_layout(self->p)->n, 0) < 0)
        return PyErr_NoMemory();
    const double *x = PyArray_DATA(poses);
    hp_error e;
    char err[HP_DIAG_MAX];
    hpy_planner_lock(self);
    Py_BEGIN_ALLOW_THREADS e = plan_rows(self->p, x, &b);
    /* An answer (closest, uncommanded) explains itself in the note; a failure in the
     * error. The note is composed on demand, so it is asked for here, under the lock. */
    snprintf(err, sizeof err, "%s", hp_planner_error(self->p));
    if (msg) snprintf(msg, HP_DIAG_MAX, "%s", *err ? err : hp_planner_note(self->p));
    Py_END_ALLOW_THREADS PyThread_release_lock(self->lock);
    PyObject *d = e == HP_OK ? hpy_block_dict(&b)
                             : hpy_fail("plan: %s: %s", hp_error_message(e), err);
    hpy_block_free(&b);
    return d;
}

static PyObject *planner_plan_many(PyObject *o, PyObject *arg)
{
    hpy_planner *self = (hpy_planner *)o;
    if (!built(self)) return NULL;
    PyArrayObject *poses = hpy_rows(arg, "poses", 6, 0);
    if (!poses) return NULL;
    PyObject *d = plan_array(self, poses, NULL);
    Py_DECREF(poses);
    return d;
}

/* One row of a block dict -> the same keys with the leading axis dropped. */
static PyObject *first_row(PyObject *block)
{
    PyObject *d = PyDict_New(), *key, *value;
    Py_ssize_t pos = 0;
    while (d && PyDict_Next(block, &pos, &key, &value)) {
        PyObject *row = PySequence_GetItem(value, 0);
        /* Scalars come back as Python numbers and str, not 0-d arrays. */
        if (row && PyArray_IsScalar(row, Generic)) {
            PyObject *item = PyObject_CallMethod(row, "item", NULL);
            Py_DECREF(row);
            row = item;
        }
        if (!row || PyDict_SetItem(d, key, row) < 0) Py_CLEAR(d);
        Py_XDECREF(row);
    }
    return d;
}

static PyObject *planner_plan(PyObject *o, PyObject *args, PyObject *kwargs)
{
    hpy_planner *self = (hpy_planner *)o;
    static char *kw[] = {"correction", NULL};
    PyObject *corr;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O:plan", kw, &corr)) return NULL;
    if (!built(self)) return NULL;
    PyArrayObject *pose = hpy_doubles(corr, "correction", 0);
    if (!pose) return NULL;
    if (PyArray_NDIM(pose) != 1 || PyArray_DIM(pose, 0) != 6) {
        Py_DECREF(pose);
        return hpy_fail("correction: expected 6 values [x_mm, y_mm, z_mm, pitch_deg, "
                        "roll_deg, yaw_deg]");
    }
    npy_intp d2[2] = {1, 6};
    PyArray_Dims shape = {d2, 2};
    PyArrayObject *one = (PyArrayObject *)PyArray_Newshape(pose, &shape, NPY_CORDER);
    Py_DECREF(pose);
    if (!one) return NULL;
    char msg[HP_DIAG_MAX];
    PyObject *block = plan_array(self, one, msg);
    Py_DECREF(one);
    if (!block) return NULL;
    PyObject *d = first_row(block);
    Py_DECREF(block);
    if (d && hpy_put(d, "message", PyUnicode_FromString(msg)) < 0) Py_CLEAR(d);
    return d;
}

static PyObject *get_level(PyObject *o, void *c)
{
    (void)c;
    hpy_planner *self = (hpy_planner *)o;
    return built(self) ? PyUnicode_FromString(hp_level_name(hp_planner_level(self->p))) : NULL;
}

static PyObject *get_level_choice(PyObject *o, void *c)
{
    (void)c;
    hpy_planner *self = (hpy_planner *)o;
    if (!built(self)) return NULL;
    char why[HP_DIAG_MAX];                             /* the reason whole */
    hp_planner_level_choice(self->p, why, sizeof why); /* built: HP_OK */
    if (!why[0]) Py_RETURN_NONE;
    return PyUnicode_FromString(why);
}

static PyObject *get_backend(PyObject *o, void *c)
{
    (void)c;
    hpy_planner *self = (hpy_planner *)o;
    return built(self) ? PyUnicode_FromString(hp_backend_name(self->s.backend)) : NULL;
}

static PyObject *get_names(PyObject *o, void *c)
{
    (void)c;
    hpy_planner *self = (hpy_planner *)o;
    if (!built(self)) return NULL;
    Py_INCREF(self->names);
    return self->names;
}

static PyObject *get_settings(PyObject *o, void *c)
{
    (void)c;
    hpy_planner *self = (hpy_planner *)o;
    if (!built(self)) return NULL;
    const hp_settings *s = &self->s;
    double cp[6]; /* auto_pose in a correction's units, mm and degrees */
    hp_pose_to_clinical(s->auto_pose, cp);
    return Py_BuildValue("{s:s,s:s,s:d,s:d,s:i,s:d,s:d,s:i,s:i,s:[dddddd]}", "backend",
                         hp_backend_name(s->backend), "level", hp_level_name(s->level),
                         "level_tolerance_mm", s->level_tolerance * 1e3, "tolerance", s->tolerance,
                         "max_iter", s->max_iter, "max_time_s", s->max_time, "weight_mm_per_deg",
                         s->weight_mm_per_deg, "warm_start", s->warm_start, "restarts", s->restarts,
                         "auto_pose", cp[0], cp[1], cp[2], cp[3], cp[4], cp[5]);
}

static PyMethodDef planner_methods[] = {
    {"plan", (PyCFunction)(void (*)(void))planner_plan, METH_VARARGS | METH_KEYWORDS,
     "plan(correction) -> dict\n\n"
     "Plans one correction [x_mm, y_mm, z_mm, pitch_deg, roll_deg, yaw_deg] from the nominal\n"
     "pose, like `headplan solve` (no rate limits). Returns a dict: the result columns of\n"
     "headplan.columns() that have a key (status, the poses in mm and degrees, the\n"
     "bladders' pressures in Pa, radii, stretches and binding flags, see binding_names, ...)\n"
     "and message (the planner's text for a non-reached status). A status other\n"
     "than 'reached'/'closest' carries the safe output (the nominal pressures). NaN in the\n"
     "correction gives status 'invalid-input'."},
    {"plan_many", planner_plan_many, METH_O,
     "plan_many(poses) -> dict of arrays\n\n"
     "Plans every row of an N×6 array of corrections (mm and degrees), each independently\n"
     "from the nominal pose (as plan does, bit for bit). The loop runs in C with the GIL\n"
     "released, so threads with their own planners run at once. Returns the keys of plan\n"
     "with a leading axis N (dtypes and shapes from headplan.columns(): N, N×6 or N×n).\n"
     "Any numeric dtype and any strides are\n"
     "accepted (converted to float64); other dtypes raise TypeError, other shapes\n"
     "headplan.Error. Rows with NaN get status 'invalid-input'."},
    {"run_trace", (PyCFunction)(void (*)(void))hpy_planner_run_trace, METH_VARARGS | METH_KEYWORDS,
     "run_trace(trace=None, t=None, rows=None, rate_limits=True, mode='batch', horizon=None,\n"
     "          prediction=None, rate_kpa_per_s=None, window=None, overlap=None)\n"
     "    -> dict of arrays\n\n"
     "Plans a trace greedily, row after row, as `headplan batch` does: each plan starts from\n"
     "the previous row's pressures (rate limits carry over; the first row starts from the\n"
     "nominal pressures). trace is a path to a CSV / JSON Lines trace file, an N×6 array of\n"
     "poses (mm, degrees) with time stamps t [s] (default 0, 0.1, 0.2, ...), or None for the\n"
     "scene's own trace. rows is 'deviation' (the head's measured offset; the correction is\n"
     "its exact inverse rigid motion) or 'correction'; None keeps what the file or scene\n"
     "states; an array must say (the kind is never guessed). Returns the keys of plan_many\n"
     "plus line (the input line, the row index for arrays) and t_s. A bad file row gets status\n"
     "'bad-row' and NaN values, and its message is in 'messages' (a list), as batch reports\n"
     "it; so is the planner's reason for a row it refused (invalid-input).\n\n"
     "mode plans over a horizon instead, as `headplan horizon` does (every row must be\n"
     "good): 'greedy' (row by row with the per-row and per-second rate limits), 'receding'\n"
     "(horizon rows ahead, prediction 'hold', 'velocity' or 'periodic'), 'offline' (the whole "
     "trace in\n"
     "one sparse Ipopt NLP, or windows of `window` rows overlapping by `overlap`);\n"
     "rate_kpa_per_s is the per-second pressure rate limit [kPa/s]."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef planner_getset[] = {
    {"level", get_level, NULL, "the resolved contact level ('auto' resolved at build)", NULL},
    {"level_choice", get_level_choice, NULL,
     "why auto chose the level, in the words of `headplan solve`'s 'level choice'; None when\n"
     "the level is named (by the scene or the level keyword)",
     NULL},
    {"backend", get_backend, NULL, "the backend name", NULL},
    {"bladder_names", get_names, NULL, "tuple of the bladders' names (column order)", NULL},
    {"settings", get_settings, NULL,
     "dict of the settings in use (tolerance in mm and degrees, level_tolerance_mm, auto_pose\n"
     "in mm and degrees)",
     NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject hpy_planner_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "headplan.Planner",
    .tp_basicsize = sizeof(hpy_planner),
    .tp_dealloc = planner_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc =
        "Planner(scene, *, backend=None, level=None, tolerance=None, max_iter=None,\n"
        "        max_time_s=None, weight_mm_per_deg=None, level_tolerance_mm=None,\n"
        "        warm_start=None, restarts=None, auto_pose=None)\n\n"
        "A planner for a layout scene, with the scene's model and solver settings and these\n"
        "overrides: backend ('realtime', 'ipopt', 'nlopt-slsqp', 'nlopt-cobyla'), level\n"
        "('linear', 'plane', 'surface', 'auto'), tolerance (pose tolerance, mm and degrees),\n"
        "max_iter, max_time_s [s], weight_mm_per_deg, level_tolerance_mm [mm] (for 'auto'),\n"
        "warm_start (0/1), restarts (0..64: Ipopt's and NLopt SLSQP's further starts after a\n"
        "closest answer), auto_pose (6 values [x_mm, y_mm, z_mm, pitch_deg, roll_deg, yaw_deg]:\n"
        "the correction at which 'auto' on a scene with a load measures the levels' model\n"
        "error; default the scene's correction, as `headplan solve` plans it). Raises\n"
        "headplan.Error for a bad value. One call at a time per\n"
        "planner (a second thread waits); use one planner per thread for parallel work.",
    .tp_methods = planner_methods,
    .tp_getset = planner_getset,
    .tp_init = planner_init,
    .tp_new = PyType_GenericNew,
};
