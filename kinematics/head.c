/* The rigid head: shapes, validation, and the signed distance from a point to its surface
 * with exact first and second derivatives. */
#include "kin_internal.h"
#include "common/minmax.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* The root find's budget of steps (it usually ends in one to four; the bracket's halvings,
 * its fallback, take more). */
#define ELL_MAX_STEPS 200

hp_error hpi_kin_head_validate(const hp_head *h, hp_diag *diag)
{
    if (h->shape != HP_HEAD_SPHERE && h->shape != HP_HEAD_ELLIPSOID)
        return hp_diag_set(diag, HP_ERR_INVALID, "head: shape: must be sphere or ellipsoid");
    if (!hpi_kin_finite3(h->center))
        return hp_diag_set(diag, HP_ERR_INVALID, "head: center: must be finite");
    static const char *const axis[3] = {"x", "y", "z"};
    int na = h->shape == HP_HEAD_SPHERE ? 1 : 3;
    for (int i = 0; i < na; ++i) {
        if (!(h->semi_axes[i] > 0) || !isfinite(h->semi_axes[i])) {
            if (h->shape == HP_HEAD_SPHERE)
                return hp_diag_set(diag, HP_ERR_INVALID,
                                   "head: radius: must be finite and > 0 (got %g m)",
                                   h->semi_axes[0]);
            return hp_diag_set(diag, HP_ERR_INVALID,
                               "head: semi_axes.%s: must be finite and > 0 (got %g m)", axis[i],
                               h->semi_axes[i]);
        }
    }
    if (!(h->mass >= 0) || !isfinite(h->mass))
        return hp_diag_set(diag, HP_ERR_INVALID, "head: mass: must be finite and >= 0 (got %g kg)",
                           h->mass);
    return HP_OK;
}

double hpi_kin_head_min_curvature_radius(const hp_head *h)
{
    if (h->shape == HP_HEAD_SPHERE) return h->semi_axes[0];
    double amin = fmin(h->semi_axes[0], fmin(h->semi_axes[1], h->semi_axes[2]));
    double amax = fmax(h->semi_axes[0], fmax(h->semi_axes[1], h->semi_axes[2]));
    return amin * amin / amax;
}

/* Hessian of a distance whose gradient is n = m/|m|: (I − n nᵀ)/|m| · Dm (im = 1/|m|). */
static void project_hessian(const double n[3], double im, const double Dm[9], double hess[9])
{
    double P[9], T[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) P[i * 3 + j] = ((i == j) - n[i] * n[j]) * im;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            T[i * 3 + j] = P[i * 3] * Dm[j] + P[i * 3 + 1] * Dm[3 + j] + P[i * 3 + 2] * Dm[6 + j];
    /* The exact Hessian is symmetric; average away the rounding asymmetry. On the diagonal
     * the average 0.5·(T_ii + T_ii) is T_ii itself (a doubling and a halving, both exact
     * for a finite T_ii), and each off-diagonal average is formed once and mirrored. */
    for (int i = 0; i < 3; ++i) {
        hess[i * 3 + i] = T[i * 3 + i];
        for (int j = i + 1; j < 3; ++j)
            hess[i * 3 + j] = hess[j * 3 + i] = 0.5 * (T[i * 3 + j] + T[j * 3 + i]);
    }
}

static hp_error sphere_distance(const hp_head *h, const double y[3], double *d, double grad[3],
                                double hess[9], double foot[3])
{
    double r = h->semi_axes[0];
    double len = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
    if (!(len >= 1e-3 * r)) return HP_ERR_DOMAIN; /* at the centre: no unique closest point */
    double n[3] = {y[0] / len, y[1] / len, y[2] / len};
    *d = len - r;
    if (grad) memcpy(grad, n, sizeof n);
    if (foot)
        for (int i = 0; i < 3; ++i) foot[i] = h->center[i] + r * n[i];
    if (hess) {
        const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        project_hessian(n, 1.0 / len, I, hess);
    }
    return HP_OK;
}

/* One point's root find in progress (ellipsoid_distance; hpi_kin_head_distances runs several
 * side by side): the point y (head frame), r∘z with z = |y|/a, the bracket and the iterate. */
typedef struct ell_pt {
    double y[3], rz[3], lo, hi, s;
    int evals, running;
} ell_pt;

/* The bracket and the start of the root find at y (see ellipsoid_distance). */
static hp_error ell_setup(const hp_head *h, const hp_kin_head_k *k, const double y[3],
                          const hp_kin_dist_warm *ws, ell_pt *p)
{
    const double *a = h->semi_axes, *r = k->r;
    double z[3], g0 = -1.0;
    for (int i = 0; i < 3; ++i) {
        p->y[i] = y[i];
        z[i] = fabs(y[i]) / a[i];
        p->rz[i] = r[i] * z[i];
        g0 += z[i] * z[i];
    }
    double lo = -1.0, hi;
    for (int i = 0; i < 3; ++i) lo = hpi_max2(lo, r[i] * (z[i] - 1.0));
    if (g0 > 0) {
        lo = hpi_max2(lo, 0.0);
        hi = sqrt(p->rz[0] * p->rz[0] + p->rz[1] * p->rz[1] + p->rz[2] * p->rz[2]) - 1.0;
        if (hi < lo) hi = lo;
    } else {
        /* Deep inside, near the set of centres of curvature, the distance is not smooth. */
        if (!(lo + 1.0 >= 1e-3)) return HP_ERR_DOMAIN;
        hi = 0.0;
        if (lo > hi) lo = hi;
    }
    double s = g0 == 0.0 ? 0.0 : lo; /* exactly on the surface: t = 0 */
    /* Warm start: the multiplier at the previous point of the same bladder, moved to this
     * point to first order, s_w + ∂s/∂y·(y − y_w). The points a fit or an SQP evaluates one
     * after another are mostly under 1 mm apart (1e-10 m near the end of a solve), so the
     * prediction is off by O(|y − y_w|²) where the multiplier alone is off by O(|y − y_w|),
     * and with the third-order step below one evaluation usually ends the climb where it
     * took two or three. The bracket guards every step whatever the start, so a bad guess
     * (a far jump, a stale state) costs steps, never the answer. */
    if (g0 != 0.0 && ws && ws->s == ws->s) {
        double sp = ws->s + (ws->ds[0] * (y[0] - ws->y[0]) + ws->ds[1] * (y[1] - ws->y[1]) +
                             ws->ds[2] * (y[2] - ws->y[2]));
        if (sp > lo && sp < hi) s = sp;
        else if (ws->s > lo && ws->s < hi) s = ws->s;
    }
    p->lo = lo;
    p->hi = hi;
    p->s = s;
    p->evals = 0;
    p->running = g0 != 0.0;
    return HP_OK;
}

/* One step of the root find (see ellipsoid_distance); clears p->running when it ends. */
static inline void ell_step(const hp_kin_head_k *k, ell_pt *p)
{
    const double *r = k->r, *rz = p->rz;
    double s = p->s, lo = p->lo, hi = p->hi;
    double Q = 0.0, dQ = 0.0, d2Q = 0.0, d3Q = 0.0;
    ++p->evals;
    p->running = 0;
    for (int i = 0; i < 3; ++i) {
        double inv = 1.0 / (r[i] + s); /* one division a term, not two */
        double q2 = rz[i] * inv * (rz[i] * inv), q2i = q2 * inv, q2ii = q2i * inv;
        Q += q2;
        dQ -= 2.0 * q2i;
        d2Q += 6.0 * q2ii;
        d3Q -= 24.0 * q2ii * inv;
    }
    if (Q == 1.0) return;
    if (Q > 1.0) p->lo = lo = s;
    else p->hi = hi = s;
    /* est: the step's own error, Newton's |c|·δ² or Chebyshev's |2c² − c3|·|δ|³ with
     * c = ψ''/(2ψ') and c3 = ψ'''/(6ψ'), where ψ''/ψ' = Q''/Q' − 1.5·Q'/Q and
     * ψ'''/ψ' = 3.75·(Q'/Q)² − 4.5·Q''/Q + Q'''/Q'. One division, 1/(Q'·Q), serves all of
     * them and runs beside the square root. */
    double sn, est = INFINITY;
    if (dQ < 0) {
        double R = 1.0 / (dQ * Q), qq = dQ * dQ * R; /* qq = Q'/Q */
        double dn = -2.0 * (Q * Q) * (sqrt(Q) - 1.0) * R;
        double c = 0.5 * (d2Q * Q - 1.5 * dQ * dQ) * R, cd = c * dn;
        if (fabs(cd) <= 0.25) {
            double c3 = (3.75 * qq * qq - 4.5 * d2Q * dQ * R + d3Q * Q * R) * (1.0 / 6.0);
            sn = s + (dn - cd * dn);
            est = fabs((2.0 * c * c - c3) * dn * dn * dn);
        } else {
            sn = s + dn;
            est = fabs(cd * dn);
        }
    } else {
        sn = 0.5 * (lo + hi);
    }
    /* s enters only as r_i + s with r_i >= 1: absolute resolution 2ε·max(1,|s|). */
    double res = 2.0 * DBL_EPSILON * hpi_max2(1.0, fabs(s)), step = fabs(sn - s);
    if (step <= res) return;
    if (!(sn > lo && sn < hi)) {
        sn = 0.5 * (lo + hi);
        if (sn == lo || sn == hi) return; /* bracket down to adjacent doubles */
    } else if (est <= 0.25 * res) {
        /* When the step's error is below the resolution its result is the root to
         * rounding and the next evaluation would only confirm it. */
        p->s = sn;
        return;
    }
    p->s = sn;
    p->running = p->evals < ELL_MAX_STEPS;
}

/* The distance and what was asked for at the root p->s (see ellipsoid_distance). */
static hp_error ell_finish(const hp_head *h, const hp_kin_head_k *k, const ell_pt *p,
                           hp_kin_dist_warm *ws, double *d, double grad[3], double hess[9],
                           double foot[3])
{
    const double *r = k->r, *y = p->y;
    double e = k->e, e2 = k->e2, s = p->s;
    double t = s * e * e;
    double m[3];
    for (int i = 0; i < 3; ++i)
        m[i] = y[i] / (e2 * (r[i] + s)); /* x_i/a_i²: the unnormalised outward normal */
    double mn = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    if (!(mn > 0)) return HP_ERR_DOMAIN;
    double n[3] = {m[0] / mn, m[1] / mn, m[2] / mn};
    *d = t * mn;
    if (grad) memcpy(grad, n, sizeof n);
    if (!ws && !hess && !foot) return HP_OK;
    /* The closest point x = a²∘m, w_i = x_i/(a_i² + t), v_i = w_i/a_i² = m_i/(a_i² + t)
     * and S = Σ x_i v_i, only when asked for (the distance and normal above do not depend
     * on them). */
    double x[3], w[3], v[3], id[3], S = 0.0;
    for (int i = 0; i < 3; ++i) {
        id[i] = 1.0 / (e2 * (r[i] + s));
        x[i] = e2 * r[i] * m[i];
        w[i] = x[i] * id[i];
        v[i] = m[i] * id[i];
        S += x[i] * v[i];
    }
    double iS = 1.0 / S;
    if (ws) {
        /* ∂t/∂y = w/S (implicit differentiation of G(y, t) = 0), so ∂s/∂y = w/(e²·S) =
         * r∘v/S. Off the answer's path: only the next evaluation waits for it. An S that
         * underflowed leaves a non-finite gradient, and the next start falls back to s. */
        ws->s = s;
        ws->evals = p->evals;
        for (int i = 0; i < 3; ++i) {
            ws->y[i] = y[i];
            ws->ds[i] = r[i] * v[i] * iS;
        }
    }
    if (!hess && !foot) return HP_OK;
    /* S = Σ x_i²/(a_i²(a_i² + t)) > 0 wherever m ≠ 0 unless it underflows (the Hessian
     * divides by it). */
    if (!(S > 0)) return HP_ERR_DOMAIN;
    if (foot)
        for (int i = 0; i < 3; ++i) foot[i] = h->center[i] + x[i];
    if (hess) {
        /* ∂m/∂y = diag(1/(a²+t)) − v wᵀ/S, from implicit differentiation of G(y, t) = 0:
         * ∂t/∂y = w/S, ∂x/∂y = diag(a²/(a²+t)) − w wᵀ/S. */
        double Dm[9];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) Dm[i * 3 + j] = (i == j ? id[i] : 0.0) - v[i] * w[j] * iS;
        project_hessian(n, 1.0 / mn, Dm, hess);
    }
    return HP_OK;
}

/* The ellipsoid sum(x_i²/a_i²) = 1. The closest point is x_i = a_i² y_i/(a_i² + t) where t
 * is the root of G(t) = Σ (a_i y_i/(a_i² + t))² − 1 with t > −a_min² (Lagrange multiplier;
 * the signed distance is t·|x/a²|). In the scaled variable s = t/e², e = a_min,
 * r_i = (a_i/e)² >= 1 and z_i = |y_i|/a_i (the first octant; symmetry restores the signs),
 * G(s) = Σ (r_i z_i/(r_i + s))² − 1 is decreasing on s > −1 with one root there; a
 * bracket [lo, hi] guards the Newton iteration against rounding (ell_setup).
 * Left bound: the term j alone reaches 1 at s = r_j(z_j − 1), so G >= 0 at the largest of
 * these (and at 0 outside). Right bound outside: G <= |r∘z|²/(1 + s)² − 1 <= 0 at
 * s = |r∘z| − 1. Inside, s <= 0. Points on an axis or on equal axes need no special case.
 * Newton on ψ(s) = Q(s)^(-1/2) − 1, Q = G + 1 (ell_step): ψ is a power mean with exponent
 * −2 of the affine (r_i + s)/(r_i z_i), hence concave and increasing, and exactly linear
 * for a sphere; Newton from the left (ψ <= 0) climbs monotonically and converges in a few
 * steps where Newton on G itself would crawl. Near the root (the correction below under a
 * quarter of the step) each Newton step δ = −ψ/ψ' gets Chebyshev's correction
 * −(ψ''/(2ψ'))·δ², third order instead of second for a few more multiplications: a start
 * 1e-6 off (a warm start after a 0.1 mm move) then ends in one evaluation. */
static hp_error ellipsoid_distance(const hp_head *h, const hp_kin_head_k *k, const double y[3],
                                   hp_kin_dist_warm *ws, double *d, double grad[3], double hess[9],
                                   double foot[3])
{
    ell_pt p;
    hp_error e = ell_setup(h, k, y, ws, &p);
    if (e != HP_OK) return e;
    while (p.running) ell_step(k, &p);
    return ell_finish(h, k, &p, ws, d, grad, hess, foot);
}

void hpi_kin_head_consts(const hp_head *h, hp_kin_head_k *k)
{
    const double *a = h->semi_axes;
    double e = hpi_min2(a[0], hpi_min2(a[1], a[2]));
    k->e = e;
    k->e2 = e * e;
    for (int i = 0; i < 3; ++i) {
        k->r[i] = (a[i] / e) * (a[i] / e);
    }
}

hp_error hpi_kin_head_distance(const hp_head *h, const double q[3], double *d, double grad[3],
                               double hess[9], double foot[3])
{
    return hpi_kin_head_distance_warm(h, q, NULL, d, grad, hess, foot);
}

hp_error hpi_kin_head_distance_warm(const hp_head *h, const double q[3], hp_kin_dist_warm *w,
                                    double *d, double grad[3], double hess[9], double foot[3])
{
    hp_kin_head_k k = {0}; /* a sphere reads none of it */
    if (h->shape != HP_HEAD_SPHERE) hpi_kin_head_consts(h, &k);
    return hpi_kin_head_distance_k(h, &k, q, w, d, grad, hess, foot);
}

/* y = q − centre, or the error for a point no head question is about: beyond 1000 km
 * (where squares could overflow; the one comparison per coordinate also fails for NaN and
 * inf, told apart only then). */
static hp_error head_point(const hp_head *h, const double q[3], double y[3])
{
    for (int i = 0; i < 3; ++i) y[i] = q[i] - h->center[i];
    if (!(fabs(y[0]) <= 1e6 && fabs(y[1]) <= 1e6 && fabs(y[2]) <= 1e6))
        return hpi_kin_finite3(y) ? HP_ERR_DOMAIN : HP_ERR_INVALID;
    return HP_OK;
}

hp_error hpi_kin_head_distance_k(const hp_head *h, const hp_kin_head_k *k, const double q[3],
                                 hp_kin_dist_warm *w, double *d, double grad[3], double hess[9],
                                 double foot[3])
{
    double y[3];
    hp_error e = head_point(h, q, y);
    if (e != HP_OK) return e;
    if (h->shape == HP_HEAD_SPHERE) return sphere_distance(h, y, d, grad, hess, foot);
    return ellipsoid_distance(h, k, y, w, d, grad, hess, foot);
}

hp_error hpi_kin_head_distances(const hp_head *h, const hp_kin_head_k *k, int n,
                                const double (*q)[3], hp_kin_dist_warm *w, double *d,
                                double (*grad)[3], double (*hess)[9], const unsigned char *want_h,
                                int *bad)
{
    *bad = -1;
    if (n < 0 || n > HP_MAX_BLADDERS) return HP_ERR_INVALID;
    double y[HP_MAX_BLADDERS][3];
    hp_error e[HP_MAX_BLADDERS];
    if (h->shape == HP_HEAD_SPHERE) {
        for (int j = 0; j < n; ++j) {
            hp_error ej = head_point(h, q[j], y[j]);
            if (ej == HP_OK)
                ej = sphere_distance(h, y[j], &d[j], grad[j],
                                     hess && (!want_h || want_h[j]) ? hess[j] : NULL, NULL);
            if (ej != HP_OK) return *bad = j, ej;
        }
        return HP_OK;
    }
    /* The points' root finds side by side, one step of each in turn: every step is a short
     * chain of divisions and a square root, and with the other points' steps between them
     * the processor overlaps the chains (one point after another, each waits for its own).
     * Each point takes exactly the steps, and so gives the bits, it would alone. */
    ell_pt p[HP_MAX_BLADDERS];
    int running = 0;
    for (int j = 0; j < n; ++j) {
        e[j] = head_point(h, q[j], y[j]);
        if (e[j] == HP_OK) e[j] = ell_setup(h, k, y[j], w ? &w[j] : NULL, &p[j]);
        if (e[j] != HP_OK) p[j].running = 0;
        running |= p[j].running;
    }
    while (running) {
        running = 0;
        for (int j = 0; j < n; ++j)
            if (p[j].running) {
                ell_step(k, &p[j]);
                running |= p[j].running;
            }
    }
    for (int j = 0; j < n; ++j)
        if (e[j] == HP_OK)
            e[j] = ell_finish(h, k, &p[j], w ? &w[j] : NULL, &d[j], grad[j],
                              hess && (!want_h || want_h[j]) ? hess[j] : NULL, NULL);
    for (int j = 0; j < n; ++j)
        if (e[j] != HP_OK) return *bad = j, e[j];
    return HP_OK;
}

hp_error hp_head_center_from_touch(const hp_head *h, const double p[3], double Ro, double preload,
                                   double center[3], hp_diag *diag)
{
    if (!h || !p || !center) return hp_diag_set(diag, HP_ERR_NULL, "touch: NULL argument");
    hp_error err = hpi_kin_head_validate(h, diag);
    if (err) return err;
    if (!hpi_kin_finite3(p)) return hp_diag_set(diag, HP_ERR_INVALID, "touch: must be finite");
    if (!(Ro > 0) || !isfinite(Ro))
        return hp_diag_set(diag, HP_ERR_INVALID, "Ro: must be finite and > 0 (got %g m)", Ro);
    if (!isfinite(preload) || !(Ro + preload > 0))
        return hp_diag_set(diag, HP_ERR_INVALID, "preload: must be finite and > -Ro (got %g m)",
                           preload);
    double m[3], F = -1.0;
    for (int i = 0; i < 3; ++i) {
        double a = h->shape == HP_HEAD_SPHERE ? h->semi_axes[0] : h->semi_axes[i];
        double u = (p[i] - h->center[i]) / a;
        F += u * u;
        m[i] = u / a;
    }
    if (!(fabs(F) <= 1e-9))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "touch: point is not on the head surface (implicit function %.3g, "
                           "tolerance 1e-9)",
                           F);
    double mn = hypot(hypot(m[0], m[1]), m[2]);
    for (int i = 0; i < 3; ++i) center[i] = p[i] + (Ro + preload) * (m[i] / mn);
    return HP_OK;
}
