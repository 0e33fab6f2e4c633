/* Closed-form inverse kinematics (radius -> pressure), its exact derivatives and the wall
 * stresses. See iab_internal.h for why the differences are written the way they are. */
#include "iab/iab_internal.h"

#include <math.h>

/* hpi_iab_s_energy_diff with the stretches l1 = r1/R1, l2 = r2/R2 formed by the caller (the
 * root find's evaluation forms them once for the pressure and its slope). */
static inline double energy_diff_l(const hp_iab_s *s, double r1, double R1, double r2, double R2,
                                   double a, double c21, double l1, double l2)
{
    double x = r1 * R2, y = r2 * R1;
    double dl = a * c21 / ((x * x + x * y + y * y) * (R1 * R2)); /* λ1 − λ2 */
    double p = l1 * l2, p2 = p * p;
    double F = 1.0 / p + (l1 + l2) * (l1 * l1 + l2 * l2) / (4.0 * p2 * p2);
    double G = 1.0 + (l1 + l2) / (2.0 * p2);
    return 2.0 * dl * (s->C1 * F + s->C2 * G);
}

double hpi_iab_s_energy_diff(const hp_iab_s *s, double r1, double R1, double r2, double R2,
                             double a, double c21)
{
    return energy_diff_l(s, r1, R1, r2, R2, a, c21, r1 / R1, r2 / R2);
}

/* f'(λ) = λ⁻² + λ⁻⁵, g'(λ) = 1 + λ⁻³ and their derivatives. */
static double fp(double l) { return 1.0 / (l * l) + 1.0 / (l * l * l * l * l); }
static double gp(double l) { return 1.0 + 1.0 / (l * l * l); }
static double fpp(double l)
{
    double l3 = l * l * l;
    return -2.0 / l3 - 5.0 / (l3 * l3);
}
static double gpp(double l) { return -3.0 / (l * l * l * l); }

/* The pressure at scaled inner radius ri whose scaled outer radius is r, the stretches
 * li = ri/Ri and lo = r/Ro formed by the caller. */
static hp_error pressure_at_l(const hp_iab_s *s, double ri, double r, double li, double lo,
                              double *P)
{
    double a = hpi_iab_cube_diff(ri, s->Ri); /* ri³ − Ri³ */
    double p = energy_diff_l(s, ri, s->Ri, r, s->Ro, a, s->W, li, lo);
    if (!isfinite(p)) return HP_ERR_DOMAIN;
    *P = p;
    return HP_OK;
}

/* The pressure at scaled inner radius ri whose scaled outer radius is r. */
static hp_error pressure_at(const hp_iab_s *s, double ri, double r, double *P)
{
    return pressure_at_l(s, ri, r, ri / s->Ri, r / s->Ro, P);
}

/* The pressure at scaled inner radius ri whose scaled outer radius is r, and r. */
static inline hp_error pressure_ro_at(const hp_iab_s *s, double ri, double r, double *P, double *ro)
{
    if (pressure_at(s, ri, r, P) != HP_OK) return HP_ERR_DOMAIN;
    *ro = r;
    return HP_OK;
}

hp_error hpi_iab_s_pressure_ro(const hp_iab_s *s, double ri, double *P, double *ro)
{
    return pressure_ro_at(s, ri, hpi_iab_s_ro(s, ri), P, ro);
}

/* hpi_iab_s_slopes with the stretches li = ri/Ri, lo = ro/Ro formed by the caller. */
static inline hp_error slopes_l(const hp_iab_s *s, double ri, double ro, double li, double lo,
                                double *d1, double *d2)
{
    double ro2 = ro * ro;
    double q = ri * ri / (s->Ro * ro2); /* dλo/dri */
    double iRi = s->iRi;                /* 1.0 / s->Ri, formed once per bladder (off the divider) */
    double dp = 2.0 * s->C1 * (fp(li) * iRi - fp(lo) * q) +
                2.0 * s->C2 * (gp(li) * iRi - gp(lo) * q);
    if (!isfinite(dp)) return HP_ERR_DOMAIN;
    /* The curvature only when asked: the FK's Newton steps take the slope alone, and the
     * curvature's terms (λ⁻⁶, ro⁻⁵) were a third of each of their evaluations. */
    if (d2) {
        double qp = 2.0 * ri * s->W / (s->Ro * ro2 * ro2 * ro); /* d²λo/dri² */
        double ddp = 2.0 * s->C1 * (fpp(li) * iRi * iRi - fpp(lo) * q * q - fp(lo) * qp) +
                     2.0 * s->C2 * (gpp(li) * iRi * iRi - gpp(lo) * q * q - gp(lo) * qp);
        if (!isfinite(ddp)) return HP_ERR_DOMAIN;
        *d2 = ddp;
    }
    if (d1) *d1 = dp;
    return HP_OK;
}

hp_error hpi_iab_s_slopes(const hp_iab_s *s, double ri, double ro, double *d1, double *d2)
{
    return slopes_l(s, ri, ro, ri / s->Ri, ro / s->Ro, d1, d2);
}

/* The pressure and slope at scaled inner radius ri whose scaled outer radius is r. */
static inline hp_error pressure_slope_at(const hp_iab_s *s, double ri, double r, double *P,
                                         double *ro, double *d1)
{
    double li = ri / s->Ri, lo = r / s->Ro, p;
    if (pressure_at_l(s, ri, r, li, lo, &p) != HP_OK ||
        slopes_l(s, ri, r, li, lo, d1, NULL) != HP_OK)
        return HP_ERR_DOMAIN;
    *P = p;
    *ro = r;
    return HP_OK;
}

hp_error hpi_iab_s_pressure_slope(const hp_iab_s *s, double ri, double *P, double *ro, double *d1)
{
    return pressure_slope_at(s, ri, hpi_iab_s_ro(s, ri), P, ro, d1);
}

/* The outer radius at ri from a nearby evaluation (ri0, ro0), by the first-order step
 * dro/dri = ri²/ro² from it: within ~(Δri/ri)² of the root, so hpi_iab_cbrt_near takes it
 * for Newton steps and neighbours (the root find's are within 1e-7); NAN ro0 or a far ri0:
 * the full cube root. */
static inline double ro_from_near(const hp_iab_s *s, double ri, double ri0, double ro0)
{
    double q = ri0 / ro0;
    return hpi_iab_cbrt_near(s->W + ri * ri * ri, ro0 + q * q * (ri - ri0));
}

hp_error hpi_iab_s_pressure_slope_near(const hp_iab_s *s, double ri, double ri0, double ro0,
                                       double *P, double *ro, double *d1)
{
    return pressure_slope_at(s, ri, ro_from_near(s, ri, ri0, ro0), P, ro, d1);
}

hp_error hpi_iab_s_pressure_ro_near(const hp_iab_s *s, double ri, double ri0, double ro0, double *P,
                                    double *ro)
{
    return pressure_ro_at(s, ri, ro_from_near(s, ri, ri0, ro0), P, ro);
}

hp_error hpi_iab_s_ik(const hp_iab_s *s, double ri, double *P, double *d1, double *d2)
{
    double p, ro;
    if (hpi_iab_s_pressure_ro(s, ri, &p, &ro) != HP_OK) return HP_ERR_DOMAIN;
    if ((d1 || d2) && hpi_iab_s_slopes(s, ri, ro, d1, d2) != HP_OK) return HP_ERR_DOMAIN;
    *P = p;
    return HP_OK;
}

/* Validates the bladder and the radius, and scales the radius. */
static hp_error prepare(const hp_iab *b, double ri, hp_iab_s *s, double *ris)
{
    hp_error e = hpi_iab_scaled_init(b, s, NULL);
    return e != HP_OK ? e : hpi_iab_s_radius(s, ri, ris);
}

hp_error hpi_iab_s_ik_m(const hp_iab_s *s, double ri, double *P)
{
    double ris, p;
    hp_error e = hpi_iab_s_radius(s, ri, &ris);
    if (e == HP_OK) e = hpi_iab_s_ik(s, ris, &p, NULL, NULL);
    if (e != HP_OK) return e;
    *P = p;
    return HP_OK;
}

hp_error hpi_iab_s_ik_ro_m(const hp_iab_s *s, double ri, double *P, double *ro)
{
    double ris, r;
    hp_error e = hpi_iab_s_radius(s, ri, &ris);
    if (e == HP_OK) e = hpi_iab_s_pressure_ro(s, ris, P, &r);
    if (e != HP_OK) return e;
    *ro = r * s->inv_scale; /* hpi_iab_s_ro_m's bits: the same root, the same exact scaling */
    return HP_OK;
}

hp_error hpi_iab_s_ik_near_m(const hp_iab_s *s, double ri, double ro_near, double *P)
{
    double ris;
    hp_error e = hpi_iab_s_radius(s, ri, &ris);
    if (e != HP_OK) return e;
    /* hpi_iab_s_ro's cube root, from the nearby radius (NaN or far off: from scratch). */
    double r = hpi_iab_cbrt_near(s->W + ris * ris * ris, ro_near * s->scale);
    return pressure_at(s, ris, r, P);
}

hp_error hp_iab_ik(const hp_iab *b, double ri, double *P)
{
    if (!P) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    hp_error e = hpi_iab_scaled_init(b, &s, NULL);
    return e != HP_OK ? e : hpi_iab_s_ik_m(&s, ri, P);
}

hp_error hp_iab_ik_derivs(const hp_iab *b, double ri, double *P, double *dP_dri, double *d2P_dri2)
{
    if (!P) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    double ris, p, d1, d2;
    hp_error e = prepare(b, ri, &s, &ris);
    if (e == HP_OK) e = hpi_iab_s_ik(&s, ris, &p, dP_dri ? &d1 : NULL, d2P_dri2 ? &d2 : NULL);
    if (e != HP_OK) return e;
    *P = p;
    /* Scaled length = length × scale, so d/dri = scale · d/dri_scaled. */
    if (dP_dri) *dP_dri = d1 * s.scale;
    if (d2P_dri2) *d2P_dri2 = d2 * s.scale * s.scale;
    return HP_OK;
}

hp_error hp_iab_wall_stress(const hp_iab *b, double ri, double r, double *s_rr, double *s_tt)
{
    if (!s_rr || !s_tt) return HP_ERR_NULL;
    hp_iab_s s = {0}; /* written by hpi_iab_scaled_init; zeroed for -O3's flow analysis */
    double ris;
    hp_error e = prepare(b, ri, &s, &ris);
    if (e != HP_OK) return e;
    if (!isfinite(r)) return HP_ERR_INVALID;
    double rs = r * s.scale;
    double ro = hpi_iab_s_ro(&s, ris);
    /* Accept r a few ulps outside [ri, ro]: a caller's ro from hp_iab_ro is bit-identical,
     * but one formed another way may differ by rounding. */
    double slack = 8.0 * 0x1p-52;
    if (!(rs >= ris * (1.0 - slack) && rs <= ro * (1.0 + slack))) return HP_ERR_DOMAIN;
    if (rs < ris) rs = ris;
    if (rs > ro) rs = ro;
    double a = hpi_iab_cube_diff(ris, s.Ri);
    /* R(r)³ = Ri³ + (r³ − ri³): positive terms only. */
    double R = rs == ro    ? s.Ro
               : rs == ris ? s.Ri
                           : cbrt(s.Ri * s.Ri * s.Ri + hpi_iab_cube_diff(rs, ris));
    /* σrr(r) = −∫_r^ro (dσrr/dr) dr: the closed form between r and the outer surface. */
    double c21 = rs == ris ? s.W : hpi_iab_cube_diff(ro, rs); /* ro³ − r³ */
    double srr = rs == ro ? 0.0 : -hpi_iab_s_energy_diff(&s, rs, R, ro, s.Ro, a, c21);
    /* σθθ − σrr = C1(λ² − λ⁻⁴) + C2(λ⁴ − λ⁻²) = (λ³ − 1)(λ³ + 1)(C1λ⁻⁴ + C2λ⁻²), with
     * λ³ − 1 = a/R³ formed without cancellation. */
    double l = rs / R, l2 = l * l;
    double R3 = R * R * R;
    double diff = (a / R3) * (l2 * l + 1.0) * (s.C1 / (l2 * l2) + s.C2 / l2);
    double stt = srr + diff;
    if (!isfinite(srr) || !isfinite(stt)) return HP_ERR_DOMAIN;
    *s_rr = srr;
    *s_tt = stt;
    return HP_OK;
}
