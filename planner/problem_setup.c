/* Limits as radius bounds, commanded directions, scaled contact evaluation. */
#include "planner/problem_setup.h"

#include <math.h>
#include <string.h>

/* Moves ri up (dir > 0) or down until pred holds; FK roots sit within a few ulps of the
 * exact radius, so a few widening steps always suffice. Returns 0 when it could not. */
static int nudge_lo(const hp_iab *b, double *ri, double p_min)
{
    double r = *ri, step = fabs(r) * 1e-16;
    for (int i = 0; i < 80; ++i) {
        double P;
        if (hp_iab_ik(b, r, &P) == HP_OK && P >= p_min) {
            *ri = r;
            return 1;
        }
        r += step;
        step *= 2.0;
    }
    return 0;
}

static int nudge_hi(const hp_iab *b, double *ri, double p_max)
{
    double r = *ri, step = fabs(r) * 1e-16;
    for (int i = 0; i < 80; ++i) {
        double P;
        if (hp_iab_ik(b, r, &P) == HP_OK && P <= p_max) {
            *ri = r;
            return 1;
        }
        r -= step;
        step *= 2.0;
    }
    return 0;
}

/* Tightest of two bounds with their flags; equal bounds keep both flags. */
static void take_max(double *v, unsigned *f, double cand, unsigned cf)
{
    if (cand > *v) {
        *v = cand;
        *f = cf;
    } else if (cand == *v) {
        *f |= cf;
    }
}

static void take_min(double *v, unsigned *f, double cand, unsigned cf)
{
    if (cand < *v) {
        *v = cand;
        *f = cf;
    } else if (cand == *v) {
        *f |= cf;
    }
}

hp_error hp_setup_static_bounds(const hp_layout *L, hp_static_bounds *b, hp_diag *d)
{
    if (!L || !b) return hp_diag_set(d, HP_ERR_NULL, "layout or bounds is NULL");
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        const hp_iab *m = &B->iab;
        hp_iab_limit lp;
        hp_error e = hp_iab_limit_point(m, &lp);
        if (e != HP_OK)
            return hp_diag_set(d, e, "bladder %s: limit point: %s", B->name,
                               hp_error_message(e));
        double lo = B->stretch_min * m->Ri, hi = B->stretch_max * m->Ri;
        unsigned lof = HP_BIND_STRETCH_MIN, hif = HP_BIND_STRETCH_MAX;
        if (lp.exists) take_min(&hi, &hif, lp.ri * (1.0 - HP_STABLE_MARGIN), HP_BIND_LIMIT_POINT);
        double rs; /* the hoop-stress limit as a radius bound (monotone: iab/iab_stress.c) */
        if (B->stress_max > 0 && isfinite(B->stress_max) && hi > m->Ri &&
            hp_iab_stress_radius(m, B->stress_max, hi, &rs) == HP_OK)
            take_min(&hi, &hif, rs, HP_BIND_STRESS_MAX);

        double r;
        e = hp_iab_fk(m, B->p_min, &r);
        if (e != HP_OK)
            return hp_diag_set(d, HP_ERR_INVALID,
                               "bladder %s: pressure_min %.6g Pa has no stable radius (%s)",
                               B->name, B->p_min, hp_error_message(e));
        take_max(&lo, &lof, r, HP_BIND_PRESSURE_MIN);
        if (!lp.exists || B->p_max < lp.pressure) {
            e = hp_iab_fk(m, B->p_max, &r);
            if (e == HP_OK) take_min(&hi, &hif, r, HP_BIND_PRESSURE_MAX);
            else if (e != HP_ERR_NO_STABLE)
                return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: pressure_max %.6g Pa: %s",
                                   B->name, B->p_max, hp_error_message(e));
        }
        /* FK roots are exact to a few ulps; make the pressure bounds hold exactly. */
        if ((lof & HP_BIND_PRESSURE_MIN) && !nudge_lo(m, &lo, B->p_min))
            return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: pressure_min bound", B->name);
        if ((hif & HP_BIND_PRESSURE_MAX) && !nudge_hi(m, &hi, B->p_max))
            return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: pressure_max bound", B->name);
        double plo, phi;
        if (!(lo < hi) || hp_iab_ik(m, lo, &plo) != HP_OK || hp_iab_ik(m, hi, &phi) != HP_OK)
            return hp_diag_set(d, HP_ERR_INVALID,
                               "bladder %s: the pressure and stretch limits leave no stable "
                               "radius (ri %.6g..%.6g mm)",
                               B->name, lo * HP_MM_PER_M, hi * HP_MM_PER_M);
        /* Pressures are returned clamped into [p_lo, p_hi] c [p_min, p_max]. */
        b->limit[k] = lp;
        b->ri_lo[k] = lo;
        b->ri_hi[k] = hi;
        b->lo_flags[k] = lof;
        b->hi_flags[k] = hif;
        b->p_lo[k] = plo > B->p_min ? plo : B->p_min;
        b->p_hi[k] = phi < B->p_max ? phi : B->p_max;
    }
    return HP_OK;
}

hp_error hp_setup_cycle_bounds(const hp_layout *L, const hp_static_bounds *b,
                               const double *p_prev, int use_rate, hp_problem *pb,
                               unsigned *lo_flags, unsigned *hi_flags, hp_diag *d)
{
    for (int k = 0; k < L->n; ++k) {
        const hp_bladder *B = &L->bladders[k];
        double lo = b->ri_lo[k], hi = b->ri_hi[k];
        unsigned lof = b->lo_flags[k], hif = b->hi_flags[k];
        if (use_rate && p_prev && isfinite(B->rate_max)) {
            double r, pl = p_prev[k] - B->rate_max, ph = p_prev[k] + B->rate_max;
            if (pl > b->p_lo[k]) {
                if (hp_iab_fk_limit(&B->iab, &b->limit[k], pl, &r) == HP_OK && nudge_lo(&B->iab, &r, pl))
                    take_max(&lo, &lof, r, HP_BIND_RATE_DOWN);
                else
                    return hp_diag_set(d, HP_ERR_INVALID,
                                       "bladder %s: rate limit: no stable radius at %.6g Pa",
                                       B->name, pl);
            }
            if (ph < b->p_hi[k]) {
                if (hp_iab_fk_limit(&B->iab, &b->limit[k], ph, &r) == HP_OK && nudge_hi(&B->iab, &r, ph))
                    take_min(&hi, &hif, r, HP_BIND_RATE_UP);
                else
                    return hp_diag_set(d, HP_ERR_INVALID,
                                       "bladder %s: rate limit: no stable radius at %.6g Pa",
                                       B->name, ph);
            }
        }
        double rol, roh;
        if (!(lo <= hi) || hp_iab_ro(&B->iab, lo, &rol) != HP_OK ||
            hp_iab_ro(&B->iab, hi, &roh) != HP_OK)
            return hp_diag_set(d, HP_ERR_INVALID,
                               "bladder %s: the rate limit around %.6g Pa leaves no radius "
                               "inside the pressure and stretch limits",
                               B->name, p_prev ? p_prev[k] : 0.0);
        pb->ri_lo[k] = lo * HP_MM_PER_M;
        pb->ri_hi[k] = hi * HP_MM_PER_M;
        pb->ro_lo[k] = rol * HP_MM_PER_M;
        pb->ro_hi[k] = roh * HP_MM_PER_M;
        if (lo_flags) lo_flags[k] = lof;
        if (hi_flags) hi_flags[k] = hif;
    }
    return HP_OK;
}

hp_error hp_setup_contact_scaled(const hp_layout *L, hp_level level, const double x[6],
                                 double *rho_mm, double *J_s)
{
    double xi[6], J[HP_MAX_BLADDERS * 6];
    for (int i = 0; i < 3; ++i) {
        xi[i] = x[i] / HP_MM_PER_M;
        xi[i + 3] = x[i + 3] / HP_DEG_PER_RAD;
    }
    hp_error e = hp_contact_eval(L, level, xi, rho_mm, J_s ? J : NULL, NULL);
    if (e != HP_OK) return e;
    for (int k = 0; k < L->n; ++k) {
        rho_mm[k] *= HP_MM_PER_M;
        if (!isfinite(rho_mm[k])) return HP_ERR_DOMAIN;
        if (!J_s) continue;
        for (int i = 0; i < 3; ++i) {
            J_s[k * 6 + i] = J[k * 6 + i];                                 /* mm/mm */
            J_s[k * 6 + i + 3] = J[k * 6 + i + 3] * HP_MM_PER_M / HP_DEG_PER_RAD; /* mm/deg */
        }
    }
    return HP_OK;
}

/* Singular values of the m×c matrix A (row-major, leading dimension 6; destroyed) by
 * one-sided Jacobi: rotate column pairs until all are orthogonal; the norms are the
 * singular values. */
static void jacobi_sv(double *A, int m, int c, double *sv)
{
    for (int sweep = 0; sweep < 60; ++sweep) {
        double off = 0.0;
        for (int p = 0; p < c; ++p)
            for (int q = p + 1; q < c; ++q) {
                double a = 0, bb = 0, g = 0;
                for (int i = 0; i < m; ++i) {
                    a += A[i * 6 + p] * A[i * 6 + p];
                    bb += A[i * 6 + q] * A[i * 6 + q];
                    g += A[i * 6 + p] * A[i * 6 + q];
                }
                if (g == 0.0 || fabs(g) <= 1e-15 * sqrt(a * bb)) continue;
                off = fmax(off, fabs(g) / sqrt(a * bb));
                double zeta = (bb - a) / (2.0 * g);
                double t = (zeta >= 0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
                double cs = 1.0 / sqrt(1.0 + t * t), sn = cs * t;
                for (int i = 0; i < m; ++i) {
                    double u = A[i * 6 + p], v = A[i * 6 + q];
                    A[i * 6 + p] = cs * u - sn * v;
                    A[i * 6 + q] = sn * u + cs * v;
                }
            }
        if (off <= 1e-15) break;
    }
    for (int p = 0; p < c; ++p) {
        double s = 0;
        for (int i = 0; i < m; ++i) s += A[i * 6 + p] * A[i * 6 + p];
        sv[p] = sqrt(s);
    }
}

/* Numerical rank of the columns of J_s (n×6) selected by keep[]; tol is absolute. */
static int rank_of(const double *J_s, int n, const int keep[6], double tol)
{
    double A[HP_MAX_BLADDERS * 6], sv[6];
    int c = 0;
    for (int j = 0; j < 6; ++j) {
        if (!keep[j]) continue;
        for (int i = 0; i < n; ++i) A[i * 6 + c] = J_s[i * 6 + j];
        ++c;
    }
    if (c == 0) return 0;
    jacobi_sv(A, n, c, sv);
    int r = 0;
    for (int j = 0; j < c; ++j) r += sv[j] > tol;
    return r;
}

hp_error hp_setup_commanded(const hp_layout *L, hp_level level, int commanded[6],
                            hp_diag *d)
{
    double x0[6] = {0}, rho[HP_MAX_BLADDERS], J_s[HP_MAX_BLADDERS * 6];
    hp_error e = hp_setup_contact_scaled(L, level, x0, rho, J_s);
    if (e != HP_OK)
        return hp_diag_set(d, e, "contact model at the nominal pose: %s", hp_error_message(e));
    double A[HP_MAX_BLADDERS * 6], sv[6];
    memcpy(A, J_s, sizeof(double) * 6 * (size_t)L->n);
    jacobi_sv(A, L->n, 6, sv);
    double smax = 0;
    for (int j = 0; j < 6; ++j) smax = fmax(smax, sv[j]);
    if (!(smax > 0)) return hp_diag_set(d, HP_ERR_INVALID, "layout: the contact Jacobian is zero");
    double tol = 1e-9 * smax;
    for (int j = 0; j < 6; ++j) commanded[j] = 1;
    int rank = rank_of(J_s, L->n, commanded, tol);
    /* Rotations first (a sphere head's rotations are the natural unobservable ones). */
    static const int order[6] = {HP_YAW, HP_ROLL, HP_PITCH, HP_Z, HP_Y, HP_X};
    int dropped = 0;
    for (int t = 0; t < 6 && dropped < 6 - rank; ++t) {
        commanded[order[t]] = 0;
        if (rank_of(J_s, L->n, commanded, tol) == rank) ++dropped;
        else commanded[order[t]] = 1;
    }
    return HP_OK;
}

hp_error hp_setup_bladder_from_ro(const hp_bladder *B, double ro, double ri_lo, double ri_hi,
                                  double p_lo, double p_hi, hp_bladder_result *out,
                                  int *clamped)
{
    double ri, P;
    int c = 0;
    if (!isfinite(ro)) return HP_ERR_INVALID;
    hp_error e = hp_iab_ri(&B->iab, ro, &ri);
    if (e != HP_OK) {
        ri = ri_lo; /* collapsed cavity: the lower bound is the nearest valid radius */
        c = 1;
    }
    if (ri < ri_lo) { ri = ri_lo; c = 1; }
    if (ri > ri_hi) { ri = ri_hi; c = 1; }
    if (c && hp_iab_ro(&B->iab, ri, &ro) != HP_OK) return HP_ERR_DOMAIN;
    e = hp_iab_ik(&B->iab, ri, &P);
    if (e != HP_OK || !isfinite(P)) return HP_ERR_DOMAIN;
    if (P < p_lo) P = p_lo;
    if (P > p_hi) P = p_hi;
    out->ri = ri;
    out->ro = ro;
    out->pressure = P;
    out->stretch = ri / B->iab.Ri;
    out->binding = 0;
    if (clamped) *clamped = c;
    return HP_OK;
}
