/* The layout: the head and the bladders around it, in the frame of hp_pose.h (IEC 61217,
 * metres), checked by hp_layout_prepare.
 *
 * Functions are reentrant and allocate nothing unless they say so. */
#ifndef HP_LAYOUT_H
#define HP_LAYOUT_H

#include "headplan/hp_common.h"
#include "headplan/hp_iab.h"
#include "headplan/hp_pose.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum hp_head_shape { HP_HEAD_SPHERE = 0, HP_HEAD_ELLIPSOID } hp_head_shape;
HP_API const char *hp_head_shape_name(hp_head_shape s); /* "sphere", "ellipsoid" */
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
    double center[3];    /* fixed centre on its panel [m] */
    hp_iab iab;          /* reference radii and material */
    double p_min, p_max; /* safe pressure [Pa], p_min < p_max */
    double stretch_min;  /* safe inner stretch λi = ri/Ri, lower bound (> 0) */
    double stretch_max;  /* upper bound, below any limit point */
    double rate_max;     /* largest pressure change per cycle [Pa]; +inf when unlimited */
    double stress_max;   /* largest hoop stress at the inner surface [Pa] (> 0); 0 or
                             +inf: no stress limit (hp_iab_hoop_stress_inner) */
} hp_bladder;

/* The head and its bladders at the nominal pose: inputs only. Nothing in it is derived, so
 * a layout may be edited at any time; every call that takes a layout reads it as it is
 * then (the contact geometry is derived on each call, or once by an object that keeps its
 * own private copy, such as the planner). */
typedef struct hp_layout {
    hp_head head;
    double pivot[3]; /* [m] */
    int n;           /* number of bladders, 1..HP_MAX_BLADDERS */
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

#ifdef __cplusplus
}
#endif
#endif
