/* Writing batch results as CSV or JSON Lines, to a temporary name renamed when complete. */
#define _POSIX_C_SOURCE 200809L
#include "cli/batch_output.h"

#include <errno.h>
#include <jansson.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const POSE_KEYS[6] = {"x_mm", "y_mm", "z_mm",
                                         "pitch_deg", "roll_deg", "yaw_deg"};

/* The temporary file an interrupted run must not leave behind (signal handler). */
static char tmp_path[4096];
static volatile sig_atomic_t tmp_live;

static void on_signal(int sig)
{
    if (tmp_live) unlink(tmp_path);
    signal(sig, SIG_DFL);
    raise(sig);
}

static void binding_text(const hp_layout *L, const batch_out *o, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < L->n; ++k) {
        if (!o->binding[k]) continue;
        int n = snprintf(buf + used, size - used, "%s%s:", used ? ";" : "",
                         L->bladders[k].name);
        if (n < 0 || (size_t)n >= size - used) return;
        used += (size_t)n;
        int first = 1;
        for (int b = 0; b < HP_BIND_COUNT; ++b) {
            if (!(o->binding[k] & (1u << b))) continue;
            n = snprintf(buf + used, size - used, "%s%s", first ? "" : "|",
                         hp_binding_name(1u << b));
            if (n < 0 || (size_t)n >= size - used) return;
            used += (size_t)n;
            first = 0;
        }
    }
}

static const char *status_text(const batch_out *o)
{
    return o->bad ? "bad-row" : hp_status_name(o->status);
}

static int write_csv(FILE *f, const hp_layout *L, const batch_in *in, const batch_out *out,
                     size_t rows, int times)
{
    fprintf(f, "line,t_s,status");
    for (int i = 0; i < 6; ++i) fprintf(f, ",%s", POSE_KEYS[i]);
    fprintf(f, ",pose_error");
    for (int k = 0; k < L->n; ++k) fprintf(f, ",%s_pa", L->bladders[k].name);
    fprintf(f, ",binding,iterations%s\n", times ? ",solve_time_us" : "");
    char bind[2048];
    for (size_t i = 0; i < rows; ++i) {
        const batch_out *o = &out[i];
        if (o->bad) {
            fprintf(f, "%ld,,bad-row", in[i].line);
            for (int c = 0; c < 7 + L->n + 2 + times; ++c) fputc(',', f);
            fputc('\n', f);
            continue;
        }
        double pose[6];
        hp_pose_to_clinical(o->achieved, pose);
        char num[HP_FMT_MAX];
        fprintf(f, "%ld,%s,%s", in[i].line, hp_cli_fmt(num, in[i].t), status_text(o));
        for (int c = 0; c < 6; ++c) fprintf(f, ",%s", hp_cli_fmt(num, pose[c]));
        fprintf(f, ",%s", hp_cli_fmt(num, o->pose_error));
        for (int k = 0; k < L->n; ++k) fprintf(f, ",%s", hp_cli_fmt(num, o->pressure[k]));
        binding_text(L, o, bind, sizeof bind);
        fprintf(f, ",%s,%d", bind, o->iterations);
        if (times) fprintf(f, ",%.3f", o->solve_time * 1e6);
        fputc('\n', f);
    }
    return 0;
}

static int write_jsonl(FILE *f, const hp_layout *L, const batch_in *in, const batch_out *out,
                       size_t rows, int times)
{
    const size_t flags = JSON_COMPACT | JSON_PRESERVE_ORDER |
                         JSON_REAL_PRECISION(HP_JSON_REAL_PRECISION);
    for (size_t i = 0; i < rows; ++i) {
        const batch_out *o = &out[i];
        json_t *row = json_object();
        json_object_set_new(row, "line", json_integer(in[i].line));
        if (o->bad) {
            json_object_set_new(row, "status", json_string("bad-row"));
            json_object_set_new(row, "error", json_string(in[i].msg ? in[i].msg : ""));
        } else {
            double pose[6];
            hp_pose_to_clinical(o->achieved, pose);
            json_object_set_new(row, "t_s", json_real(in[i].t));
            json_object_set_new(row, "status", json_string(status_text(o)));
            json_t *ach = json_object();
            for (int c = 0; c < 6; ++c) json_object_set_new(ach, POSE_KEYS[c], json_real(pose[c]));
            json_object_set_new(row, "achieved", ach);
            json_object_set_new(row, "pose_error", json_real(o->pose_error));
            json_t *pr = json_object(), *bind = json_object();
            for (int k = 0; k < L->n; ++k) {
                json_object_set_new(pr, L->bladders[k].name, json_real(o->pressure[k]));
                if (!o->binding[k]) continue;
                json_t *list = json_array();
                for (int b = 0; b < HP_BIND_COUNT; ++b)
                    if (o->binding[k] & (1u << b))
                        json_array_append_new(list, json_string(hp_binding_name(1u << b)));
                json_object_set_new(bind, L->bladders[k].name, list);
            }
            json_object_set_new(row, "pressures_pa", pr);
            json_object_set_new(row, "binding", bind);
            json_object_set_new(row, "iterations", json_integer(o->iterations));
            if (times) json_object_set_new(row, "solve_time_us", json_real(o->solve_time * 1e6));
        }
        char *text = json_dumps(row, flags);
        json_decref(row);
        if (!text) return -1;
        fputs(text, f);
        fputc('\n', f);
        free(text);
    }
    return 0;
}

FILE *batch_open(const char *path)
{
    if (!path) return stdout;
    int n = snprintf(tmp_path, sizeof tmp_path, "%s.partial-%ld", path, (long)getpid());
    if (n < 0 || (size_t)n >= sizeof tmp_path) {
        fprintf(stderr, "headplan batch: -o: %s: path too long\n", path);
        return NULL;
    }
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        fprintf(stderr, "headplan batch: -o: %s is a directory, not a file\n", path);
        return NULL;
    }
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGHUP, on_signal);
    FILE *f = fopen(tmp_path, "wx");
    if (!f) {
        fprintf(stderr, "headplan batch: -o: cannot create %s (as %s): %s\n", path, tmp_path,
                strerror(errno));
        return NULL;
    }
    tmp_live = 1;
    return f;
}

void batch_abandon(FILE *f, const char *path)
{
    if (!f || !path) return;
    fclose(f);
    unlink(tmp_path);
    tmp_live = 0;
}

int batch_write(FILE *f, const char *path, hp_trace_format fmt, const hp_layout *L,
                const batch_in *in, const batch_out *out, size_t rows, int times)
{
    int rc = fmt == HP_TRACE_CSV ? write_csv(f, L, in, out, rows, times)
                                 : write_jsonl(f, L, in, out, rows, times);
    if (fflush(f) != 0 || ferror(f)) rc = -1;
    if (path) {
        if (rc == 0 && fsync(fileno(f)) != 0) rc = -1;
        if (fclose(f) != 0) rc = -1;
        if (rc == 0 && rename(tmp_path, path) != 0) rc = -1;
        if (rc != 0) {
            fprintf(stderr, "headplan batch: -o: cannot write %s: %s\n", path, strerror(errno));
            unlink(tmp_path);
        }
        tmp_live = 0;
    }
    return rc == 0 ? 0 : HP_EXIT_CANTCREAT;
}
