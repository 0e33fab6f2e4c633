/* The planner's nonlinear program in scaled units (mm, degrees, ri in mm): objective,
 * contact constraints and their exact first and second derivatives, shared by every backend.
 *
 * The kinematics and bladder modules work in SI; the chain rule to scaled units is
 *   ξ_SI,i = s_i · x_i,  s_i = 1e-3 m/mm (i < 3) or π/180 rad/deg (i >= 3),
 *   ρ_mm = 1000 · ρ_SI  =>  ∂ρ_mm/∂x_i = 1000·s_i·J_ik,  ∂²ρ_mm/∂x_i∂x_j = 1000·s_i·s_j·H_kij,
 *   ri_SI = 1e-3 · ri_mm =>  dP/dri_mm = 1e-3 · dP/dri_SI,  d²P/dri_mm² = 1e-6 · d²P/dri_SI².
 * The volume law ro³ = Ro³ + ri³ − Ri³ is homogeneous, so ro' = ri²/ro² (dimensionless) and
 * ro'' = 2ri/ro² − 2ri²ro'/ro³ = (2ri/ro²)(1 − ri³/ro³) [1/mm] hold directly in mm. */
#include "planner/problem.h"
#include "common/units.h"

#include <math.h>
#include <string.h>

/* SI per scaled unit of pose component i. */

static hp_error check_problem(const hp_problem *pb, const double *x)
{
    if (!pb || !x || !pb->layout || !pb->geom) return HP_ERR_NULL;
    if (pb->n < 1 || pb->n > HP_MAX_BLADDERS || pb->n != pb->layout->n || pb->nx != 6 + pb->n)
        return HP_ERR_INVALID;
    for (int i = 0; i < pb->nx; i++)
        if (!isfinite(x[i])) return HP_ERR_INVALID;
    return HP_OK;
}

hp_error hpi_problem_objective(const hp_problem *pb, const double *x, double *f, double *grad,
                               double *hess)
{
    hp_error e = check_problem(pb, x);
    if (e != HP_OK) return e;
    if (!f) return HP_ERR_NULL;
    const int nx = pb->nx;
    if (grad) memset(grad, 0, (size_t)nx * sizeof *grad);
    if (hess) memset(hess, 0, (size_t)nx * (size_t)nx * sizeof *hess);

    double sum = 0.0;
    for (int i = 0; i < 6; i++) {
        double r = x[i] - pb->d[i];
        sum += pb->w[i] * r * r;
        if (grad) grad[i] = 2.0 * pb->w[i] * r;
        if (hess) hess[i * nx + i] = 2.0 * pb->w[i];
    }
    /* mu = 0 (the default) skips the bladder model entirely: the pressure term is only a
     * tie-breaker and must not make an evaluation fail where the pose term is defined. */
    if (pb->mu > 0.0) {
        for (int k = 0; k < pb->n; k++) {
            double P, dP, d2P;
            e = hp_iab_ik_derivs(&pb->layout->bladders[k].iab, x[6 + k] * 1e-3, &P, &dP, &d2P);
            if (e != HP_OK) return e;
            dP *= 1e-3;
            d2P *= 1e-6;
            double r = P - pb->p_prev[k];
            sum += pb->mu * r * r;
            if (grad) grad[6 + k] = 2.0 * pb->mu * r * dP;
            if (hess) hess[(6 + k) * nx + 6 + k] = 2.0 * pb->mu * (dP * dP + r * d2P);
        }
    }
    if (!isfinite(sum)) return HP_ERR_DOMAIN;
    *f = sum;
    return HP_OK;
}

hp_error hpi_problem_constraints(const hp_problem *pb, const double *x, double *c, double *jac,
                                 const double *lambda, double *hess)
{
    hp_error e = check_problem(pb, x);
    if (e != HP_OK) return e;
    if (lambda && !hess) return HP_ERR_NULL;
    const int n = pb->n, nx = pb->nx;
    const int want_h = lambda != NULL;

    double xi[6];
    for (int i = 0; i < 6; i++) xi[i] = x[i] * hpi_pose_si_per_scaled(i);
    double rho[HP_MAX_BLADDERS];
    double J[HP_MAX_BLADDERS * 6];
    double H[HP_MAX_BLADDERS * 36];
    e = hpi_contact_eval_g(pb->layout, pb->geom, pb->level, xi, rho, jac ? J : NULL,
                           want_h ? H : NULL);
    if (e != HP_OK) return e;

    if (jac) memset(jac, 0, (size_t)n * (size_t)nx * sizeof *jac);
    for (int k = 0; k < n; k++) {
        const hp_iab *b = &pb->layout->bladders[k].iab;
        double ri = x[6 + k];
        double ro_si;
        e = hp_iab_ro(b, ri * 1e-3, &ro_si);
        if (e != HP_OK) return e;
        double ro = ro_si * 1e3;
        double q = ri / ro;
        if (!isfinite(ro) || !isfinite(rho[k])) return HP_ERR_DOMAIN;
        if (c) c[k] = ro - rho[k] * 1e3;
        if (jac) {
            for (int i = 0; i < 6; i++)
                jac[k * nx + i] = -1e3 * hpi_pose_si_per_scaled(i) * J[k * 6 + i];
            jac[k * nx + 6 + k] = q * q;
        }
        if (want_h) {
            double lk = lambda[k];
            for (int i = 0; i < 6; i++)
                for (int j = 0; j < 6; j++)
                    hess[i * nx + j] -= lk * 1e3 * hpi_pose_si_per_scaled(i) *
                                        hpi_pose_si_per_scaled(j) * H[k * 36 + i * 6 + j];
            hess[(6 + k) * nx + 6 + k] += lk * (2.0 * q / ro) * (1.0 - q * q * q);
        }
    }
    return HP_OK;
}
