/* A plan's pressures against the finite-element reference: the one home of the model error
 * measurement. Internal; `auto` compares levels by it (level_choice.c), and the command
 * line (cli/cli_fidelity.c: solve's and analyze's `model error` line) and the benchmark
 * lab's fidelity family (bench/bench_fidelity.c) state it.
 *
 * The pressures are held and the head let go under its weight: its rest (hp_load_rest,
 * surface geometry) on a load model that evaluates the contact law fitted to the CalculiX
 * tables, whatever law the load level plans with, from the pose the plan claims. The error
 * is that rest against the claimed pose. With a band b > 0, the law's own error is bounded
 * too: the rests with the force scaled by 1 + b and 1 − b (a force scaled by s rests where
 * the weight over s does, so the model's mass is divided by s), the larger deviation
 * reported. */
#ifndef HP_PLANNER_MODEL_ERROR_H
#define HP_PLANNER_MODEL_ERROR_H

#include "headplan/hp_load.h"
#include "headplan/hp_planner.h"

/* The reference models of a layout and load: the fitted law, and with band > 0 the two
 * scaled ones. */
typedef struct hpi_fidelity_ref {
    hp_load_model *M[3];
    int n; /* 1, or 3 with a band */
} hpi_fidelity_ref;

/* Builds the models (band in [0, 0.5)). HP_OK, or the first error of hp_load_model_create
 * (the models built so far are freed by hpi_fidelity_close, which is always called). */
hp_error hpi_fidelity_open(const hp_layout *L, const hp_load_spec *spec, double band,
                           hpi_fidelity_ref *r);
void hpi_fidelity_close(hpi_fidelity_ref *r);

/* One plan's pressures against the reference. */
typedef struct hpi_fidelity_result {
    double pose_mm, pose_deg; /* the rest against the claimed pose: translation norm, rotation
                                 angle; +inf: no rest */
    double band_mm, band_deg; /* the larger deviation with the band (= pose_* without one) */
    double indent_max;        /* the largest delta/ro at the rest (NaN: no rest) */
    double carried;           /* share of the weight the bladders bear along gravity at the
                                 claimed pose (1 at a pose the pressures hold) */
    char domain[48];          /* "in", "BLADDER:GROUP" outside the fitted law's domain, or
                                 "no rest" */
} hpi_fidelity_result;

void hpi_fidelity_measure(const hpi_fidelity_ref *r, const double *P, const double xi[6],
                          hpi_fidelity_result *out);

/* 1 when a plan of this status is an answer whose pressures are measured (reached, closest,
 * uncommanded: the answers solve prints); 0 for the others (failed, a time or iteration
 * limit, refused input), whose pressures are only the safe output, no plan to measure. */
int hpi_fidelity_answered(hp_status status);

/* Translation between two poses [mm]: the norm of the difference of (x, y, z). */
double hpi_pose_translation_mm(const double a[6], const double b[6]);

#endif
