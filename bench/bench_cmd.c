/* headplan-bench: speed versus accuracy of every method, per family, on the same inputs.
 * Writes DIR/<family>.csv and the charts DIR/<family>_pareto.{png,svg} (gnuplot), prints a
 * summary table on stdout and progress on stderr. A benchmark measures; it never fails on
 * a time. */
#include "bench/bench.h"
#include "headplan/hp_contact.h"
#include "headplan/hp_planner.h"
#include "common/unconst.h"
#include "bench/bench_report.h"
#include "bench/bench_util.h"
#include "cli/cli_args.h"
#include "cli/exit_codes.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

#define CMD "bench"
#define DEFAULT_OUT "out/bench"
/* The lab reads the project's own catalogue and peer script wherever it is run from: the
 * build puts the source tree's path in HP_SOURCE_DIR. */
#define DEFAULT_SCENE HP_SOURCE_DIR "/scenarios/default.yaml"
#define DEFAULT_SCENARIOS HP_SOURCE_DIR "/scenarios"
#define DEFAULT_PYTHON "/usr/bin/python3"
#define DEFAULT_PEER_SCRIPT HP_SOURCE_DIR "/bench/scipy_peer.py"

/* The families, in the order they run. A new family is one row here and either one
 * bench_family_fn that appends rows to the table (CSV and Pareto chart written here) or
 * one bench_files_fn that writes its own files. */
typedef struct {
    bench_chart chart;
    bench_family_fn run;
    bench_files_fn files;
    unsigned reads; /* READS_SCENE: --scene; READS_CATALOGUE: the --scenarios folder */
} family;
enum { READS_SCENE = 1u, READS_CATALOGUE = 2u };

static const family families[] = {
    {{"ik", "Bladder inverse kinematics (radius to pressure): speed versus accuracy",
      "median time per evaluation [ns]", "max relative error vs float128 reference (1000 inputs)"},
     bench_ik,
     NULL,
     0},
    {{"planner", "Planner: speed versus accuracy (default layout, targets where a limit binds)",
      "median time per plan [ns]",
      "max pose difference from the reference after the exact-model round trip [mm or deg]"},
     bench_planner,
     NULL,
     READS_SCENE},
    {{"stability", NULL, NULL, NULL}, NULL, bench_stability, READS_CATALOGUE},
    {{"peers", "Peers on the same NLP (linear contact level, default layout, binding targets)",
      "median time per plan [ns]",
      "max pose difference from Ipopt (exact Hessian, tolerance 1e-10) [mm or deg]"},
     bench_peers,
     NULL,
     READS_SCENE},
    {{"levels", NULL, NULL, NULL}, NULL, bench_levels, READS_CATALOGUE},
    {{"load", NULL, NULL, NULL}, NULL, bench_load, READS_CATALOGUE},
    {{"loop", NULL, NULL, NULL}, NULL, bench_loop, READS_SCENE},
    {{"fidelity", NULL, NULL, NULL}, NULL, bench_fidelity, READS_CATALOGUE},
};
#define N_FAMILIES (sizeof families / sizeof families[0])

static void help(void)
{
    printf("usage: headplan-bench [--out DIR] [--quick] [--only FAMILY[,FAMILY]] [--seed N]\n"
           "                      [--scene FILE] [--scenarios DIR] [--python EXE]\n"
           "                      [--peer-script FILE] [--repeat N]\n"
           "                      [--loop-level LEVEL] [--loop-backend NAME]\n"
           "                      [--loop-budget-us US]\n\n"
           "Measures every method of each family on the same inputs: median and 99th\n"
           "percentile time per evaluation (CLOCK_MONOTONIC, warm-up, batches timed together;\n"
           "the planner and peers methods take turns, 7 rounds of 9 turns, so a slow spell of\n"
           "the host hits them all) and accuracy against a high-precision reference. Writes\n"
           "DIR/FAMILY.csv and the charts DIR/FAMILY_pareto.png and .svg (time versus error,\n"
           "log scales, Pareto front) with gnuplot; prints a summary table on stdout, progress\n"
           "on stderr. The stability family writes DIR/stability.csv, stability_wrong.csv\n"
           "and the chart stability.png/.svg (success rate, iterations, violations versus\n"
           "correction size);\n"
           "the levels family writes DIR/levels.csv (what each contact level costs and errs);\n"
           "the load family writes DIR/load.csv (the load level's cost on each backend and\n"
           "the sag a kinematic plan leaves on the load scenes) and the chart load.png/.svg;\n"
           "the loop family writes DIR/loop.csv (traces planned cycle by cycle with rate\n"
           "limits, measured pressures and a deadline, against the plan without rate limits);\n"
           "the fidelity family writes DIR/fidelity.csv (each level's pose error against the\n"
           "finite-element reference: its pressures rested under the head's weight with the\n"
           "fitted contact law, on the catalogue's corrections and a seeded clinical sweep).\n\n"
           "  --out DIR      output folder, created if missing (default %s)\n"
           "  --quick        a test run: few timing samples; the IK's accuracy is still measured\n"
           "                 on every input, the planner's on 4 targets per group (not 40)\n"
           "  --only LIST    comma-separated families to run (default: all):",
           DEFAULT_OUT);
    for (size_t i = 0; i < N_FAMILIES; ++i) printf(" %s", families[i].chart.family);
    printf("\n"
           "  --seed N       order in which the timed batches walk the inputs (default 1)\n"
           "  --scene FILE   layout scene of the planner and peers families (default %s)\n"
           "  --scenarios DIR  scenario catalogue of the stability and levels families\n"
           "                 (default " DEFAULT_SCENARIOS ")\n"
           "  --python EXE   Python with SciPy for the peers family (default " DEFAULT_PYTHON ")\n"
           "  --peer-script FILE  the SciPy peer (default " DEFAULT_PEER_SCRIPT ")\n"
           "  --repeat N     loop family: run each trace N times (fresh planners each time) and\n"
           "                 take its percentiles over all N x cycles (default 1; 1..100);\n"
           "                 from N = 3 also the p99.9 of each cycle's median time over the\n"
           "                 N runs (the plans' own tail, without the host's stalls)\n"
           "  --loop-level LEVEL  loop family: only this contact level (linear, plane or\n"
           "                 surface; default all three)\n"
           "  --loop-backend NAME  loop family: only this backend (realtime or nlopt-slsqp;\n"
           "                 default both): under a second for realtime at one level, so two\n"
           "                 builds can take many turns\n"
           "  --loop-budget-us US  loop family: the deadline planner's time budget in\n"
           "                 microseconds (default %g; > 0, at most %g)\n"
           "  --help         this text\n\n"
           "exit status: 0 ok, 64 bad command line, 70 gnuplot or SciPy missing or failed,\n"
           "66 scene, catalogue or peer script cannot be read, 73 cannot write the output\n"
           "folder\n",
           DEFAULT_SCENE, BENCH_LOOP_BUDGET_US, BENCH_LOOP_BUDGET_MAX_US);
}

/* Marks the families named in a comma-separated list. Returns 0 or CLI_EXIT_USAGE. */
static int parse_only(const char *list, int *on)
{
    char buf[256];
    if (strlen(list) >= sizeof buf || !*list)
        return cli_fail(CLI_EXIT_USAGE, CMD, "--only: expected a list of families");
    strcpy(buf, list);
    for (char *p = buf;;) {
        char *comma = strchr(p, ',');
        if (comma) *comma = '\0';
        size_t k = 0;
        while (k < N_FAMILIES && strcmp(families[k].chart.family, p) != 0) ++k;
        if (k == N_FAMILIES)
            return cli_fail(CLI_EXIT_USAGE, CMD,
                            "--only: unknown family '%s' (known: ik, "
                            "planner, stability, peers, levels, load, loop, fidelity)",
                            p);
        on[k] = 1;
        if (!comma) break;
        p = comma + 1;
    }
    return 0;
}

static int csv_writer(const void *arg, FILE *f) { return bench_write_csv(arg, f); }

/* Runs one family and writes its files. Returns 0 or an exit status. */
static int run_family(const family *fam, const bench_options *o, const char *dir)
{
    if (fam->files) return fam->files(o, dir);
    bench_table t = {0};
    int rc = fam->run(o, &t);
    if (rc == 0) {
        bench_table_finish(&t);
        char name[64];
        snprintf(name, sizeof name, "%s.csv", fam->chart.family);
        rc = bench_save(dir, name, csv_writer, &t);
    }
    if (rc == 0) rc = bench_plot(&t, &fam->chart, dir);
    if (rc == 0) {
        bench_print_summary(&t, stdout);
        fprintf(stderr, "bench %s: wrote %s/%s.csv, %s/%s_pareto.png, %s/%s_pareto.svg\n",
                fam->chart.family, dir, fam->chart.family, dir, fam->chart.family, dir,
                fam->chart.family);
    }
    bench_table_free(&t);
    return rc;
}

/* The options that take a value, in the order help() lists them. */
enum {
    O_OUT,
    O_ONLY,
    O_SEED,
    O_SCENE,
    O_SCENARIOS,
    O_PYTHON,
    O_PEER,
    O_REPEAT,
    O_LEVEL,
    O_BACKEND,
    O_BUDGET,
    N_OPTS
};
static const char *const opt_names[N_OPTS] = {
    "--out",         "--only",   "--seed",       "--scene",        "--scenarios",     "--python",
    "--peer-script", "--repeat", "--loop-level", "--loop-backend", "--loop-budget-us"};

/* The loop family's level and backend from --loop-level and --loop-backend (either may be
 * NULL: all). Returns 0 or CLI_EXIT_USAGE after one line naming the option. */
static int loop_choice(const char *level, const char *backend, int *lv_out, int *bk_out)
{
    hp_level lv = HP_LEVEL_LINEAR; /* read only when given */
    hp_backend bk = HP_BACKEND_REALTIME;
    if (level && (hp_level_parse(level, &lv) != HP_OK ||
                  (lv != HP_LEVEL_LINEAR && lv != HP_LEVEL_PLANE && lv != HP_LEVEL_SURFACE)))
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "--loop-level: '%s' is not a level the loop family runs (linear, "
                        "plane or surface)",
                        level);
    if (backend && (hp_backend_parse(backend, &bk) != HP_OK ||
                    (bk != HP_BACKEND_REALTIME && bk != HP_BACKEND_NLOPT_SLSQP)))
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "--loop-backend: '%s' is not a backend the loop family runs (realtime "
                        "or nlopt-slsqp)",
                        backend);
    *lv_out = level ? (int)lv : -1;
    *bk_out = backend ? (int)bk : -1;
    return 0;
}

int bench_run_cli(int argc, char **argv)
{
    const char *val[N_OPTS] = {0}, **slots[N_OPTS];
    for (int o = 0; o < N_OPTS; ++o) slots[o] = &val[o];
    int quick = 0, rc;
    int loop_level = -1, loop_backend = -1;
    int on[N_FAMILIES] = {0};
    long seed = 1, repeat = 1;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            help();
            return CLI_EXIT_OK;
        }
    }
    /* Each option at most once (cli_named_opt): of two values one would be dropped silently. */
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--quick") == 0) {
            if (quick) return cli_fail(CLI_EXIT_USAGE, CMD, "--quick: given more than once");
            quick = 1;
            continue;
        }
        int m = cli_named_opt(CMD, argc, argv, &i, opt_names, slots, N_OPTS);
        if (m < 0) return CLI_EXIT_USAGE;
        if (m == 0)
            return cli_fail(CLI_EXIT_USAGE, CMD, "unknown option '%s' (see headplan-bench --help)",
                            argv[i]);
    }
    const char *out = val[O_OUT] ? val[O_OUT] : DEFAULT_OUT;
    const char *scene = val[O_SCENE] ? val[O_SCENE] : DEFAULT_SCENE;
    const char *scenarios = val[O_SCENARIOS] ? val[O_SCENARIOS] : DEFAULT_SCENARIOS;
    const char *python = val[O_PYTHON] ? val[O_PYTHON] : DEFAULT_PYTHON;
    const char *peer_script = val[O_PEER] ? val[O_PEER] : DEFAULT_PEER_SCRIPT;
    const int only_given = val[O_ONLY] != NULL, repeat_given = val[O_REPEAT] != NULL;
    /* the loop-only option named when there is no loop family */
    const char *loop_opt = val[O_LEVEL]     ? "--loop-level"
                           : val[O_BACKEND] ? "--loop-backend"
                           : val[O_BUDGET]  ? "--loop-budget-us"
                                            : NULL;
    /* An empty name names no file: refused as itself, not as a file that cannot be read. */
    for (int o = 0; o < N_OPTS; ++o)
        if (val[o] && !*val[o] &&
            (o == O_OUT || o == O_SCENE || o == O_SCENARIOS || o == O_PYTHON || o == O_PEER))
            return cli_fail(CLI_EXIT_USAGE, CMD, "%s: empty name", opt_names[o]);
    if (only_given && parse_only(val[O_ONLY], on) != 0) return CLI_EXIT_USAGE;
    if (repeat_given && cli_int(CMD, "--repeat", val[O_REPEAT], 1, 100, &repeat) != 0)
        return CLI_EXIT_USAGE;
    if (val[O_SEED] && cli_int(CMD, "--seed", val[O_SEED], 0, LONG_MAX, &seed) != 0)
        return CLI_EXIT_USAGE;
    if (loop_choice(val[O_LEVEL], val[O_BACKEND], &loop_level, &loop_backend) != 0)
        return CLI_EXIT_USAGE;
    double budget_us = BENCH_LOOP_BUDGET_US;
    if (val[O_BUDGET]) {
        if (cli_double(CMD, "--loop-budget-us", val[O_BUDGET], &budget_us) != 0)
            return CLI_EXIT_USAGE;
        if (!(budget_us * 1e-6 > 0) || !(budget_us <= BENCH_LOOP_BUDGET_MAX_US))
            return cli_fail(CLI_EXIT_USAGE, CMD,
                            "--loop-budget-us: must be > 0 and at most %g (got %s)",
                            BENCH_LOOP_BUDGET_MAX_US, val[O_BUDGET]);
    }
    if (!only_given)
        for (size_t k = 0; k < N_FAMILIES; ++k) on[k] = 1;
    int loop_on = 0;
    for (size_t k = 0; k < N_FAMILIES; ++k)
        loop_on |= on[k] && strcmp(families[k].chart.family, "loop") == 0;
    if (repeat_given && !loop_on) /* it would be silently ignored */
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "--repeat: only the loop family repeats its traces (add loop to --only)");
    if (loop_opt && !loop_on)
        return cli_fail(CLI_EXIT_USAGE, CMD,
                        "%s: only the loop family takes it (add loop to --only)", loop_opt);

    /* Fail before minutes of measuring, not after. */
    if (bench_gnuplot_available() != 0)
        return cli_fail(CLI_EXIT_SOFTWARE, CMD,
                        "gnuplot not found on PATH (it draws the charts; install the "
                        "'gnuplot' package)");
    for (size_t k = 0; k < N_FAMILIES; ++k) {
        if (on[k] && (families[k].reads & READS_CATALOGUE) &&
            (rc = bench_catalogue_readable(scenarios)) != 0)
            return rc;
        if (!on[k] || !(families[k].reads & READS_SCENE)) continue;
        FILE *f = fopen(scene, "r");
        if (!f)
            return cli_fail(CLI_EXIT_NOINPUT, CMD,
                            "--scene: cannot open '%s' (the %s "
                            "family needs a layout scene)",
                            scene, families[k].chart.family);
        fclose(f);
    }
    int peers_on = 0;
    for (size_t k = 0; k < N_FAMILIES; ++k) peers_on |= on[k] && families[k].run == bench_peers;
    if (peers_on) { /* SciPy must be there before minutes of measuring */
        FILE *f = fopen(peer_script, "r");
        if (!f)
            return cli_fail(CLI_EXIT_NOINPUT, CMD, "--peer-script: cannot open '%s'", peer_script);
        fclose(f);
        char *const chk[] = {hpi_unconst(python), "-c", "import scipy.optimize, numpy", NULL};
        if (bench_run_child(chk, NULL, 1) != 0)
            return cli_fail(CLI_EXIT_SOFTWARE, CMD,
                            "--python: '%s' cannot import scipy "
                            "(install Debian's python3-scipy, or name a Python that has "
                            "SciPy)",
                            python);
    }
    if ((rc = bench_mkdirs(out)) != 0) return rc;

    bench_options o;
    bench_options_default(&o, quick, (unsigned long)seed);
    o.scene = scene;
    o.scenarios = scenarios;
    o.python = python;
    o.peer_script = peer_script;
    o.out_dir = out;
    o.repeat = (int)repeat;
    o.loop_level = loop_level;
    o.loop_backend = loop_backend;
    o.loop_budget_us = budget_us;
    for (size_t k = 0; k < N_FAMILIES; ++k)
        if (on[k] && (rc = run_family(&families[k], &o, out)) != 0) return rc;
    return CLI_EXIT_OK;
}
