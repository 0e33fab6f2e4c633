/* headplan ik / headplan fk: one bladder, inner radius <-> pressure (closed form, stable
 * branch). Command-line units: mm and Pa; the library works in m and Pa. */
#include "cli/cli_output.h"
#include "cli/cli_args.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "headplan/hp_iab.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The options both subcommands take; "--ri" for ik, "--pressure" for fk. */
enum { O_RI_BIG, O_RO_BIG, O_TARGET, O_C1, O_C2, O_C10, O_C01, O_COUNT };

typedef struct {
    const char *cmd;    /* "ik" or "fk" */
    const char *target; /* "--ri" or "--pressure" */
    const char *text[O_COUNT];
    int json;
} ik_args;

static const char *option_name(const ik_args *a, int o)
{
    static const char *const names[O_COUNT] = {"--Ri", "--Ro",  NULL,   "--c1",
                                               "--c2", "--c10", "--c01"};
    return o == O_TARGET ? a->target : names[o];
}

static void help(const char *cmd)
{
    int ik = strcmp(cmd, "ik") == 0;
    printf("usage: headplan %s --Ri MM --Ro MM %s --c1 PA --c2 PA [--json]\n"
           "       headplan %s --Ri MM --Ro MM %s --c10 PA --c01 PA [--json]\n\n",
           cmd, ik ? "--ri MM" : "--pressure PA", cmd, ik ? "--ri MM" : "--pressure PA");
    if (ik)
        printf("One bladder (thick Mooney-Rivlin sphere): the internal pressure that holds the\n"
               "inner radius --ri, by the closed form of the paper's integrals.\n\n");
    else
        printf("One bladder (thick Mooney-Rivlin sphere): the inner radius that holds the\n"
               "internal pressure --pressure, on the stable branch (below any inflation limit\n"
               "point; at or above it there is no stable radius and the command fails).\n\n");
    printf("  --Ri MM        reference (unpressurised) inner radius, mm\n"
           "  --Ro MM        reference outer radius, mm (> --Ri)\n");
    if (ik) printf("  --ri MM        current inner radius, mm (> 0)\n");
    else printf("  --pressure PA  internal pressure above ambient, Pa (negative: suction)\n");
    printf("  --c1, --c2 PA  moduli in the paper's convention W = C1(I1-3)/2 + C2(I2-3)/2\n"
           "  --c10, --c01   moduli in the finite-element convention W = C10(I1-3) + C01(I2-3)\n"
           "                 (C1 = 2 C10, C2 = 2 C01); give one pair, not both\n"
           "  --json         one JSON object on stdout instead of the table\n"
           "  --help         this text\n\n"
           "exit status: 0 ok, 64 bad command line, 65 bad value%s\n",
           ik ? "" : " or no stable radius");
}

/* Parses argv into a. Returns -1 to continue, or the exit status (0 after --help). */
static int parse(int argc, char **argv, ik_args *a)
{
    if (cli_wants_help(argc, argv, 1)) {
        help(a->cmd);
        return CLI_EXIT_OK;
    }
    for (int i = 1, operands = 0; i < argc; ++i) {
        if (!operands && strcmp(argv[i], "--") == 0) {
            operands = 1;
            continue;
        }
        if (operands)
            return cli_fail(CLI_EXIT_USAGE, a->cmd,
                            "unexpected argument '%s' (%s takes options only; see headplan "
                            "%s --help)",
                            argv[i], a->cmd, a->cmd);
        if (strcmp(argv[i], "--json") == 0) {
            a->json = 1;
            continue;
        }
        int matched = 0;
        for (int o = 0; o < O_COUNT && !matched; ++o) {
            const char *v = NULL;
            int m = cli_opt(a->cmd, argc, argv, &i, option_name(a, o), &v);
            if (m < 0) return CLI_EXIT_USAGE;
            if (m == 0) continue;
            if (a->text[o])
                return cli_fail(CLI_EXIT_USAGE, a->cmd, "%s: given more than once",
                                option_name(a, o));
            a->text[o] = v;
            matched = 1;
        }
        if (!matched && argv[i][0] != '-')
            return cli_fail(CLI_EXIT_USAGE, a->cmd,
                            "unexpected argument '%s' (%s takes options only; see headplan "
                            "%s --help)",
                            argv[i], a->cmd, a->cmd);
        if (!matched)
            return cli_fail(CLI_EXIT_USAGE, a->cmd, "unknown option '%s' (see headplan %s --help)",
                            argv[i], a->cmd);
    }
    int paper = a->text[O_C1] || a->text[O_C2], fe = a->text[O_C10] || a->text[O_C01];
    if (paper && fe)
        return cli_fail(CLI_EXIT_USAGE, a->cmd,
                        "%s: cannot mix the paper's --c1/--c2 with the finite-element --c10/--c01",
                        a->text[O_C10] ? "--c10" : "--c01");
    const int need[] = {O_RI_BIG, O_RO_BIG, O_TARGET, fe ? O_C10 : O_C1, fe ? O_C01 : O_C2};
    for (size_t k = 0; k < sizeof need / sizeof need[0]; ++k)
        if (!a->text[need[k]])
            return cli_fail(CLI_EXIT_USAGE, a->cmd,
                            "%s: missing (required; see headplan %s --help)",
                            option_name(a, need[k]), a->cmd);
    return -1;
}

typedef struct {
    double Ri_mm, Ro_mm, target, C1, C2;
    hp_iab b;
} ik_values;

/* Converts and checks the values. Returns -1 to continue, or the exit status. */
static int values(const ik_args *a, ik_values *v)
{
    int fe = a->text[O_C10] != NULL;
    int oc1 = fe ? O_C10 : O_C1, oc2 = fe ? O_C01 : O_C2;
    double m1, m2;
    int rc;
    if ((rc = cli_double(a->cmd, "--Ri", a->text[O_RI_BIG], &v->Ri_mm)) ||
        (rc = cli_double(a->cmd, "--Ro", a->text[O_RO_BIG], &v->Ro_mm)) ||
        (rc = cli_double(a->cmd, a->target, a->text[O_TARGET], &v->target)) ||
        (rc = cli_double(a->cmd, option_name(a, oc1), a->text[oc1], &m1)) ||
        (rc = cli_double(a->cmd, option_name(a, oc2), a->text[oc2], &m2)))
        return rc;
    if (!(v->Ri_mm > 0))
        return cli_fail(CLI_EXIT_DATAERR, a->cmd, "--Ri: must be > 0 mm (got %g)", v->Ri_mm);
    if (!(v->Ro_mm > v->Ri_mm))
        return cli_fail(CLI_EXIT_DATAERR, a->cmd,
                        "--Ro: must be greater than --Ri (got --Ro %g mm, --Ri %g mm)", v->Ro_mm,
                        v->Ri_mm);
    if (a->target[2] == 'r' && !(v->target > 0))
        return cli_fail(CLI_EXIT_DATAERR, a->cmd, "--ri: must be > 0 mm (got %g)", v->target);
    if (!(m1 > 0))
        return cli_fail(CLI_EXIT_DATAERR, a->cmd, "%s: must be > 0 Pa (got %g)",
                        option_name(a, oc1), m1);
    if (!(m2 >= 0))
        return cli_fail(CLI_EXIT_DATAERR, a->cmd, "%s: must be >= 0 Pa (got %g)",
                        option_name(a, oc2), m2);
    if (hp_iab_moduli_to_paper(fe ? HP_MATERIAL_FE : HP_MATERIAL_PAPER, m1, m2, &v->C1, &v->C2) !=
        HP_OK)
        return cli_fail(CLI_EXIT_DATAERR, a->cmd, "%s/%s: moduli out of range", option_name(a, oc1),
                        option_name(a, oc2));
    v->b = (hp_iab){v->Ri_mm * 1e-3, v->Ro_mm * 1e-3, v->C1, v->C2};
    hp_diag d;
    if (hp_iab_validate(&v->b, &d) != HP_OK)
        return cli_fail(CLI_EXIT_DATAERR, a->cmd, "bladder: %s", d.text);
    return -1;
}

/* Everything one run reports. */
typedef struct {
    double ri_m, ro_m, P, dP, d2P;
    hp_iab_limit lp;
} ik_result;

static json_t *real_or_null(double x) { return isfinite(x) ? json_real(x) : json_null(); }

static int print_json(const ik_values *v, const ik_result *r, const char *cmd)
{
    json_t *o = json_object();
    json_object_set_new(o, "ri_mm", json_real(r->ri_m * 1e3));
    json_object_set_new(o, "ro_mm", json_real(r->ro_m * 1e3));
    json_object_set_new(o, "pressure_pa", json_real(r->P));
    json_object_set_new(o, "lambda_i", json_real(r->ri_m / v->b.Ri));
    json_object_set_new(o, "lambda_o", json_real(r->ro_m / v->b.Ro));
    json_object_set_new(o, "Ri_mm", json_real(v->Ri_mm));
    json_object_set_new(o, "Ro_mm", json_real(v->Ro_mm));
    json_object_set_new(o, "c1_pa", json_real(v->C1));
    json_object_set_new(o, "c2_pa", json_real(v->C2));
    json_object_set_new(o, "dP_dri_pa_per_mm", json_real(r->dP * 1e-3));
    json_object_set_new(o, "d2P_dri2_pa_per_mm2", json_real(r->d2P * 1e-6));
    json_object_set_new(o, "stable", json_boolean(r->ri_m < r->lp.ri));
    if (r->lp.exists) {
        json_t *l = json_object();
        json_object_set_new(l, "lambda_i", real_or_null(r->lp.lambda_i));
        json_object_set_new(l, "ri_mm", real_or_null(r->lp.ri * 1e3));
        json_object_set_new(l, "pressure_pa", real_or_null(r->lp.pressure));
        json_object_set_new(o, "limit_point", l);
    } else {
        json_object_set_new(o, "limit_point", json_null());
    }
    char *s = json_dumps(o, JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(CLI_JSON_REAL_PRECISION));
    json_decref(o);
    if (!s) return cli_fail(CLI_EXIT_SOFTWARE, cmd, "cannot format JSON output");
    cli_put_line(s);
    free(s);
    return CLI_EXIT_OK;
}

static void row(const char *name, double value, const char *unit)
{
    if (*unit) printf("%-16s %-20.10g %s\n", name, value, unit);
    else printf("%-16s %.10g\n", name, value);
}

static void print_table(const ik_values *v, const ik_result *r)
{
    row("Ri", v->Ri_mm, "mm");
    row("Ro", v->Ro_mm, "mm");
    row("ri", r->ri_m * 1e3, "mm");
    row("ro", r->ro_m * 1e3, "mm");
    row("pressure", r->P, "Pa");
    row("lambda_i", r->ri_m / v->b.Ri, "");
    row("lambda_o", r->ro_m / v->b.Ro, "");
    row("C1", v->C1, "Pa");
    row("C2", v->C2, "Pa");
    row("dP/dri", r->dP * 1e-3, "Pa/mm");
    if (r->lp.exists) {
        row("limit lambda_i", r->lp.lambda_i, "");
        row("limit ri", r->lp.ri * 1e3, "mm");
        row("limit pressure", r->lp.pressure, "Pa");
    } else {
        printf("%-16s none (P rises monotonically)\n", "limit point");
    }
}

/* The shared body of both subcommands. */
static int run(int argc, char **argv, const char *cmd, const char *target)
{
    ik_args a;
    memset(&a, 0, sizeof a);
    a.cmd = cmd;
    a.target = target;
    int rc = parse(argc, argv, &a);
    if (rc >= 0) return rc;
    ik_values v;
    rc = values(&a, &v);
    if (rc >= 0) return rc;
    ik_result r;
    hp_error le = hp_iab_limit_point(&v.b, &r.lp);
    /* Moduli near DBL_MAX overflow the pressure: a bad value, not an internal failure. */
    if (le == HP_ERR_DOMAIN || le == HP_ERR_INVALID)
        return cli_fail(CLI_EXIT_DATAERR, cmd,
                        "%s/%s: C1 %g Pa, C2 %g Pa: %s (the limit point cannot be located)",
                        a.text[O_C10] ? "--c10" : "--c1", a.text[O_C10] ? "--c01" : "--c2", v.C1,
                        v.C2, hp_error_message(le));
    if (le != HP_OK)
        return cli_fail(CLI_EXIT_SOFTWARE, cmd, "cannot locate the limit point: %s",
                        hp_error_message(le));
    hp_error e;
    if (strcmp(cmd, "ik") == 0) {
        r.ri_m = v.target * 1e-3;
    } else {
        r.P = v.target;
        e = hp_iab_fk(&v.b, v.target, &r.ri_m);
        if (e == HP_ERR_NO_STABLE)
            return cli_fail(CLI_EXIT_DATAERR, cmd,
                            "--pressure: %.10g Pa is at or above the limit-point pressure "
                            "%.10g Pa (lambda_i %.10g, ri %.10g mm): no stable radius",
                            v.target, r.lp.pressure, r.lp.lambda_i, r.lp.ri * 1e3);
        if (e != HP_OK)
            return cli_fail(CLI_EXIT_DATAERR, cmd, "--pressure: %.10g Pa: %s", v.target,
                            hp_error_message(e));
    }
    e = hp_iab_ik_derivs(&v.b, r.ri_m, &r.P, &r.dP, &r.d2P);
    if (e == HP_OK) e = hp_iab_ro(&v.b, r.ri_m, &r.ro_m);
    if (e != HP_OK)
        return cli_fail(CLI_EXIT_DATAERR, cmd, "%s: %.10g: %s", target, v.target,
                        hp_error_message(e));
    if (strcmp(cmd, "fk") == 0) r.P = v.target; /* report the pressure asked for */
    if (a.json) return print_json(&v, &r, cmd);
    print_table(&v, &r);
    return CLI_EXIT_OK;
}

int cmd_ik(int argc, char **argv) { return run(argc, argv, "ik", "--ri"); }

int cmd_fk(int argc, char **argv) { return run(argc, argv, "fk", "--pressure"); }
