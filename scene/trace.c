/* Streaming reader of correction/deviation traces in CSV or JSON Lines (see hp_trace.h). */
#define _POSIX_C_SOURCE 200809L
#include "headplan/hp_trace.h"
#include "headplan/hp_pose.h"
#include "scene/strict_number.h"
#include "scene/text_check.h"

#include <ctype.h>
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define TRACE_NAME_MAX 256
#define FORM_COLS_MAX 17
#define DIRECTIVE "# headplan-trace: rows="

/* The columns of each pose form, t_s first. */
typedef struct form_cols {
    int n;
    const char *key[FORM_COLS_MAX];
} form_cols;

static const form_cols FORMS[3] = {
    {7, {"t_s", "x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"}},
    {8, {"t_s", "x_mm", "y_mm", "z_mm", "qw", "qx", "qy", "qz"}},
    {17,
     {"t_s", "m00", "m01", "m02", "m03_mm", "m10", "m11", "m12", "m13_mm", "m20", "m21", "m22",
      "m23_mm", "m30", "m31", "m32", "m33"}},
};

struct hp_trace_reader {
    FILE *f;
    int owns_f;
    char *mem; /* copy of an in-memory trace (fmemopen does not copy) */
    char line[HP_TRACE_LINE_MAX + 1];
    size_t len;
    size_t noeol_col; /* a last line without its end of line: where that would begin */
    long lineno;
    hp_trace_format format;
    hp_trace_rows rows;
    hp_trace_form form;
    int form_known; /* JSON Lines: set by the first data row */
    char name[TRACE_NAME_MAX];
    int pending; /* non-zero: `line` holds a line (this read_line code) not yet used */
    int stopped; /* a line passed the limit: the reader cannot go on */
    int stated;  /* the file states the kind of its rows */
    int read_errno;
};

hp_trace_rows hp_trace_rows_of(const hp_trace_reader *r) { return r->rows; }
hp_trace_form hp_trace_form_of(const hp_trace_reader *r) { return r->form; }
int hp_trace_states_rows(const hp_trace_reader *r) { return r->stated; }

void hp_trace_close(hp_trace_reader *r)
{
    if (!r) return;
    if (r->f && r->owns_f) fclose(r->f);
    free(r->mem);
    free(r);
}

/* Line-reading outcomes. */
enum { LINE_OK = 1, LINE_EOF = 0, LINE_IOERR = -1, LINE_LONG = -2, LINE_NOEOL = -3 };

/* Reads one physical line into r->line without its end of line, one byte at a time, so
 * that nothing past the line is consumed and a line is refused as soon as it passes the
 * limit (a stream without newlines, /dev/zero, cannot grow memory or loop). */
static int read_line(hp_trace_reader *r)
{
    size_t n = 0;
    int c;
    errno = 0;
    while ((c = getc_unlocked(r->f)) != EOF && c != '\n') {
        if (n == HP_TRACE_LINE_MAX) {
            r->lineno++;
            r->stopped = 1;
            return LINE_LONG;
        }
        r->line[n++] = (char)c;
    }
    if (c == EOF) {
        if (ferror(r->f)) {
            r->read_errno = errno;
            return LINE_IOERR;
        }
        if (n == 0) return LINE_EOF;
    }
    r->lineno++;
    if (r->lineno == 1 && n >= 3 && memcmp(r->line, "\xEF\xBB\xBF", 3) == 0) {
        memmove(r->line, r->line + 3, n - 3); /* a UTF-8 byte-order mark is skipped */
        n -= 3;
    }
    /* Counted before a '\r' is dropped, as the other columns count the line's bytes (and
     * as the calibration reader counts them). */
    r->noeol_col = n + 1;
    if (n > 0 && r->line[n - 1] == '\r') --n;
    r->line[n] = '\0';
    r->len = n;
    return c == EOF ? LINE_NOEOL : LINE_OK;
}

/* The one-line message for a line that could not be read, or HP_OK for a clean line. */
static hp_error line_problem(const hp_trace_reader *r, int code, hp_diag *diag)
{
    if (code == LINE_IOERR)
        return hp_diag_set(diag, HP_ERR_IO, "%s: cannot read: %s", r->name,
                           r->read_errno ? strerror(r->read_errno) : "I/O error");
    if (code == LINE_LONG)
        return hp_diag_set(diag, HP_ERR_STATE,
                           "%s:%ld: line longer than %d bytes; the rest is not read", r->name,
                           r->lineno, HP_TRACE_LINE_MAX);
    if (code == LINE_NOEOL)
        return hp_diag_set(diag, HP_ERR_PARSE,
                           "%s:%ld:%zu: truncated: the last line has no end of line", r->name,
                           r->lineno, r->noeol_col);
    int nul = 0;
    long at = hpi_text_bad_byte(r->line, r->len, &nul);
    if (at >= 0)
        return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld:%ld: %s", r->name, r->lineno, at + 1,
                           nul ? "NUL byte" : "invalid UTF-8");
    return HP_OK;
}

static int is_blank(const char *s)
{
    for (; *s; ++s)
        if (*s != ' ' && *s != '\t') return 0;
    return 1;
}

/* A comment that a reader could take for a directive: '#', blanks, then "headplan" or
 * "rows" in any case. Such a line must be the exact directive on line 1. */
static int looks_like_directive(const char *s)
{
    if (s[0] != '#') return 0;
    const char *p = s + 1;
    while (*p == ' ' || *p == '\t') ++p;
    return strncasecmp(p, "headplan", 8) == 0 || strncasecmp(p, "rows", 4) == 0;
}

/* Parses line 1 as the directive; returns HP_OK and sets *rows, or the error with column. */
static hp_error csv_directive(const hp_trace_reader *r, hp_trace_rows *rows, hp_diag *diag)
{
    size_t k = strlen(DIRECTIVE);
    size_t i = 0;
    while (i < k && r->line[i] == DIRECTIVE[i]) ++i;
    if (i < k || hp_trace_rows_parse(r->line + k, rows) != HP_OK)
        return hp_diag_set(diag, HP_ERR_PARSE,
                           "%s:%ld:%zu: directive must read exactly '" DIRECTIVE
                           "deviation' or '" DIRECTIVE "correction'",
                           r->name, r->lineno, i + 1);
    return HP_OK;
}

static hp_error csv_header(hp_trace_reader *r, int *stated, hp_trace_rows *rows, hp_diag *diag)
{
    for (;;) {
        int rc = r->pending ? r->pending : read_line(r);
        r->pending = 0;
        if (rc == LINE_EOF)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s: empty trace: no header line", r->name);
        hp_error e = line_problem(r, rc, diag);
        if (e != HP_OK) return e;
        if (looks_like_directive(r->line)) {
            if (r->lineno != 1)
                return hp_diag_set(diag, HP_ERR_PARSE,
                                   "%s:%ld:1: a directive must be the first line", r->name,
                                   r->lineno);
            if ((e = csv_directive(r, rows, diag))) return e;
            *stated = 1;
            continue;
        }
        if (is_blank(r->line) || r->line[0] == '#') continue;
        for (int f = 0; f < 3; ++f) {
            char want[256];
            size_t used = 0;
            for (int c = 0; c < FORMS[f].n; ++c)
                used += (size_t)snprintf(want + used, sizeof want - used, "%s%s", c ? "," : "",
                                         FORMS[f].key[c]);
            if (strcmp(r->line, want) == 0) {
                r->form = (hp_trace_form)f;
                return HP_OK;
            }
        }
        return hp_diag_set(diag, HP_ERR_PARSE,
                           "%s:%ld:1: header must be 't_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,"
                           "yaw_deg' (or the quaternion or 4x4 form of docs/batch.md)",
                           r->name, r->lineno);
    }
}

/* A JSON Lines file may start with {"headplan_trace": 1, "rows": "..."}; a first line that
 * is anything else is kept as data. */
static hp_error jsonl_header(hp_trace_reader *r, int *stated, hp_trace_rows *rows, hp_diag *diag)
{
    for (;;) {
        int rc = r->pending ? r->pending : read_line(r);
        r->pending = 0;
        if (rc == LINE_EOF) return HP_OK;
        if (rc == LINE_IOERR || rc == LINE_LONG) return line_problem(r, rc, diag);
        hp_diag scratch;
        if (rc != LINE_OK || line_problem(r, rc, &scratch) != HP_OK) {
            r->pending = rc; /* a bad line: hp_trace_next reports it */
            return HP_OK;
        }
        if (!is_blank(r->line)) {
            r->pending = rc;
            break;
        }
    }
    json_error_t jerr;
    json_t *obj = json_loadb(r->line, r->len, JSON_REJECT_DUPLICATES, &jerr);
    hp_error e = HP_OK;
    if (obj && json_is_object(obj) &&
        (json_object_get(obj, "headplan_trace") || json_object_get(obj, "rows"))) {
        r->pending = 0;
        json_t *v = json_object_get(obj, "headplan_trace");
        const char *s = json_string_value(json_object_get(obj, "rows"));
        if (!v || !json_is_integer(v) || json_integer_value(v) != 1 || !s ||
            json_object_size(obj) != 2 || hp_trace_rows_parse(s, rows) != HP_OK)
            e = hp_diag_set(diag, HP_ERR_PARSE,
                            "%s:%ld:1: header record must be exactly "
                            "{\"headplan_trace\": 1, \"rows\": \"deviation\"} (or \"correction\")",
                            r->name, r->lineno);
        else *stated = 1;
    }
    json_decref(obj);
    return e;
}

/* Settles the kind of rows from the file's statement and the caller's. */
static hp_error settle_rows(hp_trace_reader *r, int stated, hp_trace_rows file_rows,
                            const hp_trace_rows *rows, const char *rows_from, hp_diag *diag)
{
    const char *from = rows_from ? rows_from : "the caller";
    if (stated && rows && *rows != file_rows)
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "%s: the trace states rows=%s but %s says %s: they must agree", r->name,
                           hp_trace_rows_name(file_rows), from, hp_trace_rows_name(*rows));
    if (!stated && !rows)
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "%s: does not state what its rows are: start it with '" DIRECTIVE
                           "deviation' (or correction; JSON Lines: "
                           "{\"headplan_trace\": 1, \"rows\": ...}), or give %s",
                           r->name, from);
    r->rows = stated ? file_rows : *rows;
    r->stated = stated;
    return HP_OK;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

/* format: HP_TRACE_CSV / HP_TRACE_JSONL, or -1 to take it from the name or the content. */
static hp_error open_common(hp_trace_reader *r, int format, const hp_trace_rows *rows,
                            const char *rows_from, hp_trace_reader **out, hp_diag *diag)
{
    if (format < 0) {
        if (ends_with(r->name, ".csv")) format = HP_TRACE_CSV;
        else if (ends_with(r->name, ".jsonl") || ends_with(r->name, ".ndjson"))
            format = HP_TRACE_JSONL;
    }
    if (format < 0) {
        /* Look at the first non-blank line, keeping it for the header reader: no rewind. */
        int rc;
        while ((rc = read_line(r)) == LINE_OK && is_blank(r->line)) {}
        if (rc == LINE_OK || rc == LINE_NOEOL) r->pending = rc;
        if (rc == LINE_IOERR || rc == LINE_LONG) {
            hp_error e = line_problem(r, rc, diag);
            hp_trace_close(r);
            return e;
        }
        format = (r->pending && r->line[strspn(r->line, " \t")] == '{') ? HP_TRACE_JSONL
                                                                        : HP_TRACE_CSV;
    }
    r->format = (hp_trace_format)format;
    int stated = 0;
    hp_trace_rows file_rows = HP_TRACE_CORRECTION;
    hp_error e = r->format == HP_TRACE_CSV ? csv_header(r, &stated, &file_rows, diag)
                                           : jsonl_header(r, &stated, &file_rows, diag);
    if (e == HP_OK) e = settle_rows(r, stated, file_rows, rows, rows_from, diag);
    if (e != HP_OK) {
        hp_trace_close(r);
        return e;
    }
    *out = r;
    return HP_OK;
}

static hp_trace_reader *new_reader(const char *name)
{
    hp_trace_reader *r = calloc(1, sizeof *r);
    if (r) snprintf(r->name, sizeof r->name, "%s", name ? name : "<trace>");
    return r;
}

hp_error hp_trace_open_stream(FILE *f, const char *name, const hp_trace_rows *rows,
                              const char *rows_from, hp_trace_reader **out, hp_diag *diag)
{
    if (!f || !out) return hp_diag_set(diag, HP_ERR_NULL, "trace: NULL argument");
    *out = NULL;
    hp_trace_reader *r = new_reader(name);
    if (!r) return hp_diag_set(diag, HP_ERR_NOMEM, "%s: out of memory", name ? name : "trace");
    r->f = f;
    return open_common(r, -1, rows, rows_from, out, diag);
}

hp_error hp_trace_open(const char *path, const hp_trace_rows *rows, hp_trace_reader **out,
                       hp_diag *diag)
{
    if (!path || !out) return hp_diag_set(diag, HP_ERR_NULL, "trace: NULL argument");
    *out = NULL;
    hp_trace_reader *r = new_reader(path);
    if (!r) return hp_diag_set(diag, HP_ERR_NOMEM, "%s: out of memory", path);
    r->f = fopen(path, "rb");
    if (!r->f) {
        hp_trace_close(r);
        return hp_diag_set(diag, HP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    }
    r->owns_f = 1;
    return open_common(r, -1, rows, NULL, out, diag);
}

hp_error hp_trace_open_mem(const char *data, size_t len, const char *name, hp_trace_format format,
                           const hp_trace_rows *rows, hp_trace_reader **out, hp_diag *diag)
{
    if (!data || !out) return hp_diag_set(diag, HP_ERR_NULL, "trace: NULL argument");
    *out = NULL;
    if (format != HP_TRACE_CSV && format != HP_TRACE_JSONL)
        return hp_diag_set(diag, HP_ERR_INVALID, "trace: unknown format");
    hp_trace_reader *r = new_reader(name);
    if (!r) return hp_diag_set(diag, HP_ERR_NOMEM, "trace: out of memory");
    /* fmemopen of a zero-length buffer fails on some libcs: keep one spare byte. */
    r->mem = malloc(len + 1);
    if (!r->mem) {
        hp_trace_close(r);
        return hp_diag_set(diag, HP_ERR_NOMEM, "%s: out of memory", r->name);
    }
    memcpy(r->mem, data, len);
    r->mem[len] = '\0';
    r->f = len ? fmemopen(r->mem, len, "rb") : fmemopen(r->mem, 1, "rb");
    if (!r->f) {
        hp_trace_close(r);
        return hp_diag_set(diag, HP_ERR_IO, "%s: cannot open in memory", name ? name : "trace");
    }
    r->owns_f = 1;
    if (len == 0) (void)fgetc(r->f); /* the spare byte is not data */
    return open_common(r, (int)format, rows, NULL, out, diag);
}

/* The row's values (form columns after t_s, in file units) -> the desired correction. */
static hp_error fill_row(const hp_trace_reader *r, long lineno, const double *v, hp_trace_row *row,
                         hp_diag *diag)
{
    double pose[6];
    hp_diag d; /* only read when a conversion fails; not zeroed (512 bytes) for every row */
    d.text[0] = '\0';
    hp_error e = HP_OK;
    if (r->form == HP_TRACE_ANGLES) {
        hp_pose_from_clinical(v + 1, pose);
    } else if (r->form == HP_TRACE_QUATERNION) {
        const double t[3] = {v[1] / 1e3, v[2] / 1e3, v[3] / 1e3};
        e = hp_pose_from_quaternion(t, v + 4, pose, &d);
    } else {
        double M[16];
        memcpy(M, v + 1, sizeof M);
        for (int i = 0; i < 3; ++i) M[i * 4 + 3] /= 1e3; /* mm -> m */
        e = hp_pose_from_matrix(M, pose, &d);
    }
    if (e != HP_OK) return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: %s", r->name, lineno, d.text);
    if (r->rows == HP_TRACE_DEVIATION) hp_pose_inverse(pose, pose);
    for (int i = 0; i < 6; ++i) {
        /* −0 compares equal to 0 but would print as "-0" in outputs: store +0. */
        /* cppcheck-suppress duplicateConditionalAssign ; the assignment turns -0 into +0 */
        if (pose[i] == 0.0) pose[i] = 0.0;
        row->correction[i] = pose[i];
    }
    row->t = v[0];
    return HP_OK;
}

static hp_error csv_row(hp_trace_reader *r, hp_trace_row *row, hp_diag *diag)
{
    double v[FORM_COLS_MAX];
    const form_cols *fc = &FORMS[r->form];
    const char *p = r->line, *end = r->line + r->len;
    for (int i = 0; i < fc->n; ++i) {
        const char *comma = memchr(p, ',', (size_t)(end - p));
        const char *stop = comma ? comma : end;
        if (i < fc->n - 1 && !comma)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: %d fields, expected %d", r->name,
                               r->lineno, i + 1, fc->n);
        if (i == fc->n - 1 && comma)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: more than %d fields", r->name,
                               r->lineno, fc->n);
        const char *why = hpi_strict_double(p, (size_t)(stop - p), &v[i]);
        if (why)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld:%ld: %s: %s", r->name, r->lineno,
                               (long)(p - r->line) + 1, fc->key[i], why);
        p = stop + 1;
    }
    return fill_row(r, r->lineno, v, row, diag);
}

/* The form whose keys are exactly obj's, or -1. */
static int json_form(json_t *obj)
{
    for (int f = 0; f < 3; ++f) {
        if (json_object_size(obj) != (size_t)FORMS[f].n) continue;
        int all = 1;
        for (int c = 0; c < FORMS[f].n && all; ++c)
            all = json_object_get(obj, FORMS[f].key[c]) != NULL;
        if (all) return f;
    }
    return -1;
}

static hp_error jsonl_row(hp_trace_reader *r, hp_trace_row *row, hp_diag *diag)
{
    json_error_t jerr;
    long ln = r->lineno;
    const char *ukey, *uwhy;
    size_t uklen;
    long at = hpi_json_out_of_range(r->line, r->len, &ukey, &uklen, &uwhy);
    if (at >= 0)
        return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld:%ld: %.*s: %s", r->name, ln, at + 1,
                           (int)uklen, ukey, uwhy);
    /* Every number as a double, as the CSV reader reads it: an integer beyond 64 bits was
     * "too big integer" here and a number (then out of range) in CSV. */
    json_t *obj = json_loadb(r->line, r->len, JSON_REJECT_DUPLICATES | JSON_DECODE_INT_AS_REAL,
                             &jerr);
    if (!obj)
        return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld:%d: %s", r->name, ln, jerr.column,
                           jerr.text);
    hp_error e = HP_OK;
    double v[FORM_COLS_MAX];
    int f = json_is_object(obj) ? json_form(obj) : -1;
    if (!json_is_object(obj)) {
        e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld:1: expected a JSON object", r->name, ln);
    } else if (json_object_get(obj, "headplan_trace") || json_object_get(obj, "rows")) {
        e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld:1: a header record must be the first line",
                        r->name, ln);
    } else if (f < 0 || (r->form_known && f != (int)r->form)) {
        const form_cols *want = &FORMS[r->form_known ? r->form : HP_TRACE_ANGLES];
        const char *key;
        json_t *val;
        const char *odd = NULL;
        json_object_foreach(obj, key, val)
        {
            int known = 0;
            for (int c = 0; c < want->n; ++c) known |= strcmp(key, want->key[c]) == 0;
            if (!known && !odd) odd = key;
        }
        for (int c = 0; c < want->n && !odd; ++c)
            if (!json_object_get(obj, want->key[c])) {
                e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: missing key '%s'", r->name, ln,
                                want->key[c]);
                goto done;
            }
        e = odd ? hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: unknown key '%s'", r->name, ln, odd)
                : hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: keys of another pose form", r->name, ln);
    } else {
        r->form = (hp_trace_form)f;
        r->form_known = 1;
        for (int c = 0; c < FORMS[f].n && e == HP_OK; ++c) {
            json_t *x = json_object_get(obj, FORMS[f].key[c]);
            if (!json_is_number(x))
                e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: %s: not a number", r->name, ln,
                                FORMS[f].key[c]);
            else if (!isfinite(v[c] = json_number_value(x)))
                e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: %s: not finite", r->name, ln,
                                FORMS[f].key[c]);
        }
        if (e == HP_OK) e = fill_row(r, ln, v, row, diag);
    }
done:
    json_decref(obj);
    return e;
}

hp_error hp_trace_next(hp_trace_reader *r, hp_trace_row *row, hp_diag *diag)
{
    if (!r || !row) return hp_diag_set(diag, HP_ERR_NULL, "trace: NULL argument");
    if (diag) diag->text[0] = '\0';
    if (r->stopped)
        return hp_diag_set(diag, HP_ERR_STATE,
                           "%s:%ld: line longer than %d bytes; the rest "
                           "is not read",
                           r->name, r->lineno, HP_TRACE_LINE_MAX);
    for (;;) {
        int rc = r->pending ? r->pending : read_line(r);
        r->pending = 0;
        if (rc == LINE_EOF) return HP_END;
        row->line = r->lineno;
        hp_error e = line_problem(r, rc, diag);
        if (e != HP_OK) return e;
        if (is_blank(r->line)) continue;
        if (r->format == HP_TRACE_JSONL) return jsonl_row(r, row, diag);
        if (r->line[0] != '#') return csv_row(r, row, diag);
        if (looks_like_directive(r->line))
            return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld:1: a directive must be the first line",
                               r->name, r->lineno);
    }
}
