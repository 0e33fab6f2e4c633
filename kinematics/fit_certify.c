/* The fit's certificate (hpi_kin_fit_certified): a proof, from the iterate the fit has reached
 * and what its caller knows, that the rest of the fit ends where the caller expects, so the
 * fit can stop there. docs/kinematics.md (section 5) has the argument in full; in short, in
 * the solvers' scaled units (pose in mm and degrees over the free components, distances in
 * mm), with x the iterate, J its Jacobian (σ >= the lower bound σ̂ of its smallest singular
 * value, column norms ĉ), a the anchor (a pose whose distances ρ(a) are known), ρ* the
 * fit's target, t = |ρ(x) − ρ*|, r0 = |ρ(a) − ρ*|, e = |x − a|, and B the ball of radius R
 * around x on which every distance's Hessian is bounded by h_k (hpi_kin_contact_ball_curvature,
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
    if (!hpi_cholesky(A, nf, nf, 0.0, L, nf)) return 0.0;
    for (int j = 0; j < nf; ++j) v[j] = 1.0 + 0.01 * j; /* not orthogonal to any axis */
    double mu = 0.0;
    for (int it = 0; it < 3; ++it) {
        hpi_cholesky_solve(L, nf, nf, v); /* v <- A⁻¹v */
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
    if (hpi_cholesky(M, nf, nf, 0.0, M, nf)) lb = s;
    else lb = 1.0 / hpi_cholesky_inv_frob2(L, nf, nf);
    return hpi_max2(0.0, lb - 1e-12 * tr);
}

/* What every form of the proof shares: the ball's centre and the model there. */
typedef struct cert_ctx {
    const hp_layout *L;
    const hp_geom *G;
    hp_level level;
    int nf;
    const int *col;
    const hp_kin_fit_near *near;
    const double *centre; /* SI pose */
    hp_kin_cert_model m;  /* the model there */
} cert_ctx;

/* Fills the scaled normal matrix Â = S·A·S (A nf×nf with leading dimension lda, SI) and its
 * column norms' range. */
static void scaled_normal(cert_ctx *cx, const double *A, int lda)
{
    int nf = cx->nf;
    double sc[6];
    for (int j = 0; j < nf; ++j) sc[j] = HP_MM_PER_M * hpi_pose_si_per_scaled(cx->col[j]);
    for (int j = 0; j < nf; ++j)
        for (int k = 0; k < nf; ++k) cx->m.Ah[j * nf + k] = A[j * lda + k] * sc[j] * sc[k];
    cx->m.cmin = INFINITY;
    cx->m.cmax = 0.0;
    for (int j = 0; j < nf; ++j) {
        double c = sqrt(cx->m.Ah[j * nf + j]);
        cx->m.cmin = hpi_min2(cx->m.cmin, c);
        cx->m.cmax = hpi_max2(cx->m.cmax, c);
    }
}

/* The noise ν√n, r0 and the centre's distances (rho_m: the model's at the centre, m), and
 * 0 unless the anchor lies in the fit's space (the components it does not move equal the
 * start's, x0) and every number is finite. */
static int noise_and_r0(cert_ctx *cx, const double *x0, const double *rho_m, const double *target)
{
    const hp_kin_fit_near *near = cx->near;
    int n = cx->L->n, freec[6] = {0};
    for (int j = 0; j < cx->nf; ++j) freec[cx->col[j]] = 1;
    for (int i = 0; i < 6; ++i)
        if (!freec[i] && near->anchor[i] != x0[i]) return 0;
    /* ν bounds each computed distance's evaluation noise (a few ulps; the realtime
     * backend's extrapolated distances are within one ulp) with room to spare. */
    double rmax = 0.0, r02 = 0.0;
    for (int k = 0; k < n; ++k) {
        rmax = hpi_max2(rmax, hpi_max2(fabs(target[k]), fabs(near->anchor_rho[k])));
        rmax = hpi_max2(rmax, fabs(rho_m[k]));
        double d = near->anchor_rho[k] - target[k];
        r02 += d * d;
    }
    double nu = 64.0 * DBL_EPSILON * rmax; /* m */
    for (int k = 0; k < n; ++k) cx->m.rho_c[k] = rho_m[k] - nu;
    cx->m.snu = sqrt((double)n) * nu * HP_MM_PER_M;
    cx->m.r0 = sqrt(r02) * HP_MM_PER_M + cx->m.snu;
    return isfinite(cx->m.r0) && isfinite(cx->m.snu);
}

/* |p − q| over the free components, scaled (mm, degrees). */
static double scaled_dist(const cert_ctx *cx, const double *p, const double *q)
{
    double e2 = 0.0;
    for (int j = 0; j < cx->nf; ++j) {
        int i = cx->col[j];
        double d = (p[i] - q[i]) / hpi_pose_si_per_scaled(i);
        e2 += d * d;
    }
    return sqrt(e2);
}

/* η = |h|₂ of the curvature bounds on the ball of radius R around the centre, or −1 when
 * the bound fails (every caller then refuses). */
static double ball_eta(const cert_ctx *cx, double R)
{
    double h[HP_MAX_BLADDERS], eta2 = 0.0;
    if (hpi_kin_contact_ball_curvature(cx->L, cx->G, cx->level, cx->centre, R, cx->m.rho_c, h) !=
        HP_OK)
        return -1.0;
    for (int k = 0; k < cx->L->n; ++k) eta2 += h[k] * h[k];
    return sqrt(eta2);
}

/* The proof (file header; docs/kinematics.md, section 5) for an iterate x of the fit: e_ca
 * = |centre − anchor|, e_xc = |x − centre|, tt and tc bounds on x's true and computed
 * residual (mm), lambda the damping of x's steps, sig the lower bound σ̂ of the centre's
 * Jacobian's smallest singular value; eta a curvature bound valid up to radius R_eta (0:
 * none yet). */
static int certify(const cert_ctx *cx, double sig, double e_ca, double e_xc, double tt, double tc,
                   double lambda, int iters_left, double eta, double R_eta)
{
    const hp_kin_fit_near *near = cx->near;
    double sigB = (1.0 - CERT_Q) * sig, r0 = cx->m.r0, snu = cx->m.snu;
    if (!(sig > 0) || !(cx->m.cmin > CERT_Q * sig) || !isfinite(tt) || !isfinite(tc)) return 0;
    double cD = (cx->m.cmax + CERT_Q * sig) / (cx->m.cmin - CERT_Q * sig);
    double tstop = hpi_max2(100.0 * (r0 + snu), 1.1e-12 * cx->nf);
    /* The damped step dx differs from the Gauss–Newton step g (|g| <= t/σ_B) by
     * (JᵀJ + λC²)⁻¹λC²g, so |dx| <= (1 + κ)|g| and |J(dx − g)| <= κ|Jg| <= κt with
     * κ = λ·c_max²/σ_B² (c_max the largest column norm on the ball); λ only decreases
     * while every step is accepted. Below tstop a step of any damping is at most
     * c_D·tstop/σ_B long. */
    double cm = cx->m.cmax + CERT_Q * sig;
    double kap = lambda * cm * cm / (sigB * sigB);
    if (!(kap <= 0.5)) return 0;
    double R = (e_ca + (tt + r0 + (1.0 + kap) * tc * (1.0 + 1e-6) + cD * tstop) / sigB) *
               (1.0 + 1e-9);
    if (!(e_xc <= R)) return 0;
    if (!(R <= R_eta)) eta = ball_eta(cx, R); /* a bound on a larger ball is a safe one */
    if (!(eta >= 0) || !(eta * R <= CERT_Q * sig)) return 0;
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
    /* steps to the floor, then the floor phase: the fit's arrived test stops it at once
     * (x within δ of a, its Gauss–Newton step below δ), but the full fit without it takes
     * its own stops there after up to 16 more iterations (measured): the margin. */
    if (!(steps + HP_KIN_FIT_STOP_MARGIN <= iters_left)) return 0;
    double delta = (tstop + snu + r0) / sigB;
    for (int j = 0; j < cx->nf; ++j) {
        int i = cx->col[j];
        double s = hpi_pose_si_per_scaled(i);
        double off = fabs(near->anchor[i] - near->pose[i]) / s;
        if (!(off + delta <= 0.25 * near->tol[i] / s)) return 0;
    }
    return 1;
}

int hpi_kin_fit_certified(const hp_layout *L, const hp_geom *G, hp_level level, int nf,
                          const int *col, const double x[6], const double *A6, const double *r,
                          double lambda, const double *target, int iters_left,
                          const hp_kin_fit_near *near)
{
    if (!near || !near->has_anchor || nf < 1 || level == HP_LEVEL_LINEAR) return 0;
    int n = L->n;
    cert_ctx cx = {.L = L, .G = G, .level = level, .nf = nf, .col = col, .near = near, .centre = x};
    /* = {0}: GCC at -O1 (the sanitizer build) cannot see that n > 0 fills what is read. */
    double rho_x[HP_MAX_BLADDERS] = {0}, t2 = 0.0;
    for (int k = 0; k < n; ++k) {
        rho_x[k] = target[k] + r[k];
        t2 += r[k] * r[k];
    }
    if (!noise_and_r0(&cx, x, rho_x, target)) return 0;
    scaled_normal(&cx, A6, 6);
    double e = scaled_dist(&cx, x, near->anchor);
    double tc = sqrt(t2) * HP_MM_PER_M * (1.0 + 1e-14); /* the computed residual */
    double tt = tc + cx.m.snu;                          /* the true one */
    if (!isfinite(tt) || !isfinite(e) || !(cx.m.cmin > 0)) return 0;
    /* A cheap necessary condition first (most iterates far from the answer fail it): σ̂ is
     * at most the smallest column norm, so R is at least R_lo. The curvature bound grows
     * with the radius: taken on a ball of radius R_up = 4·R_lo it serves any R up to R_up
     * (the usual case: σ̂ is rarely below a quarter of the smallest column norm). */
    double R_lo = e + (tt + tc) / ((1.0 - CERT_Q) * cx.m.cmin), R_up = 4.0 * R_lo;
    double eta = ball_eta(&cx, R_up);
    if (!(eta >= 0) || !(eta * R_lo <= CERT_Q * cx.m.cmin)) return 0;
    double sig = sqrt(lambda_min_lower(cx.m.Ah, nf));
    return certify(&cx, sig, e, 0.0, tt, tc, lambda, iters_left, eta, R_up);
}

int hpi_kin_fit_certified_trial(const hp_layout *L, const hp_geom *G, hp_level level, int nf,
                                const int *col, const double xt[6], const double *A6, double cost,
                                double lambda_next, const double *target, int iters_left,
                                const hp_kin_fit_near *near, hp_kin_trial_cache *cache)
{
    if (!near || !near->has_anchor || !near->anchor_J || nf < 1 || level == HP_LEVEL_LINEAR)
        return 0;
    int n = L->n;
    cert_ctx cx = {
        .L = L, .G = G, .level = level, .nf = nf, .col = col, .near = near, .centre = near->anchor};
    /* The true Jacobian at the anchor lies within err of the given one (spectral norm): its
     * column norms and smallest singular value within err of theirs (Weyl). */
    double err = near->anchor_J_err, sig = -1.0;
    if (!(err >= 0) || !isfinite(err)) return 0;
    if (cache && cache->ready) {
        cx.m = cache->m;
        sig = cache->sig;
    } else {
        if (!noise_and_r0(&cx, xt, near->anchor_rho, target)) return 0;
        scaled_normal(&cx, A6, 6);
        cx.m.cmin -= err;
        cx.m.cmax += err;
        if (cache) {
            cache->m = cx.m;
            cache->sig = -1.0;
            cache->ready = 1;
        }
    }
    /* The trial's residual through the anchor, by Taylor's theorem on the segment:
     * |ρ(xt) − ρ*| <= |J(a)·(xt − a)| + ½η|xt − a|² + r0, and ½η e² <= ½(σ̂/4)·e once
     * certify has checked ηR <= σ̂/4 with e <= R. J(a)·(xt − a) in mm, exactly as summed
     * with the given Jacobian, whose error adds at most err·e. */
    double e = scaled_dist(&cx, xt, near->anchor), jd2 = 0.0, dv[6] = {0};
    /* The fixed columns enter as exact zeros (a finite J times +0 adds nothing). */
    for (int j = 0; j < nf; ++j) dv[col[j]] = xt[col[j]] - near->anchor[col[j]];
    for (int k = 0; k < n; ++k) {
        const double *Jk = &near->anchor_J[k * 6];
        double v = 0.0;
#pragma GCC unroll 6
        for (int i = 0; i < 6; ++i) v += Jk[i] * dv[i];
        v *= HP_MM_PER_M;
        jd2 += v * v;
    }
    double jd = sqrt(jd2) * (1.0 + 1e-12);
    /* Cheap necessary conditions first (a trial far from the anchor fails them): accepted
     * needs jd² < cost; certify needs e <= R and η(R)·R <= ¼σ̂, where R >= 2·jd/σ_B and
     * σ_B = ¾σ̂ <= ¾·c_min, and the curvature bound η grows with the radius. Taken on a
     * ball of 4·R_lo, the bound serves certify for any R up to that. */
    if (!(jd2 < cost * HP_MM_PER_M * HP_MM_PER_M) || !isfinite(e)) return 0;
    double R_lo = fmax(e, 2.0 * jd / ((1.0 - CERT_Q) * cx.m.cmin)), R_up = 4.0 * R_lo;
    double eta = ball_eta(&cx, R_up);
    if (!(eta >= 0) || !(eta * R_lo <= CERT_Q * cx.m.cmin)) return 0;
    if (!(sig >= 0)) {
        sig = sqrt(lambda_min_lower(cx.m.Ah, nf)) - err;
        if (!(sig > 0)) sig = 0.0;
    }
    if (cache) cache->sig = sig;
    if (!(sig > 0)) return 0;
    double tt = jd + err * e + 0.5 * CERT_Q * sig * e + cx.m.r0;
    double tc = tt + cx.m.snu;
    /* Accepted: its computed squared residual is below the start's (cost, m²). */
    if (!(tc * tc * (1.0 + 1e-14) < cost * HP_MM_PER_M * HP_MM_PER_M)) return 0;
    return certify(&cx, sig, 0.0, e, tt, tc, lambda_next, iters_left, eta, R_up);
}

double hpi_kin_jacobian_drift(const hp_layout *L, const hp_geom *G, hp_level level,
                              const double xa[6], const double *rho_a, const double *J, double d)
{
    double h[HP_MAX_BLADDERS], eta2 = 0.0, jf2 = 0.0;
    if (!(d >= 0) || !isfinite(d) ||
        hpi_kin_contact_ball_curvature(L, G, level, xa, d, rho_a, h) != HP_OK)
        return INFINITY;
    for (int k = 0; k < L->n; ++k) {
        eta2 += h[k] * h[k];
        for (int i = 0; i < 6; ++i) {
            double v = J[k * 6 + i] * HP_MM_PER_M * hpi_pose_si_per_scaled(i);
            jf2 += v * v;
        }
    }
    double err = (sqrt(eta2) * d + 4.0 * DBL_EPSILON * sqrt(jf2)) * (1.0 + 1e-9);
    return isfinite(err) ? err : INFINITY;
}
