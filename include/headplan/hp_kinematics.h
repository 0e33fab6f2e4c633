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
} hp_bladder;

/* The head and its bladders at the nominal pose, plus what hp_layout_prepare derives. */
typedef struct hp_layout {
    hp_head head;
    double pivot[3];                     /* [m] */
    int n;                               /* number of bladders, 1..HP_MAX_BLADDERS */
    hp_bladder bladders[HP_MAX_BLADDERS];
    /* Derived by hp_layout_prepare (do not set by hand): */
    double contact[HP_MAX_BLADDERS][3];  /* nominal contact point on the head surface [m] */
    double normal[HP_MAX_BLADDERS][3];   /* outward unit head normal there */
    double rho0[HP_MAX_BLADDERS];        /* nominal contact distance |c − p| [m] */
    int prepared;
} hp_layout;

/* Validates the layout and derives the nominal contact point, normal and distance of every
 * bladder; sets prepared = 1 on success (0 on failure). Checks: finite head centre and
 * pivot, semi-axes finite > 0 (a sphere reads semi_axes[0] and this call copies it to the
 * other two), mass finite >= 0, n in 1..HP_MAX_BLADDERS, names non-empty, NUL-terminated
 * and unique, centres finite and outside the head, hp_iab_validate, finite p_min < p_max,
 * 0 < stretch_min < stretch_max, stretch_max below any inflation limit point, rate_max > 0
 * (+inf allowed), and the nominal pose holdable: the stretch at ro = rho0 strictly inside
 * (stretch_min, stretch_max) by at least 1e-9 and its pressure inside [p_min, p_max].
 * HP_ERR_INVALID (or the bladder model's code) with a message naming the bladder and
 * field at fault, e.g. "bladder 'side_fore_left': stretch_max: ...". Uses the bladder
 * model; allocates nothing. */
HP_API hp_error hp_layout_prepare(hp_layout *L, hp_diag *diag);

/* Point of the head surface a bladder touches placed by "touch": returns the bladder centre
 * c = p + (Ro + preload)·n(p) for surface point p (which must lie on the surface to within
 * 1e-9 relative of its implicit function; otherwise HP_ERR_INVALID). */
HP_API hp_error hp_head_center_from_touch(const hp_head *h, const double p[3], double Ro,
                                   double preload, double center[3], hp_diag *diag);

/* Fidelity levels of the contact model. */
typedef enum hp_level {
    HP_LEVEL_LINEAR = 0, /* rho(0) + J·xi */
    HP_LEVEL_PLANE,      /* tangent plane at the nominal contact, moving with the head */
    HP_LEVEL_SURFACE,    /* exact distance to the moved sphere or ellipsoid */
    HP_LEVEL_AUTO        /* the cheapest level whose error bound meets a tolerance */
} hp_level;
HP_API const char *hp_level_name(hp_level l); /* "linear", "plane", "surface", "auto" */
HP_API hp_error hp_level_parse(const char *s, hp_level *out);

/* Contact distances rho[k] (m) from each bladder centre to the head surface at pose xi,
 * for level linear, plane or surface (not auto). rho is signed (negative when a centre is
 * inside the moved head). J (n×6, row-major, per m and per rad) and H (n×6×6,
 * H[k*36 + i*6 + j] = ∂²rho_k/∂xi_i∂xi_j) are exact derivatives; any of rho, J, H may be
 * NULL. HP_ERR_STATE when the layout is not prepared; HP_ERR_INVALID for a non-finite xi
 * or bad level; HP_ERR_DOMAIN (surface) when a pose puts a bladder centre so deep inside
 * the head that its closest surface point is not unique. On error the given outputs are
 * NaN. Allocates nothing; about 1–2 µs for eight bladders with J (surface, -O2). */
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

/* The reach search stops at these (mm, degrees): a reach equal to one means "at least". */
#define HP_REACH_CAP_MM 50.0
#define HP_REACH_CAP_DEG 30.0

/* Layout analysis at the nominal pose, translation per mm and rotation per degree. */
typedef struct hp_layout_analysis {
    double singular_values[6];  /* of J scaled to mm/mm and mm/deg, descending */
    int rank;                   /* numerical rank (sv > 1e-9·sv_max) */
    double condition;           /* sv_max / sv_min; +inf when rank < 6 */
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
 * nominal pose itself violates a limit. A sphere head gets rotation_commandable = 0 and
 * rotation reach 0. weakest_words names the dominant component of the weakest vector and
 * any other component of magnitude >= 0.3. */
HP_API hp_error hp_layout_analyze(const hp_layout *L, hp_level level, hp_layout_analysis *out);

#ifdef __cplusplus
}
#endif
#endif
