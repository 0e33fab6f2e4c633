/* headplan: the command-line program. Dispatches to one subcommand; stdout carries only
 * results, every diagnostic goes to stderr. */
#include "cli/cli_args.h"
#include "cli/cli_paths.h"
#include "cli/cli_output.h"
#include "cli/commands.h"
#include "cli/exit_codes.h"
#include "headplan/headplan.h"

#include <locale.h>
#include <stdio.h>
#include <string.h>

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} command;

static const command commands[] = {
    {"ik", cmd_ik, "one bladder: inner radius -> pressure (closed form)"},
    {"fk", cmd_fk, "one bladder: pressure -> inner radius (stable branch)"},
    {"paper", cmd_paper, "reproduce the paper's expansion and compression tables"},
    {"solve", cmd_solve, "a scene -> bladder pressures for one correction"},
    {"batch", cmd_batch, "a scene and a trace -> one planned row per trace row"},
    {"horizon", cmd_horizon, "a scene and a trace -> greedy, receding and offline plans"},
    {"analyze", cmd_analyze, "a scene -> layout conditioning, weakest direction and reach"},
    {"fit", cmd_fit, "calibration: bladder moduli or layout from measurements"},
    {"render", cmd_render, "a scene and one plan drawn in 3-D (gnuplot): PNG or SVG"},
    {"plot", cmd_plot, "a batch result over time (gnuplot): pose error, pressures"},
};
static const size_t n_commands = sizeof commands / sizeof commands[0];

/* The full text for --help; the mistake's reply (on stderr) leaves out where the files are. */
static void usage(FILE *out)
{
    fprintf(out, "usage: headplan COMMAND [OPTIONS]   (headplan COMMAND --help)\n\ncommands:\n");
    for (size_t i = 0; i < n_commands; ++i)
        fprintf(out, "  %-8s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\n  --version  print the version\n  --help     this text\n"
                 "\nexit status: 0 ok, 1 closest reachable only, 2 uncommanded (solve, batch\n"
                 "--strict), 64 usage, 65 bad data, 66 cannot open input, 69 gnuplot missing\n"
                 "(render, plot), 70 solver or internal failure, 73 output refused or cannot be\n"
                 "created, 74 a write to stdout or a file failed\n");
    if (out == stdout)
        printf("\ndocumentation: %s\nexample scenes: %s\n", cli_doc_dir(), cli_scene_dir());
}

int main(int argc, char **argv)
{
    setlocale(LC_ALL, "C");
    cli_guard_std_fds();
    if (argc < 2) {
        usage(stderr);
        return CLI_EXIT_USAGE;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(stdout);
        return cli_finish_stdout("--help", CLI_EXIT_OK);
    }
    if (strcmp(argv[1], "--version") == 0) {
        printf("headplan %s\n", hp_version());
        return cli_finish_stdout("--version", CLI_EXIT_OK);
    }
    /* Every subcommand's stdout is checked here, after it returns: a result that could not
     * be written in full is never exit 0. */
    for (size_t i = 0; i < n_commands; ++i)
        if (strcmp(argv[1], commands[i].name) == 0)
            return cli_finish_stdout(commands[i].name, commands[i].run(argc - 1, argv + 1));
    fprintf(stderr, "headplan: unknown command '");
    cli_put_escaped(stderr, argv[1]);
    fprintf(stderr, "' (see headplan --help)\n");
    return CLI_EXIT_USAGE;
}
