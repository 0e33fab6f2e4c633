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
void hpi_claw_cap(double P, double ro, double rho, hp_claw *c);

/* The law fitted to the finite-element reference (fem/, docs/accuracy.md): a thick,
 * nearly incompressible Mooney–Rivlin bladder with its centre held, pressure held, pressed
 * along its axis by a rigid frictionless plane or sphere. With d = delta/ro and
 * mu = C1 + C2 (the rubber's initial shear modulus),
 *     F = pi·ro²·(P·s·G(d) + w·H(d)),   G(d) = d·(a1 + a2·d + a3·d²),  H(d) = G(d)·(1 + b_d·d),
 *     s = 1 + b_w·(wall/ro − w0) + b_k·ro/Rh,   w = b_p·mu·P/sqrt(P² + (p_c·mu)²),
 * and W = ro·pi·ro²·(P·s·∫G + w·∫H) (integrals from 0 to d; s and w do not depend on rho).
 * w is the wall's own share: the rubber carries a force that does not scale with the
 * pressure (F/(P·pi·ro²) grows as the pressure falls), and p_c > 0 makes it vanish with P,
 * so the force is 0 at P = 0 (where the load model switches it off) and the law is smooth
 * and finite for every P (the negative pressures the scenes allow too, which its domain
 * refuses). The coefficients and the domain they were fitted over are generated
 * into contact_law_fit.h by fem/fit_law.py. */
typedef struct hp_claw_bladder {
    double C1, C2; /* [Pa] moduli, paper convention */
    double wall;   /* [m] reference wall thickness Ro − Ri */
    double curv;   /* [1/m] the head's curvature at the contact, 1/Rh (0: a plane) */
} hp_claw_bladder;

/* Which part of the fitted law's domain a state leaves (0 = inside). */
typedef enum hp_claw_domain {
    HP_CLAW_IN = 0,
    HP_CLAW_INDENT,   /* delta/ro beyond the largest indentation of the tables */
    HP_CLAW_WALL,     /* wall/ro outside the tables' range */
    HP_CLAW_PRESSURE, /* P/C1 outside the tables' range */
    HP_CLAW_MODULI,   /* C2/C1 outside the tables' range */
    HP_CLAW_CURVATURE /* ro/Rh outside the tables' range (or a concave head) */
} hp_claw_domain;

/* The fitted law's value, exact first and second derivatives in (P, ro, rho) (through
 * d, wall/ro, P/C1 and ro/Rh) and its work W. No domain check: see hpi_claw_fem_domain. */
void hpi_claw_fem(const hp_claw_bladder *b, double P, double ro, double rho, hp_claw *c);

/* HP_CLAW_IN when (P, ro, rho) and the bladder lie in the domain the law was fitted over,
 * else the first group that leaves it (a caller refuses or flags the state by that name). */
hp_claw_domain hpi_claw_fem_domain(const hp_claw_bladder *b, double P, double ro, double rho);

/* Which law a caller evaluates: the load level reads its choice from the load model. */
typedef enum hp_claw_law { HP_CLAW_LAW_CAP = 0, HP_CLAW_LAW_FEM } hp_claw_law;

/* What the fitted law needs from a bladder (iab: moduli, wall Ro − Ri) and the head at the
 * contact point x (head frame, relative to its centre; semi the head's semi-axes, a sphere
 * with all three equal): curv is the head's mean curvature there, (k1 + k2)/2. The tables
 * are axisymmetric (a sphere, one curvature) and the law is linear in ro/Rh, so the mean of
 * the two principal curvatures (the average normal curvature over the directions around
 * the normal) is the first-order axisymmetric equivalent of an ellipsoid's patch; the mean
 * of the principal radii would weight the flatter direction more. For an ellipsoid
 * x²/a² + y²/b² + z²/c² = 1, with h = (x²/a⁴ + y²/b⁴ + z²/c⁴)^(−1/2),
 *     H = h³·(a² + b² + c² − |x|²) / (2·a²·b²·c²). */
struct hp_iab;
void hpi_claw_bladder_of(const struct hp_iab *iab, const double semi[3], const double x[3],
                         hp_claw_bladder *b);

/* The one entry for a caller that picks its law: hpi_claw_cap (b unused) or hpi_claw_fem. */
void hpi_claw_eval(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                   hp_claw *c);

/* How much of the law a caller needs: F; also the gradient d; also the Hessian d2; and, or-ed
 * with one of them, HP_CLAW_WORK for the work W too (of the load model's callers only the
 * potential energy reads W). Two levels or-ed together name the higher. */
typedef enum hp_claw_order {
    HP_CLAW_VALUE = 0,
    HP_CLAW_GRADIENT = 1,
    HP_CLAW_HESSIAN = 2,
    HP_CLAW_WORK = 4
} hp_claw_order;

/* hpi_claw_eval up to order o: what it computes has the same bits as hpi_claw_eval's (the
 * fitted law skips the arithmetic of what is not asked for), what it does not is NaN.
 * hpi_claw_eval is this at HP_CLAW_HESSIAN | HP_CLAW_WORK. */
void hpi_claw_eval_to(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                      hp_claw_order o, hp_claw *c);

/* The law's dF/drho as a function of (P, ro, rho), with its own exact first and second
 * derivatives in c->d and c->d2 (c->W is 0): what a caller needs to differentiate the
 * contact stiffness (−dF/drho along the normal) twice in P. */
void hpi_claw_eval_drho(hp_claw_law law, const hp_claw_bladder *b, double P, double ro, double rho,
                        hp_claw *c);

/* The group's name for messages ("indent", "wall", "pressure", "moduli", "curvature"). */
const char *hpi_claw_domain_name(hp_claw_domain d);

#endif
