/* Test helper: the default eight-bladder layout on the default adult head.
 *
 * Touch points (mm, on the ellipsoid 77.5 × 115 × 97.5 centred at the origin): each has
 * its x and y chosen and the third coordinate on the surface,
 *   base (z = −97.5·sqrt(1 − (x/77.5)² − (y/115)²), normal mostly −Z):
 *     base_neck_left   ( 25, −40, z)    base_neck_right  (−25, −40, z)
 *     base_skull_left  ( 25,  40, z)    base_skull_right (−25,  40, z)
 *   side (x = ±77.5·sqrt(1 − (y/115)² − (z/97.5)²), normal mostly ±X), z = −15:
 *     side_fore_left   ( x,  45, −15)   side_fore_right  (−x,  45, −15)
 *     side_chin_left   ( x, −45, −15)   side_chin_right  (−x, −45, −15)
 * Centres c = p + Ro·n(p) (no preload). Bladders: Ri 27 mm, Ro 30 mm, C1 1.1e4 Pa,
 * C2 2.2e4 Pa, pressure −5 .. +10 kPa, stretch 0.8 .. 1.3, no rate limit. Pivot origin. */
#ifndef HP_TEST_DEFAULT_LAYOUT_H
#define HP_TEST_DEFAULT_LAYOUT_H

#include "headplan/hp_contact.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Touch point (mm) of bladder k of the default layout. */
static inline void default_touch_mm(int k, double p[3])
{
    static const double xy[4][2] = {{25, -40}, {-25, -40}, {25, 40}, {-25, 40}};
    static const double yz[4][3] = {{45, -15, 1}, {45, -15, -1}, {-45, -15, 1}, {-45, -15, -1}};
    const double a = 77.5, b = 115.0, c = 97.5;
    if (k < 4) {
        p[0] = xy[k][0];
        p[1] = xy[k][1];
        p[2] = -c * sqrt(1.0 - (p[0] / a) * (p[0] / a) - (p[1] / b) * (p[1] / b));
    } else {
        p[1] = yz[k - 4][0];
        p[2] = yz[k - 4][1];
        p[0] = yz[k - 4][2] * a * sqrt(1.0 - (p[1] / b) * (p[1] / b) - (p[2] / c) * (p[2] / c));
    }
}

static inline const char *default_name(int k)
{
    static const char *const names[8] = {"base_neck_left",   "base_neck_right", "base_skull_left",
                                         "base_skull_right", "side_fore_left",  "side_fore_right",
                                         "side_chin_left",   "side_chin_right"};
    return names[k];
}

/* One default bladder with its centre left at 0 (placed by the caller). */
static inline void default_bladder(int k, hp_bladder *b)
{
    memset(b, 0, sizeof *b);
    snprintf(b->name, sizeof b->name, "%s", default_name(k));
    b->iab.Ri = 0.027;
    b->iab.Ro = 0.030;
    b->iab.C1 = 1.1e4;
    b->iab.C2 = 2.2e4;
    b->p_min = -5e3;
    b->p_max = 10e3;
    b->stretch_min = 0.8;
    b->stretch_max = 1.3;
    b->rate_max = INFINITY;
}

/* Fills L with the default layout (not yet prepared) on the given head, touching it at the
 * default points scaled onto that head (x, y, z each scaled by the head's semi-axis over
 * the default's, so a sphere head gets the same arrangement). Returns 0 on success. */
static inline int default_layout_on(hp_layout *L, const hp_head *head, double preload)
{
    memset(L, 0, sizeof *L);
    L->head = *head;
    L->n = 8;
    const double def[3] = {HP_HEAD_DEFAULT_A, HP_HEAD_DEFAULT_B, HP_HEAD_DEFAULT_C};
    for (int k = 0; k < 8; ++k) {
        double pmm[3], p[3];
        default_touch_mm(k, pmm);
        for (int i = 0; i < 3; ++i) {
            double ax = head->shape == HP_HEAD_SPHERE ? head->semi_axes[0] : head->semi_axes[i];
            p[i] = head->center[i] + pmm[i] * 1e-3 * ax / def[i];
        }
        default_bladder(k, &L->bladders[k]);
        if (hp_head_center_from_touch(head, p, L->bladders[k].iab.Ro, preload,
                                      L->bladders[k].center, NULL) != HP_OK)
            return -1;
    }
    return 0;
}

static inline hp_head default_head(void)
{
    hp_head h;
    memset(&h, 0, sizeof h);
    h.shape = HP_HEAD_ELLIPSOID;
    h.semi_axes[0] = HP_HEAD_DEFAULT_A;
    h.semi_axes[1] = HP_HEAD_DEFAULT_B;
    h.semi_axes[2] = HP_HEAD_DEFAULT_C;
    h.mass = HP_HEAD_DEFAULT_MASS;
    return h;
}

/* The default layout, prepared. Returns 0 on success. */
static inline int default_layout(hp_layout *L)
{
    hp_head h = default_head();
    if (default_layout_on(L, &h, 0.0) != 0) return -1;
    return hp_layout_prepare(L, NULL) == HP_OK ? 0 : -1;
}

#endif
