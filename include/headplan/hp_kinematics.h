/* Head, bladder layout and contact kinematics.
 *
 * Frame: IEC 61217 patient-support axes, head-first supine: +X lateral (patient's left),
 * +Y longitudinal (superior), +Z vertical (anterior, up). A correction (pose) is the vector
 * xi = [x, y, z, pitch, roll, yaw] in metres and radians: pitch about X, roll about Y, yaw
 * about Z, right-hand positive, applied about the layout's pivot, with
 * R = Rz(yaw)·Ry(roll)·Rx(pitch) (pitch applied first). A head point q moves to
 * pivot + R·(q − pivot) + t.
 *
 * Functions are reentrant and allocate nothing unless they say so. */
#ifndef HP_KINEMATICS_H
#define HP_KINEMATICS_H

#include "headplan/hp_common.h"
#include "headplan/hp_iab.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Index of each component of a pose vector. */
enum { HP_X = 0, HP_Y, HP_Z, HP_PITCH, HP_ROLL, HP_YAW, HP_DOF };

/* Clinical units (mm, degrees) <-> SI (m, rad), the one place these conversions live. */
HP_API void hp_pose_from_clinical(const double mm_deg[6], double xi[6]);
HP_API void hp_pose_to_clinical(const double xi[6], double mm_deg[6]);
/* Names of the pose components as a user types them: "x_mm" ... "yaw_deg". */
HP_API const char *hp_pose_key(int i);

/* Rotation matrix R = Rz(yaw)·Ry(roll)·Rx(pitch), row-major 3×3. */
HP_API void hp_rotation(double pitch, double roll, double yaw, double R[9]);

/* The angles (rad) of a rotation matrix R (row-major, orthonormal) in the convention above:
 * pitch and yaw in (−π, π], roll in [−π/2, π/2]. At roll = ±π/2 (gimbal lock) any split of
 * pitch and yaw that gives R is returned. */
HP_API void hp_rotation_angles(const double R[9], double *pitch, double *roll, double *yaw);

/* The exact inverse of a pose about the pivot: the rotation Rᵀ and translation −Rᵀ·t, in
 * the angle convention above. A measured deviation's correction is its inverse (not its
 * negation: −xi leaves 0.26 mm of a 5 mm / 3° yaw deviation uncorrected). inv may be xi. */
HP_API void hp_pose_inverse(const double xi[6], double inv[6]);

/* A pose from translation t [m] and a unit quaternion q = (w, x, y, z) (Hamilton, active:
 * the same rotation R as the pose's). |q| must be 1 within 1e-6 (it is normalised); else
 * HP_ERR_INVALID, as for non-finite input. q and −q give the same pose. */
HP_API hp_error hp_pose_from_quaternion(const double t[3], const double q[4], double xi[6],
                                 hp_diag *diag);
/* The pose's translation t [m] and its unit quaternion (w >= 0). */
HP_API void hp_pose_to_quaternion(const double xi[6], double t[3], double q[4]);

/* A pose from a 4×4 rigid transform M (row-major, translation column in metres) in the
 * frame centred on the pivot: M maps q − pivot to R·(q − pivot) + t. The last row must be
 * exactly 0 0 0 1 and the 3×3 block a rotation (RᵀR = I within 1e-6, det +1); else
 * HP_ERR_INVALID naming what is wrong. */
HP_API hp_error hp_pose_from_matrix(const double M[16], double xi[6], hp_diag *diag);
/* The pose as a 4×4 rigid transform (same layout). */
HP_API void hp_pose_to_matrix(const double xi[6], double M[16]);

/* ROS REP 103: the pose in the head's body frame x anterior (IEC +Z), y patient's left
 * (IEC +X), z superior (IEC +Y), origin at the pivot, as ros = [x, y, z (m), roll, pitch,
 * yaw (rad)] with R = Rz(yaw)·Ry(pitch)·Rx(roll). Exact (through the rotation matrix), so
 * the two calls invert each other; the mapping of single angles is tabled in
 * docs/kinematics.md. */
HP_API void hp_pose_to_rep103(const double xi[6], double ros[6]);
HP_API void hp_pose_from_rep103(const double ros[6], double xi[6]);

typedef enum hp_head_shape { HP_HEAD_SPHERE = 0, HP_HEAD_ELLIPSOID } hp_head_shape;
HP_API const char *hp_head_shape_name(hp_head_shape s);            /* "sphere", "ellipsoid" */
HP_API hp_error hp_head_shape_parse(const char *s, hp_head_shape *out);

/* A rigid head. A sphere uses semi_axes[0] as its radius (all three equal). */
typedef struct hp_head {
    hp_head_shape shape;
    double center[3];    /* [m] at the nominal pose */
    double semi_axes[3]; /* [m] along X, Y, Z */
    double mass;         /* [kg]; 0 when the scene does not state it (no load model) */
} hp_head;

/* Default adult head: ellipsoid 77.5 × 115 × 97.5 mm semi-axes, 4.5 kg, at the origin. */
#define HP_HEAD_DEFAULT_A 0.0775
#define HP_HEAD_DEFAULT_B 0.115
#define HP_HEAD_DEFAULT_C 0.0975
#define HP_HEAD_DEFAULT_MASS 4.5

/* One bladder of a layout: where it sits and what it may do. */
typedef struct hp_bladder {
    char name[HP_NAME_MAX];
    double center[3];     /* fixed centre on its panel [m] */
    hp_iab iab;           /* reference radii and material */
    double p_min, p_max;  /* safe pressure [Pa], p_min < p_max */
    double stretch_min;   /* safe inner stretch λi = ri/Ri, lower bound (> 0) */
    double stretch_max;   /* upper bound, below any limit point */
    double rate_max;      /* largest pressure change per cycle [Pa]; +inf when unlimited */
    double stress_max;    /* largest hoop stress at the inner surface [Pa] (> 0); 0 or
                             +inf: no stress limit (hp_iab_hoop_stress_inner) */
} hp_bladder;

/* The head and its bladders at the nominal pose: inputs only. Nothing in it is derived, so
 * a layout may be edited at any time; every call that takes a layout reads it as it is
 * then (the contact geometry is derived on each call, or once by an object that keeps its
 * own private copy, such as the planner). */
typedef struct hp_layout {
    hp_head head;
    double pivot[3];                     /* [m] */
    int n;                               /* number of bladders, 1..HP_MAX_BLADDERS */
    hp_bladder bladders[HP_MAX_BLADDERS];
} hp_layout;

/* Validates the layout; derives and keeps nothing (the name is kept from when it did).
 * The one change it makes: a sphere's radius semi_axes[0] is copied to the other two
 * semi-axes. Checks: finite head centre and
 * pivot, semi-axes finite > 0 (a sphere reads semi_axes[0]), mass finite >= 0, n in
 * 1..HP_MAX_BLADDERS, names non-empty, NUL-terminated
 * and unique, centres finite and outside the head, hp_iab_validate, finite p_min < p_max,
 * 0 < stretch_min < stretch_max, stretch_max below any inflation limit point, rate_max > 0
 * (+inf allowed), and the nominal pose holdable: the stretch at ro = rho0 (the nominal
 * contact distance, hp_layout_contact) strictly inside
 * (stretch_min, stretch_max) by at least 1e-9 and its pressure inside [p_min, p_max].
 * HP_ERR_INVALID (or the bladder model's code) with a message naming the bladder and
 * field at fault, e.g. "bladder 'side_fore_left': stretch_max: ...". Uses the bladder
 * model; allocates nothing. */
HP_API hp_error hp_layout_prepare(hp_layout *L, hp_diag *diag);

/* The nominal contact of bladder k (0-based): the head-surface point nearest its centre
 * (point, m), the outward unit head normal there (normal) and the nominal contact distance
 * rho0 = |centre − point| (m). Any output may be NULL. Derived from L as it is now on
 * every call. HP_ERR_INVALID when the head, the pivot or n is invalid, k is out of range
 * or the centre is not finite and outside the head. Allocates nothing. */
HP_API hp_error hp_layout_contact(const hp_layout *L, int k, double point[3], double normal[3],
                                  double *rho0);

/* Point of the head surface a bladder touches placed by "touch": returns the bladder centre
 * c = p + (Ro + preload)·n(p) for surface point p (which must lie on the surface to within
 * 1e-9 relative of its implicit function; otherwise HP_ERR_INVALID). */
HP_API hp_error hp_head_center_from_touch(const hp_head *h, const double p[3], double Ro,
                                   double preload, double center[3], hp_diag *diag);

/* Layout calls. Every call below that takes a const hp_layout derives the nominal contact
 * geometry it needs from the layout as it is, on its own stack, on every call (for eight
 * bladders one closest-point solve each: about 3.4 µs at -O2, measured on a loaded 2-core
 * machine where a surface-level hp_contact_eval with J took 5.1 µs); the layout need not
 * have been through hp_layout_prepare, but its geometry must hold: a valid head, a finite
 * pivot, n in 1..HP_MAX_BLADDERS and every centre finite and outside the head, else
 * HP_ERR_INVALID. Objects that keep a private copy of a layout (the planners) derive it
 * once at creation and do not pay this per call. */

/* Fidelity levels of the contact model. */
typedef enum hp_level {
    HP_LEVEL_LINEAR = 0, /* rho(0) + J·xi */
    HP_LEVEL_PLANE,      /* tangent plane at the nominal contact, moving with the head */
    HP_LEVEL_SURFACE,    /* exact distance to the moved sphere or ellipsoid */
    HP_LEVEL_AUTO,       /* the cheapest level whose error bound meets a tolerance */
    HP_LEVEL_LOAD        /* a planner level, not a contact geometry: the head's weight held by
                            the bladders' contact forces (hp_load.h, hp_planner.h). The
                            contact functions below refuse it (HP_ERR_INVALID) */
} hp_level;
/* "linear", "plane", "surface", "auto", "load"; "unknown" for other values. */
HP_API const char *hp_level_name(hp_level l);
HP_API hp_error hp_level_parse(const char *s, hp_level *out);

/* Contact distances rho[k] (m) from each bladder centre to the head surface at pose xi,
 * for level linear, plane or surface (not auto). rho is signed (negative when a centre is
 * inside the moved head). J (n×6, row-major, per m and per rad) and H (n×6×6,
 * H[k*36 + i*6 + j] = ∂²rho_k/∂xi_i∂xi_j) are exact derivatives; any of rho, J, H may be
 * NULL. HP_ERR_INVALID for a non-finite xi, a bad level or a layout whose geometry is
 * invalid (see "Layout calls" below); HP_ERR_DOMAIN (surface) when a pose puts a bladder centre so deep inside
 * the head that its closest surface point is not unique. On error the given outputs are
 * NaN. Allocates nothing; about 1–2 µs for eight bladders with J (surface, -O2), plus
 * the derivation of the geometry (above). */
HP_API hp_error hp_contact_eval(const hp_layout *L, hp_level level, const double xi[6],
                         double *rho, double *J, double *H);

/* Upper bound on max_k |rho_k(level) − rho_k(surface)| over all poses with translation
 * norm |(x, y, z)|₂ <= trans (m) and angle-vector norm |(pitch, roll, yaw)|₂ <= rot (rad).
 * 0 for surface. A proof from second-order Taylor remainders (head curvature, lever arm,
 * rotation) is in kinematics/bound.c; for the default layout the bound is within ×1.2–1.6
 * (plane) and ×6–11 (linear) of sampled worst errors at 1–10 mm, 1–5°. */
HP_API hp_error hp_contact_error_bound(const hp_layout *L, hp_level level, double trans, double rot,
                                double *bound);

/* The cheapest level (linear, then plane, else surface) whose error bound for corrections
 * up to (trans, rot) is <= tol (m). */
HP_API hp_error hp_contact_auto(const hp_layout *L, double tol, double trans, double rot,
                         hp_level *level);

/* Forward contact kinematics: the pose whose contact distances best fit the given outer
 * radii ro[0..n-1] (finite, > 0) in least squares (Levenberg–Marquardt, QR steps through
 * Eigen), starting at xi0 (NULL = zero). residual = RMS of rho(xi) − ro [m]; residual and
 * iters may be NULL. For a sphere head only translation is fitted and the rotation
 * components are returned as 0 (not observable). Needs n >= 6 (3 for a sphere), else
 * HP_ERR_INVALID; HP_ERR_NO_CONVERGENCE after 200 iterations. Consistent radii give the
 * pose back to ~1e-14 m. Allocates nothing. */
HP_API hp_error hp_contact_fk(const hp_layout *L, hp_level level, const double *ro,
                       const double *xi0, double xi[6], double *residual, int *iters);

/* Forward contact kinematics in the pose components with free_[i] = 1 (the others held at
 * 0): Levenberg–Marquardt as in hp_contact_fk, fitting the contact distances at level to
 * target[0..n-1] (finite, any sign: a desired pose's own distances may be <= 0), started
 * at x0 (free components only). The engine of hp_contact_fk, and what the planner uses to
 * check that a commanded pose is recovered from the nominal one. residual and iters may be
 * NULL. HP_ERR_NO_CONVERGENCE after 200 iterations. Allocates nothing. */
HP_API hp_error hp_contact_fit(const hp_layout *L, hp_level level, const double *target,
                        const int free_[6], const double x0[6], double xi[6], double *residual,
                        int *iters);

/* The reach search stops at these (mm, degrees): a reach equal to one means "at least". */
#define HP_REACH_CAP_MM 50.0
#define HP_REACH_CAP_DEG 30.0

/* Layout analysis at the nominal pose, translation per mm and rotation per degree. */
typedef struct hp_layout_analysis {
    double singular_values[6];  /* of J scaled to mm/mm and mm/deg, descending */
    int rank;                   /* rank as decided by hp_layout_identify (dimensionless,
                                   head-centred: independent of units, scale and pivot) */
    double condition;           /* sv_max / sv_min (mm, degrees); +inf when rank < 6 */
    double weakest[6];          /* right singular vector of the smallest sv (unit, mm/deg) */
    char weakest_words[160];    /* e.g. "pitch with some longitudinal shift" */
    double reach[6][2];         /* largest correction along each axis, [i][0] negative
                                   direction (<= 0), [i][1] positive (>= 0), mm or deg */
    int rotation_commandable;   /* 0 for a sphere head: rotation about its centre */
} hp_layout_analysis;

/* Analyses the conditioning of the layout (J at the nominal pose, Eigen JacobiSVD) and the
 * reach of each axis inside every bladder's pressure and stretch limits (using the bladder
 * model, rho at the given level): the first boundary along the axis, found by a scan in
 * 1/100 of the cap (50 mm, 30°) and bisection; the cap when none is met; 0 when the
 * nominal pose itself violates a limit. A component the planner does not command
 * (hp_identifiable.commanded: a sphere's rotations, with rotation_commandable = 0) gets
 * reach 0. This reach ignores the planner's own caps (the margin below an inflation limit
 * point, the hoop-stress limit): hp_planner_reach gives the reach a plan sees. weakest_words names the dominant component of the weakest vector and
 * any other component of magnitude >= 0.3. */
HP_API hp_error hp_layout_analyze(const hp_layout *L, hp_level level, hp_layout_analysis *out);

/* Relative singular value below which a direction of the nondimensional contact Jacobian
 * (hp_layout_identify) counts as unobservable: far above rounding (~1e-15 for 16 rows), far
 * below a genuinely weak but observable direction (the near-spherical 90/90.01/90.02 mm
 * ellipsoid has ~1e-4). */
#define HP_IDENT_RANK_TOL 1e-8

/* What the contact model can tell apart: the identifiable range of a layout and head shape.
 *
 * Observable motions. The contact distances see the moved head only as a set, so a motion
 * that maps the head onto itself is invisible. The rank is decided on the contact Jacobian
 * at the nominal pose written in the head-centred frame (translation of the head centre,
 * rotation about it, the rotation columns divided by the head's largest semi-axis): every
 * entry is then dimensionless, so the decision does not depend on units, on the overall
 * scale of the scene, or on where the pivot is (the pivot only changes coordinates: a
 * rotation about a far pivot is a rotation about the centre plus a translation). A sphere's
 * rotation about its centre has exactly zero columns there (rank 3); a head of revolution
 * loses the turn about its axis (rank <= 5); fewer than six bladders or bladders facing too
 * few directions lose more.
 *
 * Commanded components. The pose components the planner moves (commanded[i] = 1) are chosen
 * among x, y, z, pitch, roll, yaw about the pivot: rotations (yaw, roll, pitch) then
 * translations (z, y, x) are dropped while the others keep the full rank. The commanded
 * part of a desired correction is the pose in those components alone that the exact model
 * cannot tell from it (for a sphere, exactly: the same motion of its centre, whatever the
 * pivot); the rest is not commanded.
 *
 * Range. Rotations: the head's symmetries are the rotations about its centre that map it
 * onto itself. An ellipsoid with three distinct semi-axes has the half-turns about each of
 * its axes; one with two equal semi-axes also every turn about its axis of revolution
 * (unobservable, above) and half-turns about every axis across it. Two rotations are
 * confused when they differ by a symmetry, i.e. by a half-turn (angle 180°); so poses whose
 * rotation angle (the angle of R about its own axis, whatever the axis and the pivot) is
 * below 90° are pairwise distinct, and 90° is the largest such bound (±90° about one axis
 * differ by a half-turn). A sphere identifies no rotation: only the motion of its centre
 * (rot_limit = pi, i.e. any correction is accepted and its rotation about the centre is
 * reported not commanded). Translations: |(x, y, z)|₂ up to the head's smallest semi-axis,
 * so the moved head still contains its nominal centre and every bladder faces the side of
 * the head it faced at rest (the planner's strict round-trip tests sample this range; far
 * beyond any bladder's reach). */
typedef struct hp_identifiable {
    int rank;                  /* of the nondimensional Jacobian, 0..6 */
    double rel_sv[6];          /* its singular values over the largest, descending */
    int commanded[6];          /* 1: the planner moves this pose component; 0: holds it at 0 */
    int n_null;                /* 6 − rank */
    double null_space[6][6];   /* rows 0..n_null−1: unobservable motions, pose coordinates
                                  about the pivot (SI), unit length in the nondimensional
                                  metric */
    int centre_only;           /* 1: all semi-axes equal: only the centre's motion is seen */
    double length;             /* [m] characteristic length: the largest semi-axis */
    double rot_limit;          /* [rad] rotation angle must be < this (pi/2), or pi when no
                                  rotation is identified (centre_only) */
    double trans_limit;        /* [m] translation norm must be <= this */
    char symmetry[128];        /* the head's symmetries in words */
} hp_identifiable;

/* Fills out for a layout (see hp_identifiable). HP_ERR_NULL, HP_ERR_INVALID (the layout's
 * geometry is invalid, or the Jacobian is zero), HP_ERR_NO_CONVERGENCE (SVD). Allocates
 * nothing. */
HP_API hp_error hp_layout_identify(const hp_layout *L, hp_identifiable *out);

/* Angle [rad] of the rotation of pose xi (pitch, roll, yaw in xi[3..5]) about its own axis,
 * in [0, pi]: the quantity hp_identifiable.rot_limit bounds. */
HP_API double hp_pose_rotation_angle(const double xi[6]);

/* The commanded part xc of a desired pose xd for a layout (see hp_identifiable): zeros in
 * the components id->commanded[] drops, and the contact distances of xd. For a centre_only
 * head commanding x, y, z: exactly the translation that moves the head centre where xd
 * moves it (pivot + R(centre − pivot) + t − centre), at every level (the surface level's
 * distances are then those of xd exactly). Otherwise the projection along the unobservable
 * motions that zeroes the dropped components (exact at the linear level), refined at the
 * plane and surface levels by hp_contact_fit of xd's distances in the commanded components
 * (exact when they can reproduce them, e.g. up to five bladders; least squares when the
 * layout sees the dropped directions at second order, e.g. a flat layout). xc = xd bit for
 * bit when rank is 6 or xd is already zero in the dropped components. Allocates nothing.
 * HP_ERR_INVALID for a non-finite xd; the contact model's errors otherwise. */
HP_API hp_error hp_pose_commanded_part(const hp_layout *L, const hp_identifiable *id, hp_level level,
                                const double xd[6], double xc[6]);

#ifdef __cplusplus
}
#endif
#endif
