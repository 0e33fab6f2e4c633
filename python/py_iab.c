/* headplan.ik / headplan.fk: one bladder's closed-form inverse kinematics (inner radius ->
 * pressure) and forward kinematics (pressure -> inner radius on the stable branch), over
 * arrays of any shape, the loop in C without the GIL. Units: mm and Pa. */
#include "hpy.h"

#include <string.h>

/* Parses (values, *, Ri_mm, Ro_mm, c1_pa, c2_pa) and checks the bladder. */
static PyArrayObject *bladder_args(const char *fn, const char *what, PyObject *args,
                                   PyObject *kwargs, hp_iab *b)
{
    static char *kw[] = {"values", "Ri_mm", "Ro_mm", "c1_pa", "c2_pa", NULL};
    PyObject *values, *Ri, *Ro, *c1, *c2;
    char fmt[64];
    snprintf(fmt, sizeof fmt, "O$OOOO:%s", fn);
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, fmt, kw, &values, &Ri, &Ro, &c1, &c2))
        return NULL;
    double Ri_mm, Ro_mm, C1, C2;
    if (hpy_double(Ri, "Ri_mm", &Ri_mm) || hpy_double(Ro, "Ro_mm", &Ro_mm) ||
        hpy_double(c1, "c1_pa", &C1) || hpy_double(c2, "c2_pa", &C2))
        return NULL;
    /* The radii in the caller's units and names, as headplan ik says them; the library's
     * check below says them in m. */
    if (!(Ri_mm > 0))
        return (PyArrayObject *)hpy_fail("%s: Ri_mm: must be > 0 mm (got %g)", fn, Ri_mm);
    if (!(Ro_mm > Ri_mm))
        return (PyArrayObject *)hpy_fail(
            "%s: Ro_mm: must be greater than Ri_mm (got Ro_mm %g, Ri_mm %g)", fn, Ro_mm, Ri_mm);
    *b = (hp_iab){Ri_mm * 1e-3, Ro_mm * 1e-3, C1, C2};
    hp_diag d = {{0}};
    if (hp_iab_validate(b, &d) != HP_OK)
        return (PyArrayObject *)hpy_fail("%s: bladder: %s", fn, d.text);
    return hpy_doubles(values, what, 1);
}

/* Fills out[i] for every in[i]; returns the index of the first failure (and its code in
 * *err), or -1. */
static npy_intp ik_loop(const hp_iab *b, const double *in, double *out, npy_intp n, hp_error *err)
{
    for (npy_intp i = 0; i < n; ++i) {
        hp_error e = hp_iab_ik(b, in[i] * 1e-3, &out[i]);
        if (e != HP_OK) {
            *err = e;
            return i;
        }
    }
    return -1;
}

static npy_intp fk_loop(const hp_iab *b, const hp_iab_limit *lp, const double *in, double *out,
                        npy_intp n, hp_error *err)
{
    for (npy_intp i = 0; i < n; ++i) {
        double ri;
        hp_error e = hp_iab_fk_limit(b, lp, in[i], &ri);
        if (e != HP_OK) {
            *err = e;
            return i;
        }
        out[i] = ri * 1e3;
    }
    return -1;
}

static PyObject *run(int fk, PyObject *args, PyObject *kwargs)
{
    const char *fn = fk ? "fk" : "ik", *what = fk ? "pressure_pa" : "ri_mm";
    hp_iab b;
    PyArrayObject *in = bladder_args(fn, what, args, kwargs, &b);
    if (!in) return NULL;
    PyArrayObject *out = (PyArrayObject *)PyArray_NewLikeArray(in, NPY_CORDER, NULL, 0);
    if (!out) {
        Py_DECREF(in);
        return NULL;
    }
    const double *x = PyArray_DATA(in);
    double *y = PyArray_DATA(out);
    npy_intp n = PyArray_SIZE(in), bad = -1;
    hp_error e = HP_OK;
    hp_iab_limit lp;
    Py_BEGIN_ALLOW_THREADS if (fk)
    {
        e = hp_iab_limit_point(&b, &lp);
        if (e == HP_OK) bad = fk_loop(&b, &lp, x, y, n, &e);
    }
    else
    {
        bad = ik_loop(&b, x, y, n, &e);
    }
    Py_END_ALLOW_THREADS PyObject *result = (PyObject *)out;
    if (e != HP_OK) {
        Py_DECREF(out);
        if (bad < 0) result = hpy_fail("%s: limit point: %s", fn, hp_error_message(e));
        else if (fk && e == HP_ERR_NO_STABLE)
            result = hpy_fail("%s: %s[%zd] = %.17g Pa: no stable radius (at or above the "
                              "limit-point pressure %.17g Pa)",
                              fn, what, (Py_ssize_t)bad, x[bad], lp.pressure);
        else
            result = hpy_fail("%s: %s[%zd] = %.17g: %s", fn, what, (Py_ssize_t)bad, x[bad],
                              hp_error_message(e));
    }
    Py_DECREF(in);
    return result;
}

PyObject *hpy_iab_ik(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    return run(0, args, kwargs);
}

PyObject *hpy_iab_fk(PyObject *self, PyObject *args, PyObject *kwargs)
{
    (void)self;
    return run(1, args, kwargs);
}
