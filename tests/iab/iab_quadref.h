/* __float128 reference for the bladder model, shared by the iab tests: the closed form
 * evaluated NAIVELY (f(λi) − f(λo) as written). The naive difference loses about
 * log2(1/|λi − 1|) bits near λi = 1; with a 113-bit significand that leaves more than 70
 * bits for every |λi − 1| >= 1e-12, i.e. a reference ~1e-21 relative — far below the
 * double-precision errors under test (~1e-16). Inputs are the same doubles the library
 * sees, converted exactly. */
#ifndef HP_TEST_IAB_QUADREF_H
#define HP_TEST_IAB_QUADREF_H

#include <quadmath.h>

typedef __float128 q128;

static q128 qf(q128 l) { return -1 / l - 1 / (4 * l * l * l * l); }
static q128 qg(q128 l) { return l - 1 / (2 * l * l); }
static q128 qfp(q128 l) { return 1 / (l * l) + 1 / (l * l * l * l * l); }
static q128 qgp(q128 l) { return 1 + 1 / (l * l * l); }

static q128 q_ro(double Ri, double Ro, q128 ri)
{
    q128 qRi = Ri, qRo = Ro;
    return cbrtq(qRo * qRo * qRo + ri * ri * ri - qRi * qRi * qRi);
}

static q128 q_ik(double Ri, double Ro, double C1, double C2, q128 ri)
{
    q128 ro = q_ro(Ri, Ro, ri);
    q128 li = ri / Ri, lo = ro / Ro;
    return 2 * (q128)C1 * (qf(li) - qf(lo)) + 2 * (q128)C2 * (qg(li) - qg(lo));
}

/* Analytic dP/dri in quad, from the chain rule dλo/dri = ri²/(Ro·ro²). */
static q128 q_dik(double Ri, double Ro, double C1, double C2, q128 ri)
{
    q128 ro = q_ro(Ri, Ro, ri);
    q128 li = ri / Ri, lo = ro / Ro, s = ri * ri / ((q128)Ro * ro * ro);
    return 2 * (q128)C1 * (qfp(li) / Ri - qfp(lo) * s) +
           2 * (q128)C2 * (qgp(li) / Ri - qgp(lo) * s);
}

#endif
