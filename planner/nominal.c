/* The pressures that hold a layout's nominal pose (nominal.h): where a trace run starts
 * (hp_planner_nominal_pressures, planner.c) and what auto measures the contact levels by
 * (level_choice.c). It calls nothing of the planner's, so both may call it. */
#include "headplan/hp_iab.h"
#include "planner/nominal.h"
#include "planner/problem_setup.h"

#include <math.h>

hp_error hpi_nominal_pressures_of(const hp_layout *L, const hp_geom *G, double *pressures, int *bad)
{
    for (int k = 0; k < L->n; ++k) {
        const hp_iab *b = &L->bladders[k].iab;
        double ri, P;
        hp_error e = hp_iab_ri(b, G->rho0[k], &ri);
        if (e == HP_OK) e = hp_iab_ik(b, ri, &P);
        if (e != HP_OK) {
            *bad = k;
            return e;
        }
        pressures[k] = P;
    }
    return HP_OK;
}
