/* The one table of a planned trace row's columns (hp_trace_columns.h). */
#include "headplan/hp_trace_columns.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* ---- values: one function per column (or per family), in the column's units ---- */

static void get_line(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)r;
    o[0] = (double)row->line;
}
static void get_t(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)r;
    o[0] = row->t;
}
static void get_status(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    o[0] = (double)r->status;
}
static void get_desired(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    hp_pose_to_clinical(r->desired, o);
}
static void get_achieved(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    hp_pose_to_clinical(r->achieved, o);
}
static void get_error(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    double want[6];
    hp_pose_to_clinical(r->desired, want);
    hp_pose_to_clinical(r->achieved, o);
    for (int i = 0; i < 6; ++i) o[i] -= want[i];
}
static void get_commanded(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    for (int i = 0; i < 6; ++i) o[i] = r->commanded[i] ? 1.0 : 0.0;
}
static void get_uncommanded(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    hp_pose_to_clinical(r->uncommanded, o);
}
/* The largest |achieved − desired| over the commanded translations (first) or rotations,
 * NaN propagating: what the row's error is in the clinic's two units. */
static double worst_error(const hp_result *r, int from)
{
    double e[6], worst = 0.0;
    get_error(NULL, r, e);
    for (int i = from; i < from + 3; ++i)
        if (r->commanded[i] && !(fabs(e[i]) <= worst)) worst = fabs(e[i]);
    return worst;
}
static void get_error_mm(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    o[0] = worst_error(r, 0);
}
static void get_error_deg(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    o[0] = worst_error(r, 3);
}
static void get_pose_error(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    o[0] = r->pose_error;
}
/* A double field of every bladder's result (offset in hp_bladder_result), times scale. */
static void per_bladder(const hp_result *r, size_t field, double scale, double *o)
{
    for (int k = 0; k < r->n; ++k) {
        double v;
        memcpy(&v, (const char *)&r->bladders[k] + field, sizeof v);
        o[k] = v * scale;
    }
}
static void get_pressure(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    per_bladder(r, offsetof(hp_bladder_result, pressure), 1.0, o);
}
static void get_ri(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    per_bladder(r, offsetof(hp_bladder_result, ri), 1e3, o); /* mm */
}
static void get_ro(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    per_bladder(r, offsetof(hp_bladder_result, ro), 1e3, o);
}
static void get_stretch(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    per_bladder(r, offsetof(hp_bladder_result, stretch), 1.0, o);
}
static void get_binding(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    for (int k = 0; k < r->n; ++k) o[k] = (double)r->bladders[k].binding;
}
static void get_iterations(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    o[0] = (double)r->iterations;
}
static void get_solve_time(const hp_trace_row *row, const hp_result *r, double *o)
{
    (void)row;
    o[0] = round(r->solve_time * 1e9) / 1e3; /* whole nanoseconds */
}

/* ---- the table: the rows' column order; the NumPy dict follows it too ---- */

/* name, unit, format, shape, source, in the rows, NumPy key and dtype, measured, value */
#define C(name, unit, fmt, shape, src, rows, key, dtype, measured, get)                            \
    {                                                                                              \
        name, unit, HP_COLUMN_##fmt, HP_COLUMN_##shape, HP_COLUMN_FROM_##src, rows, key, dtype,    \
            measured, get                                                                          \
    }
static const hp_column TABLE[] = {
    C("line", "1", INTEGER, ONE, ROW, 1, "line", "int64", 0, get_line),
    C("t_s", "s", NUMBER, ONE, ROW, 1, "t_s", "float64", 0, get_t),
    C("status", "-", TEXT, ONE, RESULT, 1, "status", "str", 0, get_status),
    C("status_code", "-", INTEGER, ONE, RESULT, 0, "status_code", "int32", 0, get_status),
    C("desired_{axis}_{unit}", "mm|deg", NUMBER, AXES, RESULT, 1, "desired", "float64", 0,
      get_desired),
    C("achieved_{axis}_{unit}", "mm|deg", NUMBER, AXES, RESULT, 1, "achieved", "float64", 0,
      get_achieved),
    C("error_{axis}_{unit}", "mm|deg", NUMBER, AXES, RESULT, 1, "error", "float64", 0, get_error),
    C("commanded_{axis}", "1", INTEGER, AXES, RESULT, 1, NULL, NULL, 0, get_commanded),
    /* The part of the desired correction the layout cannot observe (status uncommanded when
     * beyond the tolerance): never silently dropped. */
    C("uncommanded_{axis}_{unit}", "mm|deg", NUMBER, AXES, RESULT, 1, NULL, NULL, 0,
      get_uncommanded),
    C("pose_error_mm", "mm", NUMBER, ONE, RESULT, 1, NULL, NULL, 0, get_error_mm),
    C("pose_error_deg", "deg", NUMBER, ONE, RESULT, 1, NULL, NULL, 0, get_error_deg),
    /* The planner's own: against the commanded part of the desired correction. */
    C("pose_error", "mm|deg", NUMBER, ONE, RESULT, 0, "pose_error", "float64", 0, get_pose_error),
    C("{bladder}_pressure_pa", "Pa", NUMBER, BLADDERS, RESULT, 1, "pressure_pa", "float64", 0,
      get_pressure),
    C("{bladder}_ri_mm", "mm", NUMBER, BLADDERS, RESULT, 1, "ri_mm", "float64", 0, get_ri),
    C("{bladder}_ro_mm", "mm", NUMBER, BLADDERS, RESULT, 1, "ro_mm", "float64", 0, get_ro),
    C("{bladder}_stretch", "1", NUMBER, BLADDERS, RESULT, 1, "stretch", "float64", 0, get_stretch),
    C("binding", "-", FLAGS, BLADDERS, RESULT, 1, "binding", "uint32", 0, get_binding),
    C("iterations", "1", INTEGER, ONE, RESULT, 1, "iterations", "int32", 0, get_iterations),
    C("solve_time_us", "us", NUMBER, ONE, RESULT, 1, "solve_time_us", "float64", 1, get_solve_time),
    C("error", "-", TEXT, ONE, MESSAGE, 1, NULL, NULL, 0, NULL),
};
#undef C
#define NCOLS (sizeof TABLE / sizeof TABLE[0])
_Static_assert(NCOLS <= HP_COLUMNS_MAX, "HP_COLUMNS_MAX bounds the table");

const hp_column *hp_columns(size_t *count)
{
    if (count) *count = NCOLS;
    return TABLE;
}

const hp_column *hp_column_find(const char *name)
{
    for (size_t i = 0; name && i < NCOLS; ++i)
        if (strcmp(TABLE[i].name, name) == 0) return &TABLE[i];
    return NULL;
}

int hp_column_width(const hp_column *c, int n)
{
    if (!c) return 0;
    return c->shape == HP_COLUMN_AXES ? 6 : c->shape == HP_COLUMN_BLADDERS ? n : 1;
}

/* Appends len bytes of s at buf[*used] (size bytes); 0 when they did not fit. */
static int put(char *buf, size_t size, size_t *used, const char *s, size_t len)
{
    size_t room = size - 1 - *used, c = len < room ? len : room;
    memcpy(buf + *used, s, c);
    *used += c;
    buf[*used] = '\0';
    /* c < len when room < len: cppcheck takes c for len in every branch. */
    // cppcheck-suppress knownConditionTrueFalse
    return c == len;
}

hp_error hp_column_name(const hp_column *c, int k, const hp_layout *L, char *buf, size_t size)
{
    if (!c || !buf || !size || (c->shape == HP_COLUMN_BLADDERS && !L)) return HP_ERR_NULL;
    buf[0] = '\0';
    if ((c->shape == HP_COLUMN_AXES && (k < 0 || k >= 6)) ||
        (c->shape == HP_COLUMN_BLADDERS && (k < 0 || k >= L->n)))
        return HP_ERR_INVALID;
    /* The axis's key is "AXIS_UNIT" (hp_pose_key). */
    const char *key = c->shape == HP_COLUMN_AXES ? hp_pose_key(k) : "";
    size_t axis_len = strcspn(key, "_");
    size_t used = 0;
    int fits = 1;
    for (const char *p = c->name; *p && fits;) {
        if (strncmp(p, "{axis}", 6) == 0) {
            fits = put(buf, size, &used, key, axis_len);
            p += 6;
        } else if (strncmp(p, "{unit}", 6) == 0) {
            fits = put(buf, size, &used, key + axis_len + 1, strlen(key + axis_len + 1));
            p += 6;
        } else if (strncmp(p, "{bladder}", 9) == 0) {
            const char *nm = L->bladders[k].name;
            fits = put(buf, size, &used, nm, strlen(nm));
            p += 9;
        } else {
            fits = put(buf, size, &used, p, 1);
            p += 1;
        }
    }
    return fits ? HP_OK : HP_ERR_INVALID;
}

int hp_column_values(const hp_column *c, int n, const hp_trace_row *row, const hp_result *r,
                     double *out)
{
    int w = hp_column_width(c, n);
    if (!c || !out) return 0;
    if (c->source == HP_COLUMN_FROM_ROW && row) {
        c->get(row, r, out);
    } else if (c->source == HP_COLUMN_FROM_RESULT && r) {
        c->get(row, r, out);
    } else {
        /* A row the reader refused: nothing planned. */
        double none = c->format == HP_COLUMN_NUMBER || c->source == HP_COLUMN_FROM_MESSAGE ? NAN
                      : c->get == get_status                                               ? -1.0
                                                                                           : 0.0;
        for (int i = 0; i < w; ++i) out[i] = none;
    }
    return w;
}

const char *hp_column_text(const hp_column *c, double v)
{
    if (!c || c->get != get_status) return NULL;
    return v < 0 ? "bad-row" : hp_status_name((hp_status)v);
}

const char *hp_column_format_name(hp_column_format f)
{
    static const char *const names[] = {"number", "integer", "flags", "text"};
    return (unsigned)f < sizeof names / sizeof names[0] ? names[f] : "unknown";
}

const char *hp_column_shape_name(hp_column_shape s)
{
    static const char *const names[] = {"one", "axes", "bladders"};
    return (unsigned)s < sizeof names / sizeof names[0] ? names[s] : "unknown";
}
