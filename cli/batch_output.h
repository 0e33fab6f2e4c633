/* Internal to the batch subcommand: output files. */
#ifndef HP_CLI_BATCH_OUTPUT_H
#define HP_CLI_BATCH_OUTPUT_H

#include "cli/batch.h"
#include "cli/cli_args.h"
#include "cli/exit_codes.h"

/* Writes one output row per input row, in order, to path (NULL: stdout). A file is written
 * under "PATH.partial-PID" and renamed to PATH only once complete and synced; SIGINT,
 * SIGTERM and SIGHUP remove the partial file. times: add the solve_time_us column (a
 * measurement, so two runs differ there). Returns 0 or an exit status after printing why. */
int batch_write(const char *path, hp_trace_format fmt, const hp_layout *L, const batch_in *in,
                const batch_out *out, size_t rows, int times);

#endif
