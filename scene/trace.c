/* Streaming reader of correction/deviation traces in CSV or JSON Lines (see hp_trace.h). */
#define _POSIX_C_SOURCE 200809L
#include "headplan/hp_trace.h"
#include "headplan/hp_kinematics.h"
#include "scene/strict_number.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TRACE_LINE_MAX 4096
#define TRACE_NAME_MAX 256

static const char *const trace_keys[7] = {"t_s", "x_mm", "y_mm", "z_mm",
                                          "pitch_deg", "roll_deg", "yaw_deg"};

struct hp_trace_reader {
    FILE *f;
    char *mem;            /* copy of an in-memory trace (fmemopen does not copy) */
    char *line;           /* getline's buffer */
    size_t cap;
    long lineno;
    hp_trace_format format;
    hp_trace_rows rows;
    char name[TRACE_NAME_MAX];
    int pending;          /* a data line was read while looking for the header */
    char *pending_line;
    long pending_lineno;
    int read_errno;       /* errno of the last failed read (EISDIR for a directory) */
};

const char *hp_trace_rows_name(hp_trace_rows r)
{
    switch (r) {
    case HP_TRACE_CORRECTION: return "correction";
    case HP_TRACE_DEVIATION: return "deviation";
    }
    return "unknown";
}

hp_error hp_trace_rows_parse(const char *s, hp_trace_rows *out)
{
    if (!s || !out) return HP_ERR_NULL;
    if (strcmp(s, "correction") == 0) *out = HP_TRACE_CORRECTION;
    else if (strcmp(s, "deviation") == 0) *out = HP_TRACE_DEVIATION;
    else return HP_ERR_INVALID;
    return HP_OK;
}

const char *hp_trace_format_name(hp_trace_format f)
{
    switch (f) {
    case HP_TRACE_CSV: return "csv";
    case HP_TRACE_JSONL: return "jsonl";
    }
    return "unknown";
}

hp_error hp_trace_format_parse(const char *s, hp_trace_format *out)
{
    if (!s || !out) return HP_ERR_NULL;
    if (strcmp(s, "csv") == 0) *out = HP_TRACE_CSV;
    else if (strcmp(s, "jsonl") == 0) *out = HP_TRACE_JSONL;
    else return HP_ERR_INVALID;
    return HP_OK;
}

hp_trace_rows hp_trace_rows_of(const hp_trace_reader *r) { return r->rows; }

void hp_trace_close(hp_trace_reader *r)
{
    if (!r) return;
    if (r->f) fclose(r->f);
    free(r->mem);
    free(r->line);
    free(r->pending_line);
    free(r);
}

/* Reads one physical line without its end-of-line. Returns 1 with a line, 0 at the end,
 * -1 for an I/O error, -2 for a line that is too long, has a NUL byte, or lacks its final
 * newline (a truncated file). */
static int read_line(hp_trace_reader *r, size_t *len_out)
{
    errno = 0;
    ssize_t n = getline(&r->line, &r->cap, r->f);
    if (n < 0) {
        r->read_errno = errno;
        return ferror(r->f) ? -1 : 0;
    }
    r->lineno++;
    size_t len = (size_t)n;
    int had_newline = len > 0 && r->line[len - 1] == '\n';
    if (had_newline) r->line[--len] = '\0';
    if (len > 0 && r->line[len - 1] == '\r') r->line[--len] = '\0';
    *len_out = len;
    if (strlen(r->line) != len || len > TRACE_LINE_MAX || !had_newline) return -2;
    return 1;
}

static int is_blank(const char *s)
{
    for (; *s; ++s)
        if (*s != ' ' && *s != '\t') return 0;
    return 1;
}

static hp_error line_problem(const hp_trace_reader *r, int code, size_t len, hp_diag *diag)
{
    if (code == -1)
        return hp_diag_set(diag, HP_ERR_IO, "%s: cannot read: %s", r->name,
                           r->read_errno ? strerror(r->read_errno) : "I/O error");
    if (len > TRACE_LINE_MAX)
        return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: line longer than %d characters",
                           r->name, r->lineno, TRACE_LINE_MAX);
    if (strlen(r->line) != len)
        return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: NUL byte in line", r->name, r->lineno);
    return hp_diag_set(diag, HP_ERR_PARSE,
                       "%s:%ld: truncated: the last line has no end of line", r->name,
                       r->lineno);
}

/* "# rows: deviation" sets what the rows are; other comments are skipped. */
static hp_error csv_comment(hp_trace_reader *r, const char *s, int apply, hp_diag *diag)
{
    const char *p = s + 1;
    while (*p == ' ') ++p;
    if (strncmp(p, "rows:", 5) != 0) return HP_OK;
    p += 5;
    while (*p == ' ') ++p;
    char word[32];
    size_t n = strcspn(p, " \t");
    if (n == 0 || n >= sizeof word || !is_blank(p + n))
        return hp_diag_set(diag, HP_ERR_PARSE,
                           "%s:%ld: rows: expected 'deviation' or 'correction'", r->name,
                           r->lineno);
    memcpy(word, p, n);
    word[n] = '\0';
    hp_trace_rows rows;
    if (hp_trace_rows_parse(word, &rows) != HP_OK)
        return hp_diag_set(diag, HP_ERR_PARSE,
                           "%s:%ld: rows: '%s' is neither 'deviation' nor 'correction'",
                           r->name, r->lineno, word);
    if (apply) r->rows = rows;
    return HP_OK;
}

static hp_error csv_header(hp_trace_reader *r, int apply_rows, hp_diag *diag)
{
    for (;;) {
        size_t len = 0;
        int rc = read_line(r, &len);
        if (rc == 0)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s: empty trace: no header line", r->name);
        if (rc < 0) return line_problem(r, rc, len, diag);
        if (is_blank(r->line)) continue;
        if (r->line[0] == '#') {
            hp_error e = csv_comment(r, r->line, apply_rows, diag);
            if (e) return e;
            continue;
        }
        char want[128];
        snprintf(want, sizeof want, "%s,%s,%s,%s,%s,%s,%s", trace_keys[0], trace_keys[1],
                 trace_keys[2], trace_keys[3], trace_keys[4], trace_keys[5], trace_keys[6]);
        if (strcmp(r->line, want) != 0)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: header must be '%s'", r->name,
                               r->lineno, want);
        return HP_OK;
    }
}

/* A JSON Lines file may start with {"rows": "..."}; anything else is kept as data. */
static hp_error jsonl_header(hp_trace_reader *r, int apply_rows, hp_diag *diag)
{
    for (;;) {
        size_t len = 0;
        int rc = read_line(r, &len);
        if (rc == 0) return HP_OK;
        if (rc < 0) return line_problem(r, rc, len, diag);
        if (is_blank(r->line)) continue;
        json_error_t jerr;
        json_t *obj = json_loadb(r->line, len, JSON_REJECT_DUPLICATES, &jerr);
        if (obj && json_is_object(obj) && json_object_size(obj) == 1 &&
            json_object_get(obj, "rows")) {
            const char *s = json_string_value(json_object_get(obj, "rows"));
            hp_trace_rows rows;
            hp_error e = HP_OK;
            if (!s || hp_trace_rows_parse(s, &rows) != HP_OK)
                e = hp_diag_set(diag, HP_ERR_PARSE,
                                "%s:%ld: rows: expected \"deviation\" or \"correction\"",
                                r->name, r->lineno);
            else if (apply_rows)
                r->rows = rows;
            json_decref(obj);
            return e;
        }
        json_decref(obj);
        r->pending = 1;
        r->pending_line = strdup(r->line);
        r->pending_lineno = r->lineno;
        if (!r->pending_line) return hp_diag_set(diag, HP_ERR_NOMEM, "%s: out of memory", r->name);
        return HP_OK;
    }
}

static hp_error finish_open(hp_trace_reader *r, const hp_trace_rows *rows_override,
                            hp_trace_reader **out, hp_diag *diag)
{
    r->rows = rows_override ? *rows_override : HP_TRACE_CORRECTION;
    int apply = rows_override == NULL;
    hp_error e = r->format == HP_TRACE_CSV ? csv_header(r, apply, diag)
                                           : jsonl_header(r, apply, diag);
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

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

hp_error hp_trace_open(const char *path, const hp_trace_rows *rows_override,
                       hp_trace_reader **out, hp_diag *diag)
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
    if (ends_with(path, ".csv")) {
        r->format = HP_TRACE_CSV;
    } else if (ends_with(path, ".jsonl") || ends_with(path, ".ndjson")) {
        r->format = HP_TRACE_JSONL;
    } else {
        int c;
        do c = fgetc(r->f); while (c == ' ' || c == '\t' || c == '\n' || c == '\r');
        r->format = c == '{' ? HP_TRACE_JSONL : HP_TRACE_CSV;
        rewind(r->f);
    }
    return finish_open(r, rows_override, out, diag);
}

hp_error hp_trace_open_mem(const char *data, size_t len, const char *name,
                           hp_trace_format format, const hp_trace_rows *rows_override,
                           hp_trace_reader **out, hp_diag *diag)
{
    if (!data || !out) return hp_diag_set(diag, HP_ERR_NULL, "trace: NULL argument");
    *out = NULL;
    if (format != HP_TRACE_CSV && format != HP_TRACE_JSONL)
        return hp_diag_set(diag, HP_ERR_INVALID, "trace: unknown format");
    hp_trace_reader *r = new_reader(name);
    if (!r) return hp_diag_set(diag, HP_ERR_NOMEM, "trace: out of memory");
    r->format = format;
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
    if (len == 0) (void)fgetc(r->f); /* the spare byte is not data */
    return finish_open(r, rows_override, out, diag);
}

static hp_error fill_row(const hp_trace_reader *r, long lineno, const double v[7],
                         hp_trace_row *row, hp_diag *diag)
{
    double mm_deg[6];
    (void)diag;
    for (int i = 0; i < 6; ++i) {
        mm_deg[i] = r->rows == HP_TRACE_DEVIATION ? -v[i + 1] : v[i + 1];
        /* −0 compares equal to 0 but would print as "-0" in outputs: store +0. */
        /* cppcheck-suppress duplicateConditionalAssign ; the assignment turns -0 into +0 */
        if (mm_deg[i] == 0.0) mm_deg[i] = 0.0;
    }
    row->line = lineno;
    row->t = v[0];
    hp_pose_from_clinical(mm_deg, row->correction);
    return HP_OK;
}

static hp_error csv_row(hp_trace_reader *r, size_t len, hp_trace_row *row, hp_diag *diag)
{
    double v[7];
    const char *p = r->line, *end = r->line + len;
    for (int i = 0; i < 7; ++i) {
        const char *comma = memchr(p, ',', (size_t)(end - p));
        const char *stop = comma ? comma : end;
        if (i < 6 && !comma)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: %d fields, expected 7", r->name,
                               r->lineno, i + 1);
        if (i == 6 && comma)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: more than 7 fields", r->name,
                               r->lineno);
        const char *why = hp_strict_double(p, (size_t)(stop - p), &v[i]);
        if (why)
            return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: %s: %s", r->name, r->lineno,
                               trace_keys[i], why);
        p = stop + 1;
    }
    return fill_row(r, r->lineno, v, row, diag);
}

static hp_error jsonl_row(hp_trace_reader *r, const char *text, size_t len, long lineno,
                          hp_trace_row *row, hp_diag *diag)
{
    json_error_t jerr;
    json_t *obj = json_loadb(text, len, JSON_REJECT_DUPLICATES, &jerr);
    if (!obj)
        return hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld:%d: %s", r->name, lineno, jerr.column,
                           jerr.text);
    hp_error e = HP_OK;
    double v[7];
    if (!json_is_object(obj)) {
        e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: expected a JSON object", r->name, lineno);
        goto done;
    }
    const char *key;
    json_t *val;
    json_object_foreach(obj, key, val) {
        int known = 0;
        for (int i = 0; i < 7; ++i) known |= strcmp(key, trace_keys[i]) == 0;
        if (!known) {
            e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: unknown key '%s'", r->name, lineno,
                            key);
            goto done;
        }
    }
    for (int i = 0; i < 7; ++i) {
        json_t *x = json_object_get(obj, trace_keys[i]);
        if (!x) {
            e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: missing key '%s'", r->name, lineno,
                            trace_keys[i]);
            goto done;
        }
        if (!json_is_number(x)) {
            e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: %s: not a number", r->name, lineno,
                            trace_keys[i]);
            goto done;
        }
        v[i] = json_number_value(x);
        if (!isfinite(v[i])) {
            e = hp_diag_set(diag, HP_ERR_PARSE, "%s:%ld: %s: not finite", r->name, lineno,
                            trace_keys[i]);
            goto done;
        }
    }
    e = fill_row(r, lineno, v, row, diag);
done:
    json_decref(obj);
    return e;
}

hp_error hp_trace_next(hp_trace_reader *r, hp_trace_row *row, hp_diag *diag)
{
    if (!r || !row) return hp_diag_set(diag, HP_ERR_NULL, "trace: NULL argument");
    if (diag) diag->text[0] = '\0';
    if (r->pending) {
        r->pending = 0;
        hp_error e = jsonl_row(r, r->pending_line, strlen(r->pending_line), r->pending_lineno,
                               row, diag);
        free(r->pending_line);
        r->pending_line = NULL;
        return e;
    }
    for (;;) {
        size_t len = 0;
        int rc = read_line(r, &len);
        if (rc == 0) return HP_ERR_STATE;
        if (rc < 0) return line_problem(r, rc, len, diag);
        if (is_blank(r->line)) continue;
        if (r->format == HP_TRACE_CSV) {
            if (r->line[0] == '#') continue;
            return csv_row(r, len, row, diag);
        }
        return jsonl_row(r, r->line, len, r->lineno, row, diag);
    }
}
