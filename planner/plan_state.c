/* The planner's state between plans, shared by its lifecycle (planner.c) and its plan
 * (plan.c): pose scaling, the answer of a pose, the fit from the nominal pose and the
 * previous answer. */
#include "planner/planner_internal.h"
#include "common/minmax.h"
#include "common/same_bits.h"
#include "common/test_count.h"

#include <math.h>
#include <stdatomic.h>
#include <string.h>

static atomic_ulong answer_rows;
static atomic_int answer_memo_off;

unsigned long hpi_test_answer_rows(void) { return atomic_load(&answer_rows); }
void hpi_test_answer_memo(int on) { atomic_store(&answer_memo_off, !on); }

void hpi_plan_to_scaled(const double xi[6], double x[6])
{
    for (int i = 0; i < 6; ++i) x[i] = xi[i] * hpi_pose_scaled_per_si(i);
}

void hpi_plan_from_scaled(const double x[6], double xi[6]) { hpi_setup_pose_from_scaled(x, xi); }

/* 1 when the memo holds the rows of these distances rho [mm] and radius bounds. The first
 * distance decides most misses (a new answer moves every bladder). */
static int memo_holds(const hp_answer_memo *m, const double *rho, const double *lo,
                      const double *hi, int n)
{
    if (!m->ok) return 0;
    int k = 0;
    while (k < n && hpi_same_bits(&m->rho[k], &rho[k], 1) &&
           hpi_same_bits(&m->ri_lo[k], &lo[k], 1) && hpi_same_bits(&m->ri_hi[k], &hi[k], 1))
        ++k;
    return k == n;
}

/* Bladder k's pressure window in this plan: its limits, within the rate window around the
 * previous pressure (a reading's, derived or not; the plan's, hp_problem.w_lo) when rate
 * limits apply; w (may be NULL) receives that rate window ([-inf, inf] without one). */
static inline void row_window(const hp_planner *p, int k, double *plo, double *phi, double *w)
{
    *plo = p->sb.p_lo[k];
    *phi = p->sb.p_hi[k];
    double wl = -INFINITY, wh = INFINITY;
    if (!p->rate_free) {
        wl = p->pb.w_lo[k];
        wh = p->pb.w_hi[k];
        /* No operand is a NaN here (static limits, a window around a finite pressure or
         * [-inf, inf]): a compare and a select, not two library calls on every bladder of
         * every rate-limited plan. On equal values both return the second operand, as
         * glibc's x86-64 fmax/fmin (maxsd/minsd) do, so the window is the same bits there
         * (another libm may give the other sign of a zero limit: the same value). */
        *plo = hpi_max2(*plo, wl);
        *phi = hpi_min2(*phi, wh);
    }
    if (w) {
        w[0] = wl;
        w[1] = wh;
    }
}

/* The rest of bladder k's row br (its pressure in its window) at distance rho_mm: the
 * radius correction (c: its inner radius was clamped), the binding flags, and 0 when it
 * left a limit or was not finite. */
static inline int row_finish(const hp_planner *p, int k, hp_bladder_result *br, int c,
                             double rho_mm, double *clamp_mm)
{
    const hp_bladder *B = &p->L.bladders[k];
    if (c) *clamp_mm = fmax(*clamp_mm, fabs(br->ro * HP_MM_PER_M - rho_mm));
    double ro_mm = br->ro * HP_MM_PER_M;
    if (ro_mm <= p->pb.ro_lo[k] + HP_BINDING_TOL_MM) br->binding |= p->lo_flags[k];
    if (ro_mm >= p->pb.ro_hi[k] - HP_BINDING_TOL_MM) br->binding |= p->hi_flags[k];
    return br->pressure >= B->p_min && br->pressure <= B->p_max && isfinite(br->ri) &&
           isfinite(br->ro);
}

/* The answer from the memo's rows: this plan's windows, flags and checks. */
static int answer_from_memo(hp_planner *p, const double x[6], const double *rho, hp_result *res,
                            double *clamp_mm)
{
    const hp_answer_memo *m = &p->ans_memo;
    for (int k = 0; k < p->L.n; ++k) {
        double plo, phi;
        row_window(p, k, &plo, &phi, NULL);
        hp_bladder_result *br = &res->bladders[k];
        *br = m->res[k];
        br->pressure = hpi_setup_pressure_in(br->pressure, plo, phi);
        if (!row_finish(p, k, br, m->clamped[k], rho[k], clamp_mm)) return 0;
    }
    hpi_plan_from_scaled(x, res->achieved);
    return 1;
}

/* Bladder k's inner radius for its outer radius rho_mm [mm], clamped into this plan's
 * bounds (*clamped says so): the first half of a row, answer_eval's and the look's. */
static inline hp_error row_ri(const hp_planner *p, int k, double rho_mm, double *ri, int *clamped)
{
    return hpi_setup_ri_from_ro_s(&p->sb.iab_s[k], rho_mm / HP_MM_PER_M, p->pb.ri_lo_si[k],
                                  p->pb.ri_hi_si[k], ri, clamped);
}

/* The row's second half: bladder k's pressure (clamped into [plo, phi]) and radii from ri. */
static inline hp_error row_pressure(const hp_planner *p, int k, double rho_mm, double ri,
                                    int clamped, double plo, double phi, hp_bladder_result *br)
{
    return hpi_setup_bladder_from_ri_s(&p->L.bladders[k], &p->sb.iab_s[k], rho_mm / HP_MM_PER_M, ri,
                                       clamped, plo, phi, br);
}

/* The answer evaluated from the distances rho [mm]: every bladder's inner radius first,
 * then the pressures (each half is a chain of roots and divisions, and back to back the
 * processor overlaps one bladder's chain with the next one's: the same bits as one pass).
 * hold (may be NULL): where each pressure before its window and clamp flag are held for
 * hpi_plan_answer_keep. Called with hold NULL, it is specialised without them (the answers
 * of every solve). */
static inline int answer_eval(hp_planner *p, const double x[6], const double *rho,
                              hp_answer_memo *hold, hp_result *res, double *clamp_mm)
{
    const int n = p->L.n;
    hpi_count(&answer_rows, (unsigned long)n);
    double ri[HP_MAX_BLADDERS];
    int clamped[HP_MAX_BLADDERS];
    for (int k = 0; k < n; ++k)
        if (row_ri(p, k, rho[k], &ri[k], &clamped[k]) != HP_OK) return 0;
    for (int k = 0; k < n; ++k) {
        double plo, phi;
        row_window(p, k, &plo, &phi, NULL);
        hp_bladder_result *br = &res->bladders[k];
        /* A row held is the row before any window; the clamp after is the one the call
         * makes. */
        if (row_pressure(p, k, rho[k], ri[k], clamped[k], hold ? -INFINITY : plo,
                         hold ? INFINITY : phi, br) != HP_OK)
            return 0;
        if (hold) {
            hold->res[k].pressure = br->pressure;
            hold->clamped[k] = (unsigned char)clamped[k];
            br->pressure = hpi_setup_pressure_in(br->pressure, plo, phi);
        }
        if (!row_finish(p, k, br, clamped[k], rho[k], clamp_mm)) return 0;
    }
    hpi_plan_from_scaled(x, res->achieved);
    return 1;
}

int hpi_plan_direct_left(hp_planner *p, const double *rho)
{
    unsigned near;
    if (hpi_setup_rate_surely_left(&p->L, &p->sb, p->pb.p_prev, rho, 2.0 * HP_BINDING_TOL_MM,
                                   &near))
        return 1;
    /* A radius within a knot spacing of a window's end: its row alone (answer_eval's calls,
     * so its bits) tells whether the answer would be discarded for it. A row that fails or
     * leaves a limit stops the look: the answer is built and refused as before. */
    for (int k = 0; near; ++k, near >>= 1) {
        if (!(near & 1u)) continue;
        double ri, plo, phi, w[2], clamp_mm = 0;
        int clamped;
        hp_bladder_result br;
        row_window(p, k, &plo, &phi, w);
        br.binding = 0;
        if (row_ri(p, k, rho[k], &ri, &clamped) != HP_OK ||
            row_pressure(p, k, rho[k], ri, clamped, plo, phi, &br) != HP_OK ||
            !row_finish(p, k, &br, clamped, rho[k], &clamp_mm))
            return 0;
        if (!hpi_setup_rate_clear_row(&p->sb, k, w[0], w[1], br.pressure)) return 1;
    }
    return 0;
}

int hpi_plan_answer_from_pose(hp_planner *p, const double x[6], const double *rho_known, int direct,
                              hp_result *res, double *clamp_mm)
{
    double rho[HP_MAX_BLADDERS];
    *clamp_mm = 0;
    if (rho_known) memcpy(rho, rho_known, sizeof(double) * (size_t)p->L.n);
    else if (hpi_setup_contact_scaled(&p->L, &p->G, p->level, x, rho, NULL) != HP_OK) return 0;
    hp_answer_memo *m = &p->ans_memo;
    m->pending = 0;
    if (!direct || atomic_load_explicit(&answer_memo_off, memory_order_relaxed))
        return answer_eval(p, x, rho, NULL, res, clamp_mm);
    /* Rows whose distances and radius bounds the discarded answer had, bit for bit, are its
     * rows (hp_answer_memo): only the windows are this plan's. */
    if (memo_holds(m, rho, p->pb.ri_lo_si, p->pb.ri_hi_si, p->L.n))
        return answer_from_memo(p, x, rho, res, clamp_mm);
    m->ok = 0; /* its pressures are overwritten */
    if (!answer_eval(p, x, rho, m, res, clamp_mm)) return 0;
    m->pending = 1;
    return 1;
}

void hpi_plan_answer_keep(hp_planner *p, const double *rho, const hp_result *res)
{
    hp_answer_memo *m = &p->ans_memo;
    if (!m->pending) return;
    for (int k = 0; k < p->L.n; ++k) {
        m->rho[k] = rho[k];
        m->ri_lo[k] = p->pb.ri_lo_si[k];
        m->ri_hi[k] = p->pb.ri_hi_si[k];
        /* ri, ro and stretch are the row's own; the pressure held is before the window. */
        const hp_bladder_result *br = &res->bladders[k];
        m->res[k].ri = br->ri;
        m->res[k].ro = br->ro;
        m->res[k].stretch = br->stretch;
        m->res[k].binding = 0;
    }
    m->pending = 0;
    m->ok = 1;
}

hp_error hpi_plan_fit_from_nominal(const hp_planner *p, const double *ro, const int free_[6],
                                   const hp_kin_fit_near *near, double xi[6], double *residual_rms)
{
    /* With fk_free: hp_contact_fk's own checks, so this is a drop-in for it. */
    if (free_ == p->fk_free) {
        int nf = 0;
        for (int i = 0; i < 6; ++i) nf += free_[i] != 0;
        if (p->L.n < nf) return HP_ERR_INVALID;
        for (int k = 0; k < p->L.n; ++k)
            if (!(ro[k] > 0) || !isfinite(ro[k])) return HP_ERR_INVALID;
    }
    const double zero[6] = {0};
    return hpi_kin_fit(&p->L, &p->G, p->level, ro, free_, zero, p->nom_ok ? &p->nom : NULL, near,
                       xi, residual_rms, NULL);
}

void hpi_plan_set_previous_answer(hp_planner *p, const hp_result *r)
{
    if (r != &p->prev) p->prev = *r;
    p->prev_checked = 1; /* hp_planner_set_previous clears it after this call */
    p->meas_pending = 0;
    hpi_plan_to_scaled(r->achieved, p->x_prev);
    for (int k = 0; k < p->L.n; ++k) p->x_prev[6 + k] = r->bladders[k].ri * HP_MM_PER_M;
    for (int k = 0; k < p->L.n; ++k) p->pb.p_prev[k] = r->bladders[k].pressure;
    /* The next start is this answer's pose and radii, not a backend's own last point. */
    if (p->ops && p->ops->warm_point && p->bstate) p->ops->warm_point(p->bstate, 0);
}
