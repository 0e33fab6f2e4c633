/* The contact laws (contact_law.h): one function per law, each with its exact first and
 * second derivatives, so that the load model, the load planner and its stiffness all use
 * the same formula. */
#include "contact_law.h"
#include "common/units.h"

#include <string.h>

void hp_claw_cap(double P, double ro, double rho, hp_claw *c)
{
    const double pi = HP_PI;
    double a = pi * (ro - rho) * (ro + rho); /* the cap's base area; (ro − rho)(ro + rho)
                                              * keeps its relative accuracy near touching */
    double d = ro - rho;
    memset(c, 0, sizeof *c);
    c->F = P * a;
    c->d[HP_CLAW_P] = a;
    c->d[HP_CLAW_RO] = 2.0 * pi * P * ro;
    c->d[HP_CLAW_RHO] = -2.0 * pi * P * rho;
    c->d2[HP_CLAW_P][HP_CLAW_RO] = c->d2[HP_CLAW_RO][HP_CLAW_P] = 2.0 * pi * ro;
    c->d2[HP_CLAW_P][HP_CLAW_RHO] = c->d2[HP_CLAW_RHO][HP_CLAW_P] = -2.0 * pi * rho;
    c->d2[HP_CLAW_RO][HP_CLAW_RO] = 2.0 * pi * P;
    c->d2[HP_CLAW_RHO][HP_CLAW_RHO] = -2.0 * pi * P;
    c->W = P * pi * d * d * (ro - d / 3.0);
}
