/* Test helper for the identifiable-range tests: layouts built from the head, the pivot and
 * the rays along which the bladders touch the head, optionally scaled as a whole.
 *
 * Rays (from the head centre; the touch point is where the ray meets the surface):
 *   default: the eight of scenarios/default.yaml, base (±0.35, ±0.45, −1) and side
 *            (±1, 0.45, 0.15), (±1, −0.45, −0.15);
 *   flat:    eight rays in the head's XY plane, every 45° (all normals in that plane, so z,
 *            pitch and roll change no contact distance: rank 3).
 * Bladders: Ri 27 mm, Ro 30 mm (times the scale), C1 1.1e4 Pa, C2 2.2e4 Pa, −5..10 kPa,
 * stretch 0.8..1.3, no preload, no rate limit. */
#ifndef HP_TEST_IDENT_LAYOUTS_H
#define HP_TEST_IDENT_LAYOUTS_H

#include "headplan/hp_contact.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const double il_default_rays[8][3] = {
    {0.35, -0.45, -1}, {-0.35, -0.45, -1}, {0.35, 0.45, -1},  {-0.35, 0.45, -1},
    {1, 0.45, 0.15},   {-1, 0.45, 0.15},   {1, -0.45, -0.15}, {-1, -0.45, -0.15}};

static inline void il_flat_rays(double rays[8][3])
{
    for (int k = 0; k < 8; ++k) {
        double a = k * 3.14159265358979323846 / 4.0 + 0.3; /* off the axes */
        rays[k][0] = cos(a);
        rays[k][1] = sin(a);
        rays[k][2] = 0.0;
    }
}

/* Builds and prepares a layout: head of the given shape and semi-axes ax [m] centred at
 * centre [m], pivot [m], the first n rays; every length times s. Returns HP_OK or the
 * error of hp_layout_prepare / hp_head_center_from_touch. */
static inline hp_error il_layout(hp_layout *L, hp_head_shape shape, const double ax[3],
                                 const double centre[3], const double pivot[3], int n,
                                 const double (*rays)[3], double s)
{
    memset(L, 0, sizeof *L);
    L->head.shape = shape;
    for (int i = 0; i < 3; ++i) {
        L->head.semi_axes[i] = ax[shape == HP_HEAD_SPHERE ? 0 : i] * s;
        L->head.center[i] = centre[i] * s;
        L->pivot[i] = pivot[i] * s;
    }
    L->head.mass = 4.5;
    L->n = n;
    for (int k = 0; k < n; ++k) {
        hp_bladder *B = &L->bladders[k];
        snprintf(B->name, sizeof B->name, "b%d", k);
        B->iab.Ri = 0.027 * s;
        B->iab.Ro = 0.030 * s;
        B->iab.C1 = 1.1e4;
        B->iab.C2 = 2.2e4;
        B->p_min = -5e3;
        B->p_max = 10e3;
        B->stretch_min = 0.8;
        B->stretch_max = 1.3;
        B->rate_max = INFINITY;
        const double *u = rays[k];
        double q = 0.0;
        for (int i = 0; i < 3; ++i)
            q += (u[i] / L->head.semi_axes[i]) * (u[i] / L->head.semi_axes[i]);
        double t = 1.0 / sqrt(q), p[3];
        for (int i = 0; i < 3; ++i) p[i] = L->head.center[i] + t * u[i];
        hp_error e = hp_head_center_from_touch(&L->head, p, B->iab.Ro, 0.0, B->center, NULL);
        if (e != HP_OK) return e;
    }
    return hp_layout_prepare(L, NULL);
}

/* The default head's semi-axes [m] and the origin. */
static const double il_default_axes[3] = {0.0775, 0.115, 0.0975};
static const double il_origin[3] = {0, 0, 0};

#endif
