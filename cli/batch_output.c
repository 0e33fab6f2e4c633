/* Writing batch results (see batch_output.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/batch_output.h"
#include "cli/cli_output.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Every column of the table at its widest: a column added to the table always fits. */
#define MAX_COLS (HP_COLUMNS_MAX * HP_COLUMN_WIDTH_MAX)

/* The output cells in order: cell n is value val_of[n] of table column col_of[n]. */
static char col_names[MAX_COLS][HP_COLUMN_NAME_MAX];
static int col_of[MAX_COLS], val_of[MAX_COLS];

static int ext_format(const char *path, hp_trace_format *fmt)
{
    const char *dot = strrchr(path, '.');
    const char *slash = strrchr(path, '/');
    if (!dot || (slash && dot < slash)) return 0;
    if (strcmp(dot, ".csv") == 0) *fmt = HP_TRACE_CSV;
    else if (strcmp(dot, ".jsonl") == 0 || strcmp(dot, ".ndjson") == 0) *fmt = HP_TRACE_JSONL;
    else return 0;
    return 1;
}

int batch_output_format(const char *format, const char *out, hp_trace_format *fmt)
{
    int to_file = out && strcmp(out, "-") != 0;
    hp_trace_format by_ext = HP_TRACE_CSV;
    int has_ext = to_file && ext_format(out, &by_ext);
    if (format) {
        if (hp_trace_format_parse(format, fmt) != HP_OK)
            return cli_fail(CLI_EXIT_USAGE, "batch", "--format: unknown format '%s' (csv, jsonl)",
                            format);
        if (has_ext && by_ext != *fmt)
            return cli_fail(CLI_EXIT_USAGE, "batch",
                            "--format %s contradicts the extension of -o %s", format, out);
        return 0;
    }
    if (has_ext) {
        *fmt = by_ext;
        return 0;
    }
    /* Standard output has no name to read a format from, and a study that silently gets CSV
     * where it expected JSON Lines is the guess this refuses. */
    if (to_file)
        return cli_fail(CLI_EXIT_USAGE, "batch",
                        "-o %s: cannot tell the format: give --format csv|jsonl or name the "
                        "file .csv or .jsonl",
                        out);
    return cli_fail(CLI_EXIT_USAGE, "batch",
                    "standard output has no file name to tell the format: give --format "
                    "csv|jsonl (or -o FILE.csv|FILE.jsonl)");
}

static void name_columns(batch_sink *k);

int batch_sink_open(batch_sink *k, const char *out, hp_trace_format fmt, const hp_layout *L,
                    int times, const cli_input *inputs, int ninputs)
{
    memset(k, 0, sizeof *k);
    k->fmt = fmt;
    k->L = L;
    k->times = times;
    name_columns(k);
    if (!out || strcmp(out, "-") == 0) {
        k->f = stdout;
        return 0;
    }
    int rc = cli_out_open(&k->file, "batch", "-o", out, inputs, ninputs);
    if (rc) return rc;
    k->f = k->file.f;
    k->path = out;
    return 0;
}

/* ---- cells: a row's columns from the one table; CSV and JSON Lines print the same ---- */

typedef enum { CELL_NUM, CELL_INT, CELL_TEXT, CELL_NONE } cell_kind;
typedef struct cell {
    cell_kind kind;
    double num;       /* CELL_NUM; NaN prints as an empty field / null */
    long i;           /* CELL_INT */
    const char *text; /* CELL_TEXT */
} cell;

/* Appends s to buf (size bytes, *used of them taken), truncating as snprintf does; 0 when
 * it did not fit. */
static int add_text(char *buf, size_t size, size_t *used, const char *s)
{
    size_t len = strlen(s), room = size - *used - 1, c = len < room ? len : room;
    memcpy(buf + *used, s, c);
    *used += c;
    buf[*used] = '\0';
    return c == len;
}

/* "name:limit|limit;..." of the bladders on a limit, from a flags column's values
 * (without printf: its format machinery cost more than the rest of writing a row). */
static void binding_text(const hp_layout *L, const double *flags, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < L->n; ++k) {
        unsigned f = (unsigned)flags[k];
        if (!f) continue;
        if ((used && !add_text(buf, size, &used, ";")) ||
            !add_text(buf, size, &used, L->bladders[k].name) || !add_text(buf, size, &used, ":"))
            return;
        int first = 1;
        for (int b = 0; b < HP_BIND_COUNT; ++b) {
            if (!(f & (1u << b))) continue;
            if ((!first && !add_text(buf, size, &used, "|")) ||
                !add_text(buf, size, &used, hp_binding_name(1u << b)))
                return;
            first = 0;
        }
    }
}

/* The rows' cells from the one column table (hp_trace_columns.h): its columns in the rows
 * (without the measured ones under --no-times), an axes column as six cells, a run of
 * per-bladder number columns bladder by bladder (NAME_pressure_pa, NAME_ri_mm, ... of one
 * bladder together), a flags column as one text cell. */
static void name_columns(batch_sink *k)
{
    size_t nt;
    const hp_column *t = hp_columns(&nt);
    int n = 0;
    for (size_t j = 0; j < nt; ++j) {
        const hp_column *c = &t[j];
        if (!c->in_rows || (c->measured && !k->times)) continue;
        if (c->shape == HP_COLUMN_BLADDERS && c->format != HP_COLUMN_FLAGS) {
            size_t end = j;
            while (end < nt && t[end].in_rows && t[end].shape == HP_COLUMN_BLADDERS &&
                   t[end].format != HP_COLUMN_FLAGS)
                ++end;
            for (int b = 0; b < k->L->n; ++b)
                for (size_t g = j; g < end; ++g, ++n) {
                    col_of[n] = (int)g;
                    val_of[n] = b;
                    hp_column_name(&t[g], b, k->L, col_names[n], HP_COLUMN_NAME_MAX);
                }
            j = end - 1;
            continue;
        }
        int w = c->shape == HP_COLUMN_AXES ? 6 : 1;
        for (int v = 0; v < w; ++v, ++n) {
            col_of[n] = (int)j;
            val_of[n] = v;
            hp_column_name(c, v, k->L, col_names[n], HP_COLUMN_NAME_MAX);
        }
    }
    k->ncols = n;
}

/* The cells of one row. A bad row fills only its integer trace-row columns (line), its
 * status (bad-row) and its message. */
static void row_cells(const batch_sink *k, const hp_trace_row *in, const char *msg,
                      const batch_out *o, cell *cells, char *bind, size_t bind_size)
{
    size_t nt;
    const hp_column *t = hp_columns(&nt);
    double vals[HP_COLUMNS_MAX][HP_COLUMN_WIDTH_MAX];
    int done[HP_COLUMNS_MAX] = {0};
    for (int n = 0; n < k->ncols; ++n) {
        const int j = col_of[n];
        const hp_column *c = &t[j];
        cell *x = &cells[n];
        if (!done[j]) {
            hp_column_values(c, k->L->n, in, o->bad ? NULL : &o->r, vals[j]);
            done[j] = 1;
        }
        const double v = vals[j][val_of[n]];
        x->kind = CELL_NONE;
        if (c->source == HP_COLUMN_FROM_MESSAGE) {
            if (o->bad) {
                x->kind = CELL_TEXT;
                x->text = msg ? msg : "bad row";
            }
        } else if (c->format == HP_COLUMN_TEXT) {
            x->kind = CELL_TEXT;
            x->text = hp_column_text(c, v);
        } else if (o->bad && !(c->source == HP_COLUMN_FROM_ROW && c->format == HP_COLUMN_INTEGER)) {
            /* nothing planned */
        } else if (c->format == HP_COLUMN_FLAGS) {
            binding_text(k->L, vals[j], bind, bind_size);
            x->kind = CELL_TEXT;
            x->text = bind;
        } else if (c->format == HP_COLUMN_INTEGER) {
            x->kind = CELL_INT;
            x->i = (long)v;
        } else {
            x->kind = CELL_NUM;
            x->num = v;
        }
    }
}

/* Text with control characters and broken UTF-8 escaped (\xNN), then quoted as the format
 * needs: CSV (cli_put_csv_text) or a JSON string. */
/* The length of the leading printable ASCII of s that needs no quoting in either format. */
static size_t plain_len(const char *s)
{
    size_t plain = 0;
    while (s[plain] >= 0x20 && s[plain] < 0x7f && s[plain] != ',' && s[plain] != '"' &&
           s[plain] != '\\')
        ++plain;
    return plain;
}

static void put_text(FILE *f, const char *s, hp_trace_format fmt)
{
    /* Fast path: printable ASCII that needs no quoting in either format. */
    if (s[plain_len(s)] == '\0') {
        if (fmt == HP_TRACE_JSONL) fputc('"', f);
        fputs(s, f);
        if (fmt == HP_TRACE_JSONL) fputc('"', f);
        return;
    }
    if (fmt == HP_TRACE_CSV) {
        cli_put_csv_text(f, s);
        return;
    }
    char *clean = cli_escaped_copy(s);
    if (!clean) return;
    fputc('"', f); /* a JSON string */
    for (const char *p = clean; *p; ++p) {
        if (*p == '"' || *p == '\\') fputc('\\', f);
        fputc(*p, f);
    }
    fputc('"', f);
    free(clean);
}

/* A row is built in memory and written with one fwrite: ~70 cells a row through stdio one
 * call each (fputs, fputc, fprintf's format machinery for the integers) cost as much as
 * printing the numbers. Text that needs escaping (rare: a bad row's message) flushes the
 * buffer and goes through put_text. */
typedef struct row_buf {
    FILE *f;
    size_t n;
    char b[8192];
} row_buf;

static void rb_flush(row_buf *r)
{
    size_t w = r->n ? fwrite(r->b, 1, r->n, r->f) : 0;
    /* A stream whose write fails drops its buffer and the rest of this fwrite: hand the
     * rest over again, so that it waits in the buffer and the final flush fails again with
     * its reason (errno), as it did when every cell was written on its own. */
    if (w < r->n) fwrite(r->b + w, 1, r->n - w, r->f);
    r->n = 0;
}

static void rb_put(row_buf *r, const char *s, size_t len)
{
    if (len > sizeof r->b - r->n) {
        rb_flush(r);
        if (len > sizeof r->b) {
            fwrite(s, 1, len, r->f);
            return;
        }
    }
    memcpy(r->b + r->n, s, len);
    r->n += len;
}

static void rb_putc(row_buf *r, char c)
{
    if (r->n == sizeof r->b) rb_flush(r);
    r->b[r->n++] = c;
}

/* The digits of v, as "%ld" prints them. */
static void rb_put_long(row_buf *r, long v)
{
    char tmp[24];
    int len = 0;
    unsigned long u = v < 0 ? 0ul - (unsigned long)v : (unsigned long)v;
    do {
        tmp[sizeof tmp - 1 - len++] = (char)('0' + (int)(u % 10u));
        u /= 10u;
    } while (u);
    if (v < 0) tmp[sizeof tmp - 1 - len++] = '-';
    rb_put(r, tmp + sizeof tmp - len, (size_t)len);
}

/* put_text into the row: plain text directly, anything else through put_text. */
static void rb_text(row_buf *r, const char *s, hp_trace_format fmt)
{
    size_t plain = plain_len(s);
    if (s[plain] != '\0') {
        rb_flush(r);
        put_text(r->f, s, fmt);
        return;
    }
    if (fmt == HP_TRACE_JSONL) rb_putc(r, '"');
    rb_put(r, s, plain);
    if (fmt == HP_TRACE_JSONL) rb_putc(r, '"');
}

static void put_cell(row_buf *r, const cell *c, hp_trace_format fmt)
{
    int json = fmt == HP_TRACE_JSONL;
    switch (c->kind) {
    case CELL_NUM:
        if (isfinite(c->num)) {
            /* Straight into the row: no copy, no strlen. */
            if (sizeof r->b - r->n < CLI_FMT_MAX) rb_flush(r);
            r->n += cli_fmt_len(r->b + r->n, c->num);
        } else if (json) {
            rb_put(r, "null", 4);
        }
        break;
    case CELL_INT: rb_put_long(r, c->i); break;
    case CELL_TEXT: rb_text(r, c->text, fmt); break;
    case CELL_NONE:
        if (json) rb_put(r, "null", 4);
        break;
    }
}

void batch_columns_print(FILE *f)
{
    size_t nt;
    const hp_column *t = hp_columns(&nt);
    fputs("name\tunit\tformat\tshape\trows\tnumpy\tmeasured\n", f);
    for (size_t j = 0; j < nt; ++j)
        fprintf(f, "%s\t%s\t%s\t%s\t%s\t%s\t%s\n", t[j].name, t[j].unit,
                hp_column_format_name(t[j].format), hp_column_shape_name(t[j].shape),
                t[j].in_rows ? "yes" : "no", t[j].numpy ? t[j].numpy : "-",
                t[j].measured ? "yes" : "no");
}

void batch_sink_meta(batch_sink *k, const batch_meta *m)
{
    char ver[64], tol[CLI_FMT_MAX], tmax[CLI_FMT_MAX], w[CLI_FMT_MAX], iters[24], rst[24];
    snprintf(ver, sizeof ver, "headplan %s", hp_version());
    snprintf(iters, sizeof iters, "%d", m->s->max_iter);
    snprintf(rst, sizeof rst, "%d", m->s->restarts);
    cli_fmt(tol, m->s->tolerance);
    cli_fmt(tmax, m->s->max_time);
    cli_fmt(w, m->s->weight_mm_per_deg);
    /* auto_pose in a correction's units: "x,y,z,pitch,roll,yaw" (mm, degrees) */
    char ap[6 * CLI_FMT_MAX];
    double cp[6];
    hp_pose_to_clinical(m->s->auto_pose, cp);
    ap[0] = '\0';
    for (int i = 0; i < 6; ++i) {
        char one[CLI_FMT_MAX];
        strcat(strcat(ap, i ? "," : ""), cli_fmt(one, cp[i]));
    }
    /* key, value, 1 when the value is a number (JSON); a NULL value is JSON null and, in a
     * CSV comment, the entry's `none` text */
    static const char *const not_file = "none (not a regular file)";
    const struct {
        const char *key, *value;
        int number;
        const char *none;
    } meta[] = {
        {"headplan_batch", "1", 1, NULL},
        {"program", ver, 0, NULL},
        {"scene", m->scene, 0, NULL},
        {"scene_sha256", m->scene_sha256, 0, not_file},
        {"trace", m->trace, 0, NULL},
        {"trace_sha256", m->trace_sha256, 0, not_file},
        {"rows", m->rows, 0, NULL},
        {"rows_from", m->rows_from, 0, NULL},
        {"pose_form", m->pose_form, 0, NULL},
        {"backend", hp_backend_name(m->s->backend), 0, NULL},
        {"level", m->level, 0, NULL},
        {"level_choice", m->level_choice, 0, "none (the level is stated, not auto)"},
        {"tolerance_mm_deg", tol, 1, NULL},
        {"max_iter", iters, 1, NULL},
        {"max_time_s", tmax, 1, NULL},
        {"weight_mm_per_deg", w, 1, NULL},
        {"rate_limits", m->s->use_rate_limits ? "true" : "false", 1, NULL},
        {"warm_start", m->s->warm_start ? "true" : "false", 1, NULL},
        {"restarts", rst, 1, NULL},
        {"auto_pose_mm_deg", ap, 0, NULL},
    };
    const size_t nm = sizeof meta / sizeof meta[0];
    FILE *f = k->f;
    if (k->fmt == HP_TRACE_CSV) {
        for (size_t i = 0; i < nm; ++i) {
            fprintf(f, "# %s: ", meta[i].key);
            cli_put_escaped(f, meta[i].value  ? meta[i].value
                               : meta[i].none ? meta[i].none
                                              : "none");
            fputc('\n', f);
        }
        for (int c = 0; c < k->ncols; ++c) {
            if (c) fputc(',', f);
            put_text(f, col_names[c], HP_TRACE_CSV);
        }
        fputc('\n', f);
        return;
    }
    fputc('{', f);
    for (size_t i = 0; i < nm; ++i) {
        if (i) fputc(',', f);
        put_text(f, meta[i].key, HP_TRACE_JSONL);
        fputc(':', f);
        if (!meta[i].value) fputs("null", f);
        else if (meta[i].number) fputs(meta[i].value, f);
        else put_text(f, meta[i].value, HP_TRACE_JSONL);
    }
    fputs("}\n", f);
}

int batch_sink_rows(batch_sink *k, const batch_in *in, const batch_out *out, size_t rows)
{
    cell cells[MAX_COLS];
    char bind[2048];
    row_buf rb;
    rb.f = k->f;
    rb.n = 0;
    const int json = k->fmt == HP_TRACE_JSONL;
    for (size_t r = 0; r < rows; ++r) {
        row_cells(k, &in->row[r], in->msg[r], &out[r], cells, bind, sizeof bind);
        const int n = k->ncols;
        if (json) rb_putc(&rb, '{');
        for (int c = 0; c < n; ++c) {
            if (c) rb_putc(&rb, ',');
            if (json) {
                rb_text(&rb, col_names[c], HP_TRACE_JSONL);
                rb_putc(&rb, ':');
            }
            put_cell(&rb, &cells[c], k->fmt);
        }
        if (json) rb_putc(&rb, '}');
        rb_putc(&rb, '\n');
        /* A row at a time: smaller than stdio's own buffer, so stdio buffers it as it did
         * the cells, and a failing stream keeps its errno for the final flush's message. */
        rb_flush(&rb);
    }
    return ferror(k->f) ? CLI_EXIT_IOERR : 0;
}

int batch_sink_commit(batch_sink *k)
{
    if (!k->path) return 0; /* main checks and closes stdout, with its one line */
    k->f = NULL;
    return cli_out_commit(&k->file, "batch");
}

void batch_sink_abandon(batch_sink *k)
{
    if (!k->path) return;
    k->f = NULL;
    cli_out_abandon(&k->file);
}
