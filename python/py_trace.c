/* Planner.run_trace: a trace planned greedily, row after row, as `headplan batch` plans it.
 * Rows are read by the library's trace reader: a file directly, an array through the same
 * CSV text a file would hold (printed with 17 significant digits, so every double reads
 * back exactly), so deviation rows, -0 and bad rows are handled by one piece of code. */
#include "hpy.h"
#include "common/c_locale.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    size_t n, cap;
    hp_trace_row *row;  /* line (an array's: its index), t, the correction (SI) */
    unsigned char *bad; /* 1: the row could not be read */
    char **msg;         /* NULL for a good row */
    char **why;         /* the planner's reason for a row it refused (invalid-input), else NULL */
} trace_in;

static void trace_free(trace_in *in)
{
    for (size_t i = 0; i < in->n; ++i) {
        free(in->msg[i]);
        if (in->why) free(in->why[i]);
    }
    free(in->why);
    free(in->row);
    free(in->bad);
    free(in->msg);
    memset(in, 0, sizeof *in);
}

static int trace_grow(trace_in *in)
{
    size_t cap = in->cap ? in->cap * 2 : 1024;
    hp_trace_row *row = realloc(in->row, cap * sizeof *row);
    if (row) in->row = row;
    unsigned char *bad = realloc(in->bad, cap * sizeof *bad);
    if (bad) in->bad = bad;
    char **msg = realloc(in->msg, cap * sizeof *msg);
    if (msg) in->msg = msg;
    if (!row || !bad || !msg) return -1;
    in->cap = cap;
    return 0;
}

/* An array's bad row named by its index, as the result's `line` names it: the reader's
 * "<array>:LINE:COL: why" counts lines and columns of the CSV text the array was written as
 * (a NaN in row 1 was "<array>:3:23"). Returns a malloc'd message or NULL. */
static char *array_message(const char *msg, size_t row)
{
    const char *why = msg;
    if (strncmp(msg, "<array>:", 8) == 0) {
        why = msg + 8;
        while (*why >= '0' && *why <= '9') ++why; /* line */
        if (*why == ':' && why[1] >= '0' && why[1] <= '9') {
            ++why;
            while (*why >= '0' && *why <= '9') ++why; /* column */
        }
        if (*why == ':') ++why;
        if (*why == ' ') ++why;
    }
    size_t n = strlen(why) + 48;
    char *out = malloc(n);
    if (out) snprintf(out, n, "<array> row %zu: %s", row, why);
    return out;
}

/* Reads every row (bad rows keep their message); an array's rows are numbered by index.
 * No GIL needed. */
static hp_error read_all(hp_trace_reader *r, trace_in *in, int array, hp_diag *d)
{
    for (;;) {
        hp_trace_row row;
        hp_diag rd = {{0}};
        hp_error e = hp_trace_next(r, &row, &rd);
        if (e == HP_END) return HP_OK;
        if (e == HP_ERR_IO) return hp_diag_set(d, e, "%s", rd.text);
        if (in->n == in->cap && trace_grow(in) < 0)
            return hp_diag_set(d, HP_ERR_NOMEM, "trace: out of memory");
        size_t i = in->n++;
        in->msg[i] = NULL;
        in->bad[i] = e != HP_OK;
        if (e == HP_OK) {
            in->row[i] = row;
            if (array) in->row[i].line = (long)i;
        } else {
            /* The message starts "NAME:LINE:" (hp_trace.h). */
            const char *colon = strchr(rd.text, ':');
            memset(&in->row[i], 0, sizeof in->row[i]);
            in->row[i].line = array ? (long)i : colon ? strtol(colon + 1, NULL, 10) : 0;
            in->row[i].t = NAN;
            in->msg[i] = array ? array_message(rd.text, i) : strdup(rd.text);
            if (!in->msg[i]) return hp_diag_set(d, HP_ERR_NOMEM, "trace: out of memory");
        }
    }
}

/* run_trace's sink: a planned row into the block, with the reason of a row the planner
 * refused, named as batch names it ("NAME:LINE: reason"; an array's "<array> row I:
 * reason"); name is NULL for an array. */
typedef struct plan_ctx {
    trace_in *in;
    hpy_block *b;
    const char *name;
    hp_planner *p;
} plan_ctx;

static hp_error store_row(void *ctx, size_t i, const hp_result *r)
{
    plan_ctx *c = ctx;
    if (r->status == HP_STATUS_INVALID_INPUT) {
        const char *err = hp_planner_error(c->p);
        const char *why = *err ? err : hp_planner_note(c->p);
        size_t len = strlen(why) + (c->name ? strlen(c->name) : 0) + 48;
        char **said = &c->in->why[i];
        if (!(*said = malloc(len))) return HP_ERR_NOMEM;
        if (c->name) snprintf(*said, len, "%s:%ld: %s", c->name, c->in->row[i].line, why);
        else snprintf(*said, len, "<array> row %zu: %s", i, why);
    }
    hpy_block_store(c->b, (npy_intp)i, &c->in->row[i], r);
    return HP_OK;
}

/* Plans the rows greedily into the block, as headplan batch does (hp_trace_plan_run: every
 * plan starts from the previous good row's result, the nominal answer before the first;
 * the planner's own per-plan rate limits). */
static hp_error plan_all(hp_planner *p, trace_in *in, hpy_block *b, const char *name)
{
    in->why = calloc(in->n ? in->n : 1, sizeof *in->why);
    if (!in->why) return HP_ERR_NOMEM;
    for (size_t i = 0; i < in->n; ++i)
        if (in->bad[i]) hpy_block_store(b, (npy_intp)i, &in->row[i], NULL);
    hp_trace_plan *tp = NULL;
    hp_error e = hp_trace_plan_create(p, NULL, &tp, NULL);
    plan_ctx c = {in, b, name, p};
    if (e == HP_OK) e = hp_trace_plan_run(tp, in->row, in->bad, in->n, store_row, &c, NULL, NULL);
    hp_trace_plan_destroy(tp);
    return e;
}

/* The horizon modes of run_trace (hp_horizon.h): the same rows planned greedily with the
 * horizon's per-row and per-second rate limits, by the receding-horizon planner, or all at
 * once by the offline NLP (Ipopt). Every row must be good: a plan over a horizon has no
 * place for a row it cannot read. Each planned row becomes an hp_result for the block
 * (radii, pressures and stretches as planned; outer radii by the volume law; pose error
 * against the row's desired pose). Allocates (the offline NLP does). */
static hp_error plan_horizon(const hp_layout *L, const hp_settings *s,
                             const hp_horizon_settings *hs, int mode, const trace_in *in,
                             hpy_block *b, hp_diag *d)
{
    for (size_t i = 0; i < in->n; ++i)
        if (in->msg[i]) return hp_diag_set(d, HP_ERR_PARSE, "%s", in->msg[i]);
    const hp_trace_row *rows = in->row;
    hp_horizon_row *out = calloc(in->n ? in->n : 1, sizeof *out);
    hp_error e = out ? HP_OK : hp_diag_set(d, HP_ERR_NOMEM, "trace: out of memory");
    /* The start pressures are held one sampling interval before row 0, as headplan horizon
     * takes it (the trace's first interval). */
    hp_horizon_settings h = *hs;
    h.start_interval_s = hp_horizon_start_interval(rows, in->n, hs->start_interval_s);
    hs = &h;
    if (e == HP_OK) {
        if (mode == 1) e = hp_horizon_greedy(L, s, hs, rows, in->n, NULL, out, d);
        else if (mode == 2) e = hp_horizon_receding(L, s, hs, rows, in->n, NULL, out, d);
        else e = hp_horizon_offline(L, s, hs, rows, in->n, NULL, out, NULL, d);
    }
    for (size_t i = 0; e == HP_OK && i < in->n; ++i) {
        hp_result r;
        memset(&r, 0, sizeof r);
        r.status = out[i].status;
        r.n = L->n;
        memcpy(r.desired, out[i].desired, sizeof r.desired);
        memcpy(r.achieved, out[i].achieved, sizeof r.achieved);
        double a[6], w[6];
        hp_pose_to_clinical(out[i].achieved, a);
        hp_pose_to_clinical(out[i].desired, w);
        for (int c = 0; c < 6; ++c) r.pose_error = fmax(r.pose_error, fabs(a[c] - w[c]));
        for (int k = 0; k < L->n; ++k) {
            hp_bladder_result *br = &r.bladders[k];
            br->ri = out[i].ri[k];
            br->pressure = out[i].pressure[k];
            br->stretch = br->ri / L->bladders[k].iab.Ri;
            if (hp_iab_ro(&L->bladders[k].iab, br->ri, &br->ro) != HP_OK) br->ro = NAN;
        }
        hpy_block_store(b, (npy_intp)i, &rows[i], &r);
    }
    free(out);
    return e;
}

/* The CSV text of an array trace; NULL with an exception set on failure. */
static char *array_text(PyObject *poses_obj, PyObject *t_obj, size_t *len)
{
    PyArrayObject *poses = hpy_rows(poses_obj, "trace", 6, 0), *t = NULL;
    if (!poses) return NULL;
    npy_intp N = PyArray_DIM(poses, 0);
    if (t_obj && t_obj != Py_None) {
        t = hpy_doubles(t_obj, "t", 1);
        if (t && (PyArray_NDIM(t) != 1 || PyArray_DIM(t, 0) != N)) {
            hpy_fail("t: expected %zd time stamps [s], one per row", (Py_ssize_t)N);
            Py_CLEAR(t);
        }
        if (!t) {
            Py_DECREF(poses);
            return NULL;
        }
    }
    /* A row: 7 numbers of at most 24 characters and their separators. */
    size_t cap = 64 + (size_t)N * 7 * 26;
    char *text = malloc(cap);
    if (!text) {
        Py_DECREF(poses);
        Py_XDECREF(t);
        PyErr_NoMemory();
        return NULL;
    }
    const double *x = PyArray_DATA(poses), *ts = t ? PyArray_DATA(t) : NULL;
    size_t used = (size_t)snprintf(text, cap, "t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg\n");
    /* The trace reader reads '.': a host's comma locale (setlocale(LC_ALL, "")) made "0,1". */
    hp_c_numeric cl;
    hpi_c_numeric_begin(&cl);
    for (npy_intp i = 0; i < N; ++i) {
        double tv = ts ? ts[i] : 0.1 * (double)i;
        used += (size_t)snprintf(text + used, cap - used, "%.17g", tv);
        for (int c = 0; c < 6; ++c)
            used += (size_t)snprintf(text + used, cap - used, ",%.17g", x[i * 6 + c]);
        text[used++] = '\n';
    }
    hpi_c_numeric_end(&cl);
    Py_DECREF(poses);
    Py_XDECREF(t);
    *len = used;
    return text;
}

PyObject *hpy_planner_run_trace(PyObject *o, PyObject *args, PyObject *kwargs)
{
    hpy_planner *self = (hpy_planner *)o;
    static char *kw[] = {"trace",  "t",       "rows",       "rate_limits",
                         "mode",   "horizon", "prediction", "rate_kpa_per_s",
                         "window", "overlap", NULL};
    PyObject *trace = Py_None, *t = Py_None;
    PyObject *horizon_o = Py_None, *rate_o = Py_None, *window_o = Py_None, *overlap_o = Py_None;
    const char *rows = NULL, *mode_s = "batch", *pred = NULL;
    int rate_limits = 1, horizon = -1, window = -1, overlap = -1;
    double rate_kpa_s = NAN;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "|OOzpsOzOOO:run_trace", kw, &trace, &t, &rows,
                                     &rate_limits, &mode_s, &horizon_o, &pred, &rate_o, &window_o,
                                     &overlap_o))
        return NULL;
    /* None is "not given"; any value given goes to the validator as it is (NaN, -1 and
     * infinity included, which no sentinel may swallow). */
    int given = horizon_o != Py_None || rate_o != Py_None || window_o != Py_None ||
                overlap_o != Py_None;
    if ((horizon_o != Py_None && hpy_int(horizon_o, "horizon", &horizon) < 0) ||
        (window_o != Py_None && hpy_int(window_o, "window", &window) < 0) ||
        (overlap_o != Py_None && hpy_int(overlap_o, "overlap", &overlap) < 0) ||
        (rate_o != Py_None && hpy_double(rate_o, "rate_kpa_per_s", &rate_kpa_s) < 0))
        return NULL;
    /* mode: 0 as batch; over a horizon (hp_horizon.h) 1 greedy, 2 receding, 3 offline. */
    static const char *const modes[4] = {"batch", "greedy", "receding", "offline"};
    int mode = -1;
    for (int m = 0; m < 4; ++m)
        if (strcmp(mode_s, modes[m]) == 0) mode = m;
    if (mode < 0) return hpy_fail("mode: '%s' is none of batch, greedy, receding, offline", mode_s);
    hp_horizon_settings hs;
    hp_horizon_settings_default(&hs);
    if (horizon_o != Py_None) hs.horizon = horizon;
    if (window_o != Py_None) hs.window = window;
    if (overlap_o != Py_None) hs.overlap = overlap;
    if (rate_o != Py_None) hs.rate_max_per_s = rate_kpa_s * 1e3;
    if (rate_o != Py_None && !(rate_kpa_s > 0)) /* the validator would say it in Pa/s */
        return hpy_fail("rate_kpa_per_s: must be > 0 kPa/s (got %g)", rate_kpa_s);
    if (pred && hp_prediction_parse(pred, &hs.prediction) != HP_OK)
        return hpy_fail("prediction: '%s' is not 'hold', 'velocity' or 'periodic'", pred);
    hp_diag hd = {{0}};
    if (mode > 0 && hp_horizon_settings_validate(&hs, &hd) != HP_OK) return hpy_fail("%s", hd.text);
    if (mode == 0 && (given || pred))
        return hpy_fail("horizon, prediction, rate_kpa_per_s, window, overlap: only with "
                        "mode greedy, receding or offline");
    /* An option its mode does not read would be ignored without a word: refused, by the rule
     * of headplan horizon. */
    const char *recv = horizon_o != Py_None ? "horizon" : pred ? "prediction" : NULL;
    const char *offl = window_o != Py_None ? "window" : overlap_o != Py_None ? "overlap" : NULL;
    if (recv && mode != 2 && mode != 0)
        return hpy_fail("%s: only the receding plan reads it (mode 'receding'), not mode '%s'",
                        recv, mode_s);
    if (offl && mode != 3 && mode != 0)
        return hpy_fail("%s: only the offline plan reads it (mode 'offline'), not mode '%s'", offl,
                        mode_s);
    if (!self->p) {
        PyErr_SetString(PyExc_RuntimeError, "Planner: not built");
        return NULL;
    }
    hp_trace_rows kind = HP_TRACE_CORRECTION;
    const hp_trace_rows *override = NULL;
    if (rows) {
        if (hp_trace_rows_parse(rows, &kind) != HP_OK)
            return hpy_fail("rows: '%s' is neither 'deviation' nor 'correction'", rows);
        override = &kind;
    }
    int is_path = trace == Py_None || PyUnicode_Check(trace) || PyBytes_Check(trace) ||
                  PyObject_HasAttrString(trace, "__fspath__");
    PyObject *path = NULL;
    char *text = NULL;
    size_t len = 0;
    if (trace == Py_None) {
        if (!self->has_trace) return hpy_fail("run_trace: the scene names no trace");
        /* The scene's trace.rows describes its own trace: rows must agree, as in headplan
         * batch and horizon (planning a deviation trace as corrections flips every sign). */
        if (override && *override != self->trace_rows)
            return hpy_fail("rows: '%s' but the scene's trace.rows says %s: they must agree", rows,
                            hp_trace_rows_name(self->trace_rows));
        if (!override) {
            kind = self->trace_rows;
            override = &kind;
        }
        path = PyBytes_FromString(self->trace_path);
        if (!path) return NULL;
    } else if (is_path) {
        if (t != Py_None) return hpy_fail("t: time stamps come from the trace file");
        if (!PyUnicode_FSConverter(trace, &path)) return NULL;
    } else {
        /* The kind of a trace's rows is never guessed, for arrays as for files. */
        if (!override)
            return hpy_fail("rows: an array trace needs rows='deviation' or rows='correction'");
        text = array_text(trace, t, &len);
        if (!text) return NULL;
    }

    hp_settings s = self->s;
    s.use_rate_limits = rate_limits;
    hp_diag d = {{0}};
    hp_error e = HP_OK;
    trace_in in = {0};
    hpy_block b = {0};
    int nomem = 0;
    hp_planner *p = NULL;
    const char *cpath = path ? PyBytes_AS_STRING(path) : NULL;
    Py_BEGIN_ALLOW_THREADS hp_trace_reader *r = NULL;
    e = cpath ? hp_trace_open(cpath, override, &r, &d)
              : hp_trace_open_mem(text, len, "<array>", HP_TRACE_CSV, override, &r, &d);
    if (e == HP_OK) e = read_all(r, &in, text != NULL, &d);
    hp_trace_close(r);
    if (e == HP_OK && mode > 0) {
        nomem = hpy_block_alloc(&b, (npy_intp)in.n, self->layout.n, 1) < 0;
        if (!nomem) e = plan_horizon(&self->layout, &s, &hs, mode, &in, &b, &d);
    } else if (e == HP_OK) {
        e = hp_planner_create(&self->layout, &s, &p, &d);
    }
    if (e == HP_OK && mode == 0) {
        nomem = hpy_block_alloc(&b, (npy_intp)in.n, self->layout.n, 1) < 0;
        if (!nomem) {
            e = plan_all(p, &in, &b, cpath);
            if (e == HP_ERR_NOMEM) nomem = 1;
            else if (e != HP_OK) hp_diag_set(&d, e, "run_trace: %s", hp_planner_error(p));
        }
    }
    hp_planner_destroy(p);
    Py_END_ALLOW_THREADS free(text);
    Py_XDECREF(path);

    PyObject *out = NULL;
    if (nomem) PyErr_NoMemory();
    else if (e != HP_OK) hpy_fail("%s", d.text);
    else out = hpy_block_dict(&b);
    /* Beside the table's arrays: the messages of the rows not planned or refused. */
    PyObject *msgs = out ? PyList_New(0) : NULL;
    for (size_t i = 0; msgs && i < in.n; ++i) {
        const char *said = in.msg[i] ? in.msg[i] : in.why ? in.why[i] : NULL;
        if (said) {
            PyObject *m = PyUnicode_FromString(said);
            if (!m || PyList_Append(msgs, m) < 0) Py_CLEAR(out);
            Py_XDECREF(m);
        }
    }
    if (out && hpy_put(out, "messages", msgs)) Py_CLEAR(out);
    if (!out) Py_XDECREF(msgs);
    hpy_block_free(&b);
    trace_free(&in);
    return out;
}
