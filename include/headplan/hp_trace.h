/* Reading traces of desired corrections (or measured deviations) for batch studies.
 *
 * CSV: an optional comment line "# rows: deviation" or "# rows: correction", then the header
 *   t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg
 * and one row per sample. Blank lines and other lines starting with '#' are skipped.
 * JSON Lines: one object per line with the same keys; an optional first line
 *   {"rows": "deviation"}  (or "correction").
 * A deviation is the head's measured offset from the planned pose; its correction is the
 * opposite pose (every component negated), which is what the planner is asked for.
 *
 * The reader streams: memory does not grow with the trace. One reader per thread. */
#ifndef HP_TRACE_H
#define HP_TRACE_H

#include "headplan/hp_common.h"
#include "headplan/hp_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* hp_trace_rows ("deviation" / "correction") and hp_trace_rows_name are in hp_scene.h. */
/* Parses "deviation" or "correction"; HP_ERR_INVALID otherwise. */
HP_API hp_error hp_trace_rows_parse(const char *s, hp_trace_rows *out);

typedef enum hp_trace_format { HP_TRACE_CSV = 0, HP_TRACE_JSONL } hp_trace_format;
HP_API const char *hp_trace_format_name(hp_trace_format f); /* "csv", "jsonl" */
HP_API hp_error hp_trace_format_parse(const char *s, hp_trace_format *out);

/* One sample of a trace. */
typedef struct hp_trace_row {
    long line;          /* 1-based line number in the file */
    double t;           /* [s] */
    double correction[6]; /* SI (m, rad), already negated for deviation traces */
} hp_trace_row;

typedef struct hp_trace_reader hp_trace_reader;

/* Opens a trace; the format is taken from the extension (.csv, .jsonl / .ndjson) or, failing
 * that, from the first non-blank character ('{' means JSON Lines). rows_override, if not NULL,
 * replaces what the file states (a file that states nothing means corrections). Reads the
 * header. Allocates the reader; free it with hp_trace_close. */
HP_API hp_error hp_trace_open(const char *path, const hp_trace_rows *rows_override,
                       hp_trace_reader **out, hp_diag *diag);

/* Opens a trace held in memory (len bytes, not necessarily NUL-terminated); name is used in
 * messages. Same contract as hp_trace_open; the buffer is copied. */
HP_API hp_error hp_trace_open_mem(const char *data, size_t len, const char *name,
                           hp_trace_format format, const hp_trace_rows *rows_override,
                           hp_trace_reader **out, hp_diag *diag);

/* Reads the next sample. Returns HP_OK and fills row; HP_ERR_PARSE for a bad row (diag says
 * "FILE:LINE: ..." and the reader moves on to the next line, so a caller may continue);
 * HP_ERR_IO on a read error; and HP_ERR_STATE (diag empty) at the end of the trace. */
HP_API hp_error hp_trace_next(hp_trace_reader *r, hp_trace_row *row, hp_diag *diag);

/* What the trace's rows are (after any override). */
HP_API hp_trace_rows hp_trace_rows_of(const hp_trace_reader *r);

/* Closes the reader; safe on NULL. */
HP_API void hp_trace_close(hp_trace_reader *r);

#ifdef __cplusplus
}
#endif
#endif
