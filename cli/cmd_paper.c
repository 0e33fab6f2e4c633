/* headplan paper: the paper's two simulation tables (expansion, compression), computed by
 * the volume law, the closed-form pressure and quadrature of both of the paper's integrals,
 * side by side with the values the paper printed, each marked "agrees" or "DIFFERS: why".
 * See docs/paper.md. */
#include "cli/cli_output.h"
#include "cli/cli_args.h"
#include "cli/cli_paths.h"
#include "common/units.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "headplan/hp_iab.h"
#include "headplan/hp_scene.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Built-in copies of scenarios/paper_expansion.yaml and scenarios/paper_compression.yaml,
 * so the default run needs no file; tests/cli/paper.sh checks that they give the same
 * tables as the files. */
static const char EXPANSION[] =
    "headplan_scene: 1\n"
    "name: paper table (expansion)\n"
    "bladder:\n"
    "  Ri_mm: 27\n"
    "  Ro_mm: 30\n"
    "  material: {convention: paper, C1_pa: 1.1e4, C2_pa: 2.2e4}\n"
    "  ri_mm: 30\n"
    "paper_printed:\n"
    "  title: Volumetric Deformation (Expansion)\n"
    "  C1_pa: 1.1e4\n"
    "  C2_pa: 2.2e4\n"
    "  Ri_m: .027\n"
    "  ri_m: .03\n"
    "  Ro_m: .03\n"
    "  ro_m: .033\n"
    "  pressure_pa: .76\n"
    "  dV_m3: 0\n"
    "  note: \"the printed ro and P do not follow from the volume law and the closed form "
    "(docs/model.md 3, errata)\"\n";
static const char COMPRESSION[] =
    "headplan_scene: 1\n"
    "name: paper table (compression)\n"
    "bladder:\n"
    "  Ri_mm: 25\n"
    "  Ro_mm: 30\n"
    "  material: {convention: paper, C1_pa: 1.1e4, C2_pa: 2.2e4}\n"
    "  ri_mm: 23\n"
    "paper_printed:\n"
    "  title: Volumetric Deformation (Compression)\n"
    "  C1_pa: 1.1e4\n"
    "  C2_pa: 2.2e4\n"
    "  Ri_m: .025\n"
    "  ri_m: .03\n"
    "  Ro_m: .03\n"
    "  ro_m: .028\n"
    "  pressure_pa: -.34\n"
    "  dV_m3: 0\n"
    "  note: \"the printed ri = .03 contradicts the text (displacement 0.002 m, ro .028): "
    "ri = 23 mm intended\"\n";

/* Gauss-Legendre points per integral: both integrands are smooth on short intervals, so 20
 * points reach full double precision (the table shows the difference). */
#define PAPER_GAUSS_N 20
#define PAPER_ADAPT_TOL 1e-13
/* |dV| below this fraction of the shell volume is "approx. 0" (rounding of r³ terms). */
#define PAPER_DV_REL 1e-12

/* Pressure units a printed pressure might have been written in [Pa per unit]. */
static const struct {
    const char *name;
    double pa;
} UNITS[] = {{"Pa", 1.0},
             {"kPa", 1e3},
             {"MPa", 1e6},
             {"bar", 1e5},
             {"atm", 101325.0},
             {"psi", 6894.757293168},
             {"mmHg", 133.322387415},
             {"cmH2O", 98.0665},
             {"inH2O", 249.08891}};
#define N_UNITS (sizeof UNITS / sizeof UNITS[0])

typedef struct result {
    const hp_bladder_study *s;
    double ri, ro, P, dV, shell;
    double gauss[2], adapt[2], adapt_err[2];
    int adapt_evals[2];
    hp_error gauss_e[2], adapt_e[2];
} result;

/* Half a unit in the last digit of a printed literal (".033" -> 5e-4, "1.1e4" -> 500). */
static double half_unit(const char *text)
{
    const char *dot = strchr(text, '.');
    const char *e = strpbrk(text, "eE");
    int decimals = 0;
    if (dot) {
        const char *end = e ? e : text + strlen(text);
        decimals = (int)(end - dot - 1);
    }
    int exponent = e ? atoi(e + 1) : 0;
    return 0.5 * pow(10.0, exponent - decimals);
}

static int agrees(const hp_scene_printed *p, double computed)
{
    return fabs(computed - p->value) <= half_unit(p->text) * (1 + 1e-12);
}

static int compute(const hp_bladder_study *s, result *r)
{
    memset(r, 0, sizeof *r);
    r->s = s;
    const hp_iab *b = &s->iab;
    hp_error e;
    if (s->study == HP_STUDY_IK) {
        r->ri = s->study_ri;
        e = hp_iab_ik(b, r->ri, &r->P);
    } else {
        r->P = s->study_pressure;
        e = hp_iab_fk(b, r->P, &r->ri);
    }
    if (e == HP_OK) e = hp_iab_ro(b, r->ri, &r->ro);
    if (e != HP_OK)
        return cli_fail(CLI_EXIT_DATAERR, "paper", "%s: %s", s->file, hp_error_message(e));
    /* volume of the wall now minus at rest: zero for an incompressible shell */
    const double k = 4.0 / 3.0 * HP_PI;
    double now = r->ro * r->ro * r->ro - r->ri * r->ri * r->ri;
    double rest = b->Ro * b->Ro * b->Ro - b->Ri * b->Ri * b->Ri;
    r->dV = k * (now - rest);
    r->shell = k * rest;
    for (int f = 0; f < 2; ++f) {
        r->gauss_e[f] = hp_iab_ik_gauss(b, r->ri, (hp_quad_form)f, PAPER_GAUSS_N, &r->gauss[f]);
        r->adapt_e[f] = hp_iab_ik_adaptive(b, r->ri, (hp_quad_form)f, PAPER_ADAPT_TOL, &r->adapt[f],
                                           &r->adapt_err[f], &r->adapt_evals[f]);
    }
    return 0;
}

/* The check column for each printed value: "agrees" or "DIFFERS: why". */
static void mark_radius(const result *r, const hp_scene_printed *p, double computed, int is_ri,
                        char *out, size_t size)
{
    if (!p->given) {
        snprintf(out, size, "(not printed)");
        return;
    }
    if (agrees(p, computed)) {
        snprintf(out, size, "agrees");
        return;
    }
    if (is_ri) {
        double ro_p = NAN;
        hp_iab_ro(&r->s->iab, p->value, &ro_p);
        snprintf(out, size,
                 "DIFFERS: this study uses ri = %.5f mm; the printed ri gives ro = %.5f mm by "
                 "the volume law%s",
                 r->ri * 1e3, ro_p * 1e3,
                 r->s->printed_ro.given && !agrees(&r->s->printed_ro, ro_p)
                     ? ", not the printed ro (so the printed ri is not the table's input)"
                     : "");
        return;
    }
    snprintf(out, size,
             "DIFFERS: the volume law gives %.5f mm; the printed %s m is %.5f mm away "
             "(printed precision +-%.5g mm)",
             computed * 1e3, p->text, fabs(computed - p->value) * 1e3, half_unit(p->text) * 1e3);
}

static void mark_pressure(const result *r, char *out, size_t size)
{
    const hp_scene_printed *p = &r->s->printed_pressure;
    if (!p->given) {
        snprintf(out, size, "(not printed)");
        return;
    }
    double h = half_unit(p->text);
    for (size_t u = 0; u < N_UNITS; ++u)
        if (fabs(r->P / UNITS[u].pa - p->value) <= h) {
            snprintf(out, size, u == 0 ? "agrees" : "agrees if read in %s", UNITS[u].name);
            return;
        }
    snprintf(out, size,
             "DIFFERS: the closed form gives %.4f Pa; %s matches it in no unit (Pa, kPa, MPa, "
             "bar, atm, psi, mmHg, cmH2O, inH2O)",
             r->P, p->text);
}

static void mark_plain(const hp_scene_printed *p, double computed, char *out, size_t size)
{
    if (!p->given) snprintf(out, size, "(not printed)");
    else if (agrees(p, computed)) snprintf(out, size, "agrees");
    else snprintf(out, size, "DIFFERS: computed %.10g, printed %s", computed, p->text);
}

static void mark_dv(const result *r, char *out, size_t size)
{
    const hp_scene_printed *p = &r->s->printed_dV;
    int zero = fabs(r->dV) <= PAPER_DV_REL * r->shell;
    if (!p->given) snprintf(out, size, "(not printed)");
    else if (p->value == 0.0)
        snprintf(out, size,
                 zero ? "agrees (printed as approx. 0; |dV| <= 1e-12 of the shell "
                        "volume)"
                      : "DIFFERS: the volume is not preserved");
    else mark_plain(p, r->dV, out, size);
}

static double rel_diff(double a, double b) { return b == 0 ? fabs(a) : fabs(a - b) / fabs(b); }

/* One row of the comparison: quantity, computed value (fixed format), printed literal with
 * its unit, check. */
static void row(const char *what, const char *fmt, double v, const hp_scene_printed *p,
                const char *unit, const char *mark)
{
    char num[32], printed[48];
    snprintf(num, sizeof num, fmt, v);
    if (p->given) snprintf(printed, sizeof printed, "%s%s", p->text, unit);
    else snprintf(printed, sizeof printed, "-");
    printf("%-22s %-14s %-10s %s\n", what, num, printed, mark);
}

static void print_text(const result *r, const char *label)
{
    const hp_bladder_study *s = r->s;
    char m[512];
    printf("== %s\n", s->printed_title[0] ? s->printed_title : s->name);
    printf("scene: %s\nname: %s\n", label, s->name);
    printf("model: thick Mooney-Rivlin shell, C1 = %.1f Pa, C2 = %.1f Pa (paper convention), "
           "%s\n",
           s->iab.C1, s->iab.C2,
           s->study == HP_STUDY_IK ? "inverse kinematics: ri given" : "forward: P given");
    printf("\n%-22s %-14s %-10s %s\n", "quantity", "computed", "printed", "check");
    mark_plain(&s->printed_C1, s->iab.C1, m, sizeof m);
    row("C1 [Pa]", "%.1f", s->iab.C1, &s->printed_C1, " Pa", m);
    mark_plain(&s->printed_C2, s->iab.C2, m, sizeof m);
    row("C2 [Pa]", "%.1f", s->iab.C2, &s->printed_C2, " Pa", m);
    mark_plain(&s->printed_Ri, s->iab.Ri, m, sizeof m);
    row("Ri [mm]", "%.5f", s->iab.Ri * 1e3, &s->printed_Ri, " m", m);
    mark_radius(r, &s->printed_ri, r->ri, 1, m, sizeof m);
    row(s->study == HP_STUDY_IK ? "ri [mm] (input)" : "ri [mm] (FK)", "%.5f", r->ri * 1e3,
        &s->printed_ri, " m", m);
    mark_plain(&s->printed_Ro, s->iab.Ro, m, sizeof m);
    row("Ro [mm]", "%.5f", s->iab.Ro * 1e3, &s->printed_Ro, " m", m);
    mark_radius(r, &s->printed_ro, r->ro, 0, m, sizeof m);
    row("ro [mm] (volume law)", "%.5f", r->ro * 1e3, &s->printed_ro, " m", m);
    mark_pressure(r, m, sizeof m);
    row(s->study == HP_STUDY_IK ? "P [Pa] (closed form)" : "P [Pa] (input)", "%.4f", r->P,
        &s->printed_pressure, "", m);
    mark_dv(r, m, sizeof m);
    row("dV [m^3]", "%.3e", r->dV, &s->printed_dV, "", m);

    printf("\n%-36s %-14s %s\n", "pressure by method", "P [Pa]", "rel. diff from closed form");
    printf("%-36s %-14.4f %s\n", "closed form", r->P, "-");
    static const char *const form[2] = {"P(r) form", "P(R) form"};
    for (int f = 0; f < 2; ++f) {
        char name[64];
        snprintf(name, sizeof name, "Gauss-Legendre %d pts, %s", PAPER_GAUSS_N, form[f]);
        if (r->gauss_e[f] == HP_OK)
            printf("%-36s %-14.4f %.1e\n", name, r->gauss[f], rel_diff(r->gauss[f], r->P));
        else printf("%-36s %-14s %s\n", name, "failed", hp_error_message(r->gauss_e[f]));
    }
    for (int f = 0; f < 2; ++f) {
        char name[64];
        snprintf(name, sizeof name, "adaptive Gauss-Kronrod, %s", form[f]);
        if (r->adapt_e[f] == HP_OK)
            printf("%-36s %-14.4f %.1e (%d evaluations)\n", name, r->adapt[f],
                   rel_diff(r->adapt[f], r->P), r->adapt_evals[f]);
        else printf("%-36s %-14s %s\n", name, "failed", hp_error_message(r->adapt_e[f]));
    }
    if (s->printed_note[0]) printf("\nnote: %s\n", s->printed_note);
}

static json_t *printed_json(const hp_scene_printed *p, const char *mark)
{
    if (!p->given) return json_null();
    return json_pack("{s:s, s:f, s:b, s:s}", "text", p->text, "value", p->value, "agrees",
                     strncmp(mark, "agrees", 6) == 0, "check", mark);
}

static json_t *to_json(const result *r, const char *label)
{
    const hp_bladder_study *s = r->s;
    char m[8][512];
    mark_plain(&s->printed_C1, s->iab.C1, m[0], sizeof m[0]);
    mark_plain(&s->printed_C2, s->iab.C2, m[1], sizeof m[1]);
    mark_plain(&s->printed_Ri, s->iab.Ri, m[2], sizeof m[2]);
    mark_radius(r, &s->printed_ri, r->ri, 1, m[3], sizeof m[3]);
    mark_plain(&s->printed_Ro, s->iab.Ro, m[4], sizeof m[4]);
    mark_radius(r, &s->printed_ro, r->ro, 0, m[5], sizeof m[5]);
    mark_pressure(r, m[6], sizeof m[6]);
    mark_dv(r, m[7], sizeof m[7]);
    json_t *quad = json_array();
    for (int f = 0; f < 2; ++f) {
        const char *form = f == 0 ? "current" : "reference";
        json_array_append_new(
            quad,
            json_pack("{s:s, s:s, s:i, s:o, s:o}", "method", "gauss-legendre", "form", form,
                      "points", PAPER_GAUSS_N, "pressure_pa",
                      r->gauss_e[f] == HP_OK ? json_real(r->gauss[f]) : json_null(), "rel_diff",
                      r->gauss_e[f] == HP_OK ? json_real(rel_diff(r->gauss[f], r->P))
                                             : json_null()));
    }
    for (int f = 0; f < 2; ++f) {
        const char *form = f == 0 ? "current" : "reference";
        json_array_append_new(
            quad,
            json_pack("{s:s, s:s, s:i, s:o, s:o}", "method", "adaptive-gauss-kronrod", "form", form,
                      "evaluations", r->adapt_evals[f], "pressure_pa",
                      r->adapt_e[f] == HP_OK ? json_real(r->adapt[f]) : json_null(), "rel_diff",
                      r->adapt_e[f] == HP_OK ? json_real(rel_diff(r->adapt[f], r->P))
                                             : json_null()));
    }
    return json_pack(
        "{s:s, s:s, s:s, s:{s:f, s:f, s:f, s:f, s:f}, s:{s:f, s:f, s:f, s:f}, s:o, "
        "s:{s:o, s:o, s:o, s:o, s:o, s:o, s:o, s:o}, s:s}",
        "scene", label, "name", s->name, "title", s->printed_title, "inputs", "C1_pa", s->iab.C1,
        "C2_pa", s->iab.C2, "Ri_m", s->iab.Ri, "Ro_m", s->iab.Ro, "ri_m", r->ri, "computed", "ro_m",
        r->ro, "pressure_pa", r->P, "dV_m3", r->dV, "shell_volume_m3", r->shell, "quadrature", quad,
        "printed", "C1_pa", printed_json(&s->printed_C1, m[0]), "C2_pa",
        printed_json(&s->printed_C2, m[1]), "Ri_m", printed_json(&s->printed_Ri, m[2]), "ri_m",
        printed_json(&s->printed_ri, m[3]), "Ro_m", printed_json(&s->printed_Ro, m[4]), "ro_m",
        printed_json(&s->printed_ro, m[5]), "pressure_pa", printed_json(&s->printed_pressure, m[6]),
        "dV_m3", printed_json(&s->printed_dV, m[7]), "note", s->printed_note);
}

static void help(void)
{
    printf("usage: headplan paper [SCENE...] [--json]\n\n"
           "Reproduces the paper's simulation tables (Ogunmolu et al., ICRA 2020): for each\n"
           "single-bladder scene, ro by the volume law, P by the closed form and by quadrature\n"
           "of both of the paper's integrals (Gauss-Legendre and adaptive Gauss-Kronrod, over\n"
           "the current and the reference radius), the volume change, and the values the\n"
           "paper printed, each marked 'agrees' or 'DIFFERS: why' (a printed value agrees when\n"
           "it is within half a unit of its last printed digit). Without SCENE: the built-in\n"
           "copies of paper_expansion.yaml and paper_compression.yaml, in the example scenes\n"
           "(%s).\n\n"
           "  --json   one JSON object {\"tables\": [...]} on stdout instead of the text\n"
           "  --help   this text\n\n"
           "exit status: 0 ok, 64 bad command line, 65 malformed or unsuitable scene,\n"
           "66 scene file cannot be opened\n\n"
           "documentation: %s/paper.md\n",
           cli_scene_dir(), cli_doc_dir());
}

/* A file that is a layout scene: the layout reader's message when it is malformed, else
 * that it is not a study. */
static int not_a_study(const char *path)
{
    hp_scene *sc = calloc(1, sizeof *sc);
    if (!sc) return cli_fail(CLI_EXIT_SOFTWARE, "paper", "out of memory");
    hp_diag d = {{0}};
    hp_error e = hp_scene_load(path, sc, &d);
    free(sc);
    if (e != HP_OK)
        return cli_fail(e == HP_ERR_IO ? CLI_EXIT_NOINPUT : CLI_EXIT_DATAERR, "paper", "%s",
                        d.text);
    return cli_fail(CLI_EXIT_DATAERR, "paper",
                    "%s: not a single-bladder scene (needs a 'bladder' section)", path);
}

int cmd_paper(int argc, char **argv)
{
    int json = 0, n_files = 0;
    if (cli_wants_help(argc, argv, 1)) {
        help();
        return CLI_EXIT_OK;
    }
    /* The files in order, at most argc - 1 of them (after "--" every argument is one). */
    const char **files = calloc((size_t)argc, sizeof *files);
    if (!files) return cli_fail(CLI_EXIT_SOFTWARE, "paper", "out of memory");
    for (int i = 1, operands = 0; i < argc; ++i) {
        if (!operands && strcmp(argv[i], "--") == 0) operands = 1;
        else if (!operands && strcmp(argv[i], "--json") == 0) json = 1;
        else if (!operands && argv[i][0] == '-' && argv[i][1] != '\0') {
            free(files);
            return cli_fail(CLI_EXIT_USAGE, "paper", "%s: unknown option (see --help)", argv[i]);
        } else files[n_files++] = argv[i];
    }
    int n = n_files ? n_files : 2;
    hp_bladder_study *scenes = calloc((size_t)n, sizeof *scenes);
    result *res = calloc((size_t)n, sizeof *res);
    const char **labels = calloc((size_t)n, sizeof *labels);
    int status = 0;
    if (!scenes || !res || !labels) status = cli_fail(CLI_EXIT_SOFTWARE, "paper", "out of memory");
    for (int k = 0; status == 0 && k < n; ++k) {
        hp_diag d = {{0}};
        hp_error e;
        if (n_files) {
            labels[k] = files[k];
            if (hp_scene_file_kind(labels[k]) == HP_SCENE_LAYOUT) {
                /* A layout scene: its own errors first, else the wrong kind. */
                status = not_a_study(labels[k]);
                continue;
            }
            e = hp_study_load(labels[k], &scenes[k], &d);
        } else {
            labels[k] = k == 0 ? "scenarios/paper_expansion.yaml (built in)"
                               : "scenarios/paper_compression.yaml (built in)";
            const char *text = k == 0 ? EXPANSION : COMPRESSION;
            e = hp_study_parse(text, strlen(text),
                               k == 0 ? "paper_expansion.yaml" : "paper_compression.yaml",
                               &scenes[k], &d);
        }
        if (e != HP_OK)
            status = cli_fail(e == HP_ERR_IO ? CLI_EXIT_NOINPUT : CLI_EXIT_DATAERR, "paper", "%s",
                              d.text);
        else status = compute(&scenes[k], &res[k]);
    }
    if (status == 0 && json) {
        json_t *tables = json_array();
        for (int k = 0; k < n; ++k) json_array_append_new(tables, to_json(&res[k], labels[k]));
        json_t *root = json_pack("{s:o}", "tables", tables);
        char *text = root ? json_dumps(root, JSON_PRESERVE_ORDER | JSON_INDENT(2) |
                                                 JSON_REAL_PRECISION(CLI_JSON_REAL_PRECISION))
                          : NULL;
        if (!text) status = cli_fail(CLI_EXIT_SOFTWARE, "paper", "JSON output failed");
        else cli_put_line(text);
        free(text);
        json_decref(root);
    } else if (status == 0) {
        for (int k = 0; k < n; ++k) {
            if (k) printf("\n");
            print_text(&res[k], labels[k]);
        }
    }
    free(scenes);
    free(res);
    free(labels);
    free(files);
    return status;
}
