/* Files a subcommand writes (-o, --script-out): every one goes through here, so that no
 * output path can destroy an input, a device, a FIFO or what a symbolic link points to,
 * and no interrupted or failed run leaves a partial file under the name a user asked for.
 *
 * A file is written to a temporary name beside it, created exclusively (mkstemp), and
 * renamed over the path only when complete. SIGINT, SIGTERM and SIGHUP remove the
 * temporary files, except a signal ignored on entry (nohup, trap ''), which stays ignored. */
#ifndef CLI_OUTFILE_H
#define CLI_OUTFILE_H

#include <stdio.h>
#include <sys/types.h>

/* An input by identity (device and inode), so it is refused as an output by any name. */
typedef struct cli_input {
    const char *what; /* "scene", "trace", "result", ... */
    const char *path;
    dev_t dev;
    ino_t ino;
    int known; /* 0: not a file we could stat (standard input, missing) */
} cli_input;

/* Records path as an input; "-" is standard input, recorded by what it is open on (named
 * "<stdin>"); paths that cannot be stat'ed are recorded as unknown (nothing to protect). */
void cli_input_of(cli_input *in, const char *what, const char *path);

/* 0 when path may be written by option opt of cmd; otherwise CLI_EXIT_CANTCREAT after one
 * line: a symbolic link, a directory, an existing non-regular file (device, FIFO, socket),
 * or the same file as one of the n inputs. */
int cli_out_allowed(const char *cmd, const char *opt, const char *path, const cli_input *in, int n);

/* 0 when the outputs a and b (named by options opt_a and opt_b) are different files;
 * otherwise CLI_EXIT_USAGE after one line. The same file is the same name in the same
 * directory however either is spelled ("x.svg", "./x.svg", "../d/x.svg", a link to the
 * directory): the second rename would replace the first output with exit 0. */
int cli_outputs_distinct(const char *cmd, const char *opt_a, const char *a, const char *opt_b,
                         const char *b);

/* 0 when standard output is not the input `what` NAME (open as fd, or at path when fd < 0);
 * otherwise CLI_EXIT_CANTCREAT after one line. `headplan solve s.yaml >> s.yaml` appended
 * the result to the scene, exit 0; `batch s.yaml t.csv >> t.csv` to the trace. */
int cli_stdout_not_input(const char *cmd, const char *what, const char *name, int fd,
                         const char *path);

typedef struct cli_out {
    FILE *f;          /* the temporary file, open for writing */
    const char *path; /* where it goes on commit */
    const char *opt;  /* the option that named it, for messages */
    int slot;         /* its entry in the signal handler's table */
} cli_out;

/* Checks path (cli_out_allowed) and creates its temporary file. Returns 0 or an exit
 * status after one line; on failure nothing is left on disk. */
int cli_out_open(cli_out *o, const char *cmd, const char *opt, const char *path,
                 const cli_input *in, int n);

/* The temporary file's name, for a writer that is not this process (gnuplot). */
const char *cli_out_temp(const cli_out *o);

/* Flushes, syncs and closes the temporary file, checks the path again (it may have become a
 * link or a device meanwhile) and renames the file over it. Returns 0, or CLI_EXIT_IOERR /
 * CLI_EXIT_CANTCREAT after one line, with the temporary file removed. */
int cli_out_commit(cli_out *o, const char *cmd);

/* Closes and removes the temporary file without a result (safe to call twice). */
void cli_out_abandon(cli_out *o);

#endif
