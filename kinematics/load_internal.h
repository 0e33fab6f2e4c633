/* Internal pieces of the load model shared by the forward statics and the load planner.
 * Not installed. */
#ifndef HP_LOAD_INTERNAL_H
#define HP_LOAD_INTERNAL_H

#include "headplan/hp_load.h"
#include "contact_law.h"
#include "kin_geom.h"

/* The load model behind the public handle. Every field is derived by hpi_load_model_setup
 * from its arguments and never changed afterwards, so the limits and the geometry always
 * belong to this layout. Objects that own a model embed it (the load planner) so that
 * their create is their only allocation. */
struct hp_load_model {
    hp_layout layout;                      /* validated copy (hp_layout_prepare) */
    hp_geom geom;                          /* layout's nominal contact geometry */
    hp_load_spec spec;                     /* validated copy */
    hp_level level;                        /* linear, plane or surface */
    hp_iab_limit limit[HP_MAX_BLADDERS];   /* each bladder's inflation limit point */
    hp_claw_law law;                       /* the contact law (the spec's, at setup) */
    hp_claw_bladder claw[HP_MAX_BLADDERS]; /* what the fitted law needs of each bladder,
                                              at its nominal contact point */
};

/* Bladder k's contact law at (P, ro, rho): hpi_claw_eval with the model's law and bladder. */
void hpi_load_claw(const hp_load_model *M, int k, double P, double ro, double rho, hp_claw *c);

/* hpi_load_claw up to order o (hpi_claw_eval_to): for the callers that use no Hessian. */
void hpi_load_claw_to(const hp_load_model *M, int k, double P, double ro, double rho,
                      hp_claw_order o, hp_claw *c);

/* Bladder k's dF/drho at (P, ro, rho) with its own derivatives: hpi_claw_eval_drho with the
 * model's law and bladder. */
void hpi_load_claw_drho(const hp_load_model *M, int k, double P, double ro, double rho, hp_claw *c);

/* HP_OK when bladder k's contact state (P, ro, rho) lies in the model law's domain (the
 * cap law has none); else HP_ERR_INVALID with a message naming the bladder and the group
 * that leaves the fitted law's domain (hpi_claw_fem_domain). */
hp_error hpi_load_claw_check(const hp_load_model *M, int k, double P, double ro, double rho,
                             hp_diag *diag);

/* hp_load_model_create without the allocation: fills *M (same checks, same messages). */
hp_error hpi_load_model_setup(hp_load_model *M, const hp_layout *L, const hp_load_spec *spec,
                              hp_level level, hp_diag *diag);

/* One bladder's contact force and its partial derivatives. */
typedef struct hp_load_force {
    double F;       /* [N] */
    double dF_drho; /* [N/m] */
    double dF_dP;   /* [N/Pa], through ro(P) as well */
    double dF_dro;  /* [N/m] at fixed P */
    double E;       /* [J] P times the volume of the cap the head cuts off */
} hp_load_force;

/* The membrane law for pressure P, free outer radius ro (with dro = dro/dP) and contact
 * distance rho. right = 1 gives the contact branch's derivatives also where the bladder
 * just touches (delta = 0 or P = 0), the one-sided derivative a planner needs. */
void hpi_load_law(const hp_load_model *M, int k, double P, double ro, double dro, double rho,
                  int right, hp_load_force *f);

/* Gravity's generalized force m·(dx_com/dxi)ᵀ·g at xi, its Jacobian dQ (36, row-major; may
 * be NULL) and its potential (may be NULL): Q of a head that no bladder touches, without
 * the contact geometry's cost. */
void hpi_load_gravity(const hp_load_model *M, const double xi[6], double Q[6], double *dQ,
                      double *energy);

/* Outer radii (and dro/dP when dro is not NULL) of every bladder at pressures P. */
hp_error hpi_load_radii(const hp_load_model *M, const double *P, double *ro, double *dro);

/* The load model's domain: every bladder centre strictly outside the moved head (rho_k > 0
 * for all k, whatever the pressures). A centre sits on its rigid panel, so rho_k <= 0 puts
 * the head through that panel, which the membrane law does not describe: there the
 * potential's gradient (Q, along dRho/dxi, continued through rho = 0) and the force along
 * the contact point's direction (p − c)/|p − c| point opposite ways. HP_ERR_DOMAIN outside
 * (a NaN distance too), else HP_OK. */
hp_error hpi_load_domain(const hp_load_model *M, const double *rho);

/* hp_load_eval with the radii already known (no input checks, no NaN fill): the cheap
 * inner evaluation of Newton and SQP loops. */
hp_error hpi_load_eval_radii(const hp_load_model *M, const double xi[6], const double *P,
                             const double *ro, const double *dro, int right, double Q[6],
                             double *dQ_dxi, double *dQ_dP, double *force, double *energy);

/* Cholesky factor of a symmetric n×n matrix A (row-major) in place (lower triangle);
 * returns 0 when A is positive definite, -1 otherwise. */
int hpi_load_cholesky(int n, double *A);
/* Solves L Lᵀ x = b with the factor of hpi_load_cholesky (b overwritten by x). */
void hpi_load_cholesky_solve(int n, const double *Lf, double *b);

/* Scale of pose component i: 1 mm in m, 1 degree in rad. */
double hpi_load_unit(int i);

#endif
