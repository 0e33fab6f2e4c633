/* The block of planned rows behind plan_many's and run_trace's dicts: one array per column
 * of the library's column table (hp_trace_columns.h) that has a NumPy key, its dtype and
 * shape from the table, filled without the GIL and turned into arrays with it. */
#include "hpy.h"

#include <stdlib.h>
#include <string.h>

/* The table's column j goes into this block: it has a NumPy key, and a trace-row column
 * only when the block has trace rows. */
static int in_block(const hpy_block *b, const hp_column *c)
{
    return c->numpy && (c->source != HP_COLUMN_FROM_ROW || b->with_rows);
}

int hpy_block_alloc(hpy_block *b, npy_intp rows, int n, int with_rows)
{
    memset(b, 0, sizeof *b);
    b->rows = rows;
    b->n = n;
    b->with_rows = with_rows;
    const hp_column *t = hp_columns(&b->ncols);
    size_t r = rows > 0 ? (size_t)rows : 1;
    for (size_t j = 0; j < b->ncols; ++j) {
        if (!in_block(b, &t[j])) continue;
        b->v[j] = malloc(r * (size_t)hp_column_width(&t[j], n) * sizeof(double));
        if (!b->v[j]) {
            hpy_block_free(b);
            return -1;
        }
    }
    return 0;
}

void hpy_block_free(hpy_block *b)
{
    for (size_t j = 0; j < HP_COLUMNS_MAX; ++j) free(b->v[j]);
    memset(b, 0, sizeof *b);
}

void hpy_block_store(hpy_block *b, npy_intp i, const hp_trace_row *row, const hp_result *r)
{
    const hp_column *t = hp_columns(NULL);
    for (size_t j = 0; j < b->ncols; ++j)
        if (b->v[j]) {
            int w = hp_column_width(&t[j], b->n);
            hp_column_values(&t[j], b->n, row, r, &b->v[j][i * w]);
        }
}

/* Column j's values as a new array of its dtype: N, or N×width. */
static PyObject *column_array(const hpy_block *b, const hp_column *c, const double *v)
{
    const npy_intp N = b->rows;
    const int w = hp_column_width(c, b->n);
    const size_t count = (size_t)N * (size_t)w;
    if (strcmp(c->numpy_dtype, "str") == 0) {
        const char **names = malloc((count ? count : 1) * sizeof *names);
        if (!names) return PyErr_NoMemory();
        for (size_t i = 0; i < count; ++i) names[i] = hp_column_text(c, v[i]);
        PyObject *a = hpy_str_array(names, (npy_intp)count);
        free(names);
        return a;
    }
    const int type = strcmp(c->numpy_dtype, "int32") == 0    ? NPY_INT32
                     : strcmp(c->numpy_dtype, "int64") == 0  ? NPY_INT64
                     : strcmp(c->numpy_dtype, "uint32") == 0 ? NPY_UINT32
                                                             : NPY_DOUBLE;
    PyArrayObject *a = hpy_new(c->shape == HP_COLUMN_ONE ? 1 : 2, N, w, type);
    if (!a) return NULL;
    void *d = PyArray_DATA(a);
    for (size_t i = 0; i < count; ++i) {
        switch (type) {
        case NPY_INT32: ((npy_int32 *)d)[i] = (npy_int32)v[i]; break;
        case NPY_INT64: ((npy_int64 *)d)[i] = (npy_int64)v[i]; break;
        case NPY_UINT32: ((npy_uint32 *)d)[i] = (npy_uint32)v[i]; break;
        default: ((double *)d)[i] = v[i]; break;
        }
    }
    return (PyObject *)a;
}

PyObject *hpy_block_dict(const hpy_block *b)
{
    const hp_column *t = hp_columns(NULL);
    PyObject *d = PyDict_New();
    for (size_t j = 0; d && j < b->ncols; ++j)
        if (b->v[j] && hpy_put(d, t[j].numpy, column_array(b, &t[j], b->v[j])) < 0) Py_CLEAR(d);
    return d;
}

PyObject *hpy_columns(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    size_t nt;
    const hp_column *t = hp_columns(&nt);
    PyObject *list = PyList_New(0);
    for (size_t j = 0; list && j < nt; ++j) {
        PyObject *d = Py_BuildValue(
            "{s:s,s:s,s:s,s:s,s:O,s:z,s:z,s:O}", "name", t[j].name, "unit", t[j].unit, "format",
            hp_column_format_name(t[j].format), "shape", hp_column_shape_name(t[j].shape), "rows",
            t[j].in_rows ? Py_True : Py_False, "numpy", t[j].numpy, "dtype", t[j].numpy_dtype,
            "measured", t[j].measured ? Py_True : Py_False);
        if (!d || PyList_Append(list, d) < 0) Py_CLEAR(list);
        Py_XDECREF(d);
    }
    return list;
}
