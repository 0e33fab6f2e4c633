/* One inflatable air bladder (IAB): a thick spherical shell of incompressible
 * Mooney–Rivlin rubber. All quantities in SI: metres, pascals.
 *
 * Strain energy in the paper's convention: W = ½·C1·(I1−3) + ½·C2·(I2−3).
 * Finite-element tools write W = C10·(I1−3) + C01·(I2−3); then C1 = 2·C10, C2 = 2·C01.
 *
 * Every function here is pure, reentrant, allocates nothing and is safe to call from any
 * number of threads at once. */
#ifndef HP_IAB_H
#define HP_IAB_H

#include "headplan/hp_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A bladder's reference geometry and material. Valid when 0 < Ri < Ro, C1 > 0, C2 >= 0,
 * all finite (C2 = 0 is the neo-Hookean shell, which has an inflation limit point). */
typedef struct hp_iab {
    double Ri; /* reference (unpressurised) inner radius [m] */
    double Ro; /* reference outer radius [m] */
    double C1; /* Mooney–Rivlin modulus, paper convention [Pa] */
    double C2; /* Mooney–Rivlin modulus, paper convention [Pa] */
} hp_iab;

/* Which convention a pair of moduli is written in. */
typedef enum hp_material_convention {
    HP_MATERIAL_PAPER = 0, /* "paper": C1, C2 with W = ½C1(I1−3) + ½C2(I2−3) */
    HP_MATERIAL_FE         /* "fe": C10, C01 with W = C10(I1−3) + C01(I2−3) */
} hp_material_convention;

/* "paper" / "fe"; "unknown" for other values. */
HP_API const char *hp_material_convention_name(hp_material_convention c);
/* Parses "paper" or "fe"; returns HP_ERR_INVALID for anything else. */
HP_API hp_error hp_material_convention_parse(const char *s, hp_material_convention *out);

/* Converts moduli (a, b) given in convention conv to the paper's (C1, C2). */
HP_API hp_error hp_iab_moduli_to_paper(hp_material_convention conv, double a, double b, double *C1,
                                       double *C2);

/* Checks a bladder: finite values, 0 < Ri < Ro, C1 > 0, C2 >= 0, and Ri >= 1e-9·Ro (a
 * thinner cavity is no bladder, and the bound keeps every power of a radius the model forms
 * in the double range). On failure returns HP_ERR_NULL, HP_ERR_INVALID (NaN/Inf, wrong sign)
 * or HP_ERR_DOMAIN (Ri >= Ro, Ri < 1e-9·Ro) and writes a message naming the field ("Ri",
 * "Ro", "C1", "C2") into diag (may be NULL). Every other function here runs the same checks
 * first and returns the same code. */
HP_API hp_error hp_iab_validate(const hp_iab *b, hp_diag *diag);

/* Volume law: outer radius [m] for inner radius ri [m], ro³ = Ro³ + ri³ − Ri³, formed as
 * ∛((Ro³ − Ri³) + ri³) (no cancellation; the library's own correctly rounded cube root;
 * ≤ 2 ulps asserted). HP_ERR_INVALID for NaN/Inf ri,
 * HP_ERR_DOMAIN for ri <= 0 or ri outside 1e±30 of Ro. */
HP_API hp_error hp_iab_ro(const hp_iab *b, double ri, double *ro);

/* Inverse volume law: inner radius for outer radius ro [m]; HP_ERR_DOMAIN when the cavity
 * would collapse (ro³ <= Ro³ − Ri³). Newton-refined on a cancellation-free residual: a few
 * ulps wherever the law is well conditioned (dri/dro = ro²/ri²). */
HP_API hp_error hp_iab_ri(const hp_iab *b, double ro, double *ri);

/* Inverse kinematics, closed form: internal pressure [Pa] that holds inner radius ri [m].
 * P = 2·C1·[f(λi) − f(λo)] + 2·C2·[g(λi) − g(λo)], f(λ) = −1/λ − 1/(4λ⁴), g(λ) = λ − 1/(2λ²),
 * evaluated with (λi − λo) factored out algebraically so that the relative error stays a few
 * ulps even near λi = 1 (≤ 16 ulps asserted, 5.0 measured over λi ∈ [0.5, 3]; see
 * docs/accuracy.md). P = 0 exactly at ri = Ri. HP_ERR_DOMAIN when ri <= 0 or the pressure
 * would overflow (ri below ~1e-30 of Ro); HP_ERR_INVALID for NaN/Inf. */
HP_API hp_error hp_iab_ik(const hp_iab *b, double ri, double *P);

/* Inverse kinematics with exact derivatives with respect to ri: dP/dri [Pa/m] and
 * d²P/dri² [Pa/m²], closed form (no finite differences). Any output pointer but P may be
 * NULL. The derivative is a difference of two terms that cancel at a limit point, so its
 * error is a few ulps of the larger term, not of itself. */
HP_API hp_error hp_iab_ik_derivs(const hp_iab *b, double ri, double *P, double *dP_dri,
                                 double *d2P_dri2);

/* The paper's two integral forms of the pressure. */
typedef enum hp_quad_form {
    HP_QUAD_CURRENT = 0, /* P(r): integral over the current radius r in [ri, ro] */
    HP_QUAD_REFERENCE    /* P(R): integral over the reference radius R in [Ri, Ro] */
} hp_quad_form;

/* Pressure by a fixed n-point Gauss–Legendre rule on the chosen form (1 <= n <= 64); nodes
 * computed per call by Newton on the Legendre recurrence, on the stack. The reference form
 * converges slowly under strong compression of thick walls (a branch point of r(R) nears Ri
 * as ri → 0): n = 32 leaves ~1e-10 there, n = 64 reaches rounding level. */
HP_API hp_error hp_iab_ik_gauss(const hp_iab *b, double ri, hp_quad_form form, int n, double *P);

/* Pressure by adaptive Gauss–Kronrod (7–15) quadrature on the chosen form to a relative
 * tolerance rel_tol (> 0), bisecting the interval of largest estimate |K15 − G7|. Also
 * stops when the estimate falls to the rounding noise of the paper's integrand,
 * 64ε·∫Σ|terms| (near λi = 1 the integrand is a difference of nearly equal terms). Fixed
 * stack storage (256 intervals), no allocation. err_est and evals may be NULL.
 * HP_ERR_NO_CONVERGENCE (P set to NaN, err_est and evals still written) when the budget
 * runs out first. */
HP_API hp_error hp_iab_ik_adaptive(const hp_iab *b, double ri, hp_quad_form form, double rel_tol,
                                   double *P, double *err_est, int *evals);

/* The inflation limit point: the first maximum of P(λi) for λi > 1, where dP/dλi = 0.
 * Materials with a small C2/C1 have one; past it a pressure has two radii and the bladder
 * is unstable under pressure control. */
typedef struct hp_iab_limit {
    int exists;      /* 1 when P(λi) has a maximum; 0 when it rises monotonically */
    double lambda_i; /* stretch at the limit point (+inf when none) */
    double ri;       /* inner radius there [m] (+inf when none) */
    double pressure; /* pressure there [Pa] (+inf when none) */
} hp_iab_limit;

/* Finds the limit point: a scan of dP/dri's sign on a geometric grid over λi ∈ [1, 64·Ro/Ri]
 * (with a golden-section check of each local minimum of dP/dri, so a narrow dip near the
 * C2/C1 threshold is not stepped over), then bisection to adjacent doubles. λi is accurate
 * to ~1e-13 relative (the slope's rounding noise; worse for very thin walls, whose slope is
 * a small difference of large terms). */
HP_API hp_error hp_iab_limit_point(const hp_iab *b, hp_iab_limit *lp);

/* Forward kinematics: the inner radius [m] on the stable branch (below any limit point) that
 * holds pressure P [Pa]. Newton's method safeguarded by bisection on a bracket it never
 * leaves; P = 0 gives Ri exactly. Negative P (suction) follows the branch down towards
 * ri → 0. HP_ERR_NO_STABLE when P is at or above the limit-point pressure, HP_ERR_INVALID
 * for NaN/Inf, HP_ERR_DOMAIN when the radius would leave the model's range (|P| huge).
 * Cost: the limit-point scan (~1000 closed-form evaluations) plus ~10 Newton steps. */
HP_API hp_error hp_iab_fk(const hp_iab *b, double P, double *ri);

/* The same as hp_iab_fk with the bladder's limit point lp (from hp_iab_limit_point)
 * computed once beforehand: about a thousand times cheaper for a positive pressure, for
 * callers that invert pressures every cycle. lp must belong to b. */
HP_API hp_error hp_iab_fk_limit(const hp_iab *b, const hp_iab_limit *lp, double P, double *ri);

/* Wall stresses at current radius r in [ri, ro] of a bladder held at inner radius ri:
 * radial σrr and hoop σθθ [Pa], closed form (σrr(ri) = −P, σrr(ro) = 0 exactly). r may lie
 * up to 8 ulps outside [ri, ro] (clamped); further out is HP_ERR_DOMAIN. */
HP_API hp_error hp_iab_wall_stress(const hp_iab *b, double ri, double r, double *s_rr,
                                   double *s_tt);

/* Hoop stress [Pa] at the inner surface of a bladder held at inner radius ri (closed form:
 * hp_iab_wall_stress at r = ri). The quantity of a bladder's optional `stress_max` limit. */
HP_API hp_error hp_iab_hoop_stress_inner(const hp_iab *b, double ri, double *sigma);

/* The largest inner radius in [Ri, ri_cap] whose inner hoop stress is <= sigma_max (> 0),
 * by bisection to adjacent doubles; ri_cap (> Ri, on the stable branch) itself when its
 * stress is within the bound. On the stable branch above Ri the stress rises with ri, so
 * this is the radius bound the stress limit means. HP_ERR_INVALID for bad arguments. */
HP_API hp_error hp_iab_stress_radius(const hp_iab *b, double sigma_max, double ri_cap, double *ri);

#ifdef __cplusplus
}
#endif
#endif
