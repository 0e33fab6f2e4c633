/* The fit's certificate (hp_kin_fit_certified): a proof, from the iterate the fit has reached
 * and what its caller knows, that the rest of the fit ends where the caller expects, so the
 * fit can stop there. docs/kinematics.md (section 5) has the argument in full; in short, in
 * the solvers' scaled units (pose in mm and degrees over the free components, distances in
 * mm), with x the iterate, J its Jacobian (σ >= the lower bound σ̂ of its smallest singular
 * value, column norms ĉ), a the anchor (a pose whose distances ρ(a) are known), ρ* the
 * fit's target, t = |ρ(x) − ρ*|, r0 = |ρ(a) − ρ*|, e = |x − a|, and B the ball of radius R
 * around x on which every distance's Hessian is bounded by h_k (hp_kin_contact_ball_curvature,
 * η = |h|₂):
 *   - on B, ‖J(p) − J(x)‖ <= ηR <= σ̂/4, so σ_min(J(p)) >= σ_B = ¾σ̂ and, by the mean value
 *     theorem, |ρ(p) − ρ(q)| >= σ_B|p − q|: an iterate with residual <= t is within
 *     (t + r0)/σ_B of a;
 *   - a Levenberg–Marquardt step with any damping λ >= 0 and Marquardt's column scaling is
 *     at most c_D·t/σ_B long (c_D the scaling's condition on B), so with
 *     R >= e + (t + r0 + c_D·t)/σ_B no trial leaves B and every accepted iterate stays in it;
 *   - with η·t <= σ_B²/10 and λ <= σ̃²/100 (σ̃ the column-scaled Jacobian's smallest
 *     singular value on B) every step above the noise floor is accepted and shrinks the
 *     residual by at least the factor f = 0.2 + 0.052·c_D² < 1, so λ only decreases, and
 *     within k = log(t_stop/t)/log f steps the residual is below t_stop; every way the fit
 *     can stop (arrived, a step below FK_STEP_TOL, damping beyond its cap, a zero residual)
 *     is then at a residual below t_stop, hence within δ = (t_stop + r0)/σ_B of a, inside
 *     the caller's tolerance of its pose, and before the iteration budget.
 * Each inequality carries the rounding of the computed quantities as explicit slack (ν, the
 * distances' evaluation noise; the Cholesky's backward error). Allocates nothing. */
#include "fit_internal.h"
#include "kin_geom.h"
#include "common/dense.h"
#include "common/minmax.h"
#include "common/units.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* Share of σ̂ that the Jacobian may change by on the ball. */
#define CERT_Q 0.25

/* A rigorous lower bound on the smallest eigenvalue of the symmetric positive definite A
 * (nf×nf, leading dimension nf), or 0: three steps of inverse iteration estimate it from
 * above, and a Cholesky factorisation of A − 0.8·estimate·I that succeeds proves the
 * shifted matrix positive definite up to the factorisation's backward error (far below
 * 1e-12·trace(A)), which is subtracted. If the shifted matrix fails, 1/‖L⁻¹‖_F² (up to nf
 * times too small). */
static double lambda_min_lower(const double *A, int nf)
{
    double L[36], M[36], v[6], tr = 0.0;
    for (int j = 0; j < nf; ++j) tr += A[j * nf + j];
    if (!hp_cholesky(A, nf, nf, 0.0, L, nf)) return 0.0;
    for (int j = 0; j < nf; ++j) v[j] = 1.0 + 0.01 * j; /* not orthogonal to any axis */
    double mu = 0.0;
    for (int it = 0; it < 3; ++it) {
        hp_cholesky_solve(L, nf, nf, v); /* v <- A⁻¹v */
        double nv = 0.0;
        for (int j = 0; j < nf; ++j) nv += v[j] * v[j];
        nv = sqrt(nv);
        if (!(nv > 0) || !isfinite(nv)) return 0.0;
        mu = nv;
        for (int j = 0; j < nf; ++j) v[j] /= nv;
    }
    /* |A⁻¹v| <= 1/λmin for the unit v of the last two steps: 1/mu >= λmin */
    double s = 0.8 / mu, lb;
    memcpy(M, A, sizeof(double) * (size_t)(nf * nf));
    for (int j = 0; j < nf; ++j) M[j * nf + j] -= s;
    if (hp_cholesky(M, nf, nf, 0.0, M, nf)) lb = s;
    else lb = 1.0 / hp_cholesky_inv_frob2(L, nf, nf);
    return hp_max2(0.0, lb - 1e-12 * tr);
}

int hp_kin_fit_certified(const hp_layout *L, const hp_geom *G, hp_level level, int nf,
                         const int *col, const double x[6], const double *A6, const double *r,
                         double lambda, const double *target, int iters_left,
                         const hp_kin_fit_near *near)
{
    if (!near || !near->has_anchor || nf < 1 || level == HP_LEVEL_LINEAR) return 0;
    int n = L->n, freec[6] = {0};
    for (int j = 0; j < nf; ++j) freec[col[j]] = 1;
    /* The anchor must lie in the fit's space: the components it does not move equal x's. */
    for (int i = 0; i < 6; ++i)
        if (!freec[i] && near->anchor[i] != x[i]) return 0;
    /* Scaled normal matrix Â = S·A·S (mm per scaled unit), its bounds and column norms. */
    double Ah[36], sc[6];
    for (int j = 0; j < nf; ++j) sc[j] = HP_MM_PER_M * hp_pose_si_per_scaled(col[j]);
    for (int j = 0; j < nf; ++j)
        for (int k = 0; k < nf; ++k) Ah[j * nf + k] = A6[j * 6 + k] * sc[j] * sc[k];
    double cmin = INFINITY, cmax = 0.0;
    for (int j = 0; j < nf; ++j) {
        double c = sqrt(Ah[j * nf + j]);
        cmin = hp_min2(cmin, c);
        cmax = hp_max2(cmax, c);
    }
    /* Distances in mm; ν bounds each computed distance's evaluation noise (a few ulps; the
     * realtime backend's extrapolated distances are within one ulp) with room to spare. */
    double rmax = 0.0, t2 = 0.0, r02 = 0.0, e2 = 0.0;
    for (int k = 0; k < n; ++k) {
        rmax = hp_max2(rmax, hp_max2(fabs(target[k]), fabs(near->anchor_rho[k])));
        t2 += r[k] * r[k];
        double d = near->anchor_rho[k] - target[k];
        r02 += d * d;
    }
    double nu = 64.0 * DBL_EPSILON * rmax * HP_MM_PER_M, snu = sqrt((double)n) * nu;
    for (int j = 0; j < nf; ++j) {
        double d = (x[col[j]] - near->anchor[col[j]]) / hp_pose_si_per_scaled(col[j]);
        e2 += d * d;
    }
    double tc = sqrt(t2) * HP_MM_PER_M * (1.0 + 1e-14); /* the computed residual */
    double tt = tc + snu;                                /* the true one */
    double r0 = sqrt(r02) * HP_MM_PER_M + snu, e = sqrt(e2);
    if (!isfinite(tt) || !isfinite(r0) || !isfinite(e) || !(cmin > 0)) return 0;
    /* The curvature on a ball, at x's distances (ρ* + r; less ν for the rounding). */
    double rho_x[HP_MAX_BLADDERS], h[HP_MAX_BLADDERS];
    for (int k = 0; k < n; ++k) rho_x[k] = target[k] + r[k] - nu / HP_MM_PER_M;
    /* A cheap necessary condition first (most iterates far from the answer fail it): σ̂ is
     * at most the smallest column norm, so R (below) is at least R_lo. The curvature bound
     * grows with the radius: taken on a ball of radius R_up = 4·R_lo it serves any R up to
     * R_up (the usual case: σ̂ is rarely below a quarter of the smallest column norm). */
    double R_lo = e + (tt + tc) / ((1.0 - CERT_Q) * cmin), R_up = 4.0 * R_lo;
    if (hp_kin_contact_ball_curvature(L, G, level, x, R_up, rho_x, h) != HP_OK) return 0;
    double eta2 = 0.0;
    for (int k = 0; k < n; ++k) eta2 += h[k] * h[k];
    double eta = sqrt(eta2);
    if (!(eta * R_lo <= CERT_Q * cmin)) return 0;
    double lam = lambda_min_lower(Ah, nf);
    if (!(lam > 0)) return 0;
    double sig = sqrt(lam), sigB = (1.0 - CERT_Q) * sig;
    if (!(cmin > CERT_Q * sig)) return 0;
    double cD = (cmax + CERT_Q * sig) / (cmin - CERT_Q * sig);
    double tstop = hp_max2(100.0 * (r0 + snu), 1.1e-12 * nf);
    /* The damped step dx differs from the Gauss–Newton step g (|g| <= t/σ_B) by
     * (JᵀJ + λC²)⁻¹λC²g, so |dx| <= (1 + κ)|g| and |J(dx − g)| <= κ|Jg| <= κt with
     * κ = λ·c_max²/σ_B² (c_max the largest column norm on the ball); λ only decreases
     * while every step is accepted. Below tstop a step of any damping is at most
     * c_D·tstop/σ_B long. */
    double kap = lambda * (cmax + CERT_Q * sig) * (cmax + CERT_Q * sig) / (sigB * sigB);
    if (!(kap <= 0.5)) return 0;
    double R = (e + (tt + r0 + (1.0 + kap) * tc * (1.0 + 1e-6) + cD * tstop) / sigB) *
               (1.0 + 1e-9);
    if (!(R <= R_up)) { /* the ball itself */
        if (hp_kin_contact_ball_curvature(L, G, level, x, R, rho_x, h) != HP_OK) return 0;
        eta2 = 0.0;
        for (int k = 0; k < n; ++k) eta2 += h[k] * h[k];
        eta = sqrt(eta2);
    }
    if (!(eta * R <= CERT_Q * sig)) return 0;
    /* The rate above tstop (docs): the part of r̃ outside J's range is at most
     * ½η|q − a|² + r0 + ν√n <= (½η(1.01/σ_B)²t + 0.01)·t =: w·t; the damped step leaves
     * at most that plus κt of the linearised residual, its remainder adds ½η|dx|², and the
     * noise of the two evaluations (old and new point) 2ν√n <= 0.02t. Each factor grows
     * with t, so f at t bounds the factor of every later step. */
    double w = 0.5 * eta * (1.01 / sigB) * (1.01 / sigB) * tt + 0.01;
    double f = w + kap + 0.5 * eta * ((1.0 + kap) / sigB) * ((1.0 + kap) / sigB) * tt + 0.02;
    f *= 1.0 + 1e-6;
    if (!(f <= 0.5)) return 0;
    int steps = tt > tstop ? (int)ceil(log(tstop / tt) / log(f)) : 0;
    if (!(steps + 2 <= iters_left)) return 0;
    double delta = (tstop + snu + r0) / sigB;
    for (int j = 0; j < nf; ++j) {
        int i = col[j];
        double s = hp_pose_si_per_scaled(i);
        double off = fabs(near->anchor[i] - near->pose[i]) / s;
        if (!(off + delta <= 0.25 * near->tol[i] / s)) return 0;
    }
    return 1;
}
