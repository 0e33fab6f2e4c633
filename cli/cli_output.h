/* Checked output shared by every subcommand: no command may exit 0 after a failed or
 * short write, flush or close of standard output or of a file it wrote. Such a failure is
 * exit status CLI_EXIT_IOERR (74) with one line on stderr naming what could not be
 * written. */
#ifndef CLI_OUTPUT_H
#define CLI_OUTPUT_H

#include <stdio.h>

/* Called first in main: a standard descriptor (0, 1, 2) that is closed (`>&-`) is
 * reserved on /dev/null opened the wrong way round, so that writes to a closed stdout fail
 * (and are reported) instead of landing in the first file the command opens. */
void cli_guard_std_fds(void);

/* Flushes, checks and closes f, written to `what` (a path, or "standard output"). Returns 0,
 * or CLI_EXIT_IOERR after "headplan CMD: cannot write WHAT: why" on stderr. */
int cli_close_output(FILE *f, const char *what, const char *cmd);

/* Flushes and checks f without closing it: 0, or CLI_EXIT_IOERR after the same line. */
int cli_flush_output(FILE *f, const char *what, const char *cmd);

/* Writes s and a newline to stdout (a whole --json answer), keeping the reason of a failed
 * write for the final check's message (cli_finish_stdout). */
void cli_put_line(const char *s);

/* The last step of main: checks and closes stdout after the command; a failure turns a
 * status 0 or 1 (a result was printed) into CLI_EXIT_IOERR. Returns the final status. */
int cli_finish_stdout(const char *cmd, int status);

#endif
