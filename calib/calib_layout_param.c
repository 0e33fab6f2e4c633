/* The layout a layout fit tries: the scene's layout with the fitted parameters applied (head
 * semi-axes, bladder offsets along the contact normals). Its own file because both forward
 * models of the fit use it, the contact one (calib_layout.c) and the load one
 * (calib_layout_load.c), and the first calls the second: in either of them, the two files
 * would depend on each other. */
#include "calib/calib_internal.h"

hp_error calib_layout_apply(const lay_ctx *c, const double *theta, hp_layout *L, hp_geom *G,
                            int validate, hp_diag *d)
{
    *L = *c->L0;
    for (int j = 0; j < c->n_axes; ++j) L->head.semi_axes[j] += theta[j];
    if (c->n_axes == 1) L->head.semi_axes[1] = L->head.semi_axes[2] = L->head.semi_axes[0];
    if (c->np > c->n_axes)
        for (int k = 0; k < L->n; ++k)
            for (int i = 0; i < 3; ++i)
                L->bladders[k].center[i] += theta[c->n_axes + k] * c->G0.normal[k][i];
    if (validate) {
        hp_error e = hp_layout_prepare(L, d);
        return e ? e : hpi_geom_derive(L, G, d);
    }
    for (int j = 0; j < 3; ++j)
        if (!(L->head.semi_axes[j] > 0)) return HP_ERR_DOMAIN;
    return hpi_geom_derive(L, G, NULL) == HP_OK ? HP_OK : HP_ERR_DOMAIN;
}
