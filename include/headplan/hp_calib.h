/* Calibration from measurements: fit a bladder's moduli from free-inflation data, and a
 * layout's bladder offsets and head size from measured (pressures, pose) rows.
 *
 * Statistics (both fits, docs/calibration.md): weighted least squares; the residual variance
 * is estimated from the data, s² = Σ wᵢ eᵢ² / (n − p) (weights wᵢ = 1/σᵢ² are relative: the
 * intervals do not depend on their overall scale); covariance s²·(JᵀWJ)⁻¹ at the optimum; 95 %
 * intervals value ± t(0.975, n − p)·SE with Student's t quantile (not the normal one), since
 * s² is itself estimated from few points.
 *
 * Everything is SI (m, Pa, rad). The fits allocate only temporary work memory (freed before
 * returning), print nothing and are reentrant. */
#ifndef HP_CALIB_H
#define HP_CALIB_H

#include "headplan/hp_common.h"
#include "headplan/hp_iab.h"
#include "headplan/hp_contact.h"
#include "headplan/hp_load.h"
#include "headplan/hp_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Most rows a material or layout data set may hold. */
#define HP_CALIB_MAX_ROWS 4096
/* Most layout parameters: one radial offset per bladder, three semi-axes, the carried mass. */
#define HP_CALIB_MAX_PARAMS (HP_MAX_BLADDERS + 4)
/* Longest parameter name, including the NUL. */
#define HP_CALIB_NAME_MAX 48

/* Upper quantile t(p, dof) of Student's t distribution, P(T <= t) = p, for 0.5 <= p < 1 and
 * dof >= 1 (dof > 1e6 returns the normal quantile). Regularised incomplete beta by a
 * continued fraction, inverted by bisection to ~1e-12 relative. NaN for bad arguments. */
HP_API double hp_calib_t_quantile(double p, double dof);

/* ---- material ---- */

/* Which radius a free-inflation measurement gives. */
typedef enum hp_calib_radius { HP_CALIB_INNER = 0, HP_CALIB_OUTER } hp_calib_radius;

/* One free-inflation measurement. */
typedef struct hp_calib_point {
    double pressure; /* [Pa] applied */
    double radius;   /* [m] measured, inner or outer (see hp_calib_radius) */
    double sigma;    /* [m] > 0, its standard deviation (relative weight 1/σ²) */
    long line;       /* file line for messages (0: none) */
} hp_calib_point;

/* A fit of C1, C2 (paper convention) to one bladder's free-inflation data. */
typedef struct hp_material_fit {
    double C1, C2;         /* [Pa] paper convention */
    double C10, C01;       /* [Pa] finite-element convention: C1/2, C2/2 */
    double se[2];          /* standard errors of C1, C2 [Pa] */
    double ci[2][2];       /* 95 % intervals [lo, hi] of C1, C2 [Pa] */
    double corr;           /* correlation of the C1 and C2 estimates */
    double condition;      /* of the Jacobian with columns scaled by C1, C2 */
    int n, dof;            /* points, n − 2 */
    double t;              /* t(0.975, dof) used for the intervals */
    double s;              /* residual standard deviation for unit weight (σ-scaled) */
    double rms;            /* unweighted RMS of the radius residuals [m] */
    int iterations;        /* Levenberg–Marquardt iterations */
    double limit_pressure; /* the fitted bladder's limit-point pressure [Pa] (+inf: none) */
    /* hp_fit_material_ref only (hp_fit_material: ref_fitted 0, the rest NaN): */
    int ref_fitted;           /* 1: a reference radius was fitted with the moduli */
    hp_calib_radius ref_kind; /* which: HP_CALIB_INNER (Ri) or HP_CALIB_OUTER (Ro) */
    double ref, ref_se;       /* [m] its value and standard error */
    double ref_ci[2];         /* [m] its 95 % interval */
    double ref_corr[2];       /* its correlation with C1 and with C2 */
} hp_material_fit;

/* Fits C1, C2 (paper convention) of a bladder with reference radii Ri < Ro to n points
 * (pressure applied, radius measured): minimises Σ ((r_meas − r(P; C1, C2))/σ)², r(P) the
 * stable-branch forward kinematics (inner radius, or its outer radius by the volume law), by
 * Levenberg–Marquardt started from the linear least-squares fit in pressure. The Jacobian is
 * exact: with P = C1·a(ri) + C2·b(ri), dri/dC1 = −a/(dP/dri), dri/dC2 = −b/(dP/dri).
 * Refuses (HP_ERR_INVALID, diag names why; out set to NaN):
 *   - bad points (non-finite, radius <= 0, σ <= 0, n > HP_CALIB_MAX_ROWS);
 *   - fewer than two distinct non-zero pressures (each pressure is one equation in the two
 *     moduli; P = 0 gives r = Ri whatever the moduli), or fewer than three points (no degree
 *     of freedom left to estimate the scatter);
 *   - a condition number of the scaled Jacobian above 1e4 (columns scaled by the moduli, a
 *     modulus below 0.1·(C1 + C2) by that; all points so close to λ = 1 that the data only
 *     see C1 + C2; points on one side of λ = 1 are ill-conditioned, not unidentifiable: the
 *     number grows like 0.7/max|λi − 1|, 0.18/max|λi − 1| on both sides), also when the
 *     search on such data stalled or ran into a bound or the limit point;
 *   - a fit that does not fit: the residual RMS above 5 % of the mean measured radius (a wrong
 *     unit, wrong reference radii; the message compares the data with Ri or Ro);
 *   - a fit that runs into the limit point: a measured pressure at or above the fitted
 *     bladder's limit-point pressure, or a measured radius past its limit-point radius;
 *   - C1 <= 0 at the optimum. C2 is held at the model's bound 0 when the data prefer less
 *     (neo-Hookean data, C2 = 0, are fitted with C2 = 0; its interval then reaches 0).
 * resid (may be NULL) receives the n residuals r_meas − r_fit [m]. */
HP_API hp_error hp_fit_material(double Ri, double Ro, hp_calib_radius kind,
                                const hp_calib_point *pts, int n, hp_material_fit *out,
                                double *resid, hp_diag *diag);

/* Like hp_fit_material, but also fits one reference radius: ref = HP_CALIB_INNER fits Ri
 * (Ri is then its starting value), HP_CALIB_OUTER fits Ro. Three parameters, so n − 3 degrees
 * of freedom; started from hp_fit_material at the given radii (its refusals apply), then
 * Levenberg–Marquardt on (C1, C2, R) with exact derivatives (dr/dR from the closed form's
 * ∂P/∂R by the implicit function theorem, plus the volume law's direct term for outer radii).
 * Refuses (HP_ERR_INVALID, diag names the radius and why) fewer than four points, a
 * design with fewer than three equations (each distinct non-zero pressure is one; zero
 * pressure is one only when the measured radius is the fitted one: ri(0) = Ri, ro(0) = Ro),
 * a condition number of the Jacobian (unit-norm columns) above 1e4 — the data cannot tell the
 * radius from the moduli (docs/calibration.md) — a radius leaving 0 < Ri < Ro, and the
 * limit-point cases of hp_fit_material. On success out->ref_fitted = 1
 * and the ref fields hold the radius; C1, C2 and their intervals are those of the joint fit. */
HP_API hp_error hp_fit_material_ref(double Ri, double Ro, hp_calib_radius kind, hp_calib_radius ref,
                                    const hp_calib_point *pts, int n, hp_material_fit *out,
                                    double *resid, hp_diag *diag);

/* How much one more measurement at each candidate pressure cand[j] (with standard deviation
 * sigma [m]) would shrink the intervals of a fit: shrink[2j], shrink[2j+1] = new SE / old SE
 * of C1, C2 (in (0, 1]), from the information matrix JᵀWJ + j jᵀ/σ² with s² held fixed.
 * A candidate past the fitted limit point or giving no radius gets NaN. */
HP_API hp_error hp_fit_material_gain(double Ri, double Ro, hp_calib_radius kind,
                                     const hp_calib_point *pts, int n, const hp_material_fit *fit,
                                     const double *cand, int ncand, double sigma, double *shrink,
                                     hp_diag *diag);

/* ---- layout ---- */

/* One layout measurement: every bladder's applied pressure and the head pose measured. */
typedef struct hp_calib_row {
    double pressure[HP_MAX_BLADDERS]; /* [Pa], in the layout's bladder order */
    double pose[6];                   /* [m, rad] x y z pitch roll yaw */
    long line;                        /* file line for messages (0: none) */
} hp_calib_row;

/* What a layout fit may adjust. */
typedef struct hp_layout_fit_options {
    int fit_axes;             /* 1: the head's semi-axes (a sphere: its radius) */
    int fit_offsets;          /* 1: every bladder's radial offset (centre moved along its normal) */
    int fit_mass;             /* 1: the carried mass (determined only with load != NULL) */
    hp_level level;           /* contact level of the forward model (linear, plane or surface);
                            with a load, the contact geometry of the forward statics */
    const hp_load_spec *load; /* NULL: the forward model is the contact forward kinematics;
                            else the forward statics (hp_load_rest) carrying this load, whose
                            mass is the start (and scene value) of a fitted mass */
    double sigma_trans;       /* [m] > 0: standard deviation of a measured translation */
    double sigma_rot;         /* [rad] > 0: standard deviation of a measured rotation */
} hp_layout_fit_options;

/* Defaults: offsets and semi-axes fitted, no mass, no load, surface level, σ = 0.1 mm and
 * 0.1°. */
HP_API void hp_layout_fit_options_default(hp_layout_fit_options *o);

/* The result of a layout fit. Parameters are listed semi-axes first (x, y, z; one "radius"
 * for a sphere), then one radial offset per bladder in layout order, then (only when
 * options.fit_mass) the carried mass "mass" [kg]; every other value is a length [m]. */
typedef struct hp_layout_fit {
    int np;                                            /* parameters considered */
    char name[HP_CALIB_MAX_PARAMS][HP_CALIB_NAME_MAX]; /* "semi_axis_x", "offset:NAME" */
    double scene_value[HP_CALIB_MAX_PARAMS];           /* semi-axis [m] or 0 (offset) before */
    double value[HP_CALIB_MAX_PARAMS];                 /* after [m] */
    int determined[HP_CALIB_MAX_PARAMS];               /* 1: fitted; 0: held at its scene value
                                                because the data cannot determine it;
                                                -1: not asked for (options) */
    double se[HP_CALIB_MAX_PARAMS];                    /* standard error [m] (NaN when held) */
    double ci[HP_CALIB_MAX_PARAMS][2];                 /* 95 % interval [m] (NaN when held) */
    int rank;                                          /* numerical rank of the full Jacobian */
    double sv[HP_CALIB_MAX_PARAMS];                    /* its singular values (unit-norm columns) */
    double condition;                                  /* of the fitted (determined) columns */
    double weakest[HP_CALIB_MAX_PARAMS]; /* unit direction in parameter space (held: 0)
                                                the data determine worst */
    double weakest_se;                   /* standard error along it, in the SI units of
                                                its components: m, kg when it is the mass */
    int n_rows, n_res, dof;              /* rows, residual components, n_res − fitted */
    double t, s;                         /* t(0.975, dof); residual SD for unit weight */
    double rms_before[6], rms_after[6];  /* per pose axis [m or rad] */
    int iterations;
    hp_layout fitted; /* the calibrated layout (validated) */
    int mass_index;   /* index of "mass" among the parameters; -1 */
    double mass;      /* [kg] carried mass after the fit (the load's
                                                mass when held; NaN without a load) */
} hp_layout_fit;

/* Fits the selected parameters of layout L (valid: hp_layout_prepare) to n rows: minimises
 * the weighted sum of squared differences between each measured pose and the model's pose
 * (pressures -> hp_iab_fk -> hp_iab_ro -> hp_contact_fk at opt->level), Gauss–Newton with Levenberg–
 * Marquardt damping. The Jacobian of each model pose comes from the implicit function
 * theorem on the forward kinematics' normal equations (exact second-order terms included),
 * with the contact model's derivatives in the parameters by central differences (1 µm) at
 * the fixed pose (rounding-level noise, ~1e-12 relative). The
 * rank of the Jacobian is taken from its SVD (columns scaled to unit norm, threshold 1e-7 of
 * the largest singular value); parameters are admitted in list order while each raises the
 * rank, and the rest are held at their scene values (named by determined[] = 0). A sphere
 * head's rotations are not compared (the model cannot rotate it). The mass is admitted first
 * (it is what a load calibration is for), then offsets, then semi-axes (a head can be
 * measured by hand, a bladder's seat on its panel cannot).
 * With opt->load the model pose of a row is the rest of the forward statics (hp_load_rest
 * from the nominal pose, geometry opt->level) and its Jacobian dξ/dθ = K⁻¹·∂Q/∂θ (implicit
 * function theorem on Q(ξ; θ) = 0, K = −∂Q/∂ξ exact, ∂Q/∂θ by central differences of
 * hp_load_eval at the fixed rest: 1 µm, 1 g). Without a load the kinematic model does not
 * depend on the mass: its column is zero and a requested mass is held and named.
 * Refuses (HP_ERR_INVALID)
 * bad rows (non-finite, a pressure outside the bladder's stable branch or its limits), fewer
 * rows than give one degree of freedom, nothing to fit; HP_ERR_NO_CONVERGENCE when the search
 * stalled (no step from the scene's values was accepted, or the damping ran out on steps the
 * model could not evaluate: at the load level, no rest of the statics), rather than answer
 * with the scene's values. resid_after (may be NULL) gets n×6
 * residuals measured − model after the fit. On failure every number of out is NaN and
 * out->fitted has n = 0 (no bladders: every layout call refuses it). Allocates work memory; frees it. */
HP_API hp_error hp_fit_layout(const hp_layout *L, const hp_calib_row *rows, int n,
                              const hp_layout_fit_options *opt, hp_layout_fit *out,
                              double *resid_after, hp_diag *diag);

/* The residuals measured − model (n×6, [m, rad]; a sphere head's rotations 0) of layout L
 * (prepared) on the rows, with the forward model opt selects: the "before" of a fit given the
 * scene's layout, its "after" given the fitted one. Same refusals as hp_fit_layout. */
HP_API hp_error hp_fit_layout_residuals(const hp_layout *L, const hp_calib_row *rows, int n,
                                        const hp_layout_fit_options *opt, double *resid,
                                        hp_diag *diag);

/* How much one more measurement like each row would shrink the intervals: gain[i] = mean
 * over the fitted parameters of new SE / old SE (in (0, 1]) if row i were measured once
 * more, from the information matrix with s² held fixed. */
HP_API hp_error hp_fit_layout_gain(const hp_layout *L, const hp_calib_row *rows, int n,
                                   const hp_layout_fit_options *opt, const hp_layout_fit *fit,
                                   double *gain, hp_diag *diag);

/* Writes a layout scene file at path holding the layout L (every bladder by centre, with its
 * own parameters), contact level `level`, and the given name; when base is not NULL also its
 * model tolerance and auto range, its solver section and its correction (not its trace,
 * whose path is relative to the base's folder). Written through a temporary file in the same
 * folder renamed over path, so a reader never sees half a file. Refuses (HP_ERR_INVALID,
 * nothing written) when path names the same file as any of the `inputs` (n_inputs paths, may
 * be 0), or names a symbolic link, a directory, a FIFO, device or socket. HP_ERR_IO
 * when it cannot write. */
/* The checks hp_calib_write_scene makes on its target before writing anything, for a caller
 * that wants to refuse a bad -o before a long fit: HP_ERR_INVALID when path is one of the
 * inputs, a symbolic link, a directory, a FIFO, device or socket; HP_ERR_IO when it cannot be
 * examined; HP_OK when it does not exist or is a regular file. Writes nothing. */
HP_API hp_error hp_calib_check_output(const char *path, const char *const *inputs, int n_inputs,
                                      hp_diag *diag);

HP_API hp_error hp_calib_write_scene(const char *path, const hp_layout *L, hp_level level,
                                     const hp_scene *base, const char *name,
                                     const char *const *inputs, int n_inputs, hp_diag *diag);

/* ---- data files ---- */

/* The largest data file the readers take [bytes]. */
#define HP_CALIB_MAX_BYTES (16L * 1024 * 1024)

/* Reads a material data CSV: header `pressure_pa,ri_mm` or `pressure_pa,ro_mm` (or kpa),
 * optionally a third column `sigma_mm`; '#' comment and blank lines skipped. Fills up to
 * max points (SI) and *kind; every bad field is refused with "FILE:LINE:COL: why".
 * HP_ERR_IO when the file cannot be read, HP_ERR_PARSE otherwise. */
HP_API hp_error hp_calib_read_material(const char *path, hp_calib_point *pts, int max, int *n,
                                       hp_calib_radius *kind, hp_diag *diag);

/* Reads layout data for layout L. CSV: header `p_<name>_pa` (or `_kpa`) for every bladder of
 * L and x_mm,y_mm,z_mm,pitch_deg,roll_deg,yaw_deg, in any order. JSON Lines (extension
 * .jsonl / .ndjson, or a first data character '{'): one object per line with the same keys
 * (JSON numbers; duplicate keys refused). Every pressure must lie in the bladder's
 * [p_min, p_max] and below its limit point. Same contract as above (for JSON Lines the
 * column is that of the key at fault). */
HP_API hp_error hp_calib_read_layout(const char *path, const hp_layout *L, hp_calib_row *rows,
                                     int max, int *n, hp_diag *diag);

/* The same two readers on len bytes at text (a file read elsewhere, e.g. a command's standard
 * input), named `name` in messages ("NAME:LINE:COL: why"); the bytes are copied, not kept.
 * Same limits and refusals as the readers of files, without HP_ERR_IO. */
HP_API hp_error hp_calib_parse_material(const char *text, size_t len, const char *name,
                                        hp_calib_point *pts, int max, int *n, hp_calib_radius *kind,
                                        hp_diag *diag);
HP_API hp_error hp_calib_parse_layout(const char *text, size_t len, const char *name,
                                      const hp_layout *L, hp_calib_row *rows, int max, int *n,
                                      hp_diag *diag);

#ifdef __cplusplus
}
#endif
#endif
