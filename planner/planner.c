/* The planner core: create/destroy, the direct chain, the backend call through its table,
 * and the checks every answer passes before it is returned (see hp_planner.h). */
#define _POSIX_C_SOURCE 200809L
#include "planner/backend_common.h"
#include "planner/problem_setup.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Largest correction hp_plan accepts: far beyond any bladder's reach, small enough that
 * every contact model stays well defined. */
#define HP_PLAN_MAX_TRANS 1.0                /* [m] */
#define HP_PLAN_MAX_ROT 3.14159265358979324 /* [rad] */
/* A reached pose counts as identified when forward contact kinematics started from the
 * nominal pose recovers it to HP_IDENT_FK_TOL (mm and degrees): far above the fit's own
 * precision on a well-posed layout (~1e-12), far below the distance of any second fit seen
 * (0.8 degrees on the near-degenerate layout at the plane level). A pivot far away makes
 * the pose coordinates themselves ill-conditioned (1 km: ~1e-6 mm/deg of rounding), so a
 * fit that meets the contact distances to HP_IDENT_FIT_MM and lies within HP_IDENT_SAME of
 * the pose is the same pose: another pose with the same distances would be a symmetric
 * copy (>= 90 degrees away) or a second fit (0.8 degrees). */
#define HP_IDENT_FK_TOL 1e-7
#define HP_IDENT_FIT_MM 1e-8 /* 100x the rounding of distances computed with a 1 km lever;
                                 the second fit above misses them by 5.6e-5 mm */
#define HP_IDENT_SAME 1e-3
/* Largest RMS contact residual [mm] of clamped radii that still counts as holding a pose:
 * 100× above the solvers' own contact slop (1e-9 mm tolerance, bounds kept exactly), far
 * below anything physical. */
#define HP_CLAMP_RESID_MM 1e-6

struct hp_planner {
    hp_layout L;                 /* private, prepared copy */
    hp_settings s;
    hp_level level;
    hp_identifiable id;          /* what the layout can tell apart (hp_layout_identify) */
    int commanded[6];            /* = id.commanded */
    hp_static_bounds sb;
    hp_problem pb;
    unsigned lo_flags[HP_MAX_BLADDERS], hi_flags[HP_MAX_BLADDERS];
    const hp_backend_ops *ops;
    void *bstate;
    int built;
    hp_result nominal;           /* safe output after create / reset */
    hp_result prev;              /* last valid answer: the safe output */
    double x_prev[HP_PROBLEM_NX_MAX];
    double x_work[HP_PROBLEM_NX_MAX];
    char err[HP_DIAG_MAX];
    hp_diag diag;
};

static const hp_backend_ops *backend_table(hp_backend b)
{
    switch (b) {
    case HP_BACKEND_REALTIME: return &hp_backend_realtime_ops;
    case HP_BACKEND_IPOPT: return &hp_backend_ipopt_ops;
    case HP_BACKEND_NLOPT_SLSQP: return &hp_backend_nlopt_slsqp_ops;
    case HP_BACKEND_NLOPT_COBYLA: return &hp_backend_nlopt_cobyla_ops;
    default: return NULL;
    }
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Message building without printf (hp_plan must not allocate; printf's float formatting
 * may). */
static void err_set(hp_planner *p, const char *s)
{
    size_t n = strlen(s);
    if (n >= sizeof p->err) n = sizeof p->err - 1;
    memcpy(p->err, s, n);
    p->err[n] = '\0';
}

static void err_add(hp_planner *p, const char *s)
{
    size_t have = strlen(p->err), n = strlen(s);
    if (have + n >= sizeof p->err) n = sizeof p->err - 1 - have;
    memcpy(p->err + have, s, n);
    p->err[have + n] = '\0';
}

/* Appends a decimal integer (no printf: see err_set). */
static void err_add_int(hp_planner *p, long long v)
{
    char buf[32], *q = buf + sizeof buf - 1;
    unsigned long long u = v < 0 ? 0ull - (unsigned long long)v : (unsigned long long)v;
    *q = '\0';
    do {
        *--q = (char)('0' + u % 10u);
        u /= 10u;
    } while (u);
    if (v < 0) *--q = '-';
    err_add(p, q);
}

static void to_scaled(const double xi[6], double x[6])
{
    for (int i = 0; i < 3; ++i) {
        x[i] = xi[i] * HP_MM_PER_M;
        x[i + 3] = xi[i + 3] * HP_DEG_PER_RAD;
    }
}

static void from_scaled(const double x[6], double xi[6])
{
    for (int i = 0; i < 3; ++i) {
        xi[i] = x[i] / HP_MM_PER_M;
        xi[i + 3] = x[i + 3] / HP_DEG_PER_RAD;
    }
}

/* Fills res from a scaled pose x: contact distances at the planner's level, radii,
 * pressures (clamped into this cycle's limits), binding flags and achieved pose. Returns 0
 * when something was not finite. clamp_mm receives the largest radius correction. */
static int answer_from_pose(hp_planner *p, const double x[6], hp_result *res,
                            double *clamp_mm)
{
    double rho[HP_MAX_BLADDERS];
    *clamp_mm = 0;
    if (hp_setup_contact_scaled(&p->L, p->level, x, rho, NULL) != HP_OK) return 0;
    for (int k = 0; k < p->L.n; ++k) {
        const hp_bladder *B = &p->L.bladders[k];
        double ri_lo = p->pb.ri_lo_si[k], ri_hi = p->pb.ri_hi_si[k];
        double plo = p->sb.p_lo[k], phi = p->sb.p_hi[k];
        if (p->s.use_rate_limits && isfinite(B->rate_max)) {
            plo = fmax(plo, p->prev.bladders[k].pressure - B->rate_max);
            phi = fmin(phi, p->prev.bladders[k].pressure + B->rate_max);
        }
        int c = 0;
        hp_bladder_result *br = &res->bladders[k];
        if (hp_setup_bladder_from_ro(B, rho[k] / HP_MM_PER_M, ri_lo, ri_hi, plo, phi, br, &c) !=
            HP_OK)
            return 0;
        if (c) *clamp_mm = fmax(*clamp_mm, fabs(br->ro * HP_MM_PER_M - rho[k]));
        double ro_mm = br->ro * HP_MM_PER_M;
        if (ro_mm <= p->pb.ro_lo[k] + HP_BINDING_TOL_MM) br->binding |= p->lo_flags[k];
        if (ro_mm >= p->pb.ro_hi[k] - HP_BINDING_TOL_MM) br->binding |= p->hi_flags[k];
        if (!(br->pressure >= B->p_min && br->pressure <= B->p_max) || !isfinite(br->ri) ||
            !isfinite(br->ro))
            return 0;
    }
    from_scaled(x, res->achieved);
    return 1;
}

static void pose_error(hp_planner *p, hp_result *res, const double d[6])
{
    double a[6];
    to_scaled(res->achieved, a);
    res->pose_error = 0;
    for (int i = 0; i < 6; ++i)
        if (p->commanded[i]) res->pose_error = fmax(res->pose_error, fabs(a[i] - d[i]));
}

/* The nominal pose's answer: the first safe output. */
static hp_error build_nominal(hp_planner *p, hp_diag *d)
{
    hp_result *r = &p->nominal;
    memset(r, 0, sizeof *r);
    r->status = HP_STATUS_REACHED;
    r->backend = p->s.backend;
    r->level = p->level;
    r->n = p->L.n;
    for (int i = 0; i < 6; ++i) r->commanded[i] = p->commanded[i];
    double x0[6] = {0}, rho[HP_MAX_BLADDERS];
    if (hp_setup_contact_scaled(&p->L, p->level, x0, rho, NULL) != HP_OK)
        return hp_diag_set(d, HP_ERR_INVALID, "layout: contact model fails at the nominal pose");
    for (int k = 0; k < p->L.n; ++k) {
        int c = 0;
        if (hp_setup_bladder_from_ro(&p->L.bladders[k], rho[k] / HP_MM_PER_M, p->sb.ri_lo[k],
                                     p->sb.ri_hi[k], p->sb.p_lo[k], p->sb.p_hi[k],
                                     &r->bladders[k], &c) != HP_OK)
            return hp_diag_set(d, HP_ERR_INVALID, "bladder %s: no valid state at the nominal pose",
                               p->L.bladders[k].name);
    }
    /* When a limit excludes the nominal radii, the clamped radii hold some other pose. */
    double ro[HP_MAX_BLADDERS], xi[6], resid;
    for (int k = 0; k < p->L.n; ++k) ro[k] = r->bladders[k].ro;
    if (hp_contact_fk(&p->L, p->level, ro, NULL, xi, &resid, NULL) == HP_OK) {
        for (int i = 0; i < 6; ++i) r->achieved[i] = p->commanded[i] ? xi[i] : 0.0;
    }
    for (int k = 0; k < p->L.n; ++k) r->bladders[k].binding = 0;
    return HP_OK;
}

static void set_prev_x(hp_planner *p, const hp_result *r)
{
    to_scaled(r->achieved, p->x_prev);
    for (int k = 0; k < p->L.n; ++k) p->x_prev[6 + k] = r->bladders[k].ri * HP_MM_PER_M;
    for (int k = 0; k < p->L.n; ++k) p->pb.p_prev[k] = r->bladders[k].pressure;
}

void hp_planner_reset(hp_planner *p)
{
    if (!p || !p->built) return;
    p->prev = p->nominal;
    set_prev_x(p, &p->prev);
}

hp_error hp_planner_create(const hp_layout *layout, const hp_settings *settings,
                           hp_planner **out, hp_diag *d)
{
    if (out) *out = NULL;
    if (!layout || !out) return hp_diag_set(d, HP_ERR_NULL, "layout or out is NULL");
    hp_settings s;
    if (settings) s = *settings;
    else hp_settings_default(&s);
    hp_error e = hp_settings_validate(&s, d);
    if (e != HP_OK) return e;
    const hp_backend_ops *ops = backend_table(s.backend);
    if (!ops || !ops->create || !ops->solve)
        return hp_diag_set(d, HP_ERR_INVALID, "backend: '%s' is not built into this library",
                           hp_backend_name(s.backend));

    hp_planner *p = calloc(1, sizeof *p);
    if (!p) return hp_diag_set(d, HP_ERR_NOMEM, "planner: out of memory");
    p->L = *layout;
    p->s = s;
    e = hp_layout_prepare(&p->L, d);
    if (e != HP_OK) goto fail;
    p->level = s.level;
    if (p->level == HP_LEVEL_AUTO) {
        e = hp_contact_auto(&p->L, s.level_tolerance, s.auto_trans, s.auto_rot, &p->level);
        if (e != HP_OK) {
            hp_diag_set(d, e, "level: auto could not choose a contact level (%s)",
                        hp_error_message(e));
            goto fail;
        }
    }
    if ((e = hp_layout_identify(&p->L, &p->id)) != HP_OK) {
        hp_diag_set(d, e, "layout: the contact Jacobian at the nominal pose: %s",
                    hp_error_message(e));
        goto fail;
    }
    memcpy(p->commanded, p->id.commanded, sizeof p->commanded);
    if ((e = hp_setup_static_bounds(&p->L, &p->sb, d)) != HP_OK) goto fail;

    hp_problem *pb = &p->pb;
    pb->layout = &p->L;
    pb->level = p->level;
    pb->n = p->L.n;
    pb->nx = 6 + p->L.n;
    for (int i = 0; i < 6; ++i) {
        double w = i < 3 ? 1.0 : 1.0 / (s.weight_mm_per_deg * s.weight_mm_per_deg);
        pb->w[i] = p->commanded[i] ? w : 0.0;
    }
    pb->mu = s.mu;
    if ((e = build_nominal(p, d)) != HP_OK) goto fail;
    p->prev = p->nominal;
    set_prev_x(p, &p->prev);
    e = hp_setup_cycle_bounds(&p->L, &p->sb, pb->p_prev, s.use_rate_limits, pb, p->lo_flags,
                              p->hi_flags, d);
    if (e != HP_OK) goto fail;
    p->ops = ops;
    e = ops->create(&p->bstate, pb, &s, d);
    if (e != HP_OK) goto fail;
    p->built = 1;
    *out = p;
    return HP_OK;
fail:
    hp_planner_destroy(p);
    return e;
}

void hp_planner_destroy(hp_planner *p)
{
    if (!p) return;
    if (p->ops && p->ops->destroy && p->bstate) p->ops->destroy(p->bstate);
    free(p);
}

const char *hp_planner_error(const hp_planner *p) { return p ? p->err : "planner is NULL"; }

hp_level hp_planner_level(const hp_planner *p) { return p ? p->level : HP_LEVEL_AUTO; }

const hp_layout *hp_planner_layout(const hp_planner *p) { return p ? &p->L : NULL; }

const hp_identifiable *hp_planner_identifiable(const hp_planner *p) { return p ? &p->id : NULL; }

hp_error hp_planner_set_previous(hp_planner *p, const double *pressures)
{
    if (!p) return HP_ERR_NULL;
    if (!pressures) {
        err_set(p, "set_previous: pressures is NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) return HP_ERR_STATE;
    hp_result r = p->nominal;
    double ro[HP_MAX_BLADDERS];
    for (int k = 0; k < p->L.n; ++k) {
        const hp_bladder *B = &p->L.bladders[k];
        double P = pressures[k], ri;
        if (!(P >= p->sb.p_lo[k] && P <= p->sb.p_hi[k])) {
            err_set(p, "set_previous: a pressure is outside its limits or not finite: ");
            err_add(p, B->name);
            return HP_ERR_INVALID;
        }
        if (hp_iab_fk_limit(&B->iab, &p->sb.limit[k], P, &ri) != HP_OK) {
            err_set(p, "set_previous: no stable radius for the pressure of ");
            err_add(p, B->name);
            return HP_ERR_INVALID;
        }
        /* The root of a pressure inside [p_lo, p_hi] lies inside [ri_lo, ri_hi] up to an
         * ulp or two: keep the stretch inside its limits to the last bit. */
        ri = fmin(fmax(ri, p->sb.ri_lo[k]), p->sb.ri_hi[k]);
        if (hp_iab_ro(&B->iab, ri, &ro[k]) != HP_OK) {
            err_set(p, "set_previous: no stable radius for the pressure of ");
            err_add(p, B->name);
            return HP_ERR_INVALID;
        }
        r.bladders[k].ri = ri;
        r.bladders[k].ro = ro[k];
        r.bladders[k].pressure = P;
        r.bladders[k].stretch = ri / B->iab.Ri;
        r.bladders[k].binding = 0;
    }
    double xi[6], resid;
    if (hp_contact_fk(&p->L, p->level, ro, NULL, xi, &resid, NULL) == HP_OK)
        for (int i = 0; i < 6; ++i) r.achieved[i] = p->commanded[i] ? xi[i] : 0.0;
    p->prev = r;
    set_prev_x(p, &p->prev);
    return HP_OK;
}

static const char *const pose_names[6] = {"x", "y", "z", "pitch", "roll", "yaw"};

/* The safe output: the previous valid answer, labelled with a failure status. */
static hp_error fail_safe(hp_planner *p, hp_result *res, hp_status st, double t0)
{
    double desired[6];
    memcpy(desired, res->desired, sizeof desired);
    *res = p->prev;
    memcpy(res->desired, desired, sizeof desired);
    res->status = st;
    res->iterations = 0;
    res->pose_error = INFINITY;
    for (int i = 0; i < 6; ++i) res->uncommanded[i] = 0.0;
    for (int k = 0; k < res->n; ++k) res->bladders[k].binding = 0;
    res->solve_time = now_s() - t0;
    return HP_OK;
}

/* Whether a backend's claimed optimum x (scaled, full program) meets the first-order
 * optimality conditions: contacts within max(10·tolerance, 1e-6) mm, radii inside their
 * bounds, stationarity and multiplier signs within 1e-3 of the gradient's scale. Checked for the NLopt backends, whose stopping tests (XTOL, FTOL)
 * say nothing about optimality; Ipopt stops on its own KKT test and the realtime QP on its
 * multipliers' signs. The check uses the minimum-norm multipliers, so at a degenerate vertex
 * it can refuse a true optimum: then the answer is labelled solver-error, never wrong. */
static int closest_verified(const hp_planner *p, const double *x)
{
    if (p->s.backend != HP_BACKEND_NLOPT_SLSQP && p->s.backend != HP_BACKEND_NLOPT_COBYLA)
        return 1;
    hp_kkt_measure m;
    if (hp_backend_kkt_measure(&p->pb, x, &m) != HP_OK) return 0;
    /* Loose on purpose: SLSQP's answers stop up to ~1e-5 mm/deg short and its multipliers
     * are not exact, while a stalled start point misses stationarity by O(1) of the
     * gradient; 1e-3 of the gradient's scale separates the two. */
    double feas = 10.0 * p->s.tolerance > 1e-6 ? 10.0 * p->s.tolerance : 1e-6;
    double stat = 1e-3 * (1.0 + m.grad_max);
    return m.in_bounds && m.feasibility <= feas && m.stationarity <= stat &&
           m.wrong_sign <= stat;
}

/* Appends |v| rounded to `dec` decimals, with its sign (no printf: see err_set). */
static void err_add_num(hp_planner *p, double v, int dec)
{
    double scale = 1.0;
    for (int i = 0; i < dec; ++i) scale *= 10.0;
    if (!(fabs(v) * scale < 1e15)) {
        err_add(p, v != v ? "nan" : "huge");
        return;
    }
    long long q = llround(fabs(v) * scale);
    if (v < 0 && q != 0) err_add(p, "-");
    long long ip = q;
    for (int i = 0; i < dec; ++i) ip /= 10;
    err_add_int(p, ip);
    if (dec > 0) {
        char frac[16];
        long long f = q;
        for (int i = dec - 1; i >= 0; --i) {
            frac[i] = (char)('0' + f % 10);
            f /= 10;
        }
        frac[dec] = '\0';
        err_add(p, ".");
        err_add(p, frac);
    }
}

/* 1 when desired lies in the identifiable range (hp_identifiable): translation norm up to
 * trans_limit, rotation angle below rot_limit; else 0 with the limit named in p->err. */
static int in_identifiable_range(hp_planner *p, const double desired[6])
{
    const hp_identifiable *id = &p->id;
    double tn = hypot(hypot(desired[0], desired[1]), desired[2]);
    if (!(tn <= id->trans_limit)) {
        err_set(p, "desired translation: |(x, y, z)| = ");
        err_add_num(p, tn * HP_MM_PER_M, 1);
        err_add(p, " mm is outside the identifiable range (<= ");
        err_add_num(p, id->trans_limit * HP_MM_PER_M, 1);
        err_add(p, " mm, the head's smallest semi-axis)");
        return 0;
    }
    double ang = hp_pose_rotation_angle(desired);
    if (!id->centre_only && !(ang < id->rot_limit)) {
        err_set(p, "desired rotation: angle ");
        err_add_num(p, ang * HP_DEG_PER_RAD, 1);
        err_add(p, " deg is outside the identifiable range (below ");
        err_add_num(p, id->rot_limit * HP_DEG_PER_RAD, 0);
        err_add(p, " deg: the head looks the same after ");
        err_add(p, id->symmetry);
        err_add(p, ", so the contact distances confuse such a turn with a smaller one)");
        return 0;
    }
    return 1;
}

/* 1 when the strict round trip of answer r gives xc back (HP_IDENT_FK_TOL): its pressures
 * -> stable radii -> outer radii -> forward contact kinematics in the commanded components
 * started from the NOMINAL pose. Else 0 with the other pose's distance in p->err. On a
 * near-degenerate layout at the plane level the fit from the nominal pose can end in a
 * second local fit; then the correction is not identified by this layout. Allocates
 * nothing. */
static int recovered_from_nominal(hp_planner *p, const hp_result *r, const double xc[6])
{
    /* The linear model is linear in the pose and the commanded columns have full column
     * rank (hp_layout_identify keeps exactly `rank` of them): the least-squares fit is
     * unique, so the fit from the nominal pose is the commanded part itself, to rounding.
     * The check would cost ~50 us of a ~10 us plan and could not fail. */
    if (p->level == HP_LEVEL_LINEAR) return 1;
    double ro[HP_MAX_BLADDERS], zero[6] = {0}, xf[6], a[6], b[6];
    for (int k = 0; k < p->L.n; ++k) {
        const hp_iab *m = &p->L.bladders[k].iab;
        double ri;
        if (hp_iab_fk_limit(m, &p->sb.limit[k], r->bladders[k].pressure, &ri) != HP_OK ||
            hp_iab_ro(m, ri, &ro[k]) != HP_OK)
            ro[k] = r->bladders[k].ro;
    }
    double resid = INFINITY;
    hp_error e = hp_contact_fit(&p->L, p->level, ro, p->commanded, zero, xf, &resid, NULL);
    to_scaled(xc, a);
    to_scaled(xf, b);
    double worst = e == HP_OK ? 0.0 : INFINITY;
    for (int i = 0; i < 6; ++i) worst = fmax(worst, fabs(a[i] - b[i]));
    if (worst <= HP_IDENT_FK_TOL) return 1;
    if (worst <= HP_IDENT_SAME && resid * HP_MM_PER_M <= HP_IDENT_FIT_MM) return 1;
    err_set(p, "desired: outside the identifiable range of this layout at the ");
    err_add(p, hp_level_name(p->level));
    err_add(p, " level: forward contact kinematics from the nominal pose finds another pose ");
    if (isfinite(worst)) {
        err_add_num(p, worst, 6);
        err_add(p, " mm/deg away with nearly the same contact distances");
    } else {
        err_add(p, "(it did not converge)");
    }
    return 0;
}

/* 1 when some bladder of r sits on a limit (HP_BINDING_TOL_MM). */
static int binds_any(const hp_result *r)
{
    for (int k = 0; k < r->n; ++k)
        if (r->bladders[k].binding) return 1;
    return 0;
}

/* 1 when some component of the part not commanded exceeds the pose tolerance (mm, deg). */
static int uncommanded_beyond(const hp_planner *p, const double unc[6])
{
    double u[6];
    to_scaled(unc, u);
    for (int i = 0; i < 6; ++i)
        if (fabs(u[i]) > p->s.tolerance) return 1;
    return 0;
}

/* Names the components of the part not commanded beyond the tolerance, with values. */
static void add_uncommanded(hp_planner *p, const double unc[6])
{
    double u[6];
    to_scaled(unc, u);
    err_add(p, "not commanded (the layout cannot observe it):");
    int first = 1;
    for (int i = 0; i < 6; ++i) {
        if (!(fabs(u[i]) > p->s.tolerance)) continue;
        err_add(p, first ? " " : ", ");
        err_add(p, pose_names[i]);
        err_add(p, " ");
        err_add_num(p, u[i], 6);
        err_add(p, i < 3 ? " mm" : " deg");
        first = 0;
    }
}

hp_error hp_plan(hp_planner *p, const double desired[6], hp_result *res)
{
    double t0 = now_s();
    if (!p) return HP_ERR_NULL;
    if (!res) {
        err_set(p, "result: NULL");
        return HP_ERR_NULL;
    }
    if (!p->built) {
        memset(res, 0, sizeof *res);
        res->status = HP_STATUS_SOLVER_ERROR;
        return HP_ERR_STATE;
    }
    p->err[0] = '\0';
    if (!desired) {
        for (int i = 0; i < 6; ++i) res->desired[i] = NAN;
        err_set(p, "desired: NULL");
        fail_safe(p, res, HP_STATUS_INVALID_INPUT, t0);
        return HP_ERR_NULL;
    }
    for (int i = 0; i < 6; ++i) res->desired[i] = desired[i];
    for (int i = 0; i < 6; ++i) {
        double lim = i < 3 ? HP_PLAN_MAX_TRANS : HP_PLAN_MAX_ROT;
        if (!isfinite(desired[i]) || !(fabs(desired[i]) <= lim)) {
            err_set(p, "desired ");
            err_add(p, pose_names[i]);
            err_add(p, isfinite(desired[i]) ? ": out of range (|translation| <= 1 m, "
                                              "|rotation| <= pi rad)"
                                            : ": not finite");
            return fail_safe(p, res, HP_STATUS_INVALID_INPUT, t0);
        }
    }
    if (!in_identifiable_range(p, desired)) return fail_safe(p, res, HP_STATUS_INVALID_INPUT, t0);
    /* The commanded part: what the layout can observe of the desired correction, in the
     * commanded components; the rest is reported, never silently dropped. */
    double xc[6], unc[6];
    if (hp_pose_commanded_part(&p->L, &p->id, p->level, desired, xc) != HP_OK) {
        err_set(p, "desired: the contact model cannot evaluate this correction (a bladder "
                   "centre would lie deep inside the head)");
        return fail_safe(p, res, HP_STATUS_INVALID_INPUT, t0);
    }
    for (int i = 0; i < 6; ++i) unc[i] = desired[i] - xc[i];
    hp_problem *pb = &p->pb;
    to_scaled(xc, pb->d);
    for (int i = 0; i < 6; ++i)
        if (!p->commanded[i]) pb->d[i] = 0.0;
    if (hp_setup_cycle_bounds(&p->L, &p->sb, pb->p_prev, p->s.use_rate_limits, pb, p->lo_flags,
                              p->hi_flags, NULL) != HP_OK) {
        err_set(p, "the rate limits leave no radius inside the pressure and stretch limits");
        return fail_safe(p, res, HP_STATUS_INFEASIBLE_START, t0);
    }

    hp_result *r = res;
    r->backend = p->s.backend;
    r->level = p->level;
    r->n = p->L.n;
    r->raw_code = 0;
    r->iterations = 0;
    for (int i = 0; i < 6; ++i) r->commanded[i] = p->commanded[i];
    memcpy(r->uncommanded, unc, sizeof unc);

    /* Direct chain: the desired pose itself, when every limit holds there. */
    double rho[HP_MAX_BLADDERS], clamp_mm = 0;
    int direct = hp_setup_contact_scaled(&p->L, p->level, pb->d, rho, NULL) == HP_OK;
    for (int k = 0; direct && k < p->L.n; ++k)
        direct = rho[k] >= pb->ro_lo[k] && rho[k] <= pb->ro_hi[k];
    hp_status st = HP_STATUS_REACHED;
    int converged = 1;
    const double *x = pb->d;
    if (!direct) {
        hp_backend_result br = {HP_STATUS_SOLVER_ERROR, 0, 0, 0};
        const double *x0 = NULL;
        double xcold[HP_PROBLEM_NX_MAX];
        if (p->s.warm_start) {
            x0 = p->x_prev;
        } else {
            for (int i = 0; i < 6; ++i) xcold[i] = 0.0;
            for (int k = 0; k < p->L.n; ++k)
                xcold[6 + k] = p->L.bladders[k].iab.Ri * HP_MM_PER_M;
            x0 = xcold;
        }
        p->diag.text[0] = '\0';
        hp_error e = p->ops->solve(p->bstate, pb, x0, p->x_work, &br, &p->diag);
        r->raw_code = br.raw_code;
        r->iterations = br.iterations;
        /* A backend may also report a failure through its status with HP_OK (Ipopt and
         * NLopt do for a failed solve, handing back their start point): that point is no
         * answer, so it must not be relabelled as an iteration limit. */
        int failed = e != HP_OK || br.status == HP_STATUS_SOLVER_ERROR ||
                     br.status == HP_STATUS_INFEASIBLE_START ||
                     br.status == HP_STATUS_INVALID_INPUT;
        if (failed) {
            /* The backend's own label, except that a failed call never claims success. */
            hp_status fs = br.status;
            if (fs == HP_STATUS_REACHED || fs == HP_STATUS_CLOSEST || (int)fs < 0 ||
                fs >= HP_STATUS_COUNT_)
                fs = HP_STATUS_SOLVER_ERROR;
            err_set(p, p->ops->name);
            err_add(p, ": ");
            err_add(p, hp_status_name(fs));
            err_add(p, " (raw code ");
            err_add_int(p, br.raw_code);
            err_add(p, ")");
            if (e != HP_OK && p->diag.text[0]) {
                err_add(p, ": ");
                err_add(p, p->diag.text);
            }
            err_add(p, "; holding the previous pressures");
            hp_error ret = fail_safe(p, res, fs, t0);
            res->raw_code = br.raw_code;
            res->iterations = br.iterations;
            return ret;
        }
        for (int i = 0; i < 6; ++i)
            if (!p->commanded[i]) p->x_work[i] = 0.0;
        x = p->x_work;
        converged = br.converged;
        st = br.status;
    }
    int raw = r->raw_code, iters = r->iterations;
    if (!answer_from_pose(p, x, r, &clamp_mm)) {
        err_set(p, "the answer was not finite or left a limit: holding the previous pressures");
        fail_safe(p, res, HP_STATUS_SOLVER_ERROR, t0);
        res->raw_code = raw;
        res->iterations = iters;
        return HP_OK;
    }
    if (clamp_mm > 1e-9) {
        /* A backend's radii left a limit (by its own tolerance): the clamped radii hold a
         * slightly different pose, found by forward contact kinematics (not real time). */
        double ro[HP_MAX_BLADDERS], xi[6], resid, xs[6];
        for (int k = 0; k < p->L.n; ++k) ro[k] = r->bladders[k].ro;
        from_scaled(x, xs);
        /* Radii that no pose holds (a backend that stopped at an infeasible point, e.g.
         * under rate limits that cannot all hold) are no answer: the fitted pose would not be
         * where the head goes. */
        if (hp_contact_fk(&p->L, p->level, ro, xs, xi, &resid, NULL) != HP_OK ||
            !(resid * HP_MM_PER_M <= HP_CLAMP_RESID_MM)) {
            /* A budget that ran out before a feasible iterate keeps its label. */
            hp_status fs = (st == HP_STATUS_ITERATION_LIMIT || st == HP_STATUS_TIME_LIMIT)
                               ? st
                               : HP_STATUS_SOLVER_ERROR;
            err_set(p, p->ops->name);
            err_add(p, ": ");
            err_add(p, hp_status_name(fs));
            err_add(p, " (raw code ");
            err_add_int(p, raw);
            err_add(p, "): the backend's radii, clamped into the limits, hold no pose; "
                       "holding the previous pressures");
            fail_safe(p, res, fs, t0);
            res->raw_code = raw;
            res->iterations = iters;
            return HP_OK;
        }
        for (int i = 0; i < 6; ++i) r->achieved[i] = p->commanded[i] ? xi[i] : 0.0;
        converged = 0;
    }
    pose_error(p, r, pb->d);
    int unc_any = uncommanded_beyond(p, unc);
    if (r->pose_error <= p->s.tolerance) {
        r->status = unc_any ? HP_STATUS_UNCOMMANDED : HP_STATUS_REACHED;
    } else if (converged && !closest_verified(p, x)) {
        /* A backend that claims an optimum the first-order conditions refute (NLopt SLSQP
         * far beyond reach handed back its start point with XTOL_REACHED) gives no answer:
         * label it and hold, never report it as the closest correction. */
        err_set(p, p->ops->name);
        err_add(p, ": solver-error (raw code ");
        err_add_int(p, raw);
        err_add(p, "): its claimed optimum fails the first-order (KKT) check; "
                   "holding the previous pressures");
        fail_safe(p, res, HP_STATUS_SOLVER_ERROR, t0);
        res->raw_code = raw;
        res->iterations = iters;
        return HP_OK;
    } else if (converged && !binds_any(r)) {
        /* Nothing binds, so the first-order conditions say the optimum is the target: a
         * claimed optimum short of it is not the closest (Ipopt stops its interior point
         * a few 1e-6 mm inside a bound when the remaining pose error is tiny, because its
         * complementarity test scales with the multiplier). Label it, never CLOSEST. */
        err_set(p, p->ops->name);
        err_add(p, ": solver-error (raw code ");
        err_add_int(p, raw);
        err_add(p, "): its claimed optimum binds no limit (none within ");
        err_add_num(p, HP_BINDING_TOL_MM * 1e6, 0);
        err_add(p, " nm), so it is not the closest; holding the previous pressures");
        fail_safe(p, res, HP_STATUS_SOLVER_ERROR, t0);
        res->raw_code = raw;
        res->iterations = iters;
        return HP_OK;
    } else if (converged) {
        r->status = HP_STATUS_CLOSEST;
    } else {
        r->status = (st == HP_STATUS_TIME_LIMIT) ? HP_STATUS_TIME_LIMIT
                                                  : HP_STATUS_ITERATION_LIMIT;
    }
    if ((r->status == HP_STATUS_REACHED || r->status == HP_STATUS_UNCOMMANDED) &&
        !recovered_from_nominal(p, r, xc)) {
        fail_safe(p, res, HP_STATUS_INVALID_INPUT, t0);
        res->raw_code = raw;
        res->iterations = iters;
        return HP_OK;
    }
    if (r->status == HP_STATUS_UNCOMMANDED) {
        err_set(p, "uncommanded: the commanded part is reached; ");
        add_uncommanded(p, unc);
    } else if (r->status != HP_STATUS_REACHED) {
        err_set(p, hp_status_name(r->status));
        err_add(p, ": binding");
        int any = 0;
        for (int k = 0; k < p->L.n; ++k) {
            if (!r->bladders[k].binding) continue;
            err_add(p, any ? ", " : " ");
            err_add(p, p->L.bladders[k].name);
            for (int b = 0; b < HP_BIND_COUNT; ++b)
                if (r->bladders[k].binding & (1u << b)) {
                    err_add(p, " ");
                    err_add(p, hp_binding_name(1u << b));
                }
            any = 1;
        }
        if (!any) err_add(p, " none");
        if (unc_any) {
            err_add(p, "; ");
            add_uncommanded(p, unc);
        }
    }
    p->prev = *r;
    set_prev_x(p, r);
    /* The Ipopt backend recognises its own last answer as a warm start point. */
    if (!direct && clamp_mm == 0) memcpy(p->x_prev, p->x_work, sizeof p->x_work);
    r->solve_time = now_s() - t0;
    p->prev.solve_time = r->solve_time;
    return HP_OK;
}
