/* The load model: contact forces of the membrane law, the generalized force on the head
 * with its exact derivatives, the potential, and a Newton–Euler check from the contact
 * points. The geometry (rho, its Jacobian J and Hessian H) comes from hpi_contact_eval_g on
 * the model's own geometry (derived once at setup), so every contact level has exact
 * derivatives:
 *     Q      = sum_k F_k J_k + Q_grav,
 *     dQ/dxi = sum_k (F_k H_k + dF_k/drho · J_k J_kᵀ) + dQ_grav/dxi,
 *     dQ/dP_k = dF_k/dP · J_k,
 * with F(P, ro, rho) and its derivatives from the contact law (contact_law.h, the one
 * home of the formula) and dF/dP taken through ro(P) as well: F_P + F_ro·ro'.
 * The bladder radius ro(P) comes from the bladder model's forward kinematics, and
 * ro'(P) = (dro/dri)/(dP/dri) = (ri/ro)² / (dP/dri). */
#include "headplan/hp_load.h"
#include "common/units.h"
#include "contact_law.h"
#include "load_internal.h"
#include "kin_internal.h"
#include "kinematics/names.h"
#include "common/names.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void hp_load_spec_default(const hp_head *h, hp_load_spec *s)
{
    if (!s) return;
    memset(s, 0, sizeof *s);
    if (h) {
        s->mass = h->mass;
        memcpy(s->com, h->center, sizeof s->com);
    }
    s->gravity[2] = -HP_GRAVITY;
}

hp_error hp_load_spec_validate(const hp_load_spec *s, hp_diag *diag)
{
    if (!s) return hp_diag_set(diag, HP_ERR_NULL, "load: NULL");
    if (!(s->mass > 0) || !isfinite(s->mass))
        return hp_diag_set(diag, HP_ERR_INVALID, "load: mass: must be finite and > 0 (got %g kg)",
                           s->mass);
    if (!hpi_kin_finite3(s->com))
        return hp_diag_set(diag, HP_ERR_INVALID, "load: com: must be finite");
    if (!hpi_kin_finite3(s->gravity))
        return hp_diag_set(diag, HP_ERR_INVALID, "load: gravity: must be finite");
    double g = sqrt(s->gravity[0] * s->gravity[0] + s->gravity[1] * s->gravity[1] +
                    s->gravity[2] * s->gravity[2]);
    if (!(g >= 1e-3 && g <= 1e3))
        return hp_diag_set(diag, HP_ERR_INVALID,
                           "load: gravity: magnitude must be in [1e-3, 1e3] m/s^2 (got %g)", g);
    if ((unsigned)s->law >= (unsigned)HP_LOAD_LAW_COUNT_) {
        char words[32];
        return hp_diag_set(diag, HP_ERR_INVALID, "load: law: must be %s (got %d)",
                           hpi_names_join(hpi_load_law_words, " or ", words, sizeof words),
                           (int)s->law);
    }
    return HP_OK;
}

hp_error hpi_load_model_setup(hp_load_model *M, const hp_layout *L, const hp_load_spec *spec,
                              hp_level level, hp_diag *diag)
{
    if (!M || !L || !spec) return hp_diag_set(diag, HP_ERR_NULL, "load model: NULL argument");
    memset(M, 0, sizeof *M);
    if (!hp_level_is_geometry(level)) {
        char names[64];
        return hp_diag_set(diag, HP_ERR_INVALID, "load model: level must be %s (got %s)",
                           hpi_level_geometry_names(names, sizeof names), hp_level_name(level));
    }
    hp_error err = hp_load_spec_validate(spec, diag);
    if (err) return err;
    M->layout = *L;
    if ((err = hp_layout_prepare(&M->layout, diag))) return err;
    if ((err = hpi_geom_derive(&M->layout, &M->geom, diag))) return err;
    for (int k = 0; k < M->layout.n; ++k)
        if ((err = hp_iab_limit_point(&M->layout.bladders[k].iab, &M->limit[k])))
            return hp_diag_set(diag, err, "bladder '%s': limit point: %s",
                               M->layout.bladders[k].name, hp_error_message(err));
    M->spec = *spec;
    M->level = level;
    /* The one place the load level's law is picked: the spec's (validated above). */
    M->law = spec->law == HP_LOAD_LAW_CAP ? HP_CLAW_LAW_CAP : HP_CLAW_LAW_FEM;
    for (int k = 0; k < M->layout.n; ++k) {
        double x[3]; /* the nominal contact point relative to the head's centre */
        for (int i = 0; i < 3; ++i) x[i] = M->geom.contact[k][i] - M->geom.head.center[i];
        hpi_claw_bladder_of(&M->layout.bladders[k].iab, M->geom.head.semi_axes, x, &M->claw[k]);
    }
    return HP_OK;
}

hp_error hp_load_model_create(const hp_layout *L, const hp_load_spec *spec, hp_level level,
                              hp_load_model **out, hp_diag *diag)
{
    if (!out) return hp_diag_set(diag, HP_ERR_NULL, "load model: NULL argument");
    *out = NULL;
    if (!L || !spec) return hp_diag_set(diag, HP_ERR_NULL, "load model: NULL argument");
    hp_load_model *M = malloc(sizeof *M);
    if (!M) return hp_diag_set(diag, HP_ERR_NOMEM, "load model: out of memory");
    hp_error err = hpi_load_model_setup(M, L, spec, level, diag);
    if (err) {
        free(M);
        return err;
    }
    *out = M;
    return HP_OK;
}

void hp_load_model_destroy(hp_load_model *M) { free(M); }

const hp_layout *hp_load_model_layout(const hp_load_model *M) { return M ? &M->layout : NULL; }

const hp_load_spec *hp_load_model_spec(const hp_load_model *M) { return M ? &M->spec : NULL; }

hp_level hp_load_model_level(const hp_load_model *M) { return M ? M->level : HP_LEVEL_AUTO; }

hp_error hp_load_radius(const hp_load_model *M, int k, double P, double *ro, double *dro_dP)
{
    if (!M || !ro) return HP_ERR_NULL;
    if (k < 0 || k >= M->layout.n || !isfinite(P)) return HP_ERR_INVALID;
    const hp_iab *b = &M->layout.bladders[k].iab;
    double ri, Pc, dP;
    hp_error err = hp_iab_fk_limit(b, &M->limit[k], P, &ri);
    if (!err) err = hp_iab_ro(b, ri, ro);
    if (!err && dro_dP) err = hp_iab_ik_derivs(b, ri, &Pc, &dP, NULL);
    if (err) {
        *ro = NAN;
        if (dro_dP) *dro_dP = NAN;
        return err;
    }
    if (dro_dP) *dro_dP = (ri / *ro) * (ri / *ro) / dP;
    return HP_OK;
}

hp_error hpi_load_radii(const hp_load_model *M, const double *P, double *ro, double *dro)
{
    for (int k = 0; k < M->layout.n; ++k) {
        hp_error err = hp_load_radius(M, k, P[k], &ro[k], dro ? &dro[k] : NULL);
        if (err) return err;
    }
    return HP_OK;
}

void hpi_load_claw(const hp_load_model *M, int k, double P, double ro, double rho, hp_claw *c)
{
    hpi_claw_eval(M->law, &M->claw[k], P, ro, rho, c);
}

void hpi_load_claw_to(const hp_load_model *M, int k, double P, double ro, double rho,
                      hp_claw_order o, hp_claw *c)
{
    hpi_claw_eval_to(M->law, &M->claw[k], P, ro, rho, o, c);
}

void hpi_load_claw_drho(const hp_load_model *M, int k, double P, double ro, double rho, hp_claw *c)
{
    hpi_claw_eval_drho(M->law, &M->claw[k], P, ro, rho, c);
}

hp_error hpi_load_claw_check(const hp_load_model *M, int k, double P, double ro, double rho,
                             hp_diag *diag)
{
    if (M->law != HP_CLAW_LAW_FEM) return HP_OK;
    hp_claw_domain g = hpi_claw_fem_domain(&M->claw[k], P, ro, rho);
    if (g == HP_CLAW_IN) return HP_OK;
    return hp_diag_set(diag, HP_ERR_INVALID,
                       "load: bladder '%s': contact outside the fitted law's domain (%s: "
                       "delta/ro %.3g, P/C1 %.3g, ro/Rh %.3g)",
                       M->layout.bladders[k].name, hpi_claw_domain_name(g), 1.0 - rho / ro,
                       P / M->claw[k].C1, ro * M->claw[k].curv);
}

void hpi_load_law(const hp_load_model *M, int k, double P, double ro, double dro, double rho,
                  int right, hp_load_force *f)
{
    hp_claw c; /* F, its gradient and W: no Hessian */
    hpi_load_claw_to(M, k, P, ro, rho, HP_CLAW_GRADIENT | HP_CLAW_WORK, &c);
    int on = P > 0 && ro > rho;
    /* right: the derivatives of the contact branch also where the bladder just touches
     * (the one-sided derivative a planner needs to bring a bladder into contact). */
    int d_on = on || (right && P >= 0 && ro >= rho);
    f->F = on ? c.F : 0.0;
    f->dF_drho = d_on ? c.d[HP_CLAW_RHO] : 0.0;
    f->dF_dP = d_on ? c.d[HP_CLAW_P] + c.d[HP_CLAW_RO] * dro : 0.0;
    f->dF_dro = d_on ? c.d[HP_CLAW_RO] : 0.0;
    f->E = on ? c.W : 0.0;
}

void hpi_load_gravity(const hp_load_model *M, const double xi[6], double Q[6], double *dQ,
                      double *energy)
{
    const hp_layout *L = &M->layout;
    double R[9], dR[3][9], d2R[3][3][9], v[3], mg[3];
    hpi_kin_rotation_derivs(xi + 3, R, dR, dQ ? d2R : NULL);
    for (int i = 0; i < 3; ++i) {
        v[i] = M->spec.com[i] - L->pivot[i];
        mg[i] = M->spec.mass * M->spec.gravity[i];
        Q[i] = mg[i];
    }
    for (int j = 0; j < 3; ++j) {
        double s = 0.0;
        for (int a = 0; a < 3; ++a)
            s += mg[a] * (dR[j][a * 3] * v[0] + dR[j][a * 3 + 1] * v[1] + dR[j][a * 3 + 2] * v[2]);
        Q[3 + j] = s;
    }
    if (dQ) {
        memset(dQ, 0, 36 * sizeof *dQ);
        for (int j = 0; j < 3; ++j)
            for (int l = 0; l < 3; ++l) {
                double s = 0.0;
                const double *D = d2R[j][l];
                for (int a = 0; a < 3; ++a)
                    s += mg[a] * (D[a * 3] * v[0] + D[a * 3 + 1] * v[1] + D[a * 3 + 2] * v[2]);
                dQ[(3 + j) * 6 + 3 + l] = s;
            }
    }
    if (energy) {
        /* −m gᵀ (x_com(xi) − x_com0), x_com − x_com0 = (R − I) v + t */
        double e = 0.0;
        for (int a = 0; a < 3; ++a) {
            double dx = xi[a] + R[a * 3] * v[0] + R[a * 3 + 1] * v[1] + R[a * 3 + 2] * v[2] - v[a];
            e -= mg[a] * dx;
        }
        *energy = e;
    }
}

static void fill_nan(double *v, int n)
{
    if (v)
        for (int i = 0; i < n; ++i) v[i] = NAN;
}

hp_error hpi_load_domain(const hp_load_model *M, const double *rho)
{
    for (int k = 0; k < M->layout.n; ++k)
        if (!(rho[k] > 0.0)) return HP_ERR_DOMAIN; /* NaN too */
    return HP_OK;
}

hp_error hpi_load_eval_radii(const hp_load_model *M, const double xi[6], const double *P,
                             const double *ro, const double *dro, int right, double Q[6],
                             double *dQ_dxi, double *dQ_dP, double *force, double *energy)
{
    const hp_layout *L = &M->layout;
    int n = L->n;
    double rho[HP_MAX_BLADDERS], J[HP_MAX_BLADDERS * 6], H[HP_MAX_BLADDERS * 36];
    hp_error err = hpi_contact_eval_g(L, &M->geom, M->level, xi, rho, J, dQ_dxi ? H : NULL);
    if (!err) err = hpi_load_domain(M, rho);
    if (err) return err;
    double e = 0.0;
    hpi_load_gravity(M, xi, Q, dQ_dxi, energy ? &e : NULL);
    for (int k = 0; k < n; ++k) {
        hp_load_force f;
        hpi_load_law(M, k, P[k], ro[k], dro ? dro[k] : 0.0, rho[k], right, &f);
        const double *Jk = J + 6 * k;
        for (int i = 0; i < 6; ++i) Q[i] += f.F * Jk[i];
        if (dQ_dxi && (f.F != 0.0 || f.dF_drho != 0.0))
            for (int i = 0; i < 6; ++i)
                for (int j = 0; j < 6; ++j)
                    dQ_dxi[i * 6 + j] += f.F * H[k * 36 + i * 6 + j] + f.dF_drho * Jk[i] * Jk[j];
        if (dQ_dP)
            for (int i = 0; i < 6; ++i) dQ_dP[i * n + k] = f.dF_dP * Jk[i];
        if (force) force[k] = f.F;
        e += f.E;
    }
    if (energy) *energy = e;
    return HP_OK;
}

static hp_error check_inputs(const hp_load_model *M, const double xi[6], const double *P)
{
    if (!M || !xi || !P) return HP_ERR_NULL;
    for (int i = 0; i < 6; ++i)
        if (!isfinite(xi[i])) return HP_ERR_INVALID;
    for (int k = 0; k < M->layout.n; ++k)
        if (!isfinite(P[k])) return HP_ERR_INVALID;
    return HP_OK;
}

hp_error hp_load_eval(const hp_load_model *M, const double xi[6], const double *P, double Q[6],
                      double *dQ_dxi, double *dQ_dP, double *force, double *energy)
{
    if (!Q) return HP_ERR_NULL;
    hp_error err = check_inputs(M, xi, P);
    double ro[HP_MAX_BLADDERS], dro[HP_MAX_BLADDERS];
    if (!err) err = hpi_load_radii(M, P, ro, dQ_dP ? dro : NULL);
    if (!err)
        err = hpi_load_eval_radii(M, xi, P, ro, dQ_dP ? dro : NULL, 0, Q, dQ_dxi, dQ_dP, force,
                                  energy);
    if (err) {
        int n = M ? M->layout.n : 0;
        fill_nan(Q, 6);
        fill_nan(dQ_dxi, 36);
        fill_nan(dQ_dP, 6 * n);
        fill_nan(force, n);
        fill_nan(energy, 1);
    }
    return err;
}

hp_error hp_load_indentation(const hp_load_model *M, const double xi[6], const double *P,
                             double *ratio)
{
    if (!ratio) return HP_ERR_NULL;
    hp_error err = check_inputs(M, xi, P);
    double ro[HP_MAX_BLADDERS], rho[HP_MAX_BLADDERS];
    if (!err) err = hpi_load_radii(M, P, ro, NULL);
    if (!err) err = hpi_contact_eval_g(&M->layout, &M->geom, M->level, xi, rho, NULL, NULL);
    if (!err) err = hpi_load_domain(M, rho);
    if (err) {
        fill_nan(ratio, M ? M->layout.n : 0);
        return err;
    }
    for (int k = 0; k < M->layout.n; ++k) ratio[k] = P[k] > 0 ? (ro[k] - rho[k]) / ro[k] : 0.0;
    return HP_OK;
}

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* x moved with the head: pivot + R (x0 − pivot) + t. */
static void move_point(const hp_layout *L, const double R[9], const double t[3], const double x0[3],
                       double x[3])
{
    const double v[3] = {x0[0] - L->pivot[0], x0[1] - L->pivot[1], x0[2] - L->pivot[2]};
    for (int a = 0; a < 3; ++a)
        x[a] = L->pivot[a] + R[a * 3] * v[0] + R[a * 3 + 1] * v[1] + R[a * 3 + 2] * v[2] + t[a];
}

/* The contact point p_k at pose xi (moved head), for the Newton–Euler check. */
static hp_error contact_point(const hp_load_model *M, int k, const double R[9], const double xi[6],
                              double rho, double p[3])
{
    const hp_layout *L = &M->layout;
    const double *c = L->bladders[k].center;
    const double *nk = M->geom.normal[k]; /* the nominal normal */
    if (M->level == HP_LEVEL_LINEAR) {
        for (int a = 0; a < 3; ++a) p[a] = c[a] - rho * nk[a];
        return HP_OK;
    }
    /* The centre seen from the head's own frame: c' = Rᵀ(c − pivot − t) + pivot. */
    double u[3], cp[3], foot[3];
    for (int a = 0; a < 3; ++a) u[a] = c[a] - L->pivot[a] - xi[a];
    for (int a = 0; a < 3; ++a)
        cp[a] = R[a] * u[0] + R[3 + a] * u[1] + R[6 + a] * u[2] + L->pivot[a];
    if (M->level == HP_LEVEL_SURFACE) {
        double d;
        hp_error err = hpi_kin_head_distance(&L->head, cp, &d, NULL, NULL, foot);
        if (err) return err;
    } else {
        for (int a = 0; a < 3; ++a) foot[a] = cp[a] - rho * nk[a];
    }
    move_point(L, R, xi, foot, p);
    return HP_OK;
}

hp_error hp_load_newton_euler(const hp_load_model *M, const double xi[6], const double *P,
                              double force[3], double moment[3])
{
    if (!force || !moment) return HP_ERR_NULL;
    hp_error err = check_inputs(M, xi, P);
    if (err) return err;
    const hp_layout *L = &M->layout;
    double ro[HP_MAX_BLADDERS], rho[HP_MAX_BLADDERS], R[9], com[3];
    if ((err = hpi_load_radii(M, P, ro, NULL))) return err;
    if ((err = hpi_contact_eval_g(L, &M->geom, M->level, xi, rho, NULL, NULL))) return err;
    if ((err = hpi_load_domain(M, rho))) return err;
    hp_rotation(xi[3], xi[4], xi[5], R);
    move_point(L, R, xi, M->spec.com, com);
    for (int a = 0; a < 3; ++a) {
        force[a] = M->spec.mass * M->spec.gravity[a];
        moment[a] = 0.0;
    }
    for (int k = 0; k < L->n; ++k) {
        hp_load_force f;
        hpi_load_law(M, k, P[k], ro[k], 0.0, rho[k], 0, &f);
        if (f.F == 0.0) continue;
        double p[3], u[3], fk[3], arm[3], m[3];
        if ((err = contact_point(M, k, R, xi, rho[k], p))) return err;
        const double *c = L->bladders[k].center;
        double len = sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                          (p[2] - c[2]) * (p[2] - c[2]));
        for (int a = 0; a < 3; ++a) {
            u[a] = (p[a] - c[a]) / len;
            fk[a] = f.F * u[a];
            arm[a] = p[a] - com[a];
            force[a] += fk[a];
        }
        cross(arm, fk, m);
        for (int a = 0; a < 3; ++a) moment[a] += m[a];
    }
    return HP_OK;
}
