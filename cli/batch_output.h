/* Internal to the batch subcommand: output files. */
#ifndef HP_CLI_BATCH_OUTPUT_H
#define HP_CLI_BATCH_OUTPUT_H

#include "cli/batch.h"
#include "cli/cli_args.h"
#include "cli/exit_codes.h"

/* Creates the output before any planning, so that an -o that cannot be written fails at
 * once: path NULL gives stdout; otherwise "PATH.partial-PID" is created (never an existing
 * file) and SIGINT, SIGTERM and SIGHUP remove it from then on. Returns the stream, or NULL
 * after printing one line naming PATH (exit status HP_EXIT_CANTCREAT). */
FILE *batch_open(const char *path);

/* Writes one output row per input row, in order, to f from batch_open(path); a file is
 * synced, closed and renamed to PATH only once complete. times: add the solve_time_us
 * column (a measurement, so two runs differ there). Returns 0 or an exit status after
 * printing why. */
int batch_write(FILE *f, const char *path, hp_trace_format fmt, const hp_layout *L,
                const batch_in *in, const batch_out *out, size_t rows, int times);

/* Closes f from batch_open(path) without a result and removes the partial file. */
void batch_abandon(FILE *f, const char *path);

#endif
