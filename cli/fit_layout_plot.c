/* headplan fit layout --plot: the per-axis residuals of every row before and after the fit,
 * drawn by gnuplot (the script holds its data inline, so --plot-script keeps a file that
 * redraws the picture by hand). */
#include "cli/fit_plot.h"
#include "cli/gnuplot_out.h"
#include "common/units.h"

#include <stdio.h>

typedef struct layout_plot {
    const gp_out *out;
    const char *title;
    int n, naxes;
    const long *lines;
    const double *before, *after; /* n×6, m and rad */
} layout_plot;

/* One data block per axis: line, residual before, residual after (mm or degrees). */
static int write_script(const void *arg, FILE *f)
{
    const layout_plot *p = arg;
    if (gp_terminal(f, p->out) != 0) return -1;
    for (int j = 0; j < p->naxes; ++j) {
        double k = j < 3 ? 1e3 : HP_DEG_PER_RAD;
        fprintf(f, "$axis%d << EOD\n# line before after\n", j);
        for (int i = 0; i < p->n; ++i)
            fprintf(f, "%ld %.9g %.9g\n", p->lines[i], p->before[i * 6 + j] * k,
                    p->after[i * 6 + j] * k);
        fprintf(f, "EOD\n");
    }
    fprintf(f, "set multiplot layout %d,3 title ", p->naxes > 3 ? 2 : 1);
    gp_label(f, p->title);
    fprintf(f, "\nset grid\nset key top right\nset xlabel 'data line'\n");
    for (int j = 0; j < p->naxes; ++j) {
        static const char *const AXIS[6] = {"x [mm]",      "y [mm]",     "z [mm]",
                                            "pitch [deg]", "roll [deg]", "yaw [deg]"};
        fprintf(f, "set ylabel '%s residual (measured - model)'\n", AXIS[j]);
        fprintf(f,
                "plot $axis%d using 1:2 with points pt 6 lc rgb '#b0b0b0' title 'before', "
                "$axis%d using 1:3 with points pt 7 lc rgb '#1f5fa8' title 'after', "
                "0 with lines lc rgb 'black' notitle\n",
                j, j);
    }
    fprintf(f, "unset multiplot\n");
    return 0;
}

int fit_layout_plot(const char *cmd, const char *path, const char *script, const cli_input *in,
                    int nin, const char *title, int n, int naxes, const long *lines,
                    const double *before, const double *after)
{
    gp_out o = {0};
    for (int i = 0; i < nin && i < 3; ++i) o.inputs[o.ninputs++] = in[i];
    o.path = path;
    o.script_out = script;
    o.path_opt = "--plot";
    o.script_opt = "--plot-script";
    o.width = 1500;
    o.height = naxes > 3 ? 900 : 500;
    int rc = gp_check(cmd, &o);
    if (rc >= 0) return rc;
    layout_plot p = {&o, title, n, naxes, lines, before, after};
    return gp_draw(cmd, &o, write_script, &p);
}
