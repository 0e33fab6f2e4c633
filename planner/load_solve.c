/* The load planner's two solves, shared by every backend that uses them:
 *
 * HOLD (pose fixed): at a pose xi the equilibrium is linear in the contact forces,
 *     sum_k F_k·J_k(xi) = −Q_grav(xi),
 * and each F_k = P_k·pi·(ro(P_k)² − rho_k²) rises monotonically with P_k from the pressure
 * at which the bladder starts to carry (max(p_lo, 0, the touching pressure)) to p_hi. So
 * the set of holding pressures is exactly {F in a box : A·F = b}: an SQP in F has exact
 * (linear) constraints, decides reachability exactly, and minimises the tie-breaker
 * sum (P_k(F_k) − t_k)² with its exact second derivative (Newton steps).
 *
 * POSE (pose free, when HOLD finds the desired pose unreachable): the nearest pose at which
 * some pressures inside the limits hold the head, by SQP on (xi, P) with the generalized
 * force's exact Jacobians, the weighted pose error as objective, a small proximal term on
 * P and a 2 mm / 2° trust region per step; then HOLD at that pose picks the pressures.
 *
 * Each QP is load_qp.c's 6-dimensional dual. No allocation. */
#include "planner/load_solve.h"
#include "common/units.h"
#include "iab/iab_internal.h"
#include "kinematics/contact_law.h"
#include "kinematics/load_internal.h"
#include "planner/load_qp.h"
#include "common/test_count.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

double hpi_load_row_weight(int r) { return r < 3 ? 1.0 : hpi_load_unit(r) / 1e-3; }

static double row_w(int r) { return hpi_load_row_weight(r); }

/* One bladder at pressure P against contact distance rho: F and its first two pressure
 * derivatives (ro'' from the bladder model's d²P/dri²). */
typedef struct bstate {
    double F, FP, FPP;
} bstate;

static atomic_ulong n_fk;

void hpi_test_fk_counts(unsigned long *fk) { *fk = atomic_load(&n_fk); }

/* Bladder k's inner radius at pressure P: the bladder's forward kinematics (an iterative
 * solve, the dearest step of a force), counted. */
static hp_error fk_of(const hp_load_model *M, int k, double P, double *ri)
{
    hpi_count(&n_fk, 1);
    return hp_iab_fk_limit(&M->layout.bladders[k].iab, &M->limit[k], P, ri);
}

/* ro of bladder k at inner radius ri with ro' and ro'' along the pressure (ro'' from the
 * bladder model's d²P/dri²). */
static hp_error radius_chain(const hp_load_model *M, int k, double ri, double *ro, double *o1,
                             double *o2)
{
    const hp_iab *b = &M->layout.bladders[k].iab;
    double Pc, Pr, Prr;
    hp_error err = hp_iab_ro(b, ri, ro);
    if (!err) err = hp_iab_ik_derivs(b, ri, &Pc, &Pr, &Prr);
    if (err) return err;
    double r1 = 1.0 / Pr, r2 = -Prr * r1 * r1 * r1;         /* ri', ri'' */
    double q = ri * ri / (*ro * *ro);                       /* dro/dri */
    double q2 = 2.0 * ri / (*ro * *ro) - 2.0 * q * q / *ro; /* d²ro/dri² */
    *o1 = q * r1;
    *o2 = q2 * r1 * r1 + q * r2;
    return HP_OK;
}

/* A law's value (F, or dF/drho) and its total first and second derivatives along P at a
 * fixed contact distance, through ro(P) (ro' = o1, ro'' = o2). */
static void along_p(const hp_claw *c, double o1, double o2, double *v, double *v1, double *v2)
{
    *v = c->F;
    *v1 = c->d[HP_CLAW_P] + c->d[HP_CLAW_RO] * o1;
    *v2 = c->d2[HP_CLAW_P][HP_CLAW_P] + 2.0 * c->d2[HP_CLAW_P][HP_CLAW_RO] * o1 +
          c->d2[HP_CLAW_RO][HP_CLAW_RO] * o1 * o1 + c->d[HP_CLAW_RO] * o2;
}

static atomic_ulong n_sets, n_derived;

void hpi_test_hold_counts(unsigned long *sets, unsigned long *derived)
{
    *sets = atomic_load(&n_sets);
    *derived = atomic_load(&n_derived);
}

/* Bladder k's state at pressure P whose inner radius is ri. */
static hp_error bladder_state_ri(const hp_load_model *M, int k, double P, double ri, double rho,
                                 bstate *s)
{
    hpi_count(&n_derived, 1);
    double ro, o1, o2;
    hp_error err = radius_chain(M, k, ri, &ro, &o1, &o2);
    if (err) return err;
    hp_claw c; /* F(P, ro(P), rho) and its total derivatives along P */
    hpi_load_claw(M, k, P, ro, rho, &c);
    along_p(&c, o1, o2, &s->F, &s->FP, &s->FPP);
    return HP_OK;
}

/* Bladder k's force at pressure P whose inner radius is ri (the law's value alone: the same
 * bits as bladder_state's F, without the law's derivatives or the IK's). */
static hp_error force_at_ri(const hp_load_model *M, int k, double P, double ri, double rho,
                            double *F)
{
    double ro;
    hp_error err = hp_iab_ro(&M->layout.bladders[k].iab, ri, &ro);
    if (err) return err;
    hp_claw c;
    hpi_load_claw_to(M, k, P, ro, rho, HP_CLAW_VALUE, &c);
    *F = c.F;
    return HP_OK;
}

/* Bladder k's force at pressure P (bladder_state's F alone). */
static hp_error bladder_force(const hp_load_model *M, int k, double P, double rho, double *F)
{
    double ri;
    hp_error err = fk_of(M, k, P, &ri);
    return err ? err : force_at_ri(M, k, P, ri, rho, F);
}

/* Bladder k's state at pressure P. */
static hp_error bladder_state(const hp_load_model *M, int k, double P, double rho, bstate *s)
{
    double ri;
    hp_error err = fk_of(M, k, P, &ri);
    return err ? err : bladder_state_ri(M, k, P, ri, rho, s);
}

/* The touching pressure: the one whose free radius equals rho (−inf when rho is below the
 * smallest radius the cavity allows, +inf past the limit point). *ri gets the inner radius
 * whose outer radius is rho (the bladder's volume law, closed form: what the forward
 * kinematics of the returned pressure solves for, to a few ulps), NaN when the pressure is
 * infinite. */
static double touch_pressure_ri(const hp_load_model *M, int k, double rho, double *ri)
{
    const hp_iab *b = &M->layout.bladders[k].iab;
    double P;
    *ri = NAN;
    if (hp_iab_ri(b, rho, ri) != HP_OK) return -INFINITY;
    if (M->limit[k].exists && !(*ri < M->limit[k].ri)) return INFINITY;
    if (hp_iab_ik(b, *ri, &P) != HP_OK) return *ri > b->Ri ? INFINITY : -INFINITY;
    return P;
}

double hpi_load_touch_pressure(const hp_load_model *M, int k, double rho)
{
    double ri;
    return touch_pressure_ri(M, k, rho, &ri);
}

static double indent_pressure_ri(const hp_load_model *M, int k, double rho, double *ri)
{
    return touch_pressure_ri(M, k, rho / (1.0 - HP_LOAD_INDENT_MAX), ri);
}

double hpi_load_indent_pressure(const hp_load_model *M, int k, double rho)
{
    double ri;
    return indent_pressure_ri(M, k, rho, &ri);
}

/* The pressure in [lo, hi] whose force against rho is F (F increasing in P there). Solved in
 * the inner radius ri, where the pressure (the bladder model's IK) and the outer radius (the
 * volume law) are closed forms: only the bracket's two ends need the bladder's forward
 * kinematics, not every Newton step (it was half of an unreachable plan's time).
 * Safeguarded Newton with bisection, up to its first step of at most PRESSURE_STEP of ri. */
typedef struct radius_bracket {
    double a, c, Fa, Fc; /* inner radii holding the forces Fa < Fc: the root lies between */
} radius_bracket;
/* The last Newton step of a pressure solve: a step of at most 1e-8 of the radius, applied,
 * leaves an error of the order of its square (Newton converges quadratically there),
 * rounding size, so the step that would only confirm it is not taken. On load_supine's plan:
 * 2.89 steps a solve instead of 3.37 (solves from the carrying range's ends that ran on to a
 * step of two ulps), its pressures within 1e-11 Pa of those, and load_heavy's within
 * 1e-11 Pa. */
#define PRESSURE_STEP 1e-8
static hp_error pressure_of_force_in(const hp_load_model *M, int k, double rho, double lo,
                                     double hi, radius_bracket br, double Fhi, double F, double *P,
                                     double *ri);

static atomic_ulong n_psolves, n_psteps, n_plong, n_pmodel;

void hpi_test_pressure_counts(unsigned long *solves, unsigned long *steps, unsigned long *longer)
{
    *solves = atomic_load(&n_psolves);
    *steps = atomic_load(&n_psteps);
    *longer = atomic_load(&n_plong);
}

void hpi_test_pressure_model_counts(unsigned long *passes) { *passes = atomic_load(&n_pmodel); }

/* One pass through the bladder model (validated into s once a solve) at inner radius ri [m]:
 * the pressure, its slope dP/dri (Pr NULL: not formed) and the outer radius [m] that the
 * pressure's closed form forms anyway; the same codes and bits as hp_iab_ik_derivs and
 * hp_iab_ro (iab_internal.h: hpi_iab_s_pressure_ro, hpi_iab_s_slopes). Counted. */
static hp_error model_at(const hp_iab_s *s, double ri, double *P, double *Pr, double *ro)
{
    hpi_count(&n_pmodel, 1);
    double ris, rs, d1;
    hp_error e = hpi_iab_s_radius(s, ri, &ris);
    if (e) return e;
    if (hpi_iab_s_pressure_ro(s, ris, P, &rs) != HP_OK) return HP_ERR_DOMAIN;
    if (Pr) {
        if (hpi_iab_s_slopes(s, ris, rs, &d1, NULL) != HP_OK) return HP_ERR_DOMAIN;
        *Pr = d1 * s->scale;
    }
    *ro = rs * s->inv_scale;
    return HP_OK;
}

static void count_pressure_solve(int steps)
{
    hpi_count(&n_psolves, 1);
    hpi_count(&n_psteps, (unsigned long)steps);
    if (steps > HP_LOAD_PRESSURE_STEPS_LONG) hpi_count(&n_plong, 1);
}

/* The pressure in [lo, hi] whose force against rho is F, with a bracket of the inner radius
 * known: br's radii hold its forces (the radii at lo and hi with the forces 0 and Fhi, or a
 * narrower bracket inside them), and Newton starts from the secant between them; *ri (may
 * be NULL) gets the inner radius at the answer (at lo or hi: br's a or c, when F is at or beyond an end of the carrying range). */
static hp_error pressure_of_force_in(const hp_load_model *M, int k, double rho, double lo,
                                     double hi, radius_bracket br, double Fhi, double F, double *P,
                                     double *ri)
{
    double a = br.a, c = br.c;
    if (F <= 0.0) {
        *P = lo;
        if (ri) *ri = a;
        return HP_OK;
    }
    if (F >= Fhi) {
        *P = hi;
        if (ri) *ri = c;
        return HP_OK;
    }
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    hp_error err = hpi_iab_scaled_init(&M->layout.bladders[k].iab, &s, NULL);
    if (err) return err;
    double x = a + (c - a) * ((F - br.Fa) / (br.Fc - br.Fa)), Px = lo;
    int steps = 0;
    for (int it = 0; it < 200; ++it) {
        ++steps;
        double Pr, ro;
        if ((err = model_at(&s, x, &Px, &Pr, &ro))) return err;
        hp_claw law;
        hpi_load_claw_to(M, k, Px, ro, rho, HP_CLAW_GRADIENT, &law); /* F and d only */
        double r = law.F - F;
        if (r > 0) c = x;
        else a = x;
        if (r == 0.0) break;
        /* dF/dri along the bladder: F_P·dP/dri + F_ro·dro/dri, dro/dri = ri²/ro² */
        double dF = law.d[HP_CLAW_P] * Pr + law.d[HP_CLAW_RO] * (x * x) / (ro * ro);
        double xn = dF > 0 ? x - r / dF : 0.5 * (a + c);
        int newton = dF > 0;
        if (!(xn > a && xn < c)) {
            /* A step of rounding size out of the open bracket: this step's own residual has
             * just made x an end of the bracket, and x is the root to two ulps. Halving
             * instead would close the bracket onto it from its far end, 50 steps. */
            if (dF > 0 && fabs(xn - x) <= 4e-16 * x) break;
            xn = 0.5 * (a + c);
            newton = 0;
        }
        /* Only a Newton step this short is the last: a halving this short leaves the root
         * anywhere in a bracket of twice its size. */
        int done = (newton && fabs(xn - x) <= PRESSURE_STEP * x) || c - a <= 4e-16 * x;
        x = xn;
        if (done) {
            if ((err = model_at(&s, x, &Px, NULL, &ro))) return err;
            break;
        }
    }
    count_pressure_solve(steps);
    *P = fmin(fmax(Px, lo), hi);
    if (ri) *ri = x;
    return HP_OK;
}

/* Adds bladder k's share of the tie-breaker sum at force x[k] to *e: (P(F) − t)² for a
 * carrying bladder, and for one at zero force the best pressure that carries nothing (any in
 * [lo, L], L the bottom of its carrying range), as HOLD's answer gives it; P[k] gets that
 * pressure and R[k] (R may be NULL) a carrying bladder's inner radius. Non-zero when the
 * model fails. ra, rc: the inner radii at L and U. */
static int tie_cost(const hp_load_model *M, int k, const double *rho, const double *lo,
                    const double *L, const double *U, const double *ra, const double *rc,
                    const double *Flo, const double *Fhi, const double *target, const double *x,
                    const hp_load_near *nr, double *e, double *P, double *R)
{
    double Pk;
    radius_bracket br = {ra[k], rc[k], 0.0, Fhi[k]};
    if (nr) { /* a narrower bracket: two points whose forces lie on either side of x[k] */
        const int up = nr->xa[k] < nr->xb[k];
        const double f1 = up ? nr->xa[k] : nr->xb[k], f2 = up ? nr->xb[k] : nr->xa[k];
        const double r1 = up ? nr->Ra[k] : nr->Rb[k], r2 = up ? nr->Rb[k] : nr->Ra[k];
        if (f1 > 0.0 && f1 < x[k] && x[k] < f2 && f2 < Fhi[k] && r1 < r2)
            br = (radius_bracket){r1, r2, f1, f2};
    }
    if (x[k] <= 0.0 && Flo[k] <= 0.0) {
        Pk = fmin(fmax(target[k], lo[k]), L[k]);
    } else if (pressure_of_force_in(M, k, rho[k], L[k], U[k], br, Fhi[k], x[k], &Pk,
                                    R ? &R[k] : NULL)) {
        return -1;
    }
    *e += (Pk - target[k]) * (Pk - target[k]);
    P[k] = Pk;
    return 0;
}

/* Grid points per free coordinate of the holding set (at most two coordinates): the ends
 * and the middle of each free bladder's pressure range. The vertices below carry the
 * search; the grid adds interior starts at little cost (3 x 3 points). */
#define GRID_N HP_LOAD_SCAN_GRID_N

/* The holding set at pose xi inside [lo, hi]: OK, UNREACHABLE when a bladder centre is
 * inside the head or a row no force box can meet (a necessary condition, exact, and cheap
 * where phase 1's QP must run out its multiplier updates to show infeasibility: the sinking
 * search asks this ~20 times per unreachable pose), ERROR when the model fails. */
hpi_load_solve_status hpi_load_hold_set_at(const hp_load_model *M, const double xi[6],
                                           const double *lo, const double *hi, const double *target,
                                           hp_load_hold_set *h)
{
    hpi_count(&n_sets, 1);
    const int n = M->layout.n;
    h->M = M;
    h->n = n;
    h->m = 0;
    h->lo = lo;
    h->target = target;
    double J[HP_MAX_BLADDERS * 6], Qg[6];
    if (hpi_contact_eval_g(&M->layout, &M->geom, M->level, xi, h->rho, J, NULL) != HP_OK)
        return HP_LOAD_SOLVE_ERROR;
    /* A pose with a bladder centre inside the head (through its panel) is held by nothing. */
    if (hpi_load_domain(M, h->rho) != HP_OK) return HP_LOAD_SOLVE_UNREACHABLE;
    hpi_load_gravity(M, xi, Qg, NULL, NULL);
    for (int k = 0; k < n; ++k) {
        double rt, rin; /* the inner radii at the touching and the indentation pressures */
        h->Pt[k] = touch_pressure_ri(M, k, h->rho[k], &rt);
        h->L[k] = fmax(lo[k], fmax(0.0, h->Pt[k]));
        /* The indentation range where the contact law is trusted caps a carrying bladder's
         * pressure at this pose: ro(P) <= rho/(1 − HP_LOAD_INDENT_MAX). A bladder whose
         * lowest pressure already carries beyond it cannot hold the pose. */
        double Pi = indent_pressure_ri(M, k, h->rho[k], &rin);
        if (lo[k] > 0 && lo[k] > h->Pt[k] && lo[k] > Pi) return HP_LOAD_SOLVE_UNREACHABLE;
        h->U[k] = fmin(hi[k], Pi);
        h->Flo[k] = h->Fhi[k] = h->ra[k] = h->rc[k] = 0.0;
        if (h->L[k] < h->U[k]) {
            double F;
            h->col[h->m++] = k;
            /* An end at the touching or the indentation pressure has its inner radius in
             * closed form already (the forward kinematics of that pressure returns it to
             * the solve's rounding); the others are solved. */
            if (h->L[k] == h->Pt[k]) h->ra[k] = rt;
            else if (fk_of(M, k, h->L[k], &h->ra[k])) return HP_LOAD_SOLVE_ERROR;
            if (h->U[k] == Pi) h->rc[k] = rin;
            else if (fk_of(M, k, h->U[k], &h->rc[k])) return HP_LOAD_SOLVE_ERROR;
            if (force_at_ri(M, k, h->L[k], h->ra[k], h->rho[k], &F)) return HP_LOAD_SOLVE_ERROR;
            h->Flo[k] = fmax(0.0, F);
            if (force_at_ri(M, k, h->U[k], h->rc[k], h->rho[k], &F)) return HP_LOAD_SOLVE_ERROR;
            h->Fhi[k] = F;
        }
        for (int r = 0; r < 6; ++r) h->A[r * n + k] = J[k * 6 + r] * row_w(r);
    }
    h->fscale = 0.0;
    for (int r = 0; r < 6; ++r) {
        h->b[r] = -Qg[r] * row_w(r);
        h->fscale = fmax(h->fscale, fabs(h->b[r]));
    }
    h->tol = 1e-13 * fmax(1.0, h->fscale);
    for (int r = 0; r < 6; ++r) {
        double rlo = 0.0, rhi = 0.0;
        for (int k = 0; k < n; ++k) {
            double a = h->A[r * n + k] * h->Flo[k], c = h->A[r * n + k] * h->Fhi[k];
            rlo += fmin(a, c);
            rhi += fmax(a, c);
        }
        if (h->b[r] < rlo - h->tol || h->b[r] > rhi + h->tol) return HP_LOAD_SOLVE_UNREACHABLE;
    }
    return HP_LOAD_SOLVE_OK;
}

/* The inner radii of the pressures last asked of each bladder on a holding set: HOLD asks a
 * bladder's force again at the same pressure (the SQP's state at the point its line search
 * accepted, the answer's forces, a pressure at a bound, a grid's ends), and the forward
 * kinematics is the dearest step of a force. The set's carrying ends are known (ra at L, rc
 * at U; at the touching and indentation pressures from the closed form, which may differ
 * from the forward kinematics by a few ulps): every user of the set reads these same ra, rc. */
typedef struct ri_memo {
    double P[HP_MAX_BLADDERS], ri[HP_MAX_BLADDERS];
} ri_memo;

static void memo_init(ri_memo *mm)
{
    for (int k = 0; k < HP_MAX_BLADDERS; ++k) mm->P[k] = NAN; /* NaN equals nothing */
}

/* Bladder k's inner radius at P (a carrying bladder of h: L < U). */
static hp_error memo_ri(const hp_load_hold_set *h, ri_memo *mm, int k, double P, double *ri)
{
    if (P == h->L[k]) *ri = h->ra[k];
    else if (P == h->U[k]) *ri = h->rc[k];
    else if (P == mm->P[k]) *ri = mm->ri[k];
    else {
        hp_error err = fk_of(h->M, k, P, ri);
        if (err) return err;
        mm->P[k] = P;
        mm->ri[k] = *ri;
    }
    return HP_OK;
}

/* Bladder k's force at P on h (bladder_force's, at the memo's radius). */
static hp_error memo_force(const hp_load_hold_set *h, ri_memo *mm, int k, double P, double *F)
{
    double ri;
    hp_error err = memo_ri(h, mm, k, P, &ri);
    return err ? err : force_at_ri(h->M, k, P, ri, h->rho[k], F);
}

/* The pressures of every bladder at a point before its sum: each at its best pressure that
 * carries nothing (tie_cost overwrites the carrying ones). */
static void point_start(const hp_load_hold_set *h, double *P)
{
    for (int k = 0; k < h->n; ++k) P[k] = fmin(fmax(h->target[k], h->lo[k]), h->L[k]);
}

/* The sum of a point carried on from the carrying bladder *j (the sum so far in *e) while it
 * is below stop; *j gets where it stopped. */
static int point_from(const hp_load_hold_set *h, const double *x, const hp_load_near *nr, int *j,
                      double stop, double *e, double *P, double *R)
{
    for (; *j < h->m && *e < stop; ++*j)
        if (tie_cost(h->M, h->col[*j], h->rho, h->lo, h->L, h->U, h->ra, h->rc, h->Flo, h->Fhi,
                     h->target, x, nr, e, P, R))
            return -1;
    return 0;
}

/* tie_cost over the m carrying-capable bladders col[]; the others at their best pressure
 * that carries nothing (load_solve.h). */
int hpi_load_hold_set_point(const hp_load_hold_set *h, const double *x, double stop, double *e,
                            double *P, double *R)
{
    int j = 0;
    *e = 0.0;
    point_start(h, P);
    return point_from(h, x, NULL, &j, stop, e, P, R);
}

int hpi_load_hold_set_point_near(const hp_load_hold_set *h, const hp_load_near *nr, const double *x,
                                 double *e, double *P, double *R)
{
    int j = 0;
    *e = 0.0;
    point_start(h, P);
    return point_from(h, x, nr, &j, INFINITY, e, P, R);
}

int hpi_load_hold_set_at_pressures(const hp_load_hold_set *h, const double *P, double *x,
                                   double *Pp, double *R)
{
    point_start(h, Pp);
    for (int k = 0; k < h->n; ++k) x[k] = R[k] = 0.0;
    for (int j = 0; j < h->m; ++j) {
        const int k = h->col[j];
        double ri = h->rc[k], F;
        /* At or below L: its least force, Flo (positive when its pressure floor lies above
         * touching: it carries there already), at L and ra, where the set computed Flo. */
        int at_floor = !(P[k] > h->L[k]);
        if (at_floor) {
            x[k] = h->Flo[k];
        } else {
            if (P[k] < h->U[k] && fk_of(h->M, k, P[k], &ri)) return -1;
            if (force_at_ri(h->M, k, P[k], ri, h->rho[k], &F)) return -1;
            x[k] = fmin(fmax(F, h->Flo[k]), h->Fhi[k]);
        }
        /* As tie_cost takes a force: none (the best pressure that carries nothing), the
         * least the bladder carries (L: ra), the most (U: rc), else the pick's own. Past
         * the continue, x > 0 (x >= Flo > 0, or a clamped F > 0). */
        if (x[k] <= 0.0 && h->Flo[k] <= 0.0) continue;
        Pp[k] = at_floor ? h->L[k] : x[k] >= h->Fhi[k] ? h->U[k] : P[k];
        R[k] = at_floor ? h->ra[k] : x[k] >= h->Fhi[k] ? h->rc[k] : ri;
    }
    return 0;
}

/* A point x of the holding set: kept in f when its tie-breaker sum is below *best and, with
 * a test, when the test accepts it (asked only of a point that would win: the sum stops as
 * soon as it cannot). rec (may be NULL) gets the point and its sum as far as it went.
 * 0, or -1 when the model or the test fails. */
static int consider(const hp_load_hold_set *h, hp_load_point_test test, void *ctx, const double *x,
                    double *best, double *f, hp_load_scan_rec *rec)
{
    const int m = h->m, *col = h->col;
    double e = 0.0, P[HP_MAX_BLADDERS], R[HP_MAX_BLADDERS] = {0};
    int j = 0;
    point_start(h, P);
    if (point_from(h, x, NULL, &j, *best, &e, P, R)) return -1;
    if (rec && rec->count++ < HP_LOAD_SCAN_POINTS && m <= HP_LOAD_SCAN_CARRY) {
        const int i = rec->count - 1;
        rec->done[i] = j;
        rec->e[i] = e;
        for (int q = 0; q < m; ++q) {
            rec->x[i][q] = x[col[q]];
            rec->P[i][q] = P[col[q]];
            rec->R[i][q] = R[col[q]];
        }
    }
    if (!(e < *best)) return 0;
    if (test) {
        int ok = test(ctx, x, P, R);
        if (ok < 0) return -1;
        if (!ok) return 0;
    }
    *best = e;
    memcpy(f, x, (size_t)h->n * sizeof *f);
    return 0;
}

/* The holding set written in at most two free forces: Gauss–Jordan elimination with
 * partial pivoting over the bladders that can carry; the free ones are scanned on a
 * grid_n-point grid of their pressures, the others follow (checked against their ranges);
 * then every vertex of the set (the free count of bladders at an end of their force range,
 * the six others solved for). f gets the point with the least tie-breaker sum (tie_cost: a
 * bladder at zero force takes its best pressure that carries nothing); with a test, among
 * the points it accepts only. At most grid_n² + 4·C(8, 2) points. 0 on success, -1 when no
 * point qualifies or the set has more than two free coordinates (more than eight carrying
 * bladders: not scanned). */
static atomic_ulong n_scans, n_vertices;

void hpi_test_scan_counts(unsigned long *scans, unsigned long *vertices)
{
    *scans = atomic_load(&n_scans);
    *vertices = atomic_load(&n_vertices);
}

static int grid_forces(const hp_load_hold_set *h, int grid_n, hp_load_point_test test, void *ctx,
                       double *f, hp_load_scan_rec *rec)
{
    hpi_count(&n_scans, 1);
    if (rec) rec->valid = rec->count = 0;
    const int n = h->n;
    const double *A = h->A, *b = h->b, *L = h->L, *U = h->U, *Flo = h->Flo, *Fhi = h->Fhi;
    const double tol = h->tol;
    const int m = h->m, *col = h->col;
    double E[6][HP_MAX_BLADDERS + 1];
    for (int r = 0; r < 6; ++r) {
        for (int j = 0; j < m; ++j) E[r][j] = A[r * n + col[j]];
        E[r][m] = b[r];
    }
    int pivcol[6], rank = 0, isfree[HP_MAX_BLADDERS] = {0};
    for (int j = 0; j < m && rank < 6; ++j) {
        int pr = rank;
        for (int r = rank + 1; r < 6; ++r)
            if (fabs(E[r][j]) > fabs(E[pr][j])) pr = r;
        if (!(fabs(E[pr][j]) > 1e-12)) { /* no pivot in this column: a free force */
            isfree[j] = 1;
            continue;
        }
        for (int c = 0; c <= m; ++c) {
            double t = E[rank][c];
            E[rank][c] = E[pr][c];
            E[pr][c] = t;
        }
        for (int r = 0; r < 6; ++r) {
            if (r == rank) continue;
            double q = E[r][j] / E[rank][j];
            for (int c = 0; c <= m; ++c) E[r][c] -= q * E[rank][c];
        }
        pivcol[rank++] = j;
    }
    for (int j = 0; j < m; ++j)
        if (!isfree[j]) {
            int piv = 0;
            for (int r = 0; r < rank; ++r) piv |= pivcol[r] == j;
            isfree[j] = !piv;
        }
    int fr[2], nfree = 0;
    for (int j = 0; j < m; ++j)
        if (isfree[j]) {
            if (nfree == 2) return -1;
            fr[nfree++] = j;
        }
    const int g0 = nfree > 0 ? grid_n : 1, g1 = nfree > 1 ? grid_n : 1;
    /* Free bladders on a grid of their pressures, both ends included: the force rises from
     * 0 like (P − P_touch)², so a grid in the forces would leave the cheap pressures near
     * the bottom unvisited. Each grid force once (its ends from the set's radii). */
    double Fg[2][HP_LOAD_SCAN_GRID_MAX];
    int okg[2][HP_LOAD_SCAN_GRID_MAX];
    ri_memo mm;
    memo_init(&mm);
    if (grid_n > HP_LOAD_SCAN_GRID_MAX) return -1;
    for (int q = 0; q < nfree; ++q)
        for (int i = 0; i < grid_n; ++i) {
            int k = col[fr[q]];
            double Pq = L[k] + (double)i / (grid_n - 1) * (U[k] - L[k]), Fq = 0.0;
            okg[q][i] = memo_force(h, &mm, k, Pq, &Fq) == HP_OK;
            Fg[q][i] = fmin(fmax(Fq, Flo[k]), Fhi[k]);
        }
    double best = INFINITY, x[HP_MAX_BLADDERS];
    for (int i0 = 0; i0 < g0; ++i0)
        for (int i1 = 0; i1 < g1; ++i1) {
            for (int k = 0; k < n; ++k) x[k] = 0.0;
            int ok = 1;
            for (int q = 0; q < nfree && ok; ++q) {
                const int i = q ? i1 : i0;
                ok = okg[q][i];
                x[col[fr[q]]] = Fg[q][i];
            }
            for (int r = 0; r < rank && ok; ++r) {
                int j = pivcol[r], k = col[j];
                double v = E[r][m];
                for (int q = 0; q < nfree; ++q) v -= E[r][fr[q]] * x[col[fr[q]]];
                v /= E[r][j];
                ok = v >= Flo[k] - tol && v <= Fhi[k] + tol;
                x[k] = fmin(fmax(v, Flo[k]), Fhi[k]);
            }
            for (int r = rank; r < 6 && ok; ++r) ok = fabs(E[r][m]) <= tol; /* consistent */
            if (ok && consider(h, test, ctx, x, &best, f, rec)) return -1;
        }
    /* The polytope's vertices too (nfree of the carrying bladders at an end of their range,
     * the six others solved for): where the tie-breaker is concave the least sum lies on
     * the boundary, and a dependent force reaching its end is a line the grid only comes
     * near. The elimination above already writes every carrying force as an affine
     * function of the free ones, x_j = g_j0 + g_j1·t_0 + g_j2·t_1, so a vertex is nfree
     * such equations in the t (a 2×2 or 1×1 solve), no factorisation. */
    if (rank == 6 && nfree > 0 && m - nfree == 6) {
        double g[HP_MAX_BLADDERS][3];
        for (int q = 0; q < nfree; ++q) {
            g[fr[q]][0] = 0.0;
            g[fr[q]][1] = q == 0;
            g[fr[q]][2] = q == 1;
        }
        for (int r = 0; r < rank; ++r) {
            int j = pivcol[r];
            g[j][0] = E[r][m] / E[r][j];
            for (int q = 0; q < 2; ++q) g[j][1 + q] = q < nfree ? -E[r][fr[q]] / E[r][j] : 0.0;
        }
        const int nsides = nfree > 1 ? 4 : 2;
        for (int a = 0; a < m; ++a)
            for (int bb = nfree > 1 ? a + 1 : m; bb < (nfree > 1 ? m : m + 1); ++bb) {
                /* The fixed bladders' rows of the map: singular when the two fixed forces
                 * do not determine the free ones (no vertex there). */
                double det = nfree > 1 ? g[a][1] * g[bb][2] - g[a][2] * g[bb][1] : g[a][1];
                double size = nfree > 1 ? fabs(g[a][1] * g[bb][2]) + fabs(g[a][2] * g[bb][1]) : 1.0;
                if (!(fabs(det) > 1e-12 * size)) continue;
                for (int sides = 0; sides < nsides; ++sides) {
                    const int ka = col[a], kb = nfree > 1 ? col[bb] : -1;
                    const double va = sides & 1 ? Fhi[ka] : Flo[ka];
                    const double vb = kb >= 0 ? ((sides >> 1) & 1 ? Fhi[kb] : Flo[kb]) : 0.0;
                    double t0, t1 = 0.0;
                    if (nfree > 1) { /* Cramer's rule */
                        double ea = va - g[a][0], eb = vb - g[bb][0];
                        t0 = (ea * g[bb][2] - g[a][2] * eb) / det;
                        t1 = (g[a][1] * eb - ea * g[bb][1]) / det;
                    } else {
                        t0 = (va - g[a][0]) / det;
                    }
                    hpi_count(&n_vertices, 1);
                    for (int k = 0; k < n; ++k) x[k] = 0.0;
                    int ok = 1;
                    for (int j = 0; j < m && ok; ++j) {
                        int k = col[j];
                        if (k == ka || k == kb) {
                            x[k] = k == ka ? va : vb;
                            continue;
                        }
                        double v = g[j][0] + g[j][1] * t0 + g[j][2] * t1;
                        ok = v >= Flo[k] - tol && v <= Fhi[k] + tol;
                        x[k] = fmin(fmax(v, Flo[k]), Fhi[k]);
                    }
                    if (ok && consider(h, test, ctx, x, &best, f, rec)) return -1;
                }
            }
    }
    if (rec) rec->valid = rec->count <= HP_LOAD_SCAN_POINTS && m <= HP_LOAD_SCAN_CARRY;
    return isfinite(best) ? 0 : -1;
}

int hpi_load_scan_replay(const hp_load_hold_set *h, hp_load_scan_rec *rec, hp_load_point_test test,
                         void *ctx, double *f, double *eb, double *Pb, double *Rb)
{
    const int n = h->n, m = h->m, *col = h->col;
    double best = INFINITY;
    for (int i = 0; i < rec->count; ++i) {
        double x[HP_MAX_BLADDERS] = {0}, P[HP_MAX_BLADDERS], R[HP_MAX_BLADDERS] = {0},
               e = rec->e[i];
        int j = rec->done[i];
        point_start(h, P);
        for (int q = 0; q < m; ++q) {
            x[col[q]] = rec->x[i][q];
            if (q < j) {
                P[col[q]] = rec->P[i][q];
                R[col[q]] = rec->R[i][q];
            }
        }
        /* The test's scan sums a point while it is below its own best, which is never below
         * HOLD's: the sum goes on from where HOLD's stopped, through the same terms. */
        if (j < m && e < best) {
            const int j0 = j;
            if (point_from(h, x, NULL, &j, best, &e, P, R)) return -1;
            rec->done[i] = j;
            rec->e[i] = e;
            for (int q = j0; q < j; ++q) {
                rec->P[i][q] = P[col[q]];
                rec->R[i][q] = R[col[q]];
            }
        }
        if (!(e < best)) continue;
        if (test) {
            int ok = test(ctx, x, P, R);
            if (ok < 0) return -1;
            if (!ok) continue;
        }
        *eb = best = e;
        memcpy(f, x, (size_t)n * sizeof *f);
        memcpy(Pb, P, (size_t)n * sizeof *Pb);
        memcpy(Rb, R, (size_t)n * sizeof *Rb);
    }
    return isfinite(best) ? 0 : -1;
}

/* HOLD from one start: phase 1 projects the start's forces (grid: the best point of
 * grid_forces instead) onto the holding set, phase 2 tie-breaks from there. *cost
 * gets the tie-breaker's sum (P − t)² [Pa²] of the answer when its rows are met (to
 * 1e-11 of the weight), +inf otherwise. */
static hpi_load_solve_status hold_from(const hp_load_hold_set *hs, const double xi[6],
                                       const double *hi, const double *start, int max_iter,
                                       hp_load_nlp_solver nlp_solve, int stiffness, int grid,
                                       double *P, double *F, int *iterations, int *raw,
                                       double *cost, hp_load_scan_rec *rec)
{
    *cost = INFINITY;
    const hp_load_model *M = hs->M;
    const int n = hs->n;
    const double *lo = hs->lo, *target = hs->target;
    const double *rho = hs->rho, *A = hs->A, *b = hs->b, *L = hs->L, *U = hs->U, *Flo = hs->Flo,
                 *Fhi = hs->Fhi, *Pt = hs->Pt;
    const double fscale = hs->fscale, tol = hs->tol;
    /* Phase 1, in the forces: the point of {A·F = b, Flo <= F <= Fhi} nearest to the
     * forces of the starting pressures (each force scaled by its range). The constraints are
     * linear, so this decides reachability exactly. */
    double f[HP_MAX_BLADDERS], lam[6] = {0};
    ri_memo mm;
    memo_init(&mm);
    {
        double h[HP_MAX_BLADDERS], g[HP_MAX_BLADDERS], l[HP_MAX_BLADDERS], u[HP_MAX_BLADDERS],
            d[HP_MAX_BLADDERS], c[6];
        for (int k = 0; k < n; ++k) {
            double p0 = start ? start[k] : 0.5 * (L[k] + U[k]), F0;
            p0 = fmin(fmax(p0, L[k]), U[k]);
            f[k] = 0.0;
            /* (the grid's start replaces these forces) */
            if (!grid && L[k] < U[k] && memo_force(hs, &mm, k, p0, &F0) == HP_OK)
                f[k] = fmin(fmax(F0, Flo[k]), Fhi[k]);
            double Fs = fmax(Fhi[k], 1e-6);
            h[k] = 1.0 / (Fs * Fs);
            g[k] = 0.0;
            l[k] = Flo[k] - f[k];
            u[k] = Fhi[k] - f[k];
        }
        if (grid && grid_forces(hs, GRID_N, NULL, NULL, f, rec) != 0)
            return HP_LOAD_SOLVE_UNREACHABLE;
        for (int k = 0; k < n; ++k) {
            l[k] = Flo[k] - f[k];
            u[k] = Fhi[k] - f[k];
        }
        for (int r = 0; r < 6; ++r) {
            c[r] = -b[r];
            for (int k = 0; k < n; ++k) c[r] += A[r * n + k] * f[k];
        }
        if (hpi_load_qp_solve(n, A, c, h, g, l, u, tol, 200, lam, d, NULL) != HP_LOAD_QP_OPTIMAL)
            return HP_LOAD_SOLVE_UNREACHABLE;
        for (int k = 0; k < n; ++k) f[k] = fmin(fmax(f[k] + d[k], Flo[k]), Fhi[k]);
    }
    /* Phase 2, in the pressures (kPa): SQP on ½·sum (P − t)² subject to A·F(P) = b with the
     * exact Lagrangian Hessian 1 + (Aᵀλ)_k·F''_k (clamped positive), an l1 merit line
     * search, and the box [L, U] in every QP. */
    double p[HP_MAX_BLADDERS];
    for (int k = 0; k < n; ++k) {
        p[k] = L[k];
        if (L[k] < U[k] && pressure_of_force_in(M, k, rho[k], L[k], U[k],
                                                (radius_bracket){hs->ra[k], hs->rc[k], 0.0, Fhi[k]},
                                                Fhi[k], f[k], &p[k], NULL))
            return HP_LOAD_SOLVE_ERROR;
    }
    memset(lam, 0, sizeof lam);
    int it = 0;
    double Fk[HP_MAX_BLADDERS], F1[HP_MAX_BLADDERS], F2[HP_MAX_BLADDERS], c[6];
    if (nlp_solve) { /* a general-purpose solver's tie-breaker (the backend's) */
        hp_load_hold_nlp nlp = {M, n, rho, A, b, L, U, target, xi, stiffness};
        hpi_load_solve_status st = nlp_solve(&nlp, p, max_iter, &it, raw);
        if (st != HP_LOAD_SOLVE_OK) return st;
    }
    for (; !nlp_solve; ++it) {
        for (int k = 0; k < n; ++k) {
            bstate s;
            Fk[k] = F1[k] = F2[k] = 0.0;
            if (!(L[k] < U[k])) continue;
            double ri;
            if (memo_ri(hs, &mm, k, p[k], &ri) || bladder_state_ri(M, k, p[k], ri, rho[k], &s))
                return HP_LOAD_SOLVE_ERROR;
            Fk[k] = fmax(s.F, 0.0);
            F1[k] = s.FP * 1e3; /* N per kPa */
            F2[k] = s.FPP * 1e6;
        }
        double cmax = 0.0;
        for (int r = 0; r < 6; ++r) {
            c[r] = -b[r];
            for (int k = 0; k < n; ++k) c[r] += A[r * n + k] * Fk[k];
            cmax = fmax(cmax, fabs(c[r]));
        }
        if (it >= max_iter) break;
        double h[HP_MAX_BLADDERS], g[HP_MAX_BLADDERS], l[HP_MAX_BLADDERS], u[HP_MAX_BLADDERS],
            d[HP_MAX_BLADDERS], Mx[6 * HP_MAX_BLADDERS];
        for (int k = 0; k < n; ++k) {
            double al = 0.0;
            for (int r = 0; r < 6; ++r) al += A[r * n + k] * lam[r];
            h[k] = fmin(fmax(1.0 + al * F2[k], 0.1), 1e3);
            g[k] = -(p[k] - target[k]) * 1e-3 / h[k];
            l[k] = (L[k] - p[k]) * 1e-3;
            u[k] = (U[k] - p[k]) * 1e-3;
            if (!(L[k] < U[k])) l[k] = u[k] = 0.0;
            for (int r = 0; r < 6; ++r) Mx[r * n + k] = A[r * n + k] * F1[k];
        }
        double lam_new[6];
        memcpy(lam_new, lam, sizeof lam_new);
        if (hpi_load_qp_solve(n, Mx, c, h, g, l, u, tol, 200, lam_new, d, NULL) !=
            HP_LOAD_QP_OPTIMAL)
            break; /* keep the current point: the planner checks its equilibrium */
        double dmax = 0.0, nu = 1.0, phi = 0.0, slope = 0.0;

        for (int r = 0; r < 6; ++r) nu = fmax(nu, 2.0 * fabs(lam_new[r]));
        for (int k = 0; k < n; ++k) {
            double e = (p[k] - target[k]) * 1e-3;
            dmax = fmax(dmax, fabs(d[k]));
            phi += 0.5 * e * e;
            slope += e * d[k];
        }
        double csum = 0.0;
        for (int r = 0; r < 6; ++r) csum += fabs(c[r]);
        double merit = phi + nu * csum, t = 1.0, pn[HP_MAX_BLADDERS];
        /* Directional derivative of the l1 merit along d (the QP step cancels c). */
        double dmerit = slope - nu * csum;
        for (int ls = 0; ls < 30; ++ls, t *= 0.5) {
            double phin = 0.0, cn = 0.0, cr[6];
            int okk = 1;
            for (int k = 0; k < n; ++k) {
                pn[k] = fmin(fmax(p[k] + t * d[k] * 1e3, L[k]), U[k]);
                double e = (pn[k] - target[k]) * 1e-3;
                phin += 0.5 * e * e;
            }
            for (int r = 0; r < 6; ++r) cr[r] = -b[r];
            for (int k = 0; k < n && okk; ++k) {
                double Fn;
                if (!(L[k] < U[k])) continue;
                if (memo_force(hs, &mm, k, pn[k], &Fn)) okk = 0;
                else
                    for (int r = 0; r < 6; ++r) cr[r] += A[r * n + k] * fmax(Fn, 0.0);
            }
            for (int r = 0; r < 6; ++r) cn += fabs(cr[r]);
            if (okk && (phin + nu * cn <= merit + 1e-4 * t * dmerit || dmax * t < 1e-10)) break;
        }
        memcpy(p, pn, (size_t)n * sizeof *p);
        memcpy(lam, lam_new, sizeof lam);
        /* 1e-9 kPa (a micropascal): the steps' rounding noise is ~1e-11 kPa. */
        if (dmax * t <= 1e-9 && cmax <= tol) break;
    }
    int feasible = 1;
    for (int k = 0; k < n; ++k) {
        double Fk0;
        f[k] = 0.0;
        if (!(L[k] < U[k])) continue;
        if (memo_force(hs, &mm, k, p[k], &Fk0)) return HP_LOAD_SOLVE_ERROR;
        f[k] = fmax(Fk0, 0.0);
    }
    if (iterations) *iterations = it;
    if (!feasible) return HP_LOAD_SOLVE_UNREACHABLE;
    for (int k = 0; k < n; ++k) {
        F[k] = f[k];
        P[k] = p[k];
        /* A force below what the rows resolve is no force: the bladder then takes the
         * tie-breaker's pressure among those that carry nothing, instead of the touching
         * pressure. The answer's rows are accepted to 1e-11 of the weight (below), so a force
         * of at most 1e-12 of it moves them by less than that: the SQP, stopped by its budget
         * (rows never met to 1e-13) on the tests' default load layout, left a bladder 4e-9 Pa
         * above its carrying bound with 1.5e-12 N (1.7e-13 of the weight) as a CLOSEST
         * answer that named no binding limit. */
        if (f[k] <= 1e-12 * fmax(1.0, fscale) || !(L[k] < U[k])) {
            double top = fmin(hi[k], fmax(0.0, Pt[k]));
            P[k] = fmin(fmax(target[k], lo[k]), fmax(lo[k], top));
            F[k] = 0.0;
        }
    }
    double cm = 0.0, e = 0.0;
    for (int r = 0; r < 6; ++r) {
        double v = -b[r];
        for (int k = 0; k < n; ++k) v += A[r * n + k] * F[k];
        cm = fmax(cm, fabs(v));
    }
    for (int k = 0; k < n; ++k) e += (P[k] - target[k]) * (P[k] - target[k]);
    if (cm <= 1e-11 * fmax(1.0, fscale)) *cost = e;
    return HP_LOAD_SOLVE_OK;
}

/* HOLD for the distance tie-breakers, global. At a fixed pose the holding forces form a
 * polytope (six rows on n boxes) and sum (P(F) − t)² is separable but not convex in F:
 * P(F)² curves down near a bladder's touching pressure (d²/dF² has the sign of
 * F' − P·F'', negative where the contact area starts from 0), so an SQP can stop in a
 * local minimum that differs from the global one in which bladders carry. Worse, a bladder
 * whose touching pressure is positive costs at least that pressure squared while it carries
 * and (almost) nothing once it stops (any pressure below touching holds nothing): the sum
 * jumps where a force reaches 0, which no SQP step in the carrying range sees. With at
 * most eight bladders and six rows the polytope is at most two-dimensional, so it is
 * scanned: grid_forces evaluates the true sum at its vertices (where forces reach 0 or
 * their top) and on a small grid, and HOLD runs from the best of those points as well as
 * from the caller's start; the smaller sum wins (only answers whose rows are met compete).
 * Reachability is decided by the first start's exact phase 1. */
static hpi_load_solve_status hold_core(const hp_load_model *M, const double xi[6], const double *lo,
                                       const double *hi, const double *target, const double *start,
                                       int max_iter, hp_load_nlp_solver nlp_solve, int stiffness,
                                       double *P, double *F, int *iterations, int *raw,
                                       hp_load_hold_set *keep, hp_load_scan_rec *rec)
{
    double cost;
    int it = 0;
    /* Both starts work on one holding set (the caller's, when it keeps it). */
    hp_load_hold_set own, *hs = keep ? keep : &own;
    if (rec) rec->valid = 0;
    hpi_load_solve_status st = hpi_load_hold_set_at(M, xi, lo, hi, target, hs);
    if (st == HP_LOAD_SOLVE_OK)
        st = hold_from(hs, xi, hi, start, max_iter, nlp_solve, stiffness, 0, P, F, &it, raw, &cost,
                       NULL);
    int total = it;
    if (st == HP_LOAD_SOLVE_OK && max_iter > 0 && !stiffness) {
        const int n = M->layout.n;
        double Pk[HP_MAX_BLADDERS], Fk[HP_MAX_BLADDERS], ck;
        int rk = 0;
        it = 0;
        if (hold_from(hs, xi, hi, start, max_iter, nlp_solve, 0, 1, Pk, Fk, &it, &rk, &ck, rec) ==
                HP_LOAD_SOLVE_OK &&
            ck < cost * (1.0 - 1e-12)) {
            memcpy(P, Pk, (size_t)n * sizeof *P);
            memcpy(F, Fk, (size_t)n * sizeof *F);
            if (raw) *raw = rk;
        }
        total += it;
    }
    if (iterations) *iterations = total;
    return st;
}

hpi_load_solve_status hpi_load_hold(const hp_load_model *M, const double xi[6], const double *lo,
                                    const double *hi, const double *target, const double *start,
                                    int max_iter, double *P, double *F, int *iterations)
{
    return hold_core(M, xi, lo, hi, target, start, max_iter, NULL, 0, P, F, iterations, NULL, NULL,
                     NULL);
}

hpi_load_solve_status hpi_load_hold_keep(const hp_load_model *M, const double xi[6],
                                         const double *lo, const double *hi, const double *target,
                                         const double *start, int max_iter, double *P, double *F,
                                         int *iterations, hp_load_hold_set *hs,
                                         hp_load_scan_rec *rec)
{
    return hold_core(M, xi, lo, hi, target, start, max_iter, NULL, 0, P, F, iterations, NULL, hs,
                     rec);
}

hpi_load_solve_status hpi_load_hold_with(hp_load_nlp_solver nlp_solve, const hp_load_model *M,
                                         const double xi[6], const double *lo, const double *hi,
                                         const double *target, const double *start, int max_iter,
                                         int stiffness, double *P, double *F, int *iterations,
                                         int *raw)
{
    return hold_core(M, xi, lo, hi, target, start, max_iter, nlp_solve, stiffness, P, F, iterations,
                     raw, NULL, NULL);
}

int hpi_load_hold_set_scan(const hp_load_hold_set *h, int grid_n, hp_load_point_test test,
                           void *ctx, double *f)
{
    return grid_forces(h, grid_n, test, ctx, f, NULL);
}

hp_error hpi_load_bladder_stiff(const hp_load_model *M, int k, double P, double rho, double a[3])
{
    double ri, ro, o1, o2;
    hp_error err = fk_of(M, k, P, &ri);
    if (!err) err = radius_chain(M, k, ri, &ro, &o1, &o2);
    if (err) return err;
    hp_claw c;
    hpi_load_claw_drho(M, k, P, ro, rho, &c);
    along_p(&c, o1, o2, &a[0], &a[1], &a[2]);
    for (int i = 0; i < 3; ++i) a[i] = -a[i];
    return HP_OK;
}

hp_error hpi_load_bladder_force(const hp_load_model *M, int k, double P, double rho, double *F,
                                double *dF, double *d2F)
{
    if (!dF && !d2F) return bladder_force(M, k, P, rho, F);
    bstate s;
    hp_error err = bladder_state(M, k, P, rho, &s);
    if (err) return err;
    *F = s.F;
    if (dF) *dF = s.FP;
    if (d2F) *d2F = s.FPP;
    return HP_OK;
}

/* Rest of pressures p from xi (forward statics) and the rest's sensitivity G = dxi/dP
 * = K⁻¹·dQ/dP (6×n, scaled: mm or degrees per kPa), by the implicit function theorem. */
static int rest_and_sensitivity(const hp_load_model *M, const double *p, double xi[6], double *G)
{
    const int n = M->layout.n;
    if (hp_load_rest(M, p, xi, xi, NULL) != HP_OK) return -1;
    double ro[HP_MAX_BLADDERS], dro[HP_MAX_BLADDERS], Q[6], dX[36], dP[6 * HP_MAX_BLADDERS];
    if (hpi_load_radii(M, p, ro, dro) != HP_OK ||
        hpi_load_eval_radii(M, xi, p, ro, dro, 1, Q, dX, dP, NULL, NULL) != HP_OK)
        return -1;
    /* K_s = −S dQ/dxi S (scaled, symmetric); K_s·dxi_s = S·dQ/dP·dP. */
    double K[36];
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
            K[i * 6 + j] = -0.5 * (dX[i * 6 + j] + dX[j * 6 + i]) * hpi_load_unit(i) *
                           hpi_load_unit(j);
    double F[36];
    memcpy(F, K, sizeof F);
    /* A saddle (K indefinite) still has a well-defined sensitivity: solve by Gaussian
     * elimination with partial pivoting rather than Cholesky. */
    double B[6 * HP_MAX_BLADDERS];
    for (int i = 0; i < 6; ++i)
        for (int k = 0; k < n; ++k) B[i * n + k] = dP[i * n + k] * hpi_load_unit(i) * 1e3;
    for (int c = 0; c < 6; ++c) {
        int piv = c;
        for (int r = c + 1; r < 6; ++r)
            if (fabs(F[r * 6 + c]) > fabs(F[piv * 6 + c])) piv = r;
        if (!(fabs(F[piv * 6 + c]) > 0)) return -1;
        if (piv != c) {
            for (int j = 0; j < 6; ++j) {
                double t = F[c * 6 + j];
                F[c * 6 + j] = F[piv * 6 + j];
                F[piv * 6 + j] = t;
            }
            for (int k = 0; k < n; ++k) {
                double t = B[c * n + k];
                B[c * n + k] = B[piv * n + k];
                B[piv * n + k] = t;
            }
        }
        for (int r = c + 1; r < 6; ++r) {
            double f = F[r * 6 + c] / F[c * 6 + c];
            for (int j = c; j < 6; ++j) F[r * 6 + j] -= f * F[c * 6 + j];
            for (int k = 0; k < n; ++k) B[r * n + k] -= f * B[c * n + k];
        }
    }
    for (int r = 5; r >= 0; --r)
        for (int k = 0; k < n; ++k) {
            double v = B[r * n + k];
            for (int j = r + 1; j < 6; ++j) v -= F[r * 6 + j] * G[j * n + k];
            G[r * n + k] = v / F[r * 6 + r];
        }
    return 0;
}

static double pose_cost(const double xi[6], const double desired[6], const double W[6])
{
    double c = 0.0;
    for (int j = 0; j < 6; ++j) {
        double e = (xi[j] - desired[j]) / hpi_load_unit(j);
        c += 0.5 * W[j] * e * e;
    }
    return c;
}

hpi_load_solve_status hpi_load_pose(const hp_load_model *M, const double desired[6],
                                    const double W[6], const double *lo, const double *hi,
                                    const double xi0[6], const double *P0, int max_iter,
                                    double xi[6], double *P, int *iterations)
{
    /* Every iterate is an equilibrium: the pressures are the unknowns and the pose is their
     * rest (forward statics). Gauss–Newton on the weighted pose error with the box on the
     * pressures, each step a QP in (e, dP): minimise ½eᵀWe + ½mu|dP|² subject to
     * e − G·dP = xi − desired; mu is Levenberg's damping (raised when a step fails). */
    const int n = M->layout.n;
    double x[6], p[HP_MAX_BLADDERS] = {0}, G[6 * HP_MAX_BLADDERS];
    memcpy(x, xi0, sizeof x);
    for (int k = 0; k < n; ++k) p[k] = fmin(fmax(P0[k], lo[k]), hi[k]);
    if (rest_and_sensitivity(M, p, x, G) != 0) {
        /* The starting pressures do not hold the head: start from the middle of each
         * bladder's carrying range, then from the top. */
        int ok = 0;
        for (int attempt = 0; attempt < 2 && !ok; ++attempt) {
            for (int k = 0; k < n; ++k)
                p[k] = attempt == 0 ? 0.5 * (fmax(lo[k], 0.0) + hi[k]) : hi[k];
            memset(x, 0, sizeof x);
            ok = rest_and_sensitivity(M, p, x, G) == 0;
        }
        if (!ok) return HP_LOAD_SOLVE_UNREACHABLE;
    }
    double cost = pose_cost(x, desired, W), mu = 1e-6;
    int it = 0;
    hpi_load_solve_status st = HP_LOAD_SOLVE_ITERATION_LIMIT;
    for (; it < max_iter; ++it) {
        /* The step's QP in dP alone (kPa): e = (xi − desired) + G·dP eliminated. */
        double H[HP_MAX_BLADDERS * HP_MAX_BLADDERS], g[HP_MAX_BLADDERS], l[HP_MAX_BLADDERS],
            u[HP_MAX_BLADDERS], d[HP_MAX_BLADDERS], r[6];
        for (int j = 0; j < 6; ++j) r[j] = (x[j] - desired[j]) / hpi_load_unit(j);
        for (int a = 0; a < n; ++a) {
            g[a] = 0.0;
            for (int j = 0; j < 6; ++j) g[a] += G[j * n + a] * W[j] * r[j];
            for (int b = 0; b < n; ++b) {
                double v = a == b ? mu : 0.0;
                for (int j = 0; j < 6; ++j) v += G[j * n + a] * W[j] * G[j * n + b];
                H[a * n + b] = v;
            }
            l[a] = (lo[a] - p[a]) * 1e-3;
            u[a] = (hi[a] - p[a]) * 1e-3;
        }
        if (hpi_load_box_qp(n, H, g, l, u, 4 * n + 20, d) != 0) return HP_LOAD_SOLVE_ERROR;
        double pn[HP_MAX_BLADDERS], xn[6], Gn[6 * HP_MAX_BLADDERS], dmax = 0.0;
        for (int k = 0; k < n; ++k) {
            pn[k] = fmin(fmax(p[k] + d[k] * 1e3, lo[k]), hi[k]);
            dmax = fmax(dmax, fabs(pn[k] - p[k]));
        }
        if (dmax <= 1e-9) { /* Pa: the pressures no longer move */
            st = HP_LOAD_SOLVE_OK;
            break;
        }
        memcpy(xn, x, sizeof xn);
        double cn = INFINITY;
        if (rest_and_sensitivity(M, pn, xn, Gn) == 0) cn = pose_cost(xn, desired, W);
        if (cn <= cost) {
            int small = cost - cn <= 1e-15 * (1.0 + cost);
            memcpy(p, pn, (size_t)n * sizeof *p);
            memcpy(x, xn, sizeof x);
            memcpy(G, Gn, (size_t)(6 * n) * sizeof *G);
            cost = cn;
            mu = fmax(mu * 0.3, 1e-12);
            if (small && dmax <= 1e-3) {
                st = HP_LOAD_SOLVE_OK;
                ++it;
                break;
            }
        } else {
            mu *= 10.0;
            if (mu > 1e12) {
                st = HP_LOAD_SOLVE_OK; /* no step improves: a local minimum */
                break;
            }
        }
    }
    if (iterations) *iterations = it;
    memcpy(xi, x, sizeof x);
    memcpy(P, p, (size_t)n * sizeof *P);
    return st;
}

int hpi_load_hold_vars(const hp_load_hold_nlp *nlp, const double *p, int *idx, double *xl,
                       double *xu, double *x)
{
    int nf = 0;
    for (int k = 0; k < nlp->n; ++k)
        if (nlp->L[k] < nlp->U[k]) {
            xl[nf] = nlp->L[k] * 1e-3;
            xu[nf] = nlp->U[k] * 1e-3;
            x[nf] = fmin(fmax(p[k] * 1e-3, xl[nf]), xu[nf]);
            idx[nf++] = k;
        }
    return nf;
}

void hpi_load_hold_answer(const hp_load_hold_nlp *nlp, const double *x, const int *idx, int nf,
                          double *p)
{
    for (int j = 0; j < nf; ++j) p[idx[j]] = fmin(fmax(x[j] * 1e3, nlp->L[idx[j]]), nlp->U[idx[j]]);
}
