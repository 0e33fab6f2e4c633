/* headplan fit: calibration from measurements (docs/calibration.md).
 *   fit material DATA --Ri-mm R --Ro-mm R [--fit-ref Ri|Ro] [--plot OUT.svg] [--json]
 *   fit layout SCENE DATA [-o OUT.yaml] [--level L] [--fit offsets,axes]
 *                         [--sigma-mm S] [--sigma-deg S] [--plot OUT.png|svg]
 *                         [--plot-script FILE.gp] [--json] */
#include "cli/cli_output.h"
#include "cli/cli_args.h"
#include "cli/cli_outfile.h"
#include "common/units.h"
#include "cli/cli_scene.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "cli/fit_plot.h"
#include "cli/gnuplot_out.h"
#include "headplan/headplan.h"
#include "kinematics/names.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CMD "fit"
#define DEG HP_DEG_PER_RAD
/* Candidate pressures the material planning table tries. */
#define N_CAND 9

static void help(void)
{
    char geometries[64];
    printf("usage: headplan fit material DATA --Ri-mm R --Ro-mm R [--fit-ref Ri|Ro]\n"
           "                             [--plot OUT.svg] [--json]\n"
           "       headplan fit layout SCENE DATA [-o OUT.yaml] [--level L] [--fit WHAT]\n"
           "                           [--sigma-mm S] [--sigma-deg S] [--plot OUT.png|svg]\n"
           "                           [--plot-script FILE.gp] [--json]\n\n"
           "material: fit one bladder's moduli C1, C2 (paper convention) to free-inflation\n"
           "  measurements. DATA is CSV with the header pressure_pa,ri_mm (or ro_mm; pressure_kpa\n"
           "  allowed) and an optional third column sigma_mm (the radius's standard deviation);\n"
           "  DATA - reads standard input (for layout: SCENE or DATA, not both).\n"
           "  --Ri-mm, --Ro-mm   the bladder's reference inner and outer radius (required)\n"
           "  --fit-ref Ri|Ro    also fit that reference radius (its option is then the start);\n"
           "                     refused by name when the data cannot tell it from the moduli\n"
           "  --plot OUT.svg     also write the residuals against the pressure as an SVG chart\n"
           "layout: fit every bladder's radial offset, the head's semi-axes and (with a load\n"
           "  section, by the forward statics) the carried mass to measured\n"
           "  (pressures, pose) rows. DATA is CSV: p_<bladder>_pa (or _kpa) for every bladder of\n"
           "  SCENE, then x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg.\n"
           "  -o OUT.yaml        write the calibrated scene (atomically; never over an input)\n"
           "  --level L          forward model: %s (default: the scene's\n"
           "                     level, auto resolved as solve does)\n"
           "  --fit WHAT         a comma list of offsets, axes, mass (default offsets,axes; with\n"
           "                     a load section also mass, fitted through the forward statics)\n"
           "  --sigma-mm S       standard deviation of a measured translation (default 0.1)\n"
           "  --sigma-deg S      standard deviation of a measured rotation (default 0.1)\n"
           "  --plot OUT.png     also draw every row's residual per pose axis before and after\n"
           "                     the fit (gnuplot; .png or .svg)\n"
           "  --plot-script F    keep the gnuplot script of --plot (data inline)\n"
           "  --json             one JSON object on stdout instead of text\n"
           "  --help             this text\n\n"
           "Intervals are 95 %% (Student's t), from the fit's Jacobian with the scatter estimated\n"
           "from the residuals. exit status: 0 ok, 64 usage, 65 bad data or data that cannot\n"
           "determine the fit, 66 cannot open, 69 gnuplot missing (--plot), 70 internal failure,\n"
           "73 cannot write\n",
           hpi_level_geometry_names(geometries, sizeof geometries));
}

static int status_of(hp_error e)
{
    switch (e) {
    case HP_ERR_IO: return CLI_EXIT_NOINPUT;
    case HP_ERR_NOMEM:
    case HP_ERR_NO_CONVERGENCE:
    case HP_ERR_SOLVER: return CLI_EXIT_SOFTWARE;
    default: return CLI_EXIT_DATAERR;
    }
}

static int print_json(json_t *o)
{
    char *s = json_dumps(o, JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(CLI_JSON_REAL_PRECISION));
    json_decref(o);
    if (!s) return cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
    cli_put_line(s);
    free(s);
    return CLI_EXIT_OK;
}

static json_t *real_or_null(double v) { return isfinite(v) ? json_real(v) : json_null(); }

/* The data's own millimetres back from the reader's metres (mm * 1e-3): m * 1e3 can be a
 * neighbour of the number written (25.5303 came back as 25.530300000000004). The number of
 * 15 significant digits nearest m * 1e3 is the one written whenever the data has at most 15
 * digits; it is taken only when the reader's conversion of it gives m again. */
static double data_mm(double m)
{
    char buf[32];
    snprintf(buf, sizeof buf, "%.15g", m * 1e3);
    double mm = strtod(buf, NULL);
    return mm * 1e-3 == m ? mm : m * 1e3;
}

/* DATA ("-": standard input, read whole and parsed from memory as <stdin>, as the other
 * commands read '-') through the material or (L not NULL) the layout reader. Returns 0, or
 * the exit status after one line. */
static int read_data(const char *data, const hp_layout *L, hp_calib_point *pts, hp_calib_row *rows,
                     int *n, hp_calib_radius *kind)
{
    char *buf = NULL;
    size_t len = 0;
    hp_diag d = {{0}};
    hp_error e;
    if (strcmp(data, "-") == 0) {
        int rc = cli_read_input(CMD, "data", data, (size_t)HP_CALIB_MAX_BYTES, "16 MiB", &buf,
                                &len);
        if (rc) return rc;
        e = L ? hp_calib_parse_layout(buf, len, cli_name(data), L, rows, HP_CALIB_MAX_ROWS, n, &d)
              : hp_calib_parse_material(buf, len, cli_name(data), pts, HP_CALIB_MAX_ROWS, n, kind,
                                        &d);
        free(buf);
    } else {
        int rc = cli_stdout_not_input(CMD, "data", data, -1, data);
        if (rc) return rc;
        e = L ? hp_calib_read_layout(data, L, rows, HP_CALIB_MAX_ROWS, n, &d)
              : hp_calib_read_material(data, pts, HP_CALIB_MAX_ROWS, n, kind, &d);
    }
    return e ? cli_fail(status_of(e), CMD, "%s", d.text) : 0;
}

/* ---------------------------------------------------------------- material */

/* Candidate pressures for the planning table: from the lowest measured pressure minus half
 * the span to the highest plus half, kept inside the stretches 0.7..1.5 of the fitted
 * bladder (a rubber shell is not stretched further for a calibration) and below 95 % of its
 * limit point. */
static void candidates(const hp_iab *b, const hp_calib_point *pts, int n, double limit,
                       double *cand)
{
    double pmin, pmax;
    if (hp_iab_ik(b, 0.7 * b->Ri, &pmin)) pmin = -INFINITY;
    if (hp_iab_ik(b, 1.5 * b->Ri, &pmax)) pmax = INFINITY;
    double lo = pts[0].pressure, hi = pts[0].pressure;
    for (int i = 1; i < n; ++i) {
        lo = fmin(lo, pts[i].pressure);
        hi = fmax(hi, pts[i].pressure);
    }
    double span = hi - lo;
    lo -= 0.5 * span;
    hi += 0.5 * span;
    if (isfinite(limit) && hi > 0.95 * limit) hi = 0.95 * limit;
    lo = fmax(lo, pmin);
    hi = fmin(hi, pmax);
    for (int j = 0; j < N_CAND; ++j) cand[j] = lo + (hi - lo) * j / (N_CAND - 1);
}

static int run_material(int argc, char **argv)
{
    const char *data = NULL, *ri_t = NULL, *ro_t = NULL, *plot = NULL, *ref_t = NULL;
    int json = 0;
    /* One matcher for both fits: a value given twice is refused, not silently replaced. */
    const char *const names[] = {"--Ri-mm", "--Ro-mm", "--plot", "--fit-ref"};
    const char **slots[] = {&ri_t, &ro_t, &plot, &ref_t};
    for (int i = 0, operands = 0; i < argc; ++i) {
        int m;
        if (!operands && strcmp(argv[i], "--") == 0) {
            operands = 1;
        } else if (!operands && strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (!operands && (m = cli_named_opt(CMD, argc, argv, &i, names, slots, 4)) != 0) {
            if (m < 0) return CLI_EXIT_USAGE;
        } else if (!operands && argv[i][0] == '-' && argv[i][1] != '\0') {
            return cli_fail(CLI_EXIT_USAGE, CMD, "unknown option '%s'", argv[i]);
        } else if (data) {
            return cli_fail(CLI_EXIT_USAGE, CMD, "material: one DATA file only");
        } else {
            data = argv[i];
        }
    }
    if (!data) return cli_fail(CLI_EXIT_USAGE, CMD, "material: missing DATA file");
    /* The chart is written as SVG by fit_plot_svg (no gnuplot): any other name would get
     * SVG bytes under it. An empty name or '-' is refused as every output refuses it. */
    int plot_rc = plot ? cli_out_allowed(CMD, "--plot", plot, NULL, 0) : 0;
    if (plot_rc) return plot_rc;
    if (plot && !(strlen(plot) > 4 && strcmp(plot + strlen(plot) - 4, ".svg") == 0))
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "--plot: '%s' must end in .svg (fit material draws an SVG chart)", plot);
    if (!ri_t || !ro_t)
        return cli_fail(CLI_EXIT_USAGE, CMD, "material: --Ri-mm and --Ro-mm are required");
    double Ri, Ro;
    int rc = cli_double(CMD, "--Ri-mm", ri_t, &Ri);
    if (!rc) rc = cli_double(CMD, "--Ro-mm", ro_t, &Ro);
    if (rc) return rc;
    if (!(Ri > 0) || !(Ro > Ri))
        return cli_fail(CLI_EXIT_USAGE, CMD, "--Ri-mm, --Ro-mm: need 0 < Ri < Ro (got %g, %g)", Ri,
                        Ro);
    Ri *= 1e-3;
    Ro *= 1e-3;
    int fit_ref = ref_t != NULL;
    hp_calib_radius ref = HP_CALIB_INNER;
    if (ref_t && strcmp(ref_t, "Ro") == 0) ref = HP_CALIB_OUTER;
    else if (ref_t && strcmp(ref_t, "Ri") != 0)
        return cli_fail(CLI_EXIT_USAGE, CMD, "--fit-ref: '%s': use Ri or Ro", ref_t);

    hp_calib_point *pts = malloc(sizeof *pts * HP_CALIB_MAX_ROWS);
    double *res = malloc(sizeof *res * HP_CALIB_MAX_ROWS);
    if (!pts || !res) {
        free(pts);
        free(res);
        return cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
    }
    int n = 0;
    hp_calib_radius kind;
    hp_diag d = {{0}};
    hp_material_fit f;
    hp_error e;
    rc = read_data(data, NULL, pts, NULL, &n, &kind);
    if (!rc && (e = fit_ref ? hp_fit_material_ref(Ri, Ro, kind, ref, pts, n, &f, res, &d)
                            : hp_fit_material(Ri, Ro, kind, pts, n, &f, res, &d)) != HP_OK)
        rc = cli_fail(status_of(e), CMD, "%s: %s", cli_name(data), d.text);
    if (!rc && f.ref_fitted) {
        /* From here on the bladder is the fitted one. */
        if (ref == HP_CALIB_INNER) Ri = f.ref;
        else Ro = f.ref;
    }
    if (rc) {
        free(pts);
        free(res);
        return rc;
    }
    if (plot) {
        /* Residuals in mm against pressure in kPa; dashed: ±t·s·σ of the first point, the
         * band a residual of that weight stays inside 95 % of the time. */
        double *xs = malloc(sizeof *xs * (size_t)n), *ys = malloc(sizeof *ys * (size_t)n);
        if (!xs || !ys) rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
        for (int i = 0; !rc && i < n; ++i) {
            xs[i] = pts[i].pressure * 1e-3;
            ys[i] = res[i] * 1e3;
        }
        cli_input in;
        cli_input_of(&in, "data", data);
        if (!rc)
            rc = fit_plot_svg(CMD, plot, &in, 1,
                              "headplan fit material: residuals (measured - fitted)", xs, ys, n,
                              f.t * f.s * pts[0].sigma * 1e3, "pressure [kPa]",
                              kind == HP_CALIB_INNER ? "ri residual [mm]" : "ro residual [mm]");
        free(xs);
        free(ys);
        if (rc) {
            free(pts);
            free(res);
            return rc;
        }
    }
    double cand[N_CAND], shrink[2 * N_CAND];
    /* The next point is assumed as precise as the first one measured. */
    double sig = pts[0].sigma;
    hp_iab fitted = {Ri, Ro, f.C1, f.C2};
    candidates(&fitted, pts, n, f.limit_pressure, cand);
    if (hp_fit_material_gain(Ri, Ro, kind, pts, n, &f, cand, N_CAND, sig, shrink, &d))
        for (int j = 0; j < 2 * N_CAND; ++j) shrink[j] = NAN;
    const char *rname = kind == HP_CALIB_INNER ? "ri" : "ro";

    if (json) {
        json_t *o = json_object();
        json_object_set_new(o, "data", json_string(cli_name(data)));
        json_object_set_new(o, "radius", json_string(kind == HP_CALIB_INNER ? "inner" : "outer"));
        json_object_set_new(o, "points", json_integer(n));
        json_object_set_new(o, "Ri_mm", json_real(Ri * 1e3));
        json_object_set_new(o, "Ro_mm", json_real(Ro * 1e3));
        const char *nm[2] = {"C1_pa", "C2_pa"};
        for (int j = 0; j < 2; ++j) {
            json_t *p = json_object();
            json_object_set_new(p, "value", json_real(j ? f.C2 : f.C1));
            json_object_set_new(p, "se", json_real(f.se[j]));
            json_object_set_new(p, "ci95", json_pack("[f,f]", f.ci[j][0], f.ci[j][1]));
            json_object_set_new(o, nm[j], p);
        }
        if (f.ref_fitted) {
            json_t *p = json_object();
            json_object_set_new(p, "value", json_real(f.ref * 1e3));
            json_object_set_new(p, "se", json_real(f.ref_se * 1e3));
            json_object_set_new(p, "ci95",
                                json_pack("[f,f]", f.ref_ci[0] * 1e3, f.ref_ci[1] * 1e3));
            json_object_set_new(p, "corr_C1", json_real(f.ref_corr[0]));
            json_object_set_new(p, "corr_C2", json_real(f.ref_corr[1]));
            json_object_set_new(o, ref == HP_CALIB_INNER ? "fitted_Ri_mm" : "fitted_Ro_mm", p);
        }
        json_object_set_new(o, "C10_pa", json_real(f.C10));
        json_object_set_new(o, "C01_pa", json_real(f.C01));
        json_object_set_new(o, "correlation", json_real(f.corr));
        json_object_set_new(o, "condition", json_real(f.condition));
        json_object_set_new(o, "dof", json_integer(f.dof));
        json_object_set_new(o, "t975", json_real(f.t));
        json_object_set_new(o, "s_unit_weight", json_real(f.s));
        json_object_set_new(o, "rms_mm", json_real(f.rms * 1e3));
        json_object_set_new(o, "iterations", json_integer(f.iterations));
        json_object_set_new(o, "limit_pressure_pa", real_or_null(f.limit_pressure));
        json_t *rs = json_array();
        for (int i = 0; i < n; ++i)
            json_array_append_new(rs,
                                  json_pack("{s:I,s:f,s:f,s:f}", "line", (json_int_t)pts[i].line,
                                            "pressure_pa", pts[i].pressure, "measured_mm",
                                            data_mm(pts[i].radius), "residual_mm", res[i] * 1e3));
        json_object_set_new(o, "residuals", rs);
        json_t *nx = json_array();
        for (int j = 0; j < N_CAND; ++j) {
            json_t *c = json_object();
            json_object_set_new(c, "pressure_pa", json_real(cand[j]));
            json_object_set_new(c, "se_ratio_C1", real_or_null(shrink[2 * j]));
            json_object_set_new(c, "se_ratio_C2", real_or_null(shrink[2 * j + 1]));
            json_array_append_new(nx, c);
        }
        json_object_set_new(o, "next_point", nx);
        json_object_set_new(
            o, "scene_fragment",
            json_pack("{s:s,s:f,s:f}", "convention", "paper", "C1_pa", f.C1, "C2_pa", f.C2));
        free(pts);
        free(res);
        return print_json(o);
    }
    printf("material fit: %s, %d points (%s radius), Ri %g mm, Ro %g mm\n", cli_name(data), n,
           kind == HP_CALIB_INNER ? "inner" : "outer", Ri * 1e3, Ro * 1e3);
    printf("  C1  = %-12.6g Pa  SE %-10.4g 95%% [%.6g, %.6g]\n", f.C1, f.se[0], f.ci[0][0],
           f.ci[0][1]);
    printf("  C2  = %-12.6g Pa  SE %-10.4g 95%% [%.6g, %.6g]\n", f.C2, f.se[1], f.ci[1][0],
           f.ci[1][1]);
    if (f.ref_fitted)
        printf("  %s  = %-12.6g mm  SE %-10.4g 95%% [%.6g, %.6g]  (fitted; correlation with "
               "C1 %.3f, C2 %.3f)\n",
               ref == HP_CALIB_INNER ? "Ri" : "Ro", f.ref * 1e3, f.ref_se * 1e3, f.ref_ci[0] * 1e3,
               f.ref_ci[1] * 1e3, f.ref_corr[0], f.ref_corr[1]);
    printf("  C10 = %-12.6g Pa  C01 = %.6g Pa (finite-element convention: C1/2, C2/2)\n", f.C10,
           f.C01);
    printf("  correlation(C1, C2) %.4f, condition number %.3g, %d iterations\n", f.corr,
           f.condition, f.iterations);
    printf("  residual RMS %.4g mm; scatter s = %.4g (for unit weight), %d degrees of freedom, "
           "t(0.975) = %.4f\n",
           f.rms * 1e3, f.s, f.dof, f.t);
    for (int j = 0; j < 2; ++j)
        if (f.ci[j][0] <= 0)
            printf("  warning: the interval of %s reaches 0: these data barely determine it\n",
                   j ? "C2" : "C1");
    if (isfinite(f.limit_pressure))
        printf("  limit point of the fitted bladder: %.6g Pa\n", f.limit_pressure);
    else printf("  the fitted bladder has no limit point (pressure rises monotonically)\n");
    printf("\nresiduals (measured - fitted):\n  %6s %14s %14s %14s %14s\n", "line", "pressure_pa",
           kind == HP_CALIB_INNER ? "ri_mm" : "ro_mm", "fitted_mm", "residual_mm");
    for (int i = 0; i < n; ++i)
        printf("  %6ld %14.6g %14.6f %14.6f %+14.6f\n", pts[i].line, pts[i].pressure,
               pts[i].radius * 1e3, (pts[i].radius - res[i]) * 1e3, res[i] * 1e3);
    printf("\nnext measurement: one more point at pressure P (sigma %.4g mm) would shrink the "
           "standard errors to\n  %12s %8s %10s %10s\n",
           sig * 1e3, "pressure_pa", "lambda_i", "SE(C1) x", "SE(C2) x");
    for (int j = 0; j < N_CAND; ++j) {
        double ri = NAN;
        if (hp_iab_fk(&fitted, cand[j], &ri)) ri = NAN;
        printf("  %12.6g %8.4f %10.4f %10.4f\n", cand[j], ri / Ri, shrink[2 * j],
               shrink[2 * j + 1]);
    }
    printf("\nscene fragment (%s data):\n  material: {convention: paper, C1_pa: %.6g, C2_pa: "
           "%.6g}\n",
           rname, f.C1, f.C2);
    if (f.ref_fitted)
        printf("  %s: %.6g\n", ref == HP_CALIB_INNER ? "Ri_mm" : "Ro_mm", f.ref * 1e3);
    free(pts);
    free(res);
    return CLI_EXIT_OK;
}

/* ---------------------------------------------------------------- layout */

typedef struct layout_args {
    const char *scene, *data, *out, *level, *what, *sig_mm, *sig_deg, *plot, *plot_script;
    int json;
} layout_args;

static int parse_layout(int argc, char **argv, layout_args *a)
{
    memset(a, 0, sizeof *a);
    const char *const names[] = {"-o",          "--level", "--fit",        "--sigma-mm",
                                 "--sigma-deg", "--plot",  "--plot-script"};
    const char **slots[] = {&a->out,     &a->level, &a->what,       &a->sig_mm,
                            &a->sig_deg, &a->plot,  &a->plot_script};
    for (int i = 0, operands = 0; i < argc; ++i) {
        if (!operands && strcmp(argv[i], "--") == 0) {
            operands = 1;
            continue;
        }
        if (!operands && strcmp(argv[i], "--json") == 0) {
            a->json = 1;
            continue;
        }
        int matched = operands ? 0 : cli_named_opt(CMD, argc, argv, &i, names, slots, 7);
        if (matched < 0) return CLI_EXIT_USAGE;
        if (matched) continue;
        if (!operands && argv[i][0] == '-' && argv[i][1] != '\0')
            return cli_fail(CLI_EXIT_USAGE, CMD, "unknown option '%s'", argv[i]);
        if (!a->scene) a->scene = argv[i];
        else if (!a->data) a->data = argv[i];
        else return cli_fail(CLI_EXIT_USAGE, CMD, "layout: unexpected argument '%s'", argv[i]);
    }
    if (!a->scene || !a->data) return cli_fail(CLI_EXIT_USAGE, CMD, "layout: needs SCENE and DATA");
    if (strcmp(a->scene, "-") == 0 && strcmp(a->data, "-") == 0)
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "layout: SCENE and DATA cannot both be standard input ('-')");
    if (a->plot_script && !a->plot)
        return cli_fail(CLI_EXIT_USAGE, CMD, "--plot-script: needs --plot");
    if (a->plot) {
        int rc = gp_check_name(CMD, "--plot", a->plot, NULL);
        if (rc >= 0) return rc;
    }
    int rc;
    if ((rc = cli_outputs_distinct(CMD, "-o", a->out, "--plot", a->plot)) ||
        (rc = cli_outputs_distinct(CMD, "-o", a->out, "--plot-script", a->plot_script)) ||
        (rc = cli_outputs_distinct(CMD, "--plot-script", a->plot_script, "--plot", a->plot)))
        return rc;
    return -1;
}

static int layout_options(const layout_args *a, const hp_scene *sc, hp_layout_fit_options *o)
{
    hp_layout_fit_options_default(o);
    /* A scene with a load section is fitted through the forward statics, and by default its
     * carried mass with the rest; without one the mass is fitted only when asked for (and
     * then named as not determined: the kinematic model does not depend on it). */
    o->fit_mass = sc->has_load;
    if (a->what) {
        o->fit_axes = o->fit_offsets = o->fit_mass = 0;
        const char *p = a->what;
        while (*p) {
            size_t k = strcspn(p, ",");
            if (k == 7 && strncmp(p, "offsets", 7) == 0) o->fit_offsets = 1;
            else if (k == 4 && strncmp(p, "axes", 4) == 0) o->fit_axes = 1;
            else if (k == 4 && strncmp(p, "mass", 4) == 0) o->fit_mass = 1;
            else
                return cli_fail(CLI_EXIT_USAGE, CMD,
                                "--fit: '%s': a comma list of offsets, axes, mass", a->what);
            p += k;
            if (*p == ',') ++p;
        }
    }
    double v;
    if (a->sig_mm) {
        if (cli_double(CMD, "--sigma-mm", a->sig_mm, &v)) return CLI_EXIT_USAGE;
        if (!(v > 0)) return cli_fail(CLI_EXIT_USAGE, CMD, "--sigma-mm: must be > 0");
        o->sigma_trans = v * 1e-3;
    }
    if (a->sig_deg) {
        if (cli_double(CMD, "--sigma-deg", a->sig_deg, &v)) return CLI_EXIT_USAGE;
        if (!(v > 0)) return cli_fail(CLI_EXIT_USAGE, CMD, "--sigma-deg: must be > 0");
        o->sigma_rot = v / DEG;
    }
    hp_settings s;
    int rc = cli_settings(CMD, sc, "realtime", a->level, &s);
    if (rc) return rc;
    o->level = s.level;
    if (sc->has_load) {
        o->load = &sc->load;
        if (!a->level) o->level = sc->load_geometry;
        if (!hp_level_is_geometry(o->level)) {
            char geometries[64];
            return cli_fail(CLI_EXIT_USAGE, CMD, "--level: the forward statics need %s",
                            hpi_level_geometry_names(geometries, sizeof geometries));
        }
        return 0;
    }
    if (o->level == HP_LEVEL_AUTO &&
        hp_contact_auto(&sc->layout, s.level_tolerance, s.auto_trans, s.auto_rot, &o->level))
        return cli_fail(CLI_EXIT_SOFTWARE, CMD, "%s: auto could not choose a level",
                        cli_name(a->scene));
    return 0;
}

/* The unit of the standard error along the weakest combination: the direction is a unit
 * vector in the parameters' SI units, so its SE is in mm (x1e3) when it holds lengths only,
 * in kg when it is the carried mass alone, and in SI units (m and kg) when it mixes both. */
static const char *weakest_unit(const hp_layout_fit *f, double *scale)
{
    double w = f->mass_index >= 0 ? fabs(f->weakest[f->mass_index]) : 0.0;
    *scale = 1.0;
    if (w >= 0.999) return "kg";
    if (w <= 1e-3) {
        *scale = 1e3;
        return "mm";
    }
    return "m,kg";
}

static void layout_text(const layout_args *a, const hp_layout_fit *f, const hp_calib_row *rows,
                        const double *gain, hp_level level)
{
    int held = 0;
    printf("layout fit: %s with %s, %d rows, %s %s\n", cli_name(a->scene), cli_name(a->data),
           f->n_rows,
           f->mass_index >= 0 && !isnan(f->mass) ? "forward statics (load level), geometry"
                                                 : "level",
           hp_level_name(level));
    printf("  Jacobian: %d parameters, rank %d; fitted %d; condition number of the fitted "
           "columns %.3g\n",
           f->np, f->rank, f->n_res - f->dof, f->condition);
    printf("  scatter s = %.4g (1 = as stated by --sigma-mm/--sigma-deg), %d degrees of "
           "freedom, t(0.975) = %.4f\n\n",
           f->s, f->dof, f->t);
    printf("  %-30s %12s %12s %10s %25s\n", "parameter [mm]", "scene", "fitted", "SE",
           "95% interval");
    for (int j = 0; j < f->np; ++j) {
        /* Lengths in mm; the carried mass in kg. */
        double k = j == f->mass_index ? 1.0 : 1e3;
        char nm[HP_CALIB_NAME_MAX + 8];
        snprintf(nm, sizeof nm, "%s%s", f->name[j], j == f->mass_index ? " [kg]" : "");
        if (f->determined[j] != 1) {
            printf("  %-30s %12.4f %12s %10s %25s\n", nm, f->scene_value[j] * k,
                   f->determined[j] ? "(not fitted)" : "(held)", "-", "-");
            held += f->determined[j] == 0;
            continue;
        }
        char iv[64];
        snprintf(iv, sizeof iv, "[%.4f, %.4f]", f->ci[j][0] * k, f->ci[j][1] * k);
        printf("  %-30s %12.4f %12.4f %10.4f %25s\n", nm, f->scene_value[j] * k, f->value[j] * k,
               f->se[j] * k, iv);
    }
    if (held) {
        printf("\n  not determined by these data (held at the scene's value):");
        for (int j = 0; j < f->np; ++j)
            if (f->determined[j] == 0) printf(" %s", f->name[j]);
        printf("\n  (their effect on the measured poses is a combination of the fitted ones')\n");
        if (f->mass_index >= 0 && f->determined[f->mass_index] == 0 && isnan(f->mass))
            printf("  mass: the scene has no load section, so the forward model (contact "
                   "kinematics) does not depend on it\n");
    }
    double wk;
    const char *wu = weakest_unit(f, &wk);
    printf("\n  weakest combination (SE %.4g %s along it):", f->weakest_se * wk,
           strcmp(wu, "m,kg") == 0 ? "in m and kg" : wu);
    for (int j = 0; j < f->np; ++j)
        if (fabs(f->weakest[j]) >= 0.2) printf(" %+.2f %s", f->weakest[j], f->name[j]);
    printf("\n");
    printf("\n  singular values (unit-norm columns):");
    for (int j = 0; j < f->np; ++j) printf(" %.3g", f->sv[j]);
    printf("\n\n  residual RMS per axis   %12s %12s\n", "before", "after");
    for (int j = 0; j < 6; ++j) {
        double k = j < 3 ? 1e3 : DEG;
        if (isfinite(f->rms_before[j]))
            printf("  %-22s %12.5f %12.5f\n", hp_pose_key(j), f->rms_before[j] * k,
                   f->rms_after[j] * k);
    }
    /* The rows whose repetition would help most. */
    int order[5] = {-1, -1, -1, -1, -1};
    for (int q = 0; q < 5; ++q)
        for (int i = 0; i < f->n_rows; ++i) {
            int used = 0;
            for (int r = 0; r < q; ++r) used |= order[r] == i;
            if (!used && isfinite(gain[i]) && (order[q] < 0 || gain[i] < gain[order[q]]))
                order[q] = i;
        }
    printf("\n  next measurement: repeating the pose of row (line) ... would shrink the "
           "fitted parameters' SE to (mean)\n");
    for (int q = 0; q < 5 && order[q] >= 0; ++q)
        printf("    line %ld: x %.4f\n", rows[order[q]].line, gain[order[q]]);
}

static json_t *layout_json(const layout_args *a, const hp_layout_fit *f, const hp_calib_row *rows,
                           const double *gain, hp_level level)
{
    json_t *o = json_object();
    json_object_set_new(o, "scene", json_string(cli_name(a->scene)));
    json_object_set_new(o, "data", json_string(cli_name(a->data)));
    json_object_set_new(o, "rows", json_integer(f->n_rows));
    json_object_set_new(o, "level", json_string(hp_level_name(level)));
    json_object_set_new(o, "model",
                        json_string(f->mass_index >= 0 && !isnan(f->mass) ? "forward statics"
                                                                          : "contact kinematics"));
    json_object_set_new(o, "rank", json_integer(f->rank));
    json_object_set_new(o, "parameters_considered", json_integer(f->np));
    json_object_set_new(o, "condition", real_or_null(f->condition));
    json_object_set_new(o, "dof", json_integer(f->dof));
    json_object_set_new(o, "t975", json_real(f->t));
    json_object_set_new(o, "s_unit_weight", json_real(f->s));
    json_t *ps = json_array(), *un = json_array(), *sv = json_array();
    for (int j = 0; j < f->np; ++j) {
        if (j == f->mass_index) {
            /* The carried mass has its own object (kg, not mm). */
            json_t *m = json_object();
            json_object_set_new(m, "status",
                                json_string(f->determined[j] == 1   ? "fitted"
                                            : f->determined[j] == 0 ? "undetermined"
                                                                    : "not_fitted"));
            json_object_set_new(m, "scene_kg", real_or_null(f->scene_value[j]));
            json_object_set_new(m, "fitted_kg", real_or_null(f->mass));
            json_object_set_new(m, "se_kg", real_or_null(f->se[j]));
            json_object_set_new(m, "ci95_kg",
                                f->determined[j] == 1 ? json_pack("[f,f]", f->ci[j][0], f->ci[j][1])
                                                      : json_null());
            json_object_set_new(o, "carried_mass", m);
            if (f->determined[j] == 0) json_array_append_new(un, json_string(f->name[j]));
            json_array_append_new(sv, json_real(f->sv[j]));
            continue;
        }
        json_t *p = json_object();
        json_object_set_new(p, "name", json_string(f->name[j]));
        json_object_set_new(p, "status",
                            json_string(f->determined[j] == 1   ? "fitted"
                                        : f->determined[j] == 0 ? "undetermined"
                                                                : "not_fitted"));
        json_object_set_new(p, "scene_mm", json_real(f->scene_value[j] * 1e3));
        json_object_set_new(p, "fitted_mm", json_real(f->value[j] * 1e3));
        json_object_set_new(p, "se_mm", real_or_null(f->se[j] * 1e3));
        json_object_set_new(p, "ci95_mm",
                            f->determined[j] == 1
                                ? json_pack("[f,f]", f->ci[j][0] * 1e3, f->ci[j][1] * 1e3)
                                : json_null());
        json_array_append_new(ps, p);
        if (f->determined[j] == 0) json_array_append_new(un, json_string(f->name[j]));
        json_array_append_new(sv, json_real(f->sv[j]));
    }
    json_object_set_new(o, "parameters", ps);
    json_object_set_new(o, "undetermined", un);
    json_object_set_new(o, "singular_values", sv);
    json_t *wk = json_array();
    for (int j = 0; j < f->np; ++j) json_array_append_new(wk, json_real(f->weakest[j]));
    json_object_set_new(o, "weakest_direction", wk);
    double wscale;
    const char *wu = weakest_unit(f, &wscale);
    json_object_set_new(o, "weakest_se", real_or_null(f->weakest_se * wscale));
    json_object_set_new(o, "weakest_se_unit", json_string(wu));
    json_t *rb = json_object(), *ra = json_object();
    for (int j = 0; j < 6; ++j) {
        double k = j < 3 ? 1e3 : DEG;
        json_object_set_new(rb, hp_pose_key(j), real_or_null(f->rms_before[j] * k));
        json_object_set_new(ra, hp_pose_key(j), real_or_null(f->rms_after[j] * k));
    }
    json_object_set_new(o, "rms_before", rb);
    json_object_set_new(o, "rms_after", ra);
    json_t *g = json_array();
    for (int i = 0; i < f->n_rows; ++i)
        json_array_append_new(g, json_pack("{s:I,s:o}", "line", (json_int_t)rows[i].line,
                                           "se_ratio", real_or_null(gain[i])));
    json_object_set_new(o, "repeat_row_gain", g);
    json_object_set_new(o, "output", a->out ? json_string(a->out) : json_null());
    return o;
}

static int run_layout(int argc, char **argv)
{
    layout_args a;
    int rc = parse_layout(argc, argv, &a);
    if (rc >= 0) return rc;
    hp_scene *sc = NULL;
    rc = cli_load_scene(CMD, a.scene, NULL, &sc);
    if (rc) return rc;
    hp_layout_fit_options o;
    rc = layout_options(&a, sc, &o);
    hp_calib_row *rows = malloc(sizeof *rows * HP_CALIB_MAX_ROWS);
    hp_layout_fit *f = malloc(sizeof *f);
    double *gain = malloc(sizeof *gain * HP_CALIB_MAX_ROWS);
    if (!rc && (!rows || !f || !gain)) rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
    int n = 0;
    hp_diag d = {{0}};
    hp_error e = HP_OK;
    /* The scene's trace is the user's data too, though the fit does not read it. */
    const char *inputs[3] = {a.scene, a.data, sc && sc->has_trace ? sc->trace_path : NULL};
    const int n_inputs = inputs[2] ? 3 : 2;
    if (!rc && a.out && !*a.out)
        rc = cli_fail(CLI_EXIT_CANTCREAT, CMD, "-o '': an empty file name");
    /* As every file output (cli_out_allowed): not a file named '-' in the current folder. */
    if (!rc && a.out && strcmp(a.out, "-") == 0) rc = cli_out_allowed(CMD, "-o", a.out, NULL, 0);
    if (!rc && a.out && (e = hp_calib_check_output(a.out, inputs, n_inputs, &d)) != HP_OK)
        rc = cli_fail(CLI_EXIT_CANTCREAT, CMD, "%s", d.text);
    const int scene_std = strcmp(a.scene, "-") == 0;
    if (!rc && a.out && (scene_std || strcmp(a.data, "-") == 0)) {
        cli_input std; /* the file on standard input, by identity */
        cli_input_of(&std, scene_std ? "scene" : "data", "-");
        rc = cli_out_allowed(CMD, "-o", a.out, &std, 1);
    }
    if (!rc) rc = read_data(a.data, &sc->layout, NULL, rows, &n, NULL);
    double *before = NULL, *after = NULL;
    if (!rc && a.plot) {
        before = malloc(sizeof *before * (size_t)n * 6);
        after = malloc(sizeof *after * (size_t)n * 6);
        if (!before || !after) rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
    }
    if (!rc) {
        e = hp_fit_layout(&sc->layout, rows, n, &o, f, after, &d);
        if (e) rc = cli_fail(status_of(e), CMD, "%s: %s", cli_name(a.data), d.text);
    }
    if (!rc && a.plot) {
        e = hp_fit_layout_residuals(&sc->layout, rows, n, &o, before, &d);
        if (e) rc = cli_fail(status_of(e), CMD, "%s: %s", cli_name(a.data), d.text);
        long *lines = rc ? NULL : malloc(sizeof *lines * (size_t)n);
        if (!rc && !lines) rc = cli_fail(CLI_EXIT_SOFTWARE, CMD, "out of memory");
        for (int i = 0; !rc && i < n; ++i) lines[i] = rows[i].line;
        cli_input in[3];
        cli_input_of(&in[0], "scene", a.scene);
        cli_input_of(&in[1], "data", a.data);
        if (n_inputs == 3) cli_input_of(&in[2], "scene's trace", inputs[2]);
        if (!rc)
            rc = fit_layout_plot(CMD, a.plot, a.plot_script, in, n_inputs,
                                 "headplan fit layout: residuals (measured - model) per axis", n,
                                 sc->layout.head.shape == HP_HEAD_SPHERE ? 3 : 6, lines, before,
                                 after);
        free(lines);
    }
    if (!rc && hp_fit_layout_gain(&sc->layout, rows, n, &o, f, gain, &d))
        for (int i = 0; i < n; ++i) gain[i] = NAN;
    if (!rc && a.out) {
        char name[HP_SCENE_TEXT_MAX];
        snprintf(name, sizeof name, "%.200s (calibrated)", sc->name);
        /* The calibrated load carries the fitted mass; a mass above the head's own is the
         * head's (carried_fraction cannot exceed 1). */
        if (sc->has_load && f->mass_index >= 0 && f->determined[f->mass_index] == 1) {
            sc->load.mass = f->mass;
            if (f->mass > f->fitted.head.mass) f->fitted.head.mass = f->mass;
        }
        e = hp_calib_write_scene(a.out, &f->fitted, sc->level, sc, name, inputs, n_inputs, &d);
        /* A refusal is about the output's name (an input, a link, a FIFO or device, a
         * folder that cannot be written): the "cannot create" status; a write that failed
         * once the file was made (full disk, file-size limit; the library says "cannot
         * write" and leaves nothing) is 74, as for every other output. */
        if (e)
            rc = cli_fail(e == HP_ERR_NOMEM                                    ? CLI_EXIT_SOFTWARE
                          : e == HP_ERR_IO && strstr(d.text, ": cannot write") ? CLI_EXIT_IOERR
                                                                               : CLI_EXIT_CANTCREAT,
                          CMD, "%s", d.text);
    }
    if (!rc) {
        if (a.json) rc = print_json(layout_json(&a, f, rows, gain, o.level));
        else {
            layout_text(&a, f, rows, gain, o.level);
            if (a.out) printf("\nwrote %s\n", a.out);
        }
    }
    free(rows);
    free(f);
    free(gain);
    free(before);
    free(after);
    free(sc);
    return rc;
}

int cmd_fit(int argc, char **argv)
{
    if (cli_wants_help(argc, argv, 1)) {
        help();
        return CLI_EXIT_OK;
    }
    if (argc < 2) {
        fprintf(stderr, "headplan fit: missing what to fit (material or layout; see headplan "
                        "fit --help)\n");
        return CLI_EXIT_USAGE;
    }
    if (strcmp(argv[1], "material") == 0) return run_material(argc - 2, argv + 2);
    if (strcmp(argv[1], "layout") == 0) return run_layout(argc - 2, argv + 2);
    return cli_fail(CLI_EXIT_USAGE, CMD, "unknown fit '%s' (material or layout)", argv[1]);
}
