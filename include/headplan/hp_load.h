/* The load level: the head's weight carried by the bladders' contact forces.
 *
 * A bladder carries load only by flattening against the head. With p_k the head-surface
 * point nearest to the bladder centre c_k, rho_k = |p_k − c_k| (the contact distance of the
 * chosen geometry: linear, plane or surface) and ro_k(P_k) the bladder's free outer radius
 * at pressure P_k (the bladder model's forward kinematics, stable branch), the indentation
 * is delta_k = ro_k − rho_k and the load's contact law (hp_load_spec.law) gives the contact
 * force F_k = F(P_k, ro_k, rho_k) when delta_k > 0 and P_k > 0, else 0: by default the law
 * fitted to the finite-element reference of the bladder (HP_LOAD_LAW_FEM), or the cap law
 *     F_k = P_k·pi·(2·ro_k·delta_k − delta_k²) = P_k·pi·(ro_k² − rho_k²)
 * (HP_LOAD_LAW_CAP: the pressure times the base of the spherical cap cut off by the head).
 * It pushes the head along u_k = (p_k − c_k)/rho_k. Gravity m·g acts at the centre of mass.
 * See docs/load.md.
 *
 * The six equilibrium equations are written as the generalized force on the pose
 * coordinates xi = (x, y, z, pitch, roll, yaw):
 *     Q(xi, P) = sum_k F_k·(d rho_k / d xi) + m·(d x_com / d xi)ᵀ·g = 0.
 * Its translation rows are exactly sum_k f_k + m·g (N); its rotation rows are the total
 * moment about the moved pivot projected on the three Euler-angle axes (N·m per rad), so
 * Q = 0 is the Newton–Euler equilibrium wherever the angles are regular (|roll| < 90°).
 * Q = −dPi/dxi for the potential Pi = sum_k W_k − m·gᵀ(x_com − x_com0) (W_k the work of the
 * contact force from first touch; for the cap law P_k times the cap's volume), so the
 * stiffness K = −dQ/dxi is symmetric and a rest is stable exactly when K is positive
 * definite.
 *
 * Units: SI throughout (m, rad, Pa, N, kg). Every function is reentrant and allocates
 * nothing, except hp_load_model_create. */
#ifndef HP_LOAD_H
#define HP_LOAD_H

#include "headplan/hp_common.h"
#include "headplan/hp_contact.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Standard gravity [m/s²]. */
#define HP_GRAVITY 9.80665

/* The indentation range where the contact law is trusted: a carrying bladder (P > 0, in
 * contact) with delta/ro at most this. The finite-element tables the fitted law comes from
 * end there, and docs/load.md checks the cap law against a membrane solution up to it; the load planner treats it as a limit
 * (bound by the name "indent_max", HP_BIND_INDENT_MAX) and the forward statics flags a
 * rest beyond it (hp_load_rest_info.beyond_indent). */
#define HP_LOAD_INDENT_MAX 0.26

/* The contact law the load model evaluates (docs/load.md, "The contact law").
 * HP_LOAD_LAW_FEM (the default): the law fitted to the finite-element reference of a thick
 * Mooney–Rivlin bladder (docs/accuracy.md, section 5), with its domain enforced on every
 * answer. HP_LOAD_LAW_CAP: the cap law F = P·pi·(ro² − rho²) of the header's comment, the
 * rigid-sphere picture that overestimates the force 2.5–5.6× against that reference; kept
 * for comparison studies and for tests of its own algebra. */
typedef enum hp_load_law { HP_LOAD_LAW_FEM = 0, HP_LOAD_LAW_CAP, HP_LOAD_LAW_COUNT_ } hp_load_law;
HP_API const char *hp_load_law_name(hp_load_law l); /* "fem", "cap"; "unknown" otherwise */
HP_API hp_error hp_load_law_parse(const char *s, hp_load_law *out);

/* What the bladders carry. */
typedef struct hp_load_spec {
    double mass;       /* [kg] the mass whose weight the bladders carry (> 0) */
    double com[3];     /* [m] its centre of mass at the nominal pose */
    double gravity[3]; /* [m/s²] acceleration of gravity (non-zero), e.g. (0, 0, −9.80665) */
    hp_load_law law;   /* the contact law (HP_LOAD_LAW_FEM by default) */
} hp_load_spec;

/* Defaults for head h: all of its mass, centre of mass at its centre, gravity along −Z
 * (supine patient), the fitted contact law. */
HP_API void hp_load_spec_default(const hp_head *h, hp_load_spec *s);

/* Checks: mass finite > 0, com finite, gravity finite with |g| in [1e-3, 1e3] m/s², law one
 * of hp_load_law. HP_ERR_NULL / HP_ERR_INVALID with the field named in diag (may be NULL). */
HP_API hp_error hp_load_spec_validate(const hp_load_spec *s, hp_diag *diag);

/* A layout, what it carries, and the contact level, ready for load evaluations: an opaque
 * handle. It owns private copies of the layout and the load and everything derived from
 * them (each bladder's limit point, the layout's nominal contact geometry), so nothing the
 * caller edits afterwards can leave it inconsistent. */
typedef struct hp_load_model hp_load_model;

/* Copies and validates layout L (hp_layout_prepare on the copy) and spec, checks level
 * (linear, plane or surface; not auto), finds every bladder's limit point and derives the
 * contact geometry once. *out gets the new model (NULL on error); the only allocation of
 * the load model, freed by hp_load_model_destroy. HP_ERR_* with the message in diag (may
 * be NULL). */
HP_API hp_error hp_load_model_create(const hp_layout *L, const hp_load_spec *spec, hp_level level,
                                     hp_load_model **out, hp_diag *diag);
/* Frees a model of hp_load_model_create (NULL is a no-op). */
HP_API void hp_load_model_destroy(hp_load_model *M);

/* The model's validated copy of the layout (NULL for NULL M); valid until destroy. */
HP_API const hp_layout *hp_load_model_layout(const hp_load_model *M);
/* The model's copy of what the bladders carry (NULL for NULL M); valid until destroy. */
HP_API const hp_load_spec *hp_load_model_spec(const hp_load_model *M);
/* The model's contact level (HP_LEVEL_AUTO for NULL M, which no model has). */
HP_API hp_level hp_load_model_level(const hp_load_model *M);

/* Free outer radius ro [m] of bladder k at pressure P [Pa] (stable branch) and dro/dP
 * [m/Pa] (may be NULL). HP_ERR_NO_STABLE at or above the limit-point pressure. */
HP_API hp_error hp_load_radius(const hp_load_model *M, int k, double P, double *ro, double *dro_dP);

/* The load at pose xi [m, rad] with pressures P[n] [Pa]:
 *   Q[6]        generalized force on the head (0 at a rest), N and N·m/rad;
 *   dQ_dxi[36]  its exact Jacobian (row-major, = −K), may be NULL;
 *   dQ_dP[6n]   its exact Jacobian w.r.t. the pressures (row i, column k), may be NULL;
 *   force[n]    each bladder's contact force magnitude F_k [N], may be NULL;
 *   energy      the potential Pi [J] (0 at the nominal pose with no contact), may be NULL.
 * Off contact (delta <= 0 or P <= 0) a bladder contributes nothing and its derivatives are
 * 0 (the law has a kink there). HP_ERR_INVALID for NaN/Inf inputs, HP_ERR_DOMAIN when the
 * geometry fails (surface, deep inside the head) or a bladder centre lies inside or on the
 * moved head (rho_k <= 0 for any k, whatever its pressure: the head through that bladder's
 * panel, where the membrane law describes nothing), HP_ERR_NO_STABLE for a pressure past a
 * limit point; outputs NaN on error. */
HP_API hp_error hp_load_eval(const hp_load_model *M, const double xi[6], const double *P,
                             double Q[6], double *dQ_dxi, double *dQ_dP, double *force,
                             double *energy);

/* Newton–Euler check, computed from the contact points themselves (not from Q): the net
 * force sum_k F_k·u_k + m·g [N] and the net moment sum_k (p_k − x_com) × F_k·u_k about the
 * moved centre of mass [N·m]. p_k is the moved head's surface point nearest to c_k
 * (surface), the moved tangent-plane foot (plane) or c_k − rho_k·n_k (linear, whose
 * geometry is the linearised one: there Q and this check differ at second order). Same
 * domain as hp_load_eval (HP_ERR_DOMAIN when a centre lies inside or on the moved head). */
HP_API hp_error hp_load_newton_euler(const hp_load_model *M, const double xi[6], const double *P,
                                     double force[3], double moment[3]);

/* Each bladder's indentation ratio delta_k/ro_k = (ro_k(P_k) − rho_k)/ro_k at pose xi with
 * pressures P[n] (ratio[n]; negative when the bladder is clear of the head; 0 for a bladder
 * that carries nothing, P_k <= 0, whose law says nothing about its shape). Same errors and
 * domain as hp_load_eval. The contact law is trusted up to HP_LOAD_INDENT_MAX. */
HP_API hp_error hp_load_indentation(const hp_load_model *M, const double xi[6], const double *P,
                                    double *ratio);

/* How firmly the head is held at a pose. */
typedef struct hp_load_holding {
    double K[36];              /* stiffness −dQ/dxi, SI (N/m, N/rad, N·m/m, N·m/rad) */
    int stable;                /* 1 when K is positive definite (a stable rest) */
    double compliance[6];      /* diagonal of K⁻¹: mm/N (x, y, z) and deg/(N·m) (angles);
                                 +inf when K is singular */
    double weakest[6];         /* unit direction (in mm and degrees) of least stiffness */
    double weakest_compliance; /* compliance along it: mm/N when it is mostly translation,
                                 deg/(N·m) when mostly rotation; +inf when singular */
    int weakest_is_rotation;   /* 1 when the weakest direction is mostly rotation */
    char weakest_words[160];   /* e.g. "longitudinal (y) with some pitch" */
    double k_gravity;          /* translational stiffness along gravity ĝᵀ·K_tt·ĝ [N/m] */
    double sag;                /* predicted sag m·|g| / k_gravity [m]; +inf when k <= 0 */
} hp_load_holding;

/* Stiffness, stability and compliance at pose xi with pressures P (from hp_load_eval and
 * a symmetric eigen-decomposition in mm/degree units, where 1 mm weighs as 1 degree). */
HP_API hp_error hp_load_holding_at(const hp_load_model *M, const double xi[6], const double *P,
                                   hp_load_holding *out);

/* Result of the forward statics. */
typedef struct hp_load_rest_info {
    int iterations;
    double residual_force;  /* |sum f + m g| [N] at the rest (Newton–Euler check) */
    double residual_moment; /* |net moment about the centre of mass| [N·m] */
    double q_norm;          /* max |Q_i| [N, N·m] at the rest */
    double indent_max;      /* the largest delta_k/ro_k of a carrying bladder at the rest (0
                               when none carries) */
    int beyond_indent;      /* 1 when indent_max > HP_LOAD_INDENT_MAX: the rest lies outside
                               the range where the contact law is trusted */
    hp_load_holding holding;
} hp_load_rest_info;

/* Forward statics: the pose where the head rests under pressures P[n], by Newton's method
 * on the potential (exact Hessian K, Levenberg shift where K is not positive definite,
 * Armijo backtracking on Pi, steps capped at 5 mm / 5°), from xi0 (NULL = nominal). Stops
 * when the step is below 1e-12 mm / degree or Q vanishes to rounding. xi gets the rest
 * pose; info (may be NULL) the residuals and the holding. HP_ERR_NO_CONVERGENCE when no
 * rest is found in 100 steps (e.g. the head falls: nothing pushes against gravity), the
 * pose leaves 100 mm / 60°, or the descent runs into a bladder's panel (every step, down to
 * 2^-50 of it, leaves hp_load_eval's domain) or stops where Q is above 1e-6 N (moment
 * rows per 1°/1 mm); HP_ERR_DOMAIN when xi0 lies outside it. A rest with K not positive definite is returned with
 * info->holding.stable = 0. */
HP_API hp_error hp_load_rest(const hp_load_model *M, const double *P, const double *xi0,
                             double xi[6], hp_load_rest_info *info);

/* The sag the load would cause at the nominal pose if the bladders held the pressures a
 * kinematic plan gives there (each bladder at the pressure whose free radius is the
 * nominal contact distance, touching with zero force): the weight m·|g| over the
 * bladders' combined stiffness along gravity, ĝᵀ·K_tt·ĝ, with K taken on the contact
 * branch (the stiffness a touching bladder has as soon as it is pressed). +inf when that
 * stiffness is zero (nothing inflated at the nominal pose). sag [m] and k_gravity [N/m]
 * (may be NULL). */
HP_API hp_error hp_load_predicted_sag(const hp_load_model *M, double *sag, double *k_gravity);

/* The sag criterion: the load level when the predicted sag exceeds tol [m] (> 0), else the
 * kinematic levels. `auto` itself picks by the levels' model error (docs/load.md,
 * "`auto`, `analyze`, `solve`"); this is the sag half of what `analyze` reports beside it. *use_load gets 1 or 0 and why (may be
 * NULL, len bytes) one line saying so with the numbers, e.g. "load: predicted sag
 * 12.3 mm > tolerance 0.01 mm". */
HP_API hp_error hp_load_auto_choose(const hp_load_model *M, double tol, int *use_load, double *sag,
                                    char *why, size_t len);

#ifdef __cplusplus
}
#endif
#endif
