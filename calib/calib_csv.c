/* Readers of the calibration data files (CSV, and JSON Lines for layout rows; see hp_calib.h
 * and docs/calibration.md). They share one line reader; every number goes through the project's strict parser, and every
 * refusal names FILE:LINE:COL (1-based; the column of the field at fault). */
#define _POSIX_C_SOURCE 200809L
#include "headplan/hp_calib.h"
#include "common/units.h"
#include "scene/strict_number.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CSV_MAX_BYTES HP_CALIB_MAX_BYTES
#define CSV_MAX_FIELDS (HP_MAX_BLADDERS + 8)

typedef struct csv_field {
    const char *s;
    size_t len;
    int col; /* 1-based column of the field's first character */
} csv_field;

typedef struct csv_file {
    const char *path;
    char *text;
    size_t len, pos;
    long line;
} csv_file;

/* The file at path, or (text not NULL) a copy of the len bytes at text named path in
 * messages: the readers of files and of memory (a command's standard input) are one. */
static hp_error csv_open(csv_file *f, const char *path, const char *text, size_t len, hp_diag *d)
{
    memset(f, 0, sizeof *f);
    f->path = path;
    FILE *fp = text ? NULL : fopen(path, "rb");
    if (!text && !fp)
        return hp_diag_set(d, HP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    f->text = malloc((size_t)CSV_MAX_BYTES + 1);
    if (!f->text) {
        if (fp) fclose(fp);
        return hp_diag_set(d, HP_ERR_NOMEM, "%s: out of memory", path);
    }
    int bad = 0;
    if (text) {
        f->len = len > (size_t)CSV_MAX_BYTES ? (size_t)CSV_MAX_BYTES + 1 : len;
        memcpy(f->text, text, f->len > (size_t)CSV_MAX_BYTES ? (size_t)CSV_MAX_BYTES : f->len);
    } else {
        f->len = fread(f->text, 1, (size_t)CSV_MAX_BYTES + 1, fp);
        bad = ferror(fp);
        fclose(fp);
    }
    if (bad) return hp_diag_set(d, HP_ERR_IO, "%s: cannot read", path);
    if (f->len > (size_t)CSV_MAX_BYTES)
        return hp_diag_set(d, HP_ERR_PARSE, "%s: larger than %ld bytes", path, CSV_MAX_BYTES);
    f->text[f->len] = '\0';
    /* A UTF-8 byte-order mark (a spreadsheet's export may start with one) is skipped, as the
     * scene and trace readers skip it; columns count from after it. */
    if (f->len >= 3 && memcmp(f->text, "\xEF\xBB\xBF", 3) == 0) f->pos = 3;
    return HP_OK;
}

static void csv_close(csv_file *f) { free(f->text); }

/* The next line that is neither blank nor a '#' comment (without its line end). Returns 1
 * with the line, 0 at the end, -1 after a message. */
static int next_line(csv_file *f, const char **line, size_t *len, hp_diag *d)
{
    while (f->pos < f->len) {
        const char *s = f->text + f->pos;
        size_t n = 0;
        while (f->pos + n < f->len && s[n] != '\n') ++n;
        int noeol = f->pos + n == f->len;
        f->pos += n + !noeol;
        f->line++;
        /* As the trace reader: a file cut short mid-number ("36" cut to "3") must not read
         * as a different data point. */
        if (noeol) {
            hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%zu: truncated: the last line has no end of line",
                        f->path, f->line, n + 1);
            return -1;
        }
        size_t e = n;
        if (e > 0 && s[e - 1] == '\r') --e;
        if (memchr(s, '\0', e)) {
            hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: NUL byte in line", f->path, f->line);
            return -1;
        }
        size_t i = 0;
        while (i < e && (s[i] == ' ' || s[i] == '\t')) ++i;
        if (i == e || s[i] == '#') continue;
        *line = s;
        *len = e;
        return 1;
    }
    return 0;
}

/* The next data line split at commas (spaces around a field are trimmed). Returns 1 with
 * fields, 0 at the end, -1 after a message. */
static int csv_next(csv_file *f, csv_field *fl, int *nf, hp_diag *d)
{
    const char *s;
    size_t e;
    int r = next_line(f, &s, &e, d);
    if (r != 1) return r;
    *nf = 0;
    size_t start = 0;
    for (size_t k = 0; k <= e; ++k) {
        if (k < e && s[k] != ',') continue;
        if (*nf == CSV_MAX_FIELDS) {
            hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%zu: more than %d columns", f->path, f->line,
                        k + 1, CSV_MAX_FIELDS);
            return -1;
        }
        size_t a = start, b = k;
        while (a < b && (s[a] == ' ' || s[a] == '\t')) ++a;
        while (b > a && (s[b - 1] == ' ' || s[b - 1] == '\t')) --b;
        fl[*nf] = (csv_field){s + a, b - a, (int)a + 1};
        (*nf)++;
        start = k + 1;
    }
    return 1;
}

static int field_is(const csv_field *f, const char *name)
{
    return f->len == strlen(name) && memcmp(f->s, name, f->len) == 0;
}

/* A number of a field, with the file position in the message on failure. */
static hp_error number(const csv_file *f, const csv_field *fl, const char *what, double *v,
                       hp_diag *d)
{
    const char *why = hpi_strict_double(fl->s, fl->len, v);
    if (why)
        return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: %s: '%.*s': %s", f->path, f->line, fl->col,
                           what, (int)(fl->len > 40 ? 40 : fl->len), fl->s, why);
    return HP_OK;
}

static hp_error wrong_count(const csv_file *f, int got, int want, hp_diag *d)
{
    return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: %d columns, the header has %d", f->path, f->line,
                       got, want);
}

static hp_error read_material(const char *path, const char *text, size_t tlen, hp_calib_point *pts,
                              int max, int *n, hp_calib_radius *kind, hp_diag *d)
{
    if (!path || !pts || !n || !kind) return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    *n = 0;
    csv_file f;
    hp_error err = csv_open(&f, path, text, tlen, d);
    if (err) {
        csv_close(&f);
        return err;
    }
    csv_field fl[CSV_MAX_FIELDS];
    int nf = 0, r = csv_next(&f, fl, &nf, d);
    double pscale = 1.0;
    if (r == 0)
        err = hp_diag_set(d, HP_ERR_PARSE,
                          "%s:1:1: empty file (expected the header "
                          "pressure_pa,ri_mm or pressure_pa,ro_mm)",
                          path);
    else if (r < 0) err = HP_ERR_PARSE;
    if (!err) {
        if (nf != 2 && nf != 3)
            err = hp_diag_set(d, HP_ERR_PARSE,
                              "%s:%ld:1: header: expected pressure_pa,ri_mm[,sigma_mm] or "
                              "pressure_pa,ro_mm[,sigma_mm] (%d columns)",
                              path, f.line, nf);
        else if (field_is(&fl[0], "pressure_kpa")) pscale = 1e3;
        else if (!field_is(&fl[0], "pressure_pa"))
            err = hp_diag_set(d, HP_ERR_PARSE,
                              "%s:%ld:%d: header: first column must be pressure_pa or "
                              "pressure_kpa, found '%.*s'",
                              path, f.line, fl[0].col, (int)fl[0].len, fl[0].s);
    }
    if (!err) {
        if (field_is(&fl[1], "ri_mm")) *kind = HP_CALIB_INNER;
        else if (field_is(&fl[1], "ro_mm")) *kind = HP_CALIB_OUTER;
        else
            err = hp_diag_set(d, HP_ERR_PARSE,
                              "%s:%ld:%d: header: second column must be ri_mm or ro_mm, found "
                              "'%.*s'",
                              path, f.line, fl[1].col, (int)fl[1].len, fl[1].s);
        if (!err && nf == 3 && !field_is(&fl[2], "sigma_mm"))
            err = hp_diag_set(d, HP_ERR_PARSE,
                              "%s:%ld:%d: header: third column must be sigma_mm, found '%.*s'",
                              path, f.line, fl[2].col, (int)fl[2].len, fl[2].s);
    }
    int ncol = nf;
    while (!err && (r = csv_next(&f, fl, &nf, d)) == 1) {
        if (nf != ncol) {
            err = wrong_count(&f, nf, ncol, d);
            break;
        }
        if (*n == max) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: more than %d rows", path, f.line, max);
            break;
        }
        hp_calib_point p = {0, 0, 1e-3, f.line};
        double sig = 1.0;
        err = number(&f, &fl[0], "pressure", &p.pressure, d);
        if (!err)
            err = number(&f, &fl[1], *kind == HP_CALIB_INNER ? "ri_mm" : "ro_mm", &p.radius, d);
        if (!err && ncol == 3) err = number(&f, &fl[2], "sigma_mm", &sig, d);
        if (err) break;
        if (!(p.radius > 0)) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: %s: must be > 0 mm (got %g)", path,
                              f.line, fl[1].col, *kind == HP_CALIB_INNER ? "ri_mm" : "ro_mm",
                              p.radius);
            break;
        }
        if (!(sig > 0)) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: sigma_mm: must be > 0 (got %g)", path,
                              f.line, fl[2].col, sig);
            break;
        }
        p.pressure *= pscale;
        p.radius *= 1e-3;
        p.sigma = sig * 1e-3;
        if (!isfinite(p.pressure)) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: pressure: overflows", path, f.line,
                              fl[0].col);
            break;
        }
        pts[(*n)++] = p;
    }
    if (!err && r < 0) err = HP_ERR_PARSE;
    if (!err && *n < 3)
        err = hp_diag_set(d, HP_ERR_PARSE,
                          "%s:%ld:1: %d data rows: a fit of two moduli needs "
                          "at least 3",
                          path, f.line + 1, *n);
    csv_close(&f);
    if (err) *n = 0;
    return err;
}

hp_error hp_calib_read_material(const char *path, hp_calib_point *pts, int max, int *n,
                                hp_calib_radius *kind, hp_diag *d)
{
    return read_material(path, NULL, 0, pts, max, n, kind, d);
}

hp_error hp_calib_parse_material(const char *text, size_t len, const char *name,
                                 hp_calib_point *pts, int max, int *n, hp_calib_radius *kind,
                                 hp_diag *d)
{
    if (!text) return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    return read_material(name, text, len, pts, max, n, kind, d);
}

/* What a layout data column (or JSON key) holds: a bladder's pressure (role = its index,
 * scale to Pa) or a pose component (role = -1 - component, scale to m or rad); -100 when
 * the name is none of them. */
static int column_role(const hp_layout *L, const char *name, size_t len, double *scale)
{
    csv_field f = {name, len, 1};
    for (int j = 0; j < 6; ++j)
        if (field_is(&f, hp_pose_key(j))) {
            *scale = j < 3 ? 1e-3 : HP_RAD_PER_DEG;
            return -1 - j;
        }
    for (int k = 0; k < L->n; ++k) {
        char pa[HP_NAME_MAX + 8], kpa[HP_NAME_MAX + 8];
        snprintf(pa, sizeof pa, "p_%s_pa", L->bladders[k].name);
        snprintf(kpa, sizeof kpa, "p_%s_kpa", L->bladders[k].name);
        if (field_is(&f, pa) || field_is(&f, kpa)) {
            *scale = field_is(&f, pa) ? 1.0 : 1e3;
            return k;
        }
    }
    return -100;
}

/* Stores value v (SI) of a role in row, refusing a pressure outside the bladder's limits or
 * past its limit point; col is the position for the message. */
static hp_error store(const csv_file *f, const hp_layout *L, const hp_iab_limit *lp, int role,
                      double v, int col, hp_calib_row *row, hp_diag *d)
{
    if (role < 0) {
        row->pose[-1 - role] = v;
        return HP_OK;
    }
    const hp_bladder *b = &L->bladders[role];
    if (!(v >= b->p_min && v <= b->p_max))
        return hp_diag_set(d, HP_ERR_PARSE,
                           "%s:%ld:%d: p_%s: %g Pa outside the bladder's limits [%g, %g] Pa",
                           f->path, f->line, col, b->name, v, b->p_min, b->p_max);
    if (lp[role].exists && !(v < lp[role].pressure))
        return hp_diag_set(d, HP_ERR_PARSE,
                           "%s:%ld:%d: p_%s: %g Pa is past the bladder's limit point (%g Pa): "
                           "no stable radius",
                           f->path, f->line, col, b->name, v, lp[role].pressure);
    row->pressure[role] = v;
    return HP_OK;
}

static const char *role_name(const hp_layout *L, int role, char *buf, size_t cap)
{
    if (role >= 0) snprintf(buf, cap, "p_%s", L->bladders[role].name);
    else snprintf(buf, cap, "%s", hp_pose_key(-1 - role));
    return buf;
}

/* 1-based column of "key" in a JSON line (1 when not found). */
static int key_column(const char *s, size_t len, const char *key)
{
    size_t kl = strlen(key);
    for (size_t i = 0; i + kl + 2 <= len; ++i)
        if (s[i] == '"' && memcmp(s + i + 1, key, kl) == 0 && s[i + 1 + kl] == '"')
            return (int)i + 1;
    return 1;
}

/* One JSON Lines row: an object with every bladder's pressure key and the six pose keys. */
static hp_error jsonl_row(const csv_file *f, const hp_layout *L, const hp_iab_limit *lp,
                          const char *s, size_t len, hp_calib_row *row, hp_diag *d)
{
    const char *ukey, *uwhy;
    size_t uklen;
    long at = hpi_json_out_of_range(s, len, &ukey, &uklen, &uwhy);
    if (at >= 0)
        return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%ld: %.*s: %s", f->path, f->line, at + 1,
                           (int)uklen, ukey, uwhy);
    json_error_t je;
    json_t *o = json_loadb(s, len, JSON_REJECT_DUPLICATES | JSON_DECODE_INT_AS_REAL,
                           &je); /* as CSV */
    if (!o)
        return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: %s", f->path, f->line,
                           je.column > 0 ? je.column : 1, je.text);
    hp_error err = HP_OK;
    int seen_b[HP_MAX_BLADDERS] = {0}, seen_p[6] = {0};
    if (!json_is_object(o))
        err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: expected one object per line", f->path,
                          f->line);
    const char *key;
    json_t *val;
    json_object_foreach(o, key, val)
    {
        if (err) break;
        double scale;
        int col = key_column(s, len, key);
        int role = column_role(L, key, strlen(key), &scale);
        if (role == -100) {
            err = hp_diag_set(d, HP_ERR_PARSE,
                              "%s:%ld:%d: unknown key '%.60s' (expected p_<bladder>_pa or _kpa "
                              "for the scene's bladders and x_mm ... yaw_deg)",
                              f->path, f->line, col, key);
            break;
        }
        int *seen = role >= 0 ? &seen_b[role] : &seen_p[-1 - role];
        if ((*seen)++) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: %s given twice (in Pa and kPa?)",
                              f->path, f->line, col, key);
            break;
        }
        if (!json_is_number(val)) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: %s: expected a number", f->path, f->line,
                              col, key);
            break;
        }
        err = store(f, L, lp, role, json_number_value(val) * scale, col, row, d);
    }
    for (int k = 0; !err && k < L->n; ++k)
        if (!seen_b[k])
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: missing key p_%s_pa", f->path, f->line,
                              L->bladders[k].name);
    for (int j = 0; !err && j < 6; ++j)
        if (!seen_p[j])
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: missing key %s", f->path, f->line,
                              hp_pose_key(j));
    json_decref(o);
    return err;
}

/* 1 when the file is JSON Lines: by its extension, else by its first data character. */
static int is_jsonl(const csv_file *f)
{
    size_t n = strlen(f->path);
    if ((n >= 6 && strcmp(f->path + n - 6, ".jsonl") == 0) ||
        (n >= 7 && strcmp(f->path + n - 7, ".ndjson") == 0))
        return 1;
    if (n >= 4 && strcmp(f->path + n - 4, ".csv") == 0) return 0;
    for (size_t i = f->pos; i < f->len; ++i) {
        char c = f->text[i];
        if (c == '#') {
            while (i < f->len && f->text[i] != '\n') ++i;
            continue;
        }
        if (c != ' ' && c != '\t' && c != '\r' && c != '\n') return c == '{';
    }
    return 0;
}

/* The CSV header: every column's role and scale. */
static hp_error csv_header(const csv_file *f, const hp_layout *L, const csv_field *fl, int nf,
                           int *role, double *scale, hp_diag *d)
{
    int seen_b[HP_MAX_BLADDERS] = {0}, seen_p[6] = {0};
    for (int c = 0; c < nf; ++c) {
        role[c] = column_role(L, fl[c].s, fl[c].len, &scale[c]);
        if (role[c] == -100)
            return hp_diag_set(d, HP_ERR_PARSE,
                               "%s:%ld:%d: header: unknown column '%.*s' (expected "
                               "p_<bladder>_pa or _kpa for the scene's bladders, x_mm, y_mm, "
                               "z_mm, pitch_deg, roll_deg, yaw_deg)",
                               f->path, f->line, fl[c].col, (int)(fl[c].len > 60 ? 60 : fl[c].len),
                               fl[c].s);
        int *seen = role[c] >= 0 ? &seen_b[role[c]] : &seen_p[-1 - role[c]];
        if ((*seen)++)
            return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: header: '%.*s' appears twice", f->path,
                               f->line, fl[c].col, (int)fl[c].len, fl[c].s);
    }
    for (int k = 0; k < L->n; ++k)
        if (!seen_b[k])
            return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: header: missing column p_%s_pa", f->path,
                               f->line, L->bladders[k].name);
    for (int j = 0; j < 6; ++j)
        if (!seen_p[j])
            return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: header: missing column %s", f->path,
                               f->line, hp_pose_key(j));
    return HP_OK;
}

static hp_error read_layout(const char *path, const char *text, size_t tlen, const hp_layout *L,
                            hp_calib_row *rows, int max, int *n, hp_diag *d)
{
    if (!path || !L || !rows || !n) return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    *n = 0;
    csv_file f;
    hp_error err = csv_open(&f, path, text, tlen, d);
    hp_iab_limit lp[HP_MAX_BLADDERS];
    for (int k = 0; !err && k < L->n; ++k)
        if (hp_iab_limit_point(&L->bladders[k].iab, &lp[k]))
            err = hp_diag_set(d, HP_ERR_INVALID, "bladder '%s': no limit point",
                              L->bladders[k].name);
    int jsonl = !err && is_jsonl(&f), r = 0, nf = 0, ncol = 0;
    csv_field fl[CSV_MAX_FIELDS];
    int role[CSV_MAX_FIELDS];
    double scale[CSV_MAX_FIELDS];
    if (!err && !jsonl) {
        r = csv_next(&f, fl, &nf, d);
        if (r == 0)
            err = hp_diag_set(d, HP_ERR_PARSE,
                              "%s:1:1: empty file (expected the header "
                              "p_<bladder>_pa...,x_mm,...,yaw_deg)",
                              path);
        else if (r < 0) err = HP_ERR_PARSE;
        else err = csv_header(&f, L, fl, nf, role, scale, d);
        ncol = nf;
    }
    while (!err) {
        const char *s = NULL;
        size_t len = 0;
        r = jsonl ? next_line(&f, &s, &len, d) : csv_next(&f, fl, &nf, d);
        if (r != 1) break;
        if (*n == max) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: more than %d rows", path, f.line, max);
            break;
        }
        hp_calib_row *row = &rows[*n];
        memset(row, 0, sizeof *row);
        row->line = f.line;
        if (jsonl) {
            err = jsonl_row(&f, L, lp, s, len, row, d);
        } else if (nf != ncol) {
            err = wrong_count(&f, nf, ncol, d);
        } else {
            for (int c = 0; !err && c < ncol; ++c) {
                double v;
                char what[HP_NAME_MAX + 16];
                err = number(&f, &fl[c], role_name(L, role[c], what, sizeof what), &v, d);
                if (!err) err = store(&f, L, lp, role[c], v * scale[c], fl[c].col, row, d);
            }
        }
        if (err) break;
        (*n)++;
    }
    if (!err && r < 0) err = HP_ERR_PARSE;
    if (!err && *n < 2)
        err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: %d data rows: a layout fit needs at least 2",
                          path, f.line + 1, *n);
    csv_close(&f);
    if (err) *n = 0;
    return err;
}

hp_error hp_calib_read_layout(const char *path, const hp_layout *L, hp_calib_row *rows, int max,
                              int *n, hp_diag *d)
{
    return read_layout(path, NULL, 0, L, rows, max, n, d);
}

hp_error hp_calib_parse_layout(const char *text, size_t len, const char *name, const hp_layout *L,
                               hp_calib_row *rows, int max, int *n, hp_diag *d)
{
    if (!text) return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    return read_layout(name, text, len, L, rows, max, n, d);
}
