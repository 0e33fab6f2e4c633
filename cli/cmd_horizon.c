/* headplan horizon: greedy, receding-horizon and offline plans of one trace, and their
 * comparison (docs/horizon.md). */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli_output.h"
#include "cli/cli_args.h"
#include "cli/cli_outfile.h"
#include "cli/cli_scene.h"
#include "cli/cmd_solve_load.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"

#include <errno.h>
#include <float.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const CMD = "horizon";

static void help(void)
{
    printf("usage: headplan horizon SCENE [TRACE|-] [--mode greedy|receding|offline|compare]\n"
           "           [--horizon N] [--prediction hold|velocity|periodic] [--window ROWS]\n"
           "           [--overlap ROWS] [--rate-kpa-per-s R] [--smooth S]\n"
           "           [--rows deviation|correction] [--tolerance-mm MM] [--tolerance-deg DEG]\n"
           "           [-o OUT.csv] [--json]\n\n"
           "Plans every row of TRACE (default: the scene's trace; '-': standard input) under\n"
           "the scene's limits and the rate limits between rows (each bladder's rate_max_kpa\n"
           "per row and --rate-kpa-per-s times the row interval, whichever is smaller):\n"
           "  greedy    each row on its own, from the previous row's pressures\n"
           "  receding  each row planned N rows ahead (--horizon, default 10) with a\n"
           "            predicted desired pose (--prediction, default hold)\n"
           "  offline   all rows in one NLP (Ipopt): the best tracking the limits allow;\n"
           "            --window ROWS --overlap ROWS solves long traces in windows\n"
           "            (default: a trace of more than %d rows in %d overlapping by %d)\n"
           "  compare   all three (the default)\n"
           "Prints per plan the RMS and largest error per axis, the time outside the\n"
           "tolerance (default 0.5 mm / 0.5 deg), the pressure travel and the cost; --json\n"
           "prints it as JSON. -o writes every plan's rows as CSV, the summary in its\n"
           "'# ' header lines. --smooth is the pressure-change weight (mm^2 per kPa^2).\n\n"
           "exit: 0 ok, 64 usage, 65 bad scene, trace or value, or a row the planner refused\n"
           "(outputs written), 66 no input, 70 solver failure or a row stopped by its budget\n"
           "(outputs written), 73 cannot write OUT\n",
           HP_HORIZON_WHOLE_MAX, HP_HORIZON_AUTO_WINDOW, HP_HORIZON_AUTO_OVERLAP);
}

typedef struct {
    const char *scene, *trace, *out, *mode, *prediction, *rows;
    const char *horizon, *window, *overlap, *rate, *smooth, *tol_mm, *tol_deg;
    int json;
} hz_args;

static int parse(int argc, char **argv, hz_args *a)
{
    const char *const names[] = {
        "-o",        "--mode",         "--prediction",   "--rows",
        "--horizon", "--window",       "--overlap",      "--rate-kpa-per-s",
        "--smooth",  "--tolerance-mm", "--tolerance-deg"};
    const char **slots[] = {&a->out,     &a->mode,   &a->prediction, &a->rows,
                            &a->horizon, &a->window, &a->overlap,    &a->rate,
                            &a->smooth,  &a->tol_mm, &a->tol_deg};
    const char *const flags[] = {"--json"};
    int *const flag_slots[] = {&a->json};
    const cli_grammar g = {help,       names,  slots, 11,   flags,
                           flag_slots, 1,      NULL,  NULL, {&a->scene, &a->trace},
                           2,          "SCENE"};
    return cli_parse(CMD, argc, argv, &g);
}

/* Every value option into the horizon settings and tolerances; 0 or the exit status. */
static int settings_from_args(const hz_args *a, hp_horizon_settings *hs, double *tol_mm,
                              double *tol_deg, int *modes)
{
    hp_horizon_settings_default(hs);
    long v;
    double x;
    int rc;
    if (a->horizon) {
        if ((rc = cli_int(CMD, "--horizon", a->horizon, 1, HP_HORIZON_MAX, &v))) return rc;
        hs->horizon = (int)v;
    }
    if (a->window) {
        if ((rc = cli_int(CMD, "--window", a->window, 2, 1 << 20, &v))) return rc;
        hs->window = (int)v;
    }
    if (a->overlap) {
        if (!a->window) return cli_fail(CLI_EXIT_USAGE, CMD, "--overlap: needs --window");
        if ((rc = cli_int(CMD, "--overlap", a->overlap, 1, hs->window - 1, &v))) return rc;
        hs->overlap = (int)v;
    }
    if (a->rate) {
        if ((rc = cli_double(CMD, "--rate-kpa-per-s", a->rate, &x))) return rc;
        if (!(x > 0)) return cli_fail(CLI_EXIT_USAGE, CMD, "--rate-kpa-per-s: must be > 0");
        hs->rate_max_per_s = x * 1e3;
    }
    if (a->smooth) {
        if ((rc = cli_double(CMD, "--smooth", a->smooth, &x))) return rc;
        if (!(x >= 0 && x <= 1))
            return cli_fail(CLI_EXIT_USAGE, CMD, "--smooth: must be in [0, 1]");
        hs->smooth = x;
    }
    if (a->prediction && hp_prediction_parse(a->prediction, &hs->prediction) != HP_OK)
        return cli_fail(CLI_EXIT_USAGE, CMD, "--prediction: '%s' is not hold, velocity or periodic",
                        a->prediction);
    *tol_mm = *tol_deg = 0.5;
    if (a->tol_mm) {
        if ((rc = cli_double(CMD, "--tolerance-mm", a->tol_mm, tol_mm))) return rc;
        if (!(*tol_mm >= DBL_MIN))
            return cli_fail(CLI_EXIT_USAGE, CMD, "--tolerance-mm: must be > 0 (and not subnormal)");
    }
    if (a->tol_deg) {
        if ((rc = cli_double(CMD, "--tolerance-deg", a->tol_deg, tol_deg))) return rc;
        if (!(*tol_deg >= DBL_MIN))
            return cli_fail(CLI_EXIT_USAGE, CMD,
                            "--tolerance-deg: must be > 0 (and not subnormal)");
    }
    static const char *const names[3] = {"greedy", "receding", "offline"};
    const char *mode = a->mode ? a->mode : "compare";
    modes[0] = modes[1] = modes[2] = strcmp(mode, "compare") == 0;
    for (int p = 0; p < 3; ++p) modes[p] |= strcmp(mode, names[p]) == 0;
    if (!modes[0] && !modes[1] && !modes[2])
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "--mode: '%s' is not greedy, receding, offline or compare", mode);
    /* An option no selected plan reads would be ignored without a word: refused. */
    const char *recv = a->horizon ? "--horizon" : a->prediction ? "--prediction" : NULL;
    const char *offl = a->window ? "--window" : a->overlap ? "--overlap" : NULL;
    if (recv && !modes[1])
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "%s: only the receding plan reads it (--mode receding or compare), "
                        "not --mode %s",
                        recv, mode);
    if (offl && !modes[2])
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "%s: only the offline plan reads it (--mode offline or compare), "
                        "not --mode %s",
                        offl, mode);
    return 0;
}

/* Reads every row of a trace; a bad row stops (a horizon plan needs every row). */
typedef struct {
    const char *kind, *from; /* what the rows are, and who said so */
} rows_kind;

/* Reads TRACE ("-": standard input, named <stdin> as batch names it); *id is the file it
 * read, so that -o cannot replace it under any name. */
static int read_trace(const char *path, const hp_trace_rows *ovr, const char *from,
                      hp_trace_row **out, size_t *T, rows_kind *kind, cli_input *id)
{
    hp_trace_reader *r = NULL;
    hp_diag d = {{0}};
    const int std = strcmp(path, "-") == 0;
    if (std) path = "<stdin>";
    FILE *f = std ? stdin : fopen(path, "rb");
    if (!f) return cli_fail(CLI_EXIT_NOINPUT, CMD, "%s: cannot open: %s", path, strerror(errno));
    int rc = cli_stdout_not_input(CMD, "trace", path, fileno(f), NULL);
    if (rc) {
        if (!std) fclose(f);
        return rc;
    }
    struct stat st;
    *id = (cli_input){"trace", path, 0, 0, 0};
    if (fstat(fileno(f), &st) == 0) *id = (cli_input){"trace", path, st.st_dev, st.st_ino, 1};
    /* The stream form names where the kind of rows came from in its messages. */
    hp_error e = hp_trace_open_stream(f, path, ovr, from, &r, &d);
    if (e != HP_OK) {
        if (!std) fclose(f);
        return cli_fail(e == HP_ERR_IO ? CLI_EXIT_NOINPUT : CLI_EXIT_DATAERR, CMD, "%s", d.text);
    }
    size_t n = 0, cap = 1024;
    hp_trace_row *rows = malloc(cap * sizeof *rows);
    for (;;) {
        if (!rows) {
            rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
            break;
        }
        if (n == cap) {
            cap *= 2;
            hp_trace_row *g = realloc(rows, cap * sizeof *rows);
            if (!g) free(rows);
            rows = g;
            continue;
        }
        e = hp_trace_next(r, &rows[n], &d);
        if (e == HP_END) break;
        if (e != HP_OK) {
            rc = cli_fail(e == HP_ERR_IO ? CLI_EXIT_NOINPUT : CLI_EXIT_DATAERR, CMD, "%s", d.text);
            break;
        }
        /* Rate limits per second need increasing times; the planners check it too, but
         * their message cannot name the file. */
        if (n > 0 && !(rows[n].t > rows[n - 1].t)) {
            char now[CLI_FMT_MAX], before[CLI_FMT_MAX];
            rc = cli_fail(CLI_EXIT_DATAERR, CMD,
                          "%s:%ld: t_s: %s s is not after the previous row's %s s", path,
                          rows[n].line, cli_fmt(now, rows[n].t), cli_fmt(before, rows[n - 1].t));
            break;
        }
        ++n;
    }
    kind->kind = hp_trace_rows_name(hp_trace_rows_of(r));
    /* batch's words for the same fact (its metadata key rows_from) */
    kind->from = hp_trace_states_rows(r)       ? "trace"
                 : strcmp(from, "--rows") == 0 ? "--rows"
                                               : "scene trace.rows";
    hp_trace_close(r);
    if (!std) fclose(f);
    if (rc == 0 && n == 0) rc = cli_fail(CLI_EXIT_DATAERR, CMD, "%s: no rows", path);
    if (rc) {
        free(rows);
        return rc;
    }
    *out = rows;
    *T = n;
    return 0;
}

static const char *const PLAN_NAMES[3] = {"greedy", "receding", "offline"};
static const char *const AXES[6] = {"x_mm", "y_mm", "z_mm", "pitch_deg", "roll_deg", "yaw_deg"};

static double unit(int i) { return i < 3 ? 1e3 : 57.295779513082320877; }

static void write_summary_text(FILE *f, const char *prefix, const int *modes,
                               const hp_horizon_metrics *m)
{
    char b[CLI_FMT_MAX];
    fprintf(f, "%splan,metric", prefix);
    for (int i = 0; i < 6; ++i) fprintf(f, ",%s", AXES[i]);
    fprintf(f, "\n");
    for (int p = 0; p < 3; ++p) {
        if (!modes[p]) continue;
        fprintf(f, "%s%s,rms", prefix, PLAN_NAMES[p]);
        for (int i = 0; i < 6; ++i) fprintf(f, ",%s", cli_fmt(b, m[p].rms[i]));
        fprintf(f, "\n%s%s,max", prefix, PLAN_NAMES[p]);
        for (int i = 0; i < 6; ++i) fprintf(f, ",%s", cli_fmt(b, m[p].max[i]));
        fprintf(f, "\n");
    }
    fprintf(f, "%splan,time_outside_s,rows_outside,travel_kpa,cost,pose_cost\n", prefix);
    for (int p = 0; p < 3; ++p) {
        if (!modes[p]) continue;
        fprintf(f, "%s%s,%s", prefix, PLAN_NAMES[p], cli_fmt(b, m[p].time_outside));
        fprintf(f, ",%s", cli_fmt(b, m[p].rows_outside));
        fprintf(f, ",%s", cli_fmt(b, m[p].travel * 1e-3));
        fprintf(f, ",%s", cli_fmt(b, m[p].cost));
        fprintf(f, ",%s\n", cli_fmt(b, m[p].pose_cost));
    }
}

static void write_csv(FILE *f, const hp_layout *L, const int *modes, hp_horizon_row *const *plans,
                      size_t T, const hp_horizon_metrics *m, const char *scene, const char *trace,
                      const rows_kind *kind, double tol_mm, double tol_deg)
{
    char b[CLI_FMT_MAX];
    fprintf(f, "# headplan horizon: scene %s, trace %s, %zu rows\n", scene, trace, T);
    /* desired_* is the correction asked of the planner: a deviation row's inverse. */
    fprintf(f, "# rows: %s, rows_from: %s\n", kind->kind, kind->from);
    fprintf(f, "# tolerance_mm %s", cli_fmt(b, tol_mm));
    fprintf(f, ", tolerance_deg %s\n", cli_fmt(b, tol_deg));
    write_summary_text(f, "# ", modes, m);
    fprintf(f, "plan,t_s");
    for (int i = 0; i < 6; ++i) fprintf(f, ",desired_%s", AXES[i]);
    for (int i = 0; i < 6; ++i) fprintf(f, ",achieved_%s", AXES[i]);
    fprintf(f, ",pose_error,status");
    for (int k = 0; k < L->n; ++k) fprintf(f, ",%s_kpa", L->bladders[k].name);
    fprintf(f, "\n");
    for (int p = 0; p < 3; ++p) {
        if (!modes[p]) continue;
        for (size_t t = 0; t < T; ++t) {
            const hp_horizon_row *o = &plans[p][t];
            double err = 0;
            fprintf(f, "%s,%s", PLAN_NAMES[p], cli_fmt(b, o->t));
            for (int i = 0; i < 6; ++i) fprintf(f, ",%s", cli_fmt(b, o->desired[i] * unit(i)));
            for (int i = 0; i < 6; ++i) {
                fprintf(f, ",%s", cli_fmt(b, o->achieved[i] * unit(i)));
                err = fmax(err, fabs(o->achieved[i] - o->desired[i]) * unit(i));
            }
            fprintf(f, ",%s,%s", cli_fmt(b, err), hp_status_name(o->status));
            for (int k = 0; k < L->n; ++k) fprintf(f, ",%s", cli_fmt(b, o->pressure[k] * 1e-3));
            fprintf(f, "\n");
        }
    }
}

static json_t *vec6(const double *v)
{
    json_t *o = json_object();
    for (int i = 0; i < 6; ++i) json_object_set_new(o, AXES[i], json_real(v[i]));
    return o;
}

static void print_json(const int *modes, const hp_horizon_metrics *m, size_t T,
                       const hp_horizon_settings *hs, const hp_horizon_info *info,
                       const rows_kind *kind, double tol_mm, double tol_deg)
{
    json_t *o = json_object();
    json_object_set_new(o, "rows", json_integer((json_int_t)T));
    json_object_set_new(o, "rows_kind", json_string(kind->kind));
    json_object_set_new(o, "rows_from", json_string(kind->from));
    json_object_set_new(o, "tolerance_mm", json_real(tol_mm));
    json_object_set_new(o, "tolerance_deg", json_real(tol_deg));
    json_object_set_new(o, "horizon", json_integer(hs->horizon));
    json_object_set_new(o, "prediction", json_string(hp_prediction_name(hs->prediction)));
    json_object_set_new(o, "smooth", json_real(hs->smooth));
    json_t *plans = json_object();
    for (int p = 0; p < 3; ++p) {
        if (!modes[p]) continue;
        json_t *e = json_object();
        json_object_set_new(e, "rms", vec6(m[p].rms));
        json_object_set_new(e, "max", vec6(m[p].max));
        json_object_set_new(e, "time_outside_s", json_real(m[p].time_outside));
        json_object_set_new(e, "rows_outside", json_real(m[p].rows_outside));
        json_object_set_new(e, "travel_kpa", json_real(m[p].travel * 1e-3));
        json_object_set_new(e, "cost", json_real(m[p].cost));
        json_object_set_new(e, "pose_cost", json_real(m[p].pose_cost));
        if (p == 2) {
            json_object_set_new(e, "windows", json_integer(info->windows));
            json_object_set_new(e, "iterations", json_integer(info->iterations));
            json_object_set_new(e, "largest_window", json_integer(info->largest_window));
        }
        json_object_set_new(plans, PLAN_NAMES[p], e);
    }
    json_object_set_new(o, "plans", plans);
    char *s = json_dumps(o, JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(CLI_JSON_REAL_PRECISION));
    if (s) cli_put_line(s);
    free(s);
    json_decref(o);
}

/* A row a plan could not answer (stopped by its budget, a solver failure) is in the
 * results with its status, as in batch; as in batch the run then exits 70, naming the first
 * such row of each plan and how many there were. A row hp_plan refused (invalid-input: its
 * closest pose is one the round trip from the nominal pose does not confirm) is a data
 * error, 65, as in batch and solve, unless some row also failed. */
static int failed_rows(const int *modes, hp_horizon_row *const *plans, const hp_trace_row *rows,
                       size_t T, const char *trace, char (*const why)[HP_DIAG_MAX])
{
    int rc = 0;
    for (int p = 0; p < 3; ++p) {
        if (!modes[p]) continue;
        for (int refused = 0; refused < 2; ++refused) {
            size_t n = 0, first = 0;
            for (size_t t = 0; t < T; ++t) {
                hp_status st = plans[p][t].status;
                if (st == HP_STATUS_REACHED || st == HP_STATUS_CLOSEST ||
                    st == HP_STATUS_UNCOMMANDED || (st == HP_STATUS_INVALID_INPUT) != refused)
                    continue;
                if (!n++) first = t;
            }
            if (!n) continue;
            /* A refused row's reason is the planner's, as batch prints it ("line N: ..."
             * from the plan, the line named here with the file). */
            const char *reason = refused ? strchr(why[p], ':') : NULL;
            int code = cli_fail(refused ? CLI_EXIT_DATAERR : CLI_EXIT_SOFTWARE, CMD,
                                "%s: %zu of %zu rows %s (first %s:%ld: %s%s)", PLAN_NAMES[p], n, T,
                                refused ? "refused" : "failed", trace, rows[first].line,
                                hp_status_name(plans[p][first].status), reason ? reason : "");
            if (rc != CLI_EXIT_SOFTWARE) rc = code;
        }
    }
    return rc;
}

int cmd_horizon(int argc, char **argv)
{
    hz_args a;
    memset(&a, 0, sizeof a);
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    hp_horizon_settings hs;
    double tol_mm, tol_deg;
    int modes[3];
    if ((rc = settings_from_args(&a, &hs, &tol_mm, &tol_deg, modes))) return rc;
    hp_trace_rows ovr;
    if (a.rows && hp_trace_rows_parse(a.rows, &ovr) != HP_OK)
        return cli_fail(CLI_EXIT_USAGE, CMD, "--rows: '%s' is not deviation or correction", a.rows);
    hp_scene *sc = NULL;
    if ((rc = cli_load_scene(CMD, a.scene, NULL, &sc))) return rc;
    hp_settings s;
    cli_out out = {.slot = -1};
    hp_horizon_row *plans[3] = {NULL, NULL, NULL};
    hp_trace_row *rows = NULL;
    size_t T = 0;
    const char *trace = a.trace;
    const hp_trace_rows *use_ovr = a.rows ? &ovr : NULL;
    const char *from = "--rows";
    if (!trace) {
        if (!sc->has_trace) {
            rc = cli_fail(CLI_EXIT_USAGE, CMD, "no TRACE given and the scene names none");
            goto done;
        }
        trace = sc->trace_path;
        /* The scene's trace.rows describes its own trace: --rows must agree with it, as in
         * batch (planning a deviation trace as corrections flips every sign). */
        if (a.rows && ovr != sc->trace_rows) {
            rc = cli_fail(CLI_EXIT_DATAERR, CMD,
                          "--rows says %s but the scene's trace.rows says %s: they must agree",
                          hp_trace_rows_name(ovr), hp_trace_rows_name(sc->trace_rows));
            goto done;
        }
        use_ovr = &sc->trace_rows;
        from = a.rows ? "--rows" : "the scene's trace.rows";
    }
    if ((rc = cli_settings(CMD, sc, NULL, NULL, &s))) goto done;
    rows_kind kind = {"", ""};
    cli_input trace_id;
    if ((rc = read_trace(trace, use_ovr, from, &rows, &T, &kind, &trace_id))) goto done;
    trace = trace_id.path; /* "<stdin>" for "-" */
    /* A correction solve and batch refuse is refused here too, with the file named, before
     * any planning (the planners refuse it as well, but cannot name the file). */
    {
        hp_diag d = {{0}};
        size_t bad = 0;
        hp_error e = hp_horizon_check_rows(&sc->layout, rows, T, &bad, &d);
        if (e != HP_OK) {
            rc = e == HP_ERR_INVALID
                     ? cli_fail(CLI_EXIT_DATAERR, CMD, "%s:%ld: %s", trace, rows[bad].line, d.text)
                     : cli_fail(CLI_EXIT_SOFTWARE, CMD, "%s", d.text);
            goto done;
        }
    }
    /* The output is checked and created before any planning: a refused -o costs nothing and
     * can name no input. */
    if (a.out) {
        cli_input in[3];
        int nin = 2;
        cli_input_of(&in[0], "scene", a.scene);
        in[1] = trace_id;
        /* The scene's own trace when another one is planned: the user's data all the same. */
        if (sc->has_trace) cli_input_of(&in[nin++], "scene's trace", sc->trace_path);
        if ((rc = cli_out_open(&out, CMD, "-o", a.out, in, nin))) goto done;
    }
    hp_diag d = {{0}};
    double p0[HP_MAX_BLADDERS];
    if (hp_horizon_nominal_pressures(&sc->layout, p0, &d) != HP_OK) {
        rc = cli_fail(CLI_EXIT_DATAERR, CMD, "%s", d.text);
        goto done;
    }
    /* The start pressures are held one sampling interval before row 0. */
    hs.start_interval_s = hp_horizon_start_interval(rows, T, hs.start_interval_s);
    hp_horizon_metrics m[3];
    char why[3][HP_DIAG_MAX] = {"", "", ""}; /* each plan's first refused row */
    hp_horizon_info info;
    memset(&info, 0, sizeof info);
    for (int p = 0; p < 3; ++p) {
        if (!modes[p]) continue;
        plans[p] = malloc(T * sizeof *plans[p]);
        if (!plans[p]) {
            rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
            goto done;
        }
        hp_error e;
        /* greedy from its planner's own start (p0 at the contact levels; at the load level
         * its state after create, as solve's and batch's first row) */
        if (p == 0) e = hp_horizon_greedy(&sc->layout, &s, &hs, rows, T, NULL, plans[p], &d);
        else if (p == 1) e = hp_horizon_receding(&sc->layout, &s, &hs, rows, T, p0, plans[p], &d);
        else e = hp_horizon_offline(&sc->layout, &s, &hs, rows, T, p0, plans[p], &info, &d);
        if (e != HP_OK) {
            /* The library's horizon messages mostly name their plan already. */
            size_t nl = strlen(PLAN_NAMES[p]);
            int named = strncmp(d.text, PLAN_NAMES[p], nl) == 0 && d.text[nl] == ':';
            rc = cli_fail(e == HP_ERR_INVALID ? CLI_EXIT_DATAERR : CLI_EXIT_SOFTWARE, CMD, "%s%s%s",
                          named ? "" : PLAN_NAMES[p], named ? "" : ": ", d.text);
            goto done;
        }
        if (p < 2) snprintf(why[p], sizeof why[p], "%s", d.text);
        hp_horizon_measure(plans[p], T, sc->layout.n, p0, &s, &hs, tol_mm, tol_deg, &m[p]);
    }
    if (a.out) {
        write_csv(out.f, &sc->layout, modes, plans, T, m, cli_name(a.scene), trace, &kind, tol_mm,
                  tol_deg);
        if ((rc = cli_out_commit(&out, CMD))) goto done;
    }
    if (a.json) print_json(modes, m, T, &hs, &info, &kind, tol_mm, tol_deg);
    else write_summary_text(stdout, "", modes, m);
    rc = failed_rows(modes, plans, rows, T, trace, why);
done:
    if (rc) cli_out_abandon(&out);
    for (int p = 0; p < 3; ++p) free(plans[p]);
    free(rows);
    free(sc);
    return rc;
}
