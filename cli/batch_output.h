/* Internal to the batch subcommand: where results go (never over an input, a device, a
 * FIFO or a symbolic link), the metadata record, and the rows in CSV or JSON Lines with the
 * same columns and the same number text. */
#ifndef CLI_BATCH_OUTPUT_H
#define CLI_BATCH_OUTPUT_H

#include "cli/batch.h"
#include "cli/cli_args.h"
#include "cli/cli_outfile.h"
#include "cli/exit_codes.h"

#include <sys/types.h>

/* The metadata record written before the rows (one `# key: value` line each in CSV, one
 * object in JSON Lines), in this order. */
typedef struct batch_meta {
    const char *scene, *scene_sha256, *trace, *trace_sha256; /* trace_sha256 NULL: a stream */
    const char *rows, *rows_from, *pose_form;
    const char *level;        /* the resolved contact level */
    const char *level_choice; /* why auto chose it (hp_planner_level_choice); NULL: stated */
    const hp_settings *s;
} batch_meta;

typedef struct batch_sink {
    FILE *f;          /* stdout or file.f */
    cli_out file;     /* the -o file */
    const char *path; /* final path; NULL for stdout */
    hp_trace_format fmt;
    const hp_layout *L;
    int times; /* the measured columns (solve_time_us) */
    int ncols;
} batch_sink;

/* Picks the output format: --format when given; else from OUT's extension (.csv, .jsonl,
 * .ndjson); else an error (standard output has no extension). A --format that contradicts the
 * extension is an error. Returns 0 or CLI_EXIT_USAGE after one line. */
int batch_output_format(const char *format, const char *out, hp_trace_format *fmt);

/* Opens the output before any planning: out NULL or "-" is stdout. A path is refused (exit
 * CLI_EXIT_CANTCREAT, one line, nothing written) when it is a symbolic link, exists and is
 * not a regular file, or is the same file (device and inode) as any input. Otherwise a
 * temporary file beside it is created exclusively (mkstemp) and SIGINT, SIGTERM and SIGHUP
 * remove it from then on, except a signal that was ignored on entry (nohup), which stays
 * ignored. Returns 0 or an exit status after one line. */
int batch_sink_open(batch_sink *k, const char *out, hp_trace_format fmt, const hp_layout *L,
                    int times, const cli_input *inputs, int ninputs);

/* Lists the column table (hp_trace_columns.h) for scripts: a header line, then one
 * tab-separated line per column: name pattern, unit, format, shape, yes/no in the rows,
 * NumPy key (- for none), yes/no measured. */
void batch_columns_print(FILE *f);

/* Writes the metadata record and the column header. */
void batch_sink_meta(batch_sink *k, const batch_meta *m);

/* Writes one output row per input row. Returns 0, or CLI_EXIT_IOERR when the output has
 * failed (so a caller stops early). */
int batch_sink_rows(batch_sink *k, const batch_in *in, const batch_out *out, size_t rows);

/* Completes the output: a file is flushed, synced, closed and renamed to its path; stdout
 * is flushed. Returns 0 or CLI_EXIT_IOERR after one line (the temporary file removed). */
int batch_sink_commit(batch_sink *k);

/* Closes the output without a result and removes the temporary file. */
void batch_sink_abandon(batch_sink *k);

#endif
