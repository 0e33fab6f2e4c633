/* The pressures that hold a planner's nominal pose: where a trace run starts (see
 * hp_planner_nominal_pressures in hp_planner.h). */
#include "headplan/hp_planner.h"
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

hp_error hp_planner_nominal_pressures(const hp_planner *p, double *pressures)
{
    if (!p || !pressures) return HP_ERR_NULL;
    const hp_layout *L = hp_planner_layout(p);
    if (!L) return HP_ERR_STATE;
    int bad = 0;
    hp_error e = hpi_nominal_pressures_of(L, hpi_planner_geom(p), pressures, &bad);
    if (e != HP_OK)
        for (int j = 0; j < L->n; ++j) pressures[j] = NAN;
    return e;
}
