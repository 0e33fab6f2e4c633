/* headplan-bench: the method table, its CSV file and the summary on stdout. */
#include "bench/bench.h"
#include "bench/bench_report.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bench_row *bench_table_add(bench_table *t)
{
    if (t->n == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 64;
        bench_row *r = realloc(t->rows, cap * sizeof *r);
        if (!r) return NULL;
        t->rows = r;
        t->cap = cap;
    }
    bench_row *r = &t->rows[t->n++];
    memset(r, 0, sizeof *r);
    r->median_ns = r->p99_ns = r->max_error = r->max_violation = NAN;
    r->ratio_to_baseline = r->model_error = r->round_ratio = NAN;
    return r;
}

void bench_table_free(bench_table *t)
{
    free(t->rows);
    memset(t, 0, sizeof *t);
}

/* Row a dominates row b when it is no slower and no less accurate, and better in one. A row
 * with a NaN error or time is on no front. */
static int dominates(const bench_row *a, const bench_row *b)
{
    return a->median_ns <= b->median_ns && a->max_error <= b->max_error &&
           (a->median_ns < b->median_ns || a->max_error < b->max_error);
}

void bench_table_finish(bench_table *t)
{
    double base = NAN;
    const bench_row *b = NULL;
    for (size_t i = 0; i < t->n; ++i)
        if (t->baseline && strcmp(t->rows[i].method, t->baseline) == 0) {
            b = &t->rows[i];
            base = b->median_ns;
        }
    for (size_t i = 0; i < t->n; ++i) {
        bench_row *r = &t->rows[i];
        r->ratio_to_baseline = base > 0 ? r->median_ns / base : NAN;
        r->round_ratio = b && r->rounds > 0 && r->rounds == b->rounds
                             ? bench_round_ratio(r->round_ns, b->round_ns, r->rounds)
                             : NAN;
        r->pareto = isfinite(r->median_ns) && isfinite(r->max_error) && r->failures == 0;
        for (size_t j = 0; j < t->n && r->pareto; ++j)
            if (j != i && t->rows[j].failures == 0 &&
                strcmp(t->rows[j].input_set, r->input_set) == 0 && dominates(&t->rows[j], r))
                r->pareto = 0;
    }
}

const char *const bench_csv_header =
    "method,family,variant,parameter,input_set,median_ns,p99_ns,max_error,worst_input,max_"
    "violation,"
    "model_error,failures,inputs,samples,batch,ratio_to_baseline,pareto,round_ratio,round_ns";

/* NaN is written as an empty field ("not applicable" / "not measured"). */
static void num(FILE *f, const char *fmt, double x)
{
    fputc(',', f);
    if (!isnan(x)) fprintf(f, fmt, x);
}

int bench_write_csv(const bench_table *t, FILE *f)
{
    fprintf(f, "%s\n", bench_csv_header);
    for (size_t i = 0; i < t->n; ++i) {
        const bench_row *r = &t->rows[i];
        fprintf(f, "%s,%s,%s,%s,%s", r->method, r->family, r->variant, r->parameter, r->input_set);
        num(f, "%.1f", r->median_ns);
        num(f, "%.1f", r->p99_ns);
        num(f, "%.6e", r->max_error);
        fprintf(f, ",%s", r->worst);
        num(f, "%.6e", r->max_violation);
        num(f, "%.6e", r->model_error);
        fprintf(f, ",%ld,%ld,%ld,%ld", r->failures, r->inputs, r->samples, r->batch);
        num(f, "%.4g", r->ratio_to_baseline);
        fprintf(f, ",%d", r->pareto);
        num(f, "%.4g", r->round_ratio);
        /* The rounds' medians in one field, ';'-separated, for ratios of any two rows. */
        fputc(',', f);
        for (int k = 0; k < r->rounds; ++k) fprintf(f, "%s%.1f", k ? ";" : "", r->round_ns[k]);
        fputc('\n', f);
    }
    return ferror(f) ? -1 : 0;
}

void bench_print_summary(const bench_table *t, FILE *f)
{
    fprintf(f, "%-8s %-24s %12s %12s %12s %9s %9s %8s %s\n", "family", "method", "median_ns",
            "p99_ns", "max_error", "vs_base", "rounds_vs", "failures", "pareto");
    for (size_t i = 0; i < t->n; ++i) {
        const bench_row *r = &t->rows[i];
        fprintf(f, "%-8s %-24s %12.1f %12.1f %12.3e %9.3g %9.3g %8ld %s\n", r->family, r->method,
                r->median_ns, r->p99_ns, r->max_error, r->ratio_to_baseline, r->round_ratio,
                r->failures, r->pareto ? "*" : "");
    }
}
