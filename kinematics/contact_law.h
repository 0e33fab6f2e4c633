/* The contact law: the one home of the force a pressurised bladder presses on the head
 * with, and its exact first and second derivatives. Internal (not installed).
 *
 * Variables: gauge pressure P [Pa], the bladder's free outer radius ro [m] (from the
 * bladder model at P) and the contact distance rho [m] from the bladder's centre to the
 * head (indentation delta = ro − rho). The laws here are the bare formulas: whether a
 * bladder touches (P > 0, rho < ro) is the caller's decision, and derivatives through
 * ro(P) are the caller's chain rule (dF/dP total = F_P + F_ro·ro'). */
#ifndef HP_CONTACT_LAW_H
#define HP_CONTACT_LAW_H

/* Indices of the law's variables in hp_claw.d and hp_claw.d2. */
enum { HP_CLAW_P = 0, HP_CLAW_RO = 1, HP_CLAW_RHO = 2 };

typedef struct hp_claw {
    double F;        /* [N] force along the contact normal */
    double d[3];     /* dF/dP [m²], dF/dro [N/m], dF/drho [N/m] */
    double d2[3][3]; /* second derivatives, symmetric, in the same order */
    double W;        /* [J] the work of F from first touch: integral of F over the contact
                      * distance from rho to ro (the load level's potential) */
} hp_claw;

/* The cap law: the head flattens the spherical cap of height delta, whose base disc
 * (area pi·(2·ro·delta − delta²) = pi·(ro² − rho²)) carries the pressure:
 *     F = P·pi·(ro² − rho²),  W = P·pi·delta²·(ro − delta/3) (P times the cap's volume).
 * Exact for a rigid sphere cut by a plane; against a thin membrane it overestimates the
 * force (docs/load.md), and against the finite-element reference too (docs/accuracy.md). */
void hp_claw_cap(double P, double ro, double rho, hp_claw *c);

#endif
