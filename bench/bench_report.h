/* headplan-bench: writing the results (CSV, gnuplot chart, summary) and the output folder. */
#ifndef BENCH_LAB_REPORT_H
#define BENCH_LAB_REPORT_H

#include "bench/bench.h"

#include <stdio.h>

/* The CSV header line (without newline); the columns never change order. */
extern const char *const bench_csv_header;

/* Writes the header and one line per row to f. Returns 0, or -1 on a write error. */
int bench_write_csv(const bench_table *t, FILE *f);

/* The short human-readable table printed on stdout. */
void bench_print_summary(const bench_table *t, FILE *f);

/* What the chart of one family says. */
typedef struct bench_chart {
    const char *family; /* file stem: DIR/<family>.csv, DIR/<family>_pareto.{gp,png,svg} */
    const char *title;
    const char *xlabel;
    const char *ylabel;
} bench_chart;

/* Creates dir and its parents (like mkdir -p). Returns 0, or CLI_EXIT_CANTCREAT after one
 * line on stderr naming the folder. */
int bench_mkdirs(const char *dir);

/* Writes DIR/NAME through DIR/NAME.tmp and a rename, so that a failed run never leaves a
 * partial file under the final name. writer returns 0 or -1. Returns 0, or
 * CLI_EXIT_CANTCREAT after one line on stderr naming the file. */
int bench_save(const char *dir, const char *name, int (*writer)(const void *arg, FILE *f),
               const void *arg);

/* Runs argv[0] from PATH (execvp, no shell) in folder cwd (NULL: here) with its stdout sent
 * to our stderr (our stdout carries results only) or, quiet, both to /dev/null. Returns its
 * exit status, or -1 when it could not be started or did not exit normally. */
int bench_run_child(char *const argv[], const char *cwd, int quiet);

/* Runs `gnuplot SCRIPT` in dir and checks that every file named in the NULL-terminated list
 * outputs (relative to dir) exists and is not empty. Returns 0 or CLI_EXIT_SOFTWARE after one
 * line on stderr. */
int bench_gnuplot_run(const char *dir, const char *script, const char *const *outputs);

/* 0 when `gnuplot --version` runs (found on PATH, exits 0), else -1. */
int bench_gnuplot_available(void);

/* Writes DIR/<family>_pareto.gp (reads DIR/<family>.csv, which must exist) and runs gnuplot
 * in DIR, drawing <family>_pareto.png and <family>_pareto.svg: time on x, error on y, log
 * scales, one mark and label per method, a series per variant, the Pareto front as a step
 * line, errors below BENCH_ERROR_FLOOR drawn at the floor. Returns 0, CLI_EXIT_CANTCREAT,
 * or CLI_EXIT_SOFTWARE when gnuplot fails or leaves an output missing or empty. */
int bench_plot(const bench_table *t, const bench_chart *c, const char *dir);

#endif
