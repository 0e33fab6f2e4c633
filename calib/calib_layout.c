/* Fitting a layout's bladder radial offsets and head semi-axes to measured (pressures, pose)
 * rows (see hp_calib.h and docs/calibration.md). The forward model of one row is the chain
 * the planner's own check uses: pressures -> hp_iab_fk -> hp_iab_ro -> hp_contact_fk. The
 * radii depend only on the pressures and the bladders' material, so they are computed once;
 * only the contact geometry depends on the fitted parameters. */
#include "headplan/hp_calib.h"
#include "calib/calib_internal.h"
#include "common/units.h"
#include "kinematics/kin_geom.h"
#include "kinematics/kin_internal.h"
#include "kinematics/linalg.h"
#include "kinematics/names.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LAY_MAX_ITERS 200
#define LAY_FD_STEP 1e-6 /* [m] central-difference step of the contact model: 1 µm */
/* A singular value below this fraction of the largest (unit-norm columns) counts as zero:
 * the central differences carry ~1e-9 relative noise, so an exactly unidentifiable direction
 * shows up near 1e-8 (docs/calibration.md); weak but real directions stay, with their wide
 * intervals and the condition number as the warning. */
#define LAY_RANK_TOL 1e-7
#define LAY_STEP_TOL 1e-12 /* [m] a step this small ends the iteration */

void hp_layout_fit_options_default(hp_layout_fit_options *o)
{
    if (!o) return;
    o->fit_axes = 1;
    o->fit_offsets = 1;
    o->fit_mass = 0;
    o->load = NULL;
    o->level = HP_LEVEL_SURFACE;
    o->sigma_trans = 1e-4;
    o->sigma_rot = 0.1 * HP_RAD_PER_DEG;
}

/* Weighted residuals (measured − model)/σ of every row, n×dofp. Each row's forward
 * kinematics starts from start[i] when given (the model's pose at the unperturbed
 * parameters: central differences then compare two solves from the same point, which keeps
 * their difference smooth), else from the measured pose; poses (may be NULL) receives the
 * model's poses. */
static hp_error resid(const lay_ctx *c, const hp_layout *L, const hp_geom *G, const double *theta,
                      double *e, const double (*start)[6], double (*poses)[6])
{
    if (c->load) return calib_load_resid(c, L, theta, e, start, poses);
    for (int i = 0; i < c->n; ++i) {
        double xi[6];
        hp_error err = hpi_contact_fk_g(L, G, c->level, c->ro[i],
                                        start ? start[i] : c->rows[i].pose, xi, NULL, NULL);
        if (err) return err;
        if (poses) memcpy(poses[i], xi, sizeof xi);
        for (int j = 0; j < c->dofp; ++j)
            e[i * c->dofp + j] = (c->rows[i].pose[j] - xi[j]) * c->w[j];
    }
    return HP_OK;
}

static hp_error resid_at(const lay_ctx *c, const double *theta, double *e, int validate,
                         const double (*start)[6], double (*poses)[6])
{
    hp_layout L;
    hp_geom G;
    hp_error err = calib_layout_apply(c, theta, &L, &G, validate, NULL);
    return err ? err : resid(c, &L, &G, theta, e, start, poses);
}

/* Jacobian of the weighted residuals w.r.t. all np parameters (m×np, row-major). The model's
 * pose ξ of a row solves the forward kinematics' normal equations F = Jcᵀ·r = 0, with
 * r = rho(ξ; θ) − ro and Jc = ∂rho/∂ξ; the implicit function theorem gives exactly
 *   dξ/dθ = −(JcᵀJc + Σ r_k H_k)⁻¹ (Jcᵀ ∂rho/∂θ + (∂Jc/∂θ)ᵀ r),
 * H_k = ∂²rho_k/∂ξ². The derivatives in θ at fixed ξ are central differences of direct
 * evaluations of the contact model (no iteration inside, so their noise is rounding only);
 * differencing whole forward-kinematics solves instead would inherit their stopping
 * tolerance. */
static hp_error jacobian(const lay_ctx *c, const double *theta, double *J)
{
    if (c->load) return calib_load_jacobian(c, theta, J);
    int n = c->n, nb = c->L0->n, dp = c->dofp, np = c->np;
    size_t per = (size_t)nb * 6;
    double(*xi)[6] = malloc(sizeof *xi * (size_t)n);
    double *drho = malloc(sizeof(double) * (size_t)n * (size_t)nb * (size_t)np);
    double *dJc = malloc(sizeof(double) * (size_t)n * per * (size_t)np);
    hp_error err = (!xi || !drho || !dJc) ? HP_ERR_NOMEM : HP_OK;
    hp_layout L;
    hp_geom G;
    if (!err) err = calib_layout_apply(c, theta, &L, &G, 0, NULL);
    for (int i = 0; !err && i < n; ++i)
        err = hpi_contact_fk_g(&L, &G, c->level, c->ro[i], c->rows[i].pose, xi[i], NULL, NULL);
    double th[HP_CALIB_MAX_PARAMS];
    for (int j = 0; !err && j < np; ++j) {
        hp_layout Lp, Lm;
        hp_geom Gp, Gm;
        memcpy(th, theta, sizeof(double) * (size_t)np);
        th[j] = theta[j] + LAY_FD_STEP;
        err = calib_layout_apply(c, th, &Lp, &Gp, 0, NULL);
        th[j] = theta[j] - LAY_FD_STEP;
        if (!err) err = calib_layout_apply(c, th, &Lm, &Gm, 0, NULL);
        for (int i = 0; !err && i < n; ++i) {
            double rp[HP_MAX_BLADDERS], rm[HP_MAX_BLADDERS];
            double Jp[HP_MAX_BLADDERS * 6], Jm[HP_MAX_BLADDERS * 6];
            err = hpi_contact_eval_g(&Lp, &Gp, c->level, xi[i], rp, Jp, NULL);
            if (!err) err = hpi_contact_eval_g(&Lm, &Gm, c->level, xi[i], rm, Jm, NULL);
            if (err) break;
            const size_t ij = (size_t)i * (size_t)np + (size_t)j;
            for (int k = 0; k < nb; ++k)
                drho[ij * (size_t)nb + (size_t)k] = (rp[k] - rm[k]) / (2.0 * LAY_FD_STEP);
            for (size_t q = 0; q < per; ++q)
                dJc[ij * per + q] = (Jp[q] - Jm[q]) / (2.0 * LAY_FD_STEP);
        }
    }
    for (int i = 0; !err && i < n; ++i) {
        double rho[HP_MAX_BLADDERS], Jc[HP_MAX_BLADDERS * 6], H[HP_MAX_BLADDERS * 36];
        err = hpi_contact_eval_g(&L, &G, c->level, xi[i], rho, Jc, H);
        if (err) break;
        double A[36], r[HP_MAX_BLADDERS];
        for (int k = 0; k < nb; ++k) r[k] = rho[k] - c->ro[i][k];
        for (int a = 0; a < dp; ++a)
            for (int b = 0; b < dp; ++b) {
                double sum = 0.0;
                for (int k = 0; k < nb; ++k)
                    sum += Jc[k * 6 + a] * Jc[k * 6 + b] + r[k] * H[k * 36 + a * 6 + b];
                A[a * dp + b] = sum;
            }
        for (int j = 0; j < np; ++j) {
            const size_t ij = (size_t)i * (size_t)np + (size_t)j;
            const double *dr = &drho[ij * (size_t)nb];
            const double *dj = &dJc[ij * per];
            double rhs[6], dx[6], ones[6] = {1, 1, 1, 1, 1, 1};
            for (int a = 0; a < dp; ++a) {
                double sum = 0.0;
                for (int k = 0; k < nb; ++k) sum += Jc[k * 6 + a] * dr[k] + dj[k * 6 + a] * r[k];
                rhs[a] = sum;
            }
            /* A·dx = −rhs, by the kinematics' QR least squares (no damping). */
            if (hpi_kin_damped_lstsq(dp, dp, A, rhs, ones, 0.0, dx) != 0) {
                err = HP_ERR_NO_CONVERGENCE;
                break;
            }
            for (int a = 0; a < dp; ++a) J[(i * dp + a) * np + j] = -c->w[a] * dx[a];
        }
    }
    free(xi);
    free(drho);
    free(dJc);
    return err;
}

void calib_columns(int m, int np, const double *J, const int *cols, int k, double *S, double *scale)
{
    for (int q = 0; q < k; ++q) {
        double s = 0.0;
        for (int i = 0; i < m; ++i) s += J[i * np + cols[q]] * J[i * np + cols[q]];
        scale[q] = s > 0 ? sqrt(s) : 1.0;
        for (int i = 0; i < m; ++i) S[i * k + q] = J[i * np + cols[q]] / scale[q];
    }
}

static int rank_of(const double *sv, int k)
{
    int r = 0;
    for (int j = 0; j < k; ++j)
        if (sv[j] > LAY_RANK_TOL * sv[0]) ++r;
    return r;
}

static hp_error check_rows(const hp_layout *L, const hp_calib_row *rows, int n,
                           double (*ro)[HP_MAX_BLADDERS], hp_diag *d)
{
    hp_iab_limit lp[HP_MAX_BLADDERS];
    for (int k = 0; k < L->n; ++k)
        if (hp_iab_limit_point(&L->bladders[k].iab, &lp[k]))
            return hp_diag_set(d, HP_ERR_INVALID, "bladder '%s': no limit point",
                               L->bladders[k].name);
    for (int i = 0; i < n; ++i) {
        long ln = rows[i].line ? rows[i].line : i + 1;
        for (int j = 0; j < 6; ++j)
            if (!isfinite(rows[i].pose[j]))
                return hp_diag_set(d, HP_ERR_INVALID, "row %ld: %s: must be finite", ln,
                                   hp_pose_key(j));
        for (int k = 0; k < L->n; ++k) {
            const hp_bladder *b = &L->bladders[k];
            double P = rows[i].pressure[k], ri;
            if (!isfinite(P) || P < b->p_min || P > b->p_max)
                return hp_diag_set(d, HP_ERR_INVALID,
                                   "row %ld: bladder '%s': pressure %g Pa outside its limits "
                                   "[%g, %g] Pa",
                                   ln, b->name, P, b->p_min, b->p_max);
            if (lp[k].exists && !(P < lp[k].pressure))
                return hp_diag_set(d, HP_ERR_INVALID,
                                   "row %ld: bladder '%s': pressure %g Pa is not on the stable "
                                   "branch (limit point %g Pa)",
                                   ln, b->name, P, lp[k].pressure);
            hp_error e = hp_iab_fk_limit(&b->iab, &lp[k], P, &ri);
            if (!e) e = hp_iab_ro(&b->iab, ri, &ro[i][k]);
            if (e)
                return hp_diag_set(d, HP_ERR_INVALID, "row %ld: bladder '%s': pressure %g Pa: %s",
                                   ln, b->name, P, hp_error_message(e));
        }
    }
    return HP_OK;
}

/* Builds the context: parameters, weights and every row's outer radii. */
static hp_error setup(const hp_layout *L, const hp_calib_row *rows, int n,
                      const hp_layout_fit_options *opt, lay_ctx *c, hp_layout_fit *out, hp_diag *d)
{
    if (!L || !rows || !opt || !out) return hp_diag_set(d, HP_ERR_NULL, "NULL argument");
    hp_layout chk = *L; /* the full checks, on a copy: L is the caller's */
    hp_geom G0;
    hp_error e0 = hp_layout_prepare(&chk, d);
    if (e0 == HP_OK) e0 = hpi_geom_derive(&chk, &G0, d);
    if (e0 != HP_OK) return e0;
    if (n < 1 || n > HP_CALIB_MAX_ROWS)
        return hp_diag_set(d, HP_ERR_INVALID, "rows: %d (need 1..%d)", n, HP_CALIB_MAX_ROWS);
    if (!hp_level_is_geometry(opt->level)) {
        char names[64];
        return hp_diag_set(d, HP_ERR_INVALID, "level: must be %s",
                           hpi_level_geometry_names(names, sizeof names));
    }
    if (!(opt->sigma_trans > 0) || !isfinite(opt->sigma_trans) || !(opt->sigma_rot > 0) ||
        !isfinite(opt->sigma_rot))
        return hp_diag_set(d, HP_ERR_INVALID, "sigma: must be finite and > 0");
    if (!opt->fit_axes && !opt->fit_offsets && !opt->fit_mass)
        return hp_diag_set(d, HP_ERR_INVALID, "nothing to fit: choose axes, offsets or mass");
    if (opt->load && hp_load_spec_validate(opt->load, d)) return HP_ERR_INVALID;
    memset(c, 0, sizeof *c);
    c->load = opt->load;
    c->L0 = L;
    c->G0 = G0;
    c->rows = rows;
    c->n = n;
    c->level = opt->level;
    int sphere = L->head.shape == HP_HEAD_SPHERE;
    c->dofp = sphere ? 3 : 6;
    for (int j = 0; j < 6; ++j) c->w[j] = 1.0 / (j < 3 ? opt->sigma_trans : opt->sigma_rot);
    /* Both groups are always in the parameter vector; the unselected ones stay at zero
     * change (not in sel[]). */
    c->n_axes = sphere ? 1 : 3;
    c->np = c->n_axes + L->n + (opt->fit_mass ? 1 : 0);
    c->mass_j = opt->fit_mass ? c->np - 1 : -1;
    memset(out, 0, sizeof *out);
    out->np = c->np;
    out->mass_index = c->mass_j;
    out->mass = opt->load ? opt->load->mass : NAN;
    static const char *const axis[3] = {"semi_axis_x", "semi_axis_y", "semi_axis_z"};
    for (int j = 0; j < c->np; ++j) {
        if (j == c->mass_j) {
            snprintf(out->name[j], HP_CALIB_NAME_MAX, "mass");
            out->scene_value[j] = opt->load ? opt->load->mass : NAN;
        } else if (j < c->n_axes) {
            snprintf(out->name[j], HP_CALIB_NAME_MAX, "%s", sphere ? "radius" : axis[j]);
            out->scene_value[j] = L->head.semi_axes[j];
        } else {
            snprintf(out->name[j], HP_CALIB_NAME_MAX, "offset:%s", L->bladders[j - c->n_axes].name);
            out->scene_value[j] = 0.0;
        }
        out->value[j] = out->scene_value[j];
        out->se[j] = out->ci[j][0] = out->ci[j][1] = NAN;
    }
    c->ro = malloc(sizeof *c->ro * (size_t)n);
    if (!c->ro) return hp_diag_set(d, HP_ERR_NOMEM, "out of memory");
    hp_error err = check_rows(L, rows, n, c->ro, d);
    if (err) {
        free(c->ro);
        c->ro = NULL;
    }
    return err;
}

/* Gauss–Newton step with Levenberg–Marquardt damping on the selected columns, scaled to
 * unit norm: (SᵀS + λI)·y = −Sᵀe solved through the SVD S = UΣVᵀ as y = −V(Σ² + λ)⁻¹Vᵀ·Sᵀe,
 * then dx = y / scale. */
hp_error calib_lm_step(int m, int k, const double *S, const double *scale, const double *e,
                       double lambda, double *dx)
{
    double sv[HP_CALIB_MAX_PARAMS], V[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS];
    double g[HP_CALIB_MAX_PARAMS] = {0}, y[HP_CALIB_MAX_PARAMS];
    if (hpi_kin_svd(m, k, S, sv, V)) return HP_ERR_NO_CONVERGENCE;
    for (int i = 0; i < m; ++i)
        for (int q = 0; q < k; ++q) g[q] += S[i * k + q] * e[i];
    for (int q = 0; q < k; ++q) {
        y[q] = 0.0;
        for (int j = 0; j < k; ++j) y[q] += V[j * k + q] * g[j];
        y[q] /= sv[q] * sv[q] + lambda;
    }
    for (int j = 0; j < k; ++j) {
        double s = 0.0;
        for (int q = 0; q < k; ++q) s += V[j * k + q] * y[q];
        dx[j] = -s / scale[j];
    }
    return HP_OK;
}

static double sumsq(int n, const double *v)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += v[i] * v[i];
    return s;
}

static void rms_axes(const lay_ctx *c, const double *e, double rms[6])
{
    for (int j = 0; j < 6; ++j) {
        if (j >= c->dofp) {
            rms[j] = NAN;
            continue;
        }
        double s = 0.0;
        for (int i = 0; i < c->n; ++i) s += e[i * c->dofp + j] * e[i * c->dofp + j];
        rms[j] = sqrt(s / c->n) / c->w[j];
    }
}

/* Inverse of a symmetric positive definite k×k matrix A through its SVD (= eigen-
 * decomposition): A⁻¹ = V Σ⁻¹ Vᵀ. */
static hp_error sym_inverse(int k, const double *A, double *C)
{
    double sv[HP_CALIB_MAX_PARAMS], V[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS];
    if (hpi_kin_svd(k, k, A, sv, V) || !(sv[k - 1] > 0)) return HP_ERR_INVALID;
    for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b) {
            double s = 0.0;
            for (int q = 0; q < k; ++q) s += V[a * k + q] * V[b * k + q] / sv[q];
            C[a * k + b] = s;
        }
    return HP_OK;
}

/* Inverse of the information matrix of the selected columns (k×k) through the SVD:
 * (JᵀJ)⁻¹ = V Σ⁻² Vᵀ in unit-column coordinates, unscaled. */
hp_error calib_covariance(int m, int k, const double *S, const double *scale, double *C,
                          double *cond)
{
    double sv[HP_CALIB_MAX_PARAMS], V[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS];
    if (hpi_kin_svd(m, k, S, sv, V) || !(sv[k - 1] > 0)) return HP_ERR_INVALID;
    if (cond) *cond = sv[0] / sv[k - 1];
    for (int a = 0; a < k; ++a)
        for (int b = 0; b < k; ++b) {
            double s = 0.0;
            for (int q = 0; q < k; ++q) s += V[a * k + q] * V[b * k + q] / (sv[q] * sv[q]);
            C[a * k + b] = s / (scale[a] * scale[b]);
        }
    return HP_OK;
}

/* A failed fit answers nothing: every number NaN, nothing determined, no layout. */
static void invalidate(hp_layout_fit *out)
{
    for (int j = 0; j < HP_CALIB_MAX_PARAMS; ++j) {
        out->value[j] = out->se[j] = out->ci[j][0] = out->ci[j][1] = NAN;
        out->sv[j] = out->weakest[j] = NAN;
        out->determined[j] = 0;
    }
    for (int j = 0; j < 6; ++j) out->rms_before[j] = out->rms_after[j] = NAN;
    out->condition = out->t = out->s = out->weakest_se = out->mass = NAN;
    out->rank = out->dof = 0;
    out->fitted.n = 0; /* no bladders: every call that takes a layout refuses it */
}

hp_error hp_fit_layout(const hp_layout *L, const hp_calib_row *rows, int n,
                       const hp_layout_fit_options *opt, hp_layout_fit *out, double *resid_after,
                       hp_diag *diag)
{
    lay_ctx c;
    hp_error err = setup(L, rows, n, opt, &c, out, diag);
    if (err) {
        if (out) invalidate(out);
        return err;
    }
    int m = n * c.dofp, np = c.np;
    double *e = malloc(sizeof(double) * (size_t)m * (2 * (size_t)np + 2));
    if (!e) {
        free(c.ro);
        invalidate(out);
        return hp_diag_set(diag, HP_ERR_NOMEM, "out of memory");
    }
    double *et = e + m, *J = e + 2 * m, *S = J + (size_t)m * (size_t)np;
    double theta[HP_CALIB_MAX_PARAMS] = {0}, scale[HP_CALIB_MAX_PARAMS];
    double svall[HP_CALIB_MAX_PARAMS], V[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS];
    err = resid_at(&c, theta, e, 1, NULL, NULL);
    if (!err) err = jacobian(&c, theta, J);
    if (err) {
        err = hp_diag_set(diag, err, "the scene's layout cannot reproduce the rows (%s)",
                          hp_error_message(err));
        goto done;
    }
    rms_axes(&c, e, out->rms_before);

    /* Rank of the whole parameter set, then admit parameters in order while each adds rank
     * (only the groups the options select). */
    int all[HP_CALIB_MAX_PARAMS];
    for (int j = 0; j < np; ++j) all[j] = j;
    calib_columns(m, np, J, all, np, S, scale);
    if (hpi_kin_svd(m, np, S, svall, V)) {
        err = hp_diag_set(diag, HP_ERR_NO_CONVERGENCE, "SVD of the Jacobian failed");
        goto done;
    }
    memcpy(out->sv, svall, sizeof(double) * (size_t)np);
    out->rank = rank_of(svall, np < m ? np : m);
    /* The mass first (what a load calibration is for), then the offsets (the head's size is
     * measurable by hand; the placement of a bladder on its panel is not), then the
     * semi-axes. */
    int order[HP_CALIB_MAX_PARAMS], no = 0, nb = L->n;
    if (c.mass_j >= 0) order[no++] = c.mass_j;
    for (int k = 0; k < nb; ++k) order[no++] = c.n_axes + k;
    for (int k = 0; k < c.n_axes; ++k) order[no++] = k;
    c.nsel = 0;
    for (int q = 0; q < np; ++q) {
        int j = order[q];
        int want = j == c.mass_j ? opt->fit_mass : j < c.n_axes ? opt->fit_axes : opt->fit_offsets;
        if (!want) {
            out->determined[j] = -1;
            continue;
        }
        c.sel[c.nsel] = j;
        calib_columns(m, np, J, c.sel, c.nsel + 1, S, scale);
        double sv[HP_CALIB_MAX_PARAMS];
        if (hpi_kin_svd(m, c.nsel + 1, S, sv, V)) {
            err = hp_diag_set(diag, HP_ERR_NO_CONVERGENCE, "SVD of the Jacobian failed");
            goto done;
        }
        if (rank_of(sv, c.nsel + 1 < m ? c.nsel + 1 : m) == c.nsel + 1) ++c.nsel;
    }
    if (c.nsel == 0) {
        err = hp_diag_set(diag, HP_ERR_INVALID,
                          "the data determine none of the selected parameters (rank %d)",
                          out->rank);
        goto done;
    }
    if (m - c.nsel < 1) {
        err = hp_diag_set(diag, HP_ERR_INVALID,
                          "%d rows give %d residuals for %d parameters: at least one more "
                          "residual is needed to estimate the scatter",
                          n, m, c.nsel);
        goto done;
    }

    double cost = sumsq(m, e), lambda = 1e-3;
    int it = 0, stalled = 0, accepted = 0;
    for (; it < LAY_MAX_ITERS; ++it) {
        double dx[HP_CALIB_MAX_PARAMS], th[HP_CALIB_MAX_PARAMS];
        calib_columns(m, np, J, c.sel, c.nsel, S, scale);
        if (calib_lm_step(m, c.nsel, S, scale, e, lambda, dx)) {
            err = hp_diag_set(diag, HP_ERR_NO_CONVERGENCE, "SVD of the Jacobian failed");
            goto done;
        }
        memcpy(th, theta, sizeof th);
        double step = 0.0;
        for (int q = 0; q < c.nsel; ++q) {
            th[c.sel[q]] += dx[q];
            step = fmax(step, fabs(dx[q]));
        }
        hp_error te = resid_at(&c, th, et, 1, NULL, NULL);
        double ct = te ? INFINITY : sumsq(m, et);
        if (ct <= cost) {
            memcpy(theta, th, sizeof theta);
            memcpy(e, et, sizeof(double) * (size_t)m);
            cost = ct;
            lambda = fmax(lambda * 0.1, 1e-12);
            err = jacobian(&c, theta, J);
            if (err) {
                err = hp_diag_set(diag, err, "the Jacobian failed during the fit");
                goto done;
            }
            stalled = 0;
            ++accepted;
            if (step <= LAY_STEP_TOL) break;
        } else {
            /* A trial the model cannot evaluate at all (e.g. no rest of the statics) is not a
             * worse fit: when the damping runs out on such trials the search stalled. */
            stalled = te != HP_OK;
            lambda *= 10.0;
            if (lambda > 1e12 || step <= LAY_STEP_TOL) break;
        }
    }
    /* Noisy data are never exactly at the scene's values: a search that accepted no step at
     * all, or ran out of damping on trials the model could not evaluate, stalled; its
     * numbers would be the scene's with intervals that mean nothing. */
    if ((stalled && lambda > 1e12) || !accepted) {
        err = hp_diag_set(diag, HP_ERR_NO_CONVERGENCE,
                          "the fit stalled: no step from the scene's values improved the fit "
                          "(%s); fit fewer parameters",
                          c.load ? "at the load level the statics find no rest for the steps "
                                   "the data ask for, or find it only roughly"
                                 : "the contact model fails for the steps the data ask for");
        goto done;
    }
    out->iterations = it;
    hp_geom Gf;
    err = calib_layout_apply(&c, theta, &out->fitted, &Gf, 1, diag);
    if (err) {
        hp_diag_set(diag, err, "the fitted layout is not valid: %s", diag ? diag->text : "");
        goto done;
    }
    rms_axes(&c, e, out->rms_after);
    if (resid_after)
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < 6; ++j)
                resid_after[i * 6 + j] = j < c.dofp ? e[i * c.dofp + j] / c.w[j] : 0.0;

    double C[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS];
    calib_columns(m, np, J, c.sel, c.nsel, S, scale);
    if (calib_covariance(m, c.nsel, S, scale, C, &out->condition)) {
        err = hp_diag_set(diag, HP_ERR_INVALID, "the fitted Jacobian is singular");
        goto done;
    }
    /* The weakest direction: the right singular vector of the smallest singular value,
     * back in parameter units (m), and the standard error along it. */
    {
        int k = c.nsel;
        double sv[HP_CALIB_MAX_PARAMS], u[HP_CALIB_MAX_PARAMS] = {0};
        if (hpi_kin_svd(m, k, S, sv, V) == 0) {
            double norm = 0.0, var = 0.0;
            for (int q = 0; q < k; ++q) {
                u[q] = V[q * k + (k - 1)] / scale[q];
                norm += u[q] * u[q];
            }
            norm = sqrt(norm);
            for (int q = 0; q < k; ++q) u[q] /= norm;
            /* Sign: largest component positive, so the output does not flip with rounding. */
            int big = 0;
            for (int q = 1; q < k; ++q)
                if (fabs(u[q]) > fabs(u[big])) big = q;
            double sg = u[big] < 0 ? -1.0 : 1.0;
            for (int a = 0; a < k; ++a)
                for (int b = 0; b < k; ++b) var += u[a] * C[a * k + b] * u[b];
            for (int q = 0; q < k; ++q) out->weakest[c.sel[q]] = sg * u[q];
            out->weakest_se = sqrt(cost / (m - k)) * sqrt(var);
        }
    }
    out->n_rows = n;
    out->n_res = m;
    out->dof = m - c.nsel;
    out->s = sqrt(cost / out->dof);
    out->t = hp_calib_t_quantile(0.975, out->dof);
    for (int j = 0; j < np; ++j) out->value[j] = out->scene_value[j] + theta[j];
    if (c.mass_j >= 0 && c.load) out->mass = out->value[c.mass_j];
    for (int q = 0; q < c.nsel; ++q) {
        int j = c.sel[q];
        out->determined[j] = 1;
        out->se[j] = out->s * sqrt(C[q * c.nsel + q]);
        out->ci[j][0] = out->value[j] - out->t * out->se[j];
        out->ci[j][1] = out->value[j] + out->t * out->se[j];
    }
done:
    free(e);
    free(c.ro);
    if (err) invalidate(out);
    return err;
}

hp_error hp_fit_layout_gain(const hp_layout *L, const hp_calib_row *rows, int n,
                            const hp_layout_fit_options *opt, const hp_layout_fit *fit,
                            double *gain, hp_diag *diag)
{
    if (!fit || !gain) return hp_diag_set(diag, HP_ERR_NULL, "NULL argument");
    lay_ctx c;
    hp_layout_fit scratch;
    hp_error err = setup(L, rows, n, opt, &c, &scratch, diag);
    if (err) return err;
    if (fit->np != c.np) {
        free(c.ro);
        return hp_diag_set(diag, HP_ERR_INVALID, "fit: does not belong to this layout");
    }
    double theta[HP_CALIB_MAX_PARAMS];
    for (int j = 0; j < c.np; ++j) {
        theta[j] = fit->value[j] - fit->scene_value[j];
        if (fit->determined[j] == 1) c.sel[c.nsel++] = j;
    }
    int m = n * c.dofp, np = c.np, k = c.nsel;
    double *J = malloc(sizeof(double) * (size_t)m * (size_t)np);
    if (!J || k == 0) {
        free(J);
        free(c.ro);
        return hp_diag_set(diag, J ? HP_ERR_INVALID : HP_ERR_NOMEM, "no fitted parameter");
    }
    err = jacobian(&c, theta, J);
    /* Information A = JᵀJ of the selected columns; each candidate adds its row's block. */
    double A[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS],
        B[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS];
    double Ci[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS],
        Cn[HP_CALIB_MAX_PARAMS * HP_CALIB_MAX_PARAMS];
    for (int a = 0; !err && a < k; ++a)
        for (int b = 0; b < k; ++b) {
            double s = 0.0;
            for (int i = 0; i < m; ++i) s += J[i * np + c.sel[a]] * J[i * np + c.sel[b]];
            A[a * k + b] = s;
        }
    if (!err && sym_inverse(k, A, Ci)) err = HP_ERR_INVALID;
    for (int r = 0; !err && r < n; ++r) {
        memcpy(B, A, sizeof(double) * (size_t)k * (size_t)k);
        for (int a = 0; a < k; ++a)
            for (int b = 0; b < k; ++b)
                for (int j = 0; j < c.dofp; ++j) {
                    int i = r * c.dofp + j;
                    B[a * k + b] += J[i * np + c.sel[a]] * J[i * np + c.sel[b]];
                }
        gain[r] = NAN;
        if (sym_inverse(k, B, Cn)) continue;
        double s = 0.0;
        for (int q = 0; q < k; ++q) s += sqrt(Cn[q * k + q] / Ci[q * k + q]);
        gain[r] = s / k;
    }
    free(J);
    free(c.ro);
    if (err) return hp_diag_set(diag, err, "the information matrix is singular");
    return HP_OK;
}

hp_error hp_fit_layout_residuals(const hp_layout *L, const hp_calib_row *rows, int n,
                                 const hp_layout_fit_options *opt, double *resid, hp_diag *diag)
{
    if (!resid) return hp_diag_set(diag, HP_ERR_NULL, "NULL argument");
    hp_layout_fit *scratch = malloc(sizeof *scratch);
    double *e = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1) * 6);
    lay_ctx c;
    hp_error err = (!scratch || !e) ? hp_diag_set(diag, HP_ERR_NOMEM, "out of memory")
                                    : setup(L, rows, n, opt, &c, scratch, diag);
    if (!err) {
        double theta[HP_CALIB_MAX_PARAMS] = {0};
        err = resid_at(&c, theta, e, 0, NULL, NULL);
        if (err)
            err = hp_diag_set(diag, err, "the layout cannot reproduce the rows (%s)",
                              hp_error_message(err));
        for (int i = 0; !err && i < n; ++i)
            for (int j = 0; j < 6; ++j)
                resid[i * 6 + j] = j < c.dofp ? e[i * c.dofp + j] / c.w[j] : 0.0;
        free(c.ro);
    }
    free(scratch);
    free(e);
    return err;
}
