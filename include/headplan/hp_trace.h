/* Reading traces of desired corrections (or measured deviations) for batch studies.
 *
 * The kind of the rows (deviation or correction) is never guessed: the file states it, or
 * the caller does; both may, if they agree. Format (docs/batch.md, "Input: traces"):
 *
 * CSV: an optional first line, spelled exactly
 *     # headplan-trace: rows=deviation        (or rows=correction)
 *   then one header naming the pose form, one of
 *     t_s,x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg                        (angles)
 *     t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz                                      (quaternion)
 *     t_s,m00,m01,m02,m03_mm,m10,m11,m12,m13_mm,m20,m21,m22,m23_mm,m30,m31,m32,m33
 *                                                                          (4x4 transform)
 *   and one row per sample. Blank lines and comment lines ('#') are skipped, except that a
 *   comment that looks like a directive ("# headplan...", "# rows..." in any case) anywhere
 *   but line 1, or misspelled, is an error.
 * JSON Lines: an optional first record, exactly {"headplan_trace": 1, "rows": "deviation"}
 *   (or "correction"), then one object per line whose keys are exactly one form's columns
 *   (the same in every row).
 * A UTF-8 byte-order mark at the start is skipped. Lines are at most HP_TRACE_LINE_MAX
 * bytes; a NUL byte or invalid UTF-8 is a bad row naming its line and column (bytes).
 * A deviation is the head's measured pose offset; its correction is the exact inverse rigid
 * motion about the pivot (hp_pose_inverse), which is what the planner is asked for.
 *
 * The reader reads strictly sequentially (pipes and FIFOs work) and its memory does not
 * grow with the trace or with a line. One reader per thread. */
#ifndef HP_TRACE_H
#define HP_TRACE_H

#include <stdio.h>

#include "headplan/hp_common.h"
#include "headplan/hp_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Longest line (bytes, without its end of line). */
#define HP_TRACE_LINE_MAX 4096

/* hp_trace_rows ("deviation" / "correction") and hp_trace_rows_name are in hp_scene.h. */
/* Parses "deviation" or "correction"; HP_ERR_INVALID otherwise. */
HP_API hp_error hp_trace_rows_parse(const char *s, hp_trace_rows *out);

typedef enum hp_trace_format { HP_TRACE_CSV = 0, HP_TRACE_JSONL } hp_trace_format;
HP_API const char *hp_trace_format_name(hp_trace_format f); /* "csv", "jsonl" */
HP_API hp_error hp_trace_format_parse(const char *s, hp_trace_format *out);

/* How a row gives its pose. */
typedef enum hp_trace_form {
    HP_TRACE_ANGLES = 0, /* x_mm, y_mm, z_mm, pitch_deg, roll_deg, yaw_deg */
    HP_TRACE_QUATERNION, /* x_mm, y_mm, z_mm, qw, qx, qy, qz (hp_pose_from_quaternion) */
    HP_TRACE_MATRIX      /* m00..m33 row-major, m03_mm..m23_mm in mm (hp_pose_from_matrix) */
} hp_trace_form;
HP_API const char *hp_trace_form_name(hp_trace_form f); /* "angles", "quaternion", "matrix" */

/* One sample of a trace. */
typedef struct hp_trace_row {
    long line;            /* 1-based line number in the file (set for bad rows too) */
    double t;             /* [s] */
    double correction[6]; /* SI (m, rad): the inverse of the row's pose for deviation rows */
} hp_trace_row;

typedef struct hp_trace_reader hp_trace_reader;

/* Opens a trace read from f, strictly sequentially (f may be a pipe; it is not closed by
 * the reader, close it after hp_trace_close). name is used in messages and, by its
 * extension (.csv, .jsonl / .ndjson), for the format; failing that, the first non-blank
 * line decides ('{': JSON Lines). rows, if not NULL, is what the caller knows of the rows,
 * and rows_from names where that came from ("--rows") for messages; NULL rows_from reads
 * "the caller". Reads the directive and header. Errors (diag "NAME:LINE:COL: ..."):
 * HP_ERR_INVALID when the file and rows disagree (naming both) or neither states the kind;
 * HP_ERR_PARSE for a malformed directive or header; HP_ERR_IO for a read error. Allocates
 * the reader; free it with hp_trace_close. */
HP_API hp_error hp_trace_open_stream(FILE *f, const char *name, const hp_trace_rows *rows,
                                     const char *rows_from, hp_trace_reader **out, hp_diag *diag);

/* Opens the trace file at path: as hp_trace_open_stream, with rows_from "the caller". */
HP_API hp_error hp_trace_open(const char *path, const hp_trace_rows *rows, hp_trace_reader **out,
                              hp_diag *diag);

/* Opens a trace held in memory (len bytes, not necessarily NUL-terminated); name is used in
 * messages. Same contract as hp_trace_open; the buffer is copied. */
HP_API hp_error hp_trace_open_mem(const char *data, size_t len, const char *name,
                                  hp_trace_format format, const hp_trace_rows *rows,
                                  hp_trace_reader **out, hp_diag *diag);

/* Reads the next sample. Returns HP_OK and fills row; HP_ERR_PARSE for a bad row (diag
 * says "NAME:LINE[:COL]: ...", row->line is set, and the reader moves on to the next line,
 * so a caller may continue); HP_ERR_IO on a read error; HP_ERR_STATE when the reader cannot
 * go on (a line longer than HP_TRACE_LINE_MAX; diag says so; the next calls say it again);
 * and HP_END (diag empty) at the end of the trace. */
HP_API hp_error hp_trace_next(hp_trace_reader *r, hp_trace_row *row, hp_diag *diag);

/* What the trace's rows are, and their pose form. */
HP_API hp_trace_rows hp_trace_rows_of(const hp_trace_reader *r);
HP_API hp_trace_form hp_trace_form_of(const hp_trace_reader *r);
/* 1 when the file itself states the kind of its rows (directive or header record). */
HP_API int hp_trace_states_rows(const hp_trace_reader *r);

/* Closes the reader (not a stream given to hp_trace_open_stream); safe on NULL. */
HP_API void hp_trace_close(hp_trace_reader *r);

#ifdef __cplusplus
}
#endif
#endif
