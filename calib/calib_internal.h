/* Shared inside calib/: the bladder model's radius with its derivatives for the material fits,
 * and the damped least-squares step and covariance the fits with more than two parameters
 * use. Not installed. */
#ifndef CALIB_INTERNAL_H
#define CALIB_INTERNAL_H

#include "headplan/hp_calib.h"
#include "kinematics/kin_geom.h"

/* Which reference radius a material fit adjusts besides the moduli. */
enum { CALIB_REF_NONE = 0, CALIB_REF_RI, CALIB_REF_RO };

/* The model's radius r (inner or outer, kind) at pressure P on the stable branch of bladder m
 * (limit point lp) and its exact derivatives dr[0] = dr/dC1, dr[1] = dr/dC2 and, unless ref
 * is CALIB_REF_NONE, dr[2] = dr/dRi or dr/dRo (implicit function theorem on the closed form).
 * HP_ERR_NO_STABLE when P has no stable radius. */
hp_error calib_model_radius(const hp_iab *m, const hp_iab_limit *lp, hp_calib_radius kind, double P,
                            int ref, double *r, double dr[3]);

/* Sets every number of a material fit to NaN and its counts to 0 (a failed fit answers
 * nothing). */
void calib_material_invalidate(hp_material_fit *out);

/* Fills a successful material fit: moduli C, standard errors se, their correlation, the
 * condition number, dof = n − parameters, unit-weight variance s2, weighted residuals e (resid,
 * may be NULL, gets them in metres), the iterations and the fitted limit point lp. */
void calib_material_result(hp_material_fit *out, const double C[2], const double se[2], double corr,
                           double cond, int dof, double s2, const double *e,
                           const hp_calib_point *pts, int n, double *resid, int iterations,
                           const hp_iab_limit *lp);

/* Copies the columns cols[0..k) of J (m×np, row-major) into S (m×k), each scaled to unit
 * norm (its norm in scale[q]; 1 for a zero column). */
void calib_columns(int m, int np, const double *J, const int *cols, int k, double *S,
                   double *scale);

/* Levenberg–Marquardt step dx (k values, parameter units) for unit-column Jacobian S (m×k)
 * with column norms scale and residuals e: (SᵀS + λI)·y = −Sᵀe through the SVD, dx = y/scale. */
hp_error calib_lm_step(int m, int k, const double *S, const double *scale, const double *e,
                       double lambda, double *dx);

/* (JᵀJ)⁻¹ (k×k, parameter units) from S and scale as above, and the condition number of S
 * (may be NULL). HP_ERR_INVALID when S is singular. */
hp_error calib_covariance(int m, int k, const double *S, const double *scale, double *C,
                          double *cond);

/* ---- layout fit ---- */

typedef struct lay_ctx {
    const hp_layout *L0;
    hp_geom G0; /* L0's contact geometry: the offsets move along its normals */
    const hp_calib_row *rows;
    int n, dofp, np, nsel;
    int n_axes; /* 0, 1 (sphere) or 3 */
    int mass_j; /* index of the carried mass among the parameters, or -1 */
    int sel[HP_CALIB_MAX_PARAMS];
    hp_level level;
    const hp_load_spec *load; /* NULL: contact forward kinematics; else forward statics */
    double w[6];              /* 1/σ per pose component */
    double (*ro)[HP_MAX_BLADDERS];
} lay_ctx;

/* The layout with parameters theta (np changes from the scene, in the parameter order),
 * and its contact geometry G (calib_layout_param.c); validate = 1 runs the full hp_layout_prepare checks. */
hp_error calib_layout_apply(const lay_ctx *c, const double *theta, hp_layout *L, hp_geom *G,
                            int validate, hp_diag *d);

/* The load level's weighted residuals (measured − rest pose)·w of every row, for layout L
 * (from calib_layout_apply at theta) carrying c->load with its mass changed by theta's mass
 * entry; each rest is searched from start[i] (or the nominal pose); poses may be NULL. */
hp_error calib_load_resid(const lay_ctx *c, const hp_layout *L, const double *theta, double *e,
                          const double (*start)[6], double (*poses)[6]);

/* The load level's Jacobian of those residuals (m×np, row-major): dξ/dθ = K⁻¹·∂Q/∂θ. */
hp_error calib_load_jacobian(const lay_ctx *c, const double *theta, double *J);

#endif
