/* Contact kinematics: the contact distances of a layout's bladders to the moved head at each
 * fidelity level (hp_level), their inverse (forward contact fit), and what a layout can
 * observe and reach (analysis, the identifiable range, the commanded part of a pose).
 *
 * Functions are reentrant and allocate nothing unless they say so. */
#ifndef HP_CONTACT_H
#define HP_CONTACT_H

#include "headplan/hp_common.h"
#include "headplan/hp_layout.h"
#include "headplan/hp_pose.h"

#ifdef __cplusplus
extern "C" {
#endif

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
    HP_LEVEL_LOAD,       /* a planner level, not a contact geometry: the head's weight held by
                            the bladders' contact forces (hp_load.h, hp_planner.h). The
                            contact functions below refuse it (HP_ERR_INVALID) */
    HP_LEVEL_COUNT_      /* the number of levels; not a level */
} hp_level;
/* Each level's word ("linear", "plane", "surface", "auto", "load"); "unknown" for other
 * values. */
HP_API const char *hp_level_name(hp_level l);
HP_API hp_error hp_level_parse(const char *s, hp_level *out);
/* 1 when l is a contact geometry (linear, plane or surface): a level the contact calls
 * below take, with a contact distance and an error bound; 0 for auto, load and any value
 * outside the enum. The one test of it: every call that takes a geometry asks this. */
HP_API int hp_level_is_geometry(hp_level l);

/* Contact distances rho[k] (m) from each bladder centre to the head surface at pose xi,
 * for level linear, plane or surface (not auto). rho is signed (negative when a centre is
 * inside the moved head). J (n×6, row-major, per m and per rad) and H (n×6×6,
 * H[k*36 + i*6 + j] = ∂²rho_k/∂xi_i∂xi_j) are exact derivatives; any of rho, J, H may be
 * NULL. HP_ERR_INVALID for a non-finite xi, a bad level or a layout whose geometry is
 * invalid (see "Layout calls" below); HP_ERR_DOMAIN (surface) when a pose puts a bladder centre so deep inside
 * the head that its closest surface point is not unique. On error the given outputs are
 * NaN. Allocates nothing; about 1–2 µs for eight bladders with J (surface, -O2), plus
 * the derivation of the geometry (above). */
HP_API hp_error hp_contact_eval(const hp_layout *L, hp_level level, const double xi[6], double *rho,
                                double *J, double *H);

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
                               const int free_[6], const double x0[6], double xi[6],
                               double *residual, int *iters);

/* The reach search stops at these (mm, degrees): a reach equal to one means "at least". */
#define HP_REACH_CAP_MM 50.0
#define HP_REACH_CAP_DEG 30.0

/* Layout analysis at the nominal pose, translation per mm and rotation per degree. */
typedef struct hp_layout_analysis {
    double singular_values[6]; /* of J scaled to mm/mm and mm/deg, descending */
    int rank;                  /* rank as decided by hp_layout_identify (dimensionless,
                                   head-centred: independent of units, scale and pivot) */
    double condition;          /* sv_max / sv_min (mm, degrees); +inf when rank < 6 */
    double weakest[6];         /* right singular vector of the smallest sv (unit, mm/deg) */
    char weakest_words[160];   /* e.g. "pitch with some longitudinal shift" */
    double reach[6][2];        /* largest correction along each axis, [i][0] negative
                                   direction (<= 0), [i][1] positive (>= 0), mm or deg */
    int rotation_commandable;  /* 0 for a sphere head: rotation about its centre */
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
    int rank;                /* of the nondimensional Jacobian, 0..6 */
    double rel_sv[6];        /* its singular values over the largest, descending */
    int commanded[6];        /* 1: the planner moves this pose component; 0: holds it at 0 */
    int n_null;              /* 6 − rank */
    double null_space[6][6]; /* rows 0..n_null−1: unobservable motions, pose coordinates
                                  about the pivot (SI), unit length in the nondimensional
                                  metric */
    int centre_only;         /* 1: all semi-axes equal: only the centre's motion is seen */
    double length;           /* [m] characteristic length: the largest semi-axis */
    double rot_limit;        /* [rad] rotation angle must be < this (pi/2), or pi when no
                                  rotation is identified (centre_only) */
    double trans_limit;      /* [m] translation norm must be <= this */
    char symmetry[128];      /* the head's symmetries in words */
} hp_identifiable;

/* Fills out for a layout (see hp_identifiable). HP_ERR_NULL, HP_ERR_INVALID (the layout's
 * geometry is invalid, or the Jacobian is zero), HP_ERR_NO_CONVERGENCE (SVD). Allocates
 * nothing. */
HP_API hp_error hp_layout_identify(const hp_layout *L, hp_identifiable *out);

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
HP_API hp_error hp_pose_commanded_part(const hp_layout *L, const hp_identifiable *id,
                                       hp_level level, const double xd[6], double xc[6]);

#ifdef __cplusplus
}
#endif
#endif
