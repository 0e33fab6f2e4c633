/* HOLD's stable member (load_stable.h): the stiffness of a point of the holding set from
 * the pressures and radii the set's scan already solved for, the scan with a stability test,
 * and the bisection toward the pick. No allocation. */
#include "planner/load_stable.h"
#include "kinematics/contact_law.h"
#include "kinematics/load_internal.h"
#include "common/test_count.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

static atomic_ulong n_searches, n_points, n_tests, n_eigen, n_psolves, n_psteps;

void hpi_test_stable_counts(hp_test_stable_counts *out)
{
    out->searches = atomic_load(&n_searches);
    out->points = atomic_load(&n_points);
    out->tests = atomic_load(&n_tests);
    out->eigen = atomic_load(&n_eigen);
    out->solves = atomic_load(&n_psolves);
    out->steps = atomic_load(&n_psteps);
}

/* A point of the set outside the scan (counted); nr (may be NULL) two solved points it lies
 * between. */
static int seg_point(const hp_load_hold_set *hs, const double *x, const hp_load_near *nr, double *e,
                     double *P, double *R)
{
    hpi_count(&n_points, 1);
    unsigned long s0, t0, l0, s1, t1, l1;
    hpi_test_pressure_counts(&s0, &t0, &l0);
    int r = nr ? hpi_load_hold_set_point_near(hs, nr, x, e, P, R)
               : hpi_load_hold_set_point(hs, x, INFINITY, e, P, R);
    hpi_test_pressure_counts(&s1, &t1, &l1);
    hpi_count(&n_psolves, s1 - s0);
    hpi_count(&n_psteps, t1 - t0);
    return r;
}

/* The terms of the holding stiffness with pressures P (n, Pa) whose forces are x and inner
 * radii R, counting only the bladders whose contact lasts: a bladder adds its terms when its
 * force outlasts HP_LOAD_STABLE_CONTACT of the head moving away from it (x_k >= a_k·that,
 * a_k = −dF/drho its normal stiffness). A bladder that only just touches is stiff toward the
 * head and gives nothing away from it: counting it would call a hold stable that the forward
 * statics leaves. idx, Fv, av get the nv counted bladders' terms; 0, or -1 when the model
 * fails. */
static int stiff_terms(const hp_load_stiff *S, const double *x, const double *P, const double *R,
                       int *idx, double *Fv, double *av, int *nv)
{
    *nv = 0;
    for (int k = 0; k < S->n; ++k) {
        double ro;
        hp_claw c;
        if (!(x[k] > 0.0)) continue;
        if (hp_iab_ro(&S->M->layout.bladders[k].iab, R[k], &ro) != HP_OK) return -1;
        hpi_load_claw_to(S->M, k, P[k], ro, S->rho[k], HP_CLAW_GRADIENT, &c);
        double a = -c.d[HP_CLAW_RHO];
        if (!(x[k] >= a * HP_LOAD_STABLE_CONTACT)) continue;
        idx[*nv] = k;
        Fv[*nv] = x[k];
        av[(*nv)++] = a;
    }
    return 0;
}

/* The stable test of a point: its holding stiffness's smallest eigenvalue reaches the margin
 * (1, else 0; -1 when the model fails), by one Cholesky factorisation of K − margin·I. */
static int stable_at(const hp_load_stiff *S, const double *x, const double *P, const double *R)
{
    int idx[HP_MAX_BLADDERS], nv;
    double Fv[HP_MAX_BLADDERS], av[HP_MAX_BLADDERS];
    if (stiff_terms(S, x, P, R, idx, Fv, av, &nv) != 0) return -1;
    hpi_count(&n_tests, 1);
    return hpi_load_stiff_above(S, nv, idx, Fv, av, HP_LOAD_STABLE_MARGIN);
}

/* The smallest eigenvalue [N/mm] of a point's holding stiffness, for a caller that reports
 * it. 0, or -1 when the model fails. */
static int lambda_at(const hp_load_stiff *S, const double *x, const double *P, const double *R,
                     double *lam)
{
    int idx[HP_MAX_BLADDERS], nv;
    double Fv[HP_MAX_BLADDERS], av[HP_MAX_BLADDERS];
    if (stiff_terms(S, x, P, R, idx, Fv, av, &nv) != 0) return -1;
    hpi_count(&n_eigen, 1);
    return hpi_load_stiff_lambda_at(S, nv, idx, Fv, av, lam);
}

/* The scan's test: the point is stable with the margin. */
static int stable_test(void *ctx, const double *x, const double *P, const double *R)
{
    return stable_at((const hp_load_stiff *)ctx, x, P, R);
}

/* Grid points per free coordinate of the second scan: the stable part of the family can lie
 * where the tie-breaker's 3×3 grid does not look (a side bladder's band between touching and
 * carrying at the top of its range). */
#define STABLE_GRID_N 7
_Static_assert(STABLE_GRID_N <= HP_LOAD_SCAN_GRID_MAX, "the scan keeps its grid forces");

/* The bisection's halvings: the answer within 2^-10 of the segment from the crossing of the
 * margin (docs/load.md, "Stable holds: the bounds on work": on the supine scene's own
 * correction its pressures moved by at most 8.2 Pa from 16 halvings', 0.09 % of its
 * largest pressure, and its sum of squared pressures by +0.024 %). */
#define STABLE_HALVINGS 10

hpi_load_solve_status hpi_load_stable_hold(const hp_load_model *M, const double xi[6],
                                           const double *lo, const double *hi, const double *target,
                                           double *P, double *F, double *lam_min)
{
    hp_load_hold_set hs;
    hpi_load_solve_status st = hpi_load_hold_set_at(M, xi, lo, hi, target, &hs);
    if (st != HP_LOAD_SOLVE_OK) return st;
    return hpi_load_stable_hold_set(&hs, NULL, xi, P, F, lam_min);
}

hpi_load_solve_status hpi_load_stable_hold_set(const hp_load_hold_set *hs, hp_load_scan_rec *rec,
                                               const double xi[6], double *P, double *F,
                                               double *lam_min)
{
    const hp_load_model *M = hs->M;
    hp_load_stiff S;
    if (hpi_load_stiff_init(&S, M, xi, hs->target) != HP_OK) return HP_LOAD_SOLVE_ERROR;
    const int n = hs->n;
    /* The pick's forces and inner radii from its own pressures (one forward-kinematics
     * solve a carrying bladder; a bladder at or below L its least force Flo, 0 unless its
     * pressure floor lies above touching): no pressure solve. */
    double f0[HP_MAX_BLADDERS], P0[HP_MAX_BLADDERS], R0[HP_MAX_BLADDERS];
    int ok;
    if (hpi_load_hold_set_at_pressures(hs, P, f0, P0, R0) || (ok = stable_at(&S, f0, P0, R0)) < 0)
        return HP_LOAD_SOLVE_ERROR;
    if (ok)
        return lam_min && lambda_at(&S, f0, P0, R0, lam_min) ? HP_LOAD_SOLVE_ERROR
                                                             : HP_LOAD_SOLVE_OK;
    hpi_count(&n_searches, 1);
    /* The cheapest stable point of the scan (the tie-breaker's 3×3 grid and the vertices:
     * HOLD's own scan replayed when the caller kept it, which hands over c's pressures too;
     * where none is stable, the finer grid): the segment's far end c, stable by the scan's
     * own test at the pressures seg_point solves again (the replay's: the same bits). */
    double c[HP_MAX_BLADDERS], best, fb[HP_MAX_BLADDERS], Pb[HP_MAX_BLADDERS];
    double Rb[HP_MAX_BLADDERS] = {0};
    const int replay = rec && rec->valid;
    const int found = (replay ? hpi_load_scan_replay(hs, rec, stable_test, &S, c, &best, Pb, Rb)
                              : hpi_load_hold_set_scan(hs, HP_LOAD_SCAN_GRID_N, stable_test, &S,
                                                       c)) == 0;
    if (!found && hpi_load_hold_set_scan(hs, STABLE_GRID_N, stable_test, &S, c) != 0)
        return HP_LOAD_SOLVE_UNREACHABLE;
    if (!(replay && found) && seg_point(hs, c, NULL, &best, Pb, Rb)) return HP_LOAD_SOLVE_ERROR;
    memcpy(fb, c, (size_t)n * sizeof *fb);
    /* The stable point nearest the pick on the segment of forces from it to c: the set is
     * convex in the forces, so the segment holds the head throughout. Bisection of the
     * bracket [a, b] (the pick's end unstable, the other stable): lam jumps where a
     * contact starts to count (seen on the supine scene: +0.003 to −0.031 N/mm past the
     * margin), and there false position gains nothing on halving. The cheapest stable
     * point seen wins. */
    /* Each point's pressures are solved from the inner radii at the bracket's two ends
     * (forces on a segment: each bladder's force, so its radius, lies between the ends'). */
    double a = 0.0, b = 1.0;
    double xa[HP_MAX_BLADDERS], Ra[HP_MAX_BLADDERS], xb[HP_MAX_BLADDERS], Rbr[HP_MAX_BLADDERS];
    memcpy(xa, f0, (size_t)n * sizeof *xa);
    memcpy(Ra, R0, (size_t)n * sizeof *Ra);
    memcpy(xb, c, (size_t)n * sizeof *xb);
    memcpy(Rbr, Rb, (size_t)n * sizeof *Rbr);
    const hp_load_near nr = {xa, Ra, xb, Rbr};
    for (int it = 0; it < STABLE_HALVINGS; ++it) {
        double t = 0.5 * (a + b), x[HP_MAX_BLADDERS], Px[HP_MAX_BLADDERS], e;
        double Rx[HP_MAX_BLADDERS] = {0};
        for (int k = 0; k < n; ++k)
            x[k] = fmin(fmax(f0[k] + t * (c[k] - f0[k]), hs->Flo[k]), hs->Fhi[k]);
        if (seg_point(hs, x, &nr, &e, Px, Rx) || (ok = stable_at(&S, x, Px, Rx)) < 0)
            return HP_LOAD_SOLVE_ERROR;
        memcpy(ok ? xb : xa, x, (size_t)n * sizeof *x);
        memcpy(ok ? Rbr : Ra, Rx, (size_t)n * sizeof *Rx);
        if (!ok) {
            a = t;
            continue;
        }
        b = t;
        if (e < best) {
            best = e;
            memcpy(fb, x, (size_t)n * sizeof *fb);
            memcpy(Pb, Px, (size_t)n * sizeof *Pb);
            memcpy(Rb, Rx, (size_t)n * sizeof *Rb);
        }
    }
    if (lam_min && lambda_at(&S, fb, Pb, Rb, lam_min)) return HP_LOAD_SOLVE_ERROR;
    memcpy(P, Pb, (size_t)n * sizeof *P);
    memcpy(F, fb, (size_t)n * sizeof *F);
    return HP_LOAD_SOLVE_OK;
}
