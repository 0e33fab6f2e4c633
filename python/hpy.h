/* Internal to the Python module `headplan`: the pieces its source files share. Every file
 * that includes this header sees the NumPy C API through one table (PY_ARRAY_UNIQUE_SYMBOL),
 * imported once in module.c.
 *
 * Units at the Python boundary are the command line's: mm, degrees, Pa. The library speaks
 * SI; the conversions are the library's own (hp_pose_to_clinical / hp_pose_from_clinical and
 * the factor 1e3 for radii), so that numbers match `headplan solve --json` bit for bit. */
#ifndef HP_PYTHON_HPY_H
#define HP_PYTHON_HPY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL hpy_numpy_api
#ifndef HPY_IMPORT_ARRAY
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include "headplan/headplan.h"

/* headplan.Error (a ValueError): every failure the library reports. */
extern PyObject *hpy_error;

/* Raises headplan.Error with a printf-style message; returns NULL. */
PyObject *hpy_fail(const char *fmt, ...);

/* Converts obj to a new float64, C-contiguous, aligned array (a copy when obj is not one
 * already: lists, other integer/float dtypes, strided views). Refuses with TypeError anything
 * whose dtype is not an integer or a float (bool, complex, str, object), and with
 * headplan.Error a NaN or infinite element when finite is set. name goes into messages.
 * Returns a new reference or NULL with the exception set. */
PyArrayObject *hpy_doubles(PyObject *obj, const char *name, int finite);

/* Like hpy_doubles, and the array must be N×cols (or one row of cols values when one_row is
 * set, taken as 1×cols). Returns a new reference or NULL. */
PyArrayObject *hpy_rows(PyObject *obj, const char *name, int cols, int one_row);

/* Reads a float argument (an int or a float, NumPy scalars too; finite). Returns 0 or -1
 * with the exception set. */
int hpy_double(PyObject *obj, const char *name, double *out);

/* Reads an int argument (a Python or NumPy integer that fits an int; the range is the
 * validator's). Returns 0 or -1 with the exception set. */
int hpy_int(PyObject *obj, const char *name, int *out);

/* A new 1-D or 2-D float64 / int32 / uint32 array, zero-filled. */
PyArrayObject *hpy_new(int nd, npy_intp d0, npy_intp d1, int typenum);

/* A new 1-D NumPy array of str from C strings (the status names). */
PyObject *hpy_str_array(const char *const *texts, npy_intp n);

/* Sets d[key] = value and drops the caller's reference to value; -1 when value is NULL or
 * the call fails. */
int hpy_put(PyObject *d, const char *key, PyObject *value);

/* ---- the Scene type (py_scene.c) ---- */
typedef struct {
    PyObject_HEAD hp_scene *sc; /* owned: a layout scene, or NULL */
    hp_bladder_study *st;       /* owned: a single-bladder study, or NULL (exactly one is set) */
} hpy_scene;
extern PyTypeObject hpy_scene_type;
/* headplan.load_scene(source) */
PyObject *hpy_load_scene(PyObject *self, PyObject *arg);
/* The scene's layout, or NULL with headplan.Error set when it is a single-bladder study. */
const hp_scene *hpy_layout_scene(PyObject *obj);

/* ---- settings (py_settings.c) ---- */
/* Planner settings from a scene and keyword overrides (backend, level, tolerance, max_iter,
 * max_time_s, weight_mm_per_deg, level_tolerance_mm, warm_start). Returns 0 or -1. */
int hpy_settings(const hp_scene *sc, PyObject *kwargs, hp_settings *s);

/* ---- the Planner type (py_planner.c, py_trace.c) ---- */
typedef struct {
    PyObject_HEAD hp_planner *p; /* owned: one solve at a time from the nominal pose */
    hp_settings s;               /* as built (use_rate_limits = 0, like headplan solve) */
    hp_layout layout;            /* the scene's layout, for run_trace's own planner */
    PyThread_type_lock lock;     /* one call at a time on this planner (GIL released inside) */
    PyObject *names;             /* tuple of bladder names */
    int has_trace;               /* the scene's trace, for run_trace() without one */
    hp_trace_rows trace_rows;
    char trace_path[HP_SCENE_PATH_MAX];
    int building; /* an __init__ is creating p with the GIL released */
} hpy_planner;
extern PyTypeObject hpy_planner_type;
/* Takes the planner's lock, waiting without the GIL if another thread holds it. */
void hpy_planner_lock(hpy_planner *self);
PyObject *hpy_planner_run_trace(PyObject *self, PyObject *args, PyObject *kwargs);

/* A block of planned rows (py_block.c): one array per column of the library's column table
 * (hp_trace_columns.h) that has a NumPy key, filled without the GIL, turned into a dict of
 * arrays with it (the key, dtype and shape the table gives, in its order). */
typedef struct {
    npy_intp rows;
    int n;
    int with_rows;             /* the trace-row columns (line, t_s) too: run_trace */
    size_t ncols;              /* the table's length */
    double *v[HP_COLUMNS_MAX]; /* column j: rows × its width, NULL: not in the block */
} hpy_block;
/* Allocates the block (malloc); 0 or -1 (no exception set). */
int hpy_block_alloc(hpy_block *b, npy_intp rows, int n, int with_rows);
void hpy_block_free(hpy_block *b);
/* Stores row i: the trace row (NULL for a block without trace rows) and its result, r NULL
 * for a row the trace reader refused (status "bad-row", every number NaN). */
void hpy_block_store(hpy_block *b, npy_intp i, const hp_trace_row *row, const hp_result *r);
/* The dict of arrays; the block is left to the caller to free. NULL on failure. */
PyObject *hpy_block_dict(const hpy_block *b);

/* ---- functions (py_iab.c, py_analyze.c) ---- */
PyObject *hpy_iab_ik(PyObject *self, PyObject *args, PyObject *kwargs);
PyObject *hpy_iab_fk(PyObject *self, PyObject *args, PyObject *kwargs);
PyObject *hpy_analyze(PyObject *self, PyObject *args, PyObject *kwargs);
PyObject *hpy_binding_names(PyObject *self, PyObject *arg);
/* headplan.columns() (py_block.c) */
PyObject *hpy_columns(PyObject *self, PyObject *unused);

#endif
