/* headplan-bench, family "ik": the bladder's inverse kinematics (radius -> pressure) by the
 * closed form versus the paper's two integrals by fixed Gauss–Legendre and adaptive
 * Gauss–Kronrod quadrature, all on the same grid of inputs.
 *
 * Accuracy: max relative error |P − P*|/|P*| against P*, the closed form evaluated naively
 * in __float128 from the same double inputs. The naive differences lose about
 * log2(1/|λi − λo|) bits; on this grid |λi − 1| >= 0.00625 and λi − λo >= 0.06·(λi − 1)
 * (thinnest wall, Ri/Ro = 0.98), so fewer than 15 of the 113 bits go: the reference is
 * ~1e-29 relative, far below any double-precision error. */
#include "cli/cli_args.h"
#include "bench/bench.h"
#include "bench/bench_timing.h"
#include "cli/exit_codes.h"
#include "headplan/hp_iab.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef __float128 q128;

/* The grid: λi = 0.50625 + 0.0125·k, k = 0..199 (covers [0.5, 3], never exactly 1, where
 * P = 0 and a relative error has no meaning), × wall thickness Ri/Ro, at Ro = 30 mm and the
 * paper's moduli C1 = 1.1e4 Pa, C2 = 2.2e4 Pa (docs/model.md §3). */
#define N_LAMBDA 200
static const double ratios[] = {0.5, 0.7, 0.9, 0.95, 0.98};
#define N_RATIO (sizeof ratios / sizeof ratios[0])
#define N_INPUTS (N_LAMBDA * (long)N_RATIO)
#define RO_M 0.030
#define C1_PA 1.1e4
#define C2_PA 2.2e4

typedef struct {
    hp_iab b;
    double ri, lambda, ratio;
} ik_input;

enum { K_CLOSED, K_DERIVS, K_GAUSS, K_ADAPTIVE };

typedef struct {
    int kind;
    hp_quad_form form;
    int n;      /* Gauss–Legendre points */
    double tol; /* adaptive relative tolerance */
} ik_method;

typedef struct {
    const ik_method *m;
    const ik_input *in;
    const long *perm;
    double sink;
} ik_ctx;

static q128 qabs(q128 x) { return x < 0 ? -x : x; }

/* Cube root in __float128 without libquadmath (whose header some compilers, e.g. clang,
 * do not find): the double cube root (error < 1e-16 relative) refined by three Newton steps
 * r ← r − (r³ − x)/(3r²), each of which squares the relative error: 1e-16 → 1e-32 → below
 * the 113-bit rounding (~1e-34), the third step only rounding. x > 0 here (the volume
 * law of a valid bladder). */
static q128 qcbrt(q128 x)
{
    q128 r = cbrt((double)x);
    for (int i = 0; i < 3; ++i) r -= (r * r * r - x) / (3 * r * r);
    return r;
}

static q128 qf(q128 l) { return -1 / l - 1 / (4 * l * l * l * l); }
static q128 qg(q128 l) { return l - 1 / (2 * l * l); }

/* P* in __float128: the closed form as written (naive), volume law included. */
static q128 reference(const hp_iab *b, double ri)
{
    q128 Ri = b->Ri, Ro = b->Ro, r = ri;
    q128 ro = qcbrt(Ro * Ro * Ro + r * r * r - Ri * Ri * Ri);
    q128 li = r / Ri, lo = ro / Ro;
    return 2 * (q128)b->C1 * (qf(li) - qf(lo)) + 2 * (q128)b->C2 * (qg(li) - qg(lo));
}

static hp_error eval(const ik_method *m, const hp_iab *b, double ri, double *P)
{
    double d1, d2;
    switch (m->kind) {
    case K_CLOSED: return hp_iab_ik(b, ri, P);
    case K_DERIVS: return hp_iab_ik_derivs(b, ri, P, &d1, &d2);
    case K_GAUSS: return hp_iab_ik_gauss(b, ri, m->form, m->n, P);
    default: return hp_iab_ik_adaptive(b, ri, m->form, m->tol, P, NULL, NULL);
    }
}

static void batch(void *vctx, long first, long count)
{
    ik_ctx *c = vctx;
    double s = 0;
    long pos = first % N_INPUTS; /* no division inside the loop: it would cost as much as
                                    the fastest method */
    for (long j = 0; j < count; ++j) {
        const ik_input *x = &c->in[c->perm[pos]];
        if (++pos == N_INPUTS) pos = 0;
        double P = 0;
        if (eval(c->m, &x->b, x->ri, &P) == HP_OK) s += P;
    }
    c->sink += s; /* results are used, so no call can be optimised away */
}

static void name_method(const ik_method *m, bench_row *r)
{
    const char *f = m->form == HP_QUAD_CURRENT ? "cur" : "ref";
    const char *fl = m->form == HP_QUAD_CURRENT ? "current" : "reference";
    switch (m->kind) {
    case K_CLOSED:
        snprintf(r->method, sizeof r->method, "closed");
        snprintf(r->variant, sizeof r->variant, "closed-form");
        snprintf(r->parameter, sizeof r->parameter, "P");
        break;
    case K_DERIVS:
        snprintf(r->method, sizeof r->method, "closed-derivs");
        snprintf(r->variant, sizeof r->variant, "closed-form");
        snprintf(r->parameter, sizeof r->parameter, "P+dP+d2P");
        break;
    case K_GAUSS:
        snprintf(r->method, sizeof r->method, "gl-%s-%d", f, m->n);
        snprintf(r->variant, sizeof r->variant, "gauss-%s", fl);
        snprintf(r->parameter, sizeof r->parameter, "%d", m->n);
        break;
    default:
        snprintf(r->method, sizeof r->method, "aq-%s-%.0e", f, m->tol);
        snprintf(r->variant, sizeof r->variant, "adaptive-%s", fl);
        snprintf(r->parameter, sizeof r->parameter, "%.0e", m->tol);
    }
    snprintf(r->family, sizeof r->family, "ik");
    snprintf(r->input_set, sizeof r->input_set, "grid");
}

/* Accuracy over every input; fills max_error, worst, failures, inputs. */
static void accuracy(const ik_method *m, const ik_input *in, const q128 *ref, bench_row *r)
{
    q128 worst = -1;
    long wi = 0;
    r->failures = 0;
    for (long i = 0; i < N_INPUTS; ++i) {
        double P;
        if (eval(m, &in[i].b, in[i].ri, &P) != HP_OK || !isfinite(P)) {
            r->failures++;
            continue;
        }
        q128 e = qabs((q128)P - ref[i]) / qabs(ref[i]);
        if (e > worst) {
            worst = e;
            wi = i;
        }
    }
    r->inputs = N_INPUTS;
    r->max_error = worst < 0 ? NAN : (double)worst;
    snprintf(r->worst, sizeof r->worst, "lambda_i=%.5f;Ri/Ro=%.2f", in[wi].lambda, in[wi].ratio);
}

static int build_methods(ik_method *ms, int cap)
{
    static const int orders[] = {2, 4, 8, 16, 32, 64};
    int n = 0;
    ms[n++] = (ik_method){K_CLOSED, HP_QUAD_CURRENT, 0, 0};
    ms[n++] = (ik_method){K_DERIVS, HP_QUAD_CURRENT, 0, 0};
    for (int f = 0; f < 2; ++f) {
        hp_quad_form form = f ? HP_QUAD_REFERENCE : HP_QUAD_CURRENT;
        for (size_t k = 0; k < sizeof orders / sizeof orders[0] && n < cap; ++k)
            ms[n++] = (ik_method){K_GAUSS, form, orders[k], 0};
        for (int e = 4; e <= 13 && n < cap; ++e)
            ms[n++] = (ik_method){K_ADAPTIVE, form, 0, pow(10.0, -e)};
    }
    return n;
}

int bench_ik(const bench_options *o, bench_table *t)
{
    ik_input *in = malloc((size_t)N_INPUTS * sizeof *in);
    long *perm = malloc((size_t)N_INPUTS * sizeof *perm);
    q128 *ref = malloc((size_t)N_INPUTS * sizeof *ref);
    if (!in || !perm || !ref) {
        free(in);
        free(perm);
        free(ref);
        cli_fail(0, "bench", "out of memory");
        return CLI_EXIT_SOFTWARE;
    }
    for (size_t j = 0; j < N_RATIO; ++j)
        for (long k = 0; k < N_LAMBDA; ++k) {
            ik_input *x = &in[(long)j * N_LAMBDA + k];
            x->ratio = ratios[j];
            x->lambda = 0.50625 + 0.0125 * (double)k;
            x->b = (hp_iab){ratios[j] * RO_M, RO_M, C1_PA, C2_PA};
            x->ri = x->lambda * x->b.Ri;
            ref[(long)j * N_LAMBDA + k] = reference(&x->b, x->ri);
        }
    bench_shuffle(perm, N_INPUTS, o->seed);

    ik_method ms[64];
    int nm = build_methods(ms, 64);
    int rc = 0;
    double sink = 0;
    for (int i = 0; i < nm && rc == 0; ++i) {
        bench_row *r = bench_table_add(t);
        if (!r) {
            rc = CLI_EXIT_SOFTWARE;
            break;
        }
        name_method(&ms[i], r);
        fprintf(stderr, "bench ik: [%2d/%d] %-16s", i + 1, nm, r->method);
        accuracy(&ms[i], in, ref, r);
        ik_ctx c = {&ms[i], in, perm, 0};
        bench_timing tm;
        if (bench_time(o, batch, &c, &tm) != 0) {
            rc = CLI_EXIT_SOFTWARE;
            break;
        }
        sink += c.sink;
        r->median_ns = tm.median_ns;
        r->p99_ns = tm.p99_ns;
        r->samples = tm.samples;
        r->batch = tm.batch;
        fprintf(stderr, " %10.1f ns  max error %.2e\n", r->median_ns, r->max_error);
    }
    if (rc) cli_fail(0, "bench", "out of memory");
    if (!isfinite(sink)) fprintf(stderr, "bench ik: note: a method returned a non-finite sum\n");
    t->baseline = "closed";
    free(in);
    free(perm);
    free(ref);
    return rc;
}
