/* headplan render: a scene and one plan drawn in 3-D by gnuplot — the head, every bladder as
 * a sphere of its planned outer radius coloured by its pressure (kPa scale), binding limits
 * marked, and the desired against the achieved head motion (magnified), in two views that
 * together show all the bladders. Units: mm, degrees, kPa on the picture. */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli_args.h"
#include "common/units.h"
#include "cli/cli_scene.h"
#include "cli/cmd_solve_load.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/gnuplot_out.h"
#include "headplan/hp_planner.h"
#include "headplan/hp_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const CMD = "render";

static void help(void)
{
    printf("usage: headplan render SCENE [--correction X,Y,Z,PITCH,ROLL,YAW] [--backend NAME]\n"
           "                       [--level NAME] -o FILE.png|FILE.svg [--size WxH]\n"
           "                       [--script-out FILE.gp] [--dry-run]\n\n"
           "Plans one correction like headplan solve and draws it with gnuplot: the head\n"
           "(grey mesh), every bladder as a sphere of its planned outer radius coloured by its\n"
           "pressure on a kPa scale from the lowest to the highest pressure limit, bladders\n"
           "on a limit circled in red and named with the limit, and the head's motion at three\n"
           "landmarks (nose, vertex, left side): desired (wide, green) against achieved\n"
           "(blue), magnified so that it can be seen. Two views (from the feet and from below)\n"
           "show all the bladders; a table lists pressures, limits and the two poses.\n\n"
           "  --correction X,Y,Z,PITCH,ROLL,YAW  mm and degrees; default: the scene's (else 0)\n"
           "  --backend NAME, --level NAME       as for headplan solve\n"
           "%s"
           "  --help         this text\n\n"
           "exit status: 0 picture written, 64 bad command line, 65 bad scene, 66 scene\n"
           "cannot be read, 69 gnuplot not installed, 70 planner or gnuplot failure, 73\n"
           "picture or script cannot be written\n",
           GP_HELP);
}

typedef struct render_args {
    const char *scene, *correction, *backend, *level;
    gp_out out;
} render_args;

static int parse(int argc, char **argv, render_args *a)
{
    const char *const names[] = {"--correction", "--backend", "--level"};
    const char **slots[] = {&a->correction, &a->backend, &a->level};
    const cli_grammar g = {
        help, names, slots, 3, NULL, NULL, 0, gp_option_of, &a->out, {&a->scene, NULL}, 1, "SCENE"};
    int rc = cli_parse(CMD, argc, argv, &g);
    return rc >= 0 ? rc : gp_check(CMD, &a->out);
}

/* What the picture shows. */
typedef struct picture {
    const hp_layout *L;
    const char *scene_name;
    hp_result r;
    const char *message;
    const char *level_choice; /* hp_planner_level_choice: "" for a stated level */
} picture;

/* A head point q (m) moved by pose xi (SI), in mm. */
static void moved_mm(const hp_layout *L, const double xi[6], const double q[3], double out[3])
{
    double R[9];
    hp_rotation(xi[HP_PITCH], xi[HP_ROLL], xi[HP_YAW], R);
    for (int i = 0; i < 3; ++i) {
        double v = L->pivot[i] + xi[i];
        for (int j = 0; j < 3; ++j) v += R[i * 3 + j] * (q[j] - L->pivot[j]);
        out[i] = v * 1e3;
    }
}

/* Landmarks on the head surface: nose tip (+Z), vertex (+Y), left side (+X). */
static void landmark(const hp_head *h, int k, double q[3])
{
    for (int i = 0; i < 3; ++i) q[i] = h->center[i];
    q[k == 0 ? 2 : k == 1 ? 1 : 0] += h->semi_axes[k == 0 ? 2 : k == 1 ? 1 : 0];
}

/* The magnification that makes the largest landmark motion about 25 mm: 1, 2 or 5 times a
 * power of ten, at least 1. */
static double magnification(const picture *p)
{
    double zero[6] = {0}, big = 0;
    for (int k = 0; k < 3; ++k) {
        double q[3], a[3], b[3], c[3];
        landmark(&p->L->head, k, q);
        moved_mm(p->L, zero, q, a);
        moved_mm(p->L, p->r.desired, q, b);
        moved_mm(p->L, p->r.achieved, q, c);
        for (int i = 0; i < 3; ++i) big = fmax(big, fmax(fabs(b[i] - a[i]), fabs(c[i] - a[i])));
    }
    if (!(big > 0)) return 1;
    double want = 25.0 / big, m = 1;
    while (m * 10 <= want && m < 1e6) m *= 10;
    if (m * 5 <= want) m *= 5;
    else if (m * 2 <= want) m *= 2;
    return m;
}

static void binding_text(unsigned flags, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    for (int b = 0; b < HP_BIND_COUNT; ++b)
        if (flags & (1u << b)) {
            int n = snprintf(buf + used, size - used, "%s%s", used ? "," : "",
                             hp_binding_name(1u << b));
            if (n < 0 || (size_t)n >= size - used) return;
            used += (size_t)n;
        }
}

/* Data blocks: $head (ellipsoid mesh), $bladders (one sphere grid per bladder, the 4th
 * column its pressure in kPa, the 5th its index). */
static void write_data(const picture *p, FILE *f)
{
    const hp_head *h = &p->L->head;
    fprintf(f, "$head << EOD\n");
    for (int i = 0; i <= 18; ++i) {
        double th = HP_PI * i / 18.0;
        for (int j = 0; j <= 36; ++j) {
            double ph = 2 * HP_PI * j / 36.0;
            fprintf(f, "%.4f %.4f %.4f\n",
                    (h->center[0] + h->semi_axes[0] * sin(th) * cos(ph)) * 1e3,
                    (h->center[1] + h->semi_axes[1] * cos(th)) * 1e3,
                    (h->center[2] + h->semi_axes[2] * sin(th) * sin(ph)) * 1e3);
        }
        fprintf(f, "\n");
    }
    fprintf(f, "EOD\n$bladders << EOD\n");
    for (int k = 0; k < p->L->n; ++k) {
        const double *c = p->L->bladders[k].center;
        double ro = p->r.bladders[k].ro * 1e3, kpa = p->r.bladders[k].pressure * 1e-3;
        /* The scene reader allows letters, digits, '_' and '-' only in a bladder's name;
         * the name never ends the line (a comment ending in '\\' would go on). */
        fprintf(f, "# %d %s: pressure %.6g kPa, outer radius %.6g mm\n", k + 1,
                gp_control_byte(p->L->bladders[k].name) < 0 ? p->L->bladders[k].name : "?", kpa,
                ro);
        for (int i = 0; i <= 12; ++i) {
            double th = HP_PI * i / 12.0;
            for (int j = 0; j <= 24; ++j) {
                double ph = 2 * HP_PI * j / 24.0;
                fprintf(f, "%.4f %.4f %.4f %.6g %d\n", c[0] * 1e3 + ro * sin(th) * cos(ph),
                        c[1] * 1e3 + ro * sin(th) * sin(ph), c[2] * 1e3 + ro * cos(th), kpa, k + 1);
            }
            fprintf(f, "\n");
        }
        fprintf(f, "\n");
    }
    fprintf(f, "EOD\n");
}

/* Labels and arrows common to both views. */
static void write_marks(const picture *p, FILE *f, double mag)
{
    const hp_layout *L = p->L;
    for (int k = 0; k < L->n; ++k) {
        /* The label sits outside the sphere, away from the head centre. */
        double d[3], len = 0, ro = p->r.bladders[k].ro * 1e3;
        for (int i = 0; i < 3; ++i) {
            d[i] = L->bladders[k].center[i] - L->head.center[i];
            len += d[i] * d[i];
        }
        len = sqrt(len);
        double at[3];
        for (int i = 0; i < 3; ++i) at[i] = L->bladders[k].center[i] * 1e3 + d[i] / len * (ro + 9);
        unsigned b = p->r.bladders[k].binding;
        fprintf(f, "set label %d '%d' at %.3f,%.3f,%.3f center front font ',13' tc rgb '%s'\n",
                k + 1, k + 1, at[0], at[1], at[2], b ? "#d00000" : "#202020");
        if (b)
            fprintf(f,
                    "set object %d circle at %.3f,%.3f,%.3f size char 1.6 front "
                    "fs empty border lc rgb '#d00000' lw 2\n",
                    k + 1, at[0], at[1], at[2]);
    }
    double zero[6] = {0};
    for (int k = 0; k < 3; ++k) {
        double q[3], a[3], b[3], c[3];
        landmark(&L->head, k, q);
        moved_mm(L, zero, q, a);
        moved_mm(L, p->r.desired, q, b);
        moved_mm(L, p->r.achieved, q, c);
        fprintf(f,
                "set arrow %d from %.4f,%.4f,%.4f to %.4f,%.4f,%.4f front lw 6 "
                "lc rgb '#66bd63'\n",
                10 + k, a[0], a[1], a[2], a[0] + mag * (b[0] - a[0]), a[1] + mag * (b[1] - a[1]),
                a[2] + mag * (b[2] - a[2]));
        fprintf(f,
                "set arrow %d from %.4f,%.4f,%.4f to %.4f,%.4f,%.4f front lw 2 "
                "lc rgb '#2166ac'\n",
                20 + k, a[0], a[1], a[2], a[0] + mag * (c[0] - a[0]), a[1] + mag * (c[1] - a[1]),
                a[2] + mag * (c[2] - a[2]));
    }
}

static void write_table(const picture *p, FILE *f, double mag, double left)
{
    const hp_layout *L = p->L;
    double y = 0.93, step = 0.036;
    fprintf(f,
            "set label 101 'bladder                      kPa   [min, max]' at screen %.3f,%.3f "
            "font 'Mono,10'\n",
            left, y);
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        char bind[160], text[256];
        binding_text(p->r.bladders[k].binding, bind, sizeof bind);
        y -= step;
        snprintf(text, sizeof text, "%d %-18.18s %7.3f  [%g, %g] %s", k + 1, B->name,
                 p->r.bladders[k].pressure * 1e-3, B->p_min * 1e-3, B->p_max * 1e-3, bind);
        fprintf(f, "set label %d ", 102 + k);
        gp_label(f, text);
        fprintf(f, " at screen %.3f,%.3f font 'Mono,10' tc rgb '%s' noenhanced\n", left, y,
                *bind ? "#d00000" : "#202020");
    }
    double d[6], a[6];
    hp_pose_to_clinical(p->r.desired, d);
    hp_pose_to_clinical(p->r.achieved, a);
    y -= 1.6 * step;
    fprintf(f,
            "set label 130 'pose        desired    achieved' at screen %.3f,%.3f "
            "font 'Mono,10' noenhanced\n",
            left, y);
    for (int i = 0; i < 6; ++i) {
        y -= step;
        fprintf(f,
                "set label %d '%-10s %9.4f  %9.4f' at screen %.3f,%.3f font 'Mono,10' "
                "noenhanced\n",
                131 + i, hp_pose_key(i), d[i], a[i], left, y);
    }
    y -= 1.6 * step;
    fprintf(f,
            "set label 140 'status %s, %s backend, %s contact' at screen %.3f,%.3f "
            "font 'Sans,10' noenhanced\n",
            hp_status_name(p->r.status), hp_backend_name(p->r.backend), hp_level_name(p->r.level),
            left, y);
    y -= step;
    fprintf(f,
            "set label 141 'head motion x%g: desired (wide green), achieved (blue)' at "
            "screen %.3f,%.3f font 'Sans,10' noenhanced\n",
            mag, left, y);
    y -= step;
    fprintf(f,
            "set label 142 'red: a bladder on a limit' at screen %.3f,%.3f font 'Sans,10' "
            "tc rgb '#d00000'\n",
            left, y);
    if (*p->message) {
        /* The planner's own words for a status other than reached, cut to the panel. */
        y -= step;
        fprintf(f, "set label 143 ");
        char text[72];
        snprintf(text, sizeof text, "%s", p->message);
        gp_label(f, text);
        fprintf(f, " at screen %.3f,%.3f font 'Sans,9' noenhanced\n", left, y);
    }
    if (*p->level_choice) {
        /* Too long for the panel: one line along the bottom of the whole picture. */
        char text[400];
        snprintf(text, sizeof text, "level choice: %s", p->level_choice);
        fprintf(f, "set label 144 ");
        gp_label(f, text);
        fprintf(f, " at screen 0.010,0.012 font 'Sans,8' noenhanced\n");
    }
}

/* The whole gnuplot script: terminal, data, settings, then the two views in a multiplot;
 * the second also carries the colour scale and the table. */
typedef struct full_script {
    const picture *p;
    const gp_out *out;
} full_script;

static int write_full(const void *arg, FILE *f)
{
    const full_script *s = arg;
    const picture *p = s->p;
    const hp_layout *L = p->L;
    double lo = INFINITY, hi = -INFINITY;
    for (int k = 0; k < L->n; ++k) {
        lo = fmin(lo, L->bladders[k].p_min * 1e-3);
        hi = fmax(hi, L->bladders[k].p_max * 1e-3);
    }
    double mag = magnification(p);
    /* The scene's name appears only as the quoted title (cli_gptext.h). */
    fprintf(f, "# headplan render: a scene and one plan. Units: mm; colour: pressure in kPa.\n"
               "# Redraw with: gnuplot THIS_FILE\n");
    if (gp_terminal(f, s->out) != 0) return -1;
    write_data(p, f);
    fprintf(f,
            "set view equal xyz\nset xyplane 0\nset border 0\nunset tics\nunset key\n"
            "set pm3d depthorder border lc rgb '#606060' lw 0.3\n"
            "unset colorbox\nset cbrange [%.6g:%.6g]\n",
            lo, hi);
    /* White at 0 kPa when the limits straddle it: blue is suction, red inflation. */
    if (lo < 0 && hi > 0)
        fprintf(f, "set palette defined (%.6g '#2166ac', 0 '#f7f7f7', %.6g '#b2182b')\n", lo, hi);
    else fprintf(f, "set palette defined (%.6g '#f7f7f7', %.6g '#b2182b')\n", lo, hi);
    write_marks(p, f, mag);
    fprintf(f, "set multiplot title ");
    gp_label(f, p->scene_name);
    fprintf(f,
            " noenhanced font ',14'\n"
            "set size 0.36,0.92\nset origin 0.0,0.02\n"
            "set view 90,0,1.3\nset title 'from the feet (+Z anterior up, +X left to the right)'\n"
            "splot $head using 1:2:3 with lines lc rgb '#b8b8b8' lw 0.5, \\\n"
            "      $bladders using 1:2:3:4 with pm3d\n"
            "set origin 0.33,0.02\n"
            "set view 180,0,1.3\nset title 'from below (+X left to the right, +Y superior down)'\n"
            "set colorbox user horizontal origin 0.70,0.10 size 0.27,0.03\n"
            "set cblabel 'pressure [kPa]'\nset cbtics\n");
    write_table(p, f, mag, 0.70);
    fprintf(f, "splot $head using 1:2:3 with lines lc rgb '#b8b8b8' lw 0.5, \\\n"
               "      $bladders using 1:2:3:4 with pm3d\n"
               "unset multiplot\n");
    return ferror(f) ? -1 : 0;
}

int cmd_render(int argc, char **argv)
{
    render_args a = {0};
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    double clin[6] = {0}, desired[6] = {0};
    if (a.correction && (rc = cli_doubles(CMD, "--correction", a.correction, 6, clin))) return rc;
    hp_scene *sc = NULL;
    if ((rc = cli_load_scene(CMD, a.scene, NULL, &sc))) return rc;
    if (a.correction) {
        hp_pose_from_clinical(clin, desired);
        if ((rc = cli_scene_set_correction(CMD, sc, desired))) {
            free(sc);
            return rc;
        }
    } else if (sc->has_correction) memcpy(desired, sc->correction, sizeof desired);
    hp_settings s;
    if ((rc = cli_kinematic_only(CMD, sc, a.level,
                                 "give --level surface (or plane, linear) to draw the plan "
                                 "without it")) ||
        (rc = cli_settings(CMD, sc, a.backend, a.level, &s))) {
        free(sc);
        return rc;
    }
    s.use_rate_limits = 0; /* one plan from the nominal pose, as headplan solve */
    hp_diag d = {{0}};
    hp_planner *p = NULL;
    if (hp_planner_create(&sc->layout, &s, &p, &d) != HP_OK) {
        rc = cli_fail(CLI_EXIT_DATAERR, CMD, "%s: %s", cli_name(a.scene), d.text);
        free(sc);
        return rc;
    }
    char level_why[320];
    hp_planner_level_choice(p, level_why, sizeof level_why); /* built: HP_OK */
    picture pic = {hp_planner_layout(p), sc->name, {0}, "", level_why};
    hp_error e = hp_plan(p, desired, &pic.r);
    /* hp_plan answers a refused correction with HP_OK and status invalid-input: refused
     * here as in solve (65), not drawn as a picture of the safe output. */
    if (pic.r.status == HP_STATUS_INVALID_INPUT) {
        rc = cli_fail(CLI_EXIT_DATAERR, CMD, "%s: %s", a.correction ? "--correction" : "correction",
                      hp_planner_error(p));
    } else if (e != HP_OK) {
        rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "%s: planner call failed: %s", cli_name(a.scene),
                      hp_error_message(e));
    } else {
        pic.message = hp_planner_message(p); /* a closest answer explains itself too */
        cli_input_of(&a.out.inputs[0], "scene", a.scene);
        a.out.ninputs = 1;
        /* render does not read the scene's trace, but it is the user's data all the same:
         * never written over by --script-out or -o. */
        if (sc->has_trace)
            cli_input_of(&a.out.inputs[a.out.ninputs++], "scene's trace", sc->trace_path);
        full_script fs = {&pic, &a.out};
        rc = gp_draw(CMD, &a.out, write_full, &fs);
    }
    hp_planner_destroy(p);
    free(sc);
    return rc;
}
