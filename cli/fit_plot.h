/* The residual charts of headplan fit. Both are written through cli_outfile.h: never over
 * one of the command's inputs (in[0..nin)), a link or a device, and complete or not at all. */
#ifndef CLI_FIT_PLOT_H
#define CLI_FIT_PLOT_H

#include "cli/cli_outfile.h"

/* Writes an SVG scatter of y against x (n points) to path with a zero line and, when
 * band > 0, dashed lines at ±band. Returns 0, or 73 after one line on stderr. */
int fit_plot_svg(const char *cmd, const char *path, const cli_input *in, int nin, const char *title,
                 const double *x, const double *y, int n, double band, const char *xlabel,
                 const char *ylabel);

/* headplan fit layout --plot: draws with gnuplot, into path (.png or .svg), one panel per
 * pose axis (naxes 3 or 6) of each row's residual before and after the fit against its data
 * line (before, after: n×6 in m and rad); script (may be NULL) keeps the gnuplot script.
 * Returns 0, or after one line on stderr 64 (bad name), 69 (no gnuplot), 70 or 73. */
int fit_layout_plot(const char *cmd, const char *path, const char *script, const cli_input *in,
                    int nin, const char *title, int n, int naxes, const long *lines,
                    const double *before, const double *after);

#endif
