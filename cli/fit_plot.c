/* headplan fit material --plot: the residuals against the pressure as a small SVG chart
 * (no external program; fixed number formats, so the file is the same on every machine). */
#include "cli/fit_plot.h"
#include "cli/cli_args.h"
#include "cli/exit_codes.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define W 640.0
#define H 400.0
#define ML 70.0 /* margins: left, right, top, bottom */
#define MR 20.0
#define MT 40.0
#define MB 50.0

static double map(double v, double lo, double hi, double a, double b)
{
    return hi > lo ? a + (v - lo) / (hi - lo) * (b - a) : 0.5 * (a + b);
}

int fit_plot_svg(const char *cmd, const char *path, const cli_input *in, int nin, const char *title,
                 const double *x, const double *y, int n, double band, const char *xlabel,
                 const char *ylabel)
{
    double xlo = INFINITY, xhi = -INFINITY, ylim = band > 0 ? band : 0.0;
    for (int i = 0; i < n; ++i) {
        xlo = fmin(xlo, x[i]);
        xhi = fmax(xhi, x[i]);
        ylim = fmax(ylim, fabs(y[i]));
    }
    if (!(ylim > 0)) ylim = 1.0;
    ylim *= 1.15;
    double pad = (xhi - xlo) * 0.05;
    xlo -= pad;
    xhi += pad;
    cli_out out;
    int rc = cli_out_open(&out, cmd, "--plot", path, in, nin);
    if (rc) return rc;
    FILE *f = out.f;
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
            "font-family=\"sans-serif\" font-size=\"12\">\n",
            W, H);
    fprintf(f, "<rect width=\"%.0f\" height=\"%.0f\" fill=\"white\"/>\n", W, H);
    fprintf(f, "<text x=\"%.0f\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">%s</text>\n",
            W / 2, title);
    double x0 = ML, x1 = W - MR, y0 = H - MB, y1 = MT;
    fprintf(f,
            "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
            "stroke=\"black\"/>\n",
            x0, y1, x1 - x0, y0 - y1);
    double yz = map(0, -ylim, ylim, y0, y1);
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.2f\" x2=\"%.1f\" y2=\"%.2f\" stroke=\"gray\"/>\n", x0, yz,
            x1, yz);
    if (band > 0)
        for (int s = -1; s <= 1; s += 2) {
            double yb = map(s * band, -ylim, ylim, y0, y1);
            fprintf(f,
                    "<line x1=\"%.1f\" y1=\"%.2f\" x2=\"%.1f\" y2=\"%.2f\" stroke=\"gray\" "
                    "stroke-dasharray=\"4 4\"/>\n",
                    x0, yb, x1, yb);
        }
    for (int i = 0; i < n; ++i)
        fprintf(f, "<circle cx=\"%.2f\" cy=\"%.2f\" r=\"3.5\" fill=\"#1f5fa8\"/>\n",
                map(x[i], xlo, xhi, x0, x1), map(y[i], -ylim, ylim, y0, y1));
    /* Axis labels: the ends of each range. */
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"start\">%.4g</text>\n", x0, y0 + 16, xlo);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%.4g</text>\n", x1, y0 + 16, xhi);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n", (x0 + x1) / 2,
            H - 12, xlabel);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%.3g</text>\n", x0 - 6, y1 + 4,
            ylim);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">0</text>\n", x0 - 6, yz + 4);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%.3g</text>\n", x0 - 6, y0 + 4,
            -ylim);
    fprintf(f,
            "<text x=\"16\" y=\"%.1f\" transform=\"rotate(-90 16 %.1f)\" "
            "text-anchor=\"middle\">%s</text>\n",
            (y0 + y1) / 2, (y0 + y1) / 2, ylabel);
    fprintf(f, "</svg>\n");
    return cli_out_commit(&out, cmd);
}
