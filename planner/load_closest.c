/* CLOSEST: the held pose nearest to the desired one, as one program in the pose and the
 * contact forces (see load_solve.h).
 *
 * At a pose xi, bladder k can carry any force between Flo_k(rho_k) and Fhi_k(rho_k): the
 * forces at the ends of its carrying pressures [max(lo, 0, touching), min(hi, indentation
 * edge)] (the force rises monotonically with the pressure there). Writing its force as
 * F_k = Flo_k + s_k·(Fhi_k − Flo_k) with s_k in [0, 1] makes every limit a box, and the
 * problem
 *     minimise ½·sum_i W_i·(xi_i − desired_i)²  over (xi, s) in R⁶ × [0, 1]ⁿ
 *     subject to c(xi, s) = sum_k F_k·J_k(xi) + Q_grav(xi) = 0
 * is solved by SQP: each step's QP keeps the separable objective (W on the pose, a small
 * proximal weight on s), linearises the six equilibrium rows exactly (the contact
 * distance's Jacobian and Hessian, the force ranges' derivatives in rho), bounds the pose
 * step by a trust region, and is solved by load_qp.c; an l1 merit line search accepts it.
 * The equilibrium is linear in s, so the only curvature the QP leaves out is the
 * geometry's. The answer is checked by the caller (HOLD at the pose, then the two
 * equilibrium checks). No allocation. */
#include "planner/load_solve.h"
#include "common/units.h"
#include "kinematics/kin_geom.h"
#include "kinematics/contact_law.h"
#include "kinematics/load_internal.h"
#include "planner/load_qp.h"
#include "common/test_count.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

/* The proximal weight on the force fractions s: keeps the QP strictly convex where the
 * pose alone decides the step, small against W (1 per mm²) so it does not steer it. */
#define S_PROX 1e-4
/* Initial and smallest trust region of the pose step [mm, degrees]. */
#define TRUST0 2.0
#define TRUST_MIN 1e-9
/* The l1 merit's smallest weight on the rows [mm² per N]: large, so that from a start that
 * does not hold the head the restoration steps (which move away from the desired pose) are
 * accepted; at a held start it only makes the line search stricter about the rows. */
#define NU0 1e3

typedef struct frange {
    double lo, hi;   /* [N] the force range at this rho */
    double dlo, dhi; /* [N/m] their derivatives in rho */
} frange;

static atomic_ulong n_solves, n_evals, n_radii;

void hpi_test_closest_counts(unsigned long *solves, unsigned long *evals, unsigned long *radii)
{
    *solves = atomic_load(&n_solves);
    *evals = atomic_load(&n_evals);
    *radii = atomic_load(&n_radii);
}

/* hp_load_radius (the bladder's forward kinematics: an iterative solve), counted. */
static hp_error radius(const hp_load_model *M, int k, double P, double *ro, double *dro)
{
    hpi_count(&n_radii, 1);
    return hp_load_radius(M, k, P, ro, dro);
}

/* The free outer radii at a bladder's pressure bounds: they do not move with the pose, so a
 * CLOSEST solve asks them once (the status too: an end whose radius fails fails the range
 * only where it is used). */
typedef struct bound_radii {
    double lo, hi;
    hp_error elo, ehi;
} bound_radii;

static void bound_radii_at(const hp_load_model *M, int k, double plo, double phi, bound_radii *b)
{
    b->lo = b->hi = NAN;
    b->elo = plo > 0 ? radius(M, k, plo, &b->lo, NULL) : HP_ERR_INVALID; /* used only then */
    b->ehi = radius(M, k, phi, &b->hi, NULL);
}

/* Bladder k's carrying force range at contact distance rho inside [plo, phi] and the
 * indentation range (br: the free radii at plo and phi). 0 on success, -1 when the model
 * fails, 1 when no pressure in the bounds is inside the indentation range (its lowest
 * pressure already carries beyond it). */
static int force_range(const hp_load_model *M, int k, double rho, double plo, double phi,
                       const bound_radii *br, frange *r)
{
    memset(r, 0, sizeof *r);
    const double c = 1.0 - HP_LOAD_INDENT_MAX;
    double Pt = hpi_load_touch_pressure(M, k, rho), Pi = hpi_load_indent_pressure(M, k, rho);
    if (plo > 0 && plo > Pt && plo > Pi) return 1;
    double L = fmax(plo, fmax(0.0, Pt)), U = fmin(phi, Pi);
    if (!(L < U)) return 0;
    double ro, dro;
    if (plo > 0 && plo > Pt) { /* the lowest pressure already carries */
        if (br->elo != HP_OK) return -1;
        ro = br->lo;
        hp_claw lo;
        hpi_load_claw_to(M, k, plo, ro, rho, HP_CLAW_GRADIENT, &lo);
        r->lo = lo.F;
        r->dlo = lo.d[HP_CLAW_RHO];
    }
    if (U == phi) {
        if (br->ehi != HP_OK) return -1;
        ro = br->hi;
        hp_claw hi;
        hpi_load_claw_to(M, k, phi, ro, rho, HP_CLAW_GRADIENT, &hi);
        r->hi = hi.F;
        r->dhi = hi.d[HP_CLAW_RHO];
    } else { /* at the indentation edge: ro = rho/c and P = Pi(rho), both moving with rho */
        if (radius(M, k, U, &ro, &dro) != HP_OK || !(dro > 0)) return -1;
        double dPi = 1.0 / (c * dro);
        hp_claw e;
        hpi_load_claw_to(M, k, U, rho / c, rho, HP_CLAW_GRADIENT, &e);
        r->hi = e.F;
        r->dhi = e.d[HP_CLAW_P] * dPi + e.d[HP_CLAW_RO] / c + e.d[HP_CLAW_RHO];
    }
    if (r->hi < r->lo) r->hi = r->lo;
    return 0;
}

typedef struct cl_ctx {
    const hp_load_model *M;
    const double *lo, *hi;
    int n;
    bound_radii br[HP_MAX_BLADDERS];
} cl_ctx;

/* The equilibrium rows c (weighted, N) at scaled pose y (mm, degrees) and fractions s, and
 * when Cy is not NULL their Jacobians Cy (6×6, per mm or degree) and Cs (6×n). F gets the
 * forces (may be NULL). 0 on success, -1 outside the model's domain or when it fails. */
static int cl_eval(const cl_ctx *C, const double y[6], const double *s, double c[6], double *Cy,
                   double *Cs, double *F)
{
    const hp_load_model *M = C->M;
    const int n = C->n;
    hpi_count(&n_evals, 1);
    double xi[6], rho[HP_MAX_BLADDERS], J[6 * HP_MAX_BLADDERS], H[36 * HP_MAX_BLADDERS];
    for (int i = 0; i < 6; ++i) xi[i] = y[i] * hpi_load_unit(i);
    if (hpi_contact_eval_g(&M->layout, &M->geom, M->level, xi, rho, J, Cy ? H : NULL) != HP_OK ||
        hpi_load_domain(M, rho) != HP_OK)
        return -1;
    double Qg[6], dQg[36];
    hpi_load_gravity(M, xi, Qg, Cy ? dQg : NULL, NULL);
    double q[6], D[36];
    memcpy(q, Qg, sizeof q);
    if (Cy) memcpy(D, dQg, sizeof D);
    for (int k = 0; k < n; ++k) {
        frange r;
        if (force_range(M, k, rho[k], C->lo[k], C->hi[k], &C->br[k], &r) != 0) return -1;
        double Fk = r.lo + s[k] * (r.hi - r.lo), dF = r.dlo + s[k] * (r.dhi - r.dlo);
        const double *Jk = J + 6 * k;
        if (F) F[k] = Fk;
        for (int i = 0; i < 6; ++i) q[i] += Fk * Jk[i];
        if (Cy) {
            for (int i = 0; i < 6; ++i) {
                for (int j = 0; j < 6; ++j)
                    D[i * 6 + j] += Fk * H[k * 36 + i * 6 + j] + dF * Jk[i] * Jk[j];
                Cs[i * n + k] = (r.hi - r.lo) * Jk[i] * hpi_load_row_weight(i);
            }
        }
    }
    for (int i = 0; i < 6; ++i) {
        c[i] = q[i] * hpi_load_row_weight(i);
        if (Cy)
            for (int j = 0; j < 6; ++j)
                Cy[i * 6 + j] = D[i * 6 + j] * hpi_load_row_weight(i) * hpi_load_unit(j);
    }
    return 0;
}

static double objective(const double y[6], const double yd[6], const double W[6])
{
    double f = 0.0;
    for (int i = 0; i < 6; ++i) f += 0.5 * W[i] * (y[i] - yd[i]) * (y[i] - yd[i]);
    return f;
}

static double l1(const double c[6])
{
    return fabs(c[0]) + fabs(c[1]) + fabs(c[2]) + fabs(c[3]) + fabs(c[4]) + fabs(c[5]);
}

hpi_load_solve_status hpi_load_closest(const hp_load_model *M, const double desired[6],
                                       const double W[6], const double *lo, const double *hi,
                                       const double xi0[6], const double *F0, int max_iter,
                                       double xi[6], int *iterations)
{
    const int n = M->layout.n, nv = 6 + n;
    hpi_count(&n_solves, 1);
    cl_ctx C;
    C.M = M;
    C.lo = lo;
    C.hi = hi;
    C.n = n;
    for (int k = 0; k < n; ++k) bound_radii_at(M, k, lo[k], hi[k], &C.br[k]);
    double y[6], yd[6], s[HP_MAX_BLADDERS], rho[HP_MAX_BLADDERS];
    for (int i = 0; i < 6; ++i) {
        y[i] = xi0[i] / hpi_load_unit(i);
        yd[i] = desired[i] / hpi_load_unit(i);
    }
    if (hpi_contact_eval_g(&M->layout, &M->geom, M->level, xi0, rho, NULL, NULL) != HP_OK)
        return HP_LOAD_SOLVE_ERROR;
    for (int k = 0; k < n; ++k) {
        frange r;
        if (force_range(M, k, rho[k], lo[k], hi[k], &C.br[k], &r) != 0) return HP_LOAD_SOLVE_ERROR;
        s[k] = !F0 ? 0.5 : r.hi > r.lo ? fmin(fmax((F0[k] - r.lo) / (r.hi - r.lo), 0.0), 1.0) : 0.0;
    }
    double c[6], Cy[36], Cs[6 * HP_MAX_BLADDERS];
    if (cl_eval(&C, y, s, c, NULL, NULL, NULL) != 0) return HP_LOAD_SOLVE_ERROR;
    /* Rounding of the weighted rows: forces of ~10 N summed over eight bladders. */
    const double tol = 1e-11;
    double lam[6] = {0}, nu = NU0, trust = TRUST0;
    int it = 0, converged = 0;
    for (; it < max_iter && !converged; ++it) {
        if (cl_eval(&C, y, s, c, Cy, Cs, NULL) != 0) return HP_LOAD_SOLVE_ERROR;
        double A[6 * HP_LOAD_QP_NMAX], h[HP_LOAD_QP_NMAX], g[HP_LOAD_QP_NMAX], l[HP_LOAD_QP_NMAX],
            u[HP_LOAD_QP_NMAX], d[HP_LOAD_QP_NMAX];
        for (int r = 0; r < 6; ++r) {
            for (int j = 0; j < 6; ++j) A[r * nv + j] = Cy[r * 6 + j];
            for (int k = 0; k < n; ++k) A[r * nv + 6 + k] = Cs[r * n + k];
        }
        for (int j = 0; j < 6; ++j) {
            h[j] = W[j];
            g[j] = yd[j] - y[j];
            l[j] = -trust;
            u[j] = trust;
        }
        for (int k = 0; k < n; ++k) {
            h[6 + k] = S_PROX;
            g[6 + k] = 0.0;
            l[6 + k] = -s[k];
            u[6 + k] = 1.0 - s[k];
        }
        /* The linearised rows, asked to vanish; where they cannot inside the box (a start
         * that does not hold the head, or a trust region too small), asked only to shrink
         * to a fraction of the residual (a restoration step), then the trust region shrinks. */
        double lam_new[6], red = 1.0, ce[6];
        int solved = 0;
        for (int relax = 0; relax < 8 && !solved; ++relax) {
            red = 1.0 / (double)(1 << relax); /* the part of the residual removed: 1, ½, ¼, ... */
            for (int r = 0; r < 6; ++r) ce[r] = red * c[r];
            memcpy(lam_new, lam, sizeof lam);
            solved = hpi_load_qp_solve(nv, A, ce, h, g, l, u, 1e-13, 200, lam_new, d, NULL) ==
                     HP_LOAD_QP_OPTIMAL;
        }
        if (!solved) {
            trust *= 0.25;
            if (trust < TRUST_MIN) break;
            continue;
        }
        for (int r = 0; r < 6; ++r) nu = fmax(nu, 2.0 * fabs(lam_new[r]));
        double f0 = objective(y, yd, W), m0 = f0 + nu * l1(c), slope = -red * nu * l1(c),
               dmax = 0.0;
        for (int j = 0; j < 6; ++j) slope += W[j] * (y[j] - yd[j]) * d[j];
        for (int v = 0; v < nv; ++v) dmax = fmax(dmax, fabs(d[v]));
        if (dmax <= 1e-12 && l1(c) <= tol) {
            converged = 1;
            break;
        }
        double t = 1.0, yn[6], sn[HP_MAX_BLADDERS], cn[6];
        int accepted = 0;
        for (int ls = 0; ls < 40; ++ls, t *= 0.5) {
            for (int j = 0; j < 6; ++j) yn[j] = y[j] + t * d[j];
            for (int k = 0; k < n; ++k) sn[k] = fmin(fmax(s[k] + t * d[6 + k], 0.0), 1.0);
            if (cl_eval(&C, yn, sn, cn, NULL, NULL, NULL) != 0) continue;
            double m1 = objective(yn, yd, W) + nu * l1(cn);
            if (m1 <= m0 + 1e-4 * t * fmin(slope, 0.0) || (t * dmax <= 1e-12 && l1(cn) <= tol)) {
                accepted = 1;
                break;
            }
        }
        if (!accepted) {
            trust *= 0.25;
            if (trust < TRUST_MIN) break;
            continue;
        }
        memcpy(y, yn, sizeof y);
        memcpy(s, sn, (size_t)n * sizeof *s);
        memcpy(c, cn, sizeof c);
        memcpy(lam, lam_new, sizeof lam);
        if (t == 1.0) trust = fmin(2.0 * trust, TRUST0);
        if (t * dmax <= 1e-10 && l1(c) <= tol) converged = 1;
    }
    if (iterations) *iterations = it;
    for (int i = 0; i < 6; ++i) xi[i] = y[i] * hpi_load_unit(i);
    return converged ? HP_LOAD_SOLVE_OK : HP_LOAD_SOLVE_ITERATION_LIMIT;
}
