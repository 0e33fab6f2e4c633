/* Test fixture for the planner's backends: the default adult head with the paper's eight-
 * bladder layout, and an hp_problem filled by hand (independent of the core's problem_setup).
 *
 * Head: ellipsoid, semi-axes 77.5 (X) × 115 (Y) × 97.5 (Z) mm at the origin; pivot at the
 * origin. Bladders: Ri 27 mm, Ro 30 mm, C1 1.1e4 Pa, C2 2.2e4 Pa, pressure −5..+10 kPa,
 * stretch 0.8..1.3, each placed by the surface point it touches (hp_head_center_from_touch):
 * four base bladders on the back of the head (−Z), neck at −Y, skull at +Y, left at +X; four
 * side bladders on ±X, forehead level at +Y and chin level at −Y. */
#ifndef HP_TEST_BACKEND_FIXTURE_H
#define HP_TEST_BACKEND_FIXTURE_H

#include "headplan/hp_iab.h"
#include "headplan/hp_contact.h"
#include "planner/problem.h"

#include <math.h>
#include <string.h>

#define FX_RI 0.027
#define FX_RO 0.030
#define FX_C1 1.1e4
#define FX_C2 2.2e4
#define FX_PMIN (-5000.0)
#define FX_PMAX 10000.0
#define FX_SMIN 0.8
#define FX_SMAX 1.3

/* Surface point of the default ellipsoid with two coordinates given (m) and the third solved
 * on the side of sign `s` (+1/−1). axis: the coordinate solved for. */
static inline void fx_surface_point(int axis, double u, double v, double s, double p[3])
{
    const double ax[3] = {HP_HEAD_DEFAULT_A, HP_HEAD_DEFAULT_B, HP_HEAD_DEFAULT_C};
    int i = (axis + 1) % 3, j = (axis + 2) % 3;
    p[i] = u;
    p[j] = v;
    double r = 1.0 - (u / ax[i]) * (u / ax[i]) - (v / ax[j]) * (v / ax[j]);
    p[axis] = s * ax[axis] * sqrt(r);
}

/* Builds and prepares the default layout; returns HP_OK or the first error. */
static inline hp_error fx_layout(hp_layout *L)
{
    memset(L, 0, sizeof *L);
    L->head.shape = HP_HEAD_ELLIPSOID;
    L->head.semi_axes[0] = HP_HEAD_DEFAULT_A;
    L->head.semi_axes[1] = HP_HEAD_DEFAULT_B;
    L->head.semi_axes[2] = HP_HEAD_DEFAULT_C;
    L->head.mass = HP_HEAD_DEFAULT_MASS;
    L->n = 8;
    struct {
        const char *name;
        int axis;    /* coordinate solved for on the surface */
        double u, v; /* the other two coordinates, in the order (axis+1, axis+2) mod 3 */
        double s;    /* side */
    } spec[8] = {
        /* base: axis Z, given (X, Y) */
        {"base_neck_left", 2, 0.025, -0.040, -1},
        {"base_neck_right", 2, -0.025, -0.040, -1},
        {"base_skull_left", 2, 0.025, 0.040, -1},
        {"base_skull_right", 2, -0.025, 0.040, -1},
        /* side: axis X, given (Y, Z) */
        {"side_fore_left", 0, 0.050, 0.010, +1},
        {"side_fore_right", 0, 0.050, 0.010, -1},
        {"side_chin_left", 0, -0.050, -0.010, +1},
        {"side_chin_right", 0, -0.050, -0.010, -1},
    };
    for (int k = 0; k < 8; k++) {
        hp_bladder *B = &L->bladders[k];
        strncpy(B->name, spec[k].name, HP_NAME_MAX - 1);
        B->iab.Ri = FX_RI;
        B->iab.Ro = FX_RO;
        B->iab.C1 = FX_C1;
        B->iab.C2 = FX_C2;
        B->p_min = FX_PMIN;
        B->p_max = FX_PMAX;
        B->stretch_min = FX_SMIN;
        B->stretch_max = FX_SMAX;
        B->rate_max = INFINITY;
        double p[3];
        fx_surface_point(spec[k].axis, spec[k].u, spec[k].v, spec[k].s, p);
        hp_error e = hp_head_center_from_touch(&L->head, p, FX_RO, 0.0, B->center, NULL);
        if (e != HP_OK) return e;
    }
    return hp_layout_prepare(L, NULL);
}

/* Fills pb for layout L (with its contact geometry G, derived here) at level, desired correction d (mm, deg), unit weights, mu = 0,
 * previous pressures 0, and the radius bounds of the stretch and pressure limits:
 * ri_lo = max(0.8·Ri, FK(p_min)), ri_hi = min(1.3·Ri, FK(p_max)) (mm), ro bounds by the
 * volume law. */
static inline hp_error fx_problem(const hp_layout *L, hp_geom *G, hp_level level, const double d[6],
                                  hp_problem *pb)
{
    memset(pb, 0, sizeof *pb);
    hp_error eg = hpi_geom_derive(L, G, NULL);
    if (eg != HP_OK) return eg;
    pb->layout = L;
    pb->geom = G;
    pb->level = level;
    pb->n = L->n;
    pb->nx = 6 + L->n;
    pb->mu = 0.0;
    for (int i = 0; i < 6; i++) {
        pb->w[i] = 1.0;
        pb->d[i] = d[i];
    }
    for (int k = 0; k < L->n; k++) {
        const hp_bladder *B = &L->bladders[k];
        double r_pmin, r_pmax, ro;
        hp_error e = hp_iab_fk(&B->iab, B->p_min, &r_pmin);
        if (e != HP_OK) return e;
        e = hp_iab_fk(&B->iab, B->p_max, &r_pmax);
        if (e != HP_OK) return e;
        pb->ri_lo[k] = 1e3 * fmax(B->stretch_min * B->iab.Ri, r_pmin);
        pb->ri_hi[k] = 1e3 * fmin(B->stretch_max * B->iab.Ri, r_pmax);
        e = hp_iab_ro(&B->iab, pb->ri_lo[k] * 1e-3, &ro);
        if (e != HP_OK) return e;
        pb->ro_lo[k] = ro * 1e3;
        e = hp_iab_ro(&B->iab, pb->ri_hi[k] * 1e-3, &ro);
        if (e != HP_OK) return e;
        pb->ro_hi[k] = ro * 1e3;
        pb->p_prev[k] = 0.0;
    }
    return HP_OK;
}

#endif
