/* Readers of the calibration data files (CSV, see hp_calib.h and docs/calibration.md). Both
 * share one line splitter; every number goes through the project's strict parser, and every
 * refusal names FILE:LINE:COL (1-based; the column of the field at fault). */
#define _POSIX_C_SOURCE 200809L
#include "headplan/hp_calib.h"
#include "scene/strict_number.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CSV_MAX_BYTES (16L * 1024 * 1024)
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

static hp_error csv_open(csv_file *f, const char *path, hp_diag *d)
{
    memset(f, 0, sizeof *f);
    f->path = path;
    FILE *fp = fopen(path, "rb");
    if (!fp) return hp_diag_set(d, HP_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    f->text = malloc((size_t)CSV_MAX_BYTES + 1);
    if (!f->text) {
        fclose(fp);
        return hp_diag_set(d, HP_ERR_NOMEM, "%s: out of memory", path);
    }
    f->len = fread(f->text, 1, (size_t)CSV_MAX_BYTES + 1, fp);
    int bad = ferror(fp);
    fclose(fp);
    if (bad) return hp_diag_set(d, HP_ERR_IO, "%s: cannot read", path);
    if (f->len > (size_t)CSV_MAX_BYTES)
        return hp_diag_set(d, HP_ERR_PARSE, "%s: larger than %ld bytes", path, CSV_MAX_BYTES);
    f->text[f->len] = '\0';
    return HP_OK;
}

static void csv_close(csv_file *f) { free(f->text); }

/* The next line that is neither blank nor a '#' comment, split at commas (spaces around a
 * field are trimmed). Returns 1 with fields, 0 at the end, -1 after a message. */
static int csv_next(csv_file *f, csv_field *fl, int *nf, hp_diag *d)
{
    while (f->pos < f->len) {
        const char *s = f->text + f->pos;
        size_t n = 0;
        while (f->pos + n < f->len && s[n] != '\n') ++n;
        f->pos += n + (f->pos + n < f->len);
        f->line++;
        size_t e = n;
        if (e > 0 && s[e - 1] == '\r') --e;
        if (memchr(s, '\0', e)) {
            hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: NUL byte in line", f->path, f->line);
            return -1;
        }
        size_t i = 0;
        while (i < e && (s[i] == ' ' || s[i] == '\t')) ++i;
        if (i == e || s[i] == '#') continue;
        *nf = 0;
        size_t start = 0;
        for (size_t k = 0; k <= e; ++k) {
            if (k < e && s[k] != ',') continue;
            if (*nf == CSV_MAX_FIELDS) {
                hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%zu: more than %d columns", f->path,
                            f->line, k + 1, CSV_MAX_FIELDS);
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
    return 0;
}

static int field_is(const csv_field *f, const char *name)
{
    return f->len == strlen(name) && memcmp(f->s, name, f->len) == 0;
}

/* A number of a field, with the file position in the message on failure. */
static hp_error number(const csv_file *f, const csv_field *fl, const char *what, double *v,
                       hp_diag *d)
{
    const char *why = hp_strict_double(fl->s, fl->len, v);
    if (why)
        return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: %s: '%.*s': %s", f->path, f->line,
                           fl->col, what, (int)(fl->len > 40 ? 40 : fl->len), fl->s, why);
    return HP_OK;
}

static hp_error wrong_count(const csv_file *f, int got, int want, hp_diag *d)
{
    return hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: %d columns, the header has %d", f->path,
                       f->line, got, want);
}

hp_error hp_calib_read_material(const char *path, hp_calib_point *pts, int max, int *n,
                                hp_calib_radius *kind, hp_diag *d)
{
    if (!path || !pts || !n || !kind) return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    *n = 0;
    csv_file f;
    hp_error err = csv_open(&f, path, d);
    if (err) {
        csv_close(&f);
        return err;
    }
    csv_field fl[CSV_MAX_FIELDS];
    int nf = 0, r = csv_next(&f, fl, &nf, d);
    double pscale = 1.0;
    if (r == 0) err = hp_diag_set(d, HP_ERR_PARSE, "%s:1:1: empty file (expected the header "
                                  "pressure_pa,ri_mm or pressure_pa,ro_mm)", path);
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
        if (!err) err = number(&f, &fl[1], *kind == HP_CALIB_INNER ? "ri_mm" : "ro_mm",
                               &p.radius, d);
        if (!err && ncol == 3) err = number(&f, &fl[2], "sigma_mm", &sig, d);
        if (err) break;
        if (!(p.radius > 0)) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: %s: must be > 0 mm (got %g)", path,
                              f.line, fl[1].col, *kind == HP_CALIB_INNER ? "ri_mm" : "ro_mm",
                              p.radius);
            break;
        }
        if (!(sig > 0)) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: sigma_mm: must be > 0 (got %g)",
                              path, f.line, fl[2].col, sig);
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
        err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: %d data rows: a fit of two moduli needs "
                          "at least 3", path, f.line + 1, *n);
    csv_close(&f);
    if (err) *n = 0;
    return err;
}

hp_error hp_calib_read_layout(const char *path, const hp_layout *L, hp_calib_row *rows,
                              int max, int *n, hp_diag *d)
{
    if (!path || !L || !rows || !n) return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    *n = 0;
    csv_file f;
    hp_error err = csv_open(&f, path, d);
    if (err) {
        csv_close(&f);
        return err;
    }
    csv_field fl[CSV_MAX_FIELDS];
    int nf = 0, r = csv_next(&f, fl, &nf, d);
    /* role[c]: bladder index (>= 0) or -1 - pose component. */
    int role[CSV_MAX_FIELDS], seen_b[HP_MAX_BLADDERS] = {0}, seen_p[6] = {0};
    double scale[CSV_MAX_FIELDS];
    if (r == 0) err = hp_diag_set(d, HP_ERR_PARSE, "%s:1:1: empty file (expected the header "
                                  "p_<bladder>_pa...,x_mm,...,yaw_deg)", path);
    else if (r < 0) err = HP_ERR_PARSE;
    for (int c = 0; !err && c < nf; ++c) {
        role[c] = -100;
        for (int j = 0; j < 6; ++j)
            if (field_is(&fl[c], hp_pose_key(j))) {
                role[c] = -1 - j;
                scale[c] = j < 3 ? 1e-3 : 3.14159265358979323846 / 180.0;
                if (seen_p[j]++) role[c] = -200;
            }
        for (int k = 0; k < L->n && role[c] == -100; ++k) {
            char pa[HP_NAME_MAX + 8], kpa[HP_NAME_MAX + 8];
            snprintf(pa, sizeof pa, "p_%s_pa", L->bladders[k].name);
            snprintf(kpa, sizeof kpa, "p_%s_kpa", L->bladders[k].name);
            if (field_is(&fl[c], pa) || field_is(&fl[c], kpa)) {
                role[c] = k;
                scale[c] = field_is(&fl[c], pa) ? 1.0 : 1e3;
                if (seen_b[k]++) role[c] = -200;
            }
        }
        if (role[c] == -200)
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:%d: header: '%.*s' appears twice", path,
                              f.line, fl[c].col, (int)fl[c].len, fl[c].s);
        else if (role[c] == -100)
            err = hp_diag_set(d, HP_ERR_PARSE,
                              "%s:%ld:%d: header: unknown column '%.*s' (expected p_<bladder>_pa "
                              "or _kpa for the scene's bladders, x_mm, y_mm, z_mm, pitch_deg, "
                              "roll_deg, yaw_deg)",
                              path, f.line, fl[c].col, (int)(fl[c].len > 60 ? 60 : fl[c].len),
                              fl[c].s);
    }
    for (int k = 0; !err && k < L->n; ++k)
        if (!seen_b[k])
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: header: missing column p_%s_pa", path,
                              f.line, L->bladders[k].name);
    for (int j = 0; !err && j < 6; ++j)
        if (!seen_p[j])
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: header: missing column %s", path,
                              f.line, hp_pose_key(j));
    int ncol = nf;
    hp_iab_limit lp[HP_MAX_BLADDERS];
    for (int k = 0; !err && k < L->n; ++k)
        if (hp_iab_limit_point(&L->bladders[k].iab, &lp[k]))
            err = hp_diag_set(d, HP_ERR_INVALID, "bladder '%s': no limit point",
                              L->bladders[k].name);
    while (!err && (r = csv_next(&f, fl, &nf, d)) == 1) {
        if (nf != ncol) {
            err = wrong_count(&f, nf, ncol, d);
            break;
        }
        if (*n == max) {
            err = hp_diag_set(d, HP_ERR_PARSE, "%s:%ld:1: more than %d rows", path, f.line, max);
            break;
        }
        hp_calib_row *row = &rows[*n];
        memset(row, 0, sizeof *row);
        row->line = f.line;
        for (int c = 0; !err && c < ncol; ++c) {
            double v;
            char what[HP_NAME_MAX + 16];
            if (role[c] >= 0) snprintf(what, sizeof what, "p_%s", L->bladders[role[c]].name);
            else snprintf(what, sizeof what, "%s", hp_pose_key(-1 - role[c]));
            err = number(&f, &fl[c], what, &v, d);
            if (err) break;
            v *= scale[c];
            if (role[c] < 0) {
                row->pose[-1 - role[c]] = v;
                continue;
            }
            const hp_bladder *b = &L->bladders[role[c]];
            if (!(v >= b->p_min && v <= b->p_max))
                err = hp_diag_set(d, HP_ERR_PARSE,
                                  "%s:%ld:%d: %s: %g Pa outside the bladder's limits [%g, %g] Pa",
                                  path, f.line, fl[c].col, what, v, b->p_min, b->p_max);
            else if (lp[role[c]].exists && !(v < lp[role[c]].pressure))
                err = hp_diag_set(d, HP_ERR_PARSE,
                                  "%s:%ld:%d: %s: %g Pa is past the bladder's limit point "
                                  "(%g Pa): no stable radius",
                                  path, f.line, fl[c].col, what, v, lp[role[c]].pressure);
            row->pressure[role[c]] = v;
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
