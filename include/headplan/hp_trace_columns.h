/* The columns of a planned trace row: one table that every front-end reads. `headplan
 * batch` writes its CSV header and JSON Lines keys and every cell from it, the Python
 * module builds run_trace's and plan_many's arrays from it, `headplan plot` finds the
 * columns it draws in it, `headplan batch --columns` lists it for scripts (the jobs
 * comparisons blank its measured columns). A new column is one row of the table in
 * horizon/trace_columns.c (its name, unit, format, shape, NumPy key and value); every
 * consumer follows.
 *
 * A column's name is a pattern: {axis} is x, y, z, pitch, roll or yaw and {unit} that
 * axis's unit (mm for x, y, z, deg for the angles); {bladder} a bladder's name. An axes
 * column gives 6 values per row, a bladders column one per bladder (n). */
#ifndef HP_TRACE_COLUMNS_H
#define HP_TRACE_COLUMNS_H

#include "headplan/hp_common.h"
#include "headplan/hp_layout.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_trace.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Bounds a consumer may size its arrays by: the table's length, the values of one column
 * in one row (6 axes or up to HP_MAX_BLADDERS bladders), and a column's name with its
 * terminating NUL (for any bladder name of up to HP_NAME_MAX - 1 characters). */
#define HP_COLUMNS_MAX 64
#define HP_COLUMN_WIDTH_MAX (HP_MAX_BLADDERS > 6 ? HP_MAX_BLADDERS : 6)
#define HP_COLUMN_NAME_MAX (HP_NAME_MAX + 32)

typedef enum hp_column_format {
    HP_COLUMN_NUMBER,  /* a double: the shortest text that reads back to it; NaN: empty/null */
    HP_COLUMN_INTEGER, /* an integer */
    HP_COLUMN_FLAGS,   /* hp_binding flags per bladder; in the rows one text cell
                          "NAME:limit|limit;NAME:limit" of the bladders on a limit */
    HP_COLUMN_TEXT     /* text: the status name (its value is the hp_status code, -1 for a
                          row the reader refused), or the row's message */
} hp_column_format;

typedef enum hp_column_shape {
    HP_COLUMN_ONE,     /* one value per row */
    HP_COLUMN_AXES,    /* six, in the order x, y, z, pitch, roll, yaw */
    HP_COLUMN_BLADDERS /* one per bladder, in the layout's order */
} hp_column_shape;

typedef enum hp_column_source {
    HP_COLUMN_FROM_ROW,    /* the trace row (line, time stamp) */
    HP_COLUMN_FROM_RESULT, /* the row's planned hp_result */
    HP_COLUMN_FROM_MESSAGE /* why the row was not planned (a bad row's reader message) */
} hp_column_source;

typedef struct hp_column {
    const char *name; /* pattern of the rows' column names (see above) */
    const char *unit; /* "mm|deg" (axes: mm for x, y, z, deg for the angles), "Pa",
                                "s", "us", "1" (a number without unit), "-" (text, flags) */
    hp_column_format format;
    hp_column_shape shape;
    hp_column_source source;
    int in_rows;             /* 1: a column of batch's CSV and JSON Lines rows */
    const char *numpy;       /* its key in the Python module's dict of arrays, NULL: none */
    const char *numpy_dtype; /* that array's dtype: float64, int32, int64, uint32 or str */
    int measured;            /* 1: a measurement (time), not a function of the inputs: left
                                out of every comparison of two runs */
    /* Fills the column's values (1, 6 or n) of a row; internal: use hp_column_values. */
    void (*get)(const hp_trace_row *row, const hp_result *r, double *out);
} hp_column;

/* The table, in the order of the rows' columns; *count (may be NULL) receives its length
 * (at most HP_COLUMNS_MAX). Static. */
HP_API const hp_column *hp_columns(size_t *count);

/* The column whose pattern is name, or NULL. */
HP_API const hp_column *hp_column_find(const char *name);

/* The number of values of column c in one row of a layout of n bladders (1, 6 or n). */
HP_API int hp_column_width(const hp_column *c, int n);

/* Column c's name for value k (axis 0..5 or bladder 0..n-1 of L; k ignored for a ONE
 * column) into buf (size bytes). HP_OK, HP_ERR_NULL, HP_ERR_INVALID (k out of range, or the
 * name does not fit: buf then holds its truncated start). */
HP_API hp_error hp_column_name(const hp_column *c, int k, const hp_layout *L, char *buf,
                               size_t size);

/* Column c's values of one row into out (hp_column_width(c, n) of them): from row (for a
 * FROM_ROW column) and r (its planned result; NULL for a row the trace reader refused,
 * which gives NaN numbers, 0 integers and flags, and status -1). In the units of the
 * column: clinical (mm, degrees), radii in mm, pressures in Pa, the solve time in us
 * rounded to whole nanoseconds. A FROM_MESSAGE column gives NaN. Returns the count. */
HP_API int hp_column_values(const hp_column *c, int n, const hp_trace_row *row, const hp_result *r,
                            double *out);

/* The text of a TEXT column's value v (hp_column_values): the status name, "bad-row" for
 * -1. NULL for any other column. */
HP_API const char *hp_column_text(const hp_column *c, double v);

/* The names of a format and a shape, as `headplan batch --columns` prints them. */
HP_API const char *hp_column_format_name(hp_column_format f);
HP_API const char *hp_column_shape_name(hp_column_shape s);

#ifdef __cplusplus
}
#endif
#endif
