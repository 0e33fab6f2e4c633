/* The residual chart of headplan fit. */
#ifndef CLI_FIT_PLOT_H
#define CLI_FIT_PLOT_H

/* Writes an SVG scatter of y against x (n points) to path with a zero line and, when
 * band > 0, dashed lines at ±band. Returns 0, or 73 after one line on stderr. */
int fit_plot_svg(const char *cmd, const char *path, const char *title, const double *x,
                    const double *y, int n, double band, const char *xlabel,
                    const char *ylabel);

#endif
